#!/usr/bin/env bash
# Install what a fresh Debian/Ubuntu machine lacks: a software Vulkan (Mesa lavapipe) and Xvfb for
# GGUI without a GPU or a display, poppler-utils (pdffonts: the report test checks its fonts are
# embedded), then this package with its test tools.
set -euo pipefail
cd "$(dirname "$0")/.."
export DEBIAN_FRONTEND=noninteractive
if command -v apt-get >/dev/null 2>&1; then
  need=""
  for pkg in mesa-vulkan-drivers libvulkan1 xvfb xauth poppler-utils; do
    dpkg -s "$pkg" >/dev/null 2>&1 || need="$need $pkg"
  done
  if [ -n "$need" ]; then
    SUDO=""; [ "$(id -u)" -ne 0 ] && SUDO="sudo"
    $SUDO apt-get update -q
    $SUDO apt-get install -y -q $need
  fi
else
  echo "note: no apt-get; install a Vulkan driver (e.g. Mesa lavapipe) yourself for windows and videos" >&2
fi
# The usd extra (usd-core) lets the tests read USD exports back; where it has no wheel, go on without it.
python3 -m pip install -q -e '.[dev,usd]' || {
  echo "note: usd-core did not install; USD export and its tests are skipped" >&2
  python3 -m pip install -q -e '.[dev]'
}
# The Khronos glTF validator, for tests/test_export_animation.py: into .tools/ (git-ignored), with npm.
if command -v npm >/dev/null 2>&1; then
  [ -f .tools/node_modules/gltf-validator/package.json ] ||
    npm install -s --no-audit --no-fund --prefix .tools gltf-validator@2.0.0-dev.3.10 ||
    echo "note: npm could not install gltf-validator; the validator test is skipped" >&2
else
  echo "note: no npm; the glTF validator test is skipped (install Node.js to run it)" >&2
fi
