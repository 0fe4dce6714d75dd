/* Volume-preserving muscles: the corrected seed 003 model, the tube surface, the arm.
 *
 * Index: cone sums A, B, C - the valid range of delta and of lengths - solve - surface -
 * law of cosines in half-angle form.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "internal.h"
#include "sinew/muscle.h"

/* F(delta) = A delta^2 + B delta + C: the sum of (a^2 + a b + b^2) / 3 over the cones with
 * a = r_i + m_i delta, b = r_{i+1} + m_{i+1} delta. */
typedef struct cone_sums {
    double a, b, c;
} cone_sums;

static cone_sums sums_of(const sinew_muscle_profile *p)
{
    cone_sums s = {0, 0, 0};
    for (uint32_t i = 0; i + 1 < p->node_count; i++) {
        double a = p->rest_radii[i], b = p->rest_radii[i + 1];
        double m = p->coefficients[i], q = p->coefficients[i + 1];
        s.a += (m * m + m * q + q * q) / 3.0;
        s.b += (2.0 * a * m + a * q + b * m + 2.0 * b * q) / 3.0;
        s.c += (a * a + a * b + b * b) / 3.0;
    }
    return s;
}

static double f_of(cone_sums s, double delta)
{
    return (s.a * delta + s.b) * delta + s.c;
}

double sinew_muscle_volume(uint32_t node_count, const double *radii, double length)
{
    if (node_count < 2 || !radii)
        return 0.0;
    double sum = 0.0;
    for (uint32_t i = 0; i + 1 < node_count; i++) {
        double a = radii[i], b = radii[i + 1];
        sum += (a * a + a * b + b * b) / 3.0;
    }
    return M_PI * length / (double)(node_count - 1) * sum;
}

static sinew_result check_profile(const sinew_muscle_profile *p, sinew_error *error)
{
    if (!p || !p->rest_radii || !p->coefficients)
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "muscle: no profile, radii or coefficients");
    if (p->node_count < 2)
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "muscle: %u nodes; a muscle needs at least 2",
                          p->node_count);
    if (!(p->rest_length > 0.0) || !isfinite(p->rest_length))
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "muscle: rest length %g must be positive",
                          p->rest_length);
    for (uint32_t i = 0; i < p->node_count; i++) {
        if (!(p->rest_radii[i] > 0.0) || !isfinite(p->rest_radii[i]))
            return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "muscle: node %u has radius %g; radii must be > 0",
                              i, p->rest_radii[i]);
        if (!isfinite(p->coefficients[i]))
            return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "muscle: node %u has coefficient %g", i,
                              p->coefficients[i]);
    }
    return SINEW_OK;
}

/* The open interval of delta where every radius r_i + m_i delta stays positive. */
static void positive_interval(const sinew_muscle_profile *p, double *lo, double *hi)
{
    *lo = -INFINITY, *hi = INFINITY;
    for (uint32_t i = 0; i < p->node_count; i++) {
        double m = p->coefficients[i], r = p->rest_radii[i];
        if (m > 0.0 && -r / m > *lo)
            *lo = -r / m;
        if (m < 0.0 && r / -m < *hi)
            *hi = r / -m;
    }
}

/* The branch of the parabola that holds the rest state (delta = 0): increasing when
 * B >= 0 (the larger root, as the seed says for growing radii), decreasing otherwise. */
static double branch_of(cone_sums s)
{
    return s.b >= 0.0 ? 1.0 : -1.0;
}

/* L = L0 * C / F, infinite where F reaches zero. */
static double length_for(const sinew_muscle_profile *p, cone_sums s, double f)
{
    return f > 0.0 ? p->rest_length * s.c / f : INFINITY;
}

sinew_result sinew_muscle_valid_range(const sinew_muscle_profile *p, sinew_muscle_range *out, sinew_error *error)
{
    sinew_result r = check_profile(p, error);
    if (r != SINEW_OK)
        return r;
    if (!out)
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "sinew_muscle_valid_range: no output");
    cone_sums s = sums_of(p);
    if (s.a <= 0.0) { /* every coefficient zero: the radii cannot change */
        *out = (sinew_muscle_range){p->rest_length, p->rest_length, false, false};
        return SINEW_OK;
    }
    double lo, hi, vertex = -s.b / (2.0 * s.a);
    positive_interval(p, &lo, &hi);
    if (branch_of(s) > 0.0) {
        double start = vertex > lo ? vertex : lo; /* F grows from here to hi */
        out->max_length = length_for(p, s, f_of(s, start));
        out->max_open = !(vertex > lo);
        out->min_length = isfinite(hi) ? length_for(p, s, f_of(s, hi)) : 0.0;
        out->min_open = true;
    } else {
        double end = vertex < hi ? vertex : hi; /* F falls from lo to here */
        out->max_length = length_for(p, s, f_of(s, end));
        out->max_open = !(vertex < hi);
        out->min_length = isfinite(lo) ? length_for(p, s, f_of(s, lo)) : 0.0;
        out->min_open = true;
    }
    return SINEW_OK;
}

