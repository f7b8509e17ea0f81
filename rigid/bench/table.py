"""The benchmark's table, goals and files (JSON, Markdown); numbers come from scripts/bench.py."""
from __future__ import annotations

import json
import sys
from pathlib import Path


from rigid.run.atomic import atomic_output

HEADER = ["body", "particles", "engine path", "handout loop µs", "engine µs", "MuJoCo µs",
          "speed-up vs handout", "engine / MuJoCo", "particles/s (engine)"]

# The goals: (label, row body prefix, quantity, bound, "ge" | "le").
GOALS = [("sphere: >= 50x the handout loop", "sphere", "speedup", 50.0, "ge"),
         ("torus: >= 50x the handout loop", "torus", "speedup", 50.0, "ge"),
         ("sphere: <= 1.0x MuJoCo per step", "sphere", "mujoco_ratio", 1.0, "le"),
         ("torus: <= 2.0x MuJoCo per step", "torus", "mujoco_ratio", 2.0, "le"),
         ("1M cube in flight: <= 5 ms per substep on this CPU", "cube (1,000,000 particles), in flight",
          "engine_us", 5000.0, "le"),
         ("1M cube on the floor: <= 5 ms per substep on this CPU", "cube (1,000,000 particles), on the floor",
          "engine_us", 5000.0, "le")]


def derived(row: dict) -> dict:
    """Speed-up, MuJoCo ratio and particle rate of a row (None where a side is missing)."""
    engine = row["engine_us"]
    mujoco = row.get("mujoco_us")
    return dict(speedup=row["baseline_us"] / engine,
                mujoco_ratio=engine / mujoco if mujoco else None,
                particles_per_s=row["particles"] / (engine * 1e-6))


def _fmt(value, spec: str) -> str:
    return "–" if value is None else format(value, spec)


def cells(row: dict) -> list[str]:
    d = derived(row)
    return [row["body"], f"{row['particles']:,}", row["engine_path"], _fmt(row["baseline_us"], ".1f"),
            _fmt(row["engine_us"], ".2f"), _fmt(row.get("mujoco_us"), ".2f"), _fmt(d["speedup"], ".0f") + "x",
            _fmt(d["mujoco_ratio"], ".2f"), _fmt(d["particles_per_s"], ".3g")]


def header_line() -> str:
    return " | ".join(HEADER)


def row_line(row: dict) -> str:
    return " | ".join(cells(row))


def table(rows: list[dict]) -> dict:
    return dict(header=HEADER, rows=[cells(r) for r in rows])


# The command line's goals: (label, body prefix, quantity, bound, sense); quantities from command_line rows.
CLI_GOALS = [("sphere: command line <= 1.5x the engine per substep", "sphere", "cli_ratio", 1.5, "le"),
             ("sphere: command line with --export <= 1.5x the engine", "sphere", "export_ratio", 1.5, "le"),
             ("torus: command line <= 1.5x the engine per substep", "torus", "cli_ratio", 1.5, "le"),
             ("torus: command line with --export <= 1.5x the engine", "torus", "export_ratio", 1.5, "le"),
             ("sphere: command line >= 50x the handout loop", "sphere", "cli_speedup", 50.0, "ge"),
             ("sphere: command line <= 1.0x MuJoCo per step", "sphere", "cli_mujoco", 1.0, "le")]


def cli_derived(result: dict, c: dict) -> dict:
    row = next((r for r in result["rows"] if r["body"] == c["body"]), {})
    handout, mujoco = row.get("baseline_us"), row.get("mujoco_us")
    return dict(cli_ratio=c["cli_us"] / c["engine_us"], export_ratio=c["cli_export_us"] / c["engine_us"],
                cli_speedup=handout / c["cli_us"] if handout else None,
                cli_mujoco=c["cli_us"] / mujoco if mujoco else None)


def goals(result: dict) -> list[dict]:
    """Each goal's value and whether it is met (None: not measured)."""
    found = []
    for label, body, key, bound, sense in GOALS:
        row = next((r for r in result["rows"] if r["body"].startswith(body)), None)
        found.append((label, bound, sense, None if row is None else (row[key] if key in row else derived(row)[key])))
    for label, body, key, bound, sense in CLI_GOALS if result.get("command_line") else ():
        c = next((c for c in result["command_line"] if c["body"].startswith(body)), None)
        found.append((label, bound, sense, None if c is None else cli_derived(result, c)[key]))
    return [dict(goal=label, value=value,
                 met=None if value is None else (value >= bound if sense == "ge" else value <= bound))
            for label, bound, sense, value in found]


