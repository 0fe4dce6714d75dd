/* FBX animation curves (fbx_curve.h): reading keys and their tangents, evaluating them.
 *
 *   attributes ........ FBX 7.x KeyAttrFlags / KeyAttrDataFloat, run-length coded by
 *                       KeyAttrRefCount: interpolation, tangent mode, slopes, weights, TCB
 *   tangents .......... auto (time-independent or not, clamped, with bias), TCB, user,
 *                       weighted; each key's handles from its own mode and its neighbours
 *   legacy keys ....... FBX 5.x / 6.x `Key:` lists of time, value and mode letters
 *   evaluation ........ the cubic Bezier of a segment solved for its time; constant and
 *                       linear segments; extrapolation before the first and after the last key
 *
 * The rules are those of the FBX SDK as Maya, 3ds Max and MotionBuilder write curves,
 * learnt from the FBX documentation (FbxAnimCurveDef) and from how ufbx evaluates them.
 */
#include "fbx_curve.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "alloc.h" /* last: the readers' allocations are the import's (alloc.h) */

/* KeyAttrFlags bits (FbxAnimCurveDef). */
enum {
    KEY_CONSTANT = 0x2u,
    KEY_LINEAR = 0x4u,
    KEY_CUBIC = 0x8u,
    KEY_AUTO = 0x100u,          /* cubic: automatic tangent */
    KEY_CONSTANT_NEXT = 0x100u, /* constant: hold the next key's value */
    KEY_TCB = 0x200u,
    KEY_USER = 0x400u,
    KEY_BROKEN = 0x800u,
    KEY_CLAMP = 0x1000u,
    KEY_TIME_INDEPENDENT = 0x2000u,
    KEY_CLAMP_PROGRESSIVE = 0x4000u,
    KEY_WEIGHTED_RIGHT = 0x1000000u,
    KEY_WEIGHTED_NEXT_LEFT = 0x2000000u
};

#define DEFAULT_WEIGHT (1.0 / 3.0)
/* Maya's clamped tangents go flat next to a key of the same value; "the same" is exact (the
 * FBX SDK's and ufbx's default). */
#define KEY_CLAMP_THRESHOLD 0.0

/* ---- tangents --------------------------------------------------------------------------- */

/* The slope of an automatic tangent at a key between two others, with the key's bias (in
 * percent: +-100 leans fully on one side; past +-500 an absolute slope is added) and clamps. */
static double auto_slope(double tp, double t, double tn, double vp, double v, double vn, double weight_left,
                         double weight_right, double bias, uint32_t flags)
{
    if ((flags & KEY_CLAMP) && fmin(fabs(vp - v), fabs(vn - v)) <= KEY_CLAMP_THRESHOLD)
        return 0.0;
    double slope = (vn - vp) / (tn - tp);
    if (!(flags & KEY_TIME_INDEPENDENT)) {
        /* not time-independent: half the secant, half the blend of the two sides' slopes */
        double left = (v - vp) / (t - tp), right = (vn - v) / (tn - t), at = (t - tp) / (tn - tp);
        slope = slope * 0.5 + (left * (1.0 - at) + right * at) * 0.5;
        double bias_weight = fabs(bias) / 100.0;
        if (bias_weight > 0.0001) {
            double target = bias > 0.0 ? right : left, delta = target - slope;
            slope = slope * (1.0 - bias_weight) + target * bias_weight;
            double beyond = bias_weight - 5.0;
            if (beyond > 0.0) {
                double sign = fabs(delta) > 0.00001 ? delta : bias;
                slope += beyond * beyond * (sign > 0.0 ? 1.0 : -1.0) * 40.0;
            }
        }
    }
    if (flags & KEY_CLAMP_PROGRESSIVE) { /* no handle above or below the neighbours' values */
        double sign = slope >= 0.0 ? 1.0 : -1.0, magnitude = sign * slope;
        double range_left = weight_left * (t - tp), range_right = weight_right * (tn - t);
        double max_left = range_left > 0.0 ? sign * (v - vp) / range_left : 0.0;
        double max_right = range_right > 0.0 ? sign * (vn - v) / range_right : 0.0;
        if (!(max_left > 0.0))
            max_left = 0.0;
        if (!(max_right > 0.0))
            max_right = 0.0;
        slope = sign * fmin(magnitude, fmin(max_left, max_right));
    }
    return slope;
}

/* An automatic tangent at the end of a curve: the secant to its one neighbour (a, b in time
 * order), flat when clamped. */
