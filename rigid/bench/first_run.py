"""What a user waits for the first time: every shipped scene's command line, cold and warm.

For each scene of assets/scenes, ``rigid_body_dynamic.py --headless --scene S --frames 60``
runs as a whole process with an empty Taichi kernel cache (a fresh folder named by
TI_OFFLINE_CACHE_FILE_PATH, so every kernel compiles), then once more on the cache that run
left (warm). Wall seconds from the start of the process to its exit; reported, never asserted.

``trees`` (source trees of the project, e.g. a worktree of an older commit) run interleaved,
scene by scene, so a before/after pair shares the machine's load of the moment.
"""
from __future__ import annotations

import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
FRAMES = 60


def wall(tree: Path, scene: Path, cache: Path, timeout: float = 900) -> float:
    """Seconds the command line takes on ``tree``'s code with kernel cache folder ``cache``."""
    env = {k: v for k, v in os.environ.items() if k != "RIGID_QUICK_COMPILE"}  # a user's defaults
    env.update(TI_OFFLINE_CACHE_FILE_PATH=str(cache), PYTHONPATH=str(tree))
    command = [sys.executable, str(tree / "rigid_body_dynamic.py"), "--headless", "--scene", str(scene),
               "--frames", str(FRAMES)]
    began = time.perf_counter()
    proc = subprocess.run(command, cwd=tree, env=env, capture_output=True, text=True, timeout=timeout)
    if proc.returncode:
        raise RuntimeError(f"{scene.name} on {tree}: {proc.stderr.strip().splitlines()[-1:]}")
    return time.perf_counter() - began


def label(tree: Path) -> str:
    """A tree's name in the tables: its commit (and "+" if it has changes), else its folder's name."""
    try:
        commit = subprocess.run(["git", "-C", str(tree), "rev-parse", "--short", "HEAD"], capture_output=True,
                                text=True, check=True).stdout.strip()
        dirty = subprocess.run(["git", "-C", str(tree), "status", "--porcelain", "--untracked-files=no"],
                               capture_output=True, text=True, check=True).stdout.strip()
        return commit + ("+" if dirty else "")
    except (OSError, subprocess.CalledProcessError):
        return tree.name


def run(out: Path, trees: list[Path], scenes: list[Path] | None = None) -> dict:
    """Cold and warm walls of each scene on each tree; writes bench_first_run.json/.md to ``out``."""
    scenes = scenes or sorted((ROOT / "assets" / "scenes").glob("*.toml"))
    rows = []
    for scene in scenes:
        row = dict(scene=scene.stem, trees={})
        for tree in trees:
            with tempfile.TemporaryDirectory(prefix="ticache-") as cache:
                cold = wall(tree, scene, Path(cache))
                warm = wall(tree, scene, Path(cache))
            row["trees"][str(tree)] = dict(cold_s=round(cold, 2), warm_s=round(warm, 2))
            print(f"{scene.stem:>20} {tree}: cold {cold:.1f} s, warm {warm:.1f} s", flush=True)
        rows.append(row)
    result = dict(frames=FRAMES, trees=[str(t) for t in trees], labels=[label(t) for t in trees], rows=rows)
    out.mkdir(parents=True, exist_ok=True)
    (out / "bench_first_run.json").write_text(json.dumps(result, indent=1) + "\n")
    (out / "bench_first_run.md").write_text(markdown(result))
    return result


def markdown(result: dict) -> str:
    trees = result["trees"]
    names = result.get("labels") or [Path(t).name for t in trees]
    lines = ["# First run of each shipped scene (scripts/bench_first_run.py)", "",
             f"Whole `rigid_body_dynamic.py --headless --scene S --frames {result['frames']}` processes, wall "
             "seconds: cold with an empty kernel cache, then warm on the cache it left. One process each; "
             "trees interleaved scene by scene.", ""]
    head = " | ".join(f"{name} cold | {name} warm" for name in names)
    lines += [f"| scene | {head} |", "|---|" + "---|" * (2 * len(trees))]
    for row in result["rows"]:
        cells = " | ".join(f"{row['trees'][t]['cold_s']:.1f} | {row['trees'][t]['warm_s']:.1f}" for t in trees)
        lines.append(f"| {row['scene']} | {cells} |")
    return "\n".join(lines) + "\n"
