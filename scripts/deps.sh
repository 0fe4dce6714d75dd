#!/usr/bin/env bash
# Installs the Debian packages sinew needs to build and test, and nothing when they are all there
# (GTK 4 for sinew-view, Xvfb to test it without a display, ffmpeg for videos and previews,
# SIMDe's portable AVX-512 headers to test the AVX-512 kernel on processors without it,
# Python 3 with numpy, cffi, pytest and Dask distributed for the binding and `sinew batch`).
# Uses apt-get directly as root, through sudo otherwise. Safe to run again.
set -euo pipefail

packages=(
  build-essential cmake pkg-config clang-format
  libassimp-dev libcglm-dev libcjson-dev libjsmn-dev libcmocka-dev libxml2-dev zlib1g-dev libdeflate-dev
  libepoxy-dev libegl-dev libegl-mesa0 libgl1-mesa-dri libstb-dev libmeshoptimizer-dev
  libgtk-4-dev xvfb xauth ffmpeg libsimde-dev
  python3-numpy python3-cffi python3-pytest python3-distributed
)

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  exit 0
fi

echo "deps.sh: installing ${missing[*]}"
if [ "$(id -u)" -eq 0 ]; then
  sudo=""
elif command -v sudo >/dev/null 2>&1; then
  sudo="sudo"
else
  echo "deps.sh: need root or sudo to install: ${missing[*]}" >&2
  exit 1
fi
export DEBIAN_FRONTEND=noninteractive
$sudo apt-get update -qq
$sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
