#!/usr/bin/env bash
# `make run`: opens sinew-view on the built-in demo when there is a display (and GTK 4, which
# scripts/deps.sh installs); without a display, writes the demo content with `sinew demo`, prints
# `sinew info` of the humanoid and renders it headless: waving (with its biceps and skeleton) to PNG,
# walking to MP4 when ffmpeg is installed.
set -euo pipefail
build=${1:-build}
if [ -n "${DISPLAY:-}${WAYLAND_DISPLAY:-}" ] && [ -x "$build/sinew-view" ]; then
  echo "\$ sinew-view    (the built-in demo humanoid; Open… or drop a file for another)"
  exec "$build/sinew-view"
fi
out="$build/demo"
humanoid="$out/humanoid.dae"
echo "make run: no display; showing the built-in demo headless instead (sinew-view needs a display)"
echo
echo "\$ sinew demo $out --force"
"$build/sinew" demo "$out" --force
echo
echo "\$ sinew info $humanoid"
"$build/sinew" info "$humanoid" | head -12
echo
echo "\$ sinew render $humanoid --clip wave --time 0.6 --muscles --skeleton -o $out/wave.png"
"$build/sinew" render "$humanoid" --clip wave --time 0.6 --muscles --skeleton -o "$out/wave.png"
if command -v ffmpeg >/dev/null 2>&1; then
  echo
  echo "\$ sinew render $humanoid --clip walk --from 0 --to 2 --fps 30 --loop --muscles -o $out/walk.mp4"
  "$build/sinew" render "$humanoid" --clip walk --from 0 --to 2 --fps 30 --loop --muscles -o "$out/walk.mp4"
else
  echo "(ffmpeg is not installed: no video; PNG frames: sinew render ... --fps 30 -o DIR/frame%04d.png)"
fi
echo
echo "Open $out/wave.png to see it."
