#!/bin/sh
# Regenerates the seed corpus of fuzz_model from sinew's own fixtures and generator:
#   fuzz/make-corpus.sh [path/to/sinew]      (run from anywhere; paths stored are relative)
set -eu
cd "$(dirname "$0")/.."
sinew=${1:-build/sinew}
mkdir -p fuzz/corpus
"$sinew" convert tests/fixtures/two_bone.dae fuzz/corpus/two_bone.sinew --muscles tests/fixtures/two_bone.muscles.json
"$sinew" convert tests/fixtures/two_bone_cubic.gltf fuzz/corpus/two_bone_cubic.sinew --no-muscles
"$sinew" convert builtin:arm fuzz/corpus/arm.sinew
"$sinew" convert tests/fixtures/clip_windows.dae fuzz/corpus/clip_windows.sinew --no-muscles
"$sinew" convert tests/fixtures/two_bone_textured.glb fuzz/corpus/two_bone_textured.sinew --no-muscles
"$sinew" convert tests/fixtures/bezier_kept.dae fuzz/corpus/bezier_kept.sinew --no-muscles
"$sinew" convert tests/fixtures/two_bone_painted.gltf fuzz/corpus/two_bone_painted.sinew --no-muscles
