"""scripts/bench_many.py --quick runs and writes the report's keys (speeds are never asserted)."""
import json
import subprocess
import sys

from conftest import ROOT


def test_bench_many_quick(tmp_path):
    proc = subprocess.run([sys.executable, str(ROOT / "scripts" / "bench_many.py"), "--quick", "--out", str(tmp_path)],
                          capture_output=True, text=True, timeout=120)
    assert proc.returncode == 0, proc.stderr
    report = json.loads((tmp_path / "bench_many.json").read_text())
    assert {"machine", "pile_27", "scaling", "thousand"} <= set(report)
    assert {"cpu_count", "loadavg_1_5_15"} <= set(report["machine"])
    assert {"engine_us_per_substep", "particles", "mujoco_version"} <= set(report["pile_27"])
    assert report["scaling"] and {"particles", "us_per_substep", "contact_us_per_substep", "path"} <= set(report["scaling"][0])
    assert {"fps", "contact_fps", "particles", "bodies"} <= set(report["thousand"])
    assert (tmp_path / "bench_many.md").read_text().startswith("# Many-body benchmark")
    assert (tmp_path / "figures" / "many_scaling.png").stat().st_size > 0
