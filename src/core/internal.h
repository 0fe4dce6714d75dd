/* Cross-file internals of src/core (no promise to library users).
 *
 * The model blob, version 4: the .sinew runtime file format, which sinew_model_from_blob()
 * and sinew_model_load() read and the import builder writes. Little-endian throughout.
 *
 *   blob_file_header                 at offset 0 (48 bytes)
 *   blob_section[section_count]      the directory, right after the header
 *   string pool, tables, arrays      anywhere after it, each aligned to 16 bytes
 *
 * Each directory entry is tagged with four characters and gives the offset, element count
 * and element size of one table; readers skip tags they do not know (a later minor
 * addition) but still check that their bytes lie inside the file, and refuse a known tag
 * twice or with another element size. Every reference is a byte offset from the start of
 * the blob; strings are offsets into the pool (section STRS), which ends with a NUL;
 * BLOB_NONE marks an absent string or array; arrays may be shared (clips cut from one
 * animation point at the same times and values). Version 3 added blob_clip.start and
 * blob_material.diffuse_image; later minor additions (sections older readers skip): NINH (FBX
 * inherit types), MTAN (mesh tangents), MPBR (physically based material parameters). Version 4
 * added deformers: MCHN (morph channels), MTGT (morph targets), IMRF (each instance's first
 * channel), WTRK (clips' weight tracks), VCCH (vertex caches), SKBL (skins' blend), MDQW (meshes'
 * dual-quaternion weights), CTLN (clips' place on the file's timeline); version 3 files are read
 * (they have none of these) with a warning. Later minor additions to version 4: MFLT (meshes
 * drawn with flat normals), MCOL (vertex colours), MALP (materials' alpha modes). The checksum is
 * CRC-32C (Castagnoli) of the whole blob computed with the checksum field set to 0.
 */
#ifndef SINEW_CORE_INTERNAL_H
#define SINEW_CORE_INTERNAL_H

#include <math.h>
#include <stdarg.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "sinew/anim.h"
#include "sinew/model.h"

/* Nothing here is public API: hidden from libsinew.so even where the name starts with sinew_
 * (the export test compares libsinew.so's symbols with the headers). */
#pragma GCC visibility push(hidden)

/* A shared library loaded on first use, by its soname, with `count` symbols found in it (into
 * `symbols`, in the order of `names`): a dependency only some programs need (libxml2, libepoxy,
 * meshoptimizer) is loaded when first used, not at every process start. sinew_lazy_load() tries
 * once (thread-safe) and says whether it is loaded; the reason it is not goes to `why`. The
 * library stays loaded. A static instance: {.soname = ..., .names = ..., .symbols = ..., .count = ...}. */
typedef struct sinew_lazy_library {
    const char *soname;
    const char *const *names;
    void **symbols;
    size_t count;
    bool tried, loaded;
    char failure[256];
} sinew_lazy_library;
bool sinew_lazy_load(sinew_lazy_library *library, char *why, size_t why_size);
/* What the processor and the system let this process use: read from what the C library found at
 * start (glibc 2.33's <sys/platform/x86.h>) rather than __builtin_cpu_supports(), whose first use
 * runs libgcc's own CPUID sweep at every process start (0.1 ms on a virtual machine, where CPUID
 * traps); __builtin_cpu_supports() where the C library has no such header. False off x86-64. */
typedef enum sinew_cpu_feature {
    SINEW_CPU_SSE42, /* SSE 4.2 (CRC-32C) */
    SINEW_CPU_AVX2,
    SINEW_CPU_AVX2_FMA, /* AVX2 and FMA */
    SINEW_CPU_AVX512,   /* AVX-512 F and DQ */
    SINEW_CPU_AVX512BW,
} sinew_cpu_feature;
bool sinew_cpu_has(sinew_cpu_feature feature);
/* An sRGB-encoded colour component (0..1) as linear light: the import's vertex colours, the
 * renderer's muscle colours. */
static inline float sinew_srgb_to_linear(float c)
{
    return c <= 0.04045f ? c / 12.92f : c == 1.0f ? 1.0f : powf((c + 0.055f) / 1.055f, 2.4f);
}
/* Up to `size` bytes from fd into buf, as many as there are (a read may return fewer; EINTR is
 * retried); errno set when a read fails. What the file readers use instead of stdio, whose
 * fopen, fseek and fread cost four system calls more a file (its size asked twice, a seek to
 * the end and back), about 2 us each on a virtual machine. */