static sinew_result out_of_range(const sinew_muscle_profile *p, double length, sinew_error *error)
{
    sinew_muscle_range range;
    sinew_muscle_valid_range(p, &range, NULL);
    return sinew_fail(error, SINEW_ERROR_LIMIT,
                      "muscle: length %.9g is outside the valid range %s%.9g, %.9g%s (rest length %.9g): no radii "
                      "keep the volume with every radius positive",
                      length, range.min_open ? "(" : "[", range.min_length, range.max_length,
                      range.max_open ? ")" : "]", p->rest_length);
}

sinew_result sinew_muscle_solve(const sinew_muscle_profile *p, double length, double *radii, uint32_t radius_count,
                                sinew_muscle_state *state, sinew_error *error)
{
    sinew_result r = check_profile(p, error);
    if (r != SINEW_OK)
        return r;
    if (!radii || radius_count < p->node_count)
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "muscle: %u radii of room for %u nodes", radius_count,
                          p->node_count);
    if (!(length > 0.0) || !isfinite(length))
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "muscle: length %g must be positive", length);
    cone_sums s = sums_of(p);
    double target = s.c * p->rest_length / length; /* F must reach this */
    double delta = 0.0;
    if (s.a <= 0.0) {
        if (fabs(length - p->rest_length) > 1e-12 * p->rest_length)
            return out_of_range(p, length, error);
    } else {
        double disc = s.b * s.b + 4.0 * s.a * (target - s.c);
        if (disc < 0.0)
            return out_of_range(p, length, error);
        /* The root on the rest branch, written without cancellation near the rest length. */
        double denominator = s.b + branch_of(s) * sqrt(disc);
        delta = denominator != 0.0 ? 2.0 * (target - s.c) / denominator : 0.0;
    }
    for (uint32_t i = 0; i < p->node_count; i++)
        if (!(p->rest_radii[i] + p->coefficients[i] * delta > 0.0))
            return out_of_range(p, length, error);
    for (uint32_t i = 0; i < p->node_count; i++)
        radii[i] = p->rest_radii[i] + p->coefficients[i] * delta;
    if (state) {
        state->length = length;
        state->rest_length = p->rest_length;
        state->delta = delta;
        state->volume = sinew_muscle_volume(p->node_count, radii, length);
        state->rest_volume = sinew_muscle_volume(p->node_count, p->rest_radii, p->rest_length);
    }
    return SINEW_OK;
}

/* ---- surface ------------------------------------------------------------------------- */

void sinew_muscle_surface_size(uint32_t node_count, uint32_t segments, uint32_t *vertex_count, uint32_t *index_count)
{
    if (vertex_count)
        *vertex_count = node_count * segments + 2 * (segments + 1);
    if (index_count)
        *index_count = (node_count ? node_count - 1 : 0) * segments * 6 + 2 * segments * 3;
}

static void put(float *base, size_t stride, uint32_t index, const double v[3])
{
    float *p = (float *)((char *)base + stride * index);
    p[0] = (float)v[0], p[1] = (float)v[1], p[2] = (float)v[2];
}

