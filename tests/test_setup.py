"""scripts/setup.sh on a stock Debian/Ubuntu Python (PEP 668: "externally managed", pip refused);
the README's two commands and .ci/run agree. setup.sh inside a venv the user already has, run twice:
test_setup_rerun.py.

setup.sh runs for real on a small stand-in project (setup.sh itself, a pyproject.toml with the
extras dev and usd, no dependencies and a build backend of its own, a package named rigid), offline
(no package index); apt-get, dpkg and npm are stubs that log their calls."""
import os
import re
import shutil
import stat
import subprocess
from pathlib import Path

import pytest

from conftest import ROOT

SYSTEM_PYTHON = Path("/usr/bin/python3")
PYPROJECT = """[build-system]
requires = []
build-backend = "probe_backend"
backend-path = ["."]

[project]
name = "rigid-setup-probe"
version = "0"
"""
# A PEP 517/660 build backend with no dependencies (setuptools would want wheel from an index):
# the editable wheel is a .pth file naming the project folder.
BACKEND = '''import base64, hashlib, os, zipfile

DIST = "rigid_setup_probe-0"
METADATA = "Metadata-Version: 2.1\\nName: rigid-setup-probe\\nVersion: 0\\nProvides-Extra: dev\\nProvides-Extra: usd\\n"


def build_editable(wheel_directory, config_settings=None, metadata_directory=None):
    files = {DIST + ".dist-info/METADATA": METADATA,
             DIST + ".dist-info/WHEEL": "Wheel-Version: 1.0\\nGenerator: probe\\nRoot-Is-Purelib: true\\nTag: py3-none-any\\n",
             "rigid_setup_probe.pth": os.path.dirname(os.path.abspath(__file__)) + "\\n"}
    name = DIST + "-py3-none-any.whl"
    record = []
    with zipfile.ZipFile(os.path.join(wheel_directory, name), "w") as wheel:
        for path, text in files.items():
            data = text.encode()
            wheel.writestr(path, data)
            digest = base64.urlsafe_b64encode(hashlib.sha256(data).digest()).rstrip(b"=").decode()
            record.append(f"{path},sha256={digest},{len(data)}")
        wheel.writestr(DIST + ".dist-info/RECORD", "\\n".join(record + [DIST + ".dist-info/RECORD,,"]) + "\\n")
    return name


build_wheel = build_editable
'''


def _externally_managed(python: Path) -> bool:
    if not python.exists():
        return False
    out = subprocess.run([str(python), "-c", "import sys, sysconfig; print(sysconfig.get_path('stdlib')); "
                          "print(sys.prefix == sys.base_prefix)"], capture_output=True, text=True)
    lines = out.stdout.split()
    return out.returncode == 0 and lines[1] == "True" and (Path(lines[0]) / "EXTERNALLY-MANAGED").exists()


def _project(tmp_path: Path) -> Path:
    project = tmp_path / "project"
    (project / "scripts").mkdir(parents=True)
    shutil.copy(ROOT / "scripts" / "setup.sh", project / "scripts" / "setup.sh")
    (project / "pyproject.toml").write_text(PYPROJECT)
    (project / "probe_backend.py").write_text(BACKEND)
    (project / "rigid").mkdir()
    (project / "rigid" / "__init__.py").write_text("")
    stubs = tmp_path / "stubs"
    stubs.mkdir()
    for tool, code in (("dpkg", 0), ("apt-get", 1), ("sudo", 1), ("npm", 1)):
        script = stubs / tool
        script.write_text(f'#!/bin/sh\necho "{tool} $*" >> "{tmp_path}/calls.log"\nexit {code}\n')
        script.chmod(script.stat().st_mode | stat.S_IXUSR)
    return project


def _setup(project: Path, path: str, **extra) -> subprocess.CompletedProcess:
    """scripts/setup.sh in an empty environment, as `env -i HOME=... PATH=...` runs it."""
    home = project.parent / "home"
    home.mkdir(exist_ok=True)
    env = dict(HOME=str(home), PATH=path, PIP_CONFIG_FILE=os.devnull, PIP_NO_INDEX="1", **extra)
    return subprocess.run(["bash", "scripts/setup.sh"], cwd=project, env=env, capture_output=True, text=True,
                          timeout=600)


def _imports_from(python: Path, project: Path) -> str:
    return subprocess.run([str(python), "-I", "-c", "import rigid; print(rigid.__file__)"], cwd="/",
                          capture_output=True, text=True).stdout.strip()


@pytest.mark.skipif(not _externally_managed(SYSTEM_PYTHON),
                    reason="needs a Debian/Ubuntu /usr/bin/python3 marked EXTERNALLY-MANAGED (PEP 668)")
def test_setup_on_an_externally_managed_python_makes_and_uses_dot_venv(tmp_path):
    project = _project(tmp_path)
    path = f"{tmp_path / 'stubs'}:/usr/bin:/bin"
    first = _setup(project, path)
    assert first.returncode == 0, first.stdout + first.stderr
    venv = project / ".venv"
    assert venv.is_dir() and not venv.is_symlink()
    assert _imports_from(venv / "bin" / "python", project) == str(project.resolve() / "rigid" / "__init__.py")
    assert "externally-managed" not in first.stderr
    # A second run finds everything done and leaves pip alone.
    second = _setup(project, path)
    assert second.returncode == 0, second.stdout + second.stderr
    assert "has this package installed already" in second.stdout, second.stdout + second.stderr


def test_readme_commands_and_ci_use_the_environment_setup_made():
    text = (ROOT / "README.md").read_text()
    block = text.split("## Two commands")[1].split("```bash")[1].split("```")[0]
    commands = [line.split("#")[0].strip() for line in block.strip().splitlines()]
    assert commands[0].startswith("scripts/setup.sh && .venv/bin/python rigid_body_dynamic.py"), commands
    assert commands[1] == ".venv/bin/python -m pytest", commands
    ci = (ROOT / ".ci" / "run").read_text()
    assert re.search(r"^scripts/setup\.sh$", ci, re.M) and re.search(rf"^{re.escape(commands[1])}$", ci, re.M)