static double auto_slope_end(double ta, double tb, double va, double vb, double bias, uint32_t flags)
{
    if (flags & KEY_CLAMP_PROGRESSIVE)
        return 0.0;
    if ((flags & KEY_CLAMP) && fabs(vb - va) <= KEY_CLAMP_THRESHOLD)
        return 0.0;
    double slope = (vb - va) / (tb - ta);
    if (!(flags & KEY_TIME_INDEPENDENT)) {
        double beyond = fabs(bias) / 100.0 - 5.0;
        if (beyond > 0.0)
            slope += beyond * beyond * (bias > 0.0 ? 1.0 : -1.0) * 40.0;
    }
    return slope;
}

/* Kochanek-Bartels: the incoming and outgoing slopes from tension, continuity and bias and the
 * secants on either side (at an end, one secant, taken whole). */
static void tcb_slopes(double tension, double continuity, double bias, double left, double right, bool edge, double *in,
                       double *out)
{
    double f = edge ? 1.0 : 0.5;
    *in = f * (1 - tension) * ((1 + bias) * (1 - continuity) * left + (1 - bias) * (1 + continuity) * right);
    *out = f * (1 - tension) * ((1 + bias) * (1 + continuity) * left + (1 - bias) * (1 - continuity) * right);
}

/* The handles of a key from its slopes and weights (fractions of the neighbouring intervals). */
static void set_handles(fbx_key *k, double prev_time, double next_time, double slope_left, double weight_left,
                        double slope_right, double weight_right)
{
    k->left_dx = k->left_dy = k->right_dx = k->right_dy = 0;
    if (k->time > prev_time) {
        k->left_dx = weight_left * (k->time - prev_time);
        k->left_dy = (float)(k->left_dx * slope_left);
    }
    if (next_time > k->time) {
        k->right_dx = weight_right * (next_time - k->time);
        k->right_dy = (float)(k->right_dx * slope_right);
    }
}

/* The Bezier time polynomial of a segment, x(s) = ((a s + b) s + c) s, from its handles' widths
 * as fractions of the span. */
static void time_cubic(double x1, double x2, double *a, double *b, double *c)
{
    *a = 3 * x1 - 3 * x2 + 1;
    *b = 3 * x2 - 6 * x1;
    *c = 3 * x1;
}

/* Marks the Bezier segments whose time is their parameter to rounding (handles at a third of
 * the span each, as every unweighted key has): x(s) = s within 1e-15 over the segment, where
 * bezier_parameter would stop at its first guess. They are most keys, and their value is then a
 * cubic in time with no solve (a solve a point was 6% of walk.fbx's `sinew info`). */
static void mark_uniform(fbx_curve *c)
{
    for (uint32_t k = 0; k < c->count; k++) {
        fbx_key *a = &c->keys[k];
        a->uniform = false;
        double span = k + 1 < c->count ? c->keys[k + 1].time - a->time : 0, ca, cb, cc;
        if (a->interp != FBX_INTERP_CUBIC || !(span > 0))
            continue;
        time_cubic(a->right_dx / span, 1.0 - c->keys[k + 1].left_dx / span, &ca, &cb, &cc);
        a->uniform = fabs(ca) + fabs(cb) + fabs(cc - 1.0) <= 1e-15;
    }
}

/* ---- FBX 7.x attributes ----------------------------------------------------------------- */

/* A KeyAttrDataFloat element as the float it stands for and as its 32 bits. Binary files
 * store floats; ASCII files from FBX 7.2 on write each float's bits as a whole number (-0 is
 * -2147483648), older ASCII files the float itself (then the array has reals in it). */
typedef struct attr_reader {
    const double *data;
    bool as_bits;
} attr_reader;

static uint32_t attr_bits(const attr_reader *r, uint32_t i)
{
    double v = r->data[i];
    if (r->as_bits)
        return fabs(v) <= 4294967295.0 ? (uint32_t)(int64_t)v : 0u;
    float f = (float)v;
    uint32_t bits;
    memcpy(&bits, &f, 4);
    return bits;
}

static double attr_float(const attr_reader *r, uint32_t i)
{
    uint32_t bits = attr_bits(r, i);
    float f;
    memcpy(&f, &bits, 4);
    return isfinite(f) ? f : 0.0;
}

static fbx_extrapolation read_extrapolation(const fbx_node *node, const char *name)
{
    fbx_extrapolation e = {FBX_EXTRAPOLATE_CONSTANT, -1};
    const fbx_node *x = fbx_child(node, name);
    const fbx_node *type = fbx_child(x, "Type");
    if (!type || type->value_count == 0)
        return e;
    const fbx_value *v = &type->values[0];
    int c = v->type == FBX_STRING ? (v->count ? (unsigned char)v->s[0] : 0) : (int)fbx_int(type, 0);
    switch (c) {
    case 'A':
        e.mode = FBX_EXTRAPOLATE_REPEAT_RELATIVE;
        break;
    case 'K':
        e.mode = FBX_EXTRAPOLATE_SLOPE;
        break;
    case 'M':
        e.mode = FBX_EXTRAPOLATE_MIRROR;
        break;
    case 'R':
        e.mode = FBX_EXTRAPOLATE_REPEAT;
        break;
    default:
        break;
    }
    const fbx_node *rep = fbx_child(x, "Repetition");
    if (rep) {
        int64_t n = fbx_int(rep, 0);
        e.repeat = n < 0 ? -1 : n > INT32_MAX ? INT32_MAX : (int32_t)n;
    }
    return e;
}

