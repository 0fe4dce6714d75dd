/* Combining poses (sinew/blend.h): blending and additive layers, the two-pose slerp,
 * cross-fades, two-bone and aim IK, root motion.
 *
 * Index: quaternion helpers - blend - slerp and additive deltas - cross-fade - IK (two-bone,
 * aim) - root motion.
 */
#include <math.h>
#include <string.h>

#include "internal.h"
#include "sinew/blend.h"

/* ---- quaternions (x y z w) and vectors, in double where angles are taken ------------------ */

static void quat_mul(const double a[4], const double b[4], double out[4])
{
    double r[4] = {
        a[3] * b[0] + a[0] * b[3] + a[1] * b[2] - a[2] * b[1], a[3] * b[1] - a[0] * b[2] + a[1] * b[3] + a[2] * b[0],
        a[3] * b[2] + a[0] * b[1] - a[1] * b[0] + a[2] * b[3], a[3] * b[3] - a[0] * b[0] - a[1] * b[1] - a[2] * b[2]};
    memcpy(out, r, sizeof r);
}

static void quat_normalize(double q[4])
{
    double n = sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
    if (n > 0.0)
        for (int k = 0; k < 4; k++)
            q[k] /= n;
    else
        q[0] = q[1] = q[2] = 0.0, q[3] = 1.0;
}

static void quat_conj(const double q[4], double out[4])
{
    out[0] = -q[0], out[1] = -q[1], out[2] = -q[2], out[3] = q[3];
}

static void quat_rotate(const double q[4], const double v[3], double out[3])
{
    double c1[3] = {q[1] * v[2] - q[2] * v[1] + q[3] * v[0], q[2] * v[0] - q[0] * v[2] + q[3] * v[1],
                    q[0] * v[1] - q[1] * v[0] + q[3] * v[2]};
    double r[3] = {v[0] + 2.0 * (q[1] * c1[2] - q[2] * c1[1]), v[1] + 2.0 * (q[2] * c1[0] - q[0] * c1[2]),
                   v[2] + 2.0 * (q[0] * c1[1] - q[1] * c1[0])};
    memcpy(out, r, sizeof r);
}

static void quat_axis_angle(const double axis[3], double angle, double out[4])
{
    double s = sin(0.5 * angle);
    out[0] = axis[0] * s, out[1] = axis[1] * s, out[2] = axis[2] * s, out[3] = cos(0.5 * angle);
}

static double dot3(const double a[3], const double b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

static void cross3(const double a[3], const double b[3], double out[3])
{
    double r[3] = {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
    memcpy(out, r, sizeof r);
}

static double length3(const double v[3])
{
    return sqrt(dot3(v, v));
}

static bool normalize3(double v[3])
{
    double n = length3(v);
    if (!(n > 1e-12))
        return false;
    v[0] /= n, v[1] /= n, v[2] /= n;
    return true;
}

/* A unit vector perpendicular to v. */
static void any_perpendicular(const double v[3], double out[3])
{
    double a[3] = {fabs(v[0]) < 0.9 ? 1.0 : 0.0, fabs(v[0]) < 0.9 ? 0.0 : 1.0, 0.0};
    cross3(v, a, out);
    normalize3(out);
}

/* The shortest rotation taking direction a to direction b (both non-zero). */
static void quat_between(const double a_in[3], const double b_in[3], double out[4])
{
    double a[3] = {a_in[0], a_in[1], a_in[2]}, b[3] = {b_in[0], b_in[1], b_in[2]};
    if (!normalize3(a) || !normalize3(b)) {
        out[0] = out[1] = out[2] = 0.0, out[3] = 1.0;
        return;
    }
    double c = dot3(a, b);
    if (c < -1.0 + 1e-12) { /* opposite: half a turn about any perpendicular axis */
        double axis[3];
        any_perpendicular(a, axis);
        quat_axis_angle(axis, M_PI, out);
        return;
    }
    double axis[3];
    cross3(a, b, axis);
    out[0] = axis[0], out[1] = axis[1], out[2] = axis[2], out[3] = 1.0 + c;
    quat_normalize(out);
}

/* Slerp from identity to q by t (the shorter way). */
static void quat_scale_angle(const double q_in[4], double t, double out[4])
{
    double q[4] = {q_in[0], q_in[1], q_in[2], q_in[3]};
    if (q[3] < 0.0)
        for (int k = 0; k < 4; k++)
            q[k] = -q[k];
    double s = sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2]);
    double angle = 2.0 * atan2(s, q[3]);
    if (s < 1e-15) {
        out[0] = out[1] = out[2] = 0.0, out[3] = 1.0;
        return;
    }
    double axis[3] = {q[0] / s, q[1] / s, q[2] / s};
    quat_axis_angle(axis, angle * t, out);
}

