#!/usr/bin/env python3
"""Render time per frame with each look switch, through `sinew bench render --json`.

    bench/render-look.py [--sinew build/sinew] [--frames 120] [--size 1280x720] [--model FILE]
                         [--hdri FILE.hdr]

For the generated 64-joint character of 10,016 vertices (or --model), GPU skinning, at 4x and 1x
multisampling: the defaults (Phong), then physically based shading in the built-in studio, and
each switch on top of PBR (shadows, ssao, outline, hdri-background, tone-mapping aces), then
all of them together; with --hdri, PBR lit by that file too. Prints ms/frame, fps and the ratio
to the defaults. The machine is shared and noisy: compare ratios from one run.
"""
import argparse
import json
import subprocess
import sys

CASES = [
    ("defaults (phong)", []),
    ("pbr (studio)", ["--shading", "pbr"]),
    ("pbr + shadows", ["--shading", "pbr", "--shadows"]),
    ("pbr + ssao", ["--shading", "pbr", "--ssao"]),
    ("pbr + outline", ["--shading", "pbr", "--outline"]),
    ("pbr + hdri-background", ["--shading", "pbr", "--hdri-background"]),
    ("pbr + tone-mapping aces", ["--shading", "pbr", "--tone-mapping", "aces"]),
    ("pbr + all", ["--shading", "pbr", "--shadows", "--ssao", "--outline", "--hdri-background"]),
    ("phong + all", ["--shadows", "--ssao", "--outline"]),
]


def run(sinew, model, frames, size, samples, extra):
    cmd = [sinew, "bench", "render"] + ([model] if model else [])
    cmd += ["--frames", str(frames), "--size", size, "--samples", str(samples), "--json"] + extra
    out = subprocess.run(cmd, check=True, capture_output=True, text=True).stdout
    data = json.loads(out)
    return data, data["runs"][0]["gpu_skinning_fps"]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--sinew", default="build/sinew")
    ap.add_argument("--frames", type=int, default=120)
    ap.add_argument("--size", default="1280x720")
    ap.add_argument("--model")
    ap.add_argument("--hdri")
    a = ap.parse_args()
    cases = list(CASES)
    if a.hdri:
        cases.append(("pbr, --hdri file", ["--shading", "pbr", "--hdri", a.hdri]))
        cases.append(("pbr, --hdri file + all", ["--shading", "pbr", "--hdri", a.hdri, "--shadows", "--ssao",
                                                  "--outline", "--hdri-background"]))
    for samples in (4, 1):
        base = None
        for name, extra in cases:
            data, fps = run(a.sinew, a.model, a.frames, a.size, samples, extra)
            if base is None:
                base = fps
                print(f"{data['model']} ({data['vertices']} vertices, {data['joints']} joints), "
                      f"{data['width']}x{data['height']}, {samples}x MSAA, GPU skinning, {data['gl']}")
            print(f"  {name:26s} {1e3 / fps:8.2f} ms/frame {fps:8.1f} fps   x{base / fps:5.2f} the defaults' time")
            sys.stdout.flush()


if __name__ == "__main__":
    main()