static const char *check_keys(const double *times, const double *values, uint32_t n)
{
    for (uint32_t k = 0; k < n; k++) {
        if (!isfinite(values[k]) || !isfinite(times[k]))
            return "curve has a value or key time that is not finite";
        if (k > 0 && !(times[k] >= times[k - 1]))
            return "curve's key times go backwards";
    }
    return NULL;
}

const char *fbx_curve_read(const fbx_node *node, const fbx_curve_source *src, fbx_curve *out)
{
    memset(out, 0, sizeof *out);
    out->ticks_per_second = src->ticks_per_second;
    out->pre = read_extrapolation(node, "Pre-Extrapolation");
    out->post = read_extrapolation(node, "Post-Extrapolation");
    uint32_t n = 0, n_values = 0, n_flags = 0, n_data = 0, n_refs = 0;
    const double *times = fbx_array(node, "KeyTime", &n);
    const double *values = fbx_array(node, "KeyValueFloat", &n_values);
    if (!values)
        values = fbx_array(node, "KeyValueDouble", &n_values);
    if (n_values != n)
        return "curve has another number of values than of key times";
    const char *problem = check_keys(times, values, n);
    if (problem || n == 0)
        return problem;
    const double *flags = fbx_array(node, "KeyAttrFlags", &n_flags);
    attr_reader r = {.data = fbx_array(node, "KeyAttrDataFloat", &n_data)};
    const double *refs = fbx_array(node, "KeyAttrRefCount", &n_refs);
    r.as_bits = !src->binary && !fbx_array_reals(node, "KeyAttrDataFloat");
    if (n_flags && (n_data < 4u * n_flags || n_refs < n_flags))
        return "curve's key attributes are incomplete";
    out->keys = src->arena ? import_arena_take(src->arena, n * sizeof *out->keys) : calloc(n, sizeof *out->keys);
    out->in_arena = src->arena != NULL;
    if (!out->keys)
        return "out of memory";
    out->count = n;
    double tps = src->ticks_per_second;
    for (uint32_t k = 0; k < n; k++) {
        out->keys[k].time = times[k] / tps;
        out->keys[k].value = values[k];
    }
    /* Each key's slopes and weights; the left handle of a key comes from the key before it
     * (its "next left" slope and weight) unless the key's own mode computes it. */
    double slope_left = 0, weight_left = DEFAULT_WEIGHT, prev_time = 0;
    uint32_t attr = 0, used = 0;
    for (uint32_t k = 0; k < n; k++) {
        fbx_key *key = &out->keys[k];
        double t = key->time, v = key->value;
        double next_time = k + 1 < n ? out->keys[k + 1].time : t;
        double next_value = k + 1 < n ? out->keys[k + 1].value : v;
        double prev_value = k > 0 ? out->keys[k - 1].value : v;
        while (n_flags && attr + 1 < n_flags && used >= (refs[attr] > 0 ? refs[attr] : 0)) {
            attr++;
            used = 0;
        }
        used++;
        uint32_t f = n_flags ? (fabs(flags[attr]) <= 4294967295.0 ? (uint32_t)(int64_t)flags[attr] : 0u) : KEY_LINEAR;
        double slope_right = n_flags ? attr_float(&r, 4 * attr) : 0, weight_right = DEFAULT_WEIGHT;
        double next_slope_left = n_flags ? attr_float(&r, 4 * attr + 1) : 0, next_weight_left = DEFAULT_WEIGHT;
        if (f & (KEY_WEIGHTED_RIGHT | KEY_WEIGHTED_NEXT_LEFT)) {
            /* two decimal fixed-point weights (1/10000) packed into the third float's bits */
            uint32_t packed = attr_bits(&r, 4 * attr + 2);
            if (f & KEY_WEIGHTED_RIGHT)
                weight_right = (packed & 0xffffu) * 0.0001;
            if (f & KEY_WEIGHTED_NEXT_LEFT)
                next_weight_left = (packed >> 16) * 0.0001;
        }
        if (f & KEY_CONSTANT) {
            key->interp = (f & KEY_CONSTANT_NEXT) ? FBX_INTERP_CONSTANT_NEXT : FBX_INTERP_CONSTANT_PREV;
            weight_right = next_weight_left = DEFAULT_WEIGHT;
            slope_right = next_slope_left = 0;
        } else if (f & KEY_CUBIC) {
            key->interp = FBX_INTERP_CUBIC;
            bool has_prev = k > 0 && t > prev_time, has_next = k + 1 < n && next_time > t;
            if (f & KEY_TCB) {
                double left = has_prev ? (v - prev_value) / (t - prev_time) : 0;
                double right = has_next ? (next_value - v) / (next_time - t) : 0;
                tcb_slopes(attr_float(&r, 4 * attr), attr_float(&r, 4 * attr + 1), attr_float(&r, 4 * attr + 2), left,
                           right, !has_prev || !has_next, &slope_left, &slope_right);
                next_slope_left = 0;
                next_weight_left = DEFAULT_WEIGHT;
            } else if (!(f & KEY_USER)) {
                /* automatic: the stored "slopes" are the left and right auto bias */
                double bias_right = slope_right, bias_left = -slope_left;
                if (has_prev && has_next) {
                    if (fabs(slope_left + slope_right) <= 0.0001)
                        bias_left = bias_right;
                    slope_left = auto_slope(prev_time, t, next_time, prev_value, v, next_value, weight_left,
                                            weight_right, bias_left, f);
                    slope_right = bias_right == bias_left
                                      ? slope_left /* the same slope: most keys have no bias */
                                      : auto_slope(prev_time, t, next_time, prev_value, v, next_value, weight_left,
                                                   weight_right, bias_right, f);
                } else if (has_prev) {
                    slope_left = slope_right = auto_slope_end(prev_time, t, prev_value, v, bias_left, f);
                } else if (has_next) {
                    slope_left = slope_right = auto_slope_end(t, next_time, v, next_value, bias_right, f);
                } else {
                    slope_left = slope_right = 0;
                }
            }
        } else { /* linear, or a mode FBX does not define: a straight line to the next key */
            key->interp = FBX_INTERP_LINEAR;
            weight_right = next_weight_left = DEFAULT_WEIGHT;
            slope_right = next_slope_left = next_time > t ? (next_value - v) / (next_time - t) : 0;
        }
        set_handles(key, prev_time, next_time, slope_left, weight_left, slope_right, weight_right);
        slope_left = next_slope_left;
        weight_left = next_weight_left;
        prev_time = t;
    }
    mark_uniform(out);
    return NULL;
}

