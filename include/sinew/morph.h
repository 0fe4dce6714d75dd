/* sinew/morph.h — morph targets (blend shapes), vertex caches, and a mesh posed whole.
 *
 * What: jobs over caller-owned spans, like sinew/anim.h's.
 *   1. sinew_sample_weights():       clip + time -> every morph channel's weight (defaults where
 *                                    the clip does not animate one)
 *   2. sinew_morph_target_weights(): a mesh's channel weights -> each target's weight (FBX's
 *                                    in-between shapes share a channel)
 *   3. sinew_morph_vertices():       base shape + weighted target offsets -> positions, normals
 *                                    and tangents into caller buffers, before skinning
 *   4. sinew_cache_vertices():       a vertex cache's positions at a time of the file's timeline
 *   sinew_deform_instance() does all of it and skinning for one mesh instance: what `sinew
 *   pose --mesh`, the renderer's CPU path and the tests use.
 * What not: no allocation, no threads, no pointers kept. To use two threads, give each a part
 * of the vertex range (sinew_morph_desc.first/count).
 * Errors: each job checks its spans and returns SINEW_ERROR_INVALID_ARGUMENT with a message.
 *
 *   float weights[n];                  n = model->morph_channel_count
 *   sinew_sample_weights(model, clip, t, SINEW_WRAP_LOOP, weights, n, &e);
 *   const sinew_instance *in = &model->instances[i];
 *   const sinew_mesh *mesh = &model->meshes[in->mesh];
 *   sinew_morph_target_weights(mesh, weights + in->morph_first, mesh->morph_channel_count,
 *                              target_weights, mesh->target_count, &e);
 *   sinew_morph_vertices(&(sinew_morph_desc){.mesh = mesh, .target_weights = target_weights,
 *                        .out_positions = p, .out_normals = nrm}, &e);
 *   sinew_skin_vertices(&(sinew_skin_desc){.mesh = mesh, .positions = p, .normals = nrm, ...}, &e);
 */
#ifndef SINEW_MORPH_H
#define SINEW_MORPH_H

#include "sinew/anim.h"

