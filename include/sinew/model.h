/* sinew/model.h — the runtime model: immutable, flat, ready to sample, pose and skin.
 *
 * What: nodes (names, parents before children, rest local transforms), skins (joint node
 * indices, inverse bind matrices, how they blend), meshes (positions, normals, UVs, triangles,
 * up to SINEW_MAX_INFLUENCES influences per vertex sorted by weight and normalised; morph
 * targets; a vertex cache), morph channels (the weights that morph targets follow), materials,
 * clips (per-node tracks whose translation, rotation and scale channels each have their own
 * keys and interpolation, and weight tracks of morph channels), and the import warnings.
 * What not: no editing; the import side (sinew/import.h) builds models, the core only reads them.
 * Memory: a model is one block owned by the sinew_model object; every pointer inside it
 * stays valid until sinew_model_free(). The blob functions read and write the same layout
 * as a flat byte buffer (the start of the .sinew runtime format).
 * Errors: see sinew/result.h.
 * Conventions: right-handed, Y up, metres, column vectors, column-major matrices,
 * quaternions x,y,z,w, radians, seconds.
 */
#ifndef SINEW_MODEL_H
#define SINEW_MODEL_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "sinew/result.h"

#ifdef __cplusplus
extern "C" {
#endif

#define SINEW_MAX_INFLUENCES 8 /* influences kept per vertex (the largest, renormalised) */
#define SINEW_MAX_JOINTS 1024  /* joints per skin */

/* Column-major 4x4 matrix: m[col * 4 + row]. */
typedef struct sinew_mat4 {
    float m[16];
} sinew_mat4;

typedef struct sinew_transform {
    float translation[3];
    float rotation[4]; /* x, y, z, w */
    float scale[3];
} sinew_transform;

typedef enum sinew_interp {
    SINEW_INTERP_STEP = 0,
    SINEW_INTERP_LINEAR = 1, /* lerp for vectors, shortest-path slerp for rotations */
    SINEW_INTERP_CUBIC = 2,  /* cubic Hermite spline: each key stores in-tangent, value, out-tangent */
    /* Cubic Bezier with 2-D control points (COLLADA's BEZIER, the curves of animation tools),
     * each component on its own: a key stores its value, the (time, value) of the control
     * point before it and of the one after it, component by component: value[w], in_time[w],
     * in_value[w], out_time[w], out_value[w]. A segment's component runs from (t0, v0) through
     * (out_time, out_value) of the first key and (in_time, in_value) of the second to (t1, v1),
     * the time polynomial solved for the curve's parameter; control times lie within the
     * segment (checked when a model is built or loaded). Translation and scale only:
     * rotations are quaternions, not curves of their own components. */
    SINEW_INTERP_BEZIER = 3
} sinew_interp;

enum { SINEW_CHANNEL_TRANSLATION = 0, SINEW_CHANNEL_ROTATION = 1, SINEW_CHANNEL_SCALE = 2, SINEW_CHANNEL_COUNT = 3 };
/* The kind of a morph channel's weight keys (sinew_weight_track): one float a key. Not one of
 * a node track's SINEW_CHANNEL_COUNT channels. */
#define SINEW_CHANNEL_WEIGHT 3

/* How a node combines with its parent (FBX's inherit types; ufbx's names). With s the node's
 * local scale and P its parent's world matrix:
 *  - NORMAL: world = P * T * R * S (matrix composition; FBX RSrs, glTF, COLLADA).
 *  - IGNORE_PARENT_SCALE: the parent's own scale is taken off P before the child is
 *    applied, the child's translation keeps it (FBX Rrs; Maya's segment scale compensate).
 *  - COMPONENTWISE_SCALE: the parent's scale multiplies the child's scale axis by axis
 *    instead of being applied before the child's rotation (FBX RrSs; MotionBuilder).
 * Roots (and a parent's scale of zero) behave as NORMAL. sinew_local_to_world() and the
 * player evaluate all three; "inherited scale" of a node is its local scale times, while it
 * is COMPONENTWISE_SCALE, its parent's inherited scale. */
typedef enum sinew_inherit {
    SINEW_INHERIT_NORMAL = 0,
    SINEW_INHERIT_IGNORE_PARENT_SCALE = 1,
    SINEW_INHERIT_COMPONENTWISE_SCALE = 2
} sinew_inherit;

/* One channel of one node: key_count keys at times[first_key ...]; values at
 * values[first_value ...], 3 floats a key for translation/scale and 4 for rotation,
 * three times that for SINEW_INTERP_CUBIC (in-tangent, value, out-tangent), five times for
 * SINEW_INTERP_BEZIER (value, in time, in value, out time, out value).
 * key_count 0 means "not animated": the node's rest value is used. Channels with the same key
 * times share them (the same first_key): an importer writes each run of times once (a glTF
 * sampler input that many channels use, a baked FBX node's keys), so time_count may be less
 * than the channels' key_counts added up. */
typedef struct sinew_channel {
    uint32_t key_count;
    uint32_t interp; /* sinew_interp */
    uint32_t first_key;
    uint32_t first_value;
} sinew_channel;

typedef struct sinew_track {
    uint32_t node;
    uint32_t reserved;
    sinew_channel channels[SINEW_CHANNEL_COUNT];
} sinew_track;

/* The weight of one morph channel over a clip: keys of one float (SINEW_CHANNEL_WEIGHT) in
 * the clip's times and values, interpolated like any channel. */
typedef struct sinew_weight_track {
    uint32_t channel; /* index into the model's morph_channels */
    sinew_channel keys;
} sinew_weight_track;

/* A clip plays [start, start + duration] of its keys' timeline as clip times [0, duration]:
 * clips cut from one longer animation (COLLADA's <animation_clip>s) share its times and
 * values and differ in start and in the keys their channels take. sinew_sample(),
 * sinew_channel_eval() and the player add start; key times are on the keys' timeline. */
typedef struct sinew_clip {
    const char *name;
    float duration; /* seconds */
    float start;    /* seconds on the keys' timeline where clip time 0 is */
    uint32_t track_count;
    const sinew_track *tracks; /* sorted by node index, at most one per node */
    uint32_t time_count;
    uint32_t value_count;
    const float *times; /* seconds, non-decreasing within a channel */
    const float *values;
    uint32_t weight_track_count;
    const sinew_weight_track *weight_tracks; /* sorted by channel, at most one per channel */
    float timeline;   /* seconds on the source file's own timeline where clip time 0 is (an FBX take's
                       * start; 0 for most files): where vertex caches, which keep the file's times, are read */
    float frame_rate; /* the frames a second the file keeps its animation in (FBX's time mode), or 0 when
                       * it says none (glTF, COLLADA): for showing frame numbers, and stepping by frames */
} sinew_clip;

/* How a skin blends its joints by default (sinew_skin_desc.method chooses at run time). */
typedef enum sinew_skin_blend {
    SINEW_SKIN_BLEND_LINEAR = 0,          /* linear blend skinning */
    SINEW_SKIN_BLEND_DUAL_QUATERNION = 1, /* dual-quaternion skinning */
    SINEW_SKIN_BLEND_MIXED = 2            /* per vertex: linear and dual quaternion mixed by the mesh's dq_weights
                                           * (FBX's "Blend" skinning type) */
} sinew_skin_blend;

typedef struct sinew_skin {
    uint32_t joint_count;
    const uint32_t *joints;         /* node indices */
    const sinew_mat4 *inverse_bind; /* one a joint: mesh space -> joint space at bind time */
    uint32_t blend;                 /* sinew_skin_blend: what the file asked for */
} sinew_skin;

/* A morph target (blend shape, shape key): offsets of some vertices of one mesh, weighed by one
 * morph channel. glTF gives each target a channel of its own; FBX's in-between shapes are
 * several targets of one channel, each whole at its own channel weight (full_weight), between
 * which the channel's weight moves linearly (sinew_morph_target_weights()). */
typedef struct sinew_morph_target {
    const char *name;
    uint32_t channel;  /* the mesh's channel: model channel instance.morph_first + channel */
    float full_weight; /* the channel weight at which the target applies whole: 1, or an
                        * in-between's (never 0; negative for a shape below zero) */
    uint32_t delta_count;
    const uint32_t *vertices; /* delta_count vertex indices, ascending */
    const float *positions;   /* 3 floats a delta: offsets in mesh space */
    const float *normals;     /* 3 floats a delta, or NULL */
    const float *tangents;    /* 3 floats a delta (the tangent's xyz; its handedness stays), or NULL */
} sinew_morph_target;

/* Vertex positions recorded frame by frame (an FBX geometry cache: Maya's .mc/.mcx, 3ds Max's
 * .pc2), which replace the mesh's positions, morphs and skin while a clip is within them. */
typedef struct sinew_vertex_cache {
    uint32_t frame_count;
    const float *times;     /* frame_count seconds on the file's timeline (sinew_clip.timeline), ascending */
    const float *positions; /* frame_count * vertex_count * 3 floats, mesh space */
} sinew_vertex_cache;

typedef struct sinew_mesh {
    const char *name;
    uint32_t vertex_count;
    uint32_t index_count;   /* triangles * 3 */
    const float *positions; /* 3 floats a vertex, mesh space */
    const float *normals;   /* 3 floats a vertex */
    const float *uvs;       /* 2 floats a vertex (v up: 0 is the image's bottom row), or NULL */
    const float *tangents;  /* 4 floats a vertex (xyz, handedness +-1: bitangent = w * normal x tangent), or NULL */
    const uint32_t *indices;
    uint32_t influence_count; /* per vertex, 0 for a rigid mesh, at most SINEW_MAX_INFLUENCES */
    const uint16_t *joints;   /* influence_count a vertex, indices into the skin's joints */
    const float *weights;     /* influence_count a vertex, sorted descending, summing to 1 */
    int32_t skin;             /* index into skins, -1 for a rigid mesh */
    int32_t material;         /* index into materials, -1 for none */
    const float *dq_weights;  /* a float a vertex: its share of dual-quaternion skinning under a
                               * SINEW_SKIN_BLEND_MIXED skin, or NULL */
    uint32_t target_count;
    const sinew_morph_target *targets; /* sorted by channel, then full weight */
    uint32_t morph_channel_count;      /* channels its targets use (largest channel + 1) */
    const sinew_vertex_cache *cache;   /* or NULL */
    /* The file gave no normals and its format asks for faceted ones (glTF: "client implementations
     * MUST calculate flat normals"): `normals` holds smooth ones computed for skinning and tools,
     * and sinew's renderer shades each triangle flat. False when the file gave normals, or when
     * its format smooths them (FBX, COLLADA, IQM: computed smooth, drawn smooth). */
    bool flat_normals;
    /* 4 floats a vertex: linear RGBA that multiplies the material's base colour (glTF's COLOR_0,
     * FBX's and COLLADA's vertex colours, converted from sRGB where the format stores that), or NULL */
    const float *colors;
} sinew_mesh;

/* A mesh drawn at a node. Rigid meshes follow the node's world matrix; skinned meshes
 * come out of skinning in world space and ignore the node (as glTF specifies). A mesh with
 * morph targets takes its channel weights from morph_first on (two instances of one mesh may
 * have weights of their own, as glTF nodes do). */
typedef struct sinew_instance {
    uint32_t mesh;
    uint32_t node;
    uint32_t morph_first; /* the model's channel of the mesh's channel 0 */
} sinew_instance;

/* A morph channel: one weight that clips animate and that the targets of one or more meshes
 * (the parts of one deformed object) follow. */
typedef struct sinew_morph_channel {
    const char *name;
    float default_weight; /* where no clip animates it */
} sinew_morph_channel;

/* The texture maps a material may have. */
typedef enum sinew_map {
    SINEW_MAP_BASE_COLOR = 0,         /* sRGB colour (and alpha), multiplied by base_color */
    SINEW_MAP_METALLIC_ROUGHNESS = 1, /* linear: G roughness, B metallic (glTF's packing), times the factors */
    SINEW_MAP_NORMAL = 2,             /* linear tangent-space normal: X along the tangent (+u), Y along the
                                       * bitangent (+v, up the image), Z out of the surface */
    SINEW_MAP_OCCLUSION = 3,          /* linear: R is ambient occlusion */
    SINEW_MAP_EMISSIVE = 4,           /* sRGB, multiplied by emissive */
    SINEW_MAP_COUNT = 5
} sinew_map;

/* One texture map: a file or the bytes a file embeds (or neither). */
typedef struct sinew_texture {
    const char *path;           /* resolved against the model's folder, or NULL */
    const unsigned char *image; /* the image itself when the file embeds it (a .glb's PNG or JPEG, as
                                 * stored: encoded), else NULL; maps of one material may share it */
    uint32_t image_size;        /* bytes */
} sinew_texture;

/* A material: the colour every renderer shows, and the metallic-roughness parameters of
 * glTF's physically based model (read from glTF; from other formats, values derived from
 * what they store: shininess gives roughness, emission gives emissive). */
typedef enum sinew_alpha_mode { SINEW_ALPHA_OPAQUE = 0, SINEW_ALPHA_MASK = 1, SINEW_ALPHA_BLEND = 2 } sinew_alpha_mode;

typedef struct sinew_material {
    const char *name;
    float base_color[4];      /* linear RGBA */
    float metallic;           /* 0..1 */
    float roughness;          /* 0..1 (perceptual, squared for the microfacet distribution) */
    float emissive[3];        /* linear RGB, may exceed 1 (KHR_materials_emissive_strength) */
    float normal_scale;       /* the normal map's XY scale */
    float occlusion_strength; /* 0..1 */
    bool metallic_roughness;  /* the file gave metallic-roughness parameters (glTF, or Assimp's PBR keys) */
    sinew_texture maps[SINEW_MAP_COUNT];
    /* How the alpha (base_color[3] times the base colour map's and the vertex colour's) is taken,
     * as glTF's alphaMode says: opaque (ignored), mask (a fragment below alpha_cutoff is not drawn:
     * hair cards, leaves) or blend (see-through; sinew's renderer draws it as coverage of the
     * multisampled pixel, in any order: no sorting). */
    sinew_alpha_mode alpha_mode;
    float alpha_cutoff; /* SINEW_ALPHA_MASK's threshold, 0..1 (glTF's default 0.5) */
} sinew_material;

typedef struct sinew_model {
    const char *source;         /* the file it was read from */
    const char *converted_from; /* a .sinew file: the file `sinew convert` read; else NULL */
    const char *format;         /* "collada", "gltf2", ... as the importer named it (for a .sinew file, that of
                                 * the file it was converted from) */

    uint32_t node_count;
    const char *const *node_names;
    const int32_t *node_parents;      /* -1 for roots; parent index < node index */
    const sinew_transform *node_rest; /* rest local transforms */
    const uint8_t *node_inherit;      /* sinew_inherit a node, or NULL when every node is NORMAL */

    uint32_t skin_count;
    const sinew_skin *skins;
    uint32_t mesh_count;
    const sinew_mesh *meshes;
    uint32_t instance_count;
    const sinew_instance *instances;
    uint32_t material_count;
    const sinew_material *materials;
    uint32_t clip_count;
    const sinew_clip *clips;
    uint32_t morph_channel_count;
    const sinew_morph_channel *morph_channels;
    uint32_t warning_count;
    const char *const *warnings;

    /* Muscle definitions stored with the model (a .sinew file converted with muscles), or
     * NULL; see sinew/muscle_file.h and sinew_muscle_rig_create(). */
    const struct sinew_muscle_set *muscles;
} sinew_model;

typedef struct sinew_allocator {
    void *(*alloc)(size_t size, void *user); /* must return memory aligned to 16 bytes */
    void (*free)(void *ptr, void *user);
    void *user;
} sinew_allocator;

/* Builds a model from a blob written by sinew_model_write_blob() (or the import child):
 * the bytes of a .sinew file.
 * The bytes are validated (magic, version, sizes, checksum, every offset and index) and
 * copied; `name` is used in messages. `allocator` may be NULL for malloc/free. */
sinew_result sinew_model_from_blob(const void *bytes, size_t size, const char *name, const sinew_allocator *allocator,
                                   sinew_model **out, sinew_error *error);

/* Reads a .sinew file (sinew_model_save() writes one) and validates it like
 * sinew_model_from_blob(): every prefix, changed byte or foreign file is refused with
 * SINEW_ERROR_FORMAT naming the path; SINEW_ERROR_IO when it cannot be read. With a NULL
 * allocator the model keeps the bytes it read (not copied); a file of 1 MiB or more is read
 * into 2 MB pages (transparent huge pages, where the kernel has them): loading touches a page
 * fault each 2 MB instead of each 4 KiB, for at most 2 MB more memory than the file. With an
 * allocator every byte the model keeps is the allocator's. */
sinew_result sinew_model_load(const char *path, const sinew_allocator *allocator, sinew_model **out,
                              sinew_error *error);

/* The model's own blob: the exact bytes it was loaded from. */
void sinew_model_blob(const sinew_model *model, const void **bytes, size_t *size);

void sinew_model_free(sinew_model *model);

/* Index of the first node/clip with this name, or -1. */
int32_t sinew_model_find_node(const sinew_model *model, const char *name);
int32_t sinew_model_find_clip(const sinew_model *model, const char *name);

/* The clip a user means by `text`: the first clip of that name, else the clip whose index
 * it is written as (decimal), or -1. */
int32_t sinew_model_pick_clip(const sinew_model *model, const char *text);

/* The node a user means by a joint name: the first joint of that name, else the first node
 * of that name (files may name a mesh node like a bone, as robot.glb does), or -1. */
int32_t sinew_model_find_joint(const sinew_model *model, const char *name);

/* True when node `node` is a joint of some skin. */
bool sinew_model_node_is_joint(const sinew_model *model, uint32_t node);

#ifdef __cplusplus
}
#endif
#endif
