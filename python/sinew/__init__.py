"""sinew from Python: animated characters as numpy arrays.

Reads FBX (5 to 7, binary and ASCII), glTF 2.0, COLLADA, BVH, IQM, .sinew and every format
Assimp reads, with libsinew (the C library `sinew` and `sinew-view` are built on), and turns
their skeletons, clips and skinned meshes into numpy arrays:

    import sinew
    model = sinew.load("walk.fbx")              # imported in a hardened helper process
    clip = model.clips[0]                       # name, duration, frame_rate
    pose = clip.sample(fps=30)                  # local translations (T,J,3), rotations (T,J,4), scales
    worlds = model.world(clip, fps=30)          # (T,J,4,4) world matrices, metres, Y up
    joints = model.positions(clip, fps=30)      # (T,J,3) joint positions
    verts = model.skin(clip, times=[0.0, 0.5])  # (T,V,3) skinned vertices, all meshes
    image = sinew.render(model, clip, time=0.5) # (H,W,4) uint8 RGBA

Every call that takes a while (import, sampling, skinning, rendering) runs in C with the GIL
released. Errors raise sinew.Error subclasses that carry the file and the library's kind;
a malformed or hostile file never takes the interpreter down (imports run in the
`sinew-import` helper, with a deadline and a memory limit).
The library is found through $SINEW_LIBRARY, the build tree beside this package, or the
installed libsinew.so.0.2.
"""

import os
from dataclasses import dataclass
from typing import List, Optional, Sequence, Union

import numpy as np

from ._ffi import ffi, lib, library_path  # noqa: F401  (sinew.library_path: the libsinew loaded)

__all__ = [
    "load", "load_bytes", "demo", "synthetic", "retarget", "render", "version", "Importer",
    "Model", "Clip", "Joints", "Mesh", "Sample",
    "Error", "ArgumentError", "FileError", "FormatError", "ImporterError", "DataError",
    "LimitError", "TimeLimitError", "MemoryLimitError", "OutOfMemoryError", "GraphicsError", "CancelledError",
    "UnsupportedError", "InternalError",
]


# ---- errors -------------------------------------------------------------------------------

class Error(Exception):
    """A failure libsinew reported: `kind` is the library's error kind ("io", "format",
    "importer", "data", "limit", "limit_time", "limit_memory", "out_of_memory", "graphics",
    "cancelled", "unsupported", "internal", "invalid_argument"), `file` the file concerned (or
    None), `offset` the byte offset and `line` the line in it where the reader found the problem
    (None when not known), `message` its text."""

    kind = "error"

    def __init__(self, message: str, file: Optional[str] = None, offset: Optional[int] = None,
                 line: Optional[int] = None):
        super().__init__(message)
        self.message = message
        self.file = file
        self.offset = offset
        self.line = line


class ArgumentError(Error, ValueError):
    """A bad argument: a clip the model lacks, a bad size, a time that is not finite."""
    kind = "invalid_argument"


class FileError(Error, OSError):
    """The file is missing, a folder, or unreadable."""
    kind = "io"


class FormatError(Error):
    """Not a model file sinew reads, or one cut short or corrupted."""
    kind = "format"


class ImporterError(Error):
    """Assimp refused the file, or the import helper crashed on it."""
    kind = "importer"


class DataError(Error):
    """The file parsed but its content is invalid (NaN, bad indices)."""
    kind = "data"


class LimitError(Error):
    """Over a limit: the import's deadline or memory limit, joints per skin, picture size."""
    kind = "limit"


class TimeLimitError(LimitError):
    """The import took longer than its deadline (timeout=) and was stopped."""
    kind = "limit_time"


class MemoryLimitError(LimitError):
    """The import needed more than its memory limit (memory=) and was stopped."""
    kind = "limit_memory"


class UnsupportedError(Error):
    """Valid, but something sinew does not do (a format only Assimp reads, given as bytes)."""
    kind = "unsupported"


