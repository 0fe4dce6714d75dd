"""The Python binding against the C library's own answers: `sinew info --json` for what a
model holds (which also checks the binding's structure layouts), `sinew pose --json` for world
transforms and `sinew pose --mesh` for deformed vertices, on shared models of every format."""
import json
import os
import subprocess
import threading
import time

import numpy as np
import pytest

import sinew

# a sample across formats and exporters: (file under testdata, clip, times)
MODELS = [
    ("gltf-samples/Fox.glb", 1, [0.0, 0.3, 0.65]),
    ("gltf-samples/AnimatedMorphCube.glb", 0, [0.0, 0.5, 1.0]),
    ("ozz/pab/arnaud.fbx", 0, [0.0, 0.4]),
    ("ozz/pab/walk.dae", 0, [0.1, 0.9]),
    ("blender/robot_walk.dae", 0, [0.0, 0.5]),
    ("raylib/robot.glb", 3, [0.2, 0.7]),
    ("raylib/guy.iqm", None, [0.0]),
    ("assimp/BVH/01_01.bvh", 0, [0.0, 1.0, 2.5]),
    ("assimp/X/anim_test.x", 0, [0.0, 0.5]),
    ("ufbx/maya_anim_layers_7500_ascii.fbx", 0, [0.0, 0.5, 1.0]),
    ("ufbx/max_transformed_skin_6100_binary.fbx", 0, [5 / 30, 15 / 30]),
    ("ufbx/blender440_shape_weight_anim_7400_binary.fbx", 0, [5 / 24, 15 / 24]),
    ("ufbx/max7_blend_cube_5000_binary.fbx", 0, [8 / 30, 24 / 30]),
]


def run_json(cli, *args):
    done = subprocess.run([cli, *args], stdout=subprocess.PIPE, stderr=subprocess.PIPE, check=True)
    return json.loads(done.stdout)


def model_path(testdata, rel):
    path = os.path.join(testdata, rel)
    if not os.path.exists(path):
        pytest.skip("%s is not in the shared test data" % rel)
    return path


def quat_matrix(q):
    x, y, z, w = (float(v) for v in q)
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                     [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                     [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])


@pytest.mark.parametrize("rel,clip,times", MODELS, ids=[m[0] for m in MODELS])
def test_model_matches_info(testdata, cli, rel, clip, times):
    path = model_path(testdata, rel)
    info = run_json(cli, "info", path, "--json")
    m = sinew.load(path)
    assert m.path == path
    assert len(m.joints) == info["counts"]["nodes"]
    assert m.joints.names == [n["name"] for n in info["nodes"]]
    names = m.joints.names
    assert [names[p] if p >= 0 else None for p in m.joints.parents] == [n["parent"] for n in info["nodes"]]
    assert int(m.joints.is_skin_joint.sum()) == info["counts"]["joints"]
    assert [c.name for c in m.clips] == [c["name"] for c in info["clips"]]
    assert np.allclose([c.duration for c in m.clips], [c["duration"] for c in info["clips"]], atol=1e-6)
    assert [x.name for x in m.meshes] == [x["name"] for x in info["meshes"]]
    assert [x.vertex_count for x in m.meshes] == [x["vertices"] for x in info["meshes"]]
    assert [len(x.triangles) for x in m.meshes] == [x["triangles"] for x in info["meshes"]]
    assert m.morph_channels == [c["name"] for c in info["morph_channels"]]
    assert m.warnings == info["warnings"]


@pytest.mark.parametrize("rel,clip,times", MODELS, ids=[m[0] for m in MODELS])
def test_worlds_match_pose(testdata, cli, rel, clip, times):
    path = model_path(testdata, rel)
    args = ["pose", path, "--json", "--time", ",".join("%.9g" % t for t in times)]
    args += ["--clip", str(clip)] if clip is not None else ["--clip", "none"]
    pose = run_json(cli, *args)
    m = sinew.load(path)
    worlds = m.world(clip, times=times)
    assert worlds.shape == (len(times), len(m.joints), 4, 4)
    positions = m.positions(clip, times=times)
    size = max(1.0, float(np.ptp(positions.reshape(-1, 3), axis=0).max()))
    for f, frame in enumerate(pose["frames"]):
        assert frame["time"] == pytest.approx(times[f], abs=1e-6)
        for j, node in enumerate(frame["nodes"]):
            w = worlds[f, j].astype(np.float64)
            assert np.allclose(w[:3, 3], node["translation"], rtol=0, atol=1e-6 * size), (node["name"], f)
            assert np.allclose(positions[f, j], node["translation"], rtol=0, atol=1e-6 * size)
            # pose prints a decomposition (rotation and scale) of the matrix, which loses a few
            # ulps where the matrix is not exactly orthogonal: the 3x3 part agrees to 1e-5
            expected = quat_matrix(node["rotation"]) * np.array(node["scale"])[None, :]
            scale = max(1.0, float(np.abs(node["scale"]).max()))
            assert np.allclose(w[:3, :3], expected, rtol=0, atol=1e-5 * scale), (node["name"], f)
        if "weights" in frame:
            weights = m.morph_weights(clip, times=[times[f]])[0]
            assert np.allclose(weights, [c["weight"] for c in frame["weights"]], atol=1e-6)


