/* sinew/blend.h — combining poses: blending, additive layers, cross-fades, inverse
 * kinematics and root motion.
 *
 * The composition of all of these for one character, every frame, is sinew/character.h:
 * start there; these are its parts, for engines that compose their own.
 * What: jobs over local poses (model->node_count sinew_transform, as sinew_sample() and
 * sinew_player_sample() write them), in the style of ozz-animation's BlendingJob and IK jobs:
 *   sinew_blend()          N poses with weights and optional per-node masks -> one pose;
 *                          rotations as normalised quaternion sums in one hemisphere, the
 *                          rest pose filling weight below a threshold; additive layers after.
 *   sinew_pose_slerp()     the exact path for two poses (slerp of rotations).
 *   sinew_additive_delta() a pose minus its reference pose: what an additive layer adds.
 *   sinew_blend_soa()      the same on structure-of-arrays poses (the player's), 8 nodes at a
 *                          time with AVX2+FMA, with sinew_blend_soa_scalar() beside it.
 *   sinew_crossfade_at()   a cross-fade from clip A to clip B over T seconds: each clip's time
 *                          (with phase sync by normalised time) and B's weight.
 *   sinew_ik_two_bone()    a chain of start, middle and end joint reaching a target, bending
 *                          towards a pole; corrects the start and middle local rotations.
 *   sinew_ik_aim()         one joint turned so a local axis points at a target (look-at).
 *   sinew_root_motion_*()  the root's horizontal translation and yaw taken out of a pose
 *                          (the character walks in place) and returned.
 * What not: no allocation, no threads, no state kept between calls; IK reads world matrices
 * the caller computed (sinew_local_to_world()) for the pose it corrects, and the caller
 * computes them again after.
 * Errors: SINEW_ERROR_INVALID_ARGUMENT with a message for spans too short, bad node
 * indices, negative or non-finite weights.
 * Conventions: sinew/model.h; rotations x y z w; world-space targets in the model's space.
 *
 *   sinew_transform walk[n], run[n], out[n];
 *   sinew_player_sample(walk_player, t_walk, SINEW_WRAP_LOOP, walk, n, &e);
 *   sinew_player_sample(run_player, t_run, SINEW_WRAP_LOOP, run, n, &e);
 *   sinew_blend_layer layers[2] = {{walk, 1 - w}, {run, w}};
 *   sinew_blend(&(sinew_blend_desc){.model = m, .layers = layers, .layer_count = 2, .out = out, .out_count = n}, &e);
 *   sinew_local_to_world(m, out, n, NULL, worlds, n, &e);
 */
#ifndef SINEW_BLEND_H
#define SINEW_BLEND_H

#include <stdbool.h>

#include "sinew/anim.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct sinew_blend_layer {
    const sinew_transform *locals; /* node_count local transforms */
    float weight;                  /* >= 0 */
    const float *node_weights;     /* node_count weights in [0, 1] (a mask), or NULL: every node 1 */
} sinew_blend_layer;

typedef struct sinew_blend_desc {
    const sinew_model *model;
    const sinew_blend_layer *layers; /* blended: weighted sums, rotations in one hemisphere */
    uint32_t layer_count;
    /* additive layers, applied after the blend in order: each layer's locals are deltas from
     * sinew_additive_delta(), added with its weight w (times its mask): translation + w dt,
     * scale * (1 + w (ds - 1)), rotation * nlerp(identity, dq, w) (as ozz-animation: exact at
     * w = 0, 1/2 and 1, within 0.3 degrees between for deltas up to 60 degrees, 0.9 up to 90) */
    const sinew_blend_layer *additive;
    uint32_t additive_count;
    /* where a node's total weight is below this, the rest pose fills the difference (so a
     * node no layer covers stays at rest); 0 means 0.1 */
    float threshold;
    sinew_transform *out; /* may be one of the layers' locals */
    uint32_t out_count;
} sinew_blend_desc;

sinew_result sinew_blend(const sinew_blend_desc *desc, sinew_error *error);

/* ---- the same blend on structure-of-arrays poses (sinew/anim.h), 8 nodes at a time ----
 *
 * sinew_blend()'s rules on sinew_soa_pose: what sinew_player_advance() gives, with no
 * conversion. Layer rotations are normalised before they are summed (the player's need
 * not be unit). AVX2+FMA where the processor has them; sinew_blend_soa_scalar() is the
 * reference the SIMD path is tested against (within 1e-6), and both against sinew_blend(). */
#define SINEW_BLEND_SOA_MAX_LAYERS 16u

typedef struct sinew_blend_soa_layer {
    const sinew_soa_pose *pose; /* the model's node_count */
    float weight;               /* >= 0 */
    const float *node_weights;  /* node_count weights in [0, 1] (a mask), or NULL: every node 1 */
} sinew_blend_soa_layer;

typedef struct sinew_blend_soa_desc {
    const sinew_model *model;
    /* the model's rest pose as a structure of arrays (sinew_soa_pose_from_locals() of
     * model->node_rest, made once), or NULL: read from the model at every call (slower) */
    const sinew_soa_pose *rest;
    const sinew_blend_soa_layer *layers; /* at most SINEW_BLEND_SOA_MAX_LAYERS */
    uint32_t layer_count;
    const sinew_blend_soa_layer *additive; /* deltas (sinew_additive_delta()), at most SINEW_BLEND_SOA_MAX_LAYERS */
    uint32_t additive_count;
    float threshold;     /* as sinew_blend_desc's; 0 means 0.1 */
    sinew_soa_pose *out; /* may be one of the layers' poses */
} sinew_blend_soa_desc;

