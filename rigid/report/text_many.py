"""The report's many-bodies section: how bodies collide, the pile and the dominoes, what was
learnt (friction, stacking), and the many-body benchmark. Numbers come from the runs
(rigid.report.many) and report/bench_many.json, never typed in: the report states what was
measured (a student hands it in; the project's own goals are not its business)."""
from __future__ import annotations

from pathlib import Path

from rigid.bench.peers import table


def write(doc, out: Path, pile: dict, dominoes: dict, bench: dict | None) -> None:
    doc.heading("Many bodies", 2)
    doc.para(PIPELINE)
    doc.image(pile["path"], f"`assets/scenes/pile.toml`: {pile['bodies']} bodies of five meshes, "
              f"{pile['particles']:,} volume particles, {pile['integrator']}, {pile['substeps']} substeps "
              f"per frame, at t = {_times(pile)} s. Drawn offscreen by the project's Taichi rasteriser "
              "(`rigid/view/raster.py`), each body in its own colour.")
    total = pile["kinetic_energy"] + pile["potential_energy"]
    rise = float((total - _running_min(total)).max())
    t, end = pile["t"], pile["t"][-1]
    lowest = "" if total.min() == total[-1] else f", {total.min():.1f} J at the lowest"
    doc.image(out / "figures" / "energy_pile.png",
              f"The pile's energies (totals over the bodies): {total[0]:.1f} J at the start{lowest}, "
              f"{total[-1]:.1f} J at t = {end:.2f} s, when the kinetic energy is {pile['kinetic_energy'][-1]:.2g} J. "
              "Falling bodies turn potential into kinetic energy; the contacts' damping and friction take it "
              "out. " + _rise(rise) + (f" From t = 1 s on the pile still compacts slowly: the total falls a "
              f"further {total[t >= 1.0][0] - total[-1]:.1f} J by the end." if end > 2.0 else ""))
    fallen = ", ".join(str(n) for n in dominoes["fallen"])
    doc.image(dominoes["path"], f"`assets/scenes/dominoes.toml`: {dominoes['bodies']} dominoes "
              f"({dominoes['particles']:,} particles); the first starts tipped with a push and each topples "
              f"the next. At t = {_times(dominoes)} s, {fallen} of {dominoes['bodies']} lean more than 45°.")
    doc.para(FRICTION)
    doc.para(STACK)
    _bench(doc, out, bench)


