/* sinew/arrays.h — a clip as arrays: many times posed in one call.
 *
 * What: sinew_clip_arrays() plays a clip at each of `time_count` times and writes what the
 * caller asks for into flat arrays, frame after frame: every node's local translation,
 * rotation (x, y, z, w) and scale, its world matrix, the morph channel weights, and every
 * instance's vertices (and normals) deformed as the file means them (sinew_deform_instance():
 * morph targets, vertex caches, each skin's method), in world space, instances in the model's
 * order. It is the player (sinew_player_update(), sinew_player_sample()) that `sinew pose`
 * runs, so the arrays equal what `sinew pose --json` prints. For analysis and training data:
 * the Python binding and `sinew batch` fill numpy arrays through it.
 * What not: no blending, IK or retargeting (sinew/blend.h; sinew_retarget() makes a model
 * whose clips carry another's motion). Local rotations are as sampled: consecutive frames may
 * flip sign (q and -q are the same turn).
 * Memory: the caller owns every array; scratch (a player, one frame of worlds, the deformer's
 * scratch) goes through desc->allocator and is freed before returning.
 * Errors: SINEW_ERROR_INVALID_ARGUMENT (no model, a clip not the model's, times without a
 * count, a time that is not finite), SINEW_ERROR_OUT_OF_MEMORY; the deformer's errors.
 * Threads: reads the model only; calls on different arrays may run at once.
 */
#ifndef SINEW_ARRAYS_H
#define SINEW_ARRAYS_H

#include "sinew/anim.h"
#include "sinew/model.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct sinew_clip_arrays_desc {
    const sinew_model *model;
    const sinew_clip *clip; /* one of model->clips, or NULL: the rest pose at every time */
    const float *times;     /* time_count seconds on the clip's time (wrapped or clamped by `wrap`) */
    uint32_t time_count;
    sinew_wrap wrap;
    const sinew_allocator *allocator; /* the scratch; NULL: malloc/free */
    /* Outputs: each NULL, or time_count frames of */
    float *translations; /* node_count * 3 floats: local translations */
    float *rotations;    /* node_count * 4: local rotations, x y z w, unit length */
    float *scales;       /* node_count * 3: local scales */
    float *worlds;       /* node_count * 16: world matrices, column-major (sinew_mat4) */
    float *weights;      /* morph_channel_count: each channel's weight */
    float *vertices;     /* sinew_model_vertex_total() * 3: deformed positions, world space */
    float *normals;      /* the same for normals (zero for a mesh without them) */
} sinew_clip_arrays_desc;

/* Vertices of every instance together: the length of a frame of sinew_clip_arrays_desc.vertices
 * over 3. Saturates at UINT32_MAX. */
uint32_t sinew_model_vertex_total(const sinew_model *model);

sinew_result sinew_clip_arrays(const sinew_clip_arrays_desc *desc, sinew_error *error);

#ifdef __cplusplus
}
#endif
#endif