size_t sinew_read_fully(int fd, void *buf, size_t size);
/* `path` opened for reading when it is a regular file: the descriptor, its size in *size. -1 with
 * errno from open(), or with EINVAL (nothing left open) when it is something else: a directory,
 * a FIFO (opened without waiting for a writer, O_NONBLOCK), a device. */
int sinew_open_regular(const char *path, uint64_t *size);
/* Fills in the pages of a large block about to be written whole (MADV_POPULATE_WRITE: one call
 * instead of a fault a page, which costs microseconds on a virtual machine); nothing for a block
 * under 64 KiB, or where the kernel cannot. */
void sinew_prefault(void *p, size_t size);

/* Whether every float is finite (its exponent bits not all ones), and whether finite times never
 * go down: blocks at a time without exits, which the compiler vectorises (the blob's checks and
 * the builder's). */
bool sinew_floats_finite(const float *values, uint64_t count);
bool sinew_times_ascending(const float *times, uint32_t count);

/* A large block in 2 MB pages where the kernel gives them (transparent huge pages, asked for with
 * MADV_HUGEPAGE): a first touch costs a fault a 2 MB page instead of a 4 KiB one (on a virtual
 * machine with shadow page tables, some microseconds each: 1.4 MB read from a file and checked
 * cost 3 ms in 4 KiB pages, 0.5 ms in 2 MB ones). The first `populate` bytes are filled in at
 * once. The mapping is `size` rounded up to 2 MB, so it is for blocks of about a megabyte and
 * more. NULL when it cannot be mapped or 64 blocks are live already: the caller mallocs instead.
 * Such a block is freed with sinew_pages_free(), which says false for any other pointer (then the
 * caller frees it as it came), or sinew_block_free() (the block or a malloc'd pointer). A freed
 * block may be kept (up to 32 MB of them, MADV_FREE) for sinew_large_alloc() to give again;
 * sinew_pages_alloc() itself always maps fresh, zeroed pages.
 * sinew_pages_length() is the mapping's length, 0 for any other pointer; sinew_pages_rounded()
 * the length a block of `size` bytes maps (0 for none or too large a size). */
void *sinew_pages_alloc(size_t size, size_t populate);
bool sinew_pages_free(void *p);
size_t sinew_pages_length(const void *p);
size_t sinew_pages_rounded(size_t size);
void sinew_block_free(void *p);
/* A block about to be written whole: in 2 MB pages (filled in) when it has `pages_from` bytes or
 * more and they can be had (a kept block of the same length first, its contents undefined),
 * else malloc'd with its pages filled in (sinew_prefault); freed by sinew_block_free. NULL when
 * out of memory. */
void *sinew_large_alloc(size_t size, size_t pages_from);

/* sinew_model_from_blob() for malloc'd (or sinew_pages_alloc'd) bytes the model then owns (freed
 * with it) instead of copying them, when `allocator` is NULL (with an allocator they are copied,
 * and stay the caller's). On failure the bytes stay the caller's. `built`: the bytes are what
 * this process's builder just wrote (raw_model_build), so their checksum, which the builder took
 * over them, is not taken again; every other check is made. */
sinew_result sinew_model_adopt_blob(void *bytes, size_t size, bool built, const char *name,
                                    const sinew_allocator *allocator, sinew_model **out, sinew_error *error);

/* A model blob this long or longer, read from a .sinew file or built by an import, is kept in
 * 2 MB pages (sinew_pages_alloc): under 2 MB more than its length, for a megabyte's pages
 * touched at a fault each (twice for a file's bytes: the kernel's copy, then the checks). */
#define MODEL_PAGES_MIN ((size_t)1 << 20)

#define BLOB_MAGIC "SINEW\r\n\x1a"
#define BLOB_VERSION 4u
#define BLOB_OLDEST_VERSION 3u /* the oldest version read */
#define BLOB_NONE 0xffffffffu
#define BLOB_ALIGN 16u
#define BLOB_MAX_SECTIONS 64u

typedef struct blob_span {
    uint32_t offset;
    uint32_t count;
} blob_span;

typedef struct blob_file_header {
    char magic[8];
    uint32_t version;
    uint32_t header_size; /* sizeof(blob_file_header) */
    uint64_t size;        /* of the whole blob */
    uint32_t checksum;
    uint32_t flags; /* 0 */
    uint32_t section_count;
    uint32_t source; /* string: the file the model was converted from */
    uint32_t format; /* string: its format, as the importer named it */
    uint32_t reserved;
} blob_file_header;

