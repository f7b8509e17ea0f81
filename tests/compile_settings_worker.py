"""A one-thread loop that reads and writes array elements through pointer statements of their
own, compiled as for users: with the serial frame kernel's settings (rigid.runtime.CSE_OFF), and
with Taichi's whole-kernel CSE off but its loop-invariant caching left on. Prints the arrays and
the frame kernel's settings as JSON (tests/test_compile_settings.py judges them)."""
import json
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

import numpy as np  # noqa: E402
import taichi as ti  # noqa: E402

import rigid  # noqa: E402
from rigid.runtime import CSE_OFF, compile_settings  # noqa: E402

STEPS = 5


@ti.func
def get(ints: ti.template(), slot: ti.template()):
    return ints[slot]


@ti.func
def put(ints: ti.template(), slot: ti.template(), value):
    ints[slot] = value


@ti.kernel
def count(ints: ti.types.ndarray(dtype=ti.i32, ndim=1), steps: ti.i32, flag: ti.template(), counter: ti.template()):
    # The broadphase's pattern (neighbours.start_build, clear_flag): a flag raised and read back,
    # a counter bumped while it is up, the flag lowered; every access a helper's, so each is a
    # pointer statement of its own until a CSE pass merges them. Right: flag 0, counter = steps.
    # (Two slot pairs: two kernels, which Taichi's disk cache keeps apart; its key leaves out the
    # caching flag.)
    ti.loop_config(serialize=True)
    for _ in range(1):
        for e in range(steps):
            put(ints, flag, get(ints, flag) + 1)
            if get(ints, flag) > 0:
                put(ints, counter, get(ints, counter) + 1)
            put(ints, flag, 0)


def run(slots, **settings) -> list:
    ints = ti.ndarray(ti.i32, 4)
    ints.from_numpy(np.zeros(4, np.int32))
    with compile_settings(**settings):
        count(ints, STEPS, *slots)
    return ints.to_numpy()[list(slots)].tolist()


def main() -> None:
    rigid.init("cpu")
    from rigid.engine.kernels import engine_kernels
    from rigid.engine.units import default_units

    frame_kernel = engine_kernels(default_units(), "euler", True).run_frames
    print(json.dumps(dict(frame_kernel=frame_kernel.settings, engine=run((0, 1), **CSE_OFF),
                          caching_on=run((2, 3), **{**CSE_OFF, "cache_loop_invariant_global_vars": True}))))


if __name__ == "__main__":
    main()
