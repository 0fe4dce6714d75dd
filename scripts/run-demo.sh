#!/usr/bin/env bash
# `make run`: until the viewer and the built-in demo exist, show what sinew does on a
# bundled sample: `sinew info` and `sinew pose` on a small skinned, animated glTF that is
# sinew's own test fixture.
set -euo pipefail
build=${1:-build}
sample=tests/fixtures/two_bone_cubic.gltf
echo "make run: the viewer is not built yet; running the command line on the bundled sample $sample"
echo
echo "\$ sinew info $sample"
"$build/sinew" info "$sample"
echo
echo "\$ sinew pose $sample --time 0,0.5,1"
"$build/sinew" pose "$sample" --time 0,0.5,1