typedef struct blob_section {
    char tag[4];
    uint32_t offset;
    uint32_t count;
    uint32_t elem_size;
} blob_section;

/* The sections by name, as the writer fills them and the reader finds them (not on disk). */
typedef struct blob_header {
    uint32_t source, format;
    uint32_t version;         /* of the file (reader only) */
    blob_span strings;        /* STRS bytes */
    blob_span node_names;     /* NNAM uint32_t strings */
    blob_span node_parents;   /* NPAR int32_t */
    blob_span node_rest;      /* NRST sinew_transform */
    blob_span skins;          /* SKIN blob_skin */
    blob_span meshes;         /* MESH blob_mesh */
    blob_span instances;      /* INST sinew_instance */
    blob_span materials;      /* MATL blob_material */
    blob_span clips;          /* CLIP blob_clip */
    blob_span warnings;       /* WARN uint32_t strings */
    blob_span muscles;        /* MUSC blob_muscle */
    blob_span node_inherit;   /* NINH uint8_t sinew_inherit, absent when every node is NORMAL */
    blob_span mesh_tangents;  /* MTAN uint32_t a mesh: offset of 4 floats a vertex or BLOB_NONE; absent when none */
    blob_span materials_pbr;  /* MPBR blob_pbr a material; absent in older files */
    blob_span morph_channels; /* MCHN blob_morph_channel */
    blob_span morph_targets;  /* MTGT blob_morph_target, by mesh, then channel and full weight */
    blob_span instance_morph; /* IMRF uint32_t an instance: its first morph channel; absent: all 0 */
    blob_span weight_tracks;  /* WTRK blob_weight_track, by clip, then channel */
    blob_span caches;         /* VCCH blob_cache, at most one a mesh */
    blob_span skin_blend;     /* SKBL uint32_t a skin: sinew_skin_blend; absent: all linear */
    blob_span mesh_dq;        /* MDQW uint32_t a mesh: offset of a float a vertex or BLOB_NONE; absent: none */
    blob_span clip_timeline;  /* CTLN two floats a clip: sinew_clip.timeline and frame_rate; absent: all 0 */
    blob_span mesh_flat;      /* MFLT uint8_t a mesh: 1 sinew_mesh.flat_normals, else 0; absent: all 0 */
    blob_span mesh_colors;    /* MCOL uint32_t a mesh: offset of 4 floats a vertex or BLOB_NONE; absent: none */
    blob_span material_alpha; /* MALP blob_alpha a material; absent: all opaque */
} blob_header;

/* One known section: its tag, where its span lives in blob_header, its element size. */
typedef struct blob_section_kind {
    char tag[5];
    size_t field; /* offsetof(blob_header, ...) */
    uint32_t elem_size;
} blob_section_kind;

extern const blob_section_kind sinew_blob_section_kinds[];
/* The warning the reader adds to a model read from an older version (model.c). */
extern const char *const sinew_blob_old_version_warning;
extern const uint32_t sinew_blob_section_kind_count;

typedef struct blob_skin {
    blob_span joints;       /* uint32_t */
    blob_span inverse_bind; /* sinew_mat4 */
} blob_skin;

typedef struct blob_mesh {
    uint32_t name;
    uint32_t vertex_count;
    uint32_t index_count;
    uint32_t influence_count;
    int32_t skin;
    int32_t material;
    uint32_t positions; /* offsets of vertex_count elements (influence_count per vertex for joints/weights) */
    uint32_t normals;
    uint32_t uvs; /* BLOB_NONE when absent */
    uint32_t indices;
    uint32_t joints; /* BLOB_NONE for a rigid mesh */
    uint32_t weights;
} blob_mesh;

/* INST, one a mesh instance (sinew_instance without its morph channel, which is in IMRF). */
typedef struct blob_instance {
    uint32_t mesh;
    uint32_t node;
} blob_instance;

typedef struct blob_morph_channel {
    uint32_t name; /* string */
    float default_weight;
} blob_morph_channel;

typedef struct blob_morph_target {
    uint32_t mesh;
    uint32_t name; /* string */
    uint32_t channel;
    float full_weight;
    uint32_t delta_count;
    uint32_t vertices;  /* offset of delta_count uint32_t */
    uint32_t positions; /* offset of delta_count * 3 floats */
    uint32_t normals;   /* the same, or BLOB_NONE */
    uint32_t tangents;  /* the same, or BLOB_NONE */
} blob_morph_target;

