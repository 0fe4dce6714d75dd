/* sinew/anim.h — runtime evaluation: sample a clip, build world matrices, skin meshes.
 *
 * What: jobs over caller-owned spans, in the style of ozz-animation's runtime jobs.
 *   1. sinew_sample():        clip + time -> local transforms of every node (rest where untracked)
 *   2. sinew_local_to_world(): local transforms -> world matrices, one pass, parents first
 *   3. sinew_skin_palette():   world matrices + skin -> skinning matrices (world * inverse bind)
 *   4. sinew_skin_vertices():  linear-blend or dual-quaternion skinning of positions, normals and
 *                              tangents into caller buffers
 * What not: no allocation, no threads, no pointers kept after a call returns. To use two
 * threads, give each a part of the vertex range (sinew_skin_desc.first/count).
 * Memory: frame-to-frame state (key cursors) lives in a sinew_sample_context the caller owns
 * and sizes with sinew_sample_context_size().
 * Errors: each job checks its spans and returns SINEW_ERROR_INVALID_ARGUMENT with a message.
 * Conventions: see sinew/model.h.
 */
#ifndef SINEW_ANIM_H
#define SINEW_ANIM_H

#include "sinew/model.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum sinew_wrap {
    SINEW_WRAP_CLAMP = 0, /* times outside [0, duration] clamp to the ends */
    SINEW_WRAP_LOOP = 1   /* times wrap around the duration */
} sinew_wrap;

/* Key cursors for one clip, so that forward playback does not search from scratch.
 * Allocate sinew_sample_context_size(clip) bytes (aligned like a pointer) and call
 * sinew_sample_context_init() on it; one context per clip being played. */
typedef struct sinew_sample_context sinew_sample_context;

size_t sinew_sample_context_size(const sinew_clip *clip);
sinew_result sinew_sample_context_init(void *memory, size_t size, const sinew_clip *clip, sinew_sample_context **out,
                                       sinew_error *error);

typedef struct sinew_sample_desc {
    const sinew_model *model;
    const sinew_clip *clip; /* NULL: every node at rest */
    float time;             /* seconds */
    sinew_wrap wrap;
    sinew_sample_context *context; /* may be NULL (each channel is then searched) */
    sinew_transform *locals;       /* out: model->node_count transforms */
    uint32_t local_count;
} sinew_sample_desc;

sinew_result sinew_sample(const sinew_sample_desc *desc, sinew_error *error);

/* Evaluates one channel at a clip-local time (already wrapped/clamped; the clip's start is
 * added here); out gets 3 or 4 floats. Exposed for tests and tools; sinew_sample() calls it for every channel. */
void sinew_channel_eval(const sinew_clip *clip, const sinew_channel *channel, int kind, float time, uint32_t *cursor,
                        float *out);

/* The clip-local time that `time` maps to under `wrap` (duration 0 gives 0). */
float sinew_clip_time(const sinew_clip *clip, float time, sinew_wrap wrap);

/* Translation * rotation * scale as a matrix. */
void sinew_transform_to_mat4(const sinew_transform *transform, sinew_mat4 *out);

/* Splits an affine matrix into translation, rotation and scale (a mirrored matrix gets a
 * negative x scale). Shear is dropped. */
void sinew_mat4_decompose(const sinew_mat4 *matrix, sinew_transform *out);

/* world[i] = world[parent[i]] * local[i]; roots get root * local[i] (root NULL: identity). */
sinew_result sinew_local_to_world(const sinew_model *model, const sinew_transform *locals, uint32_t local_count,
                                  const sinew_mat4 *root, sinew_mat4 *worlds, uint32_t world_count, sinew_error *error);

/* palette[j] = world[skin->joints[j]] * skin->inverse_bind[j]. */
sinew_result sinew_skin_palette(const sinew_skin *skin, const sinew_mat4 *worlds, uint32_t world_count,
                                sinew_mat4 *palette, uint32_t palette_count, sinew_error *error);