/* The rotation of an affine matrix's columns (scale removed), as a unit quaternion. */
static void mat_rotation(const sinew_mat4 *m, double out[4])
{
    sinew_transform t;
    sinew_mat4_decompose(m, &t);
    for (int k = 0; k < 4; k++)
        out[k] = t.rotation[k];
    quat_normalize(out);
}

static void mat_position(const sinew_mat4 *m, double out[3])
{
    out[0] = m->m[12], out[1] = m->m[13], out[2] = m->m[14];
}

static bool finite_weight(float w)
{
    return isfinite(w) && w >= 0.0f;
}

/* ---- blend ---------------------------------------------------------------------------------- */

static sinew_result check_layers(const sinew_blend_layer *layers, uint32_t count, const char *what, sinew_error *error)
{
    if (count && !layers)
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "sinew_blend: %u %s layers and no array", count, what);
    for (uint32_t i = 0; i < count; i++) {
        if (!layers[i].locals)
            return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "sinew_blend: %s layer %u has no pose", what, i);
        if (!finite_weight(layers[i].weight))
            return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT,
                              "sinew_blend: %s layer %u's weight %g is negative or not finite", what, i,
                              (double)layers[i].weight);
    }
    return SINEW_OK;
}

static float layer_weight(const sinew_blend_layer *layer, uint32_t node)
{
    float w = layer->weight;
    if (layer->node_weights) {
        float m = layer->node_weights[node];
        w *= isfinite(m) ? fminf(fmaxf(m, 0.0f), 1.0f) : 0.0f;
    }
    return w;
}

/* Adds w * pose to the accumulator, its rotation in the hemisphere of the first one added. */
static void accumulate(double acc[10], bool *first, const sinew_transform *pose, double w)
{
    double q[4] = {pose->rotation[0], pose->rotation[1], pose->rotation[2], pose->rotation[3]};
    double sign = 1.0;
    if (!*first && acc[3] * q[0] + acc[4] * q[1] + acc[5] * q[2] + acc[6] * q[3] < 0.0)
        sign = -1.0;
    *first = false;
    for (int k = 0; k < 3; k++) {
        acc[k] += w * pose->translation[k];
        acc[7 + k] += w * pose->scale[k];
    }
    for (int k = 0; k < 4; k++)
        acc[3 + k] += sign * w * q[k];
}

sinew_result sinew_blend(const sinew_blend_desc *d, sinew_error *error)
{
    if (!d || !d->model || !d->out)
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "sinew_blend: missing model or output");
    const sinew_model *m = d->model;
    if (d->out_count < m->node_count)
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "sinew_blend: %u outputs for %u nodes", d->out_count,
                          m->node_count);
    sinew_result r = check_layers(d->layers, d->layer_count, "blend", error);
    if (r == SINEW_OK)
        r = check_layers(d->additive, d->additive_count, "additive", error);
    if (r != SINEW_OK)
        return r;
    if (!(d->threshold >= 0.0f) || !isfinite(d->threshold))
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "sinew_blend: threshold %g is not a weight",
                          (double)d->threshold);
    double threshold = d->threshold > 0.0f ? d->threshold : 0.1;
    for (uint32_t n = 0; n < m->node_count; n++) {
        double acc[10] = {0}, total = 0.0;
        bool first = true;
        for (uint32_t i = 0; i < d->layer_count; i++) {
            float w = layer_weight(&d->layers[i], n);
            if (w <= 0.0f)
                continue;
            accumulate(acc, &first, &d->layers[i].locals[n], w);
            total += w;
        }
        if (total < threshold) { /* the rest pose fills what the layers leave */
            accumulate(acc, &first, &m->node_rest[n], threshold - total);
            total = threshold;
        }
        double q[4] = {acc[3], acc[4], acc[5], acc[6]};
        quat_normalize(q);
        sinew_transform *o = &d->out[n];
        for (int k = 0; k < 3; k++) {
            o->translation[k] = (float)(acc[k] / total);
            o->scale[k] = (float)(acc[7 + k] / total);
        }
        for (int k = 0; k < 4; k++)
            o->rotation[k] = (float)q[k];
        for (uint32_t i = 0; i < d->additive_count; i++) { /* out = out + w * delta */
            double w = layer_weight(&d->additive[i], n);
            if (w <= 0.0)
                continue;
            const sinew_transform *delta = &d->additive[i].locals[n];
            double dq[4] = {delta->rotation[0], delta->rotation[1], delta->rotation[2], delta->rotation[3]};
            double base[4] = {o->rotation[0], o->rotation[1], o->rotation[2], o->rotation[3]};
            quat_normalize(dq);
            double sign = dq[3] < 0.0 ? -w : w; /* nlerp(identity, delta, w), the shorter way */
            double part[4] = {sign * dq[0], sign * dq[1], sign * dq[2], sign * dq[3] + (1.0 - w)};
            quat_normalize(part);
            quat_mul(base, part, base);
            quat_normalize(base);
            for (int k = 0; k < 3; k++) {
                o->translation[k] += (float)(w * delta->translation[k]);
                o->scale[k] *= (float)(1.0 + w * (delta->scale[k] - 1.0));
            }
            for (int k = 0; k < 4; k++)
                o->rotation[k] = (float)base[k];
        }
    }
    return SINEW_OK;
}

