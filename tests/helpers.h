/* Shared test helpers: where the test data lives, loading models, comparing floats. */
#ifndef SINEW_TEST_HELPERS_H
#define SINEW_TEST_HELPERS_H

#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "sinew/sinew.h"

/* $SINEW_TESTDATA/rel, or NULL (with a message) when the shared test data is absent. */
const char *testdata_path(const char *rel, char *buf, size_t size);
/* $SINEW_FIXTURES/rel (sinew's own fixtures, always present). */
const char *fixture_path(const char *rel, char *buf, size_t size);
/* A path under the build's scratch folder. */
const char *tmp_path(const char *name, char *buf, size_t size);

/* Imports in a child process, failing the test with the message on error. */
sinew_model *load_or_fail(const char *path);

/* Writes bytes to a file. */
void write_file(const char *path, const void *bytes, size_t size);
/* Reads a whole file (malloc'd); NULL when missing. */
void *read_file(const char *path, size_t *size);

/* Fails the test when |a - b| > tol, naming what. */
void assert_near(double a, double b, double tol, const char *what);

/* One component of a cubic Bezier segment through the (time, value) points p[0..3], at time
 * t, in doubles (bisection on the parameter): what sinew's Bezier keys are checked against. */
double bezier_reference(const double p[4][2], double t);

/* The local transforms (malloc'd) of a model posed by a clip at t, wrapped or clamped. */
sinew_transform *pose_locals(const sinew_model *model, const sinew_clip *clip, float t, sinew_wrap wrap);
/* Largest difference between two poses of n nodes: rotations (a quaternion and its negation
 * are the same), scales, and translations relative to their size where that is over 1 (float's
 * precision of a hips translation tens of units out is 2e-6). */
double pose_difference(const sinew_transform *a, const sinew_transform *b, uint32_t n);
/* Largest difference between two sets of n matrices, element by element. */
double worlds_difference(const sinew_mat4 *a, const sinew_mat4 *b, uint32_t n);
/* Largest difference between two arrays of n floats. */
double floats_difference(const float *a, const float *b, size_t n);
/* A skinned mesh's influences dealt out of order (malloc'd): vertex v takes those of vertex
 * v * 7919 mod n, so that no block of neighbours shares its joints. */
void influences_out_of_order(const sinew_mesh *mesh, uint16_t **joints, float **weights);
/* The demo humanoid (fails the test when it cannot be made). */
sinew_model *demo_humanoid(void);
/* World matrices of a model at time t of clip (NULL: rest), malloc'd. */
sinew_mat4 *pose_worlds(const sinew_model *model, const sinew_clip *clip, float t);

/* A player with its own layout and memory, for tests that play one clip (fails the test
 * when it cannot be made). test_player_close() frees all three. */
typedef struct test_player {
    sinew_clip_layout *layout;
    sinew_player *player;
    void *memory;
} test_player;
sinew_player *test_player_open(test_player *tp, const sinew_model *model, const sinew_clip *clip);
/* Another player of tp's layout, in memory the caller frees. */
sinew_player *test_player_another(const test_player *tp, void **memory);
void test_player_close(test_player *tp);

/* All mesh instances skinned/placed at the pose, as one malloc'd xyz array. */
float *posed_vertices(const sinew_model *model, const sinew_mat4 *worlds, uint32_t *count);
/* The same with the morph weights and vertex caches of `clip` at `time` (clamped). */
float *posed_vertices_at(const sinew_model *model, const sinew_mat4 *worlds, const sinew_clip *clip, float time,
                         uint32_t *count);

/* Comparing pictures: a pixel differs when one channel differs by more than PIXEL_TOLERANCE
 * levels; pictures match when at most IMAGE_TOLERANCE of their pixels differ. */
#define PIXEL_TOLERANCE 32
#define IMAGE_TOLERANCE 0.005

/* Differing pixels of two RGB images of `pixels` pixels; fills `diff` (RGB, may be NULL) with
 * `a` dimmed and the differing pixels red. */
/* Triangles of a mesh with tangents and UVs whose bitangent (w * normal x tangent, at the
 * first corner) points the way v grows on the triangle: the count, and in *checked those with a
 * UV gradient and a bitangent not perpendicular to it (within 1e-6). */
uint32_t bitangents_along_v(const sinew_mesh *mesh, uint32_t *checked);

long differing_pixels(const unsigned char *a, const unsigned char *b, long pixels, unsigned char *diff);

/* What a run of the sinew command gave: exit code (128 + signal when killed) and both
 * streams, NUL-terminated (malloc'd). */
typedef struct run_result {
    int code;
    char *out, *err;
    size_t out_size, err_size;
} run_result;

/* Runs $SINEW_EXE with NULL-terminated arguments; `env` (NULL or NULL-terminated
 * "NAME=value" strings) is added to the child's environment. */
run_result run_sinew(const char *const *env, const char *const *args);
void run_free(run_result *result);

#define RUN(...) run_sinew(NULL, (const char *const[]){__VA_ARGS__, NULL})
#define RUN_ENV(env, ...) run_sinew((env), (const char *const[]){__VA_ARGS__, NULL})

#endif