class InternalError(Error):
    """A bug in sinew: please report it with the file."""
    kind = "internal"


class OutOfMemoryError(Error, MemoryError):
    kind = "out_of_memory"


class GraphicsError(Error):
    """No EGL display or OpenGL 3.3 context for rendering."""
    kind = "graphics"


class CancelledError(Error):
    kind = "cancelled"


_KINDS = {
    lib.SINEW_ERROR_INVALID_ARGUMENT: ArgumentError,
    lib.SINEW_ERROR_IO: FileError,
    lib.SINEW_ERROR_FORMAT: FormatError,
    lib.SINEW_ERROR_IMPORTER: ImporterError,
    lib.SINEW_ERROR_DATA: DataError,
    lib.SINEW_ERROR_LIMIT: LimitError,
    lib.SINEW_ERROR_OUT_OF_MEMORY: OutOfMemoryError,
    lib.SINEW_ERROR_GRAPHICS: GraphicsError,
    lib.SINEW_ERROR_CANCELLED: CancelledError,
    lib.SINEW_ERROR_UNSUPPORTED: UnsupportedError,
    lib.SINEW_ERROR_LIMIT_TIME: TimeLimitError,
    lib.SINEW_ERROR_LIMIT_MEMORY: MemoryLimitError,
    lib.SINEW_ERROR_INTERNAL: InternalError,
}


def _check(result, error, file=None):
    if result == lib.SINEW_OK:
        return
    cls = _KINDS.get(result, Error)
    message = ffi.string(error.message).decode("utf-8", "replace") or ffi.string(
        lib.sinew_result_string(result)).decode()
    said = ffi.string(error.file).decode("utf-8", "replace")
    raise cls(message, file or said or None, error.offset if error.offset >= 0 else None, error.line or None)


def version() -> str:
    """The version of libsinew loaded ("0.2.0")."""
    return ffi.string(lib.sinew_version()).decode()


def _text(p) -> str:
    return ffi.string(p).decode("utf-8", "replace") if p != ffi.NULL else ""


def _floats(pointer, count):
    """A numpy copy of `count` floats at a C pointer (one memcpy)."""
    if count == 0 or pointer == ffi.NULL:
        return np.zeros(0, np.float32)
    return np.frombuffer(ffi.buffer(pointer, count * 4), np.float32).copy()


def _ptr(array, ctype="float *"):
    return ffi.cast(ctype, array.ctypes.data) if array is not None else ffi.NULL


# ---- the model ----------------------------------------------------------------------------

@dataclass
class Sample:
    """Local transforms of every node at each time: translations (T,J,3), rotations (T,J,4,
    x y z w, unit), scales (T,J,3), the morph channel weights (T,C), and the times (T,)."""
    times: np.ndarray
    translations: np.ndarray
    rotations: np.ndarray
    scales: np.ndarray
    weights: np.ndarray


