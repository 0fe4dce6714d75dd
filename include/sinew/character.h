/* sinew/character.h — one character's pose, composed: libsinew's front door for playing animation.
 *
 * What: the composition an engine (and sinew's own viewer and command line) runs every frame,
 * in one call. A description, made once and shared by every instance (it is only read):
 *   layers       clips blended by weight, each optionally masked to some nodes
 *                (sinew_character_subtree_mask()), or added on top (additive: each clip's
 *                motion from its first frame, times its weight);
 *   a fade       a cross-fade from one layer to another over some seconds, scheduled on the
 *                character's clock (phases kept in step for looping clips with `sync`);
 *   IK           two-bone chains whose end joints reach world targets;
 *   root motion  the horizontal motion and yaw of one layer's clip taken out, so the character
 *                stays in place (and what was taken is there to move it with);
 * and the state of one instance (its clock, each layer's time and weight, fades started at run
 * time, IK targets) in memory the caller owns, sized by sinew_character_size(), as the player's.
 * sinew_character_evaluate() then writes whichever the caller asks for: the final local pose,
 * world matrices, every skin's skinning palette, morph channel weights and the muscles.
 *
 * Clock: sinew_character_seek() puts the character at any time (scrubbing; the description's
 * weights and fade decide each layer's time and weight there). sinew_character_advance() moves
 * on by dt, and sinew_character_play() fades one layer in and the other blended layers out from
 * now, as three.js's AnimationMixer.crossFadeTo() (with sync: in step, the shared cycle's
 * length blended by weight). After a play, seek drops the fades started at run time.
 *
 * Paths: one blended layer alone, with no mask, additive layer, IK or root motion, is the
 * player (sinew_player_update()); several blended layers alone are blended on
 * structure-of-arrays poses (sinew_blend_soa(), AVX2); anything more on local transforms
 * (sinew_blend(), sinew_ik_two_bone(), sinew_root_motion_extract()). Results agree within 1e-5.
 * What not: no allocation after init, no threads (instances are independent: evaluate many
 * with sinew_jobs_run(), one instance on one thread at a time), no file reading, no drawing.
 * Memory: the description's layouts, masks and model must outlive the instances; the
 * description itself may go after init (what is needed is copied).
 * Errors: SINEW_ERROR_INVALID_ARGUMENT with a message for a bad description or span.
 *
 *   sinew_clip_layout *walk, *run;        made once: sinew_clip_layout_create()
 *   sinew_character_layer layers[2] = {{.layout = walk, .weight = 1}, {.layout = run}};
 *   sinew_character_ik foot = {.end = sinew_model_find_joint(m, "LeftFoot"), .target = {0.1f, 0, 0.2f}};
 *   sinew_character_desc d = {.model = m, .layers = layers, .layer_count = 2, .ik = &foot, .ik_count = 1};
 *   size_t size = sinew_character_size(&d);
 *   sinew_character *c;
 *   sinew_character_init(malloc(size), size, &d, &c, &e);
 *   sinew_character_play(c, 1, 0.5f, true, &e);          into the run over half a second, in step
 *   each frame:
 *     sinew_character_advance(c, dt, &e);
 *     sinew_character_set_target(c, 0, ground_hit, 1.0f);  the foot on the ground
 *     sinew_character_evaluate(c, &(sinew_character_output){.worlds = worlds, .world_count = n,
 *                                  .palettes = palettes, .palette_count = p}, &e);
 *   at the end: free the memory (nothing else to free), then the layouts.
 */
#ifndef SINEW_CHARACTER_H
#define SINEW_CHARACTER_H

#include <stdbool.h>

#include "sinew/anim.h"
#include "sinew/blend.h"
#include "sinew/muscle_rig.h"

