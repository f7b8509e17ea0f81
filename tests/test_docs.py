"""The documentation site builds with ``mkdocs build --strict``: every link and every API
reference resolves, and the performance tables come from report/*.json. A page with a broken
link fails the build (checked on a copy). Needs the docs extra (scripts/setup.sh installs it)."""
import os
import shutil
import subprocess
import sys

import pytest

from conftest import ROOT

pytest.importorskip("mkdocs", reason="the docs extra is not installed: pip install -e '.[docs]'")
pytest.importorskip("mkdocstrings", reason="the docs extra is not installed: pip install -e '.[docs]'")


def _build(project, site):
    env = dict(os.environ, NO_MKDOCS_2_WARNING="1")
    return subprocess.run([sys.executable, "-m", "mkdocs", "build", "--strict", "-f",
                           str(project / "mkdocs.yml"), "-d", str(site)], capture_output=True, text=True,
                          timeout=300, env=env)


def test_the_site_builds_strict_with_the_api_and_the_report_tables(tmp_path):
    proc = _build(ROOT, tmp_path / "site")
    assert proc.returncode == 0, proc.stdout + proc.stderr
    api = (tmp_path / "site" / "api" / "index.html").read_text()
    assert "advance_frames" in api and "load_scene" in api  # made from the docstrings
    performance = (tmp_path / "site" / "performance" / "index.html").read_text()
    assert "<!-- report:" not in performance and performance.count("<table>") >= 5
    physics = (tmp_path / "site" / "physics" / "index.html").read_text()
    assert "<!-- report:" not in physics and "PyBullet hull" in physics  # report/contact.json's table
    assert (tmp_path / "site" / "figures" / "many_scaling.png").is_file()


def test_a_broken_link_fails_the_build(tmp_path):
    project = tmp_path / "project"
    shutil.copytree(ROOT / "docs", project / "docs", ignore=shutil.ignore_patterns("__pycache__"))
    shutil.copy(ROOT / "mkdocs.yml", project / "mkdocs.yml")
    for name in ("rigid", "report"):  # what mkdocstrings and the report hook read
        (project / name).symlink_to(ROOT / name)
    index = project / "docs" / "index.md"
    index.write_text(index.read_text() + "\nSee [the missing page](no-such-page.md).\n")
    proc = _build(project, tmp_path / "site")
    assert proc.returncode != 0
    assert "no-such-page.md" in proc.stdout + proc.stderr