def _bench(doc, out: Path, bench: dict | None) -> None:
    doc.heading("Speed with many bodies", 3)
    if not bench or "pile_125" not in bench:
        doc.para("(run `python scripts/bench_many.py` to add the many-body benchmark)")
        return
    machine, pile, thousand = bench["machine"], bench["pile_125"], bench.get("thousand", {})
    load = machine.get("loadavg_1_5_15", ["?"])[0]
    ratio = pile.get("ratio_engine_over_mujoco")
    text = (f"`python scripts/bench_many.py` (`report/bench_many.md`), float32 on the CPU: "
            f"{machine.get('cpu_count', '?')} CPUs, shared, with a load average of {load} at the start; "
            "other processes ran on the same cores, so these times are noisy. Measured:")
    doc.para(text)
    items = []
    if ratio is not None:
        items.append(f"a 125-sphere pile: the engine takes **{ratio:.2f}×** MuJoCo's time per step "
                     f"({1 / ratio:.1f} times as fast as MuJoCo);")
    if thousand:
        contact = (f", **{thousand['contact_fps']:.1f}** in contact (from 1 s, "
                   f"{thousand['contact_ms_per_frame']:.0f} ms a frame)" if "contact_fps" in thousand else "")
        items.append(f"1,000 bodies: **{thousand['fps']:.1f}** frames per second while they fall"
                     f"{contact} ({thousand['particles']:,} particles, {thousand['substeps_per_frame']} substeps "
                     "a frame, engine only, no drawing).")
    fixed = bench.get("fixed")
    if fixed:
        first, last = fixed["rows"][0], fixed["rows"][-1]
        items.append(f"small piles: {first['us_per_substep']:.1f} µs a substep for {first['bodies']} bodies "
                     f"({first['particles']} particles), {last['us_per_substep']:.1f} for {last['bodies']} "
                     f"({last['particles']:,}); a line through them: {fixed['fixed_us_per_substep']:.2f} µs "
                     f"fixed + {fixed['ns_per_particle']:.1f} ns a particle.")
    doc.bullets(items)
    _peers(doc, bench)
    _profile(doc, bench)
    rows = [[f"{r['bodies']}", f"{r['particles']:,}", f"{r['engine_us_per_substep']:,.0f}",
             f"{r['mujoco_us_per_step']:,.0f}", f"{r['ratio_engine_over_mujoco']:.2f}"]
            for r in (bench.get(k) for k in ("pile_125", "pile_27")) if r and "mujoco_us_per_step" in r]
    if rows:
        doc.para("Piles of vertex spheres (42 particles each, scale 0.15, Δt = 1 ms), the engine and MuJoCo "
                 "on the same pile in one process, medians over alternating repeats (ratio < 1: the "
                 "engine is faster):")
        doc.table(["bodies", "particles", "engine µs/substep", "MuJoCo µs/step", "engine / MuJoCo"], rows)
    scaling = bench.get("scaling") or []
    if (out / "figures" / "many_scaling.png").exists():
        doc.image(out / "figures" / "many_scaling.png",
                  "Cost per substep against particle count, 125 volume-sampled spheres, falling and in "
                  "contact (bench_many.py).",
                  width_cm=11)
    if scaling:
        doc.table(["particles", "path", "µs/substep falling", "ns per particle-substep", "µs/substep in contact",
                   "ns per particle-substep"],
                  [[f"{p['particles']:,}", p["path"], f"{p['us_per_substep']:,.0f}", f"{p['ns_per_particle_substep']:.0f}",
                    f"{p['contact_us_per_substep']:,.0f}" if "contact_us_per_substep" in p else "–",
                    f"{p['contact_ns_per_particle_substep']:.0f}" if "contact_us_per_substep" in p else "–"]
                   for p in scaling])
        doc.para("Those spheres grow heavier as they get finer (1 kg a particle on the same springs) and sink "
                 "into one another. With more bodies instead, the peers' 42-vertex spheres of 0.42 kg, smaller "
                 "as they multiply so that the lattice fits the box (bench_many.py's pile_scaling):")
    piles = bench.get("pile_scaling") or []
    if piles:
        doc.table(["bodies", "particles", "path", "ns/particle-substep falling", "in contact", "full rebuilds/substep",
                   "partial rebuilds/substep"],
                  [[f"{p['bodies']:,}", f"{p['particles']:,}", p["path"], f"{p['falling_ns_per_particle_substep']:.0f}",
                    f"{p['contact_ns_per_particle_substep']:.0f}", f"{p['contact_rebuilds_per_substep']:.2f}",
                    f"{p.get('contact_refreshes_per_substep', 0.0):.2f}"]
                   for p in piles])
        doc.para("A partial rebuild (rigid/engine/refresh.py) makes again only the lists of the bodies that outran "
                 "half the skin, their particles searching side by side on both threads; the whole grid and "
                 "every list are rebuilt once a refresh would cost more than the substeps since the last full "
                 "build did on average, or the refreshed bodies pass a quarter of the particles. Without it "
                 "the 24,000-body pile, whose top layer still lands at 1 s, rebuilt all 1,008,000 particles' "
                 "lists every substep: 162-172 ns a particle-substep.")


def _peers(doc, bench: dict) -> None:
    """The peers' table (rigid/bench/peers.py) and what sleeping saves (rigid/bench/sleeping.py)."""
    peers, versions = bench.get("peers") or [], bench.get("peer_versions") or {}
    if peers:
        named = ", ".join(f"{name} {v}" for name, v in (("PyBullet", versions.get("pybullet")),
                                                         ("MuJoCo", versions.get("mujoco"))) if v)
        doc.para(f"The same pile of icospheres in PyBullet and MuJoCo ({named or 'not installed'}; each "
                 "body as the same mesh, its convex hull, or as a sphere primitive of the mesh's radius), 3 s "
                 "simulated, each engine at its own default step (this engine 1 ms symplectic Euler, PyBullet "
                 "1/240 s, MuJoCo 2 ms with its CG solver), in wall seconds per simulated second (below 1: "
                 "faster than real time), medians of interleaved repeats:")
        doc.table(*table(peers))
    sleeping = bench.get("sleeping")
    if sleeping and sleeping.get("all_asleep"):
        doc.para(f"Bodies at rest sleep: {sleeping['bodies']} spheres cost {sleeping['falling_us_per_substep']:.0f} µs "
                 f"a substep while they fall and {sleeping['settled_us_per_substep']:.1f} once all are asleep "
                 f"(from {sleeping['all_asleep_at_s']:.1f} s), {100 * sleeping['settled_over_falling']:.0f} % of "
                 f"falling; the same settled pile with sleeping off: "
                 f"{sleeping['settled_sleep_off_us_per_substep']:.0f} µs.")


