"""scripts/setup.sh inside a venv the user already has, run twice: it installs there and links .venv
to it; npm's install of the glTF validator is capped and a failure is remembered, so a second run
neither waits for npm nor asks it again (it took 71 s each run offline). Runs setup.sh for real on
test_setup.py's stand-in project. The venv borrows pip from the interpreter it was made from
(--system-site-packages, --without-pip): setup.sh runs "$VPY -m pip" either way, and installing a
pip of its own (ensurepip) would cost the test more CPU than the rest of it."""
import subprocess
import sys
import time

from test_setup import _imports_from, _project, _setup


def _venv(tmp_path):
    env = tmp_path / "user env"  # a space in the path, too
    subprocess.run([getattr(sys, "_base_executable", sys.executable), "-m", "venv", "--without-pip",
                    "--system-site-packages", str(env)], check=True, capture_output=True)
    return env


def test_setup_inside_an_active_venv_installs_there_and_a_slow_npm_is_not_asked_again(tmp_path):
    project = _project(tmp_path)
    npm = tmp_path / "stubs" / "npm"  # npm offline: retries and waits
    npm.write_text(f'#!/bin/sh\necho "npm $*" >> "{tmp_path}/calls.log"\nexec sleep 60\n')
    env = _venv(tmp_path)
    path = f"{env / 'bin'}:{tmp_path / 'stubs'}:/usr/bin:/bin"
    began = time.monotonic()
    first = _setup(project, path, VIRTUAL_ENV=str(env), NPM_TIMEOUT="1")
    took = time.monotonic() - began
    assert first.returncode == 0, first.stdout + first.stderr
    venv = project / ".venv"
    assert venv.is_symlink() and venv.resolve() == env.resolve()
    assert _imports_from(env / "bin" / "python", project) == str(project.resolve() / "rigid" / "__init__.py")
    assert took < 40, f"npm was not cut off: {took:.0f} s"
    assert "could not install gltf-validator within 1 s" in first.stderr, first.stderr
    assert (project / ".tools" / "gltf-validator.failed").is_file()
    began = time.monotonic()
    second = _setup(project, path, VIRTUAL_ENV=str(env), NPM_TIMEOUT="1")
    took = time.monotonic() - began
    assert second.returncode == 0, second.stdout + second.stderr
    assert "has this package installed already" in second.stdout
    assert "rm .tools/gltf-validator.failed" in second.stderr, second.stderr
    assert (tmp_path / "calls.log").read_text().count("npm ") == 1  # not asked again
    assert took < 10, f"a second run took {took:.1f} s"