/* ---- FBX 5.x and 6.x keys ----------------------------------------------------------------- */

/* Element i of a `Key:` list: a number, or a letter as its character code (ASCII writes the
 * letters as words, binary as 'C' values). */
static bool legacy_item(const fbx_node *keys, uint32_t i, double *out)
{
    if (keys->value_count == 1 && keys->values[0].type == FBX_ARRAY) {
        if (i >= keys->values[0].count)
            return false;
        *out = keys->values[0].a[i];
        return true;
    }
    if (i >= keys->value_count)
        return false;
    const fbx_value *v = &keys->values[i];
    *out = v->type == FBX_STRING ? (v->count ? (unsigned char)v->s[0] : 0) : v->d;
    return v->type != FBX_ARRAY;
}

static int legacy_char(const fbx_node *keys, uint32_t *at, bool *ok)
{
    double v = 0;
    *ok = *ok && legacy_item(keys, (*at)++, &v);
    return v >= 0 && v <= 127 ? (int)v : 0;
}

static double legacy_number(const fbx_node *keys, uint32_t *at, bool *ok)
{
    double v = 0;
    *ok = *ok && legacy_item(keys, (*at)++, &v);
    *ok = *ok && isfinite(v);
    return v;
}

const char *fbx_curve_read_legacy(const fbx_node *channel, const fbx_curve_source *src, fbx_curve *out)
{
    memset(out, 0, sizeof *out);
    out->ticks_per_second = src->ticks_per_second;
    out->pre = read_extrapolation(channel, "Pre-Extrapolation");
    out->post = read_extrapolation(channel, "Post-Extrapolation");
    const fbx_node *keys = fbx_child(channel, "Key");
    int64_t count = fbx_int(fbx_child(channel, "KeyCount"), 0);
    if (!keys || count <= 0)
        return NULL;
    uint32_t items =
        keys->value_count == 1 && keys->values[0].type == FBX_ARRAY ? keys->values[0].count : keys->value_count;
    if (count > items / 3 + 1)
        return "channel's KeyCount is larger than its keys";
    uint32_t n = (uint32_t)count;
    out->keys = src->arena ? import_arena_take(src->arena, n * sizeof *out->keys) : calloc(n, sizeof *out->keys);
    out->in_arena = src->arena != NULL;
    if (!out->keys)
        return "out of memory";
    out->count = n;
    /* First pass: times, values and modes; the slopes need the next key's time and value. */
    double *slope_r = calloc(n, sizeof *slope_r), *slope_nl = calloc(n, sizeof *slope_nl);
    double *weight_r = malloc(n * sizeof *weight_r), *weight_nl = malloc(n * sizeof *weight_nl);
    bool *automatic = calloc(n, sizeof *automatic);
    const char *problem = NULL;
    bool ok = slope_r && slope_nl && weight_r && weight_nl && automatic;
    if (!ok)
        problem = "out of memory";
    uint32_t at = 0;
    for (uint32_t k = 0; ok && k < n; k++) {
        fbx_key *key = &out->keys[k];
        key->time = legacy_number(keys, &at, &ok) / src->ticks_per_second;
        key->value = legacy_number(keys, &at, &ok);
        weight_r[k] = weight_nl[k] = DEFAULT_WEIGHT;
        int mode = legacy_char(keys, &at, &ok);
        if (!ok)
            break;
        if (mode == 'U') {
            key->interp = FBX_INTERP_CUBIC;
            int slope_mode = legacy_char(keys, &at, &ok);
            int weight_modes = 1;
            if (slope_mode == 's' || slope_mode == 'b') { /* explicit right and next-left slopes */
                slope_r[k] = legacy_number(keys, &at, &ok);
                slope_nl[k] = legacy_number(keys, &at, &ok);
            } else if (slope_mode == 'a') { /* automatic (baked animation) */
                automatic[k] = true;
                if (src->version == 5000)
                    weight_modes = 0;
            } else if (slope_mode == 'p') { /* two values of unknown meaning, two weight modes */
                at += 2;
                weight_modes = 2;
            } else if (slope_mode == 't') { /* three values of unknown meaning, no weights */
                at += 3;
                weight_modes = 0;
            } else if (ok) {
                problem = "channel has a key of an unknown slope mode";
                ok = false;
            }
            for (; ok && weight_modes > 0; weight_modes--) {
                int w = legacy_char(keys, &at, &ok);
                if (w == 'a') {
                    weight_r[k] = legacy_number(keys, &at, &ok);
                    weight_nl[k] = legacy_number(keys, &at, &ok);
                } else if (w == 'l') {
                    weight_nl[k] = legacy_number(keys, &at, &ok);
                } else if (w == 'r') {
                    weight_r[k] = legacy_number(keys, &at, &ok);
                } else if (w != 'n' && w != 'c' && ok) {
                    problem = "channel has a key of an unknown weight mode";
                    ok = false;
                }
            }
        } else if (mode == 'L') {
            key->interp = FBX_INTERP_LINEAR;
        } else if (mode == 'C') {
            key->interp = legacy_char(keys, &at, &ok) == 'n' ? FBX_INTERP_CONSTANT_NEXT : FBX_INTERP_CONSTANT_PREV;
        } else if (ok) {
            problem = "channel has a key of an unknown interpolation";
            ok = false;
        }
        if (ok && k > 0 && !(key->time >= out->keys[k - 1].time)) {
            problem = "channel's key times go backwards";
            ok = false;
        }
    }
    if (ok && at != items) {
        problem = "channel's keys do not fill its Key list";
        ok = false;
    }
    if (!ok && !problem)
        problem = "channel's Key list is cut short or has a value of the wrong kind";
    /* Second pass: the handles. */
    double slope_left = 0, weight_left = DEFAULT_WEIGHT, prev_time = 0;
    for (uint32_t k = 0; ok && k < n; k++) {
        fbx_key *key = &out->keys[k];
        double next_time = k + 1 < n ? out->keys[k + 1].time : key->time;
        double next_value = k + 1 < n ? out->keys[k + 1].value : key->value;
        double slope_right = slope_r[k], next_slope_left = slope_nl[k];
        if (automatic[k]) {
            if (k > 0 && k + 1 < n && key->time > prev_time && next_time > key->time)
                slope_left = slope_right =
                    auto_slope(prev_time, key->time, next_time, out->keys[k - 1].value, key->value, next_value,
                               weight_left, weight_r[k], 0, KEY_CLAMP_PROGRESSIVE | KEY_TIME_INDEPENDENT);
            else
                slope_left = slope_right = 0;
        }
        if (key->interp == FBX_INTERP_LINEAR)
            slope_right = next_slope_left =
                next_time > key->time ? (next_value - key->value) / (next_time - key->time) : 0;
        if (key->interp != FBX_INTERP_CUBIC)
            weight_r[k] = weight_nl[k] = DEFAULT_WEIGHT;
        set_handles(key, prev_time, next_time, slope_left, weight_left, slope_right, weight_r[k]);
        slope_left = next_slope_left;
        weight_left = weight_nl[k];
        prev_time = key->time;
    }
    free(slope_r);
    free(slope_nl);
    free(weight_r);
    free(weight_nl);
    free(automatic);
    if (!ok)
        fbx_curve_free(out);
    else
        mark_uniform(out);
    return problem;
}

