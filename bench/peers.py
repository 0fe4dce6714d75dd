#!/usr/bin/env python3
"""How long opening a file takes, sinew against the fastest open readers, side by side.

Builds the peer loaders of ../shared/peers (ufbx 0.23 for FBX, cgltf 1.15 for glTF; `build.sh`)
and times whole processes on the same files, runs interleaved so that the machine's noise falls
on every reader alike (sinew with the open readers in one set of rounds, and with its helper and
Assimp in another, whose heavy processes would leave the caches cold for the next):

    sinew info FILE -q                      the default: sinew's reader in the sinew process
    sinew info FILE -q  (isolated)          SINEW_IMPORT_ISOLATE=1: in the sinew-import helper
    sinew info FILE.sinew -q                the same model converted to .sinew (goal: 5 ms)
    ufbx_load FILE / ufbx_load FILE --bake  FBX: load, and load + bake every stack (sinew bakes clips)
    cgltf_load FILE                         glTF: parse, load buffers, validate
    assimp info FILE                        Assimp's command line, where installed

plus `sinew --help` and an empty C program (what a process that does nothing costs here). It
prints each reader's median and min-max in milliseconds and the ratios issue 31 sets goals on:
sinew / ufbx --bake (goal 1.3), sinew / cgltf (1.3), sinew / assimp (0.5), each as the ratio of
the medians and, paired, as the median of each round's own ratio (steadier where the machine
swings between modes within a run); and the import without the process, in MB/s of the file,
each the best of --runs from memory in one process, all timed by bench/peers_inproc.c (built
here against the build's libsinew and ../shared/peers; goal: sinew at least 0.8 of ufbx --bake
and of cgltf), with cgltf also timed unpacking every accessor into floats (cgltf-decode: cgltf
itself decodes none, where sinew decodes and checks them all).

    bench/peers.py [--sinew build/sinew] [--runs 7] [--testdata ../shared/testdata] [--json] [FILE...]
"""
import json
import os
import shutil
import statistics
import subprocess
import sys

from timing import HERE, process_args, run_ms

DEFAULT_FILES = ["ozz/pab/walk.fbx", "ozz/pab/arnaud.fbx", "ufbx/motionbuilder_sausage_rrss_7700_binary.fbx",
                 "raylib/robot.glb", "gltf-samples/Fox.glb", "blender/robot_walk.dae", "assimp/BVH/01_01.bvh"]


def build_peers(shared, sinew):
    out = os.environ.get("OUT", "/tmp/peers")
    subprocess.run(["bash", os.path.join(shared, "peers", "build.sh")], check=True, stdout=subprocess.DEVNULL,
                   env=dict(os.environ, OUT=out))
    empty = os.path.join(out, "empty")
    with open(empty + ".c", "w") as f:
        f.write("int main(void) { return 0; }\n")
    subprocess.run(["cc", "-O2", empty + ".c", "-o", empty], check=True)
    # the imports from memory, for the in-library column (bench/peers_inproc.c), against the build's
    # libsinew beside `sinew` and the peers' sources
    peers = os.path.join(shared, "peers")
    build = os.path.dirname(os.path.abspath(sinew))
    inproc = os.path.join(out, "peers_inproc")
    r = subprocess.run(["cc", "-O2", "-I" + os.path.join(HERE, "..", "include"), "-I" + os.path.join(peers, "ufbx"),
                        "-I" + os.path.join(peers, "cgltf"), os.path.join(HERE, "peers_inproc.c"),
                        os.path.join(peers, "ufbx", "ufbx.c"), "-L" + build, "-Wl,-rpath," + build, "-lsinew", "-lm",
                        "-o", inproc])
    return os.path.join(out, "ufbx_load"), os.path.join(out, "cgltf_load"), empty, out, \
        inproc if r.returncode == 0 else None


def in_library_ms(inproc, reader, path, runs):
    """Best milliseconds of a reader's import from memory in one process, the first run left out (sinew:
    sinew_import_memory; ufbx: load + bake; cgltf: parse + buffers + validate); None where it fails."""
    if not inproc:
        return None
    r = subprocess.run([inproc, reader, path, str(runs)], capture_output=True, text=True)
    try:
        return float(r.stdout) if r.returncode == 0 else None
    except ValueError:
        return None


def converted(sinew, path, folder):
    """The file as .sinew (sinew convert), or None when it cannot be converted."""
    out = os.path.join(folder, os.path.basename(path) + ".sinew")
    r = subprocess.run([sinew, "convert", path, out], stdout=subprocess.DEVNULL,
                       stderr=subprocess.DEVNULL)
    return out if r.returncode == 0 and os.path.exists(out) else None


def readers_for(path, sinew, ufbx, cgltf, assimp, dot_sinew):
    """(name, command, extra environment) of every reader of this file, in two groups timed apart:
    sinew against the open readers, and sinew against the heavy processes (its helper, Assimp)."""
    ext = os.path.splitext(path)[1].lower()
    mine = ("sinew", [sinew, "info", path, "-q"], {})
    light = [mine]
    if dot_sinew:
        light += [("sinew .sinew", [sinew, "info", dot_sinew, "-q"], {})]
    if ext == ".fbx":
        light += [("ufbx", [ufbx, path], {}), ("ufbx --bake", [ufbx, path, "--bake"], {})]
    if ext in (".gltf", ".glb"):
        light += [("cgltf", [cgltf, path], {})]
    heavy = [mine, ("sinew isolated", [sinew, "info", path, "-q"], {"SINEW_IMPORT_ISOLATE": "1"})]
    if assimp:
        heavy += [("assimp", [assimp, "info", path], {})]
    return light, heavy