/* ---- slerp and additive deltas ------------------------------------------------------------- */

sinew_result sinew_pose_slerp(const sinew_transform *a, const sinew_transform *b, float t, sinew_transform *out,
                              uint32_t count, sinew_error *error)
{
    if ((count && (!a || !b || !out)) || !isfinite(t))
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "sinew_pose_slerp: missing pose or t not finite");
    for (uint32_t n = 0; n < count; n++) {
        double qa[4], qb[4];
        float fa[4], fb[4];
        for (int k = 0; k < 4; k++)
            qa[k] = a[n].rotation[k], qb[k] = b[n].rotation[k];
        quat_normalize(qa);
        quat_normalize(qb);
        for (int k = 0; k < 4; k++)
            fa[k] = (float)qa[k], fb[k] = (float)qb[k];
        sinew_transform o;
        sinew_slerp_shortest(fa, fb, t, o.rotation); /* the sampler's slerp (sample.c) */
        for (int k = 0; k < 3; k++) {
            o.translation[k] = a[n].translation[k] + t * (b[n].translation[k] - a[n].translation[k]);
            o.scale[k] = a[n].scale[k] + t * (b[n].scale[k] - a[n].scale[k]);
        }
        out[n] = o;
    }
    return SINEW_OK;
}

sinew_result sinew_additive_delta(const sinew_transform *reference, const sinew_transform *pose, sinew_transform *delta,
                                  uint32_t count, sinew_error *error)
{
    if (count && (!reference || !pose || !delta))
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "sinew_additive_delta: missing pose");
    for (uint32_t n = 0; n < count; n++) {
        double qr[4], qp[4], inv[4], q[4];
        for (int k = 0; k < 4; k++)
            qr[k] = reference[n].rotation[k], qp[k] = pose[n].rotation[k];
        quat_normalize(qr);
        quat_normalize(qp);
        quat_conj(qr, inv);
        quat_mul(inv, qp, q);
        quat_normalize(q);
        sinew_transform o;
        for (int k = 0; k < 3; k++) {
            o.translation[k] = pose[n].translation[k] - reference[n].translation[k];
            o.scale[k] = reference[n].scale[k] != 0.0f ? pose[n].scale[k] / reference[n].scale[k] : 0.0f;
        }
        for (int k = 0; k < 4; k++)
            o.rotation[k] = (float)q[k];
        delta[n] = o;
    }
    return SINEW_OK;
}

/* ---- cross-fade --------------------------------------------------------------------------- */

