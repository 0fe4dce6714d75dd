#!/usr/bin/env bash
# `make run`: until the viewer (sinew-view) and the built-in demo content exist, show what sinew does on
# a bundled sample, sinew's own small skinned and animated glTF: `sinew info`, then a headless render to
# PNG (and to MP4 when ffmpeg is installed) under BUILD/demo.
set -euo pipefail
build=${1:-build}
sample=tests/fixtures/two_bone_cubic.gltf
out="$build/demo"
mkdir -p "$out"
echo "make run: the viewer is not built yet; rendering the bundled sample $sample headless instead"
echo
echo "\$ sinew info $sample"
"$build/sinew" info "$sample"
echo
echo "\$ sinew render $sample --time 0.75 --skeleton --camera orbit:40,20 -o $out/sample.png"
"$build/sinew" render "$sample" --time 0.75 --skeleton --camera orbit:40,20 -o "$out/sample.png"
if command -v ffmpeg >/dev/null 2>&1; then
  echo
  echo "\$ sinew render $sample --fps 30 --skeleton --camera orbit:40,20 -o $out/sample.mp4"
  "$build/sinew" render "$sample" --fps 30 --skeleton --camera orbit:40,20 -o "$out/sample.mp4"
else
  echo "(ffmpeg is not installed: no video; PNG frames: sinew render ... --fps 30 -o DIR/frame%04d.png)"
fi
echo
echo "Open $out/sample.png to see it."
