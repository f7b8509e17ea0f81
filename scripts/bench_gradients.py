"""Cost of a gradient against its forward run, and the tape's memory (docs/gradients.md,
report/gradients.md); beside it, in the same interleaved runs, the gradient with the per-substep
adjoint (one launch a substep, the schedule for scenes of many particles). Prints; asserts nothing.

    .venv/bin/python scripts/bench_gradients.py [--frames 120] [--checkpoint K] [--repeats 7] [--per-substep]
"""
import argparse
import sys
import time
from pathlib import Path

import numpy as np
from taichi.lang.util import to_numpy_type

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

import rigid  # noqa: E402
from rigid.diff.gradient import prepare  # noqa: E402
from rigid.diff.passes import Pass  # noqa: E402

SCENE = dict(mesh="sphere.obj", scale=0.3, initial_velocity=(0.8, -1.0, 0.4), initial_angular_velocity=(0, 0, 2.0),
             restitution=0.6, friction=0.3)


def median_times(fns, repeats):
    """Each of ``fns`` run once to compile, then ``repeats`` times in turn (so that a busy machine
    slows all alike): the median seconds of each."""
    for fn in fns:
        fn()
    times = [[] for _ in fns]
    for _ in range(repeats):
        for fn, out in zip(fns, times):
            start = time.perf_counter()
            fn()
            out.append(time.perf_counter() - start)
    return [float(np.median(t)) for t in times]


def tape_bytes(tape) -> int:
    total = 0
    for name in dir(tape):
        f = getattr(tape, name)
        if hasattr(f, "shape") and hasattr(f, "dtype") or hasattr(f, "n"):
            try:
                count = int(np.prod(f.shape)) * (getattr(f, "n", 1) * getattr(f, "m", 1))
            except Exception:
                continue
            size = np.dtype(to_numpy_type(f.dtype)).itemsize
            total += count * size * (2 if getattr(f, "grad", None) is not None else 1)
    return total


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--frames", type=int, default=120)
    parser.add_argument("--checkpoint", type=int, default=None, help="frames a segment (default: the pass's)")
    parser.add_argument("--repeats", type=int, default=7)
    parser.add_argument("--per-substep", action="store_true",
                        help="one launch a substep (the schedule for scenes of many particles)")
    args = parser.parse_args()
    rigid.init("cpu", fp64=True)
    frames = args.frames
    problem, _n, _f, units = prepare(SCENE, frames, ["restitution"])
    run = Pass(problem, units, frames, **({} if args.checkpoint is None else dict(checkpoint_frames=args.checkpoint)))
    run.serial = run.serial and not args.per_substep
    apart = Pass(problem, units, frames, fused=False, **({} if args.checkpoint is None else
                                                         dict(checkpoint_frames=args.checkpoint)))
    apart.serial = run.serial
    cot = {"x": np.ones((frames + 1, 1, 3))}
    engine, forward, per_substep, gradient = median_times(
        [lambda: rigid.Simulator(rigid.scene(**SCENE)).advance(frames), run.forward,
         lambda: (apart.forward(), apart.backward(cot)), lambda: (run.forward(), run.backward(cot))], args.repeats)
    schedule = "one launch a substep" if not run.serial else "one launch a segment"
    print(f"{frames} frames ({frames * problem.substeps} substeps), 1 body of {problem.num_particles} particles, "
          f"{len(problem.planes)} planes, float64, {run.segment // problem.substeps} frames a segment "
          f"({run.num_segments} segments), {schedule}; medians of {args.repeats}")
    print(f"engine forward (rigid.Simulator.advance, incl. build): {engine * 1e3:.1f} ms")
    print(f"differentiable forward:                             {forward * 1e3:.1f} ms")
    print(f"gradient (forward + backward):                      {gradient * 1e3:.1f} ms "
          f"= {gradient / forward:.2f}x its forward, {gradient / engine:.2f}x the engine's")
    print(f"gradient, the per-substep adjoint:                  {per_substep * 1e3:.1f} ms "
          f"= {per_substep / forward:.2f}x its forward")
    print(f"  of the backward: re-runs {run.seconds['rerun'] * 1e3:.1f} ms, adjoints {run.seconds['adjoint'] * 1e3:.1f} ms"
          f" (last call)")
    print(f"tape memory (fields and their adjoints):            {tape_bytes(run.tape) / 2**20:.2f} MiB "
          f"for {run.segment} substeps a segment; checkpoints on the host: "
          f"{sum(c.nbytes for c in run.checkpoints if c is not None) / 2**10:.1f} KiB")


if __name__ == "__main__":
    main()