void fbx_curve_free(fbx_curve *c)
{
    if (!c->in_arena)
        free(c->keys);
    c->keys = NULL;
    c->count = 0;
}

/* ---- evaluation --------------------------------------------------------------------------- */

/* The parameter s of a cubic Bezier in time with handles at x1 and x2 (fractions of the
 * segment) where its time is x: Newton's method kept inside a shrinking bracket. */
static double bezier_parameter(double x, double x1, double x2)
{
    double a, b, c;
    time_cubic(x1, x2, &a, &b, &c);
    double lo = 0, hi = 1, s = x;
    for (int i = 0; i < 50; i++) {
        double f = ((a * s + b) * s + c) * s - x;
        if (fabs(f) <= 1e-15)
            break;
        if (f > 0)
            hi = s;
        else
            lo = s;
        double d = (3 * a * s + 2 * b) * s + c;
        double next = d != 0 ? s - f / d : (lo + hi) / 2;
        s = next > lo && next < hi ? next : (lo + hi) / 2;
    }
    return s;
}

/* The first key after t (count when none). Bakers ask for times close to the last one (a key,
 * points just around it, points inside the interval before or after it), so the last answer
 * and the keys on either side of it are tried before a binary search. */
static uint32_t key_after(const fbx_curve *c, double t)
{
    const fbx_key *keys = c->keys;
    uint32_t n = c->count, h = c->hint;
    if (h < n && (h == 0 || keys[h - 1].time <= t) && t < keys[h].time)
        return h;
    if (h < n && keys[h].time <= t && (h + 1 == n || t < keys[h + 1].time))
        return ((fbx_curve *)c)->hint = h + 1;
    if (h >= 1 && h <= n && (h == 1 || keys[h - 2].time <= t) && t < keys[h - 1].time)
        return ((fbx_curve *)c)->hint = h - 1;
    uint32_t lo = 0, hi = n;
    while (lo < hi) {
        uint32_t mid = lo + (hi - lo) / 2;
        if (keys[mid].time <= t)
            lo = mid + 1;
        else
            hi = mid;
    }
    return ((fbx_curve *)c)->hint = lo;
}