/* How skinning blends a vertex's joints. */
typedef enum sinew_skin_method {
    SINEW_SKIN_LINEAR = 0,          /* linear blend skinning: the weighted sum of the joints' matrices */
    SINEW_SKIN_DUAL_QUATERNION = 1, /* dual quaternions for rotation and translation (no candy wrapper), a
                                       linearly blended scale/shear matrix before them (Kavan et al. 2008) */
    SINEW_SKIN_MIXED = 2            /* per vertex, the two above mixed by mesh->dq_weights (FBX's "Blend"
                                       skinning: Maya's weight-blended DQ): needs both palettes */
} sinew_skin_method;

/* One joint for dual-quaternion skinning, made from its skinning matrix by
 * sinew_skin_dq_palette(): M = [R | t] * S with R the rotation of the polar decomposition
 * (a proper rotation: a mirror goes into S), S symmetric, in mesh space. 64 bytes, the size
 * of a sinew_mat4: the GPU path uploads it in place of the matrix. */
typedef struct sinew_dq_joint {
    float real[4];  /* the rotation R as a unit quaternion, x y z w */
    float dual[4];  /* 0.5 * t * real: the translation */
    float scale[6]; /* S: xx yy zz xy xz yz */
    float unused[2];
} sinew_dq_joint;

/* Turns skinning matrices into dual-quaternion joints (polar decomposition in double; a
 * singular matrix, such as a joint scaled to 0, keeps the rotation sinew_mat4_decompose()
 * finds). palette and out may not overlap. */
sinew_result sinew_skin_dq_palette(const sinew_mat4 *palette, uint32_t count, sinew_dq_joint *out, sinew_error *error);

typedef struct sinew_skin_desc {
    const sinew_mesh *mesh;           /* vertex data, joints and weights */
    const sinew_mat4 *palette;        /* skinning matrices of the mesh's skin (SINEW_SKIN_LINEAR) */
    uint32_t palette_count;           /* entries of palette or dq_palette */
    sinew_skin_method method;         /* 0: linear blend (sinew_skin.blend says what the file asked for) */
    const sinew_dq_joint *dq_palette; /* SINEW_SKIN_DUAL_QUATERNION, MIXED: from sinew_skin_dq_palette() */
    const float *positions;           /* NULL: mesh->positions; else 3 floats a vertex (a morphed shape) */
    const float *normals;             /* NULL: mesh->normals; else 3 floats a vertex */
    const float *tangents;            /* NULL: mesh->tangents; else 4 floats a vertex */
    uint32_t first;                   /* vertex range to skin: [first, first + count) */
    uint32_t count;                   /* 0 means every vertex from first on */
    float *out_positions;             /* indexed by vertex number (not by range), 3 floats at out_stride */
    float *out_normals;               /* may be NULL */
    float *out_tangents;              /* may be NULL; 4 floats (xyz, handedness) at out_stride; needs mesh->tangents */
    size_t out_stride;                /* bytes between vertices; 0 means 12 (16 with tangents) */
} sinew_skin_desc;

/* Linear blend: v' = sum_k w_k * palette[j_k] * v; normals through the cofactor (inverse
 * transpose up to scale) of the blended 3x3 part, renormalised, so that non-uniform scale
 * and mirrored joints keep normals pointing out; tangents through the blended 3x3 part,
 * renormalised, their handedness flipped where it mirrors. Dual quaternion: the blended
 * scale/shear S first (normals through its cofactor), then the blended, normalised dual
 * quaternion (each joint's quaternion taken in the hemisphere of the vertex's first joint).
 * Mixed: with a = mesh->dq_weights[v] (NULL: 0), (1 - a) * linear + a * dual quaternion,
 * normals and tangents renormalised (a vertex at 0 or 1 takes one path alone, SIMD included).
 * The SIMD paths (AVX-512: 16 vertices at a time in structure-of-arrays registers; AVX2+FMA:
 * 8 at a time; both every method and output) are chosen at run time and give the results of
 * sinew_skin_vertices_scalar() within 2e-6. Different ranges may be skinned on different
 * threads at once. A palette (or dq_palette) aligned to 64 bytes is read in place; the SIMD
 * paths copy one that is not, of up to 256 joints, to 16 KB of the stack first when the range is
 * at least 64 vertices and one a joint (a record that crosses a cache line costs two loads). */
