"""The C declarations sinew's Python binding uses, and where libsinew is found.

cffi's ABI mode (python3-cffi): nothing is compiled. The declarations below are the subset of
include/sinew/*.h the binding calls, with the structures laid out as the headers lay them out;
tests/test_python.py checks them against `sinew info --json` on real files.
"""

import ctypes.util
import os

import cffi

CDEF = r"""
typedef enum sinew_result {
    SINEW_OK = 0, SINEW_ERROR_INVALID_ARGUMENT, SINEW_ERROR_IO, SINEW_ERROR_FORMAT, SINEW_ERROR_IMPORTER,
    SINEW_ERROR_DATA, SINEW_ERROR_LIMIT, SINEW_ERROR_OUT_OF_MEMORY, SINEW_ERROR_GRAPHICS, SINEW_ERROR_CANCELLED,
    SINEW_ERROR_UNSUPPORTED, SINEW_ERROR_LIMIT_TIME, SINEW_ERROR_LIMIT_MEMORY, SINEW_ERROR_INTERNAL
} sinew_result;
typedef struct sinew_error {
    sinew_result kind; char message[512]; char file[256]; int64_t offset; uint32_t line;
} sinew_error;
const char *sinew_result_string(sinew_result result);
const char *sinew_version(void);

typedef struct sinew_mat4 { float m[16]; } sinew_mat4;
typedef struct sinew_transform { float translation[3]; float rotation[4]; float scale[3]; } sinew_transform;
typedef struct sinew_channel { uint32_t key_count; uint32_t interp; uint32_t first_key; uint32_t first_value; } sinew_channel;
typedef struct sinew_clip {
    const char *name; float duration; float start; uint32_t track_count; const void *tracks;
    uint32_t time_count; uint32_t value_count; const float *times; const float *values;
    uint32_t weight_track_count; const void *weight_tracks; float timeline; float frame_rate;
} sinew_clip;
typedef struct sinew_skin { uint32_t joint_count; const uint32_t *joints; const sinew_mat4 *inverse_bind; uint32_t blend; } sinew_skin;
typedef struct sinew_morph_target {
    const char *name; uint32_t channel; float full_weight; uint32_t delta_count; const uint32_t *vertices;
    const float *positions; const float *normals; const float *tangents;
} sinew_morph_target;
typedef struct sinew_mesh {
    const char *name; uint32_t vertex_count; uint32_t index_count; const float *positions; const float *normals;
    const float *uvs; const float *tangents; const uint32_t *indices; uint32_t influence_count;
    const uint16_t *joints; const float *weights; int32_t skin; int32_t material; const float *dq_weights;
    uint32_t target_count; const sinew_morph_target *targets; uint32_t morph_channel_count; const void *cache;
    bool flat_normals; const float *colors;
} sinew_mesh;
typedef struct sinew_instance { uint32_t mesh; uint32_t node; uint32_t morph_first; } sinew_instance;
typedef struct sinew_morph_channel { const char *name; float default_weight; } sinew_morph_channel;
typedef struct sinew_model {
    const char *source; const char *converted_from; const char *format;
    uint32_t node_count; const char *const *node_names; const int32_t *node_parents;
    const sinew_transform *node_rest; const uint8_t *node_inherit;
    uint32_t skin_count; const sinew_skin *skins;
    uint32_t mesh_count; const sinew_mesh *meshes;
    uint32_t instance_count; const sinew_instance *instances;
    uint32_t material_count; const void *materials;
    uint32_t clip_count; const sinew_clip *clips;
    uint32_t morph_channel_count; const sinew_morph_channel *morph_channels;
    uint32_t warning_count; const char *const *warnings;
    const void *muscles;
} sinew_model;
typedef struct sinew_allocator { void *(*alloc)(size_t size, void *user); void (*free)(void *ptr, void *user); void *user; } sinew_allocator;
void sinew_model_free(sinew_model *model);
sinew_result sinew_model_load(const char *path, const sinew_allocator *allocator, sinew_model **out, sinew_error *error);
bool sinew_model_node_is_joint(const sinew_model *model, uint32_t node);
int32_t sinew_model_pick_clip(const sinew_model *model, const char *text);
void sinew_model_blob(const sinew_model *model, const void **bytes, size_t *size);

typedef struct sinew_import_desc {
    const char *path; bool isolate; bool assimp; const sinew_allocator *allocator;
    const char *helper; double timeout; uint64_t memory_limit; int stderr_fd;
    bool (*progress)(float fraction, void *user); void *progress_user;
    bool (*read_file)(const char *path, void **bytes, size_t *size, void *user); void *read_user;
} sinew_import_desc;
sinew_result sinew_import(const sinew_import_desc *desc, sinew_model **out, sinew_error *error);
sinew_result sinew_import_memory(const void *bytes, size_t size, const char *format, const sinew_import_desc *desc,
                                 sinew_model **out, sinew_error *error);
typedef struct sinew_import_session sinew_import_session;
sinew_result sinew_import_session_create(const sinew_import_desc *desc, sinew_import_session **out, sinew_error *error);
sinew_result sinew_import_session_load(sinew_import_session *session, const char *path, sinew_model **out, sinew_error *error);
void sinew_import_session_free(sinew_import_session *session);
int sinew_import_session_helper_pid(const sinew_import_session *session);
sinew_result sinew_model_save(const sinew_model *model, const void *muscles, const char *path, sinew_error *error);
typedef struct sinew_synthetic_desc {
    uint32_t joints; uint32_t vertices; uint32_t influences; float duration; float keys_per_second; bool keyed_trs;
    uint32_t morph_targets; uint32_t morph_animated;
} sinew_synthetic_desc;
sinew_result sinew_synthetic_model(const sinew_synthetic_desc *desc, sinew_model **out, sinew_error *error);
sinew_result sinew_demo_humanoid(sinew_model **out, sinew_error *error);
typedef struct sinew_retarget_desc { const sinew_model *target; const sinew_model *source; const char *name_map; float frame_rate; } sinew_retarget_desc;
sinew_result sinew_retarget(const sinew_retarget_desc *desc, sinew_model **out, sinew_error *error);

typedef enum sinew_wrap { SINEW_WRAP_CLAMP = 0, SINEW_WRAP_LOOP = 1 } sinew_wrap;
typedef struct sinew_clip_arrays_desc {
    const sinew_model *model; const sinew_clip *clip; const float *times; uint32_t time_count; sinew_wrap wrap;
    const sinew_allocator *allocator;
    float *translations; float *rotations; float *scales; float *worlds; float *weights; float *vertices; float *normals;
} sinew_clip_arrays_desc;
uint32_t sinew_model_vertex_total(const sinew_model *model);
sinew_result sinew_clip_arrays(const sinew_clip_arrays_desc *desc, sinew_error *error);

typedef struct sinew_render_options sinew_render_options;
typedef struct sinew_camera sinew_camera;
typedef struct sinew_snapshot_desc {
    const sinew_model *model; const sinew_clip *clip; const float *times; uint32_t time_count; sinew_wrap wrap;
    int width, height; int samples; const sinew_render_options *options; const sinew_camera *camera;
    uint8_t *rgba; size_t rgba_size;
} sinew_snapshot_desc;
sinew_result sinew_render_snapshots(const sinew_snapshot_desc *desc, sinew_error *error);
"""