class Joints:
    """The skeleton: every node of the file's hierarchy, parents before children.

    names (list of str), parents (J,) int32 (-1 for roots), rest (a Sample-like record of
    rest local translations/rotations/scales, each (J,k)), rest_worlds (J,4,4), bind (J,4,4)
    the world matrix at bind time (the rest world where no skin binds the node), is_skin_joint
    (J,) bool."""

    def __init__(self, model: "Model"):
        m = model._m
        n = m.node_count
        self.names: List[str] = [_text(m.node_names[i]) for i in range(n)]
        self.parents = np.frombuffer(ffi.buffer(m.node_parents, n * 4), np.int32).copy() if n else np.zeros(0, np.int32)
        rest = np.frombuffer(ffi.buffer(m.node_rest, n * ffi.sizeof("sinew_transform")), np.float32).reshape(n, 10) \
            if n else np.zeros((0, 10), np.float32)
        self.rest_translations = rest[:, 0:3].copy()
        self.rest_rotations = rest[:, 3:7].copy()
        self.rest_scales = rest[:, 7:10].copy()
        self.rest_worlds = model.world(None, times=[0.0])[0] if n else np.zeros((0, 4, 4), np.float32)
        self.is_skin_joint = np.array([bool(lib.sinew_model_node_is_joint(m, i)) for i in range(n)], bool)
        self.bind = self.rest_worlds.copy()
        for s in range(m.skin_count - 1, -1, -1):  # the first skin's binding wins
            skin = m.skins[s]
            if skin.joint_count == 0:
                continue
            inverse = np.frombuffer(ffi.buffer(skin.inverse_bind, skin.joint_count * 64), np.float32)
            inverse = inverse.reshape(skin.joint_count, 4, 4).transpose(0, 2, 1).astype(np.float64)
            joints = np.frombuffer(ffi.buffer(skin.joints, skin.joint_count * 4), np.uint32)
            invertible = np.abs(np.linalg.det(inverse)) > 1e-20
            if invertible.any():
                self.bind[joints[invertible]] = np.linalg.inv(inverse[invertible]).astype(np.float32)

    def __len__(self):
        return len(self.names)

    def index(self, name: str) -> int:
        """The node called `name`; ValueError when none is."""
        return self.names.index(name)

    def __repr__(self):
        return "<sinew.Joints %d nodes, %d skin joints>" % (len(self), int(self.is_skin_joint.sum()))


class Mesh:
    """One mesh of the model: name, positions (V,3) and normals (V,3) in mesh space,
    triangles (F,3) uint32, the skin it uses (index or -1), its morph target names, and
    flat_normals: the file gave no normals and its format asks for faceted ones (glTF); the
    normals given here are then computed smooth, and sinew draws its triangles flat. colors:
    (V,4) linear RGBA vertex colours, or None."""

    def __init__(self, mesh):
        v = mesh.vertex_count
        self.name = _text(mesh.name)
        self.vertex_count = v
        self.positions = _floats(mesh.positions, v * 3).reshape(v, 3)
        self.normals = _floats(mesh.normals, v * 3).reshape(-1, 3)
        self.triangles = np.frombuffer(ffi.buffer(mesh.indices, mesh.index_count * 4), np.uint32).reshape(-1, 3).copy() \
            if mesh.index_count else np.zeros((0, 3), np.uint32)
        self.skin = mesh.skin
        self.morph_targets = [_text(mesh.targets[t].name) for t in range(mesh.target_count)]
        self.flat_normals = bool(mesh.flat_normals)
        self.colors = _floats(mesh.colors, v * 4).reshape(-1, 4) if mesh.colors != ffi.NULL else None

    def __repr__(self):
        return "<sinew.Mesh %r %d vertices, %d triangles>" % (self.name, self.vertex_count, len(self.triangles))


class Clip:
    """One clip (take, action, animation) of a model: name, index, duration (seconds),
    frame_rate (the file's frames a second, or the rate its keys were written at, or 30)."""

    def __init__(self, model: "Model", index: int):
        c = model._m.clips[index]
        self._model = model
        self._clip = c
        self.index = index
        self.name = _text(c.name)
        self.duration = float(c.duration)
        self.key_count = int(c.time_count)
        rate = float(c.frame_rate)
        if rate <= 0 and c.time_count > 1:
            times = np.unique(_floats(c.times, c.time_count))
            steps = np.diff(times)
            steps = steps[steps > 1e-6]
            rate = float(np.round(1.0 / np.median(steps), 3)) if len(steps) else 0.0
        self.frame_rate = rate if rate > 0 else 30.0

    def times(self, fps: Optional[float] = None) -> np.ndarray:
        """Frame times from 0 to the duration (both included) at `fps` (default: the clip's
        frame rate)."""
        fps = float(fps or self.frame_rate)
        if not fps > 0:
            raise ArgumentError("fps must be positive, not %r" % fps)
        # a thousandth of a frame short of the end counts as the end: a long clip's float duration
        # (2,751 frames at 120.0005 fps: 2750.99994) is off by more than rounding in frames
        count = int(np.floor(self.duration * fps + 1e-3)) + 1
        return (np.arange(count, dtype=np.float64) / fps).astype(np.float32)

    def sample(self, times: Optional[Sequence[float]] = None, fps: Optional[float] = None,
               loop: bool = False) -> Sample:
        """Local transforms at `times` (seconds), or every frame at `fps`."""
        return self._model.sample(self, times=times, fps=fps, loop=loop)

    def __repr__(self):
        return "<sinew.Clip %d %r %.3f s @ %g fps>" % (self.index, self.name, self.duration, self.frame_rate)


