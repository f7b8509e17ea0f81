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
python3 -m pip install -q -e '.[dev]'
