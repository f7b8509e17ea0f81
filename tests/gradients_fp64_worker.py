"""The float64 runs of tests/test_gradients.py, in one process: prints one JSON object.

Taichi takes one precision per process and the suite runs in float32, so the test starts this
file and judges its numbers. Every reference is from outside rigid.diff: closed forms, or
central differences of the forward engine (rigid.Simulator).
"""
import json
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

import rigid  # noqa: E402
from rigid.diff.gradient import rows as diff_rows  # noqa: E402

H = 1e-6  # central differences' step (no contact starts a substep earlier within ±H here)


def advance(scene, frames):
    return rigid.Simulator(rigid.scene(**scene)).advance(frames)


def loss(rows, cot):
    return float(sum((cot[k] * rows[k]).sum() for k in cot))


def central(scene, frames, cot, key, component=None, h=H):
    """dL/d scene[key] (one component) by central differences of rigid.Simulator."""
    def moved(sign):
        value = np.array(scene[key], np.float64)
        if component is None:
            value = value + sign * h
        else:
            value[component] += sign * h
        return {**scene, key: float(value) if value.ndim == 0 else tuple(value)}
    return (loss(advance(moved(1), frames), cot) - loss(advance(moved(-1), frames), cot)) / (2 * h)


def cotangent(frames, final=(1.0, 1.0, 1.0), every_y=0.1):
    cot = np.zeros((frames + 1, 1, 3))
    cot[-1, 0] = final
    cot[:, 0, 1] += every_y
    return {"x": cot}


BOUNCE = dict(mesh="sphere.obj", scale=0.3, initial_velocity=(0.8, -1.0, 0.4), initial_angular_velocity=(0.0, 0.0, 2.0))
# A ball and a box bouncing apart: in company a body touches with spheres set inside its mesh
# (the engine's model, rigid.bodies.inset: moved in along a smooth vertex's normal, and along a
# corner's three faces), which the pass must place as the Simulator does. The same scene checks
# symplectic Euler, with the materials' law (friction turns the ball at its bounce): each kernel
# configuration is transformed and compiled once per process, two bodies compile the engine with
# its pair stages whatever else they set, and a lone symplectic ball was one more configuration
# for no check this scene does not make (~1.5 CPU-s with a cold cache).
# 50 particles, 2 bodies: the pass's tape is the size of a lone body's (64 particles, 2 bodies).
TWO_BODIES = dict(mesh="sphere.obj", scale=0.2, sleep=False, integrator="symplectic", restitution=0.6, friction=0.3,
                  bodies=[dict(position=(-0.5, 0.0, 0.0), initial_velocity=(0.3, -1.0, 0.0)),
                          dict(mesh="box.obj", position=(0.5, 0.3, 0.0), initial_velocity=(-0.2, -0.5, 0.1))])
# test_gradients computes this one in the suite's float32 process against this process's float64.
FLOAT32_CASE = dict(scene=dict(mesh="sphere.obj", scale=0.3, initial_velocity=(0.8, -1.0, 0.4), restitution=0.6),
                    frames=30, wrt=["initial_velocity", "restitution"])


def float32_case_cotangent():
    cot = np.zeros((FLOAT32_CASE["frames"] + 1, 1, 3))
    cot[-1, 0, 1] = 1.0  # the final height
    return {"x": cot}


def repeat() -> dict:
    """The gradient at A, then runs at other values B (gradients by the default, fused adjoint, and
    one by the per-substep adjoint), then the gradient at A again; and at A in segments of 8 frames
    (checkpoints, re-runs, carried adjoints), and the per-substep adjoint's, whole and in segments.
    The adjoint kernels share one tape and one thread's native stack with every run between."""
    from rigid.diff.gradient import gather, prepare
    from rigid.diff.passes import Pass

    frames, wrt = 30, ["restitution", "initial_velocity", "orientation", "position"]
    scene = {**BOUNCE, "restitution": 0.4, "initial_velocity": (0.8, -0.94, 0.41)}
    rng = np.random.default_rng(1)
    cot = {"x": rng.normal(size=(frames + 1, 1, 3)), "q": rng.normal(size=(frames + 1, 1, 4))}
    flat = lambda g: np.concatenate([np.ravel(g[n]) for n in wrt]).tolist()

    def per_substep(keys, **options):
        problem, names, _frames, units = prepare(keys, frames, wrt)
        run = Pass(problem, units, frames, **{"fused": False, **options})
        run.forward()
        return flat(gather(problem, run.backward(cot), names))

    first = flat(rigid.gradient(scene, frames, cot, wrt))
    for e in (0.55, 0.7, 0.3):
        rigid.gradient({**scene, "restitution": e, "initial_velocity": (0.9, -1.1, 0.3)}, frames, cot, wrt)
    per_substep({**scene, "restitution": 0.62})
    again = flat(rigid.gradient(scene, frames, cot, wrt))
    segments = flat(rigid.gradient(scene, frames, cot, wrt, checkpoint_frames=8))  # 4 segments, re-run
    return dict(first=first, again=again, segments=segments, per_substep=per_substep(scene),
                per_substep_segments=per_substep(scene, checkpoint_frames=8))


