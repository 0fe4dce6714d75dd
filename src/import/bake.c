/* Clips baked from an exact evaluation: the keys of a node's track as cubic Hermite keys
 * (value and one-sided derivatives at each key time), intervals halved where the runtime's
 * Hermite curve misses the exact transform by more than the tolerances at 1/4, 1/2, 3/4.
 * Used where a file's curves are not the runtime's (FBX Euler curves with Bezier weights,
 * COLLADA transform stacks with Bezier or Hermite samplers).
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "internal.h"
#include "sinew/anim.h"
#include "alloc.h" /* last: the readers' allocations are the import's (alloc.h) */

#define BAKE_MAX_DEPTH 10

/* A baked key: time, value and one-sided derivatives (per second) of the ten numbers of a
 * local transform: translation 0..2, rotation 3..6 (x, y, z, w), scale 7..9. */
typedef struct bake_key {
    float time;
    double value[10], in[10], out[10];
} bake_key;

typedef struct bake {
    const bake_desc *d;
    uint32_t count, capacity;
    bake_key *keys;
    double chord; /* the distance of two unit quaternions tol_r apart */
    bool failed;
} bake;

/* Ten numbers whose rotation (3..6) is put on the side of `near`'s (NULL: left as it is). */
static void rotation_beside(double ten[10], const double *near)
{
    double d = near ? ten[3] * near[3] + ten[4] * near[4] + ten[5] * near[5] + ten[6] * near[6] : 1.0;
    for (int c = 3; c < 7 && d < 0; c++)
        ten[c] = -ten[c];
}

void bake_trs_ten(const bake_trs *l, const double *near, double out[10])
{
    for (int c = 0; c < 3; c++) {
        out[c] = l->t[c];
        out[7 + c] = l->s[c];
    }
    for (int c = 0; c < 4; c++)
        out[3 + c] = l->q[c];
    rotation_beside(out, near);
}

/* The local transform at clip time `t` as ten numbers, its rotation on the side of `near`'s. */
static void bake_eval(const bake *b, double t, const double *near, double out[10])
{
    bake_trs l;
    b->d->eval(b->d->context, t, &l);
    bake_trs_ten(&l, near, out);
}

/* A key at `t`: its value (rotation on the side of `near`) and its derivatives from each side
 * (second-order one-sided differences over `h` seconds, inside the neighbouring intervals),
 * taken around the file's own key time where the reader knows it: `t` is a float clip time,
 * up to half a float step away, and differences around it mixed the key's exact value with
 * points beside it (in and out then differed by 0.1% at smooth keys of walk.fbx, and the
 * halving added a third more keys to make up for it). One-sided even where in and out agree:
 * keyed curves are C1 at their keys but their second derivative jumps there, which a central
 * difference carries as an error of h * (jump) / 4 (tried: 70% more keys). */
static void bake_key_at(const bake *b, double t, double h, const double *near, const double *known, bake_key *k)
{
    double f1[10], f2[10], g1[10], g2[10];
    k->time = (float)t;
    double at = b->d->key_time ? b->d->key_time(b->d->context, t) : t;
    if (!known && b->d->key && b->d->key(b->d->context, at, near, k->value, k->in, k->out))
        return;
    if (known) /* the value at t, evaluated already (rotation on near's side) */
        memcpy(k->value, known, sizeof k->value);
    else
        bake_eval(b, t, near, k->value);
    t = at;
    if (b->d->derivatives && b->d->derivatives(b->d->context, t, k->value, k->in, k->out))
        return;
    bake_eval(b, t - h, k->value, f1);
    bake_eval(b, t - 2 * h, k->value, f2);
    bake_eval(b, t + h, k->value, g1);
    bake_eval(b, t + 2 * h, k->value, g2);
    for (int c = 0; c < 10; c++) {
        k->in[c] = (3 * k->value[c] - 4 * f1[c] + f2[c]) / (2 * h);
        k->out[c] = (-3 * k->value[c] + 4 * g1[c] - g2[c]) / (2 * h);
    }
}

static void bake_push(bake *b, const bake_key *k)
{
    if (b->failed)
        return;
    if (b->count == b->capacity) {
        uint32_t cap = b->capacity ? b->capacity * 2 : 16;
        bake_key *keys = realloc(b->keys, cap * sizeof *keys);
        if (!keys) {
            b->failed = true;
            return;
        }
        b->keys = keys;
        b->capacity = cap;
    }
    b->keys[b->count++] = *k;
}

/* The runtime's cubic Hermite between two keys at u (rotation normalised, as sinew_sample). */
static void hermite10(const bake_key *a, const bake_key *c, double u, double out[10])
{
    double dt = (double)c->time - a->time, u2 = u * u, u3 = u2 * u;
    double h00 = 2 * u3 - 3 * u2 + 1, h10 = u3 - 2 * u2 + u, h01 = -2 * u3 + 3 * u2, h11 = u3 - u2;
    for (int i = 0; i < 10; i++)
        out[i] = h00 * a->value[i] + h10 * dt * a->out[i] + h01 * c->value[i] + h11 * dt * c->in[i];
    double n = sqrt(out[3] * out[3] + out[4] * out[4] + out[5] * out[5] + out[6] * out[6]);
    for (int i = 3; i < 7 && n > 0; i++)
        out[i] /= n;
}

