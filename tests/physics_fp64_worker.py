"""The float64 physics runs of the test suite, in one process: prints one JSON object.

Taichi takes one precision per process and the suite runs in float32, so the
tests start this file once (tests/physics_results.py) and judge its numbers.
Every section is a function of rigid.science.experiments; its reference (closed form,
scipy) is computed there too, outside the simulator.
"""
import json
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from rigid.science import experiments as ex  # noqa: E402
from rigid.runtime import init_taichi  # noqa: E402
from rigid.engine.units import load_units  # noqa: E402

# The flip, where explicit Euler's energy drift moves the orbit: Δt = 1e-4 keeps Euler's period
# error near 1 % (at the default 1e-3 it is 6 %: see scripts/validate.py); RK4 at 1/240 s. ω0 is rigid.science.experiments.FLIP_W0.
EULER_DTS = (1 / 250, 1 / 500, 1 / 1000)
RK4_DTS = (1 / 60, 1 / 120, 1 / 240)


def main() -> None:
    # Taichi's advanced IR optimisations off (rigid.runtime's quick_compile): these runs judge the
    # method (orders, conservation, closed forms) to tolerances far above round-off, and with them
    # off the float64 kernels compile ~3x faster in a fresh clone (the many-body worker: 83 -> 22 s,
    # the physics worker: 31 -> 12 s; every number the tests read agrees to round-off). Float32
    # tests and the command line run the default set-up.
    init_taichi("cpu", fp64=True, quick_compile=True)
    get = ex.SimulatorCache(load_units(ROOT / "rigid_body_dynamic.py"), fp64=True)
    out, seconds = {}, {}

    def run(name, fn, *args, **kwargs):
        start = time.perf_counter()
        out[name] = fn(get, *args, **kwargs)
        seconds[name] = round(time.perf_counter() - start, 3)

    run("free_fall_euler", ex.free_fall, "euler")
    run("free_fall_symplectic", ex.free_fall, "symplectic")
    run("angular_momentum", ex.angular_momentum_drift, "euler")
    run("rotational_energy", ex.rotational_energy_drift, "euler", (1e-3, 5e-4, 2.5e-4))
    run("accuracy_euler", ex.accuracy, "euler", EULER_DTS)
    run("accuracy_symplectic", ex.accuracy, "symplectic", EULER_DTS)
    run("accuracy_rk4", ex.accuracy, "rk4", RK4_DTS)
    run("flip_euler", ex.flip, "euler", 1e-4, ex.FLIP_W0, duration=7.0)
    run("flip_rk4", ex.flip, "rk4", 1 / 240, ex.FLIP_W0, duration=7.0)
    for axis in (0, 1, 2):
        run(f"spin_axis_{axis}", ex.axis_stability, axis)
    run("drop", ex.symmetric_drop)
    # The models' mass properties, for the tests to recompute with numpy.
    t_handle = get(**ex.T_HANDLE).model
    sphere = get(particles="volume", grid=10).model
    out["models"] = {name: dict(mass=m.mass, particle_mass=float(m.particle_mass.to_numpy()[0]),
                                count=m.num_particles, inertia=m.inertia_body_np[0].tolist(),
                                center_of_mass=m.center_of_mass_np[0].tolist())
                     for name, m in (("t_handle", t_handle), ("sphere_volume_10", sphere))}
    out["seconds"] = seconds
    json.dump(out, sys.stdout, default=float)


if __name__ == "__main__":
    main()