ffi = cffi.FFI()
ffi.cdef(CDEF)

_HERE = os.path.dirname(os.path.abspath(__file__))
# libsinew's soname: it follows the ABI (CMakeLists.txt's SINEW_SOVERSION; CHANGELOG.md)
SONAME = "libsinew.so.0.3"


def _candidates():
    """Where libsinew.so may be: $SINEW_LIBRARY, the build tree beside this source tree, the
    installed library."""
    given = os.environ.get("SINEW_LIBRARY")
    if given:
        yield given
        return
    tree = os.path.normpath(os.path.join(_HERE, "..", ".."))
    for build in ("build", "build-release"):
        yield os.path.join(tree, build, "libsinew.so")
    # installed: PREFIX/share/sinew/python/sinew, the library in PREFIX/lib
    prefix = os.path.normpath(os.path.join(_HERE, "..", "..", "..", ".."))
    for libdir in ("lib", "lib64", "lib/x86_64-linux-gnu", "lib/aarch64-linux-gnu"):
        yield os.path.join(prefix, libdir, SONAME)
    found = ctypes.util.find_library("sinew")
    if found:
        yield found
    yield SONAME


def _open():
    tried = []
    for path in _candidates():
        if os.sep in path and not os.path.exists(path):
            tried.append(path + " (missing)")
            continue
        try:
            return ffi.dlopen(path), path
        except OSError as e:
            tried.append("%s (%s)" % (path, e))
    raise ImportError(
        "sinew: cannot load libsinew (set $SINEW_LIBRARY to libsinew.so): tried " + "; ".join(tried)
    )


lib, library_path = _open()
