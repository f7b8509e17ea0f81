"""report/bench_many.md from the benchmark's JSON (rigid.bench.many): one section per part run."""


def markdown(r: dict) -> str:
    from . import fixed_cost, peers, pile_scaling, sleeping

    m = r["machine"]
    lines = ["# Many-body benchmark", "",
             f"CPU, float32, {m['cpu_count']} CPUs, load average {m['loadavg_1_5_15']} (1/5/15 min) at the "
             "start: other processes shared these cores during the run, so the times are noisy "
             "and are reported, never asserted. Medians over repeats.", ""]
    if r.get("peers"):
        lines += peers.markdown(r["peers"], r.get("peer_versions", {}))
    if r.get("sleeping"):
        lines += sleeping.markdown(r["sleeping"])
    if r.get("fixed"):
        lines += fixed_cost.markdown(r["fixed"])
    if r.get("profile"):
        lines += ["## Where a substep's time goes (each stage alone, one thread, µs per substep)", "",
                  "At 1 s (falling, in contact); the full rebuild (grid and neighbour lists) counted at its measured "
                  "rate (rigid/bench/profile.py). The partial rebuilds (rigid/engine/refresh.py) are not timed "
                  "alone (each makes again only the lists of the bodies that moved): the whole substep, as the "
                  "engine runs it, includes them.", "",
                  "| scene | particles | whole substep | place | full rebuild (each) | full rebuilds/substep "
                  "| partial rebuilds/substep | pairs | blocks | update |",
                  "|---|---|---|---|---|---|---|---|---|---|"]
        for name, p in r["profile"].items():
            s, e = p["per_substep_us"], p["stage_us"]
            lines.append(f"| {name} | {p['particles']:,} | {p['whole_us']:,} | {s['place']} | {s['rebuild']} "
                         f"({e['rebuild']:,}) | {p['rebuilds_per_substep']} | {p.get('refreshes_per_substep', '')} | "
                         f"{s['pairs']} | {s['blocks']} | {s['update']} |")
        lines.append("")
    if any(k in r for k in ("pile_125", "pile_27")):
        lines += ["## Pile of vertex spheres (42 vertices, scale 0.15, Δt = 1e-3), side by side with MuJoCo", "",
                  "The handout's materials (1 kg particles, damping 1e3), MuJoCo's Euler at the same 1 ms. Repeats of "
                  "the engine and MuJoCo alternate (same load, same stretch of simulated time: `simulated_s` in the "
                  "JSON). Ratio < 1: the engine is faster.", "",
                  "| bodies | particles | engine µs/substep | MuJoCo µs/step | engine / MuJoCo |", "|---|---|---|---|---|"]
        for key in ("pile_125", "pile_27"):
            p = r.get(key)
            if p:
                mj = p.get("mujoco_us_per_step", "not installed")
                lines.append(f"| {p['bodies']} | {p['particles']:,} | {p['engine_us_per_substep']:,} | {mj} | "
                             f"{p.get('ratio_engine_over_mujoco', '-')} |")
        lines.append("")
    if r.get("scaling"):
        lines += ["## Cost per substep against particle count (125 volume-sampled spheres)", "",
                  "The same simulated windows at every size: falling (frames 2-7, no contact yet) and in "
                  "contact (frames 61-66, the pile formed). A particle weighs 1 kg at every grid, so finer spheres "
                  "are heavier on the same springs and sink into one another: at 1 s their centres are 0.47-0.66 of "
                  "a diameter apart at 21,375 and 54,000 particles, and 37-50 % of the particles touch another "
                  "body's (measured at 4,000-54,000; `pile_scaling` below keeps the bodies' weight).", "",
                  "![scaling](figures/many_scaling.png)", "",
                  "| particles | grid | path | µs/substep falling | ns per particle-substep | µs/substep in contact "
                  "| ns per particle-substep |", "|---|---|---|---|---|---|---|"]
        lines += [f"| {p['particles']:,} | {p['grid']} | {p['path']} | {p['us_per_substep']:,} | "
                  f"{p['ns_per_particle_substep']} | {_get(p, 'contact_us_per_substep', ',')} | "
                  f"{_get(p, 'contact_ns_per_particle_substep')} |" for p in r["scaling"]]
        lines.append("")
    if r.get("pile_scaling"):
        lines += pile_scaling.markdown(r["pile_scaling"])
    t = r.get("thousand")
    if t:
        lines += ["## 1,000 bodies", "",
                  f"{t['bodies']:,} volume spheres (scale {t['scale']}, grid {t['grid']}), {t['particles']:,} particles: "
                  f"{t['ms_per_frame']} ms per frame of {t['substeps_per_frame']} substeps = **{t['fps']} frames per "
                  "second** while they fall (frames 3-17, the pile forming in the last repeats: "
                  f"{', '.join(map(str, t.get('fps_repeats', [])))}), "
                  + (f"**{t['contact_fps']}** in contact (frames 61-66, {t['contact_ms_per_frame']} ms a frame)"
                     if "contact_fps" in t else "in contact not measured")
                  + " (engine only, headless, no drawing).", ""]
    return "\n".join(lines)


def _get(point: dict, key: str, spec: str = "") -> str:
    """A scaling point's value, or "–" where an older run did not measure it."""
    return format(point[key], spec) if key in point else "–"
