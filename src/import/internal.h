/* Cross-file internals of src/import: the raw (offline, editable) model that importers
 * fill and the builder turns into a runtime blob. No promise to library users.
 *
 * Raw data is loose: influences per vertex up to any count and unsorted, keys in any
 * order, quaternions with either sign. The builder (builder.c) validates it, repairs what
 * can be repaired with a warning, and writes the blob that sinew_model_from_blob() reads.
 */
#ifndef SINEW_IMPORT_INTERNAL_H
#define SINEW_IMPORT_INTERNAL_H

#include <stddef.h>
#include <stdint.h>

#include "sinew/import.h"
#include "sinew/model.h"

/* A channel owns its keys (times, values), or plays keys in one of the model's key pools
 * (pool > 0; times and values NULL): keys [first_key, first_key + count) of pool - 1, values
 * from first_value. Pooled keys are the builder's already (sorted, unit rotations). */
typedef struct raw_channel {
    uint32_t interp; /* sinew_interp */
    uint32_t count;  /* keys */
    float *times;    /* seconds */
    float *values;   /* sinew_channel_stride(kind, interp) floats a key */
    uint32_t pool;   /* 0: the arrays above; else 1 + index into raw_model.pools */
    uint32_t first_key, first_value;
    bool finite; /* the reader found every time and value finite: the builder does not look again */
} raw_channel;

typedef struct raw_track {
    uint32_t node;
    raw_channel channels[SINEW_CHANNEL_COUNT];
} raw_track;

/* A morph channel's weight over a clip: keys of one float (SINEW_CHANNEL_WEIGHT), owned. */
typedef struct raw_weight_track {
    uint32_t channel; /* the model's morph channel */
    raw_channel keys;
} raw_weight_track;

/* A clip plays [start, start + duration] of its keys' timeline (start > 0 for a window cut
 * from a longer animation whose keys it shares through a pool). Either every channel of a
 * clip owns its keys or every one is in the same pool. */
typedef struct raw_clip {
    char *name;
    float duration;
    float start;
    uint32_t track_count;
    raw_track *tracks;
    uint32_t weight_track_count;
    raw_weight_track *weight_tracks; /* not in pooled clips */
    float timeline;                  /* seconds on the file's timeline at clip time 0 (sinew_clip.timeline) */
    float frame_rate;                /* sinew_clip.frame_rate, 0 for none */
} raw_clip;

/* Keys that clips share: every channel's times, then its values, one after another. */
typedef struct raw_key_pool {
    uint32_t time_count, value_count;
    float *times;
    float *values;
} raw_key_pool;

typedef struct raw_skin {
    uint32_t joint_count;
    uint32_t *joints; /* node indices */
    sinew_mat4 *inverse_bind;
    uint32_t blend; /* sinew_skin_blend */
} raw_skin;

/* A morph target of a mesh (sinew_morph_target): offsets of some vertices, any order (the
 * builder sorts them and drops zero offsets). */
typedef struct raw_morph_target {
    char *name;
    uint32_t channel; /* the mesh's channel (instance.morph_first + channel is the model's) */
    float full_weight;
    uint32_t delta_count;
    uint32_t *vertices;
    float *positions; /* 3 a delta */
    float *normals;   /* 3 a delta, or NULL */
    float *tangents;  /* 3 a delta (xyz), or NULL */
} raw_morph_target;

typedef struct raw_vertex_cache {
    uint32_t frame_count;
    float *times;     /* seconds on the file's timeline, ascending */
    float *positions; /* frame_count * vertex_count * 3 */
} raw_vertex_cache;

typedef struct raw_morph_channel {
    char *name;
    float default_weight;
} raw_morph_channel;

typedef struct raw_mesh {
    char *name;
    uint32_t vertex_count;
    uint32_t index_count;
    float *positions; /* 3 a vertex */
    float *normals;   /* 3 a vertex, or NULL: the builder computes smooth normals */
    float *uvs;       /* 2 a vertex, or NULL */
    float *tangents;  /* 4 a vertex (xyz, handedness: bitangent = w * normal x tangent along +v), or NULL */
    uint32_t *indices;
    int32_t skin; /* -1 rigid */
    int32_t material;
    uint32_t influence_count; /* slots a vertex, any number; unused slots have joint UINT32_MAX or weight 0 */
    uint32_t *joints;         /* influence_count a vertex, indices into the skin's joints */
    float *weights;
    float *dq_weights; /* a vertex: its share of dual-quaternion skinning (SINEW_SKIN_BLEND_MIXED), or NULL */
    uint32_t target_count;
    raw_morph_target *targets;
    raw_vertex_cache *cache; /* or NULL */
    bool flat_normals;       /* sinew_mesh.flat_normals: none given, and the format wants faceted ones */
    float *colors;           /* 4 a vertex, linear RGBA, or NULL */
} raw_mesh;