void sinew_crossfade_at(const sinew_crossfade *f, float clock, float *from_time, float *to_time, float *to_weight)
{
    float since = clock - f->start;
    float w = f->duration > 0.0f ? since / f->duration : (since >= 0.0f ? 1.0f : 0.0f);
    w = fminf(fmaxf(w, 0.0f), 1.0f);
    w = w * w * (3.0f - 2.0f * w); /* smoothstep */
    float from_t = f->from_time + since;
    float to_t = f->to_time + since;
    float a = f->from ? f->from->duration : 0.0f, b = f->to ? f->to->duration : 0.0f;
    if (f->sync && a > 0.0f && b > 0.0f) {
        /* one phase for both: it advances at the cycle rate blended by weight (engines'
         * locomotion sync), starting at from's phase when the fade starts */
        float phase0 = f->from_time / a;
        /* integral of the blended rate 1 / ((1 - w) a + w b) over the time so far, with w
         * taken linear in time for a closed form, and the rate of b after the fade */
        double phase = phase0;
        if (since > 0.0f) {
            double fade = fminf(since, f->duration);
            if (f->duration > 0.0f && fabs(b - a) > 1e-9) {
                double k = (b - a) / f->duration; /* cycle length grows at k a second */
                phase += log((a + k * fade) / a) / k;
            } else {
                phase += fade / a;
            }
            phase += fmax(0.0, since - f->duration) / b;
        } else {
            phase += since / a;
        }
        from_t = (float)(phase * a);
        to_t = (float)(phase * b);
    }
    *from_time = from_t;
    *to_time = to_t;
    *to_weight = since < 0.0f ? 0.0f : w;
}

/* ---- IK -------------------------------------------------------------------------------- */

/* Whether `node` lies below `above` in the hierarchy (or is it). */
static bool descends(const sinew_model *m, uint32_t node, uint32_t above)
{
    for (int32_t n = (int32_t)node; n >= 0; n = m->node_parents[n])
        if ((uint32_t)n == above)
            return true;
    return false;
}

/* Turns node's local rotation so that its world rotation becomes delta * (its world rotation),
 * where the parent's world rotation is `parent_rotation` (before any change above it). */
static void apply_world_delta(sinew_transform *local, const double parent_rotation[4], const double delta[4])
{
    double inv[4], q[4] = {local->rotation[0], local->rotation[1], local->rotation[2], local->rotation[3]}, t[4];
    quat_normalize(q);
    quat_conj(parent_rotation, inv);
    /* local' = inv(P) * D * P * local */
    quat_mul(delta, parent_rotation, t);
    quat_mul(inv, t, t);
    quat_mul(t, q, q);
    quat_normalize(q);
    for (int k = 0; k < 4; k++)
        local->rotation[k] = (float)q[k];
}

static void parent_rotation(const sinew_model *m, const sinew_mat4 *worlds, uint32_t node, double out[4])
{
    int32_t p = m->node_parents[node];
    if (p < 0) {
        out[0] = out[1] = out[2] = 0.0, out[3] = 1.0;
        return;
    }
    mat_rotation(&worlds[p], out);
}

static bool finite3(const float v[3])
{
    return isfinite(v[0]) && isfinite(v[1]) && isfinite(v[2]);
}