def markdown(result: dict) -> str:
    t = result["table"]
    lines = ["| " + " | ".join(t["header"]) + " |", "|" + "---|" * len(t["header"])]
    lines += ["| " + " | ".join(r) + " |" for r in t["rows"]]
    s = result["scenario"]
    notes = [f"Machine: {result['machine']}; Taichi {result['taichi']}, CPU backend, {s['precision']}; "
             f"MuJoCo {result['mujoco'] or 'not installed'}.",
             f"Δt = {s['dt']:g} s, {s['substeps_per_frame']} substeps per frame; µs per substep = median over "
             "repeats of the wall time of whole frames / substeps. Sphere and torus: thrown from the centre "
             f"(v0 = {s['initial_velocity']}, ω0 = {s['initial_angular_velocity']}) for "
             f"{result['rows'][0]['frames']} frames; the cube is volume-sampled (rigid.bodies.sampling).",
             "Handout loop: one kernel launch per substep from Python, parallel particle loops, atomic sums "
             "(scripts/bench_handout.py). MuJoCo: the same box and Δt, Euler, the mesh's convex hull "
             "(a box geom for the cube), mj_step(nstep=16) per frame.",
             "The machine is shared (other jobs ran during the measurement; load averages "
             f"{sorted({r.get('load_average') for r in result['rows']} - {None})} at the rows' ends), "
             "so timings vary by up to 2x between runs; the launch-bound handout loop varies most."]
    if result.get("command_line"):
        notes.append(command_line_markdown(result))
    if result.get("startup"):
        st = result["startup"]
        notes.append(f"Start-up, `python rigid_body_dynamic.py --headless --frames 1` (command to first frame "
                     f"and exit): {st['cold_cache_s']} s with an empty kernel cache, {st['warm_cache_s']} s warm.")
    if result.get("memory"):
        m = result["memory"]
        notes.append(f"Peak memory (RSS) of a process running the {m['cube_particles']:,}-particle cube: "
                     f"{m['cube_peak_rss_mib']} MiB (the 42-particle sphere: {m['sphere_peak_rss_mib']} MiB).")
    if result.get("crossover"):
        lines_c = ["| particles | serial flight µs | parallel flight µs | serial floor µs | parallel floor µs |",
                   "|---|---|---|---|---|"]
        lines_c += [f"| {c['particles']:,} | {c['serial_flight_us']:.1f} | {c['parallel_flight_us']:.1f} | "
                    f"{c['serial_floor_us']:.1f} | {c['parallel_floor_us']:.1f} |" for c in result["crossover"]]
        notes.append("Serial vs parallel path (volume-sampled cubes, per substep):\n\n" + "\n".join(lines_c))
    goal_lines = [f"- {g['goal']}: {_fmt(g['value'], '.3g')} — "
                  f"{'met' if g['met'] else 'not met' if g['met'] is not None else 'not measured'}"
                  for g in result["goals"]]
    return "\n".join(lines) + "\n\n" + "\n\n".join(notes) + "\n\nGoals (reported, not asserted):\n\n" + \
        "\n".join(goal_lines) + "\n"


CLI_HEADER = ["body", "engine µs", "command line µs", "with --export µs", "command line / engine",
              "with export / engine", "vs handout loop", "command line / MuJoCo"]


def command_line_markdown(result: dict) -> str:
    """The command line's figures beside the engine's, per substep (rigid.bench.command_line)."""
    lines = ["| " + " | ".join(CLI_HEADER) + " |", "|" + "---|" * len(CLI_HEADER)]
    for c in result["command_line"]:
        row = next((r for r in result["rows"] if r["body"] == c["body"]), {})
        handout, mujoco = row.get("baseline_us"), row.get("mujoco_us")
        lines.append("| " + " | ".join([
            c["body"], f"{c['engine_us']:.2f}", f"{c['cli_us']:.2f}", f"{c['cli_export_us']:.2f}",
            f"{c['cli_us'] / c['engine_us']:.2f}", f"{c['cli_export_us'] / c['engine_us']:.2f}",
            _fmt(handout / c["cli_us"] if handout else None, ".0f") + ("x" if handout else ""),
            _fmt(c["cli_us"] / mujoco if mujoco else None, ".2f")]) + " |")
    first = result["command_line"][0]
    return ("The command line, as a user runs it: whole `python rigid_body_dynamic.py --headless --frames N` "
            "processes, (median wall of a long run − median wall of a short one) / (extra frames × 16 substeps), "
            f"{first['frames_long'] - first['frames_short']:,} extra frames for the sphere "
            "(rigid/bench/command_line.py); the engine column is the in-process figure above. Load averages "
            f"{[c.get('load_average') for c in result['command_line']]} at the rows' ends:\n\n" +
            "\n".join(lines))


def write(result: dict, json_path: Path, md_path: Path) -> None:
    with atomic_output(json_path) as tmp:
        Path(tmp).write_text(json.dumps(result, indent=1) + "\n")
    with atomic_output(md_path) as tmp:
        Path(tmp).write_text("# Benchmark\n\n" + markdown(result))