ClipLike = Union[None, int, str, Clip]


class Model:
    """An imported character: joints (the skeleton), meshes, clips, morph channels, warnings.
    Made by sinew.load(), sinew.demo(), sinew.synthetic() or sinew.retarget()."""

    def __init__(self, pointer, keep=()):
        self._m = ffi.gc(pointer, lib.sinew_model_free)
        self._keep = keep
        m = self._m
        self.path: str = _text(m.source)
        self.format: str = _text(m.format)
        self.warnings: List[str] = [_text(m.warnings[i]) for i in range(m.warning_count)]
        self.clips: List[Clip] = [Clip(self, i) for i in range(m.clip_count)]
        self.meshes: List[Mesh] = [Mesh(m.meshes[i]) for i in range(m.mesh_count)]
        self.morph_channels: List[str] = [_text(m.morph_channels[i].name) for i in range(m.morph_channel_count)]
        self.vertex_count = int(lib.sinew_model_vertex_total(m))
        self._joints = None

    @property
    def joints(self) -> Joints:
        if self._joints is None:
            self._joints = Joints(self)
        return self._joints

    @property
    def instances(self) -> List[dict]:
        """Each placed mesh: {"mesh", "node", "first_vertex", "vertex_count"} — how skin()'s
        vertices split by mesh."""
        out, first = [], 0
        for i in range(self._m.instance_count):
            inst = self._m.instances[i]
            count = self._m.meshes[inst.mesh].vertex_count
            out.append({"mesh": int(inst.mesh), "node": int(inst.node), "first_vertex": first, "vertex_count": count})
            first += count
        return out

    def triangles(self) -> np.ndarray:
        """Every instance's triangles (F,3), numbered as skin()'s vertices."""
        parts = [self.meshes[i["mesh"]].triangles + np.uint32(i["first_vertex"]) for i in self.instances]
        return np.concatenate(parts) if parts else np.zeros((0, 3), np.uint32)

    def clip(self, which: ClipLike) -> Optional[Clip]:
        """A clip by index, name (or unambiguous part of one), or Clip; None is the rest pose."""
        if which is None or isinstance(which, Clip):
            if isinstance(which, Clip) and which._model is not self:
                raise ArgumentError("the clip %r belongs to another model" % which.name, self.path)
            return which
        if isinstance(which, (int, np.integer)):
            if not 0 <= which < len(self.clips):
                raise ArgumentError("%s has %d clips, no clip %d" % (self.path, len(self.clips), which), self.path)
            return self.clips[which]
        index = lib.sinew_model_pick_clip(self._m, str(which).encode())
        if index < 0:
            names = ", ".join(c.name for c in self.clips) or "none"
            raise ArgumentError("%s has no clip %r (clips: %s)" % (self.path, which, names), self.path)
        return self.clips[index]

    def _times(self, clip: Optional[Clip], times, fps) -> np.ndarray:
        if times is not None:
            t = np.ascontiguousarray(np.atleast_1d(np.asarray(times, np.float32)))
            if t.ndim != 1:
                raise ArgumentError("times must be one-dimensional")
            return t
        if clip is None:
            return np.zeros(1, np.float32)
        return clip.times(fps)

    def _arrays(self, which, times, fps, loop, **outputs):
        clip = self.clip(which)
        t = self._times(clip, times, fps)
        arrays = {}
        n, c, v = self._m.node_count, self._m.morph_channel_count, self.vertex_count
        shapes = {"translations": (n, 3), "rotations": (n, 4), "scales": (n, 3), "worlds": (n, 16),
                  "weights": (c,), "vertices": (v, 3), "normals": (v, 3)}
        desc = ffi.new("sinew_clip_arrays_desc *")
        desc.model = self._m
        desc.clip = ffi.addressof(self._m.clips[clip.index]) if clip else ffi.NULL
        desc.times = _ptr(t)
        desc.time_count = len(t)
        desc.wrap = lib.SINEW_WRAP_LOOP if loop else lib.SINEW_WRAP_CLAMP
        for name, wanted in outputs.items():
            if wanted:
                arrays[name] = np.empty((len(t),) + shapes[name], np.float32)
                setattr(desc, name, _ptr(arrays[name]))
        error = ffi.new("sinew_error *")
        _check(lib.sinew_clip_arrays(desc, error), error, self.path)
        arrays["times"] = t
        return arrays

    def arrays(self, clip: ClipLike = 0, times=None, fps=None, loop=False, *, translations=False, rotations=False,
               scales=False, worlds=False, weights=False, vertices=False, normals=False) -> dict:
        """Several of the arrays below from one pass over the clip: a dict with "times" and each
        one asked for (worlds as (T,J,4,4) with column vectors, the rest as their methods give
        them)."""
        a = self._arrays(clip, times, fps, loop, translations=translations, rotations=rotations, scales=scales,
                         worlds=worlds, weights=weights, vertices=vertices, normals=normals)
        if worlds:
            a["worlds"] = np.ascontiguousarray(a["worlds"].reshape(len(a["times"]), -1, 4, 4).transpose(0, 1, 3, 2))
        return a

    def sample(self, clip: ClipLike = 0, times=None, fps=None, loop=False) -> Sample:
        """Local transforms of every node at `times` (default: every frame of the clip at
        `fps`, default its frame rate). loop wraps times past the end; else they clamp."""
        a = self._arrays(clip, times, fps, loop, translations=True, rotations=True, scales=True, weights=True)
        return Sample(a["times"], a["translations"], a["rotations"], a["scales"], a["weights"])

    def world(self, clip: ClipLike = 0, times=None, fps=None, loop=False) -> np.ndarray:
        """World matrices (T,J,4,4) of every node (column vectors: p_world = M @ p)."""
        a = self._arrays(clip, times, fps, loop, worlds=True)
        return np.ascontiguousarray(a["worlds"].reshape(len(a["times"]), -1, 4, 4).transpose(0, 1, 3, 2))

    def positions(self, clip: ClipLike = 0, times=None, fps=None, loop=False) -> np.ndarray:
        """World positions (T,J,3) of every node."""
        a = self._arrays(clip, times, fps, loop, worlds=True)
        return np.ascontiguousarray(a["worlds"].reshape(len(a["times"]), -1, 16)[:, :, 12:15])

    def morph_weights(self, clip: ClipLike = 0, times=None, fps=None, loop=False) -> np.ndarray:
        """Each morph channel's weight (T,C)."""
        return self._arrays(clip, times, fps, loop, weights=True)["weights"]

    def skin(self, clip: ClipLike = 0, times=None, fps=None, loop=False, normals=False):
        """Every instance's vertices (T,V,3) in world space, deformed as the file means
        (morph targets, vertex caches, linear or dual-quaternion skins); with normals=True a
        pair (vertices, normals)."""
        a = self._arrays(clip, times, fps, loop, vertices=True, normals=normals)
        return (a["vertices"], a["normals"]) if normals else a["vertices"]

    def save(self, path: str) -> None:
        """Writes the model as a .sinew file (compact, checksummed; loads in milliseconds)."""
        error = ffi.new("sinew_error *")
        _check(lib.sinew_model_save(self._m, ffi.NULL, os.fsencode(path), error), error, path)

    def __repr__(self):
        return "<sinew.Model %r (%s): %d nodes, %d meshes, %d clips>" % (
            self.path, self.format, self._m.node_count, len(self.meshes), len(self.clips))