def _profile(doc, bench: dict) -> None:
    """Where a substep's time goes (rigid/bench/profile.py): each stage alone on one thread."""
    profile = bench.get("profile") or {}
    if not profile:
        return
    doc.para("Where a substep's time goes in contact (at 1 s), each stage timed alone on one thread, in µs a "
             "substep; the full rebuild of the grid and lists counted at its rate (its own time in brackets); "
             "the whole substep as the engine runs it, partial rebuilds included:")
    doc.table(["scene", "particles", "whole", "place", "full rebuild", "pairs", "blocks", "update"],
              [[name, f"{p['particles']:,}", f"{p['whole_us']:,.0f}", f"{p['per_substep_us']['place']:.0f}",
                f"{p['per_substep_us']['rebuild']:.0f} ({p['stage_us']['rebuild']:,.0f} every "
                f"{1 / max(p['rebuilds_per_substep'], 1e-9):.0f} substeps)",
                f"{p['per_substep_us']['pairs']:.0f}", f"{p['per_substep_us']['blocks']:.0f}",
                f"{p['per_substep_us']['update']:.0f}"] for name, p in profile.items()])


def _rise(rise: float) -> str:
    if rise <= 0.0:
        return "The total never rises from one frame to the next."
    return (f"The total rises at most {rise:.3g} J above its lowest value so far (symplectic Euler "
            "conserves a nearby energy, not the energy; the springs' stored energy counts as potential).")


def _times(run: dict) -> str:
    return ", ".join(f"{t:.2f}" for t in run["still_times"])


def _running_min(values):
    import numpy as np

    return np.minimum.accumulate(values)


PIPELINE = (
    "A scene's `[[body]]` tables put several bodies in the box, and bodies collide through their "
    "particles (Harada, GPU Gems 3, ch. 29). One substep is a pipeline of stages "
    "(`rigid/engine/substep.py`, the same for one body, without the grid and pairs): (1) every particle's position and velocity from its body's x, R, v "
    "and ω; (2) a uniform grid of cells one particle diameter wide, built by counting sort (count the "
    "particles per cell, prefix sum, scatter; no cap per cell); (3) per particle, gravity (TODO 2), "
    "the walls on its sphere, and for every overlapping particle of another body in the 27 cells "
    "around it a spring on the overlap, normal damping that never pulls, and friction. That pair force "
    "acts at the contact point in the middle of the overlap: the engine applies it at the particle "
    "centre and adds the couple (c − pᵢ) × fᵢ that moves it there, so each pair's two forces are equal "
    "and opposite at one point and conserve the total momentum and angular momentum; (4) per body, "
    "F (TODO 3) and τ (TODO 4, plus the couples) summed over its particles, then the update of x, P, q, "
    "L, I⁻¹ and ω (TODO 5, 6 and 7). Every sum has a fixed order, so a run is bit-reproducible: the "
    "figures below regenerate byte for byte.")

FRICTION = (
    "**Friction.** Every contact's friction, with the walls and between bodies, is Coulomb's μ f_n "
    "capped by viscous damping, min(μ f_n, k_d |v_t|) against the tangential velocity v_t "
    "(`rigid/engine/contact.py`: one law for walls and pairs). A viscous coefficient that grows with "
    "the load, μ f_n / v_slip (the single body's walls used it once), failed between bodies: in a "
    "stack the lower bodies carry many times their own weight, the load-scaled "
    "coefficient μ f_n / v_slip passed explicit integration's stability limit (Δt c / m < 2), and the "
    "stack tipped over. Capped at k_d, the tangential damping is no stiffer than the normal damping, "
    "which the step already resolves.")

STACK = (
    "**Stacking.** Particles stacked exactly on top of one another are balls on balls: an unstable "
    "balance that only friction holds, so a tower of boxes crept over within seconds. "
    "`assets/scenes/stack.toml` shifts every other box by half a particle spacing (2 cm in x and z), "
    "so that a box's bottom particles rest in the hollows between the particles of the box below, as "
    "oranges in a crate; the tower of six boxes then stands still.")