def measure(rows, runs):
    """Interleaved: each round runs every reader once, in turn, starting one further along each round,
    so that every reader follows every other equally often."""
    times = {name: [] for name, _, _ in rows}
    failed = set()
    for r in range(runs + 1):  # the first round warms the page cache and is dropped
        for name, cmd, extra in rows[r % len(rows):] + rows[:r % len(rows)]:
            ms, code = run_ms(cmd, dict(os.environ, **extra))
            if code != 0:
                failed.add(name)
            times[name].append(ms)
    return {name: t[1:] for name, t in times.items() if name not in failed}, failed


def main():
    ap = process_args(__doc__)
    ap.add_argument("files", nargs="*", help="files to open (default: seven shared FBX, glTF, COLLADA and BVH models)")
    args = ap.parse_args()
    shared = os.path.dirname(os.path.normpath(args.testdata))
    ufbx, cgltf, empty, folder, inproc = build_peers(shared, args.sinew)
    assimp = shutil.which("assimp")
    files = args.files or [os.path.join(args.testdata, f) for f in DEFAULT_FILES]
    report = {"runs": args.runs, "files": []}
    help_rows = [("empty process", [empty], {}), ("sinew --help", [args.sinew, "--help"], {})]
    help_times, _ = measure(help_rows, args.runs)
    report["empty_process_ms"] = statistics.median(help_times["empty process"])
    report["sinew_help_ms"] = statistics.median(help_times["sinew --help"])
    for path in files:
        if not os.path.exists(path):
            print(f"{path}: missing", file=sys.stderr)
            continue
        # Two groups of rounds: a process of Assimp (8-70 ms) or of the helper leaves the caches cold
        # for the next, which weighs most on the largest program: with Assimp in the same rounds,
        # sinew took 1.6x cgltf's time on Fox.glb, against 1.35x without.
        light, heavy = readers_for(path, args.sinew, ufbx, cgltf, assimp, converted(args.sinew, path, folder))
        times, failed = measure(light, args.runs)
        heavy_times, heavy_failed = measure(heavy, args.runs)
        failed |= heavy_failed
        times.update({name: t for name, t in heavy_times.items() if name != "sinew"})
        size = os.path.getsize(path)
        entry = {"file": os.path.relpath(path, args.testdata), "bytes": size,
                 "median_ms": {k: statistics.median(v) for k, v in times.items()},
                 "min_ms": {k: min(v) for k, v in times.items()}, "max_ms": {k: max(v) for k, v in times.items()},
                 "failed": sorted(failed)}
        med = entry["median_ms"]
        for mine, peer in (("sinew", "ufbx --bake"), ("sinew", "cgltf"), ("sinew", "assimp"),
                           ("sinew isolated", "assimp")):
            group = heavy_times if peer == "assimp" else times  # sinew's own times in the peer's rounds
            if mine in group and peer in group:
                key = (mine + " / " + peer).replace(" ", "_").replace("--", "").replace("/", "over")
                entry[key] = statistics.median(group[mine]) / statistics.median(group[peer])
                # the median of each round's own ratio: the two ran seconds apart, so a swing of
                # the machine between its fast and slow modes falls on both
                entry["paired_" + key] = statistics.median(a / b for a, b in zip(group[mine], group[peer]))
        if "sinew" in heavy_times:
            entry["median_ms"]["sinew, Assimp set"] = statistics.median(heavy_times["sinew"])
            entry["min_ms"]["sinew, Assimp set"] = min(heavy_times["sinew"])
            entry["max_ms"]["sinew, Assimp set"] = max(heavy_times["sinew"])
        # in the library: MB/s of the file, sinew from memory, the peers without their process start
        mine = in_library_ms(inproc, "sinew", path, args.runs)
        speeds = {}
        if mine:
            speeds["sinew"] = size / 1e6 / (mine / 1000.0)
        # cgltf-decode: cgltf with every accessor unpacked into floats, as sinew decodes them all
        for peer in ("ufbx --bake", "cgltf", "cgltf-decode"):
            if peer.replace("-decode", "") in med:
                ms = in_library_ms(inproc, peer.split()[0], path, args.runs)
                if ms:
                    speeds[peer] = size / 1e6 / (ms / 1000.0)
        entry["in_library_mb_s"] = speeds
        for peer in ("ufbx --bake", "cgltf", "cgltf-decode"):
            if "sinew" in speeds and peer in speeds:
                entry["in_library_sinew_over_" + peer.replace(" --", "_")] = speeds["sinew"] / speeds[peer]
        report["files"].append(entry)
    if args.json:
        json.dump(report, sys.stdout, indent=1)
        print()
        return
    print(f"sinew --help: {report['sinew_help_ms']:.1f} ms, an empty C program {report['empty_process_ms']:.1f} ms "
          f"(medians of {args.runs})")
    for e in report["files"]:
        print(f"\n{e['file']} ({e['bytes'] / 1e6:.2f} MB)")
        for k, m in e["median_ms"].items():
            print(f"  {k:18s} {m:7.1f} ms  ({e['min_ms'][k]:.1f}-{e['max_ms'][k]:.1f})")
        ratios = [f"{k.replace('_over_', ' / ').replace('_', ' ')} {v:.2f} (paired {e['paired_' + k]:.2f})"
                  for k, v in e.items() if "_over_" in k and not k.startswith(("in_library", "paired_"))]
        if ratios:
            print("  " + ", ".join(ratios))
        speeds = e["in_library_mb_s"]
        if speeds:
            print("  in the library: " + ", ".join(f"{k} {v:.1f} MB/s" for k, v in speeds.items()) +
                  "".join(f"; sinew / {k} {speeds['sinew'] / v:.2f}" for k, v in speeds.items() if k != "sinew"
                          and "sinew" in speeds))
        if e["failed"]:
            print("  failed: " + ", ".join(e["failed"]))


if __name__ == "__main__":
    main()