typedef struct raw_texture {
    char *path;           /* resolved path, or NULL */
    unsigned char *image; /* the encoded image when the file embeds it, or NULL */
    uint32_t image_size;
} raw_texture;

typedef struct raw_material {
    char *name;
    float base_color[4];
    float metallic, roughness, emissive[3], normal_scale, occlusion_strength;
    bool metallic_roughness; /* the file gave the PBR parameters */
    raw_texture maps[SINEW_MAP_COUNT];
    sinew_alpha_mode alpha_mode;
    float alpha_cutoff;
} raw_material;

typedef struct raw_model {
    char *source;
    char *format;
    uint32_t node_count;
    char **node_names;
    int32_t *node_parents; /* parents before children */
    sinew_transform *node_rest;
    uint8_t *node_inherit; /* sinew_inherit a node, or NULL: all SINEW_INHERIT_NORMAL */
    uint32_t skin_count;
    raw_skin *skins;
    uint32_t mesh_count;
    raw_mesh *meshes;
    uint32_t instance_count;
    sinew_instance *instances;
    uint32_t material_count;
    raw_material *materials;
    uint32_t clip_count;
    raw_clip *clips;
    uint32_t morph_channel_count;
    raw_morph_channel *morph_channels;
    uint32_t pool_count;
    raw_key_pool *pools;
    uint32_t warning_count;
    bool warning_lost;  /* raw_model_warn() ran out of memory: the build fails rather than lose it */
    bool blob_in_pages; /* raw_model_write: a blob of MODEL_PAGES_MIN and more may be in 2 MB pages
                         * (sinew_pages_alloc; for a model that adopts it; import_free frees it) */
    char **warnings;
    const struct sinew_muscle_set *muscles; /* borrowed, not freed: stored with the model, or NULL */
} raw_model;

/* Frees what a raw clip points to (not the clip itself). */
void raw_clip_free(raw_clip *clip);

/* Frees what a raw mesh points to (not the mesh itself). */
void raw_mesh_free(raw_mesh *mesh);
/* Vertex colours that FBX, COLLADA, IQM and Assimp's formats store as painting tools write them,
 * sRGB-encoded (three.js's and Blender's reading), as the linear RGBA raw_mesh.colors holds: `n`
 * colours of `stride` components (3: alpha 1) from `in` into `out` (4 a colour; `out` may be `in`
 * when `stride` is 4). */
void raw_colors_from_srgb(const float *in, uint32_t stride, uint32_t n, float *out);

/* Every pointer in a raw model is from malloc/calloc (or NULL); this frees them all. */
void raw_model_free(raw_model *model);

/* Appends a formatted warning; returns false when out of memory. */
bool raw_model_warn(raw_model *model, const char *format, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 2, 3)))
#endif
    ;

char *raw_strdup(const char *text);

/* The skeleton of a file that has one but no skin to say so (a skeleton-only animation):
 * out[n] is true for a node that is not excluded[n] (cameras, lights, meshes) and that a
 * clip moves, or that has a moved node below it, or whose parent is moved (BVH-style end
 * sites). `out` holds node_count entries. False when out of memory. */
bool raw_model_moved_nodes(const raw_model *model, const bool *excluded, bool *out);

/* Grows the node arrays (names, parents, rest) to hold `capacity` nodes; false when out of
 * memory (those grown are kept, the model stays freeable). */
bool raw_model_grow_nodes(raw_model *model, uint32_t capacity);

/* A skeleton of nodes [first, node_count) as raw_model_add_skeleton() adds it; false when out
 * of memory. */
bool raw_model_joints_from(raw_model *model, uint32_t first);