sinew_result sinew_ik_two_bone(const sinew_ik_two_bone_desc *d, sinew_error *error)
{
    if (d && d->reached)
        *d->reached = false;
    if (!d || !d->model || !d->worlds || !d->locals)
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "sinew_ik_two_bone: missing model, worlds or locals");
    const sinew_model *m = d->model;
    if (d->node_count < m->node_count || d->start >= m->node_count || d->middle >= m->node_count ||
        d->end >= m->node_count)
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT,
                          "sinew_ik_two_bone: a node index or count is out of range");
    if (d->middle == d->start || d->end == d->middle || !descends(m, d->middle, d->start) ||
        !descends(m, d->end, d->middle))
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT,
                          "sinew_ik_two_bone: \"%s\" -> \"%s\" -> \"%s\" is not a chain down the hierarchy",
                          m->node_names[d->start], m->node_names[d->middle], m->node_names[d->end]);
    if (!finite3(d->target) || !finite3(d->pole) || !isfinite(d->weight) || !isfinite(d->soften))
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT,
                          "sinew_ik_two_bone: a target, pole or weight is not finite");
    double weight = fmin(fmax(d->weight, 0.0), 1.0);
    if (weight <= 0.0)
        return SINEW_OK;
    double s[3], mid[3], e[3], target[3] = {d->target[0], d->target[1], d->target[2]},
                               pole[3] = {d->pole[0], d->pole[1], d->pole[2]};
    mat_position(&d->worlds[d->start], s);
    mat_position(&d->worlds[d->middle], mid);
    mat_position(&d->worlds[d->end], e);
    double sm[3], me[3], st[3];
    for (int k = 0; k < 3; k++)
        sm[k] = mid[k] - s[k], me[k] = e[k] - mid[k], st[k] = target[k] - s[k];
    double a = length3(sm), b = length3(me), reach = length3(st);
    if (!(a > 1e-9) || !(b > 1e-9) || !(reach > 1e-9))
        return SINEW_OK; /* a bone of no length, or the target on the start joint: nothing to solve */
    /* the distance to reach: within what the chain can span, eased out near full stretch */
    double longest = a + b, shortest = fabs(a - b);
    double want = reach;
    if (d->soften > 0.0f && d->soften < 1.0f) {
        double ds = d->soften * longest, da = longest - ds;
        if (want > ds)
            want = ds + da * (1.0 - exp(-(want - ds) / da));
    }
    want = fmin(fmax(want, shortest + 1e-9 * longest), longest);
    /* the bend plane's normal: the chain's own, else towards the pole */
    double n[3], ms[3] = {-sm[0], -sm[1], -sm[2]};
    cross3(sm, me, n);
    if (!normalize3(n)) {
        double sp[3] = {pole[0] - s[0], pole[1] - s[1], pole[2] - s[2]};
        cross3(sm, sp, n);
        if (!normalize3(n))
            any_perpendicular(sm, n);
    }
    /* 1. the middle joint: the interior angle the law of cosines asks for */
    double u[3] = {ms[0], ms[1], ms[2]}, v[3] = {me[0], me[1], me[2]};
    normalize3(u);
    normalize3(v);
    double now = acos(fmin(fmax(dot3(u, v), -1.0), 1.0));
    double cos_goal = (a * a + b * b - want * want) / (2.0 * a * b);
    double goal = acos(fmin(fmax(cos_goal, -1.0), 1.0));
    /* turning v about u x v by x opens the angle from u to v by x; a straight chain (no plane)
     * turns about the pole's normal n, the twist below then brings the bend to the pole */
    double un[3];
    cross3(u, v, un);
    double mid_delta[4];
    if (normalize3(un))
        quat_axis_angle(un, goal - now, mid_delta);
    else
        quat_axis_angle(n, -(goal - now), mid_delta);
    double me2[3], e2[3], se2[3];
    quat_rotate(mid_delta, me, me2);
    for (int k = 0; k < 3; k++)
        e2[k] = mid[k] + me2[k], se2[k] = e2[k] - s[k];
    /* 2. the start joint: the end towards the target */
    double aim[4];
    quat_between(se2, st, aim);
    /* 3. about the start-target axis: the middle joint towards the pole */
    double sm2[3], axis[3] = {st[0], st[1], st[2]}, twist[4] = {0, 0, 0, 1};
    quat_rotate(aim, sm, sm2);
    normalize3(axis);
    double sp[3] = {pole[0] - s[0], pole[1] - s[1], pole[2] - s[2]};
    double pm[3], pp[3];
    for (int k = 0; k < 3; k++) {
        pm[k] = sm2[k] - axis[k] * dot3(sm2, axis);
        pp[k] = sp[k] - axis[k] * dot3(sp, axis);
    }
    if (normalize3(pm) && normalize3(pp)) {
        double c[3];
        cross3(pm, pp, c);
        double angle = atan2(dot3(c, axis), dot3(pm, pp));
        quat_axis_angle(axis, angle, twist);
    }
    double start_delta[4];
    quat_mul(twist, aim, start_delta);
    quat_normalize(start_delta);
    if (weight < 1.0) {
        quat_scale_angle(start_delta, weight, start_delta);
        quat_scale_angle(mid_delta, weight, mid_delta);
    }
    /* local rotations: start's parent is unchanged; middle's parent turned with start, which
     * cancels (see apply_world_delta): middle's delta is taken in the frame before the change */
    double ps[4], pmid[4];
    parent_rotation(m, d->worlds, d->start, ps);
    parent_rotation(m, d->worlds, d->middle, pmid);
    apply_world_delta(&d->locals[d->start], ps, start_delta);
    apply_world_delta(&d->locals[d->middle], pmid, mid_delta);
    if (d->reached) {
        double end_now[3], r[3];
        quat_rotate(start_delta, se2, end_now);
        for (int k = 0; k < 3; k++)
            r[k] = s[k] + end_now[k] - target[k];
        *d->reached = weight >= 1.0 && length3(r) < 1e-4 * fmax(1.0, longest);
    }
    return SINEW_OK;
}

