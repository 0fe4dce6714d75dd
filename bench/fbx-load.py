#!/usr/bin/env python3
"""How long `sinew info` takes on FBX files, by FBX version, against Assimp on the same files.

For every scene of ../shared/testdata/ufbx saved in more than one FBX version (NAME_6100_ascii,
NAME_7500_binary, ...), times the whole `sinew info FILE` process (sinew's own reader) and the
same with SINEW_IMPORTER=assimp (Assimp 5.x behind the same helper), runs interleaved, and
prints the median and the min-max of each in milliseconds, with per-version totals.

    bench/fbx-load.py [--sinew build/sinew] [--runs 7] [--testdata ../shared/testdata] [--json]
"""
import collections
import json
import os
import re
import statistics
import sys

from timing import process_args, run_ms


def main():
    ap = process_args(__doc__)
    args = ap.parse_args()
    folder = os.path.join(args.testdata, "ufbx")
    scenes = collections.defaultdict(list)
    for name in sorted(os.listdir(folder)):
        m = re.match(r"(.*)_(\d{4})_(ascii|binary)\.fbx$", name)
        if m:
            scenes[m.group(1)].append((int(m.group(2)), m.group(3), name))
    files = [f for versions in scenes.values() if len({v for v, _, _ in versions}) > 1 for f in versions]
    env_sinew = dict(os.environ)
    env_assimp = dict(os.environ, SINEW_IMPORTER="assimp")
    times = {name: {"sinew": [], "assimp": []} for _, _, name in files}
    status = {}
    for _ in range(args.runs):
        for _, _, name in files:
            path = os.path.join(folder, name)
            ms, rc = run_ms([args.sinew, "info", "-q", path], env_sinew)
            times[name]["sinew"].append(ms)
            status[name] = rc
            ms, rc = run_ms([args.sinew, "info", "-q", path], env_assimp)
            times[name]["assimp"].append(ms if rc == 0 else float("nan"))
    rows = []
    for version, enc, name in sorted(files, key=lambda f: (f[2].rsplit("_", 2)[0], f[0], f[1])):
        s, a = times[name]["sinew"], [x for x in times[name]["assimp"] if x == x]
        rows.append({"file": name, "version": version, "encoding": enc, "sinew_ok": status[name] == 0,
                     "sinew_ms": statistics.median(s), "sinew_min": min(s), "sinew_max": max(s),
                     "assimp_ms": statistics.median(a) if a else None,
                     "size": os.path.getsize(os.path.join(folder, name))})
    if args.json:
        json.dump(rows, sys.stdout, indent=1)
        print()
        return
    print("%-58s %8s %18s %10s" % ("file", "KiB", "sinew ms (min-max)", "Assimp ms"))
    for r in rows:
        assimp = "%.1f" % r["assimp_ms"] if r["assimp_ms"] is not None else "refused"
        print("%-58s %8.1f %7.1f (%4.1f-%4.1f) %10s%s" % (r["file"], r["size"] / 1024, r["sinew_ms"], r["sinew_min"],
                                                        r["sinew_max"], assimp, "" if r["sinew_ok"] else "  FAILED"))
    print()
    by = collections.defaultdict(list)
    for r in rows:
        by[(r["version"] // 1000, r["encoding"])].append(r)
    print("%-14s %6s %14s %16s %10s" % ("version", "files", "sinew median", "Assimp median", "read by Assimp"))
    for key in sorted(by):
        group = by[key]
        read = [r["assimp_ms"] for r in group if r["assimp_ms"] is not None]
        print("%-14s %6d %11.1f ms %13s ms %7d/%d" % (
            "%d.x %s" % key, len(group), statistics.median(r["sinew_ms"] for r in group),
            "%.1f" % statistics.median(read) if read else "-", len(read), len(group)))


if __name__ == "__main__":
    main()
