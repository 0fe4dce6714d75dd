"""sinew batch: every model file under the inputs turned into arrays, on a Dask cluster.

    sinew batch INPUT... -o OUTDIR [--fps N] [--clips all|NAME] [--retarget SKELETON_FILE]
                [--skin] [--preview] [--workers N | --scheduler tcp://HOST:PORT]

For each model file found (folders are searched recursively for the extensions sinew reads;
files named on the command line are always taken), each clip becomes OUTDIR/REL/NNN_CLIP.npz,
where REL is the file's path under its input (the file's name kept, so that two formats of
one scene do not collide). Each .npz holds the clip's times (T,), local translations (T,J,3),
rotations (T,J,4, x y z w), scales (T,J,3), world matrices (T,J,4,4), joint positions (T,J,3),
morph weights (T,C), the joint names and parents, rest transforms, fps, and the source's path
and SHA-256; with --skin the deformed vertices (T,V,3) and triangles; with --preview a GIF
beside it and a contact sheet of every clip in OUTDIR/contact-sheet.png.

OUTDIR/manifest.jsonl has a row per file: status (ok, cached, failed), error text and kind,
clips, frames, joints, vertices, seconds taken, warnings. The run ends by printing the failed
files' errors and the first 20 warnings (a file cut short, weights renormalised, ...). Each file is imported in sinew's helper
process with a deadline (--timeout) and a memory limit (--memory): a bad, hanging or huge file
is a failed row, never the end of the run. Outputs are written through temporary files renamed
into place, and a file is recorded as done only when all its outputs are: a rerun skips files
whose source hash and options are unchanged (after Ctrl+C or a lost worker), and redoes the
rest. The arrays do not depend on how many workers ran.
"""

import argparse
import hashlib
import json
import os
import signal
import subprocess
import sys
import tempfile
import time
from typing import List, Optional

EXTENSIONS = (
    ".fbx", ".gltf", ".glb", ".dae", ".zae", ".bvh", ".iqm", ".sinew", ".x", ".md5mesh", ".smd", ".3ds",
    ".ms3d", ".b3d", ".md2", ".md3", ".mdl", ".ogex", ".lwo", ".lws", ".ase", ".cob", ".q3o", ".irr",
)
STATE = ".sinew-batch"        # per-file records of finished work, under OUTDIR
PARTIAL = ".partial-"         # the infix of temporary files
FORMAT_VERSION = 1            # of the .npz layout; part of the options' hash
# exit statuses, as the other sinew commands have them
EXIT_OK, EXIT_USAGE, EXIT_BAD_INPUT, EXIT_UNAVAILABLE, EXIT_OUTPUT, EXIT_INTERRUPTED = 0, 1, 2, 3, 4, 130
_UMASK = os.umask(0o022)
os.umask(_UMASK)


# ---- finding the files -------------------------------------------------------------------------

def discover(inputs: List[str]) -> List[dict]:
    """(path, rel) for each model file: folders recursively (sorted, hidden names skipped,
    only the extensions sinew reads), files as given."""
    found, seen = [], set()
    for given in inputs:
        if os.path.isdir(given):
            base = os.path.basename(os.path.normpath(given)) or "input"
            for root, dirs, files in os.walk(given):
                dirs[:] = sorted(d for d in dirs if not d.startswith("."))
                for name in sorted(files):
                    path = os.path.join(root, name)
                    if name.startswith(".") or not name.lower().endswith(EXTENSIONS) or not os.path.isfile(path):
                        continue
                    rel = os.path.join(base, os.path.relpath(path, given))
                    if os.path.realpath(path) not in seen:
                        seen.add(os.path.realpath(path))
                        found.append({"path": path, "rel": rel})
        else:
            if os.path.realpath(given) not in seen:
                seen.add(os.path.realpath(given))
                found.append({"path": given, "rel": os.path.basename(given), "named": True})
    # files named with the same name from different folders keep as many of their folders' names
    # as tell them apart (a/walk.fbx, b/walk.fbx), so that their outputs do not collide
    depth = 1
    while True:
        rels = {}
        for f in found:
            rels.setdefault(f["rel"], []).append(f)
        clashing = [f for group in rels.values() if len(group) > 1 for f in group if f.get("named")]
        if not clashing or depth > 64:
            break
        depth += 1
        for f in clashing:
            parts = os.path.abspath(f["path"]).strip(os.sep).split(os.sep)
            f["rel"] = os.path.join(*parts[-depth:])
    for f in found:
        f.pop("named", None)
    return found