/* got - exact, the rotation compared on got's side (q and -q are one rotation). */
static void difference(const double got[10], const double exact[10], double out[10])
{
    double d = got[3] * exact[3] + got[4] * exact[4] + got[5] * exact[5] + got[6] * exact[6];
    for (int c = 0; c < 10; c++)
        out[c] = got[c] - (c >= 3 && c < 7 && d < 0 ? -exact[c] : exact[c]);
}

/* Whether a difference from the exact transform is within `share` of the tolerances. The
 * rotations' angle apart is 4 asin(|got - exact| / 2): their distance is held to `chord` (an
 * acos of their dot product loses half its digits there). */
static bool small(const bake *b, const double off[10], const double exact[10], double share)
{
    double chord = off[3] * off[3] + off[4] * off[4] + off[5] * off[5] + off[6] * off[6];
    if (chord > share * share * b->chord * b->chord)
        return false;
    for (int k = 0; k < 3; k++)
        if (fabs(off[k]) > share * b->d->tol_t ||
            fabs(off[7 + k]) > share * b->d->tol_s * fmax(1.0, fabs(exact[7 + k])))
            return false;
    return true;
}

/* The float clip time halfway between x and y (rounded). */
static float midpoint(double x, double y)
{
    return (float)(x + (y - x) / 2);
}

/* Adds keys after a up to and including c (a is already there): halves the interval where
 * the Hermite curve of the two keys strays from the exact transform at its quarters or its
 * middle. The quarters are the middles of the halves, as float times, so that a halved
 * interval's three exact points are the new key's value and its halves' middles (`known_mid`:
 * the exact transform at the middle, rotation on a's side, or NULL): a halving evaluates three
 * points where it used to evaluate six.
 *
 * The Hermite curve meets the exact transform in value and slope at both keys, so the two
 * differ by u^2 (1 - u)^2 times a factor that changes slowly across a short interval: the
 * difference at the middle, where it is largest, follows from the quarters' (a symmetric S
 * has opposite ones, a bow equal ones, 9/16 of the middle's). Where that prediction is within
 * half the tolerances, an interval whose middle is not known yet is taken without evaluating
 * it: a third fewer evaluations on the intervals between a file's keys that need no halving.
 * Checked against the middle itself over the shared FBX and COLLADA files: 4,995 middles
 * predicted, none of them outside the tolerances, the largest at 0.54 of them (walk.fbx,
 * whose evaluations fell by 17%). */
static void bake_interval(bake *b, const bake_key *a, const bake_key *c, int depth, const double *known_mid)
{
    double ta = a->time, tc = c->time;
    float mid = midpoint(ta, tc);
    if (!(depth<BAKE_MAX_DEPTH && * b->d->budget> 0 && mid > ta && mid < tc)) {
        bake_push(b, c);
        return;
    }
    double at[3] = {midpoint(ta, mid), mid, midpoint(mid, tc)}, exact[3][10], off[3][10], u[3];
    bool fine = true;
    for (int k = 0; k < 3; k++) {
        u[k] = (at[k] - ta) / (tc - ta);
        if (k == 1)
            continue;
        double got[10];
        bake_eval(b, at[k], a->value, exact[k]);
        hermite10(a, c, u[k], got);
        difference(got, exact[k], off[k]);
        fine = fine && small(b, off[k], exact[k], 1.0);
    }
    if (fine && !known_mid) {
        double middle[10], w0 = u[0] * u[0] * (1 - u[0]) * (1 - u[0]), w2 = u[2] * u[2] * (1 - u[2]) * (1 - u[2]);
        for (int i = 0; i < 10; i++)
            middle[i] = (off[0][i] / w0 + off[2][i] / w2) / 2 / 16;
        if (small(b, middle, exact[0], 0.5)) {
            bake_push(b, c);
            return;
        }
    }
    if (known_mid)
        memcpy(exact[1], known_mid, sizeof exact[1]);
    else
        bake_eval(b, at[1], a->value, exact[1]);
    if (fine) {
        double got[10];
        hermite10(a, c, u[1], got);
        difference(got, exact[1], off[1]);
        if (small(b, off[1], exact[1], 1.0)) {
            bake_push(b, c);
            return;
        }
    }
    (*b->d->budget)--;
    bake_key m;
    bake_key_at(b, mid, fmin(1e-4, (tc - ta) / 8), a->value, exact[1], &m);
    bake_interval(b, a, &m, depth + 1, exact[0]);
    rotation_beside(exact[2], m.value); /* on m's side, as bake_eval would put it */
    bake_interval(b, &m, c, depth + 1, exact[2]);
}