sinew_result sinew_skin_vertices(const sinew_skin_desc *desc, sinew_error *error);

/* The instruction set sinew_skin_vertices() uses on this processor: "avx512", "avx2+fma" or
 * "scalar" (the player's path is AVX2+FMA or scalar). */
const char *sinew_simd_name(void);

/* A rigid mesh at a node: positions and normals transformed by one matrix. */
sinew_result sinew_transform_vertices(const sinew_mesh *mesh, const sinew_mat4 *matrix, float *out_positions,
                                      float *out_normals, size_t out_stride, sinew_error *error);

/* ---- the player: the fast path for playing clips on characters ----
 *
 * Two parts, as ozz-animation's Animation and SamplingJob::Context:
 *   sinew_clip_layout  the asset: one clip of one model laid out for playback, built once
 *                      (through an allocator), immutable after, shared by every character
 *                      and thread that plays the clip;
 *   sinew_player       one character's state (its pose and key cursors) in memory the
 *                      caller owns, sized by sinew_player_size(); a few kilobytes.
 * Each update samples the clip and writes every node's world matrix, with no allocation
 * and no search in forward play. Keys of channels that share their times are stored
 * together in time order; rotations blend component-wise and are normalised (nlerp) where
 * neighbouring keys are close (within 5e-7 rad of sinew_sample()'s slerp) and are slerped
 * where they are not; step, cubic and Bezier keys as sinew_sample() evaluates them.
 * Players of one layout may update on different threads; one player on one thread at a
 * time. AVX2+FMA where the processor has them, else scalar code that gives the same results.
 *
 *   sinew_clip_layout *layout;
 *   sinew_clip_layout_create(&(sinew_clip_layout_desc){.model = m, .clip = &m->clips[0]}, &layout, &error);
 *   size_t size = sinew_player_size(layout);
 *   for each character c: memory[c] = malloc(size); sinew_player_init(memory[c], size, layout, &player[c], &error);
 *   each frame:           sinew_player_update(player[c], time[c], SINEW_WRAP_LOOP, NULL, worlds[c], n, &error);
 *   at the end:           free(memory[c]) for each; sinew_clip_layout_free(layout);
 */
typedef struct sinew_clip_layout sinew_clip_layout;
typedef struct sinew_player sinew_player;

typedef struct sinew_clip_layout_desc {
    const sinew_model *model;         /* must outlive the layout */
    const sinew_clip *clip;           /* NULL: the rest pose; must outlive the layout */
    const sinew_allocator *allocator; /* NULL: malloc/free; the layout and its scratch */
} sinew_clip_layout_desc;

/* Lays the clip's keys out for the player. SINEW_ERROR_INVALID_ARGUMENT when the clip
 * animates a node the model does not have; SINEW_ERROR_OUT_OF_MEMORY. */
sinew_result sinew_clip_layout_create(const sinew_clip_layout_desc *desc, sinew_clip_layout **out, sinew_error *error);
void sinew_clip_layout_free(sinew_clip_layout *layout);

/* Bytes a player of `layout` needs, with room to align itself (any alignment will do). */
size_t sinew_player_size(const sinew_clip_layout *layout);
/* Makes a player in `memory` (size >= sinew_player_size(layout)), at the clip's start. The
 * layout must outlive it; there is nothing to free but the memory. Calling it again on the
 * same memory starts the character over. */
sinew_result sinew_player_init(void *memory, size_t size, const sinew_clip_layout *layout, sinew_player **out,
                               sinew_error *error);

/* Samples the clip at `time` (wrapped or clamped as sinew_clip_time() does) and writes
 * worlds[0 .. node_count): world[i] = world[parent] * local[i], roots get root * local
 * (root NULL: identity). */
sinew_result sinew_player_update(sinew_player *player, float time, sinew_wrap wrap, const sinew_mat4 *root,
                                 sinew_mat4 *worlds, uint32_t world_count, sinew_error *error);

