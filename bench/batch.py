#!/usr/bin/env python3
"""Files a second turning a motion library into arrays: `sinew batch` on 1 and 2 workers, the
CLI in a shell loop, and Blender importing each file and writing its frames.

The library is ../shared/testdata's model files repeated (copies under distinct folders) to
about --files files. Every tool writes, for every clip, each joint's world transform at every
frame (30 a second): sinew batch its .npz files; the CLI loop `sinew pose FILE --json` (one
clip, ten times: less work than the others); Blender (`blender -b`, one process a file, as
pipelines run it) its FBX or BVH importer, then the pose bones' world matrices at every frame
of the scene into an .npz. Blender reads FBX 7.1 and later binary and BVH, so it is timed on
those files of the library (--blender-files of them), and sinew batch on the same files too.
Prints files/s and ms a file, the 2-worker speed-up (beside what two processes of pure CPU work
get from this machine) and the ratio to Blender per file.

    bench/batch.py [--sinew build/sinew] [--files 500] [--blender-files 24] [--json]
"""
import argparse
import json
import os
import shutil
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "python"))

from sinew.batch import discover  # noqa: E402

BLENDER_SCRIPT = r"""
import bpy, sys, numpy as np
path, out = sys.argv[sys.argv.index("--") + 1:]
bpy.ops.wm.read_factory_settings(use_empty=True)
if path.lower().endswith(".bvh"):
    bpy.ops.import_anim.bvh(filepath=path)
else:
    bpy.ops.import_scene.fbx(filepath=path)
scene = bpy.context.scene
arms = [o for o in scene.objects if o.type == "ARMATURE"]
action_end = max([int(o.animation_data.action.frame_range[1]) for o in scene.objects
                  if o.animation_data and o.animation_data.action] or [scene.frame_end])
frames = []
for f in range(scene.frame_start, action_end + 1):
    scene.frame_set(f)
    frames.append([np.array(a.matrix_world @ b.matrix) for a in arms for b in a.pose.bones])
np.savez(out, worlds=np.array(frames, dtype=np.float32))
"""


def spin(n):
    t = time.perf_counter()
    x = 0
    for i in range(n):
        x += i * i
    return time.perf_counter() - t


def parallel_ceiling():
    """What 2 processes get from this machine's cores on pure CPU work (a 2-core VM may give
    less than 2x: shared physical cores, quotas)."""
    import multiprocessing
    n = 10_000_000
    one = min(spin(n) for _ in range(2))
    with multiprocessing.Pool(2) as pool:
        t = time.perf_counter()
        pool.map(spin, [n, n])
        two = time.perf_counter() - t
    return 2 * one / two


def spawn_loop(program, count=40):
    for _ in range(count):
        subprocess.run([program, "--help"], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)


def spawn_ceiling(program):
    """The same for starting processes (the import helper's --help), 2 loops against 1."""
    import threading
    t = time.perf_counter()
    spawn_loop(program)
    one = time.perf_counter() - t
    threads = [threading.Thread(target=spawn_loop, args=(program,)) for _ in range(2)]
    t = time.perf_counter()
    for th in threads:
        th.start()
    for th in threads:
        th.join()
    return 2 * one / (time.perf_counter() - t)


def build_library(testdata, folder, count, files=None):
    """Copies of the test data (whole trees, so that a .gltf keeps its .bin and textures) under
    folder/copyN until there are about `count` model files, or of `files` alone. Copies, not
    links: sinew batch takes a file linked twice once."""
    made = []
    c = 0
    while len(made) < count:
        target = os.path.join(folder, "copy%d" % c)
        if files:
            os.makedirs(target)
            for i, path in enumerate(files):
                copy = os.path.join(target, "%03d_%s" % (i, os.path.basename(path)))
                shutil.copyfile(path, copy)
                made.append(copy)
        else:
            shutil.copytree(testdata, target, ignore=shutil.ignore_patterns("reference", "*.obj", "*.json.gz"))
            made += [f["path"] for f in discover([target])]
        c += 1
    return made


