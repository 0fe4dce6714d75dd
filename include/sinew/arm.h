/* sinew/arm.h — the seed 003 arm: two rods joined at the elbow, moved by a biceps.
 *
 * What: a built-in model of two straight rods. The upper rod runs along its node's +X from
 * its free end (the "shoulder", x = 0) through the muscle's origin (x = free_to_origin) to
 * the elbow (x = free_to_origin + origin_to_elbow); the lower rod starts at the elbow and
 * runs through the insertion (elbow_to_insertion from the elbow) to its free end
 * (insertion_to_free further). The elbow angle is the angle between the rods (180 degrees:
 * straight; smaller: flexed); the muscle spans origin to insertion, so its length and the
 * angle follow each other by the law of cosines (sinew_arm_length / sinew_arm_angle in
 * sinew/muscle.h). Nodes: "arm" (the whole model: rotate, move, scale), "upper", "lower".
 * The model can carry a clip "flex" that bends the elbow from one angle to another and back.
 * The four distances come from the "arm" object of a JSON file (data/arm.muscles.json, which
 * also holds the biceps): {"arm": {"free_to_origin": .., "origin_to_elbow": ..,
 * "elbow_to_insertion": .., "insertion_to_free": .., "rod_radius": ..}}.
 * What not: no muscle solving here (sinew/muscle_rig.h binds the file's muscles to the
 * model's "upper" and "lower" nodes like any rig; desc->muscles, when given, travel with the
 * model as a .sinew file's do).
 * Memory: the model is one allocation (sinew_model_free()).
 * Errors: SINEW_ERROR_DATA / FORMAT with FILE:LINE:COLUMN for the JSON; INVALID_ARGUMENT for
 * non-positive distances or an angle outside [0, 180] degrees.
 */
#ifndef SINEW_ARM_H
#define SINEW_ARM_H

#include "sinew/model.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct sinew_arm_desc {
    double free_to_origin, origin_to_elbow, elbow_to_insertion, insertion_to_free;
    double rod_radius;  /* 0 means 4% of the upper rod */
    double elbow_angle; /* radians in [0, pi]: the rest pose */
    double flex_from;   /* a "flex" clip from this angle to flex_to and back; both 0: no clip */
    double flex_to;
    float flex_duration;                    /* seconds; 0 means 2 */
    sinew_transform place;                  /* the whole model: rotation, translation, scale (zero scale means 1) */
    const struct sinew_muscle_set *muscles; /* stored with the model as its own (model->muscles), or
                                               NULL; read the biceps with sinew_muscle_set_read() */
} sinew_arm_desc;

/* Reads the four distances (and rod_radius) from the "arm" object of a JSON file; leaves the
 * other fields of `out` as they were. */
sinew_result sinew_arm_read(const char *path, sinew_arm_desc *out, sinew_error *error);

sinew_result sinew_arm_model(const sinew_arm_desc *desc, sinew_model **out, sinew_error *error);

#ifdef __cplusplus
}
#endif
#endif
