"""Runs a few scenes on the backend named in argv[1] (float32) and prints their centres of mass
as JSON: {"backend": the backend Taichi ran, "<scene>": [[x, y, z] per body] per frame}. In a
process of its own: one ti.init per process. The suite compares them with the CPU's
(tests/test_backends.py)."""
import json
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

import rigid  # noqa: E402
from rigid.errors import UserError  # noqa: E402

# One frame, and scenes set up to touch early in it (a contact moves every scene's bodies 8-11 mm off
# free flight by its end): Mesa's software Vulkan runs these small scenes' shaders at ~0.02-0.1
# CPU-s a substep, so each frame costs about a second of the suite per scene.
FRAMES = 1
ASSETS = ROOT / "assets"


def scenes():
    """name -> SimConfig values: the scenes the backends must agree on (a body alone against the
    walls, explicit Euler; two bodies meeting in free space, symplectic, without and with
    materials; eight landing together, sleeping on, symplectic: head_on's kernels, so Vulkan
    compiles three sets, not four)."""
    from rigid.config import load_scene

    head_on = load_scene(ASSETS / "scenes" / "head_on.toml")  # moved closer: they meet in the first frames
    head_on["bodies"] = tuple(dict(b, position=(0.3 * b["position"][0], *b["position"][1:])) for b in head_on["bodies"])
    thrown = dict(load_scene(ASSETS / "scenes" / "thrown_sphere.toml"), position=(0.69, -0.6, 0.0))  # hits a wall
    # The materials' path (restitution and sticking friction: its own pair stage, plane law and
    # frame energy) on the same meeting.
    materials = dict(head_on, restitution=0.5, friction=0.3)
    return {"thrown_sphere": thrown, "head_on": head_on, "head_on_materials": materials,
            "pile_of_8": dict(mesh=str(ASSETS / "sphere.obj"), scale=0.15, count=8, position=(0.0, -0.84, 0.0),
                              initial_velocity=(2.0, -3.0, 1.0), integrator="symplectic")}


def run(name, values, frames=FRAMES):
    from rigid.config import SimConfig
    from rigid.engine.simulator import Simulator

    rows = Simulator(SimConfig(**values).validate()).advance_frames(frames)
    return rows["x"].tolist()


def free_flight(values, frames=FRAMES):
    """Where the bodies of ``run`` would be without any contact: x0 + v0 t + ½ g t² at the start
    (row 0) and after each frame."""
    import numpy as np

    from rigid.config import SimConfig
    from rigid.engine.simulator import Simulator

    config = SimConfig(**values).validate()
    sim = Simulator(config)
    start = sim.snapshot()
    t = (np.arange(frames + 1) * sim.substeps * config.dt)[:, None, None]
    return start["x"][None] + start["v"][None] * t + 0.5 * np.asarray(config.gravity) * t ** 2


def main():
    try:
        backend = rigid.init(sys.argv[1])
    except UserError as err:
        print(json.dumps({"backend": None, "why": str(err)}))
        return
    out = {"backend": backend}
    for name, values in scenes().items():
        out[name] = run(name, values)
    print(json.dumps(out))


if __name__ == "__main__":
    main()