# ---- making models ------------------------------------------------------------------------

def load(path: Union[str, os.PathLike], *, timeout: Optional[float] = None, memory: Optional[int] = None,
         isolate: bool = False, assimp: bool = False) -> Model:
    """Imports a model file (FBX, glTF, COLLADA, BVH, IQM, .sinew, ...).

    timeout: seconds the import may take (default 120, TimeLimitError past it); memory: bytes it
    may use (default 256 MiB and 64 times the file's size, at most half the machine's memory;
    MemoryLimitError). sinew's own readers (FBX, glTF, COLLADA, IQM, BVH, .sinew) run in this process
    under both; Assimp's formats in the `sinew-import` helper process. isolate reads every format
    in the helper (files from strangers: a crash in a reader then raises an Error instead of
    ending Python); assimp reads with Assimp even a format sinew reads itself."""
    path = os.fspath(path)
    error = ffi.new("sinew_error *")
    out = ffi.new("sinew_model **")
    if path.endswith(".sinew"):
        _check(lib.sinew_model_load(os.fsencode(path), ffi.NULL, out, error), error, path)
        return Model(out[0])
    desc = _import_desc(timeout, memory, isolate, assimp)
    encoded = ffi.new("char[]", os.fsencode(path))
    desc.path = encoded
    _check(lib.sinew_import(desc, out, error), error, path)
    return Model(out[0])


