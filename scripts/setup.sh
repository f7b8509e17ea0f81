#!/usr/bin/env bash
# Set up a fresh Debian/Ubuntu machine: a software Vulkan (Mesa lavapipe) and Xvfb for the window
# without a GPU or a display, poppler-utils (pdffonts: the report test checks its fonts are
# embedded), then this package with its test tools in the Python environment that .venv names:
#   - inside an active venv or conda env: that environment (.venv becomes a link to it);
#   - otherwise a new venv in .venv: Debian 12's and Ubuntu 24.04's python3 is "externally
#     managed" (PEP 668) and refuses pip installs; python3-venv is installed with apt where missing.
# The README's commands run .venv/bin/python. A second run with nothing to do takes about a second
# (a glTF validator that npm could not install is not tried again: see the end).
# PYTHON=python3.12 scripts/setup.sh picks the interpreter (default python3).
set -euo pipefail
cd "$(dirname "$0")/.."
export DEBIAN_FRONTEND=noninteractive
PY="${PYTHON:-python3}"
ROOT="$(pwd -P)"

SUDO=""
if [ "$(id -u)" -ne 0 ]; then
  command -v sudo >/dev/null 2>&1 && SUDO="sudo"
fi
apt_updated=""
apt_install() {  # apt_install PKG...: install what dpkg does not have; 1 where apt cannot
  local need="" pkg
  for pkg in "$@"; do dpkg -s "$pkg" >/dev/null 2>&1 || need="$need $pkg"; done
  [ -z "$need" ] && return 0
  if ! command -v apt-get >/dev/null 2>&1 || { [ "$(id -u)" -ne 0 ] && [ -z "$SUDO" ]; }; then
    echo "note: cannot install$need (no apt-get, or not root and no sudo)" >&2
    return 1
  fi
  [ -n "$apt_updated" ] || { $SUDO apt-get update -q && apt_updated=1; }
  # shellcheck disable=SC2086
  $SUDO apt-get install -y -q $need
}

if command -v dpkg >/dev/null 2>&1; then
  apt_install mesa-vulkan-drivers libvulkan1 xvfb xauth poppler-utils bubblewrap ||
    echo "note: without them the window, its test and the report's font test are skipped" >&2
else
  echo "note: no apt/dpkg; install a Vulkan driver (e.g. Mesa lavapipe) and Xvfb yourself for the window" >&2
fi

# --- the Python environment ---------------------------------------------------------------------
if ! command -v "$PY" >/dev/null 2>&1; then
  apt_install python3 python3-venv || { echo "error: no $PY; install Python 3.9-3.13" >&2; exit 1; }
fi
if ! "$PY" -c 'import sys; sys.exit(not (3, 9) <= sys.version_info[:2] <= (3, 13))'; then
  echo "error: $PY is Python $("$PY" -c 'import platform; print(platform.python_version())'); taichi 1.7" \
       "has wheels for 3.9-3.13 only: install one and run PYTHON=python3.12 scripts/setup.sh" >&2
  exit 1
fi
# The environment python3 runs in, if it is one the user made (a venv, or any conda env).
active="$("$PY" -c 'import os, sys
env = sys.prefix != getattr(sys, "base_prefix", sys.prefix) or os.path.isdir(os.path.join(sys.prefix, "conda-meta"))
print(os.path.realpath(sys.prefix) if env else "")')"
venv_real="$( [ -e .venv ] && cd .venv && pwd -P || true)"
if [ -n "$active" ] && [ "$active" != "$venv_real" ]; then
  if [ -e .venv ] && [ ! -L .venv ]; then
    echo "note: .venv is an environment of its own (from an earlier run) and stays; setting up the" \
         "active $active instead: use its python, or remove .venv and run setup again to link it" >&2
    ENV_DIR="$active"
  else
    ln -sfn "$active" .venv  # the README's .venv/bin/python is then the user's environment
    ENV_DIR=.venv
    echo "setup: installing into the active environment $active (.venv links to it)"
  fi
