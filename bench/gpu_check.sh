#!/bin/bash
# GPU skinning, morphing and headless EGL on a machine with a real GPU (NVIDIA through glvnd).
#
#   bench/gpu_check.sh SINEW MODELS OUT
#
# SINEW: a Release `sinew`; MODELS: a folder holding the models named below (and demo/, written
# by `sinew demo MODELS/demo`); OUT: where the figures (gpu.json, gpu.txt) and images go.
# Models missing from MODELS are skipped. What it does:
#  1. makes a headless context on each EGL platform in turn (SINEW_EGL_PLATFORM) and says which
#     ones work;
#  2. `sinew bench render` (frames per second, GPU and CPU skinning, 4x MSAA and none) on the
#     generated character and on each skinned model; `sinew bench crowd` on the demo humanoid;
#  3. renders each model (and three crowds) at one moment with --skinning gpu and --skinning cpu,
#     and compares the two images pixel by pixel (the vertex shader and the library's skinning
#     must agree).
# bench/README.md records what it printed. Needs python3 with numpy and Pillow for step 3.
set -u
S=$1 M=$2 O=$3
mkdir -p "$O/img"
log() { echo "$*" | tee -a "$O/gpu.txt"; }
: >"$O/gpu.txt"

log "== EGL platforms"
for p in device default surfaceless; do
    if SINEW_EGL_PLATFORM=$p "$S" render builtin:demo --size 320x180 -o "$O/img/platform-$p.png" >"$O/p.log" 2>&1; then
        log "$p: ok: $(tail -1 "$O/p.log")"
    else
        log "$p: failed: $(tail -1 "$O/p.log")"
    fi
done

log "== bench render"
echo '{"render": [' >"$O/gpu.json"
first=1
for m in synthetic robot.glb Fox.glb blender_293_barbarian_7400_binary.fbx demo/humanoid.dae; do
    f="$M/$m"
    [ "$m" = synthetic ] && f=
    [ -n "$f" ] && [ ! -f "$f" ] && continue
    r=$(timeout 120 "$S" bench render $f --json 2>"$O/b.log") || { log "$m: failed: $(tail -1 "$O/b.log")"; continue; }
    [ $first = 1 ] || echo , >>"$O/gpu.json"
    first=0
    echo "$r" >>"$O/gpu.json"
    log "$m: $(echo "$r" | tr -d '\n\t ' | sed 's/.*"gl":"\([^"]*\)".*"runs":/\1 /')"
done
echo '], "crowd": ' >>"$O/gpu.json"
c=$(timeout 150 "$S" bench crowd --most 50000 --json --png "$O/img/crowd.png" 2>"$O/c.log") || c='null'
echo "$c" >>"$O/gpu.json"
echo '}' >>"$O/gpu.json"
log "crowd: $(echo "$c" | tr -d '\n\t ' | head -c 600)"

log "== GPU against CPU skinning (640x360, one moment)"
shot() { # name file time [options]
    local n=$1 f=$2 t=$3
    shift 3
    [ -f "$f" ] || return
    for k in gpu cpu; do
        "$S" render "$f" --time "$t" --size 640x360 --skinning $k "$@" -o "$O/img/$n-$k.png" >"$O/r.log" 2>&1 ||
            log "$n $k: failed: $(tail -1 "$O/r.log")"
    done
}
shot robot "$M/robot.glb" 0.5
shot robot-pbr "$M/robot.glb" 0.5 --shading pbr
shot fox "$M/Fox.glb" 1.0 --clip Run
shot barbarian "$M/blender_293_barbarian_7400_binary.fbx" 1.0
shot dqs "$M/max_transformed_skin_7500_binary.fbx" 0.5
shot dqs-forced "$M/max_transformed_skin_7500_binary.fbx" 0.5 --skinning-method dqs
shot morphcube "$M/AnimatedMorphCube.glb" 1.0
shot morphprims "$M/MorphPrimitivesTest.glb" 0
shot humanoid-muscles "$M/demo/humanoid.dae" 0.5 --clip wave --muscles
# crowds: instanced GPU skinning against the CPU's batches (a mapped stream buffer, base vertices)
shot crowd-humanoid "$M/demo/humanoid.dae" 0.5 --crowd 64
shot crowd-far "$M/demo/humanoid.dae" 0.5 --crowd 400
shot crowd-robot "$M/robot.glb" 0.5 --crowd 16
python3 - "$O/img" <<'EOF' | tee -a "$O/gpu.txt"
import sys, glob, os
import numpy as np
from PIL import Image
d = sys.argv[1]
for g in sorted(glob.glob(os.path.join(d, "*-gpu.png"))):
    c = g[:-8] + "-cpu.png"
    if not os.path.exists(c):
        continue
    a = np.asarray(Image.open(g).convert("RGB"), dtype=np.int16)
    b = np.asarray(Image.open(c).convert("RGB"), dtype=np.int16)
    diff = np.abs(a - b).max(axis=2)
    bg = (a != a[0, 0]).any(axis=2)
    print(f"{os.path.basename(g)[:-8]:18s} max {diff.max():3d}  pixels over 16: {(diff > 16).mean() * 100:6.3f} %"
          f"  over 64: {(diff > 64).mean() * 100:6.3f} %  covered: {bg.mean() * 100:5.1f} %")
EOF