typedef struct blob_weight_track {
    uint32_t clip;
    uint32_t channel;
    sinew_channel keys; /* into the clip's times and values */
} blob_weight_track;

typedef struct blob_cache {
    uint32_t mesh;
    uint32_t frame_count;
    uint32_t times;     /* offset of frame_count floats */
    uint32_t positions; /* offset of frame_count * vertex_count * 3 floats */
} blob_cache;

typedef struct blob_texture {
    uint32_t path;   /* string, BLOB_NONE when absent */
    blob_span image; /* bytes of an embedded image (PNG, JPEG, ...), count 0 when none; may be shared */
} blob_texture;

typedef struct blob_material {
    uint32_t name;
    float base_color[4];
    blob_texture base_color_map;
} blob_material;

/* MPBR, one a material (absent: every material has the defaults of sinew_model_load()). */
typedef struct blob_pbr {
    float metallic, roughness, emissive[3], normal_scale, occlusion_strength;
    uint32_t flags;                         /* 1: the file gave metallic-roughness parameters */
    blob_texture maps[SINEW_MAP_COUNT - 1]; /* sinew_map 1.. (the base colour map is in MATL) */
} blob_pbr;

typedef struct blob_alpha {
    uint32_t mode; /* sinew_alpha_mode */
    float cutoff;
} blob_alpha;

typedef struct blob_muscle {
    double rest_length;                     /* 0: taken from the rest pose */
    uint32_t name;                          /* string */
    uint32_t origin_joint, insertion_joint; /* strings, BLOB_NONE for a point in model space */
    float origin_offset[3], insertion_offset[3];
    uint32_t node_count; /* 1..SINEW_MUSCLE_MAX_NODES */
    uint32_t segments;
    uint32_t radii;        /* offset of node_count doubles */
    uint32_t coefficients; /* offset of node_count doubles */
    float color[3];
} blob_muscle;

typedef struct blob_clip {
    uint32_t name;
    float duration;
    float start; /* on the keys' timeline; clips may share times and values */
    uint32_t reserved;
    blob_span tracks; /* sinew_track */
    blob_span times;  /* float */
    blob_span values; /* float */
} blob_clip;

/* CRC-32C (Castagnoli), continued from `crc` (0 to start): the SSE4.2 instruction where
 * the processor has it, else sinew_crc32c_scalar(), the table-driven reference. */
uint32_t sinew_crc32c(uint32_t crc, const void *bytes, size_t size);
uint32_t sinew_crc32c_scalar(uint32_t crc, const void *bytes, size_t size);

/* The checksum a blob of `size` >= sizeof(blob_file_header) bytes should carry. */
uint32_t sinew_blob_checksum(const void *bytes, size_t size);

/* sinew_channel_eval() at a time on the keys' timeline (a clip time plus the clip's start). */
void sinew_channel_eval_keys(const sinew_clip *clip, const sinew_channel *channel, int kind, float time,
                             uint32_t *cursor, float *out);

/* Index k of the key segment [times[k], times[k+1]) holding t, 0 <= k < count - 1, found
 * from *cursor: stepping ahead in forward play, a binary search after a jump back (sample.c).
 * Requires times[0] <= t < times[count - 1]. */
uint32_t sinew_find_segment(const float *times, uint32_t count, float t, uint32_t *cursor);

/* Shortest-path slerp of unit quaternions a -> b at s in [0, 1], normalised (sample.c). */
void sinew_slerp_shortest(const float *a, const float *b, float s, float *out);

/* One checked skinning call as the kernels see it (skin.c). records: 16 floats a joint, a
 * column-major matrix (linear blend) or a sinew_dq_joint (dual quaternion). */
typedef struct skin_call {
    const sinew_mesh *mesh; /* &view: the mesh with the desc's input arrays in place of its own */
    sinew_mesh view;
    const float *records;
    uint32_t record_count; /* entries of records (and dq_records): the palette's */
    bool dqs;
    const float *dq_records; /* SINEW_SKIN_MIXED: the DQ records (records are the linear ones) */
    const float *mix;        /* SINEW_SKIN_MIXED: mesh->dq_weights */
    uint32_t first, count;
    float *out_p, *out_n, *out_t; /* out_n, out_t may be NULL */
    size_t stride;                /* bytes, 12 .. 2^26 */
} skin_call;

typedef enum sinew_isa { SINEW_ISA_SCALAR, SINEW_ISA_AVX2, SINEW_ISA_AVX512 } sinew_isa;