/* The value of the Bezier segment a..b at its parameter s. */
__attribute__((always_inline)) static inline double bezier_value(const fbx_key *a, const fbx_key *b, double s)
{
    double u = 1 - s, y1 = a->value + a->right_dy, y2 = b->value - b->left_dy;
    return u * u * u * a->value + 3 * (u * u * s * y1 + u * s * s * y2) + s * s * s * b->value;
}

/* The key whose clip time is the float clip time of t (fbx_curve_key_near's match), or count
 * when none; *after gets key_after(t). One look-up serves the match and the segment. */
__attribute__((always_inline)) static inline uint32_t key_matched(const fbx_curve *c, double t, double clip_start,
                                                                  uint32_t *after)
{
    const fbx_key *keys = c->keys;
    uint32_t n = c->count, lo = key_after(c, t);
    float ft = (float)(t - clip_start);
    *after = lo;
    if (lo < n && (float)(keys[lo].time - clip_start) == ft)
        return lo;
    if (lo > 0 && (float)(keys[lo - 1].time - clip_start) == ft)
        return lo - 1;
    return n;
}

/* The segment a..b (a->time <= t < b->time) at t. */
static double segment_value(const fbx_key *a, const fbx_key *b, double t)
{
    if (a->time == t)
        return a->value;
    double span = b->time - a->time, x = (t - a->time) / span;
    switch (a->interp) {
    case FBX_INTERP_CONSTANT_PREV:
        return a->value;
    case FBX_INTERP_CONSTANT_NEXT:
        return b->value;
    case FBX_INTERP_LINEAR:
        return a->value * (1.0 - x) + b->value * x;
    default:
        return bezier_value(a, b, a->uniform ? x : bezier_parameter(x, a->right_dx / span, 1.0 - b->left_dx / span));
    }
}

/* The curve between its first and last key. */
static double eval_inside(const fbx_curve *c, double t)
{
    const fbx_key *keys = c->keys;
    uint32_t lo = key_after(c, t);
    if (lo == 0)
        return keys[0].value;
    if (lo == c->count)
        return keys[c->count - 1].value;
    return segment_value(&keys[lo - 1], &keys[lo], t);
}

/* Before the first key or after the last: held, along the end key's tangent, or the keys
 * cycled (plain, offset by the change over a cycle, or mirrored every other cycle) for the
 * extrapolation's number of cycles, then held. Cycles are counted in whole ticks. */