#ifdef __cplusplus
extern "C" {
#endif

#define SINEW_CHARACTER_MAX_LAYERS 16u /* blended and additive together */
#define SINEW_CHARACTER_MAX_IK 16u

typedef struct sinew_character_layer {
    const sinew_clip_layout *layout; /* one clip of the model, laid out (sinew_clip_layout_create()) */
    float weight;                    /* at the start: >= 0 blended; any finite additive */
    const float *mask;               /* node_count weights in [0, 1], or NULL: every node */
    bool additive;                   /* added on top: the clip's motion from its first frame */
} sinew_character_layer;

/* A cross-fade scheduled on the clock: layer `from`'s weight goes from 1 to 0 and `to`'s from
 * 0 to 1 (a smoothstep) over [start, start + duration]. `from` plays at the clock's time as
 * every layer does; `to` starts at its clip's beginning at `start`, or with sync (looping clips)
 * at `from`'s phase, the two kept in step (sinew_crossfade_at()). from == to: none (a zeroed
 * fade). The other layers keep their weights. */
typedef struct sinew_character_fade {
    uint32_t from, to; /* blended layers */
    float start;       /* clock seconds */
    float duration;    /* seconds; 0: a cut at start */
    bool sync;
} sinew_character_fade;

/* A two-bone chain: `end` reaches the target, its parent bends, its grandparent turns. */
typedef struct sinew_character_ik {
    uint32_t end;    /* a node with a parent and a grandparent */
    float target[3]; /* where it should be, world space (sinew_character_set_target() moves it) */
    float weight;    /* 0..1; 0 means 1 (sinew_character_set_target() can set 0: off) */
    bool pole_given; /* false: the chain bends the way it already bends in the pose */
    float pole[3];   /* with pole_given: a point the middle joint bends towards, world space */
} sinew_character_ik;

typedef struct sinew_character_desc {
    const sinew_model *model;
    const sinew_character_layer *layers; /* 0 .. SINEW_CHARACTER_MAX_LAYERS; none: the rest pose */
    uint32_t layer_count;
    sinew_character_fade fade;
    const sinew_character_ik *ik; /* 0 .. SINEW_CHARACTER_MAX_IK chains, applied in order */
    uint32_t ik_count;
    bool root_motion;           /* take root_motion_layer's clip's root motion out */
    uint32_t root_motion_layer; /* a blended layer (0: the first) */
    bool clamp;                 /* clip times clamp to their ends; false: they loop */
    float threshold;            /* where blended weights total less, the rest pose fills; 0 means 0.1 */
} sinew_character_desc;

typedef struct sinew_character sinew_character;

/* What sinew_character_evaluate() writes; every span may be NULL but worlds. */
typedef struct sinew_character_output {
    const sinew_mat4 *root; /* places the roots (NULL: identity): a character's place in the world */
    sinew_mat4 *worlds;     /* node_count world matrices */
    uint32_t world_count;
    sinew_transform *locals; /* node_count: the composed local pose (IK and root motion included) */
    uint32_t local_count;
    sinew_mat4 *palettes; /* every skin's palette, skin after skin: sinew_character_palette_count() */
    uint32_t palette_count;
    float *weights; /* model->morph_channel_count morph weights, blended as the pose is */
    uint32_t weight_count;
    sinew_muscle_rig *muscle_rig; /* the muscles on this pose (sinew/muscle_rig.h), one rig an instance */
    sinew_muscle_pose *muscles;
    uint32_t muscle_count;
} sinew_character_output;

/* Bytes an instance needs (0 when the description is not valid: sinew_character_init() says why). */
size_t sinew_character_size(const sinew_character_desc *desc);
/* An instance in `memory`, at clock 0 (sinew_character_seek(0)). Calling it again starts over. */
sinew_result sinew_character_init(void *memory, size_t size, const sinew_character_desc *desc, sinew_character **out,
                                  sinew_error *error);

/* Puts the clock at `time` (any finite seconds): every layer at that time with the weight the
 * description (and set_weight) gives it, the scheduled fade applied; fades from play() dropped. */
sinew_result sinew_character_seek(sinew_character *character, double time, sinew_error *error);
/* Moves the clock on by dt >= 0 seconds: layer times, fades and in-step phases. */
sinew_result sinew_character_advance(sinew_character *character, float dt, sinew_error *error);
/* Fades blended layer `layer` in over `fade` seconds (0: at once) and every other blended
 * layer out. A layer with no weight starts at its beginning, or with `sync` at the phase of the
 * layer with the most weight, the two then kept in step. A fade started during another starts
 * from the weights of that moment. */
sinew_result sinew_character_play(sinew_character *character, uint32_t layer, float fade, bool sync,
                                  sinew_error *error);
/* A layer's weight from now on (blended >= 0, additive any finite), ending a fade of it. */
sinew_result sinew_character_set_weight(sinew_character *character, uint32_t layer, float weight, sinew_error *error);
/* IK chain `chain`'s target (world space) and weight (0: off .. 1). */
sinew_result sinew_character_set_target(sinew_character *character, uint32_t chain, const float target[3], float weight,
                                        sinew_error *error);
/* Clip times clamp (true) or loop from now on. */
void sinew_character_set_clamp(sinew_character *character, bool clamp);

/* Composes the pose at the clock and writes what `output` asks for. */
sinew_result sinew_character_evaluate(sinew_character *character, const sinew_character_output *output,
                                      sinew_error *error);

double sinew_character_clock(const sinew_character *character);
/* A layer's weight and time (seconds into its clip, not wrapped) now; 0 for a layer it lacks. */
float sinew_character_weight(const sinew_character *character, uint32_t layer);
float sinew_character_time(const sinew_character *character, uint32_t layer);
/* The root motion the last evaluate took out: the clip's (its node, where it starts, one cycle's
 * motion; NULL: no root motion), and in translation (x, 0, z) and yaw (radians about +Y) the
 * motion since the clip's start, in the node's parent space. translation and yaw may be NULL. */
const sinew_root_motion *sinew_character_root_motion(const sinew_character *character, float translation[3],
                                                     float *yaw);
/* The entries of every skin's palette together (the sum of the skins' joint counts). */
uint32_t sinew_character_palette_count(const sinew_model *model);
/* mask[i] = 1 for `joint` and every node below it, else 0 (count >= model->node_count): the
 * upper body of a character for a layer that should move only that. */
sinew_result sinew_character_subtree_mask(const sinew_model *model, uint32_t joint, float *mask, uint32_t count,
                                          sinew_error *error);

#ifdef __cplusplus
}
#endif
#endif