else
  [ -L .venv ] && [ ! -e .venv ] && rm .venv  # a link to an environment since removed
  if [ ! -x .venv/bin/python ]; then
    echo "setup: making a virtual environment in .venv ($("$PY" -c 'import sys; print(sys.executable)'))"
    if ! "$PY" -m venv .venv >/dev/null 2>&1; then
      rm -rf .venv  # Debian/Ubuntu ship venv's ensurepip in python3-venv (python3.X-venv)
      ver="$("$PY" -c 'import sys; print("%d.%d" % sys.version_info[:2])')"
      apt_install python3-venv || true
      "$PY" -m venv .venv >/dev/null 2>&1 || { rm -rf .venv; apt_install "python$ver-venv" || true; }
      [ -x .venv/bin/python ] || "$PY" -m venv .venv || {
        echo "error: $PY cannot make a virtual environment; install python3-venv" \
             "(sudo apt-get install python3-venv) and run scripts/setup.sh again" >&2
        exit 1
      }
    fi
  fi
  ENV_DIR=.venv
fi
VPY="$ENV_DIR/bin/python"

# Already installed from this checkout with this pyproject.toml? Then pip has nothing to do.
stamp="$ENV_DIR/.rigid-body-setup"
want="$ROOT $(cksum < pyproject.toml)"
installed() {
  "$VPY" -I - "$ROOT" <<'EOF'
import importlib.util, os, sys
spec = importlib.util.find_spec("rigid")
sys.exit(not (spec and os.path.realpath(spec.origin).startswith(os.path.join(sys.argv[1], ""))))
EOF
}
if [ -f "$stamp" ] && [ "$(cat "$stamp")" = "$want" ] && installed; then
  echo "setup: $VPY has this package installed already"
else
  rm -f "$stamp"
  # The usd extra (usd-core) lets the tests read USD exports back, the cluster extra (Ray: an 80 MB
  # wheel, ~10 s to install) runs the sweep test on a local Ray cluster; where either has no wheel,
  # go on without it. The docs extra (MkDocs) builds the documentation site (tests/test_docs.py).
  echo "setup: installing this package and its dependencies with pip (a minute or two on a new machine)"
  if "$VPY" -m pip install -q -e '.[dev,docs,usd,cluster]'; then
    :
  elif "$VPY" -m pip install -q -e '.[dev,docs]'; then
    for extra in usd cluster; do
      "$VPY" -m pip install -q -e ".[$extra]" ||
        echo "note: the $extra extra did not install (the package did); its tests are skipped" >&2
    done
  else
    echo "error: pip could not install this package into $ENV_DIR (see above)" >&2
    exit 1
  fi
  echo "$want" > "$stamp"
fi

# The checkout's bytecode, once: each command line, test and worker process then loads it instead
# of compiling the package's ~100 modules again at every start, where PYTHONDONTWRITEBYTECODE
# keeps Python from writing it itself (some CI images and containers set it). Python checks each
# file's timestamp, so an edited file is compiled afresh as usual.
"$VPY" -m compileall -q -j 0 rigid scripts tests rigid_body_dynamic.py >/dev/null || true

# The Khronos glTF validator, for tests/test_export_animation.py: into .tools/ (git-ignored), with npm.
# npm has no timeout of its own and retries for minutes offline: cap it, and remember a failure in
# a marker file so that the next run does not wait again (remove the marker to retry).
failed=.tools/gltf-validator.failed
if [ -f .tools/node_modules/gltf-validator/package.json ]; then
  :
elif [ -f "$failed" ]; then
  echo "note: gltf-validator did not install on $(cat "$failed"); the validator test is skipped" \
       "(rm $failed and run setup again to retry)" >&2
elif command -v npm >/dev/null 2>&1; then
  capped=""
  command -v timeout >/dev/null 2>&1 && capped="timeout ${NPM_TIMEOUT:-120}"
  if ! $capped npm install -s --no-audit --no-fund --prefix .tools gltf-validator@2.0.0-dev.3.10; then
    mkdir -p .tools && date -u '+%Y-%m-%d %H:%M UTC' > "$failed"
    echo "note: npm could not install gltf-validator within ${NPM_TIMEOUT:-120} s (offline?); the validator" \
         "test is skipped; setup will not try again until you rm $failed" >&2
  fi
else
  echo "note: no npm; the glTF validator test is skipped (install Node.js to run it)" >&2
fi
echo "setup: done; run the README's commands with $VPY (or '. $ENV_DIR/bin/activate', then python3)"