def timed(cmd, env=None):
    t = time.perf_counter()
    done = subprocess.run(cmd, env=env, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    return time.perf_counter() - t, done


def batch(python, folder, out, workers, env, extra=()):
    shutil.rmtree(out, ignore_errors=True)
    seconds, done = timed([python, "-m", "sinew", "batch", folder, "-o", out, "--workers", str(workers),
                           "--fps", "30", "-q", *extra], env)
    rows = [json.loads(line) for line in open(os.path.join(out, "manifest.jsonl"))]
    return seconds, rows


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--sinew", default=os.path.join(HERE, "..", "build", "sinew"))
    ap.add_argument("--testdata", default=os.path.join(HERE, "..", "..", "shared", "testdata"))
    ap.add_argument("--files", type=int, default=500)
    ap.add_argument("--blender-files", type=int, default=24)
    ap.add_argument("--json", action="store_true")
    args = ap.parse_args()
    python = "/usr/bin/python3" if os.path.exists("/usr/bin/python3") else sys.executable
    env = dict(os.environ, PYTHONPATH=os.path.join(HERE, "..", "python"))
    env.setdefault("SINEW_LIBRARY", os.path.join(os.path.dirname(os.path.abspath(args.sinew)), "libsinew.so"))
    work = tempfile.mkdtemp(prefix="sinew-bench-batch-")
    result = {}
    try:
        library = os.path.join(work, "library")
        files = build_library(args.testdata, library, args.files)
        result["files"] = len(files)
        result["ceiling"] = parallel_ceiling()
        result["spawn_ceiling"] = spawn_ceiling(os.path.join(os.path.dirname(os.path.abspath(args.sinew)),
                                                             "sinew-import"))
        # the CLI, one process a file
        t = time.perf_counter()
        for f in files:
            subprocess.run([args.sinew, "pose", f, "--json", "-q"], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        result["cli_loop_s"] = time.perf_counter() - t
        for mode, extra in (("", ()), ("_isolated", ("--isolate",))):
            for workers in (1, 2):
                seconds, rows = batch(python, library, os.path.join(work, "out%d" % workers), workers, env, extra)
                result["batch%d%s_s" % (workers, mode)] = seconds
                result["batch%d%s_failed" % (workers, mode)] = sum(r["status"] == "failed" for r in rows)
                result["batch%d%s_frames" % (workers, mode)] = sum(r["frames"] for r in rows)
        # Blender against sinew batch on the files Blender reads
        blender = shutil.which("blender")
        if blender:
            picked = []
            for f in discover([args.testdata]):
                p = f["path"]
                if p.lower().endswith(".bvh"):
                    picked.append(p)
                elif p.lower().endswith(".fbx"):
                    head = open(p, "rb").read(27)
                    if head.startswith(b"Kaydara FBX Binary") and int.from_bytes(head[23:27], "little") >= 7100:
                        picked.append(p)
            picked = picked[: args.blender_files]
            sub = os.path.join(work, "blender-set")
            os.makedirs(sub)
            for i, p in enumerate(picked):
                os.symlink(p, os.path.join(sub, "%03d_%s" % (i, os.path.basename(p))))
            script = os.path.join(work, "export.py")
            open(script, "w").write(BLENDER_SCRIPT)
            t = time.perf_counter()
            ok = 0
            for i, p in enumerate(picked):
                _, done = timed([blender, "-b", "--factory-startup", "-noaudio", "--python", script, "--", p,
                                 os.path.join(work, "blender%03d.npz" % i)])
                ok += done.returncode == 0 and os.path.exists(os.path.join(work, "blender%03d.npz" % i))
            result["blender_files"] = len(picked)
            result["blender_ok"] = ok
            result["blender_s"] = time.perf_counter() - t
            # sinew on the same files, repeated to a library's size (its start-up spread as in real use)
            repeated = os.path.join(work, "blender-set-repeated")
            count = build_library(None, repeated, args.files, files=picked)
            seconds, rows = batch(python, repeated, os.path.join(work, "out-blender-set"), 1, env)
            result["batch1_blender_set_files"] = len(count)
            result["batch1_blender_set_s"] = seconds
            result["batch1_blender_set_in_workers_s"] = sum(r["seconds"] or 0 for r in rows)
    finally:
        shutil.rmtree(work, ignore_errors=True)
    n = result["files"]
    if args.json:
        print(json.dumps(result, indent=1))
        return
    print("library: %d files (../shared/testdata repeated)" % n)
    print("  sinew pose --json, a process a file: %6.1f files/s  %6.1f ms a file" % (
        n / result["cli_loop_s"], 1000 * result["cli_loop_s"] / n))
    for mode, label in (("", ""), ("_isolated", " --isolate")):
        for w in (1, 2):
            s = result["batch%d%s_s" % (w, mode)]
            print("  sinew batch --workers %d%-13s %6.1f files/s  %6.1f ms a file  (%d frames, %d failed)" % (
                w, label + ":", n / s, 1000 * s / n, result["batch%d%s_frames" % (w, mode)],
                result["batch%d%s_failed" % (w, mode)]))
        print("  2 workers / 1 worker%s: %.2fx" % (label, result["batch1%s_s" % mode] / result["batch2%s_s" % mode]))
    print("  (this machine gives 2 processes of pure CPU work %.2fx, and 2 loops starting processes %.2fx)" % (
        result["ceiling"], result["spawn_ceiling"]))
    if "blender_s" in result:
        b = result["blender_s"] / result["blender_files"]
        k = result["batch1_blender_set_files"]
        s = result["batch1_blender_set_s"] / k
        print("Blender 3.4 (-b, a process a file) on %d FBX/BVH files (%d written): %.0f ms a file" % (
            result["blender_files"], result["blender_ok"], 1000 * b))
        print("  sinew batch --workers 1 on the same files (repeated to %d): %.1f ms a file (run included), "
              "%.1f in the worker" % (k, 1000 * s, 1000 * result["batch1_blender_set_in_workers_s"] / k))
        print("  Blender / sinew per file: %.0fx" % (b / s))


if __name__ == "__main__":
    main()
