/* sinew/muscle.h — volume-preserving muscles (seed 003, with its formulas corrected).
 *
 * What: a muscle is n >= 2 nodes evenly spaced along a straight axis of length L, joined
 * by truncated cones; node i has a rest radius r_i and a growth coefficient m_i. At a new
 * length the radii become r_i + m_i * delta, with delta the root of
 *     A delta^2 + B delta + C = C * L0 / L
 * (A, B, C from the cone volumes, see ../shared/seeds/README.md) that keeps every radius
 * positive, so the volume pi * dx * sum (a^2 + a b + b^2) / 3 stays the rest volume.
 * Also: the valid length range, the tube surface (rings of k vertices at each node plus
 * end caps, smooth normals) into caller buffers, and the two-rod arm's law of cosines.
 * Also the muscle set (sinew_muscle_set), the runtime's description of muscles and their
 * attachments, which sinew/muscle_rig.h binds to a model.
 * What not: no allocation (sinew_muscle_set_free() releases a set the JSON reader made), no
 * files (the muscle JSON is read on the import side, sinew/muscle_file.h), no drawing.
 * Errors: SINEW_ERROR_INVALID_ARGUMENT for bad profiles (n < 2, radius <= 0, NaN) and
 * spans; SINEW_ERROR_LIMIT for a length outside the valid range (the message gives it).
 * Never a NaN.
 * Conventions: doubles for the solver (volume to 1e-9 relative); lengths in the model's
 * units; volumes in those units cubed, pi included.
 */
#ifndef SINEW_MUSCLE_H
#define SINEW_MUSCLE_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "sinew/result.h"

#ifdef __cplusplus
extern "C" {
#endif

/* A set of muscles and where they attach: read from muscle JSON (sinew/muscle_file.h) or
 * carried by a model (model->muscles, from a .sinew file). */
#define SINEW_MUSCLE_MAX_NODES 256
/* Radii, coefficients, offsets and lengths of a muscle stay within this magnitude (model units;
 * 1,000 km in metres), so that volumes (cubes) and the valid range stay finite. */
#define SINEW_MUSCLE_MAX_MAGNITUDE 1e6

typedef struct sinew_muscle_attachment {
    const char *joint; /* node name, or NULL for a point in model space */
    float offset[3];
} sinew_muscle_attachment;

typedef struct sinew_muscle_def {
    const char *name;
    sinew_muscle_attachment origin, insertion;
    double rest_length; /* 0 when the file leaves it to the rest pose */
    uint32_t node_count;
    const double *radii;
    const double *coefficients;
    uint32_t segments;
    float color[3]; /* sRGB 0..1 */
} sinew_muscle_def;

typedef struct sinew_muscle_set {
    const char *source;
    uint32_t muscle_count;
    const sinew_muscle_def *muscles;
} sinew_muscle_set;

/* Frees a set from sinew_muscle_set_read()/_parse() (one allocation); NULL is fine. Not for
 * a model's own muscles, which live inside the model. */
void sinew_muscle_set_free(sinew_muscle_set *set);

/* Index of the muscle of that name, or -1. */
int32_t sinew_muscle_set_find(const sinew_muscle_set *set, const char *name);

typedef struct sinew_muscle_profile {
    uint32_t node_count;        /* n >= 2 */
    const double *rest_radii;   /* n radii > 0 */
    const double *coefficients; /* n growth coefficients, any sign */
    double rest_length;         /* L0 > 0: origin to insertion at rest */
} sinew_muscle_profile;

/* Lengths the muscle can take with every radius positive. An end is open (not reached)
 * where a radius would become zero there; min_length 0 and max_length INFINITY mean no
 * limit on that side. With all coefficients zero only the rest length is valid. */
typedef struct sinew_muscle_range {
    double min_length, max_length;
    bool min_open, max_open;
} sinew_muscle_range;

typedef struct sinew_muscle_state {
    double length, rest_length;
    double delta;               /* the radius growth parameter */
    double volume, rest_volume; /* pi included */
} sinew_muscle_state;

/* pi * dx * sum (r_i^2 + r_i r_{i+1} + r_{i+1}^2) / 3 with dx = length / (n - 1). */
double sinew_muscle_volume(uint32_t node_count, const double *radii, double length);

sinew_result sinew_muscle_valid_range(const sinew_muscle_profile *profile, sinew_muscle_range *out, sinew_error *error);

/* Radii at `length` into radii[0..n-1] (radius_count >= n) and, when `state` is not NULL,
 * the length, delta and volumes. A length outside the range leaves radii untouched. */
sinew_result sinew_muscle_solve(const sinew_muscle_profile *profile, double length, double *radii,
                                uint32_t radius_count, sinew_muscle_state *state, sinew_error *error);

/* Sizes of the tube surface for n nodes and `segments` vertices around (>= 3): rings at
 * every node plus a cap ring and centre at each end. */
void sinew_muscle_surface_size(uint32_t node_count, uint32_t segments, uint32_t *vertex_count, uint32_t *index_count);

typedef struct sinew_muscle_surface_desc {
    uint32_t node_count;
    const double *radii;
    float origin[3], insertion[3]; /* axis ends: node 0 at origin, node n-1 at insertion */
    uint32_t segments;
    float *out_positions; /* vertex_count * 3 at out_stride */
    float *out_normals;   /* may be NULL */
    size_t out_stride;    /* bytes between vertices; 0 means 12 */
    uint32_t vertex_capacity;
    uint32_t *out_indices; /* index_count triangle indices, counter-clockwise seen from outside */
    uint32_t index_capacity;
} sinew_muscle_surface_desc;

sinew_result sinew_muscle_surface(const sinew_muscle_surface_desc *desc, sinew_error *error);

/* The two-rod arm: origin `a` from the elbow on one rod, insertion `b` from the elbow on the
 * other; the muscle spans the third side. Length for an elbow angle in [0, pi] (0 = rods
 * folded together) and the angle for a length in [|a - b|, a + b]; computed in half-angle
 * form, so both ends (0 and 180 degrees) stay exact. */
sinew_result sinew_arm_length(double a, double b, double angle, double *length, sinew_error *error);
sinew_result sinew_arm_angle(double a, double b, double length, double *angle, sinew_error *error);

#ifdef __cplusplus
}
#endif
#endif