def main() -> None:
    rigid.init("cpu", fp64=True)
    out, seconds = {}, {}
    start = time.perf_counter()

    # The same physics: the pass's rows against rigid.Simulator's (materials and plain law, both
    # schemes, one body and two). The lone balls' kernels (explicit Euler, either law) serve the
    # gradients below; the two bodies' are compiled for this check alone.
    for name, scene in (("materials", {**BOUNCE, "restitution": 0.6, "friction": 0.3}), ("plain", BOUNCE),
                        ("two_bodies_symplectic", TWO_BODIES)):
        a, b = advance(scene, 40), diff_rows(scene, 40)
        out[f"match_{name}"] = {k: float(np.abs(a[k] - b[k]).max()) for k in b}
    seconds["match"] = time.perf_counter() - start

    # Free flight: x_f = x0 + v0 t_f + (gravity terms), so dL/dv0_x = Σ_f w_f t_f.
    free = dict(mesh="sphere.obj", scale=0.3, initial_velocity=(1.0, 2.0, 0.5), walls=False)
    frames = 12
    w = np.linspace(0.5, 2.0, frames + 1)
    cot = {"x": np.zeros((frames + 1, 1, 3))}
    cot["x"][:, 0, 0] = w
    g = rigid.gradient(free, frames, cot, ["initial_velocity"])["initial_velocity"]
    out["free_flight"] = dict(grad=g.tolist(), expected=float((w * np.arange(frames + 1) * 16 * 1e-3).sum()))
    seconds["free"] = time.perf_counter() - start

    # A sphere bouncing once (materials): v0 and e (e between two nodes of the damping table, where
    # c(e) is smooth; at a node it has a kink and the gradient is one side's slope).
    frames = 40
    cot = cotangent(frames)
    scene = {**BOUNCE, "restitution": 0.6125}
    g = rigid.gradient(scene, frames, cot, ["initial_velocity", "restitution"])
    out["bounce"] = dict(v0=g["initial_velocity"].tolist(), e=float(g["restitution"]),
                         fd_v0=[central(scene, frames, cot, "initial_velocity", c) for c in range(3)],
                         fd_e=central(scene, frames, cot, "restitution"))
    seconds["bounce"] = time.perf_counter() - start

    # A box sliding on the floor (sticking friction, μ) and one resting on it (the plain law, k).
    box = dict(mesh="box.obj", scale=0.4, position=(0.0, -0.799, 0.0), initial_velocity=(1.5, 0.0, 0.0))
    frames = 20
    cot = cotangent(frames, final=(1.0, 0.0, 0.0), every_y=0.0)
    scene = {**box, "friction": 0.3}
    g = rigid.gradient(scene, frames, cot, ["friction"])
    # Segments of 8 frames (on the whole run's tape, as repeat()'s): springs carried across at frames 8 and 16.
    segments = rigid.gradient(scene, frames, cot, ["friction"], checkpoint_frames=8)
    out["sliding"] = dict(mu=float(g["friction"]), fd_mu=central(scene, frames, cot, "friction"),
                          mu_segments=float(segments["friction"]))
    scene = {**box, "initial_velocity": (0.0, 0.0, 0.0), "collision_stiffness": 1e4}
    cot = cotangent(frames, final=(0.0, 1.0, 0.0), every_y=0.0)
    g = rigid.gradient(scene, frames, cot, ["collision_stiffness"])
    out["resting"] = dict(k=float(g["collision_stiffness"]),
                          fd_k=central(scene, frames, cot, "collision_stiffness", h=1e-2))
    # Orientation: a tilted box dropped on the floor (the plain law, as the resting box). The scene
    # normalises the key, so the gradient is tangent: along q it is zero, and along a tangent d it
    # is the slope of the loss over orientation = q + h d (normalised by the config).
    q = np.array([0.95, 0.2, 0.1, 0.05]) / np.linalg.norm([0.95, 0.2, 0.1, 0.05])
    scene = {**box, "position": (0.0, -0.5, 0.0), "initial_velocity": (0.5, 0.0, 0.0), "orientation": tuple(q)}
    rng = np.random.default_rng(3)
    cot = {"x": rng.normal(size=(frames + 1, 1, 3)), "q": rng.normal(size=(frames + 1, 1, 4))}
    g = rigid.gradient(scene, frames, cot, ["orientation"])["orientation"]
    tangents = np.linalg.svd(q[None, :])[2][1:3]  # two unit directions orthogonal to q
    fd = []
    for d in tangents:
        runs = [loss(advance({**scene, "orientation": tuple(q + sign * H * d)}, frames), cot) for sign in (1, -1)]
        fd.append((runs[0] - runs[1]) / (2 * H))
    out["orientation"] = dict(grad=g.tolist(), along_q=float(g @ q), tangents=[float(g @ d) for d in tangents], fd=fd)
    seconds["gradients"] = time.perf_counter() - start

    # The time-of-impact problem: the ball's vertical speed after its bounce against the throw's
    # vertical speed. Contact events (a particle's first substep inside, the count of particles
    # sharing the load) fall on substeps, so the map is piecewise smooth with jumps where an event
    # crosses a substep: the gradient is the slope between jumps (central differences of step H
    # agree), not the slope of the map over a window holding many jumps (a line fitted to samples).
    frames = 30
    cot = {"v": np.zeros((frames + 1, 1, 3))}
    cot["v"][frames, 0, 1] = 1.0
    speeds = np.linspace(-1.01, -0.99, 11)
    for name, extra in (("plain", {}), ("materials", {"restitution": 0.6125})):
        scene = {**BOUNCE, **extra}
        g = float(rigid.gradient(scene, frames, cot, ["initial_velocity"])["initial_velocity"][1])
        local = central(scene, frames, cot, "initial_velocity", 1)
        samples = [advance({**scene, "initial_velocity": (0.8, float(v), 0.4)}, frames)["v"][frames, 0, 1] for v in speeds]
        out[f"toi_{name}"] = dict(grad=g, local=local, window_slope=float(np.polyfit(speeds, samples, 1)[0]),
                                  samples=[float(v) for v in samples])
    seconds["toi"] = time.perf_counter() - start

    # Fitting: e = 0.6 and v0 from a recording, from e = 0.4 and v0 20 % off; then 2 mm of noise on x.
    frames = 30
    true = {**BOUNCE, "restitution": 0.6}
    observed = advance(true, frames)
    guess = {**true, "restitution": 0.4, "initial_velocity": tuple(0.8 * np.array(true["initial_velocity"]))}
    for name, noise in (("fit", 0.0), ("fit_noise", 0.002)):
        data = dict(observed, x=observed["x"] + np.random.default_rng(7).normal(0.0, noise, observed["x"].shape))
        fitted, info = rigid.fit(guess, data, ["restitution", "initial_velocity"], steps=60)
        seconds[name] = time.perf_counter() - start
        out[name] = dict(e=fitted.restitution, v0=list(fitted.initial_velocity), loss=info["loss"],
                         evaluations=info["evaluations"])
    out["repeat"] = repeat()
    g = rigid.gradient(FLOAT32_CASE["scene"], FLOAT32_CASE["frames"], float32_case_cotangent(), FLOAT32_CASE["wrt"])
    out["float32_reference"] = np.concatenate([np.ravel(g[n]) for n in FLOAT32_CASE["wrt"]]).tolist()
    seconds["total"] = time.perf_counter() - start
    out["seconds"] = seconds
    print(json.dumps(out))


if __name__ == "__main__":
    main()