/* Adds a skin with no mesh whose joints are the nodes with joint[n] set (identity inverse
 * binds: nothing is bound to it), so that they count as joints; *added is how many (0: no
 * skin added). False when out of memory (the model unchanged). */
bool raw_model_add_skeleton(raw_model *model, const bool *joint, uint32_t *added);

/* Checks and repairs a clip that owns its keys as the builder does (keys sorted, one track
 * a node, unit rotations), then moves every key into a new pool of the model: the clip's
 * channels then refer to the pool, and the clip is a template for raw_model_add_window().
 * On failure the clip is unchanged apart from the repairs and stays freeable. */
sinew_result raw_model_pool_clip(raw_model *model, raw_clip *clip, sinew_error *error);

/* Appends a clip named `name` that plays [start, start + duration] of `pooled`'s timeline
 * (a clip made by raw_model_pool_clip(), not necessarily one of the model's): its tracks
 * (those of nodes with keep[node], or all when keep is NULL) narrowed to the keys around
 * the window, sharing the pool. False when out of memory (the model unchanged). */
bool raw_model_add_window(raw_model *model, const raw_clip *pooled, const char *name, float start, float duration,
                          const bool *keep);

/* Makes `c` a linear channel of `keys` (>= 2) keys evenly spaced over [0, duration], values
 * allocated for the caller to fill; false when out of memory (the channel stays freeable). */
bool raw_channel_even(raw_channel *c, int kind, float duration, uint32_t keys);

/* Makes `model`'s clips one clip of `track_count` tracks, each with a linear rotation channel
 * of `keys` (>= 2) keys at evenly spaced times over `duration`; the caller sets each track's
 * node and the quaternions. NULL when out of memory (the model stays freeable). */
raw_clip *raw_model_add_rotation_clip(raw_model *model, const char *name, float duration, uint32_t track_count,
                                      uint32_t keys);

/* Double-precision matrices (dmat.c), column-major as sinew_mat4, for readers that
 * evaluate a file's transforms exactly. */
typedef struct dmat {
    double m[16];
} dmat;

dmat dmat_identity(void);
dmat dmat_mul(const dmat *a, const dmat *b);
/* A matrix written row by row (COLLADA's <matrix>, <bind_shape_matrix>, inverse binds). */
dmat dmat_from_rows(const double v[16]);
void dmat_to_float(const dmat *a, sinew_mat4 *out);
/* Inverse of an affine matrix (last row 0 0 0 1); identity when singular. */
dmat dmat_inverse_affine(const dmat *a);
/* Translation * rotation (x, y, z, w; normalised here) * scale. */
dmat dmat_from_trs(const double t[3], const double q[4], const double s[3]);
/* The unit quaternion (x, y, z, w) of the rotation in a's upper 3x3 (orthonormal; the
 * identity when it is degenerate). */
void dmat_quat(const dmat *a, double q[4]);

/* A local transform in doubles: translation, rotation (x, y, z, w), scale. */
typedef struct bake_trs {
    double t[3], q[4], s[3];
} bake_trs;

/* A local transform as the baker's ten numbers (translation 0..2, rotation 3..6 as x, y, z, w,
 * scale 7..9), its rotation on the side of `near`'s ten (NULL: as it is). */
void bake_trs_ten(const bake_trs *l, const double *near, double out[10]);

typedef struct bake_desc {
    void (*eval)(const void *context, double time, bake_trs *out); /* exact, at clip time (s) */
    /* Optional: the exact clip time of the file's key that `time` (a float clip time) stands
     * for, or `time` itself: a key's derivatives are taken around where it really is. */
    double (*key_time)(const void *context, double time);
    /* Optional: the one-sided derivatives (per second, rotation on the side of `value`) at
     * that key time from the file's own slopes; false to take differences of eval instead. */
    bool (*derivatives)(const void *context, double time, const double value[10], double in[10], double out[10]);
    /* Optional: the transform at that key time (rotation on the side of `near`, which may be
     * NULL) and its derivatives as `derivatives` gives them, in one pass; false to evaluate it
     * and take its derivatives apart. */
    bool (*key)(const void *context, double time, const double *near, double value[10], double in[10], double out[10]);
    const void *context;
    double tol_t, tol_r, tol_s; /* translation (file units), rotation (rad), relative scale */
    uint64_t *budget;           /* keys the whole clip may still add by halving */
} bake_desc;

