/* FBX animation curves (fbx_curve.c): the keys of an AnimationCurve (FBX 7.x) or of a
 * take's channel (FBX 5.x and 6.x) with their tangents resolved the way Maya, 3ds Max and
 * MotionBuilder resolve them, evaluated at any time, before the first key and after the last
 * by the curve's extrapolation. No promise to library users.
 *
 * A key holds its value, how the segment after it interpolates, and the Bezier handles on
 * either side as (dx seconds, dy value) from the key, so that every tangent mode FBX stores
 * (user, auto with its clamps and bias, TCB, weighted, linear, constant) becomes one cubic
 * Bezier between two keys, the way ufbx and the FBX SDK evaluate it.
 */
#ifndef SINEW_IMPORT_FBX_CURVE_H
#define SINEW_IMPORT_FBX_CURVE_H

#include <stdbool.h>
#include <stdint.h>

#include "fbx_internal.h"

typedef enum fbx_interp {
    FBX_INTERP_CONSTANT_PREV, /* hold this key's value until the next key */
    FBX_INTERP_CONSTANT_NEXT, /* take the next key's value right after this key */
    FBX_INTERP_LINEAR,
    FBX_INTERP_CUBIC
} fbx_interp;

/* 48 bytes (56 with double heights): a baked file's curves hold tens of thousands of keys.
 * The handles' heights are floats, as the file's slopes are; their widths stay doubles, so
 * that the default third of a segment stays exact and its Bezier stays linear in time (the
 * time's parameter is then found without a Newton step). */
typedef struct fbx_key {
    double time; /* seconds */
    double value;
    double left_dx, right_dx; /* Bezier handles, relative to the key: widths (seconds) */
    float left_dy, right_dy;  /* and heights */
    uint8_t interp;           /* fbx_interp of the segment after this key */
    bool uniform;             /* a Bezier segment after this key whose time handles are at its thirds:
                                 its parameter is its time fraction (fbx_curve.c, mark_uniform) */
} fbx_key;

typedef enum fbx_extrapolation_mode {
    FBX_EXTRAPOLATE_CONSTANT,
    FBX_EXTRAPOLATE_REPEAT,          /* cycle */
    FBX_EXTRAPOLATE_REPEAT_RELATIVE, /* cycle with offset */
    FBX_EXTRAPOLATE_MIRROR,          /* oscillate */
    FBX_EXTRAPOLATE_SLOPE            /* linear, along the end key's tangent */
} fbx_extrapolation_mode;

typedef struct fbx_extrapolation {
    uint8_t mode;   /* fbx_extrapolation_mode */
    int32_t repeat; /* cycles before the value holds; -1 without end */
} fbx_extrapolation;

typedef struct fbx_curve {
    uint32_t count;
    fbx_key *keys;
    fbx_extrapolation pre, post;
    double ticks_per_second; /* the file's: extrapolated cycles are whole ticks */
    bool in_arena;           /* the keys belong to the source's arena (fbx_curve_free leaves them) */
    uint32_t hint;           /* the key after the time last looked up: a cache the evaluators write
                              * through const (a curve is one import's, read on one thread) */
} fbx_curve;

/* How a file writes its curves' attributes: which FBX version, whether binary, and how many
 * time ticks make a second. */
typedef struct fbx_curve_source {
    uint32_t version;
    bool binary;
    double ticks_per_second;
    import_arena *arena; /* where the keys are made (the document's); NULL: calloc */
} fbx_curve_source;

/* The keys of an FBX 7.x AnimationCurve node (KeyTime, KeyValueFloat, KeyAttrFlags,
 * KeyAttrDataFloat, KeyAttrRefCount, Pre-/Post-Extrapolation). NULL on success, else what
 * is wrong with it (the curve is then empty). Allocates the keys (fbx_curve_free). */
const char *fbx_curve_read(const fbx_node *node, const fbx_curve_source *src, fbx_curve *out);

/* The keys of a pre-7.0 channel node (`Key:` with `KeyCount:`, and the channel's
 * extrapolation). NULL on success (a channel without keys gives an empty curve), else what
 * is wrong. */
const char *fbx_curve_read_legacy(const fbx_node *channel, const fbx_curve_source *src, fbx_curve *out);

void fbx_curve_free(fbx_curve *c);

/* The curve's value at `t` seconds; `fallback` for a curve without keys. */
double fbx_curve_eval(const fbx_curve *c, double t, double fallback);

/* The same at the clip time `t - clip_start` as the runtime's float clip times see it: a key
 * whose clip time is the same float counts as at t, so that a step at a key stays at its key. */
double fbx_curve_eval_at(const fbx_curve *c, double t, double clip_start, double fallback);
/* Whether a key of the curve has the clip time of t as a float (as fbx_curve_eval_at matches
 * them); *key gets its time (seconds). */
bool fbx_curve_key_near(const fbx_curve *c, double t, double clip_start, double *key);

/* The curve's value (as fbx_curve_eval_at gives it; *value is left alone for a curve without
 * keys) and one-sided slopes (value per second) at t, matched to a key as fbx_curve_eval_at
 * matches it: at a key, the slope of the segment before it (*left) and after it (*right);
 * inside a segment, its slope twice. False where no exact slope is given (a Bezier handle
 * without length, extrapolation along a slope or by cycles): take differences then. */
bool fbx_curve_slopes_at(const fbx_curve *c, double t, double clip_start, double *value, double *left, double *right);

/* Whether the segment that starts at key k is a step, and when its value changes: the time
 * just before key k + 1 (constant-previous) or just after key k (constant-next). */
bool fbx_curve_step(const fbx_curve *c, uint32_t k, bool *after_key);

/* The times at which the curve's keys recur over [t0, t1] through its extrapolation (the
 * keys themselves included when inside): calls `emit` for each, at most `limit` times. */
void fbx_curve_key_times(const fbx_curve *c, double t0, double t1, uint32_t limit,
                         void (*emit)(void *context, double time, const fbx_curve *c, uint32_t key), void *context);

#endif