/* True when a channel's keys all hold the rest value and do not move. */
static bool channel_at_rest(const bake *b, int first, int width, const float *rest)
{
    bool negated = true, same = true;
    for (uint32_t k = 0; k < b->count; k++)
        for (int c = 0; c < width; c++) {
            double v = b->keys[k].value[first + c], tol = 1e-7 * fmax(1.0, fabs(rest[c]));
            same &= fabs(v - rest[c]) <= tol;
            negated &= width == 4 && fabs(v + rest[c]) <= tol;
            same &= fabs(b->keys[k].in[first + c]) <= 1e-6 && fabs(b->keys[k].out[first + c]) <= 1e-6;
            negated &= fabs(b->keys[k].in[first + c]) <= 1e-6 && fabs(b->keys[k].out[first + c]) <= 1e-6;
        }
    return same || negated;
}

/* A baked node's keys as the three cubic channels of a raw track (a channel that holds the
 * rest value throughout is left out). */
static bool fill_track(raw_track *track, const bake *b, const sinew_transform *rest)
{
    static const int first[SINEW_CHANNEL_COUNT] = {0, 3, 7};
    for (int kind = 0; kind < SINEW_CHANNEL_COUNT; kind++) {
        int width = kind == SINEW_CHANNEL_ROTATION ? 4 : 3;
        const float *rv = kind == SINEW_CHANNEL_TRANSLATION ? rest->translation
                          : kind == SINEW_CHANNEL_ROTATION  ? rest->rotation
                                                            : rest->scale;
        if (channel_at_rest(b, first[kind], width, rv))
            continue;
        float *values = malloc((size_t)b->count * 3 * width * sizeof *values);
        float *times = malloc(b->count * sizeof *times);
        if (!values || !times) {
            free(values);
            free(times);
            return false;
        }
        for (uint32_t k = 0; k < b->count; k++) {
            const bake_key *key = &b->keys[k];
            times[k] = key->time;
            float *v = values + (size_t)k * 3 * width;
            for (int c = 0; c < width; c++) {
                v[c] = (float)key->in[first[kind] + c];
                v[width + c] = (float)key->value[first[kind] + c];
                v[2 * width + c] = (float)key->out[first[kind] + c];
            }
        }
        track->channels[kind] =
            (raw_channel){.interp = SINEW_INTERP_CUBIC, .count = b->count, .times = times, .values = values};
    }
    return true;
}

bool bake_track(const bake_desc *d, const float *times, uint32_t n, const sinew_transform *rest, raw_track *track)
{
    bake b = {.d = d, .chord = 2 * sin(d->tol_r / 4)};
    bake_key prev, next;
    for (uint32_t k = 0; k < n && !b.failed; k++) {
        if (import_late()) { /* past the import's deadline: stop as for a failed allocation */
            b.failed = true;
            break;
        }
        /* Derivatives from inside the neighbouring intervals: a step between two keys a
         * float apart has none to speak of, and a key's own step is kept out of them. */
        double gap = fmin(k > 0 ? times[k] - times[k - 1] : INFINITY, k + 1 < n ? times[k + 1] - times[k] : INFINITY);
        double h = fmin(1e-4, (isfinite(gap) ? gap : 1.0) / 8);
        bake_key_at(&b, times[k], h > 0 ? h : 1e-7, k ? prev.value : NULL, NULL, &next);
        if (k == 0)
            bake_push(&b, &next);
        else
            bake_interval(&b, &prev, &next, 0, NULL);
        prev = next;
    }
    bool ok = !b.failed && fill_track(track, &b, rest);
    free(b.keys);
    return ok;
}

bool raw_model_rest_diagonal(const raw_model *m, double *diagonal)
{
    uint32_t n = m->node_count;
    *diagonal = 1.0;
    if (n == 0)
        return true;
    sinew_transform *locals = malloc(n * sizeof *locals);
    sinew_mat4 *w = malloc(n * sizeof *w);
    if (!locals || !w) {
        free(locals);
        free(w);
        return false;
    }
    memcpy(locals, m->node_rest, n * sizeof *locals);
    locals[0] = (sinew_transform){{0, 0, 0}, {0, 0, 0, 1}, {1, 1, 1}};
    const sinew_model view = {
        .node_count = n, .node_parents = m->node_parents, .node_rest = m->node_rest, .node_inherit = m->node_inherit};
    sinew_local_to_world(&view, locals, n, NULL, w, n, NULL);
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (uint32_t i = 0; i < n; i++)
        for (int c = 0; c < 3; c++) {
            lo[c] = fmin(lo[c], w[i].m[12 + c]);
            hi[c] = fmax(hi[c], w[i].m[12 + c]);
        }
    double d =
        sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) + (hi[2] - lo[2]) * (hi[2] - lo[2]));
    *diagonal = isfinite(d) && d > 0 ? d : 1.0;
    free(locals);
    free(w);
    return true;
}