def file_hash(path: str) -> Optional[str]:
    """SHA-256 of a regular file's bytes; None for anything else (it is imported, never cached)."""
    try:
        if not os.path.isfile(path):
            return None
        h = hashlib.sha256()
        with open(path, "rb") as f:
            for chunk in iter(lambda: f.read(1 << 20), b""):
                h.update(chunk)
        return h.hexdigest()
    except OSError:
        return None


def safe_name(text: str) -> str:
    out = "".join(c if c.isalnum() or c in "-_." else "_" for c in text).strip("._")
    return out[:80] or "clip"


# ---- writing atomically ------------------------------------------------------------------------

def atomic_write(path: str, write) -> None:
    """Calls write(file) on a temporary file beside `path`, then renames it over `path`."""
    folder = os.path.dirname(path) or "."
    os.makedirs(folder, exist_ok=True)
    fd, tmp = tempfile.mkstemp(prefix=os.path.basename(path) + PARTIAL, dir=folder)
    try:
        os.fchmod(fd, 0o666 & ~_UMASK)
        with os.fdopen(fd, "wb") as f:
            write(f)
        # renamed whole: a killed worker or run leaves a temporary, never half a file (no
        # fsync: a power cut may lose the newest files, which the rerun then redoes)
        os.replace(tmp, path)
    except BaseException:
        try:
            os.unlink(tmp)
        except OSError:
            pass
        raise


def remove_partials(outdir: str) -> int:
    """Deletes temporaries a killed run or worker left behind; returns how many."""
    removed = 0
    for root, dirs, files in os.walk(outdir):
        for name in files:
            if PARTIAL in name:
                try:
                    os.unlink(os.path.join(root, name))
                    removed += 1
                except OSError:
                    pass
    return removed


# ---- one file, on a worker ---------------------------------------------------------------------

_SKELETONS = {}  # a worker's retarget skeletons, by path and hash
_IMPORTERS = {}  # a worker's import sessions (one running helper), by settings and thread


def _importer(opts):
    """This worker thread's import session: sinew's own formats read in the worker under the file's
    deadline and memory limit; with --isolate, in a helper that stays between files (a process
    start a file costs as much as a small file's work, and does not parallelise on every machine)."""
    import threading

    import sinew
    key = (opts["timeout"], opts["memory"], opts["isolate"], threading.get_ident())
    if key not in _IMPORTERS:
        _IMPORTERS[key] = sinew.Importer(timeout=opts["timeout"], memory=opts["memory"], isolate=opts["isolate"])
    return _IMPORTERS[key]


def _skeleton(path: str, digest: Optional[str], timeout, memory):
    import sinew
    key = (path, digest)
    if key not in _SKELETONS:
        _SKELETONS.clear()
        _SKELETONS[key] = sinew.load(path, timeout=timeout, memory=memory)
    return _SKELETONS[key]


def _encode(pixels, output_args, path: str) -> None:
    """RGBA pixels (...,H,W,4: frames or one picture) encoded by ffmpeg with `output_args`, written
    to `path` whole."""
    h, w = pixels.shape[-3:-1]
    cmd = ["ffmpeg", "-loglevel", "error", "-f", "rawvideo", "-pix_fmt", "rgba", "-s", "%dx%d" % (w, h), *output_args]
    done = subprocess.run(cmd, input=pixels.tobytes(), stdout=subprocess.PIPE, stderr=subprocess.PIPE, check=False)
    if done.returncode != 0:
        raise RuntimeError("ffmpeg: " + done.stderr.decode("utf-8", "replace").strip()[-300:])
    atomic_write(path, lambda f: f.write(done.stdout))