sinew_result sinew_muscle_surface(const sinew_muscle_surface_desc *d, sinew_error *error)
{
    if (!d || !d->radii || !d->out_positions || !d->out_indices || d->node_count < 2 || d->segments < 3)
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT,
                          "muscle surface: needs radii, 2+ nodes, 3+ segments and output buffers");
    uint32_t n = d->node_count, k = d->segments, vertices, indices;
    sinew_muscle_surface_size(n, k, &vertices, &indices);
    if (d->vertex_capacity < vertices || d->index_capacity < indices)
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT,
                          "muscle surface: room for %u vertices and %u indices, %u and %u needed", d->vertex_capacity,
                          d->index_capacity, vertices, indices);
    double axis[3], length = 0.0;
    for (int i = 0; i < 3; i++) {
        axis[i] = (double)d->insertion[i] - d->origin[i];
        length += axis[i] * axis[i];
    }
    length = sqrt(length);
    if (!(length > 0.0) || !isfinite(length))
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "muscle surface: origin and insertion coincide");
    for (int i = 0; i < 3; i++)
        axis[i] /= length;
    /* u, v, axis right-handed: increasing angle turns counter-clockwise about the axis. */
    double helper[3] = {0, 0, 0};
    double ax = fabs(axis[0]), ay = fabs(axis[1]), az = fabs(axis[2]);
    helper[ax <= ay && ax <= az ? 0 : ay <= az ? 1 : 2] = 1.0;
    double u[3] = {axis[1] * helper[2] - axis[2] * helper[1], axis[2] * helper[0] - axis[0] * helper[2],
                   axis[0] * helper[1] - axis[1] * helper[0]};
    double ul = sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]);
    for (int i = 0; i < 3; i++)
        u[i] /= ul;
    double v[3] = {axis[1] * u[2] - axis[2] * u[1], axis[2] * u[0] - axis[0] * u[2], axis[0] * u[1] - axis[1] * u[0]};
    size_t stride = d->out_stride ? d->out_stride : 12;
    double dx = length / (double)(n - 1);
    for (uint32_t i = 0; i < n; i++) {
        /* Smooth normal: the side's slope averaged over the cones meeting at this node. */
        double before = i > 0 ? (d->radii[i] - d->radii[i - 1]) / dx : 0.0;
        double after = i + 1 < n ? (d->radii[i + 1] - d->radii[i]) / dx : 0.0;
        double slope = i == 0 ? after : i + 1 == n ? before : 0.5 * (before + after);
        double scale = 1.0 / sqrt(1.0 + slope * slope);
        for (uint32_t j = 0; j < k; j++) {
            double angle = 2.0 * M_PI * j / k, c = cos(angle), s = sin(angle), pos[3], nrm[3];
            for (int t = 0; t < 3; t++) {
                double radial = c * u[t] + s * v[t];
                pos[t] = d->origin[t] + axis[t] * dx * i + radial * d->radii[i];
                nrm[t] = (radial - axis[t] * slope) * scale;
            }
            put(d->out_positions, stride, i * k + j, pos);
            if (d->out_normals)
                put(d->out_normals, stride, i * k + j, nrm);
        }
    }
    uint32_t *idx = d->out_indices;
    for (uint32_t i = 0; i + 1 < n; i++)
        for (uint32_t j = 0; j < k; j++) {
            uint32_t a = i * k + j, b = i * k + (j + 1) % k, c2 = a + k, d2 = b + k;
            *idx++ = a, *idx++ = b, *idx++ = d2;
            *idx++ = a, *idx++ = d2, *idx++ = c2;
        }
    /* End caps: a ring copy with the axis normal and a centre, at each end. */
    for (int end = 0; end < 2; end++) {
        uint32_t node = end ? n - 1 : 0, first = n * k + (uint32_t)end * (k + 1), centre = first + k;
        double sign = end ? 1.0 : -1.0, nrm[3] = {axis[0] * sign, axis[1] * sign, axis[2] * sign};
        for (uint32_t j = 0; j < k; j++) {
            const float *src = (const float *)((const char *)d->out_positions + stride * (node * k + j));
            double pos[3] = {src[0], src[1], src[2]};
            put(d->out_positions, stride, first + j, pos);
            if (d->out_normals)
                put(d->out_normals, stride, first + j, nrm);
        }
        double c[3];
        for (int t = 0; t < 3; t++)
            c[t] = d->origin[t] + axis[t] * dx * node;
        put(d->out_positions, stride, centre, c);
        if (d->out_normals)
            put(d->out_normals, stride, centre, nrm);
        for (uint32_t j = 0; j < k; j++) {
            uint32_t a = first + j, b = first + (j + 1) % k;
            *idx++ = centre;
            *idx++ = end ? a : b;
            *idx++ = end ? b : a;
        }
    }
    return SINEW_OK;
}

/* ---- the arm ----------------------------------------------------------------------------- */

static sinew_result check_rods(double a, double b, sinew_error *error)
{
    if (!(a > 0.0) || !(b > 0.0) || !isfinite(a) || !isfinite(b))
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT,
                          "arm: elbow-to-origin %g and elbow-to-insertion %g must be positive", a, b);
    return SINEW_OK;
}

sinew_result sinew_arm_length(double a, double b, double angle, double *length, sinew_error *error)
{
    sinew_result r = check_rods(a, b, error);
    if (r != SINEW_OK)
        return r;
    if (!(angle >= 0.0 && angle <= M_PI) || !length)
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "arm: elbow angle %g is outside [0, pi]", angle);
    /* L^2 = a^2 + b^2 - 2ab cos(angle) = (a - b)^2 + 4ab sin^2(angle / 2). */
    double s = sin(0.5 * angle);
    *length = sqrt((a - b) * (a - b) + 4.0 * a * b * s * s);
    return SINEW_OK;
}

sinew_result sinew_arm_angle(double a, double b, double length, double *angle, sinew_error *error)
{
    sinew_result r = check_rods(a, b, error);
    if (r != SINEW_OK)
        return r;
    double lo = fabs(a - b), hi = a + b;
    if (!(length >= lo && length <= hi) || !angle)
        return sinew_fail(error, SINEW_ERROR_LIMIT,
                          "arm: muscle length %.9g is outside [%.9g, %.9g], what rods of %g and %g can span", length,
                          lo, hi, a, b);
    /* sin^2(angle/2) = (L - |a-b|)(L + |a-b|) / 4ab and cos^2(angle/2) = (a+b-L)(a+b+L) / 4ab. */
    double s2 = (length - lo) * (length + lo), c2 = (hi - length) * (hi + length);
    *angle = 2.0 * atan2(sqrt(s2), sqrt(c2));
    return SINEW_OK;
}

/* ---- muscle sets ---------------------------------------------------------------------------- */

void sinew_muscle_set_free(sinew_muscle_set *set)
{
    free(set);
}

int32_t sinew_muscle_set_find(const sinew_muscle_set *set, const char *name)
{
    for (uint32_t i = 0; set && name && i < set->muscle_count; i++)
        if (strcmp(set->muscles[i].name, name) == 0)
            return (int32_t)i;
    return -1;
}
