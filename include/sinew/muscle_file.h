/* sinew/muscle_file.h — muscle definitions read from JSON.
 *
 * What: a muscle file names muscles and says where they attach:
 *   {"muscles": [{"name": "biceps",
 *                 "origin":    {"joint": "UpperArm.L", "offset": [0, 0.02, 0.03]},
 *                 "insertion": {"joint": "LowerArm.L", "offset": [0, 0.05, 0.02]},
 *                 "rest_length": 0.31,                  (optional: else the rest pose's distance)
 *                 "radii": [0.008, 0.02, 0.03, 0.02, 0.008],
 *                 "coefficients": [0, 0.5, 1, 0.5, 0],
 *                 "segments": 16,                       (optional, 3..256, default 16)
 *                 "color": "#b03a2e"}]}                 (optional: "#rrggbb" or [r, g, b] in 0..1)
 * Offsets are in the joint's space (the joint's world matrix moves them). Joints are named
 * as in the model; a file that is not bound to a model (the arm) may leave "joint" out and
 * give points in the model's space as offsets. Found beside a model as NAME.muscles.json
 * (walker.dae -> walker.muscles.json), or given explicitly.
 * What not: no binding to a model here (sinew/muscle_rig.h does that). The set's types
 * (sinew_muscle_set, sinew_muscle_def) are the runtime's, in sinew/muscle.h: an engine that
 * gets its muscles from a .sinew file needs neither this reader nor its JSON library.
 * Memory: the set is one allocation; free it with sinew_muscle_set_free().
 * Errors: SINEW_ERROR_IO for an unreadable file; SINEW_ERROR_FORMAT for malformed JSON and
 * SINEW_ERROR_DATA for a wrong field, each with "FILE:LINE:COLUMN: field: what is wrong".
 */
#ifndef SINEW_MUSCLE_FILE_H
#define SINEW_MUSCLE_FILE_H

#include <stddef.h>
#include <stdint.h>

#include "sinew/muscle.h"

#ifdef __cplusplus
extern "C" {
#endif

sinew_result sinew_muscle_set_read(const char *path, sinew_muscle_set **out, sinew_error *error);
/* The same from text in memory; `name` is used in messages. */
sinew_result sinew_muscle_set_parse(const char *text, size_t size, const char *name, sinew_muscle_set **out,
                                    sinew_error *error);
/* The muscle file that goes with a model file: "dir/walker.dae" -> "dir/walker.muscles.json". */
void sinew_muscle_path_for(const char *model_path, char *out, size_t size);

#ifdef __cplusplus
}
#endif
#endif