def _preview(frames, path: str, fps: float) -> None:
    """An animated GIF of RGBA frames (T,H,W,4) through ffmpeg (a palette made for the clip)."""
    _encode(frames, ["-r", "%g" % fps, "-i", "-", "-vf", "split[a][b];[a]palettegen=reserve_transparent=0[p];"
                     "[b][p]paletteuse", "-loop", "0", "-f", "gif", "-"], path)


def _row(job: dict, **fields) -> dict:
    """A manifest row for the job's file, failed until said otherwise."""
    row = {"file": job["path"], "rel": job["rel"], "sha256": job["sha256"], "status": "failed", "error": None,
           "kind": None, "clips": 0, "frames": 0, "joints": 0, "vertices": 0, "outputs": [], "warnings": []}
    row.update(fields)
    return row


def process_file(job: dict) -> dict:
    """Imports one file and writes its clips' arrays; returns its manifest row. Never raises
    for a bad file: the error is the row's."""
    import numpy as np

    import sinew

    started = time.monotonic()
    row = _row(job)
    opts = job["options"]
    try:
        model = _importer(opts).load(job["path"])
        row["warnings"] = list(model.warnings)  # the model's own list stays as the file gave it
        clips = list(range(len(model.clips)))
        if opts["retarget"]:
            source_clips = len(model.clips)
            skeleton = _skeleton(opts["retarget"], opts["retarget_sha256"], opts["timeout"], opts["memory"])
            model = sinew.retarget(skeleton, model, name_map=opts["name_map"], fps=opts["fps"] or 30.0)
            clips = list(range(source_clips))
        if opts["clips"] != "all":
            wanted = model.clip(opts["clips"]) if clips else None
            clips = [wanted.index] if wanted is not None and wanted.index in clips else []
            if not clips:
                raise sinew.ArgumentError("no clip %r (clips: %s)" % (
                    opts["clips"], ", ".join(c.name for c in model.clips) or "none"), job["path"])
        joints = model.joints
        row["joints"] = len(joints)
        row["vertices"] = model.vertex_count
        folder = os.path.join(job["outdir"], job["rel"])
        stills = []
        for index in clips or [None]:
            clip = model.clips[index] if index is not None else None
            times = clip.times(opts["fps"]) if clip else np.zeros(1, np.float32)
            if len(times) > opts["max_frames"]:
                row["warnings"].append("clip %r has %d frames at %g fps: kept the first %d (--max-frames)" % (
                    clip.name, len(times), opts["fps"] or clip.frame_rate, opts["max_frames"]))
                times = times[:opts["max_frames"]]
            a = model.arrays(clip, times=times, translations=True, rotations=True, scales=True, worlds=True,
                             weights=True, vertices=opts["skin"])
            arrays = {
                "times": times, "translations": a["translations"], "rotations": a["rotations"],
                "scales": a["scales"], "worlds": a["worlds"], "positions": np.ascontiguousarray(a["worlds"][:, :, :3, 3]),
                "weights": a["weights"], "joint_names": np.array(joints.names, dtype=str),
                "parents": joints.parents, "is_skin_joint": joints.is_skin_joint,
                "rest_translations": joints.rest_translations, "rest_rotations": joints.rest_rotations,
                "rest_scales": joints.rest_scales, "bind": joints.bind,
                "morph_channels": np.array(model.morph_channels, dtype=str),
                "fps": np.float32(opts["fps"] or (clip.frame_rate if clip else 30.0)),
                "duration": np.float32(clip.duration if clip else 0.0),
                "clip_name": np.array(clip.name if clip else ""), "clip_index": np.int32(index if clip else -1),
                "source": np.array(job["path"]), "source_sha256": np.array(job["sha256"] or ""),
                "options": np.array(job["options_key"]), "sinew_version": np.array(sinew.version()),
            }
            if opts["skin"]:
                arrays["vertices"] = a["vertices"]
                arrays["triangles"] = model.triangles()
            name = ("%03d_%s" % (index, safe_name(clip.name))) if clip else "rest"
            target = os.path.join(folder, name + ".npz")
            atomic_write(target, lambda f: (np.savez_compressed if opts["compress"] else np.savez)(f, **arrays))
            row["outputs"].append(os.path.relpath(target, job["outdir"]))
            row["frames"] += len(times)
            if opts["preview"]:
                pfps = min(float(opts["fps"] or 15.0), 15.0)
                ptimes = clip.times(pfps)[:90] if clip else np.zeros(1, np.float32)
                frames = sinew.render(model, clip, times=ptimes, size=opts["preview_size"], samples=4)
                gif = os.path.join(folder, name + ".gif")
                _preview(frames, gif, pfps)
                row["outputs"].append(os.path.relpath(gif, job["outdir"]))
                stills.append(frames[len(frames) // 2])
        row["clips"] = len(clips)
        if stills:
            still = os.path.join(job["outdir"], STATE, job["key"] + ".stills.npy")
            atomic_write(still, lambda f: np.save(f, np.stack(stills)))
        row["status"] = "ok"
    except sinew.Error as e:
        row["error"], row["kind"] = str(e), e.kind
    except Exception as e:  # a bug of ours or an output that cannot be written: still a row
        row["error"], row["kind"] = "%s: %s" % (type(e).__name__, e), "internal"
    row["seconds"] = round(time.monotonic() - started, 4)
    if row["status"] == "ok":
        record = os.path.join(job["outdir"], STATE, job["key"] + ".json")
        atomic_write(record, lambda f: f.write(json.dumps({"row": row, "options": job["options_key"]}).encode()))
    return row


def process_files(jobs: List[dict]) -> List[dict]:
    """process_file() for several files in one task (fewer tasks: less scheduling per file)."""
    return [process_file(job) for job in jobs]


# ---- the run -----------------------------------------------------------------------------------

def _cached(job: dict) -> Optional[dict]:
    """The row of a previous run that did this file with these options, if its outputs are all
    there and the file is unchanged."""
    if not job["sha256"]:
        return None
    try:
        with open(os.path.join(job["outdir"], STATE, job["key"] + ".json"), "rb") as f:
            record = json.load(f)
    except (OSError, ValueError):
        return None
    row = record.get("row", {})
    if record.get("options") != job["options_key"] or row.get("sha256") != job["sha256"]:
        return None
    if not all(os.path.isfile(os.path.join(job["outdir"], o)) for o in row.get("outputs", [])):
        return None
    return dict(row, status="cached")


class Progress:
    """One line on a terminal: files done, failed, rate, time left. Silent elsewhere."""

    def __init__(self, total: int, quiet: bool):
        self.total, self.done, self.failed = total, 0, 0
        self.started = time.monotonic()
        self.live = not quiet and sys.stderr.isatty()
        self.last = 0.0

    def update(self, row: dict) -> None:
        self.done += 1
        self.failed += row["status"] == "failed"
        now = time.monotonic()
        if self.live and (now - self.last > 0.1 or self.done == self.total):
            self.last = now
            rate = self.done / max(now - self.started, 1e-6)
            left = (self.total - self.done) / rate if rate > 0 else 0
            sys.stderr.write("\rsinew batch: %d/%d files, %d failed, %.1f files/s, %d:%02d left   " % (
                self.done, self.total, self.failed, rate, left // 60, left % 60))
            sys.stderr.flush()

    def close(self):
        if self.live:
            sys.stderr.write("\n")


def contact_sheet(outdir: str, rows: List[dict], path: str) -> Optional[str]:
    """The middle frame of every clip's preview, tiled 8 across, as a PNG (through ffmpeg)."""
    import numpy as np
    tiles = []
    for row in rows:
        if row["status"] in ("ok", "cached"):
            still = os.path.join(outdir, STATE, _key(row["rel"]) + ".stills.npy")
            if os.path.isfile(still):
                tiles.extend(np.load(still))
    if not tiles:
        return None
    h, w = tiles[0].shape[:2]
    across = min(8, len(tiles))
    down = (len(tiles) + across - 1) // across
    sheet = np.empty((down * h, across * w, 4), np.uint8)
    sheet[:] = (0x29, 0x2B, 0x30, 0xFF)  # the renderer's background
    for i, tile in enumerate(tiles):
        if tile.shape[:2] == (h, w):
            sheet[(i // across) * h:(i // across + 1) * h, (i % across) * w:(i % across + 1) * w] = tile

    _encode(sheet, ["-i", "-", "-frames:v", "1", "-f", "image2", "-c:v", "png", "-"], path)
    return path


def _key(rel: str) -> str:
    return hashlib.sha1(rel.encode("utf-8", "surrogateescape")).hexdigest()[:20]


def _client(args):
    from dask.distributed import Client, LocalCluster
    if args.scheduler:
        return Client(args.scheduler, timeout="30s"), None
    # the workers find this package and libsinew as this process did
    here = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    os.environ["PYTHONPATH"] = os.pathsep.join(p for p in (here, os.environ.get("PYTHONPATH")) if p)
    from . import _ffi
    os.environ.setdefault("SINEW_LIBRARY", _ffi.library_path)
    cluster = LocalCluster(n_workers=args.workers, threads_per_worker=1, processes=True, dashboard_address=None,
                           silence_logs=40)
    return Client(cluster), cluster


WARNINGS_SHOWN = 20  # warning lines a run prints at its end (the manifest has them all)


def _naming(path, text):
    """A message with its file's path before it, unless it names the file already (the library's do)."""
    return text if path in (text or "") else "%s: %s" % (path, text)


def run(args) -> int:
    from dask.distributed import as_completed

    import sinew

    outdir = os.path.abspath(args.output)
    os.makedirs(os.path.join(outdir, STATE), exist_ok=True)
    remove_partials(outdir)
    files = discover(args.inputs)
    if not files:
        print("sinew batch: no model files under %s" % " ".join(args.inputs), file=sys.stderr)
        return EXIT_BAD_INPUT
    width, height = (int(v) for v in args.preview_size.lower().split("x"))
    options = {"fps": args.fps, "clips": args.clips, "retarget": os.path.abspath(args.retarget) if args.retarget else None,
               "retarget_sha256": file_hash(args.retarget) if args.retarget else None,
               "name_map": os.path.abspath(args.name_map) if args.name_map else None,
               "skin": args.skin, "preview": args.preview, "preview_size": (width, height),
               "isolate": args.isolate, "max_frames": args.max_frames, "compress": args.compress, "timeout": args.timeout, "memory": args.memory * (1 << 20) if args.memory else None}
    options_key = hashlib.sha256(json.dumps([FORMAT_VERSION, sinew.version(), {
        k: v for k, v in options.items() if k not in ("timeout", "memory", "retarget", "isolate")}], sort_keys=True).encode()).hexdigest()
    jobs, rows = [], {}
    for order, f in enumerate(files):
        job = dict(f, order=order, outdir=outdir, options=options, options_key=options_key,
                   key=_key(f["rel"]), sha256=None if args.force else file_hash(f["path"]))
        cached = None if args.force else _cached(job)
        if cached:
            rows[order] = cached
        else:
            jobs.append(job)
    progress = Progress(len(files), args.quiet)
    for row in rows.values():
        progress.update(row)
    interrupted = False
    client = cluster = None
    try:
        if jobs:
            client, cluster = _client(args)
            # files go out in groups of a few (each task costs the scheduler about a millisecond, as
            # much as a small file): about 8 groups a worker, at most 16 files a group; a group whose
            # worker died is sent again file by file, so that one deadly file fails alone
            workers = max(1, len(client.scheduler_info().get("workers", {})) or args.workers or 1)
            size = max(1, min(16, len(jobs) // (workers * 8)))
            futures = {}
            for start in range(0, len(jobs), size):
                group = jobs[start:start + size]
                future = client.submit(process_files, group, key="sinew-batch-%s-%s-%d" % (
                    group[0]["key"], options_key[:12], len(group)), pure=False, retries=0 if size > 1 else 2)
                futures[future] = group
            pending = as_completed(futures)
            for future in pending:
                group = futures[future]
                try:
                    results = future.result()
                except Exception as e:
                    if len(group) > 1:
                        for job in group:
                            again = client.submit(process_files, [job], key="sinew-batch-%s-%s-1" % (
                                job["key"], options_key[:12]), pure=False, retries=2)
                            futures[again] = [job]
                            pending.add(again)
                        continue
                    job = group[0]  # the file killed its worker every time it was tried
                    results = [_row(job, kind="crash", seconds=None, error="%s: the worker processing it died (%s)"
                                    % (job["path"], type(e).__name__))]
                for job, row in zip(group, results):
                    rows[job["order"]] = row
                    progress.update(row)
    except KeyboardInterrupt:
        interrupted = True
    finally:
        progress.close()
        if client is not None:
            client.close()
        if cluster is not None:
            cluster.close()
        remove_partials(outdir)
    ordered = [rows[i] for i in sorted(rows)]
    atomic_write(os.path.join(outdir, "manifest.jsonl"),
                 lambda f: f.write("".join(json.dumps(r, sort_keys=True) + "\n" for r in ordered).encode()))
    if args.preview and not interrupted:
        try:
            contact_sheet(outdir, ordered, os.path.join(outdir, "contact-sheet.png"))
        except (OSError, RuntimeError) as e:
            print("sinew batch: no contact sheet: %s" % e, file=sys.stderr)
    failed = [r for r in ordered if r["status"] == "failed"]
    warned = [r for r in ordered if r["status"] == "ok" and r["warnings"]]
    if not args.quiet:
        for r in failed:
            print("sinew batch: %s" % _naming(r["file"], r["error"]), file=sys.stderr)
        # the files read with warnings (frames lost, weights renormalised ...): the first few here,
        # every one in the manifest; an unchanged file's were said when it was read
        lines = [_naming(r["file"], w) for r in warned for w in r["warnings"]]
        for text in lines[:WARNINGS_SHOWN]:
            print("sinew batch: warning: %s" % text, file=sys.stderr)
        if len(lines) > WARNINGS_SHOWN:
            print("sinew batch: %d more warnings, in the manifest" % (len(lines) - WARNINGS_SHOWN), file=sys.stderr)
        done = sum(r["status"] == "ok" for r in ordered)
        cached = sum(r["status"] == "cached" for r in ordered)
        print("sinew batch: %d files: %d done%s, %d unchanged, %d failed%s; manifest %s" % (
            len(ordered), done, " (%d with warnings)" % len(warned) if warned else "", cached, len(failed),
            ", interrupted" if interrupted else "", os.path.join(outdir, "manifest.jsonl")), file=sys.stderr)
    if interrupted:
        return EXIT_INTERRUPTED
    return EXIT_BAD_INPUT if failed else EXIT_OK


class _Parser(argparse.ArgumentParser):
    def error(self, message):
        self.print_usage(sys.stderr)
        self.exit(EXIT_USAGE, "sinew batch: %s\n" % message)


def parser() -> argparse.ArgumentParser:
    p = _Parser(prog="sinew batch", description=__doc__.split("\n\n")[0],
                                formatter_class=argparse.RawDescriptionHelpFormatter,
                                epilog="exit status: 0 every file done, 1 usage error, 2 some files failed (the manifest "
                                       "says which and why) or none found, 3 numpy, cffi or Dask missing, 4 OUTDIR "
                                       "cannot be written, 130 interrupted (rerun to resume)")
    p.add_argument("inputs", nargs="+", metavar="INPUT", help="model files and folders (searched recursively)")
    p.add_argument("-o", "--output", required=True, metavar="OUTDIR", help="where the .npz files and manifest go")
    p.add_argument("--fps", type=float, default=None, help="frames a second to sample (default: each clip's own rate)")
    p.add_argument("--max-frames", type=int, default=18000, metavar="N",
                   help="frames kept a clip (default 18000: 10 minutes at 30 fps); longer clips keep their first N, with a warning")
    p.add_argument("--clips", default="all", metavar="all|NAME", help="every clip (default), or the one named")
    p.add_argument("--retarget", metavar="SKELETON_FILE", help="retarget every clip onto this model's skeleton")
    p.add_argument("--name-map", metavar="MAP.json", help="with --retarget: joint names {\"source\": \"target\"}")
    p.add_argument("--skin", action="store_true", help="also store the skinned vertices (T,V,3) and triangles")
    p.add_argument("--compress", action="store_true",
                   help="deflate the .npz files (smaller, slower; np.load reads both)")
    p.add_argument("--preview", action="store_true", help="an animated GIF per clip and OUTDIR/contact-sheet.png")
    p.add_argument("--preview-size", default="160x120", metavar="WxH", help="preview size (default 160x120)")
    g = p.add_mutually_exclusive_group()
    g.add_argument("--workers", type=int, default=2, metavar="N", help="local worker processes (default 2)")
    g.add_argument("--scheduler", metavar="tcp://HOST:PORT", help="run on an existing Dask scheduler's workers")
    p.add_argument("--timeout", type=float, default=60.0, metavar="S", help="seconds one file's import may take (60)")
    p.add_argument("--memory", type=int, default=None, metavar="MIB", help="memory one file's import may use")
    p.add_argument("--isolate", action="store_true",
                   help="read every file in the import helper, not only Assimp's formats: for files from strangers "
                        "(a file that crashes a reader then costs an error row, not its worker and Dask's retries); "
                        "by default sinew's own readers run in the worker under the same deadline and memory limit")
    p.add_argument("--force", action="store_true", help="redo every file, even unchanged ones")
    p.add_argument("-q", "--quiet", action="store_true", help="no progress line, no summary")
    return p


def main(argv=None) -> int:
    args = parser().parse_args(argv)
    if args.workers is not None and args.workers < 1:
        parser().error("--workers must be at least 1")
    if args.max_frames < 1:
        parser().error("--max-frames must be at least 1")
    try:
        w, h = (int(v) for v in args.preview_size.lower().split("x"))
        if not (8 <= w <= 1024 and 8 <= h <= 1024):
            raise ValueError
    except ValueError:
        parser().error("--preview-size WxH, 8 to 1024 a side")
    for given in args.inputs:
        if not os.path.exists(given):
            parser().error("%s: no such file or folder" % given)
    signal.signal(signal.SIGTERM, signal.default_int_handler)
    try:
        os.makedirs(os.path.join(args.output, STATE), exist_ok=True)
        probe = os.path.join(args.output, STATE, ".write-test")
        open(probe, "wb").close()
        os.unlink(probe)
    except OSError as e:
        print("sinew batch: %s: cannot write there (%s)" % (args.output, e.strerror or e), file=sys.stderr)
        return EXIT_OUTPUT
    try:
        import dask.distributed  # noqa: F401
        import numpy  # noqa: F401

        from . import _ffi  # noqa: F401
    except ImportError as e:
        print("sinew batch: %s; it needs numpy, cffi and Dask distributed (Debian: python3-numpy python3-cffi "
              "python3-distributed) and libsinew" % e, file=sys.stderr)
        return EXIT_UNAVAILABLE
    return run(args)


if __name__ == "__main__":
    sys.exit(main())