@pytest.mark.parametrize("rel,clip,times", MODELS[:6] + MODELS[-3:], ids=[m[0] for m in MODELS[:6] + MODELS[-3:]])
def test_skin_matches_pose_mesh(testdata, cli, tmp_path, rel, clip, times):
    path = model_path(testdata, rel)
    out = tmp_path / "pose.obj"
    args = ["pose", path, "--time", "%.9g" % times[-1], "--mesh", str(out)]
    args += ["--clip", str(clip)] if clip is not None else []
    subprocess.run([cli, *args], check=True, stdout=subprocess.DEVNULL)
    expected = np.array([[float(v) for v in line.split()[1:4]] for line in open(out) if line.startswith("v ")])
    expected = expected.reshape(-1, 3)
    m = sinew.load(path)
    vertices, normals = m.skin(clip, times=[times[-1]], normals=True)
    assert vertices.shape == (1, m.vertex_count, 3) and normals.shape == vertices.shape
    assert len(expected) == m.vertex_count
    # the OBJ keeps 6 decimals
    assert np.abs(vertices[0] - expected).max(initial=0) <= 5e-7 * max(1.0, np.abs(expected).max(initial=0)) + 1e-6
    assert m.triangles().max(initial=0) < max(m.vertex_count, 1)


def test_locals_compose_to_worlds(testdata):
    m = sinew.load(model_path(testdata, "gltf-samples/Fox.glb"))
    s = m.clips[2].sample(fps=24)
    assert s.translations.shape == (len(s.times), len(m.joints), 3)
    assert np.allclose(np.linalg.norm(s.rotations, axis=-1), 1, atol=1e-5)
    worlds = m.world(2, times=s.times).astype(np.float64)
    for f in (0, len(s.times) // 2, len(s.times) - 1):
        composed = []
        for j, parent in enumerate(m.joints.parents):
            local = np.eye(4)
            local[:3, :3] = quat_matrix(s.rotations[f, j]) * s.scales[f, j][None, :]
            local[:3, 3] = s.translations[f, j]
            composed.append(local if parent < 0 else composed[parent] @ local)
        assert np.allclose(np.array(composed), worlds[f], atol=1e-4)


def test_sampling_defaults_and_loop(testdata):
    m = sinew.load(model_path(testdata, "gltf-samples/Fox.glb"))
    walk = m.clip("Walk")
    assert walk is m.clips[1] and m.clip(1) is walk
    t = walk.times(fps=30)
    assert t[0] == 0 and t[-1] <= walk.duration + 1e-6 and len(t) == int(walk.duration * 30 + 1e-4) + 1
    a = m.positions(walk, times=[0.1])
    b = m.positions(walk, times=[0.1 + walk.duration], loop=True)
    assert np.allclose(a, b, atol=1e-4)
    c = m.positions(walk, times=[walk.duration + 5])
    assert np.allclose(c, m.positions(walk, times=[walk.duration]))
    rest = m.world(None)
    assert rest.shape == (1, len(m.joints), 4, 4)
    assert np.allclose(rest[0], m.joints.rest_worlds)


def test_bind_pose(testdata):
    m = sinew.load(model_path(testdata, "gltf-samples/Fox.glb"))
    j = m.joints
    skin = j.is_skin_joint
    assert skin.any() and np.allclose(j.bind[skin][:, 3], [0, 0, 0, 1], atol=1e-5)
    # the Fox is bound in its rest pose
    assert np.allclose(j.bind[skin], j.rest_worlds[skin], atol=1e-3)


def test_save_and_reload(testdata, tmp_path):
    m = sinew.load(model_path(testdata, "ozz/pab/arnaud.fbx"))
    out = tmp_path / "arnaud.sinew"
    m.save(str(out))
    again = sinew.load(str(out))
    assert again.joints.names == m.joints.names
    times = m.clips[0].times(10)
    assert np.array_equal(again.world(0, times=times), m.world(0, times=times))
    assert np.array_equal(again.skin(0, times=times[:2]), m.skin(0, times=times[:2]))


def test_retarget(testdata):
    bvh = sinew.load(model_path(testdata, "assimp/BVH/01_01.bvh"))
    character = sinew.demo()
    moved = sinew.retarget(character, bvh, fps=30)
    assert len(moved.clips) == len(character.clips) + len(bvh.clips)
    assert moved.joints.names == character.joints.names
    hips = moved.joints.index("Hips")
    path = moved.positions(0, fps=10)[:, hips]
    assert np.ptp(path, axis=0).max() > 0.1  # the hips travel as the capture's do


def test_render(testdata):
    m = sinew.load(model_path(testdata, "gltf-samples/Fox.glb"))
    try:
        image = sinew.render(m, "Walk", time=0.2, size=(160, 120))
    except sinew.GraphicsError as e:
        pytest.skip("no EGL here: %s" % e)
    assert image.shape == (120, 160, 4) and image.dtype == np.uint8
    background = np.array([0x29, 0x2B, 0x30])
    covered = (np.abs(image[..., :3].astype(int) - background).sum(-1) > 60).mean()
    assert 0.02 < covered < 0.8  # the fox is in the picture, and does not fill it
    frames = sinew.render(m, 2, times=[0.0, 0.2, 0.4], size=(64, 48))
    assert frames.shape == (3, 48, 64, 4) and not np.array_equal(frames[0], frames[1])
    bones = sinew.render(sinew.load(model_path(testdata, "assimp/BVH/01_01.bvh")), 0, time=1.0, size=(64, 48))
    assert (np.abs(bones[..., :3].astype(int) - background).sum(-1) > 60).any()  # a skeleton-only file shows bones


def written(path, data):
    path.write_bytes(data)
    return str(path)


@pytest.mark.parametrize("make,kind,needle", [
    (lambda d: str(d / "missing.fbx"), sinew.FileError, "missing.fbx"),
    (lambda d: written(d / "empty.glb", b""), sinew.FormatError, "empty.glb"),
    (lambda d: written(d / "junk.dae", b"<COLLADA><library_nodes"), sinew.FormatError, "junk.dae"),
    (lambda d: str(d), sinew.FileError, ""),
])
def test_errors_carry_file_and_kind(tmp_path, make, kind, needle):
    path = make(tmp_path)
    with pytest.raises(kind) as e:
        sinew.load(path)
    assert e.value.file == path and needle in str(e.value) and isinstance(e.value, sinew.Error)
    assert e.value.kind == kind.kind


def test_truncated_file_is_an_error(testdata, tmp_path):
    data = open(model_path(testdata, "ozz/pab/arnaud.fbx"), "rb").read()
    cut = tmp_path / "cut.fbx"
    cut.write_bytes(data[: len(data) // 3])
    with pytest.raises(sinew.FormatError) as e:
        sinew.load(str(cut))
    assert "cut.fbx" in str(e.value)


def test_motion_capture_frames_on_its_keys(testdata):
    """A BVH clip's frame rate is its Frame Time's inverse as written (CMU's 0.0083333 s: 120.0005),
    so its frames at that rate are its keys, all 2,752 of them: at 120 they would drift off the keys
    and miss the last."""
    clip = sinew.load(model_path(testdata, "assimp/BVH/01_01.bvh")).clips[0]
    assert abs(clip.frame_rate - 1 / 0.0083333) < 1e-3
    times = clip.times()
    assert len(times) == 2752 and abs(times[-1] - clip.duration) < 1e-5
    assert np.abs(times - np.arange(2752) * 0.0083333).max() < 1e-5


def test_load_bytes(testdata):
    path = model_path(testdata, "gltf-samples/Fox.glb")
    with open(path, "rb") as f:
        data = f.read()
    a, b = sinew.load(path), sinew.load_bytes(data, name=path)
    assert a.joints.names == b.joints.names and [c.name for c in a.clips] == [c.name for c in b.clips]
    assert np.array_equal(a.world("Walk", times=[0.3]), b.world("Walk", times=[0.3]))
    assert sinew.load_bytes(data).joints.names == a.joints.names  # told from the bytes
    with pytest.raises(sinew.UnsupportedError) as e:  # Assimp's formats are read from files
        sinew.load_bytes(b"xof 0303txt 0032\nFrame Root {\n}\n", "x")
    assert e.value.kind == "unsupported" and e.value.file == "(memory).x"
    with open(model_path(testdata, "assimp/BVH/01_01.bvh"), "rb") as f:
        bvh = f.read()
    assert sinew.load_bytes(bvh).joints.names == sinew.load(model_path(testdata, "assimp/BVH/01_01.bvh")).joints.names
    with pytest.raises(sinew.FormatError) as e:
        sinew.load_bytes(b"HIERARCHY\nROOT Hips\n", "bvh")
    assert e.value.file == "(memory).bvh" and "line 3" in str(e.value)
    with pytest.raises(sinew.FormatError) as e:
        sinew.load_bytes(data[:100], name="cut.glb")
    assert "cut.glb" in str(e.value) and e.value.file == "cut.glb"


def test_hanging_file_stops_at_the_deadline(testdata, tmp_path):
    from test_batch import hanging_file
    path = hanging_file(testdata, tmp_path)
    started = time.monotonic()
    with pytest.raises(sinew.TimeLimitError) as e:
        sinew.load(path, timeout=1.5, memory=4 << 30)  # room enough that the deadline stops it
    assert time.monotonic() - started < 20 and "deadline" in str(e.value)
    assert isinstance(e.value, sinew.LimitError) and e.value.kind == "limit_time" and e.value.file == path


def test_bad_arguments(testdata):
    m = sinew.load(model_path(testdata, "gltf-samples/Fox.glb"))
    with pytest.raises(sinew.ArgumentError, match="no clip 'Jump'.*Survey"):
        m.world("Jump")
    with pytest.raises(sinew.ArgumentError):
        m.world(7)
    with pytest.raises(sinew.ArgumentError, match="not finite"):
        m.world(0, times=[float("nan")])
    with pytest.raises(sinew.ArgumentError):
        sinew.render(m, 0, size=(0, 10))
    with pytest.raises(sinew.ArgumentError, match="another model"):
        sinew.demo().world(m.clips[0])


def test_long_calls_release_the_gil():
    m = sinew.synthetic(joints=64, vertices=40000)
    times = np.linspace(0, 2, 200, dtype=np.float32)
    ticks = []
    stop = threading.Event()

    def count():
        while not stop.is_set():
            ticks.append(1)
            time.sleep(0.001)

    t = threading.Thread(target=count)
    t.start()
    started = time.monotonic()
    m.skin(0, times=times)
    took = time.monotonic() - started
    stop.set()
    t.join()
    # the other thread ran all along (a held GIL would leave it a handful of ticks)
    assert len(ticks) > took / 0.001 * 0.25


def test_help_is_useful():
    assert "numpy" in sinew.__doc__ and "load" in sinew.__doc__
    for name in ("load", "render", "retarget"):
        assert getattr(sinew, name).__doc__
    assert sinew.Model.skin.__doc__ and sinew.Clip.sample.__doc__


def test_importer_keeps_one_helper(testdata, tmp_path):
    import signal
    paths = [model_path(testdata, rel) for rel in ("gltf-samples/Fox.glb", "ozz/pab/arnaud.fbx", "ozz/pab/walk.dae",
                                                    "raylib/guy.iqm", "assimp/BVH/01_01.bvh")]
    with sinew.Importer() as inside:  # by default sinew's own formats are read in this process
        assert inside.load(paths[0]).joints.names and inside.helper_pid == 0
    with sinew.Importer(timeout=30, isolate=True) as importer:
        pid = None
        for path in paths:
            a, b = sinew.load(path), importer.load(path)
            assert np.array_equal(a.world(0, times=[0.1]), b.world(0, times=[0.1])) and a.joints.names == b.joints.names
            pid = pid or importer.helper_pid
            assert importer.helper_pid == pid > 0  # every file went to the one helper, which stayed
        from test_batch import hanging_file
        with pytest.raises(sinew.LimitError):
            sinew.Importer(timeout=1.0, isolate=True).load(hanging_file(testdata, tmp_path))
        os.kill(pid, signal.SIGKILL)  # gone while it waited: the next file starts another
        assert importer.load(paths[0]).joints.names == sinew.load(paths[0]).joints.names
        assert importer.helper_pid not in (0, pid)
        with pytest.raises(sinew.FileError):
            importer.load(str(tmp_path / "missing.glb"))
    assert importer.helper_pid == 0
    with pytest.raises(sinew.ArgumentError):
        importer.load(paths[0])