static double extrapolate(const fbx_curve *c, double t, double tps)
{
    bool pre = t < c->keys[0].time;
    const fbx_key *end = pre ? &c->keys[0] : &c->keys[c->count - 1];
    fbx_extrapolation e = pre ? c->pre : c->post;
    if (e.mode == FBX_EXTRAPOLATE_CONSTANT || e.repeat == 0)
        return end->value;
    if (e.mode == FBX_EXTRAPOLATE_SLOPE) {
        double dx = pre ? end->right_dx : end->left_dx, dy = pre ? end->right_dy : end->left_dy;
        return dx > 0 ? end->value + dy * ((t - end->time) / dx) : end->value;
    }
    double first = rint(c->keys[0].time * tps), last = rint(c->keys[c->count - 1].time * tps);
    double ticks = t * tps, duration = last - first;
    if (!(duration >= 1.0))
        return end->value;
    double delta = pre ? first - ticks : ticks - last;
    double cycle = floor(delta / duration), into = delta - cycle * duration;
    if (e.repeat > 0 && cycle >= e.repeat) {
        cycle = e.repeat - 1;
        into = duration;
    }
    if (e.mode == FBX_EXTRAPOLATE_MIRROR && cycle * 0.5 - floor(cycle * 0.5) <= 0.25)
        into = duration - into;
    if (pre)
        into = duration - into;
    double value = eval_inside(c, (first + into) / tps);
    if (e.mode == FBX_EXTRAPOLATE_REPEAT_RELATIVE) {
        double change = c->keys[c->count - 1].value - c->keys[0].value;
        value += (pre ? -change : change) * (cycle + 1.0);
    }
    return value;
}

double fbx_curve_eval(const fbx_curve *c, double t, double fallback)
{
    if (c->count == 0)
        return fallback;
    if (c->count == 1)
        return c->keys[0].value;
    if (t < c->keys[0].time || t > c->keys[c->count - 1].time)
        return extrapolate(c, t, c->ticks_per_second > 0 ? c->ticks_per_second : 46186158000.0);
    return eval_inside(c, t);
}

bool fbx_curve_key_near(const fbx_curve *c, double t, double clip_start, double *key)
{
    if (c->count == 0)
        return false;
    uint32_t lo, k = key_matched(c, t, clip_start, &lo);
    if (k == c->count)
        return false;
    *key = c->keys[k].time;
    return true;
}

double fbx_curve_eval_at(const fbx_curve *c, double t, double clip_start, double fallback)
{
    if (c->count < 2)
        return c->count ? c->keys[0].value : fallback;
    /* fbx_curve_key_near and fbx_curve_eval with one look-up: a key the float clip time
     * matches gives its value; the times between the ends fall in the segment found. */
    const fbx_key *keys = c->keys;
    uint32_t n = c->count, lo, k = key_matched(c, t, clip_start, &lo);
    if (k < n)
        return keys[k].value;
    if (!(t >= keys[0].time && t <= keys[n - 1].time)) /* NaN too */
        return fbx_curve_eval(c, t, fallback);
    return segment_value(&keys[lo - 1], &keys[lo], t);
}

/* The value and slope (per second) of the segment a..b at x (a fraction of it, 0..1), as
 * eval_inside gives the value; false where its time handle has no length there (the slope
 * is then a limit sinew does not take). */
static bool segment_slope(const fbx_key *a, const fbx_key *b, double x, double *value, double *slope)
{
    double span = b->time - a->time;
    switch (a->interp) {
    case FBX_INTERP_CONSTANT_PREV:
    case FBX_INTERP_CONSTANT_NEXT:
        *value = a->interp == FBX_INTERP_CONSTANT_PREV || x <= 0 ? a->value : b->value;
        *slope = 0;
        return true;
    case FBX_INTERP_LINEAR:
        *value = a->value * (1.0 - x) + b->value * x;
        *slope = (b->value - a->value) / span;
        return true;
    default: {
        double x1 = a->right_dx / span, x2 = 1.0 - b->left_dx / span;
        double s = x <= 0 ? 0 : x >= 1 ? 1 : a->uniform ? x : bezier_parameter(x, x1, x2), u = 1 - s;
        double y1 = a->value + a->right_dy, y2 = b->value - b->left_dy;
        *value = bezier_value(a, b, s);
        /* d/ds of the Bezier's time (as a fraction of the span) and value */
        double dx = 3 * u * u * x1 + 6 * u * s * (x2 - x1) + 3 * s * s * (1 - x2);
        double dy = 3 * u * u * (y1 - a->value) + 6 * u * s * (y2 - y1) + 3 * s * s * (b->value - y2);
        if (!(dx > 1e-9))
            return false;
        *slope = dy / (dx * span);
        return true;
    }
    }
}