sinew_result sinew_ik_aim(const sinew_ik_aim_desc *d, sinew_error *error)
{
    if (!d || !d->model || !d->worlds || !d->locals)
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "sinew_ik_aim: missing model, worlds or locals");
    const sinew_model *m = d->model;
    if (d->node_count < m->node_count || d->joint >= m->node_count)
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "sinew_ik_aim: the joint or count is out of range");
    if (!finite3(d->forward) || !finite3(d->up) || !finite3(d->target) || !finite3(d->pole_vector) ||
        !isfinite(d->weight))
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "sinew_ik_aim: an axis, target or weight is not finite");
    double weight = fmin(fmax(d->weight, 0.0), 1.0);
    double fwd_local[3] = {d->forward[0], d->forward[1], d->forward[2]};
    if (weight <= 0.0 || !normalize3(fwd_local))
        return weight <= 0.0
                   ? SINEW_OK
                   : sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "sinew_ik_aim: the forward axis is zero");
    double r[4], p[3], fwd[3], to[3];
    mat_rotation(&d->worlds[d->joint], r);
    mat_position(&d->worlds[d->joint], p);
    quat_rotate(r, fwd_local, fwd);
    for (int k = 0; k < 3; k++)
        to[k] = d->target[k] - p[k];
    if (!normalize3(to))
        return SINEW_OK; /* the target is at the joint */
    double aim[4];
    quat_between(fwd, to, aim);
    double delta[4] = {aim[0], aim[1], aim[2], aim[3]};
    double up_local[3] = {d->up[0], d->up[1], d->up[2]},
           pole[3] = {d->pole_vector[0], d->pole_vector[1], d->pole_vector[2]};
    if (normalize3(up_local) && normalize3(pole)) { /* twist about the aim so up leans to the pole */
        double up[3], up2[3], a[3], b[3];
        quat_rotate(r, up_local, up);
        quat_rotate(aim, up, up2);
        for (int k = 0; k < 3; k++) {
            a[k] = up2[k] - to[k] * dot3(up2, to);
            b[k] = pole[k] - to[k] * dot3(pole, to);
        }
        if (normalize3(a) && normalize3(b)) {
            double c[3], twist[4];
            cross3(a, b, c);
            quat_axis_angle(to, atan2(dot3(c, to), dot3(a, b)), twist);
            quat_mul(twist, aim, delta);
            quat_normalize(delta);
        }
    }
    if (weight < 1.0)
        quat_scale_angle(delta, weight, delta);
    double parent[4];
    parent_rotation(m, d->worlds, d->joint, parent);
    apply_world_delta(&d->locals[d->joint], parent, delta);
    return SINEW_OK;
}

/* ---- root motion ------------------------------------------------------------------------ */

/* Yaw (about +Y) of a rotation: the heading of its +Z axis on the ground. */
static double yaw_of(const float q_in[4])
{
    double q[4] = {q_in[0], q_in[1], q_in[2], q_in[3]}, z[3] = {0, 0, 1}, f[3];
    quat_normalize(q);
    quat_rotate(q, z, f);
    return atan2(f[0], f[2]);
}

