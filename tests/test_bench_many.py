"""scripts/bench_many.py --quick runs and writes the report's keys (speeds are never asserted).

It runs in this worker (the "engine" group, conftest.GROUPS), through the script's own ``main``:
the kernels it compiles are the group's, where a process of its own compiled them again."""
import importlib.util
import json
import math

from conftest import ROOT


def test_bench_many_quick(tmp_path, units, capsys):
    spec = importlib.util.spec_from_file_location("bench_many_script", ROOT / "scripts" / "bench_many.py")
    script = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(script)
    assert script.main(["--quick", "--out", str(tmp_path)]) == 0
    assert f"wrote {tmp_path / 'bench_many.md'}" in capsys.readouterr().out
    report = json.loads((tmp_path / "bench_many.json").read_text())
    assert {"machine", "peers", "fixed", "pile_27", "scaling", "pile_scaling", "thousand"} <= set(report)
    (peers,) = report["peers"]  # ours at least (PyBullet and MuJoCo where installed), sleep on and off
    assert peers["bodies"] == 27 and len(peers["wall_per_sim_s"]) >= 2, peers
    assert {"cpu_count", "loadavg_1_5_15"} <= set(report["machine"])
    assert {"engine_us_per_substep", "particles", "mujoco_version"} <= set(report["pile_27"])
    assert report["scaling"] and {"particles", "us_per_substep", "contact_us_per_substep", "path"} <= set(report["scaling"][0])
    assert {"fps", "contact_fps", "particles", "bodies"} <= set(report["thousand"])
    fixed = report["fixed"]  # two small piles: a line through two points
    # (the slope of two timings: any finite number, zero where they tie on a loaded machine)
    assert [r["particles"] for r in fixed["rows"]] == [84, 168] and math.isfinite(fixed["ns_per_particle"]), fixed
    assert "fixed cost per substep" in (tmp_path / "bench_many.md").read_text()
    (pile,) = report["pile_scaling"]  # the quick run: the 27-sphere pile only
    assert pile["bodies"] == 27 and pile["particles"] == 27 * 42, pile
    assert pile["contact_ns_per_particle_substep"] > 0 and pile["contact_rebuilds_per_substep"] >= 0
    md = (tmp_path / "bench_many.md").read_text()
    assert md.startswith("# Many-body benchmark") and "| 27 | 1,134 | serial |" in md
    assert (tmp_path / "figures" / "many_scaling.png").stat().st_size > 0