def load_bytes(data: bytes, format: Optional[str] = None, *, name: Optional[str] = None) -> Model:
    """Imports a model from bytes in memory (an archive member, a download), in this process, with
    sinew's own readers: format "fbx", "gltf", "glb", "dae", "iqm", "bvh" or "sinew", or None: from
    `name`'s extension, else told from the bytes. `name` names the model in errors and is the
    folder a .gltf's .bin files are looked for in. Assimp's formats need a file (load())."""
    error = ffi.new("sinew_error *")
    out = ffi.new("sinew_model **")
    desc = ffi.new("sinew_import_desc *")
    encoded = ffi.new("char[]", os.fsencode(name)) if name else ffi.NULL
    desc.path = encoded
    fmt = ffi.new("char[]", format.encode()) if format else ffi.NULL
    buf = ffi.from_buffer(data)
    _check(lib.sinew_import_memory(buf, len(buf), fmt, desc, out, error), error, name)
    return Model(out[0])


def _import_desc(timeout, memory, isolate, assimp):
    """A sinew_import_desc with the settings load() and Importer take (path unset)."""
    desc = ffi.new("sinew_import_desc *")
    desc.isolate = isolate
    desc.assimp = assimp
    desc.timeout = float(timeout) if timeout else 0.0
    desc.memory_limit = int(memory) if memory else 0
    return desc


class Importer:
    """Loads many files with the same settings (sinew_import_session): a deadline and a memory
    limit a file, as load(); with isolate, through one running import helper, so that a crash
    costs an error without starting a process for each file. Use from one thread at a time:

        with sinew.Importer(timeout=30) as importer:
            for path in paths:
                model = importer.load(path)
    """

    def __init__(self, *, timeout: Optional[float] = None, memory: Optional[int] = None, isolate: bool = False,
                 assimp: bool = False):
        desc = _import_desc(timeout, memory, isolate, assimp)
        out = ffi.new("sinew_import_session **")
        error = ffi.new("sinew_error *")
        _check(lib.sinew_import_session_create(desc, out, error), error)
        self._raw = out[0]
        self._session = ffi.gc(out[0], lib.sinew_import_session_free)

    def load(self, path: Union[str, os.PathLike]) -> "Model":
        """Imports one file, as sinew.load() does."""
        path = os.fspath(path)
        if self._session is None:
            raise ArgumentError("the importer is closed")
        error = ffi.new("sinew_error *")
        out = ffi.new("sinew_model **")
        _check(lib.sinew_import_session_load(self._session, os.fsencode(path), out, error), error, path)
        return Model(out[0])

    @property
    def helper_pid(self) -> int:
        """The running helper's process id (0: none)."""
        return lib.sinew_import_session_helper_pid(self._session) if self._session is not None else 0

    def close(self) -> None:
        """Ends the helper."""
        if self._session is not None:
            ffi.gc(self._session, None)  # no second destroy when it is collected
            self._session = None
            lib.sinew_import_session_free(self._raw)
            self._raw = None

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()