/* Bakes one node's track (bake.c): keys at `times` (sorted, distinct; include the instant
 * before each step), intervals halved until the runtime's cubic Hermite is within the
 * tolerances; channels that hold the rest value throughout are left out. False when out
 * of memory. */
bool bake_track(const bake_desc *d, const float *times, uint32_t n, const sinew_transform *rest, raw_track *track);

/* The diagonal of the rest pose's node positions with the root (node 0, the file's axes and
 * unit) left out: the scene's size in file units, for a bake's translation tolerance; 1
 * when it has none. False when out of memory. */
bool raw_model_rest_diagonal(const raw_model *model, double *diagonal);

/* Base64 (RFC 4648's alphabet) of `len` characters into `out`, which holds len / 4 * 3 + 3 bytes:
 * the bytes written, or SIZE_MAX at a character outside the alphabet. '=' ends a group, so pieces
 * padded one by one (FBX's ASCII `Content`) decode as one text; line breaks are skipped. */
size_t import_base64_decode(const char *text, size_t len, unsigned char *out);

/* Reads a whole file into *bytes (with a NUL byte after the end; import_free frees it: a file
 * of IMPORT_PAGES_MIN and more is in 2 MB pages, others are malloc'd); false when it cannot be
 * read. */
bool import_read_file(const char *path, unsigned char **bytes, size_t *size);
void import_free(void *ptr); /* alloc.h's free, for sources that do not include it */

/* Writes a whole file or nothing: into a temporary file beside `path`, renamed over it once
 * every byte is written and closed (a target that is not a regular file, such as /dev/stdout,
 * is written in place). */
sinew_result import_write_file(const char *path, const void *bytes, size_t size, sinew_error *error);

/* The import helper's reply on its stdout: this header, then the model blob (kind SINEW_OK)
 * or the error message with its terminating NUL. */
typedef struct reply_header {
    uint32_t magic;
    uint32_t kind; /* sinew_result */
    uint64_t size; /* bytes that follow */
} reply_header;
#define REPLY_MAGIC 0x53524550u /* "PERS" */
/* An error reply's payload: the message, its NUL, then offset (int64) and line (uint32), little-endian. */
#define REPLY_ERROR_TRAILER 12u
void import_reply_put_where(unsigned char *out, int64_t offset, uint32_t line);

/* isolate.c: runs the import in the helper program under the desc's deadline and memory
 * limit; decodes a whole reply (a model, or the helper's error). */
sinew_result import_in_helper(const sinew_import_desc *desc, sinew_model **out, sinew_error *error);
/* The same, the blob the helper made (malloc'd) instead of a model. */
sinew_result import_blob_in_helper(const sinew_import_desc *desc, void **bytes, size_t *size, sinew_error *error);
/* The desc's deadline in seconds: desc->timeout, 0 meaning 120; 0 or less: none. */
double import_timeout_of(const sinew_import_desc *desc);
/* The same in a session's helper (started, or started again, as needed); the session's desc. */
const sinew_import_desc *import_session_desc(const sinew_import_session *session);
sinew_result import_in_session(sinew_import_session *session, const char *path, sinew_model **out, sinew_error *error);
sinew_result import_reply_decode(const unsigned char *bytes, size_t size, const char *path,
                                 const sinew_allocator *allocator, sinew_model **out, sinew_error *error);
/* Which reader sinew_import() gives the file ("Assimp", "sinew's FBX reader", ...), for messages. */
const char *import_reader_name(const char *path, bool assimp);

/* An XML document of `size` (<= INT32_MAX) bytes, parsed with no network, huge text nodes
 * allowed and nothing printed (libxml2's own error handlers quieted for the parse); NULL
 * when it is not well-formed, or libxml2 cannot be loaded (xml.h; `first` says which). Free
 * with xmlFreeDoc. */
typedef struct import_xml_error {
    int line;         /* 0: none */
    bool unavailable; /* libxml2 could not be loaded (the message says why) */
    char message[256];
} import_xml_error;
struct _xmlDoc *import_xml_parse(const char *path, const unsigned char *bytes, size_t size, import_xml_error *first);

/* A relative URI with its %XX escapes decoded, into `out` (cut to `size`). */
void import_uri_decode(const char *uri, char *out, size_t size);

