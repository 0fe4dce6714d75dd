/* Comparing sinew's poses with the references of ../shared/testdata/reference. */
#ifndef SINEW_TEST_REFERENCE_H
#define SINEW_TEST_REFERENCE_H

#include <stdint.h>

#include <cjson/cJSON.h>

#include "helpers.h"

#define SAME_POSE 1e-5 /* of the diagonal: "the same pose" (reference/README.md) */

/* A gzip'd JSON file, parsed (fails the test when it cannot be read). */
cJSON *read_gzip_json(const char *path);

/* A COLLADA file's <node sid name> pairs: three.js names joints by SID, sinew by name. */
typedef struct sid_names {
    char (*sid)[128], (*name)[128];
    uint32_t count;
} sid_names;
/* The pairs of a .dae file; none for other files. */
sid_names read_sids(const char *path);
void sid_names_free(sid_names *s);

typedef struct outcome {
    double nodes, verts; /* largest, relative to the diagonal */
    uint32_t compared, missing;
} outcome;

/* The sinew name of a reference's node name (a COLLADA SID, or the name itself). */
const char *sid_to_name(const sid_names *s, const char *ref_name);

/* The model posed by its first clip at every time of the reference (sids: NULL or a
 * COLLADA file's names). */
outcome compare_with_reference(const sinew_model *m, const cJSON *ref, const sid_names *sids);

/* The largest distance from a point of either set to the nearest of the other. */
double point_set_distance(const float *ours, uint32_t n_ours, const double *ref, uint32_t n_ref);

/* The diagonal of every node position of every frame of a reference's "frames". */
double reference_diagonal(const cJSON *frames);

/* reference/SOURCE/NAME.json.gz of a model of the test data: its path with '/' as "__" and
 * without its extension (reference/README.md). */
void reference_name(const char *source, const char *model, char *out, size_t size);

#endif