def demo() -> Model:
    """The demo humanoid (24 joints, 15,000 vertices, clips "walk" and "wave")."""
    error = ffi.new("sinew_error *")
    out = ffi.new("sinew_model **")
    _check(lib.sinew_demo_humanoid(out, error), error)
    return Model(out[0])


def synthetic(joints: int = 64, vertices: int = 10000, influences: int = 4, duration: float = 2.0,
              keys_per_second: float = 30.0, morph_targets: int = 0) -> Model:
    """A generated character (a swaying tube on a joint chain) for tests and benchmarks."""
    desc = ffi.new("sinew_synthetic_desc *", {"joints": joints, "vertices": vertices, "influences": influences,
                                               "duration": duration, "keys_per_second": keys_per_second,
                                               "morph_targets": morph_targets, "morph_animated": morph_targets})
    error = ffi.new("sinew_error *")
    out = ffi.new("sinew_model **")
    _check(lib.sinew_synthetic_model(desc, out, error), error)
    return Model(out[0])


def retarget(target: Model, source: Model, *, name_map: Optional[str] = None, fps: float = 30.0) -> Model:
    """`target` with every clip of `source` retargeted onto its skeleton (first in its clip
    list, baked at fps), joints matched by name, Mixamo/CMU/Unity humanoid names, or
    name_map (a JSON file {"source name": "target name"})."""
    desc = ffi.new("sinew_retarget_desc *")
    desc.target = target._m
    desc.source = source._m
    keep = ffi.new("char[]", os.fsencode(name_map)) if name_map else ffi.NULL
    desc.name_map = keep
    desc.frame_rate = fps
    error = ffi.new("sinew_error *")
    out = ffi.new("sinew_model **")
    _check(lib.sinew_retarget(desc, out, error), error, target.path)
    return Model(out[0], keep=(target, source))


def render(model: Model, clip: ClipLike = 0, *, time: Optional[float] = None, times=None,
           size=(320, 240), samples: int = 4, loop: bool = False) -> np.ndarray:
    """Pictures of the model off screen (EGL; Mesa's llvmpipe without a GPU): one (H,W,4)
    uint8 RGBA image at `time`, or (T,H,W,4) at each of `times`. The camera is framed on the
    clip's motion over the times, as `sinew render` frames it. clip=None: the rest pose."""
    c = model.clip(clip)
    single = times is None
    t = np.ascontiguousarray(np.atleast_1d(np.asarray([time or 0.0] if single else times, np.float32)))
    width, height = int(size[0]), int(size[1])
    if width < 1 or height < 1:
        raise ArgumentError("size %dx%d: both sides must be positive" % (width, height))
    out = np.empty((len(t), height, width, 4), np.uint8)
    desc = ffi.new("sinew_snapshot_desc *")
    desc.model = model._m
    desc.clip = ffi.addressof(model._m.clips[c.index]) if c else ffi.NULL
    desc.times = _ptr(t)
    desc.time_count = len(t)
    desc.wrap = lib.SINEW_WRAP_LOOP if loop else lib.SINEW_WRAP_CLAMP
    desc.width, desc.height, desc.samples = width, height, samples
    desc.rgba = ffi.cast("uint8_t *", out.ctypes.data)
    desc.rgba_size = out.nbytes
    error = ffi.new("sinew_error *")
    _check(lib.sinew_render_snapshots(desc, error), error, model.path)
    return out[0] if single else out