/* A texture that a model file refers to, as the path of a regular file that exists (resolved),
 * or NULL: `reference` as written (absolute, or relative to the folder of `model_path`;
 * backslashes read as slashes), or with `by_name` only its file name, beside the model (for
 * paths written on another machine). `looked` gets the path tried. */
char *import_find_texture(const char *model_path, const char *reference, bool by_name, char *looked,
                          size_t looked_size);

/* A material's texture: `reference` as written (unless it is a Windows drive path), then by
 * its file name beside the model; *out NULL, with a warning naming `material`, when neither
 * exists. False when out of memory. */
bool import_material_texture(raw_model *model, const char *model_path, const char *material, const char *reference,
                             char **out);

/* Roughness (glTF's, perceptual) of a Blinn-Phong specular exponent: alpha^2 = 2 / (n + 2),
 * roughness = sqrt(alpha). Exponents below 1 are read as the 0..1 scale some exporters
 * write (times 128, OBJ's range). */
float import_roughness_of_shininess(double exponent);

/* Validates and repairs the raw model (sorting and limiting influences, sorting keys,
 * making consecutive rotation keys take the short way, computing missing normals) and
 * writes the runtime blob into *bytes (malloc'd). */
sinew_result raw_model_build(raw_model *model, void **bytes, size_t *size, sinew_error *error);

/* A loaded model back as a raw model (save.c): every array copied; false when out of memory
 * (what was copied is freed by raw_model_free). */
bool raw_model_from_model(const sinew_model *model, raw_model *raw);

/* Writes the blob of a raw model that is already valid (one copied from a runtime model)
 * without repairing anything. */
sinew_result raw_model_write(const raw_model *model, void **bytes, size_t *size, sinew_error *error);

/* Reads a file through Assimp into a raw model, in this process (assimp.c); in the lean import
 * helper (assimp_exec.c), becomes sinew-import-assimp instead, after import_helper_set_exec(). */
sinew_result raw_model_from_assimp(const char *path, raw_model *model, sinew_error *error);
/* The Assimp reader of this program: NULL in libsinew (which never loads Assimp: its formats are
 * read by the helper, sinew-import-assimp), raw_model_from_assimp in the helpers (set by their
 * main: the lean one's execs sinew-import-assimp). */
extern sinew_result (*import_assimp_reader)(const char *path, raw_model *model, sinew_error *error);
void import_helper_set_exec(char **argv, int reply_fd);

/* Reads an FBX 7.x file (binary or ASCII, its bytes already in memory) with sinew's own
 * reader (fbx.c): transforms, skins and curves evaluated as the authoring tools do, clips
 * baked to keys within a stated tolerance. */
sinew_result raw_model_from_fbx(const char *path, const unsigned char *bytes, size_t size, raw_model *model,
                                sinew_error *error);

/* Reads a glTF 2.0 file (.gltf JSON or .glb, its bytes already in memory) with sinew's own
 * reader (gltf.c): nodes by index, every primitive, skins, samplers as the file says. */
sinew_result raw_model_from_gltf(const char *path, const unsigned char *bytes, size_t size, raw_model *model,
                                 sinew_error *error);

/* Reads a COLLADA 1.4/1.5 file (its bytes already in memory; UTF-8 or UTF-16) with sinew's
 * own reader (collada.c): joints bound by SID, samplers kept or baked exactly, clip windows. */
sinew_result raw_model_from_collada(const char *path, const unsigned char *bytes, size_t size, raw_model *model,
                                    sinew_error *error);

/* Reads an Inter-Quake Model file (version 2, its bytes already in memory) with sinew's own
 * reader (iqm.c): joints, skinned meshes, animations, and animation-only files of poses. */
sinew_result raw_model_from_iqm(const char *path, const unsigned char *bytes, size_t size, raw_model *model,
                                sinew_error *error);

/* Reads a BVH motion capture file (its bytes already in memory) with sinew's own reader (bvh.c):
 * every joint and End Site a node of the skeleton, the frames one clip of a key a frame. */
sinew_result raw_model_from_bvh(const char *path, const unsigned char *bytes, size_t size, raw_model *model,
                                sinew_error *error);

/* True when the text starts with HIERARCHY (after a byte order mark and white space). */
bool bvh_sniff(const unsigned char *head, size_t size);