/* Samples the clip at `time` like sinew_player_update() and writes the local transforms
 * (rotations normalised) instead of world matrices: the poses sinew/blend.h combines. */
sinew_result sinew_player_sample(sinew_player *player, float time, sinew_wrap wrap, sinew_transform *locals,
                                 uint32_t local_count, sinew_error *error);

/* ---- structure-of-arrays poses: the player's own layout, which blending works on ----
 *
 * A pose of node_count nodes as SINEW_SOA_ROWS rows of `stride` floats (stride: node_count
 * rounded up to 8), 32-byte aligned: row SINEW_SOA_TX holds every node's translation x, and
 * so on; node i's component r is data[r * stride + i]. Lanes past node_count are padding
 * (identity transforms). Rotations need not be unit (the player's are interpolated
 * component-wise); whatever reads them normalises. sinew_blend_soa() (sinew/blend.h)
 * combines such poses 8 nodes at a time.
 *
 *   sinew_soa_pose walk, run, out;   out: memory of sinew_soa_pose_size(n), sinew_soa_pose_init()
 *   sinew_player_advance(walk_player, t, SINEW_WRAP_LOOP, &walk, &e);   a view of the player's pose
 *   sinew_player_advance(run_player, t, SINEW_WRAP_LOOP, &run, &e);
 *   sinew_blend_soa(&(sinew_blend_soa_desc){.model = m, .layers = ..., .out = &out}, &e);
 *   sinew_soa_pose_worlds(m, &out, NULL, worlds, n, &e);
 */
enum {
    SINEW_SOA_TX,
    SINEW_SOA_TY,
    SINEW_SOA_TZ,
    SINEW_SOA_QX,
    SINEW_SOA_QY,
    SINEW_SOA_QZ,
    SINEW_SOA_QW,
    SINEW_SOA_SX,
    SINEW_SOA_SY,
    SINEW_SOA_SZ,
    SINEW_SOA_ROWS
};

typedef struct sinew_soa_pose {
    float *data; /* SINEW_SOA_ROWS * stride floats, 32-byte aligned */
    uint32_t node_count;
    uint32_t stride; /* node_count rounded up to 8 */
} sinew_soa_pose;

/* Bytes a pose of node_count nodes needs, with room to align itself. */
size_t sinew_soa_pose_size(uint32_t node_count);
/* A pose in `memory` (size >= sinew_soa_pose_size(node_count)), every node at identity. */
sinew_result sinew_soa_pose_init(void *memory, size_t size, uint32_t node_count, sinew_soa_pose *out,
                                 sinew_error *error);
/* pose = locals (count >= pose->node_count), and back (rotations normalised on the way out). */
sinew_result sinew_soa_pose_from_locals(const sinew_transform *locals, uint32_t count, sinew_soa_pose *pose,
                                        sinew_error *error);
sinew_result sinew_soa_pose_to_locals(const sinew_soa_pose *pose, sinew_transform *locals, uint32_t count,
                                      sinew_error *error);
/* World matrices of the pose on the model's hierarchy, as sinew_player_update() computes
 * them (the same code): world[i] = world[parent] * local[i], roots root * local (root NULL:
 * identity), inherit types honoured. AVX2+FMA where the processor has them. */
sinew_result sinew_soa_pose_worlds(const sinew_model *model, const sinew_soa_pose *pose, const sinew_mat4 *root,
                                   sinew_mat4 *worlds, uint32_t world_count, sinew_error *error);

/* Samples the clip at `time` like sinew_player_update() and stops there: *pose becomes a view
 * of the player's own pose (read-only; valid until the player's next call), for
 * sinew_blend_soa(). No copy, no conversion. */
sinew_result sinew_player_advance(sinew_player *player, float time, sinew_wrap wrap, sinew_soa_pose *pose,
                                  sinew_error *error);

/* Skins like sinew_skin_vertices() with the plain C reference code, never SIMD: what tests
 * and benchmarks compare the SIMD paths with. */
sinew_result sinew_skin_vertices_scalar(const sinew_skin_desc *desc, sinew_error *error);

#ifdef __cplusplus
}
#endif
#endif