/* The path sinew_skin_vertices() takes for `call` (NULL: the best this processor has), at
 * most the limit set by sinew_skin_set_isa_limit() (tests and benchmarks; returns the old). */
sinew_isa sinew_skin_isa(const skin_call *call);
sinew_isa sinew_skin_set_isa_limit(sinew_isa limit);

/* The SIMD kernels, each doing everything the reference does: AVX-512 (skin_x86.c) 16
 * vertices at a time, AVX2+FMA (skin_avx2.c) 8 at a time. */
void sinew_skin_avx512(const skin_call *call);
void sinew_skin_avx2(const skin_call *call);

/* *allocator, or aligned_alloc/free (16-byte aligned) when it is NULL (model.c). */
sinew_allocator sinew_allocator_or_default(const sinew_allocator *allocator);

/* The model and clip (NULL: the rest pose) a layout plays (player.c). */
const sinew_model *sinew_layout_model(const sinew_clip_layout *layout);
const sinew_clip *sinew_layout_clip(const sinew_clip_layout *layout);
const sinew_clip_layout *sinew_player_layout(const sinew_player *player);

/* Chooses the player's SIMD path (when the processor has it) or the scalar reference. */
void sinew_player_set_simd(sinew_player *player, bool simd);

/* Structure-of-arrays poses (soa.c; rows SINEW_SOA_*, `stride` floats each): whether this
 * processor has the AVX2+FMA paths; identity transforms in lanes [first, stride); rotations
 * normalised into local transforms; world matrices (simd: the AVX2+FMA path, else the scalar
 * reference), as sinew_soa_pose_worlds() and the player compute them. */
bool sinew_soa_simd_supported(void);
void sinew_soa_identity(float *pose, uint32_t stride, uint32_t first);
void sinew_soa_to_locals(const float *pose, uint32_t stride, uint32_t node_count, sinew_transform *locals);
void sinew_soa_worlds(const sinew_model *model, const float *pose, uint32_t stride, const sinew_mat4 *root,
                      sinew_mat4 *worlds, bool simd);

/* Width in floats of one key value of a channel kind (translation/scale 3, rotation 4, a
 * morph channel's weight 1). */
static inline uint32_t sinew_channel_width(int kind)
{
    return kind == SINEW_CHANNEL_ROTATION ? 4u : kind == SINEW_CHANNEL_WEIGHT ? 1u : 3u;
}

/* Values a key stores per component: 1, 3 (cubic: in-tangent, value, out-tangent) or 5
 * (Bezier: value, in time, in value, out time, out value). */
static inline uint32_t sinew_interp_floats(uint32_t interp)
{
    return interp == SINEW_INTERP_CUBIC ? 3u : interp == SINEW_INTERP_BEZIER ? 5u : 1u;
}

/* Floats one key takes in the value array. */
static inline uint32_t sinew_channel_stride(int kind, uint32_t interp)
{
    return sinew_channel_width(kind) * sinew_interp_floats(interp);
}

/* One component of a cubic Bezier segment from (t0, v0) through the control points (t1, v1)
 * and (t2, v2) to (t3, v3), at time t in [t0, t3] (control times within it): the time
 * polynomial solved for the parameter (Newton's steps kept inside a shrinking bracket),
 * then the value polynomial. */
float sinew_bezier(float t0, float v0, float t1, float v1, float t2, float v2, float t3, float v3, float t);

/* True when the control times of a Bezier channel's keys lie within their segments. */
bool sinew_bezier_times_ok(const float *times, const float *values, uint32_t count, uint32_t width);

/* Scales of a pose, wherever they are kept: node j's component c at
 * base[j * node_stride + c * comp_stride] (an array of sinew_transform, or the player's
 * structure of arrays). */
typedef struct pose_scales {
    const float *base;
    size_t node_stride, comp_stride;
} pose_scales;

/* The world matrix of `node` (a child whose inherit type is not SINEW_INHERIT_NORMAL, see
 * sinew_inherit) from its parent's world matrix in `worlds` and its local translation,
 * rotation and scale; the scales of the pose give the parent's own and inherited scale. */
void sinew_pose_world_inherit(const sinew_model *model, uint32_t node, const float translation[3],
                              const float rotation[4], const float scale[3], pose_scales scales,
                              const sinew_mat4 *worlds, sinew_mat4 *out);

#pragma GCC visibility pop

#endif