/* True when the bytes start an IQM file ("INTERQUAKEMODEL\0"). */
bool iqm_sniff(const unsigned char *head, size_t size);

/* True when the first bytes hold a <COLLADA> root (UTF-8 or UTF-16). */
bool collada_sniff(const unsigned char *head, size_t size);

/* True when the bytes start a binary glTF (.glb). */
bool gltf_sniff(const unsigned char *head, size_t size);

/* COLLADA files: cuts the one clip Assimp makes of a file's <animation_clip>s into those
 * clips (collada_clips.c). Leaves the model as it is when there are none. */
void collada_split_clips(const char *path, raw_model *model);

/* alloc.c: an import's own allocation accounting and deadline (alloc.h routes the readers'
 * allocations through it). begin .. end on one thread, nested imports stacked. Past the
 * deadline (or once cancelled) every allocation fails, and import_late() says so: a reader's long
 * loops ask it and stop as for a failed allocation; the import then fails with
 * SINEW_ERROR_LIMIT_TIME (SINEW_ERROR_CANCELLED). */
typedef struct import_alloc_state {
    unsigned char opaque[128];
    void *outer;
} import_alloc_state;
typedef struct import_alloc_result {
    uint64_t peak, count, limit;
    bool over_limit; /* an allocation was refused for the limit */
    bool refused;    /* an allocation failed (import_alloc_sweep(), or the system's malloc) */
    bool late;       /* the deadline passed */
    bool cancelled;  /* the progress callback said stop */
} import_alloc_result;
/* `seconds`: the time it may take (0 or less: no deadline); `progress` (may be NULL) is asked
 * about every 50 ms, and returning false stops the import as the deadline does. */
void import_alloc_begin(import_alloc_state *state, uint64_t limit, double seconds,
                        bool (*progress)(float fraction, void *user), void *progress_user);
bool import_late(void);
void import_alloc_end(import_alloc_state *state, import_alloc_result *result);
/* A large block about to be written whole, counted as the import's: in 2 MB pages
 * (sinew_pages_alloc, counted as its whole mapping) when it has `pages_from` bytes or more, else
 * (or when it cannot be mapped) malloc'd with its pages filled in at once (sinew_prefault);
 * import_free frees it; NULL when refused. On a virtual machine with shadow page tables each first
 * touch of a 4 KiB page costs some microseconds, and a file's bytes are touched twice (the
 * kernel's copy, then the reader), so the import's large buffers (a file's bytes, JSON text and
 * nodes, the arena's chunks) are in 2 MB pages from IMPORT_PAGES_MIN: a 2 MB page zeroes at
 * most 4 times the bytes asked for, cheaper than the faults it saves. */
#define IMPORT_PAGES_MIN ((size_t)512 << 10)
void *import_large_alloc(size_t size, size_t pages_from);
/* An arena of the import: what is taken is zeroed and 16-byte aligned, and stays until the whole
 * arena is freed. Its chunks (64 KiB, doubling to 4 MiB; a large request gets its own) count
 * against the import's limit as one allocation each; those of 256 KiB and more are mapped with
 * their pages filled in a window at a time (MADV_POPULATE_WRITE), which on a virtual machine
 * costs a fraction of a fault a page; those of IMPORT_PAGES_MIN and more in 2 MB pages. */
typedef struct import_arena {
    void *head;
    size_t first; /* the first chunk's size when more than 64 KiB (import_arena_expect) */
} import_arena;
void *import_arena_take(import_arena *arena, size_t bytes);
/* The arena will hold about `bytes` (a document read from a file of half that): its first chunk
 * is that large (a power of two, at most 4 MiB), instead of growing to it from 64 KiB a chunk
 * at a time, each chunk's pages faulted in afresh. */
void import_arena_expect(import_arena *arena, size_t bytes);
void import_arena_free(import_arena *arena);
/* Tests: imports on this thread fail their allocation number `fail_at` (1 first; 0: none), and
 * how many allocations the last import made. */
void import_alloc_sweep(uint64_t fail_at);
uint64_t import_alloc_last_count(void);
/* The default memory limit of an import of a file of `size` bytes (0: not known): 256 MiB and 64
 * times the size, at most half the memory (within 1..16 GiB). */
uint64_t import_default_memory_limit(uint64_t size);

#endif