/* The slope (per second) of the segment a..b at b (at_b) or at a, as segment_slope gives it there:
 * a Bezier's handle's own height over its width (the bakers ask at every key; the Bezier at
 * its end parameter is that ratio, without the curve's value and the sums that round). Held and
 * straight segments as segment_slope takes them. */
static bool end_of_segment_slope(const fbx_key *a, const fbx_key *b, bool at_b, double *slope)
{
    if (a->interp != FBX_INTERP_CUBIC) {
        double ignored;
        return segment_slope(a, b, at_b ? 1.0 : 0.0, &ignored, slope);
    }
    double width = at_b ? b->left_dx : a->right_dx, height = at_b ? b->left_dy : a->right_dy;
    if (!(3 * width / (b->time - a->time) > 1e-9)) /* segment_slope's limit, in the same units */
        return false;
    *slope = height / width;
    return true;
}

/* The slope beyond an end key: zero where the curve holds its end value. */
static bool end_slope(const fbx_curve *c, bool pre, double *slope)
{
    fbx_extrapolation e = pre ? c->pre : c->post;
    *slope = 0;
    return e.mode == FBX_EXTRAPOLATE_CONSTANT || e.repeat == 0;
}

bool fbx_curve_slopes_at(const fbx_curve *c, double t, double clip_start, double *value, double *left, double *right)
{
    *left = *right = 0;
    if (c->count == 0)
        return true;
    const fbx_key *keys = c->keys;
    uint32_t n = c->count;
    *value = keys[0].value;
    if (n == 1)
        return true;
    uint32_t lo, k = key_matched(c, t, clip_start, &lo); /* as fbx_curve_eval_at matches */
    if (k == n && !(t >= keys[0].time && t <= keys[n - 1].time)) {
        *value = fbx_curve_eval(c, t, *value);
        return end_slope(c, t < keys[0].time, left) && end_slope(c, t < keys[0].time, right);
    }
    if (k < n) { /* at key k: each side's segment */
        *value = keys[k].value;
        bool ok_left = k == 0 ? end_slope(c, true, left) : end_of_segment_slope(&keys[k - 1], &keys[k], true, left);
        bool ok_right =
            k + 1 == n ? end_slope(c, false, right) : end_of_segment_slope(&keys[k], &keys[k + 1], false, right);
        return ok_left && ok_right;
    }
    const fbx_key *a = &keys[lo - 1], *b = &keys[lo];
    if (!segment_slope(a, b, (t - a->time) / (b->time - a->time), value, left))
        return false;
    *right = *left;
    return true;
}

bool fbx_curve_step(const fbx_curve *c, uint32_t k, bool *after_key)
{
    if (k + 1 >= c->count)
        return false;
    *after_key = c->keys[k].interp == FBX_INTERP_CONSTANT_NEXT;
    return c->keys[k].interp == FBX_INTERP_CONSTANT_PREV || c->keys[k].interp == FBX_INTERP_CONSTANT_NEXT;
}

void fbx_curve_key_times(const fbx_curve *c, double t0, double t1, uint32_t limit,
                         void (*emit)(void *context, double time, const fbx_curve *c, uint32_t key), void *context)
{
    if (c->count == 0)
        return;
    uint32_t sent = 0;
    for (uint32_t k = 0; k < c->count && sent < limit; k++)
        if (c->keys[k].time >= t0 && c->keys[k].time <= t1) {
            emit(context, c->keys[k].time, c, k);
            sent++;
        }
    double first = c->keys[0].time, last = c->keys[c->count - 1].time, span = last - first;
    if (!(span > 0))
        return;
    for (int side = 0; side < 2; side++) {
        fbx_extrapolation e = side ? c->post : c->pre;
        if (e.mode == FBX_EXTRAPOLATE_CONSTANT || e.mode == FBX_EXTRAPOLATE_SLOPE || e.repeat == 0)
            continue;
        double room = side ? t1 - last : first - t0;
        if (!(room > 0))
            continue;
        double cycles = ceil(room / span);
        if (e.repeat > 0 && cycles > e.repeat)
            cycles = e.repeat;
        for (double n = 0; n < cycles && sent < limit; n++) {
            bool mirrored = e.mode == FBX_EXTRAPOLATE_MIRROR && fmod(n, 2.0) == 0.0;
            for (uint32_t k = 0; k < c->count && sent < limit; k++) {
                double into = c->keys[k].time - first; /* within a cycle */
                if (mirrored)
                    into = span - into;
                double t = side ? last + n * span + into : first - (n + 1) * span + into;
                if (t >= t0 && t <= t1) {
                    emit(context, t, c, k);
                    sent++;
                }
            }
        }
    }
}