sinew_result sinew_blend_soa(const sinew_blend_soa_desc *desc, sinew_error *error);
sinew_result sinew_blend_soa_scalar(const sinew_blend_soa_desc *desc, sinew_error *error);

/* ---- morph weights, blended as poses are ----
 *
 * The morph channel weights of several poses (sinew_player_weights(), sinew/morph.h) combined
 * with the weights their poses blend with: out = sum w_i l_i / sum w_i, the channels' default
 * weights filling a total below the threshold (as the rest pose fills sinew_blend()'s), then
 * each additive layer's deltas (a clip's weights minus its reference's) times its weight. */
typedef struct sinew_weight_layer {
    const float *weights; /* model->morph_channel_count channel weights (additive: deltas) */
    float weight;         /* >= 0 (additive: any finite) */
} sinew_weight_layer;

typedef struct sinew_blend_weights_desc {
    const sinew_model *model;
    const sinew_weight_layer *layers;
    uint32_t layer_count;
    const sinew_weight_layer *additive;
    uint32_t additive_count;
    float threshold; /* 0 means 0.1, as sinew_blend_desc's */
    float *out;      /* may be one of the layers' weights */
    uint32_t out_count;
} sinew_blend_weights_desc;

sinew_result sinew_blend_weights(const sinew_blend_weights_desc *desc, sinew_error *error);

/* out = a where t = 0, b where t = 1: translations and scales lerped, rotations slerped (the
 * shorter way). out may be a or b. */
sinew_result sinew_pose_slerp(const sinew_transform *a, const sinew_transform *b, float t, sinew_transform *out,
                              uint32_t count, sinew_error *error);

/* delta such that reference + delta = pose: translation pose - reference, rotation
 * conj(reference) * pose, scale pose / reference (0 where reference's is 0). */
sinew_result sinew_additive_delta(const sinew_transform *reference, const sinew_transform *pose, sinew_transform *delta,
                                  uint32_t count, sinew_error *error);

/* A cross-fade from one clip to another, on a clock the caller keeps (seconds). */
typedef struct sinew_crossfade {
    const sinew_clip *from, *to;
    float from_time; /* from's time when the fade starts */
    float to_time;   /* to's time when the fade starts (ignored with sync) */
    float start;     /* clock time of the fade's start */
    float duration;  /* seconds; 0: a cut */
    bool sync;       /* to plays at from's phase (normalised time), both looping: locomotion */
} sinew_crossfade;

/* At clock time `clock`: from's and to's times (not wrapped: give them to the player with
 * SINEW_WRAP_LOOP) and to's weight, 0 before the start, smoothstep to 1 over the duration.
 * With sync, to's speed follows from's cycle towards its own as the fade goes (the phases
 * stay equal), as engines blend locomotion cycles of different lengths. */
void sinew_crossfade_at(const sinew_crossfade *fade, float clock, float *from_time, float *to_time, float *to_weight);

typedef struct sinew_ik_two_bone_desc {
    const sinew_model *model;
    const sinew_mat4 *worlds; /* node_count world matrices of `locals` */
    sinew_transform *locals;  /* in/out: the start and middle joints' rotations are corrected */
    uint32_t node_count;
    uint32_t start, middle, end; /* nodes: middle below start, end below middle (any joints between) */
    float target[3];             /* where the end joint should be, world space */
    float pole[3];               /* a point the chain bends towards, world space */
    float weight;                /* 0: no change .. 1: reach */
    float soften;                /* 0 or 1: none; in (0, 1): the stretch where reaching starts to ease out */
    bool *reached;               /* may be NULL: whether the end reaches the target (within 1e-4 of it) */
} sinew_ik_two_bone_desc;

sinew_result sinew_ik_two_bone(const sinew_ik_two_bone_desc *desc, sinew_error *error);

typedef struct sinew_ik_aim_desc {
    const sinew_model *model;
    const sinew_mat4 *worlds; /* node_count world matrices of `locals` */
    sinew_transform *locals;  /* in/out: the joint's rotation is corrected */
    uint32_t node_count;
    uint32_t joint;
    float forward[3];     /* the joint's axis to point at the target, in its own space (e.g. 0,0,1) */
    float up[3];          /* the joint's axis to keep towards pole_vector, in its own space */
    float target[3];      /* world space */
    float pole_vector[3]; /* world-space direction `up` leans towards (0,0,0: no twist control) */
    float weight;         /* 0..1 */
} sinew_ik_aim_desc;

sinew_result sinew_ik_aim(const sinew_ik_aim_desc *desc, sinew_error *error);

/* Root motion of one clip: the root node's horizontal translation and yaw, relative to the
 * clip's first frame. */
typedef struct sinew_root_motion {
    uint32_t node;   /* the node whose motion is taken (a root of the skeleton, e.g. the hips) */
    float start[3];  /* its local translation at the clip's start */
    float start_yaw; /* its yaw (about +Y, radians) at the clip's start */
    float cycle[3];  /* translation over one whole clip (x, 0, z) */
    float cycle_yaw; /* yaw over one whole clip */
} sinew_root_motion;

/* Finds the node (node < 0: the topmost node the clip translates, a skin's joint when there
 * is one) and the clip's start and end. */
sinew_result sinew_root_motion_init(const sinew_model *model, const sinew_clip *clip, int32_t node,
                                    sinew_root_motion *out, sinew_error *error);

/* Takes the motion out of a pose of that clip: the node's x, z go back to the start and its
 * yaw back to the start's, so the character stays in place; *translation (x, 0, z) and
 * *yaw get what was taken: the motion since the clip's start, in the node's parent space. */
void sinew_root_motion_extract(const sinew_root_motion *motion, sinew_transform *locals, float translation[3],
                               float *yaw);

#ifdef __cplusplus
}
#endif
#endif