sinew_result sinew_root_motion_init(const sinew_model *m, const sinew_clip *clip, int32_t node, sinew_root_motion *out,
                                    sinew_error *error)
{
    if (!m || !clip || !out)
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "sinew_root_motion_init: missing model, clip or output");
    if (node >= (int32_t)m->node_count)
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "sinew_root_motion_init: node %d out of range", node);
    if (node < 0) { /* the topmost translated node, a joint first */
        uint32_t best_depth = UINT32_MAX;
        for (int pass = 0; pass < 2 && node < 0; pass++)
            for (uint32_t i = 0; i < clip->track_count; i++) {
                const sinew_track *t = &clip->tracks[i];
                if (t->channels[SINEW_CHANNEL_TRANSLATION].key_count < 2)
                    continue;
                if (pass == 0 && m->skin_count && !sinew_model_node_is_joint(m, t->node))
                    continue;
                uint32_t depth = 0;
                for (int32_t p = m->node_parents[t->node]; p >= 0; p = m->node_parents[p])
                    depth++;
                if (depth < best_depth)
                    best_depth = depth, node = (int32_t)t->node;
            }
        if (node < 0)
            return sinew_fail(error, SINEW_ERROR_DATA, "%s: clip \"%s\" moves no node: it has no root motion",
                              m->source, clip->name);
    }
    sinew_transform first, last;
    const uint32_t n = (uint32_t)node;
    memset(out, 0, sizeof *out);
    out->node = n;
    /* the node's local at the clip's start and end (the other nodes are not needed) */
    sinew_transform *buf[2] = {&first, &last};
    float times[2] = {0.0f, clip->duration};
    for (int k = 0; k < 2; k++) {
        *buf[k] = m->node_rest[n];
        for (uint32_t i = 0; i < clip->track_count; i++) {
            const sinew_track *t = &clip->tracks[i];
            if (t->node != n)
                continue;
            uint32_t cursor = 0;
            if (t->channels[SINEW_CHANNEL_TRANSLATION].key_count)
                sinew_channel_eval(clip, &t->channels[SINEW_CHANNEL_TRANSLATION], SINEW_CHANNEL_TRANSLATION, times[k],
                                   &cursor, buf[k]->translation);
            cursor = 0;
            if (t->channels[SINEW_CHANNEL_ROTATION].key_count)
                sinew_channel_eval(clip, &t->channels[SINEW_CHANNEL_ROTATION], SINEW_CHANNEL_ROTATION, times[k],
                                   &cursor, buf[k]->rotation);
        }
    }
    memcpy(out->start, first.translation, sizeof out->start);
    out->start_yaw = (float)yaw_of(first.rotation);
    out->cycle[0] = last.translation[0] - first.translation[0];
    out->cycle[2] = last.translation[2] - first.translation[2];
    out->cycle_yaw = (float)remainder(yaw_of(last.rotation) - out->start_yaw, 2.0 * M_PI);
    return SINEW_OK;
}

void sinew_root_motion_extract(const sinew_root_motion *rm, sinew_transform *locals, float translation[3], float *yaw)
{
    sinew_transform *t = &locals[rm->node];
    double turn = remainder(yaw_of(t->rotation) - rm->start_yaw, 2.0 * M_PI);
    translation[0] = t->translation[0] - rm->start[0];
    translation[1] = 0.0f;
    translation[2] = t->translation[2] - rm->start[2];
    *yaw = (float)turn;
    t->translation[0] = rm->start[0];
    t->translation[2] = rm->start[2];
    double back[4], q[4] = {t->rotation[0], t->rotation[1], t->rotation[2], t->rotation[3]};
    double up[3] = {0, 1, 0};
    quat_axis_angle(up, -turn, back);
    quat_mul(back, q, q);
    quat_normalize(q);
    for (int k = 0; k < 4; k++)
        t->rotation[k] = (float)q[k];
}

/* ---- morph weights ---- */

sinew_result sinew_blend_weights(const sinew_blend_weights_desc *desc, sinew_error *error)
{
    if (!desc || !desc->model || (desc->model->morph_channel_count && !desc->out))
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "sinew_blend_weights: NULL model or output");
    const sinew_model *m = desc->model;
    uint32_t n = m->morph_channel_count;
    if (desc->out_count < n)
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT,
                          "sinew_blend_weights: room for %u weights, the model has %u channels", desc->out_count, n);
    if ((desc->layer_count && !desc->layers) || (desc->additive_count && !desc->additive))
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "sinew_blend_weights: NULL layers");
    float total = 0.0f;
    for (uint32_t i = 0; i < desc->layer_count; i++) {
        float w = desc->layers[i].weight;
        if (!(w >= 0.0f) || !isfinite(w) || (n && !desc->layers[i].weights))
            return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT,
                              "sinew_blend_weights: layer %u has a weight that is negative or not finite, or no "
                              "weights",
                              i);
        total += w;
    }
    for (uint32_t i = 0; i < desc->additive_count; i++)
        if (!isfinite(desc->additive[i].weight) || (n && !desc->additive[i].weights))
            return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT,
                              "sinew_blend_weights: additive layer %u has a weight that is not finite, or no deltas",
                              i);
    float threshold = desc->threshold > 0.0f ? desc->threshold : 0.1f;
    float fill = total < threshold ? threshold - total : 0.0f;
    float norm = 1.0f / (total + fill);
    for (uint32_t c = 0; c < n; c++) {
        float sum = fill * m->morph_channels[c].default_weight;
        for (uint32_t i = 0; i < desc->layer_count; i++)
            sum += desc->layers[i].weight * desc->layers[i].weights[c];
        float w = sum * norm;
        for (uint32_t i = 0; i < desc->additive_count; i++)
            w += desc->additive[i].weight * desc->additive[i].weights[c];
        desc->out[c] = w;
    }
    return SINEW_OK;
}