#ifdef __cplusplus
extern "C" {
#endif

/* weights[c] = the weight of model channel c at `time` of `clip` (wrapped or clamped as
 * sinew_sample() does; the clip's weight tracks interpolate as the file does: step, linear,
 * cubic spline, Bezier), or the channel's default_weight where the clip has no track for it
 * (clip NULL: every default). weight_count >= model->morph_channel_count. */
sinew_result sinew_sample_weights(const sinew_model *model, const sinew_clip *clip, float time, sinew_wrap wrap,
                                  float *weights, uint32_t weight_count, sinew_error *error);

/* sinew_sample_weights() for the clip a player plays (its layout's; the defaults for the rest
 * pose): a character's morph weights beside sinew_player_update()'s matrices. */
sinew_result sinew_player_weights(const sinew_player *player, float time, sinew_wrap wrap, float *weights,
                                  uint32_t weight_count, sinew_error *error);

/* The weight of one channel at `time` of `clip` (sinew_sample_weights() for one channel). */
float sinew_clip_weight(const sinew_model *model, const sinew_clip *clip, uint32_t channel, float time,
                        sinew_wrap wrap);

/* The weight of each of the mesh's targets from the weights of its channels (channel_weights[c]
 * for the mesh's channel c: model weights from instance.morph_first on; channel_count >=
 * mesh->morph_channel_count, target_count >= mesh->target_count). A channel with one target of
 * full weight 1 gives it the channel's weight. A channel with several (FBX in-between shapes,
 * each whole at its full weight) moves linearly from shape to shape as its weight passes their
 * full weights, from the base shape at weight 0, and extrapolates the nearest two beyond the
 * first and last, as Maya and ufbx do: at 0.75 between shapes full at 0.5 and 1, each has 0.5. */
sinew_result sinew_morph_target_weights(const sinew_mesh *mesh, const float *channel_weights, uint32_t channel_count,
                                        float *target_weights, uint32_t target_count, sinew_error *error);

typedef struct sinew_morph_desc {
    const sinew_mesh *mesh;
    const float *target_weights; /* mesh->target_count weights (NULL: the base shape) */
    uint32_t first;              /* vertex range: [first, first + count) */
    uint32_t count;              /* 0 means every vertex from first on */
    float *out_positions;        /* 3 floats a vertex, indexed by vertex number (not by range) */
    float *out_normals;          /* may be NULL; 3 floats a vertex, renormalised */
    float *out_tangents;         /* may be NULL; 4 floats a vertex (xyz renormalised, handedness kept);
                                  * needs mesh->tangents */
} sinew_morph_desc;

/* out = base + sum of weight * offset over the targets whose weight is not 0; normals and
 * tangents the same with the targets' normal and tangent offsets, then renormalised (a vertex
 * no target moves keeps its own). The SIMD path (AVX2+FMA: eight consecutive vertices of a
 * target in three registers) gives the results of sinew_morph_vertices_scalar() within 1e-6
 * (it rounds each multiply-add once). Different ranges may run on different threads. */
sinew_result sinew_morph_vertices(const sinew_morph_desc *desc, sinew_error *error);
sinew_result sinew_morph_vertices_scalar(const sinew_morph_desc *desc, sinew_error *error);

/* The mesh's vertex cache at `time` seconds of the file's timeline (a clip's time plus its
 * sinew_clip.timeline): linear between the two frames around it, the first or last frame
 * outside them; 3 floats a vertex into out_positions, mesh space. SINEW_ERROR_INVALID_ARGUMENT
 * when the mesh has no cache. */
sinew_result sinew_cache_vertices(const sinew_mesh *mesh, float time, float *out_positions, sinew_error *error);

/* Area-weighted smooth normals of positions on the mesh's triangles (3 floats a vertex at
 * `stride` bytes, 0 meaning 12), into out_normals at the same stride: for shapes, such as
 * a cache's, that come without normals. */
sinew_result sinew_smooth_normals(const sinew_mesh *mesh, const float *positions, float *out_normals, size_t stride,
                                  sinew_error *error);

/* ---- one mesh instance posed whole ---- */

typedef struct sinew_deform_desc {
    const sinew_model *model;
    uint32_t instance;        /* index into model->instances */
    const sinew_mat4 *worlds; /* every node's world matrix (sinew_local_to_world(), the player) */
    uint32_t world_count;     /* >= model->node_count */
    const float *weights;     /* the model's morph channel weights (sinew_sample_weights()), or NULL
                               * for their defaults */
    uint32_t weight_count;    /* >= model->morph_channel_count when weights is given */
    float cache_time;         /* seconds on the file's timeline, for a mesh with a vertex cache */
    bool no_cache;            /* show the mesh without its vertex cache */
    bool force_method;        /* skin with `method` instead of the skin's own (sinew_skin.blend) */
    sinew_skin_method method; /* when force_method */
    void *scratch;            /* sinew_deform_scratch_size(model) bytes, 16-byte aligned */
    size_t scratch_size;
    float *out_positions; /* world space, 3 floats a vertex at out_stride */
    float *out_normals;   /* may be NULL */
    size_t out_stride;    /* bytes between vertices; 0 means 12 */
} sinew_deform_desc;

/* Bytes of scratch sinew_deform_instance() needs for any instance of the model. */
size_t sinew_deform_scratch_size(const sinew_model *model);

/* Poses one instance the way the file means it: a vertex cache, while the mesh has one, gives
 * its positions in the node's space (then the node's world matrix places them, as ufbx and
 * Maya do; normals smoothed from them); otherwise the targets at their weights, then the skin
 * with its own method (linear, dual quaternion, or the two mixed per vertex by
 * mesh->dq_weights), or the node's world matrix for a rigid mesh. */
sinew_result sinew_deform_instance(const sinew_deform_desc *desc, sinew_error *error);

#ifdef __cplusplus
}
#endif
#endif
