"""sinew batch on a Dask LocalCluster: the shared test data with a truncated and a hanging file
mixed in, the manifest, a resumed rerun, a worker killed mid-run, Ctrl+C, and results that do
not depend on the number of workers."""
import json
import os
import signal
import subprocess
import sys
import time
import zipfile

import numpy as np
import pytest

import sinew

HERE = os.path.dirname(os.path.abspath(__file__))
PYTHON_DIR = os.path.dirname(HERE)


def hanging_file(testdata, folder):
    """Assimp's COLLADA reader loops without end on duck.dae with byte 245632 set to 0xC0;
    zipped as a .zae (a format only Assimp reads) it reaches Assimp: a file that hangs."""
    source = os.path.join(testdata, "assimp", "Collada", "duck.dae")
    if not os.path.exists(source):
        pytest.skip("assimp/Collada/duck.dae is not in the shared test data")
    data = bytearray(open(source, "rb").read())
    data[245632] = 0xC0
    path = os.path.join(str(folder), "hangs.zae")
    with zipfile.ZipFile(path, "w", zipfile.ZIP_DEFLATED) as z:
        z.writestr("duck.dae", bytes(data))
    return path


def truncated_file(testdata, folder):
    data = open(os.path.join(testdata, "ozz", "pab", "arnaud.fbx"), "rb").read()
    path = os.path.join(str(folder), "truncated.fbx")
    open(path, "wb").write(data[: len(data) // 2])
    return path


def batch(*args, env=None, check=None, **kw):
    """Runs `python3 -m sinew batch` as a user would (the `sinew batch` command execs it)."""
    environment = dict(os.environ, PYTHONPATH=PYTHON_DIR, **(env or {}))
    done = subprocess.run([sys.executable, "-m", "sinew", "batch", *args], env=environment,
                          stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, **kw)
    if check is not None:
        assert done.returncode == check, done.stderr
    return done


def manifest(outdir):
    return [json.loads(line) for line in open(os.path.join(outdir, "manifest.jsonl"))]


def arrays(outdir, rows):
    out = {}
    for row in rows:
        for rel in row["outputs"]:
            if rel.endswith(".npz"):
                with np.load(os.path.join(outdir, rel)) as z:
                    out[rel] = {k: z[k] for k in z.files}
    return out


def no_partials(outdir):
    left = [os.path.join(r, f) for r, _, fs in os.walk(outdir) for f in fs if ".partial-" in f]
    assert not left, left


def subset(testdata, folder, names):
    """A folder of links to some shared models (a smaller library for the slower checks)."""
    os.makedirs(folder, exist_ok=True)
    for rel in names:
        os.symlink(os.path.join(testdata, rel), os.path.join(folder, rel.replace("/", "__")))
    return folder


SMALL = ["gltf-samples/Fox.glb", "ozz/pab/arnaud.fbx", "ozz/pab/walk.dae", "assimp/BVH/01_01.bvh",
         "blender/robot_walk.dae", "raylib/guy.iqm", "assimp/X/anim_test.x", "gltf-samples/AnimatedMorphCube.glb",
         "ufbx/maya_anim_layers_7500_ascii.fbx", "ufbx/max7_blend_cube_5000_binary.fbx",
         "collada-cts/clip_2_clips_on_same_animation_different_time.dae", "ufbx/max_transformed_skin_6100_ascii.fbx"]


@pytest.fixture(scope="module")
def library_run(testdata, tmp_path_factory):
    """The whole shared test data, plus a truncated and a hanging file, on 2 workers."""
    extra = tmp_path_factory.mktemp("extra")
    truncated = truncated_file(testdata, extra)
    hangs = hanging_file(testdata, extra)
    out = str(tmp_path_factory.mktemp("out"))
    started = time.monotonic()
    done = batch(testdata, truncated, hangs, "-o", out, "--workers", "2", "--timeout", "5", "--fps", "30")
    return {"out": out, "done": done, "seconds": time.monotonic() - started, "truncated": truncated,
            "hangs": hangs, "testdata": testdata}


def test_library_manifest(library_run):
    out, done = library_run["out"], library_run["done"]
    assert done.returncode == 2, done.stderr  # some files failed, and the run went on
    rows = manifest(out)
    found = [r["file"] for r in rows]
    assert len(found) == len(set(found))
    assert library_run["truncated"] in found and library_run["hangs"] in found
    assert len(rows) > 150
    by_file = {r["file"]: r for r in rows}
    t = by_file[library_run["truncated"]]
    assert t["status"] == "failed" and t["kind"] == "format" and "truncated.fbx" in t["error"]
    h = by_file[library_run["hangs"]]
    # stopped by its deadline, or sooner by the default memory limit of a file of its size
    assert h["status"] == "failed" and h["kind"] in ("limit_time", "limit_memory")
    assert ("deadline" in h["error"]) == (h["kind"] == "limit_time")
    ok = [r for r in rows if r["status"] == "ok"]
    assert len(ok) >= len(rows) - 4, [(r["file"], r["error"]) for r in rows if r["status"] != "ok"]
    for r in rows:
        assert set(r) >= {"file", "status", "error", "kind", "clips", "frames", "joints", "seconds"}
        if r["status"] == "ok":
            assert r["outputs"] and all(os.path.isfile(os.path.join(out, o)) for o in r["outputs"])
    no_partials(out)
    assert "failed" in done.stderr and "hangs.zae" in done.stderr


def test_library_arrays_equal_the_binding(library_run):
    out, testdata = library_run["out"], library_run["testdata"]
    fox = os.path.join(testdata, "gltf-samples", "Fox.glb")
    row = next(r for r in manifest(out) if r["file"] == fox)
    assert row["clips"] == 3
    with np.load(os.path.join(out, row["outputs"][1])) as z:
        assert str(z["clip_name"]) == "Walk" and float(z["fps"]) == 30
        m = sinew.load(fox)
        times = m.clips[1].times(30)
        assert np.array_equal(z["times"], times)
        assert np.array_equal(z["worlds"], m.world(1, times=times))
        assert np.array_equal(z["rotations"], m.sample(1, times=times).rotations)
        assert list(z["joint_names"]) == m.joints.names and np.array_equal(z["parents"], m.joints.parents)
        import hashlib
        assert str(z["source_sha256"]) == hashlib.sha256(open(fox, "rb").read()).hexdigest()


def test_library_rerun_skips_unchanged(library_run):
    out = library_run["out"]
    before = manifest(out)
    started = time.monotonic()
    done = batch(library_run["testdata"], library_run["truncated"], library_run["hangs"], "-o", out,
                 "--workers", "2", "--timeout", "5", "--fps", "30")
    took = time.monotonic() - started
    assert done.returncode == 2
    after = manifest(out)
    assert [r["file"] for r in after] == [r["file"] for r in before]
    for a, b in zip(after, before):
        if b["status"] == "ok":
            assert a["status"] == "cached" and a["outputs"] == b["outputs"]
        else:
            assert a["status"] == "failed"  # failures are tried again
    assert took < library_run["seconds"]


def test_changed_options_and_sources_redo(testdata, tmp_path):
    lib = subset(testdata, str(tmp_path / "lib"), SMALL[:4])
    out = str(tmp_path / "out")
    batch(lib, "-o", out, "--workers", "1", check=0)
    assert {r["status"] for r in manifest(out)} == {"ok"}
    batch(lib, "-o", out, "--workers", "1", check=0)
    assert {r["status"] for r in manifest(out)} == {"cached"}
    batch(lib, "-o", out, "--workers", "1", "--fps", "12", check=0)
    assert {r["status"] for r in manifest(out)} == {"ok"}
    # a changed file is done again, the others are not
    changed = os.path.join(lib, "copy.bvh")
    data = open(os.path.join(testdata, "assimp/BVH/01_01.bvh"), "rb").read()
    open(changed, "wb").write(data)
    batch(lib, "-o", out, "--workers", "1", "--fps", "12", check=0)
    rows = {os.path.basename(r["file"]): r["status"] for r in manifest(out)}
    assert rows["copy.bvh"] == "ok" and list(rows.values()).count("cached") == 4
    open(changed, "wb").write(data.replace(b"Frame Time", b"Frame Time", 1) + b"\n")
    batch(lib, "-o", out, "--workers", "1", "--fps", "12", check=0)
    rows = {os.path.basename(r["file"]): r["status"] for r in manifest(out)}
    assert rows["copy.bvh"] == "ok" and list(rows.values()).count("cached") == 4


def test_same_results_for_any_worker_count(testdata, tmp_path):
    lib = subset(testdata, str(tmp_path / "lib"), SMALL)
    one, two, inside = str(tmp_path / "one"), str(tmp_path / "two"), str(tmp_path / "inside")
    batch(lib, "-o", one, "--workers", "1", "--skin", check=0)
    batch(lib, "-o", two, "--workers", "2", "--skin", check=0)
    batch(lib, "-o", inside, "--workers", "2", "--skin", "--isolate", check=0)
    a, b, c = arrays(one, manifest(one)), arrays(two, manifest(two)), arrays(inside, manifest(inside))
    assert a.keys() == b.keys() == c.keys() and len(a) >= len(SMALL)
    for rel in a:
        assert a[rel].keys() == b[rel].keys() == c[rel].keys()
        for k in a[rel]:
            assert np.array_equal(a[rel][k], b[rel][k]), (rel, k)
            assert np.array_equal(a[rel][k], c[rel][k]), (rel, k)
    assert "vertices" in a[next(k for k in a if "Fox" in k)]


def _worker_pids(parent):
    import psutil
    try:
        children = psutil.Process(parent).children(recursive=True)
    except psutil.NoSuchProcess:
        return []
    return [c.pid for c in children if any("spawn_main" in part for part in c.cmdline())]


def _wait_for_outputs(out, count, proc, seconds=120):
    deadline = time.monotonic() + seconds
    while time.monotonic() < deadline and proc.poll() is None:
        npz = [f for _, _, fs in os.walk(out) for f in fs if f.endswith(".npz")]
        if len(npz) >= count:
            return True
        time.sleep(0.05)
    return False


def test_worker_killed_mid_run_loses_nothing(testdata, tmp_path):
    lib = subset(testdata, str(tmp_path / "lib"), SMALL)
    out, reference = str(tmp_path / "out"), str(tmp_path / "ref")
    batch(lib, "-o", reference, "--workers", "1", "--skin", check=0)
    env = dict(os.environ, PYTHONPATH=PYTHON_DIR)
    proc = subprocess.Popen([sys.executable, "-m", "sinew", "batch", lib, "-o", out, "--workers", "2", "--skin"],
                            env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    killed = None
    if _wait_for_outputs(out, 2, proc):
        pids = _worker_pids(proc.pid)
        if pids:
            killed = pids[0]
            os.kill(killed, signal.SIGKILL)
    _, err = proc.communicate(timeout=300)
    assert killed, "no worker process found to kill"
    assert proc.returncode == 0, err
    rows = manifest(out)
    assert len(rows) == len(SMALL) and {r["status"] for r in rows} == {"ok"}
    no_partials(out)
    a, b = arrays(out, rows), arrays(reference, manifest(reference))
    assert a.keys() == b.keys()
    for rel in a:
        for k in a[rel]:
            assert np.array_equal(a[rel][k], b[rel][k]), (rel, k)


def test_interrupted_run_resumes(testdata, tmp_path):
    lib = subset(testdata, str(tmp_path / "lib"), SMALL)
    out = str(tmp_path / "out")
    env = dict(os.environ, PYTHONPATH=PYTHON_DIR)
    proc = subprocess.Popen([sys.executable, "-m", "sinew", "batch", lib, "-o", out, "--workers", "1", "--skin"],
                            env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    assert _wait_for_outputs(out, 3, proc)
    proc.send_signal(signal.SIGINT)
    _, err = proc.communicate(timeout=120)
    if proc.returncode == 0:
        pytest.skip("the run finished before it could be interrupted")
    assert proc.returncode == 130, err
    assert "interrupted" in err
    first = manifest(out)
    assert 0 < len(first) < len(SMALL) and {r["status"] for r in first} <= {"ok"}
    no_partials(out)
    batch(lib, "-o", out, "--workers", "2", "--skin", check=0)
    rows = manifest(out)
    assert len(rows) == len(SMALL)
    # what finished before the interrupt is kept (a worker may have finished one more meanwhile)
    assert sum(r["status"] == "cached" for r in rows) >= len(first)


def test_sinew_batch_command(testdata, cli, tmp_path):
    """`sinew batch` (the C program) runs the same Python package."""
    out = str(tmp_path / "out")
    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "SINEW_LIBRARY")}
    done = subprocess.run([cli, "batch", os.path.join(testdata, "gltf-samples", "Fox.glb"), "-o", out,
                           "--workers", "1", "--clips", "Run"], env=env, stdout=subprocess.PIPE,
                          stderr=subprocess.PIPE, text=True)
    assert done.returncode == 0, done.stderr
    rows = manifest(out)
    assert rows[0]["clips"] == 1 and rows[0]["outputs"] == ["Fox.glb/002_Run.npz"]
    assert "usage: sinew batch" in subprocess.run([cli, "batch", "--help"], env=env, stdout=subprocess.PIPE,
                                                  text=True).stdout


def test_preview_and_contact_sheet(testdata, tmp_path):
    lib = subset(testdata, str(tmp_path / "lib"), SMALL[:3])
    out = str(tmp_path / "out")
    done = batch(lib, "-o", out, "--workers", "1", "--preview", "--preview-size", "96x72")
    if "no EGL" in done.stderr or "EGL" in done.stderr and done.returncode:
        pytest.skip("no EGL here")
    assert done.returncode == 0, done.stderr
    rows = manifest(out)
    gifs = [o for r in rows for o in r["outputs"] if o.endswith(".gif")]
    assert len(gifs) == sum(r["clips"] for r in rows)
    assert all(open(os.path.join(out, g), "rb").read(6) == b"GIF89a" for g in gifs)
    sheet = open(os.path.join(out, "contact-sheet.png"), "rb").read()
    assert sheet[:8] == b"\x89PNG\r\n\x1a\n"


def test_warnings_reach_the_user(testdata, tmp_path):
    """A file read with warnings says so at the end of the run, not only in the manifest; a run
    with many says how many more the manifest holds."""
    lib = tmp_path / "lib"
    lib.mkdir()
    data = open(os.path.join(testdata, "assimp/BVH/01_01.bvh"), "rb").read()
    for i in range(22):  # cut inside its MOTION: the whole frames kept, with a warning
        (lib / ("cut%02d.bvh" % i)).write_bytes(data[: len(data) // 2 + 1000 * i])
    done = batch(str(lib), "-o", str(tmp_path / "out"), "--workers", "1", "--fps", "10", check=0)
    shown = [line for line in done.stderr.splitlines() if line.startswith("sinew batch: warning: ")]
    assert len(shown) == 20 and all("cut" in line and "frames (the" in line for line in shown)
    assert "sinew batch: 2 more warnings, in the manifest" in done.stderr
    assert "22 files: 22 done (22 with warnings)" in done.stderr
    rows = manifest(str(tmp_path / "out"))
    assert all(r["warnings"] and "ends after" in r["warnings"][0] for r in rows)


def test_usage_errors(tmp_path):
    assert batch("-o", str(tmp_path)).returncode == 1
    done = batch(str(tmp_path / "nothing-here"), "-o", str(tmp_path / "o"))
    assert done.returncode == 1 and "nothing-here" in done.stderr
    (tmp_path / "empty").mkdir()
    done = batch(str(tmp_path / "empty"), "-o", str(tmp_path / "o"))
    assert done.returncode == 2 and "no model files" in done.stderr
    (tmp_path / "file").write_bytes(b"")
    done = batch(str(tmp_path / "empty"), "-o", str(tmp_path / "file" / "o"))
    assert done.returncode == 4 and "cannot write" in done.stderr
    assert "manifest" in batch("--help").stdout


def test_on_a_running_scheduler(testdata, tmp_path):
    """--scheduler: the set-up the README gives for several machines (`dask scheduler`, `dask
    worker` with the package on PYTHONPATH), here with both on this machine."""
    import socket
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        port = s.getsockname()[1]
    address = "tcp://127.0.0.1:%d" % port
    env = dict(os.environ, PYTHONPATH=PYTHON_DIR)
    scheduler = subprocess.Popen([sys.executable, "-m", "distributed.cli.dask_scheduler", "--host", "127.0.0.1",
                                  "--port", str(port), "--dashboard-address", ":0"], env=env,
                                 stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    worker = subprocess.Popen([sys.executable, "-m", "distributed.cli.dask_worker", address, "--nworkers", "1",
                               "--nthreads", "1", "--dashboard-address", ":0"], env=env,
                              stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    try:
        lib = subset(testdata, str(tmp_path / "lib"), SMALL[:4])
        out = str(tmp_path / "out")
        done = batch(lib, "-o", out, "--scheduler", address, timeout=240)
        assert done.returncode == 0, done.stderr
        assert [r["status"] for r in manifest(out)] == ["ok"] * 4
    finally:
        for p in (worker, scheduler):
            p.terminate()
        for p in (worker, scheduler):
            try:
                p.wait(timeout=30)
            except subprocess.TimeoutExpired:
                p.kill()


def test_progress_line_on_a_terminal(testdata, tmp_path):
    """A progress line (files, failed, rate, time left) on a terminal; none when stderr is not one."""
    import pty
    lib = subset(testdata, str(tmp_path / "lib"), SMALL[:3])
    out = str(tmp_path / "out")
    leader, follower = pty.openpty()
    env = dict(os.environ, PYTHONPATH=PYTHON_DIR)
    proc = subprocess.Popen([sys.executable, "-m", "sinew", "batch", lib, "-o", out, "--workers", "1"], env=env,
                            stdout=subprocess.DEVNULL, stderr=follower)
    os.close(follower)
    seen = b""
    while True:
        try:
            chunk = os.read(leader, 4096)
        except OSError:
            break
        if not chunk:
            break
        seen += chunk
    os.close(leader)
    assert proc.wait(timeout=120) == 0
    text = seen.decode("utf-8", "replace")
    assert "3/3 files, 0 failed" in text and "files/s" in text and "left" in text
    quiet = batch(lib, "-o", out, "--workers", "1", "--force")
    assert "files/s" not in quiet.stderr and "3 files: 3 done" in quiet.stderr


def test_files_of_one_name_do_not_collide(testdata, tmp_path):
    from sinew.batch import discover
    a, b = tmp_path / "a", tmp_path / "b"
    a.mkdir()
    b.mkdir()
    data = open(os.path.join(testdata, "assimp/BVH/01_01.bvh"), "rb").read()
    (a / "walk.bvh").write_bytes(data)
    (b / "walk.bvh").write_bytes(data.replace(b"MOTION", b"MOTION", 1))
    found = discover([str(a / "walk.bvh"), str(b / "walk.bvh"), str(a)])
    assert [f["rel"] for f in found] == ["a/walk.bvh", "b/walk.bvh"]
    assert discover([str(a / "walk.bvh")])[0]["rel"] == "walk.bvh"
