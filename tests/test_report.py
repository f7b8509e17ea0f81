"""scripts/make_report.py: the report regenerates identically and its PDF holds the figures.

The first build is the command line in a process of its own; the second is the same build
(rigid.report.build.build) in this worker, which runs the "engine" group (conftest.GROUPS) and
so has the scenes' kernels compiled: measured ~5-6 s there, against 9.4 s for a second process
with a warm disk cache. Two processes, two orders of compiling, the same bytes."""
import shutil
import subprocess
import sys

from conftest import ROOT


def test_report_regenerates_identically_with_figures(tmp_path, units, capsys):
    outs = [tmp_path / "a", tmp_path / "b"]
    for out in outs:  # reuse the committed validation and benchmarks (slow scripts of their own)
        (out / "figures").mkdir(parents=True)
        for name in ("validation.json", "bench.json", "bench_many.json", "figures/many_scaling.png"):
            shutil.copy(ROOT / "report" / name, out / name)
    proc = subprocess.run([sys.executable, "scripts/make_report.py", "--quick", "--out", str(outs[0])],
                          cwd=ROOT, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, timeout=300)
    assert proc.returncode == 0, proc.stdout
    from rigid.report.build import build

    build(outs[1], quick=True)  # on the worker's Taichi (the units fixture: cpu, float32), as main's
    assert f"wrote {outs[1] / 'report.md'}" in capsys.readouterr().out

    a, b = outs
    md = (a / "report.md").read_text().splitlines()
    assert md[0].startswith("Name:") and md[2].startswith("UID:")  # the handout's two first lines
    figures = sorted(p.name for p in (a / "figures").glob("*.png"))
    for name in ("energy_assignment.png", "energy_thrown_sphere.png", "energy_tumbling_t_handle.png",
                 "trajectory_thrown_sphere.png", "flip.png", "convergence.png",
                 "many_pile.png", "many_dominoes.png", "energy_pile.png", "many_scaling.png"):
        assert name in figures
        assert f"figures/{name}" in (a / "report.md").read_text()
    for name in figures:  # fixed seeds, deterministic simulation and drawing: same bytes
        assert (a / "figures" / name).read_bytes() == (b / "figures" / name).read_bytes(), name
    assert (a / "report.pdf").read_bytes() == (b / "report.pdf").read_bytes()

    from pypdf import PdfReader

    pdf = PdfReader(a / "report.pdf")
    images = sum(len(page.images) for page in pdf.pages)
    assert len(pdf.pages) >= 3 and images == len(figures)
    assert "UID" in pdf.pages[0].extract_text()
