#!/usr/bin/env bash
# `make run`: until the viewer (sinew-view) exists, show sinew on its built-in demo content headless:
# `sinew demo` writes the humanoid and the arm as COLLADA, then `sinew info` and headless renders of
# the humanoid walking and waving (with its biceps) to PNG, and to MP4 when ffmpeg is installed.
set -euo pipefail
build=${1:-build}
out="$build/demo"
humanoid="$out/humanoid.dae"
echo "make run: the viewer is not built yet; showing the built-in demo headless instead"
echo
echo "\$ sinew demo $out"
"$build/sinew" demo "$out"
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
