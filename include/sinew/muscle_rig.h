/* sinew/muscle_rig.h — muscles attached to the joints of an animated model.
 *
 * What: binds a muscle set (sinew/muscle_file.h) to a model: each attachment's joint name
 * becomes a node (a joint wins over a mesh node of the same name), its offset is in that
 * node's space, and a muscle without "rest_length" takes the distance between its ends in
 * the model's rest pose. Each frame, sinew_muscle_rig_update() moves the ends with the world
 * matrices and re-solves every muscle at its new length (sinew/muscle.h).
 * A length outside a muscle's valid range does not fail the frame: the muscle is solved at
 * the nearest valid length and flagged (in_range false), so there is always something to draw.
 * What not: no drawing (the renderer draws sinew_muscle_pose values), no file reading.
 * Memory: create allocates the rig (it copies what it needs: the set and model may go);
 * update allocates nothing and writes the radii into the rig (valid until the next update).
 * Errors: SINEW_ERROR_DATA naming the muscle file, the muscle and the joint that the model
 * lacks, or a rest length of zero (both ends at one point).
 */
#ifndef SINEW_MUSCLE_RIG_H
#define SINEW_MUSCLE_RIG_H

#include <stdbool.h>

#include "sinew/model.h"
#include "sinew/muscle.h"
#include "sinew/muscle.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct sinew_muscle_rig sinew_muscle_rig;

typedef struct sinew_muscle_pose {
    const char *name;
    float origin[3], insertion[3]; /* world space */
    float color[3];
    uint32_t segments;
    uint32_t node_count;
    const double *radii;      /* node_count, inside the rig */
    double distance;          /* between the ends */
    sinew_muscle_state state; /* solved at `distance`, or at the valid length nearest to it */
    sinew_muscle_range range;
    bool in_range; /* false: the ends are further apart (or closer) than the muscle allows */
} sinew_muscle_pose;

/* `model` may be NULL for a set whose attachments name no joints (points in model space). */
sinew_result sinew_muscle_rig_create(const sinew_model *model, const sinew_muscle_set *set, sinew_muscle_rig **out,
                                     sinew_error *error);
void sinew_muscle_rig_free(sinew_muscle_rig *rig);
uint32_t sinew_muscle_rig_count(const sinew_muscle_rig *rig);

/* The muscles' file units shown `scale` times larger in world space (a model drawn scaled):
 * lengths are divided by it before solving; radii, lengths and volumes come out scaled
 * (volumes by scale cubed). 0 or 1: none. Meant for rest lengths given in the file: a rest
 * length taken from the rest pose is already a world length. */
void sinew_muscle_rig_set_scale(sinew_muscle_rig *rig, double scale);

/* worlds: the model's world matrices (may be NULL, with world_count 0, when no attachment
 * names a joint). Fills poses[0..count-1]. */
sinew_result sinew_muscle_rig_update(sinew_muscle_rig *rig, const sinew_mat4 *worlds, uint32_t world_count,
                                     sinew_muscle_pose *poses, uint32_t pose_count, sinew_error *error);

#ifdef __cplusplus
}
#endif
#endif
