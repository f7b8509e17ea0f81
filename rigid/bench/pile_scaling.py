"""Cost per particle-substep of piles that hold their shape, from 1,000 to 1,000,000 particles.

The scaling section (rigid.bench.many.scaling) refines 125 volume spheres of 1 kg particles:
each finer sphere is heavier on the same springs, so at 1 s the spheres have sunk into one
another (centres 0.47-0.66 of a diameter apart at 21k-54k particles, measured) and every
particle has 4-7 candidates. Here the body stays the handout's 42-vertex sphere of the
peers' scene (rigid.bench.peers: 0.42 kg, the same springs at every size) and the bodies
multiply, smaller so that the lattice fits the box: 27 to 24,000 bodies, 1,134 to 1,008,000
particles. Each on its own path (serial or parallel, schedule.py), sleeping on, as a user
runs it: falling (frames 2-7) and in contact (frames 61-66: at 1 s the pile has formed),
with the neighbour-list rebuilds per substep in that window and the Simulator's build time.
"""
import statistics
import time

# (bodies, sphere scale): layers of 5 x 5 at 0.15 m; of 13 x 13, 27 x 27, 38 x 38 below.
SIZES = ((27, 0.15), (125, 0.15), (1000, 0.07), (8000, 0.035), (24000, 0.025))


def pile_point(units, count: int, scale: float) -> dict:
    import taichi as ti
    from rigid.engine.broadphase_host import refreshes_so_far
    from rigid.engine.simulator import Simulator

    from .many import CONTACT_FRAME, _step_until, time_steps
    from .peers import scene

    start = time.perf_counter()
    config, bodies = scene(count, scale=scale)
    sim = Simulator(config, units, bodies=bodies)
    sim.step_frame()
    ti.sync()
    build_s = time.perf_counter() - start
    n = sim.num_particles
    falling = statistics.median(time_steps(sim.step_frame, ti.sync, 0, 2, 3, 16))
    _step_until(sim, CONTACT_FRAME)
    builds, refreshes = sim.neighbour_builds, refreshes_so_far(sim)
    contact = time_steps(sim.step_frame, ti.sync, 0, 2, 3, 16)
    rate = (sim.neighbour_builds - builds) / (6 * sim.substeps)
    refresh_rate = (refreshes_so_far(sim) - refreshes) / (6 * sim.substeps)
    c = statistics.median(contact)
    return dict(bodies=count, scale=scale, particles=n, path=sim.schedule, build_s=round(build_s, 2),
                falling_ns_per_particle_substep=round(falling * 1e9 / n, 1),
                contact_us_per_substep=round(c * 1e6, 1), contact_ns_per_particle_substep=round(c * 1e9 / n, 1),
                contact_rebuilds_per_substep=round(rate, 3), contact_refreshes_per_substep=round(refresh_rate, 3),
                asleep=int(sim.asleep().sum()),
                neighbours_mean=round(float(sim.neighbour_counts().mean()), 2))


def pile_scaling(units, quick: bool) -> list[dict]:
    points = []
    for count, scale in (SIZES[:1] if quick else SIZES):
        points.append(pile_point(units, count, scale))
        p = points[-1]
        print(f"  {count:,} bodies ({p['particles']:,} particles, {p['path']}): {p['falling_ns_per_particle_substep']} "
              f"ns a particle-substep falling, {p['contact_ns_per_particle_substep']} in contact", flush=True)
    return points


def markdown(points: list[dict]) -> list[str]:
    lines = ["## Piles that hold their shape: cost per particle-substep from 1k to 1M particles", "",
             "The peers' 42-vertex spheres (0.42 kg, the same springs) in larger and larger piles, smaller spheres "
             "so that the lattice fits the box (rigid/bench/pile_scaling.py); sleeping on, each on its own path. "
             "Falling: frames 2-7; in contact: frames 61-66 (the pile formed at 1 s). Build: the scene, the "
             "Simulator and its first frame (kernels already compiled after the first row).", "",
             "| bodies | particles | path | build s | ns/particle-substep falling | µs/substep in contact "
             "| ns/particle-substep in contact | full rebuilds/substep | partial (refresh.py) | asleep |",
             "|---|---|---|---|---|---|---|---|---|---|"]
    lines += [f"| {p['bodies']:,} | {p['particles']:,} | {p['path']} | {p['build_s']} | "
              f"{p['falling_ns_per_particle_substep']} | {p['contact_us_per_substep']:,} | "
              f"{p['contact_ns_per_particle_substep']} | {p['contact_rebuilds_per_substep']} | "
              f"{p.get('contact_refreshes_per_substep', '')} | {p['asleep']:,} |"
              for p in points]
    return lines + [""]
