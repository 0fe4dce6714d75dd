#!/usr/bin/env python3
"""How long opening a file takes, sinew against the fastest open readers, side by side.

Builds the peer loaders of ../shared/peers (ufbx 0.23 for FBX, cgltf 1.15 for glTF; `build.sh`)
and times whole processes on the same files, runs interleaved so that the machine's noise falls
on every reader alike:

    sinew info FILE -q                      the default: sinew's reader in the sinew-import helper
    sinew info FILE -q  (in process)        SINEW_IMPORT_IN_PROCESS=1: no helper process
    ufbx_load FILE / ufbx_load FILE --bake  FBX: load, and load + bake every stack (sinew bakes clips)
    cgltf_load FILE                         glTF: parse, load buffers, validate
    assimp info FILE                        Assimp's command line, where installed

plus `sinew --help` (what a process that never opens a file costs). It prints each reader's
median and min-max in milliseconds and the ratios issue 31 sets goals on: sinew / ufbx --bake
(goal 1.3), sinew / cgltf (1.3), sinew / assimp (0.5).

    bench/peers.py [--sinew build/sinew] [--runs 7] [--testdata ../shared/testdata] [--json] [FILE...]
"""
import json
import os
import shutil
import statistics
import subprocess
import sys

from timing import process_args, run_ms

DEFAULT_FILES = ["ozz/pab/walk.fbx", "ozz/pab/arnaud.fbx", "ufbx/motionbuilder_sausage_rrss_7700_binary.fbx",
                 "raylib/robot.glb", "gltf-samples/Fox.glb", "blender/robot_walk.dae"]


def build_peers(shared):
    out = os.environ.get("OUT", "/tmp/peers")
    subprocess.run(["bash", os.path.join(shared, "peers", "build.sh")], check=True, stdout=subprocess.DEVNULL,
                   env=dict(os.environ, OUT=out))
    return os.path.join(out, "ufbx_load"), os.path.join(out, "cgltf_load")


def readers_for(path, sinew, ufbx, cgltf, assimp):
    """(name, command, extra environment) of every reader of this file."""
    ext = os.path.splitext(path)[1].lower()
    rows = [("sinew", [sinew, "info", path, "-q"], {}),
            ("sinew in process", [sinew, "info", path, "-q"], {"SINEW_IMPORT_IN_PROCESS": "1"})]
    if ext == ".fbx":
        rows += [("ufbx", [ufbx, path], {}), ("ufbx --bake", [ufbx, path, "--bake"], {})]
    if ext in (".gltf", ".glb"):
        rows += [("cgltf", [cgltf, path], {})]
    if assimp:
        rows += [("assimp", [assimp, "info", path], {})]
    return rows


def measure(rows, runs):
    """Interleaved: each round runs every reader once, in turn."""
    times = {name: [] for name, _, _ in rows}
    failed = set()
    for _ in range(runs + 1):  # the first round warms the page cache and is dropped
        for name, cmd, extra in rows:
            ms, code = run_ms(cmd, dict(os.environ, **extra))
            if code != 0:
                failed.add(name)
            times[name].append(ms)
    return {name: t[1:] for name, t in times.items() if name not in failed}, failed


def main():
    ap = process_args(__doc__)
    ap.add_argument("files", nargs="*", help="files to open (default: six shared FBX, glTF and COLLADA models)")
    args = ap.parse_args()
    shared = os.path.dirname(os.path.normpath(args.testdata))
    ufbx, cgltf = build_peers(shared)
    assimp = shutil.which("assimp")
    files = args.files or [os.path.join(args.testdata, f) for f in DEFAULT_FILES]
    report = {"runs": args.runs, "files": []}
    help_rows = [("sinew --help", [args.sinew, "--help"], {})]
    help_times, _ = measure(help_rows, args.runs)
    report["sinew_help_ms"] = statistics.median(help_times["sinew --help"])
    for path in files:
        if not os.path.exists(path):
            print(f"{path}: missing", file=sys.stderr)
            continue
        times, failed = measure(readers_for(path, args.sinew, ufbx, cgltf, assimp), args.runs)
        entry = {"file": os.path.relpath(path, args.testdata), "bytes": os.path.getsize(path),
                 "median_ms": {k: statistics.median(v) for k, v in times.items()},
                 "min_ms": {k: min(v) for k, v in times.items()}, "max_ms": {k: max(v) for k, v in times.items()},
                 "failed": sorted(failed)}
        med = entry["median_ms"]
        for mine in ("sinew", "sinew in process"):
            for peer in ("ufbx --bake", "cgltf", "assimp"):
                if mine in med and peer in med:
                    key = (mine + " / " + peer).replace(" ", "_").replace("--", "").replace("/", "over")
                    entry[key] = med[mine] / med[peer]
        report["files"].append(entry)
    if args.json:
        json.dump(report, sys.stdout, indent=1)
        print()
        return
    print(f"sinew --help: {report['sinew_help_ms']:.1f} ms (median of {args.runs})")
    for e in report["files"]:
        print(f"\n{e['file']} ({e['bytes'] / 1e6:.2f} MB)")
        for k, m in e["median_ms"].items():
            print(f"  {k:18s} {m:7.1f} ms  ({e['min_ms'][k]:.1f}-{e['max_ms'][k]:.1f})")
        ratios = [f"{k.replace('_over_', ' / ').replace('_', ' ')} {v:.2f}" for k, v in e.items() if "_over_" in k]
        if ratios:
            print("  " + ", ".join(ratios))
        if e["failed"]:
            print("  failed: " + ", ".join(e["failed"]))


if __name__ == "__main__":
    main()
