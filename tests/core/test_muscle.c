/* The muscle solver, its valid range, the tube surface and the arm's law of cosines. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "helpers.h"

#define MAX_NODES 16

typedef struct profile_case {
    const char *name;
    uint32_t n;
    double radii[MAX_NODES], coefficients[MAX_NODES];
} profile_case;

static const profile_case PROFILES[] = {
    {"uniform", 5, {1, 1, 1, 1, 1}, {1, 1, 1, 1, 1}},
    {"spindle", 7, {0.4, 0.9, 1.3, 1.5, 1.3, 0.9, 0.4}, {0.2, 0.6, 0.9, 1.0, 0.9, 0.6, 0.2}},
    /* A biceps in the seed's spirit: thin tendon ends that do not grow, a thick belly that does. */
    {"seed biceps, tendon ends fixed",
     9,
     {0.6, 1.2, 2.0, 2.6, 2.8, 2.6, 2.0, 1.2, 0.6},
     {0, 0.3, 0.7, 1.0, 1.1, 1.0, 0.7, 0.3, 0}},
    {"mixed signs", 6, {1.0, 1.5, 2.0, 2.0, 1.5, 1.0}, {-0.5, 0.2, 1.0, 1.0, 0.2, -0.5}},
    {"all shrinking", 4, {1.0, 2.0, 2.0, 1.0}, {-0.2, -0.5, -0.5, -0.2}},
};

static sinew_muscle_profile profile_of(const profile_case *c, double rest_length)
{
    return (sinew_muscle_profile){c->n, c->radii, c->coefficients, rest_length};
}

/* Over the whole valid range: the volume stays the rest volume to 1e-9, radii stay positive. */
static void test_volume_preserved_over_the_range(void **state)
{
    (void)state;
    for (size_t p = 0; p < sizeof PROFILES / sizeof PROFILES[0]; p++) {
        sinew_muscle_profile prof = profile_of(&PROFILES[p], 10.0);
        sinew_muscle_range range;
        sinew_error e = {0};
        assert_int_equal(sinew_muscle_valid_range(&prof, &range, &e), SINEW_OK);
        assert_true(range.min_length < 10.0 && range.max_length > 10.0);
        double lo = range.min_length > 0.0 ? range.min_length : 1e-3;
        double hi = isfinite(range.max_length) ? range.max_length : 1e4;
        double worst = 0.0;
        for (int i = 0; i <= 1000; i++) {
            /* Geometric spacing, stopping a hair inside open ends. */
            double t = (double)i / 1000.0;
            double length = exp(log(lo) + (log(hi) - log(lo)) * t);
            length = fmin(fmax(length, lo * (1.0 + 1e-9)), hi * (1.0 - 1e-9));
            double radii[MAX_NODES];
            sinew_muscle_state st;
            if (sinew_muscle_solve(&prof, length, radii, MAX_NODES, &st, &e) != SINEW_OK)
                fail_msg("%s: length %.17g inside the range failed: %s", PROFILES[p].name, length, e.message);
            for (uint32_t k = 0; k < prof.node_count; k++)
                assert_true(radii[k] > 0.0 && isfinite(radii[k]));
            double drift = fabs(st.volume - st.rest_volume) / st.rest_volume;
            worst = fmax(worst, drift);
            assert_true(drift <= 1e-9);
        }
        printf("%-32s range %s%.6g, %.6g%s, worst volume drift %.2e\n", PROFILES[p].name, range.min_open ? "(" : "[",
               range.min_length, range.max_length, range.max_open ? ")" : "]", worst);
        /* The rest length gives the rest radii. */
        double radii[MAX_NODES];
        sinew_muscle_state st;
        assert_int_equal(sinew_muscle_solve(&prof, 10.0, radii, MAX_NODES, &st, &e), SINEW_OK);
        assert_near(st.delta, 0.0, 1e-15, "delta at rest");
        for (uint32_t k = 0; k < prof.node_count; k++)
            assert_near(radii[k], PROFILES[p].radii[k], 1e-15, "rest radius");
    }
}

/* r = 1, m = 1 everywhere: (1 + delta)^2 = L0 / L, so delta = sqrt(L0 / L) - 1, any length. */
static void test_uniform_profile_closed_form(void **state)
{
    (void)state;
    sinew_muscle_profile prof = profile_of(&PROFILES[0], 4.0);
    sinew_muscle_range range;
    assert_int_equal(sinew_muscle_valid_range(&prof, &range, NULL), SINEW_OK);
    assert_true(range.min_length == 0.0 && isinf(range.max_length));
    const double lengths[] = {0.01, 1.0, 3.999, 4.0, 4.001, 9.0, 1e6};
    for (size_t i = 0; i < sizeof lengths / sizeof lengths[0]; i++) {
        double radii[5];
        sinew_muscle_state st;
        assert_int_equal(sinew_muscle_solve(&prof, lengths[i], radii, 5, &st, NULL), SINEW_OK);
        double expected = sqrt(4.0 / lengths[i]) - 1.0;
        assert_near(st.delta, expected, 1e-12 * fmax(1.0, fabs(expected)), "closed-form delta");
    }
}

/* The range ends are exact: inside them a solve succeeds, just outside it fails with the range. */
static void test_range_limits_are_exact(void **state)
{
    (void)state;
    for (size_t p = 1; p < sizeof PROFILES / sizeof PROFILES[0]; p++) {
        sinew_muscle_profile prof = profile_of(&PROFILES[p], 10.0);
        sinew_muscle_range range;
        sinew_error e = {0};
        sinew_muscle_valid_range(&prof, &range, &e);
        double radii[MAX_NODES];
        if (range.min_length > 0.0) {
            assert_int_equal(sinew_muscle_solve(&prof, range.min_length * (1.0 + 1e-7), radii, MAX_NODES, NULL, &e),
                             SINEW_OK);
            double smallest = INFINITY;
            for (uint32_t k = 0; k < prof.node_count; k++)
                smallest = fmin(smallest, radii[k]);
            assert_true(smallest < 1e-3); /* a radius is about to vanish: that is why it is the end */
            assert_int_equal(sinew_muscle_solve(&prof, range.min_length * (1.0 - 1e-7), radii, MAX_NODES, NULL, &e),
                             SINEW_ERROR_LIMIT);
            assert_non_null(strstr(e.message, "valid range"));
        }
        if (isfinite(range.max_length)) {
            double inside = range.max_open ? range.max_length * (1.0 - 1e-7) : range.max_length;
            assert_int_equal(sinew_muscle_solve(&prof, inside, radii, MAX_NODES, NULL, &e), SINEW_OK);
            assert_int_equal(sinew_muscle_solve(&prof, range.max_length * (1.0 + 1e-7), radii, MAX_NODES, NULL, &e),
                             SINEW_ERROR_LIMIT);
        }
    }
}

static void test_zero_coefficients_and_bad_profiles(void **state)
{
    (void)state;
    double r[3] = {1, 2, 1}, zero[3] = {0, 0, 0}, radii[3];
    sinew_muscle_profile prof = {3, r, zero, 5.0};
    sinew_muscle_range range;
    sinew_error e = {0};
    assert_int_equal(sinew_muscle_valid_range(&prof, &range, &e), SINEW_OK);
    assert_true(range.min_length == 5.0 && range.max_length == 5.0 && !range.min_open && !range.max_open);
    assert_int_equal(sinew_muscle_solve(&prof, 5.0, radii, 3, NULL, &e), SINEW_OK);
    assert_int_equal(sinew_muscle_solve(&prof, 5.5, radii, 3, NULL, &e), SINEW_ERROR_LIMIT);
    assert_non_null(strstr(e.message, "[5, 5]"));

    double m[3] = {1, 1, 1}, neg[3] = {1, -2, 1}, nan_r[3] = {1, NAN, 1};
    sinew_muscle_profile bad[] = {{1, r, m, 5.0}, {3, neg, m, 5.0}, {3, nan_r, m, 5.0},
                                  {3, r, m, 0.0}, {3, r, m, NAN},   {3, NULL, m, 5.0}};
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++)
        assert_int_equal(sinew_muscle_solve(&bad[i], 5.0, radii, 3, NULL, &e), SINEW_ERROR_INVALID_ARGUMENT);
    prof.coefficients = m;
    const double bad_lengths[] = {0.0, -1.0, NAN, INFINITY};
    for (size_t i = 0; i < 4; i++)
        assert_int_equal(sinew_muscle_solve(&prof, bad_lengths[i], radii, 3, NULL, &e), SINEW_ERROR_INVALID_ARGUMENT);
    assert_int_equal(sinew_muscle_solve(&prof, 5.0, radii, 2, NULL, &e), SINEW_ERROR_INVALID_ARGUMENT);
}

/* Length -> angle -> length round trips to 1e-12, including folded (0) and straight (180). */
static void test_law_of_cosines(void **state)
{
    (void)state;
    const double rods[][2] = {{0.3, 0.05}, {1.0, 1.0}, {2.5, 4.0}};
    for (int r = 0; r < 3; r++) {
        double a = rods[r][0], b = rods[r][1], length, angle;
        for (int i = 0; i <= 1000; i++) {
            double theta = M_PI * i / 1000.0;
            assert_int_equal(sinew_arm_length(a, b, theta, &length, NULL), SINEW_OK);
            double direct = sqrt(a * a + b * b - 2 * a * b * cos(theta));
            assert_near(length, direct, 1e-12, "law of cosines");
            assert_int_equal(sinew_arm_angle(a, b, length, &angle, NULL), SINEW_OK);
            double back;
            sinew_arm_length(a, b, angle, &back, NULL);
            assert_near(back, length, 1e-12, "length -> angle -> length");
        }
        assert_int_equal(sinew_arm_length(a, b, 0.0, &length, NULL), SINEW_OK);
        assert_true(length == fabs(a - b));
        assert_int_equal(sinew_arm_angle(a, b, fabs(a - b), &angle, NULL), SINEW_OK);
        assert_true(angle == 0.0);
        assert_int_equal(sinew_arm_angle(a, b, a + b, &angle, NULL), SINEW_OK);
        assert_near(angle, M_PI, 1e-15, "straight arm");
        sinew_error e = {0};
        assert_int_equal(sinew_arm_angle(a, b, a + b + 1e-9, &angle, &e), SINEW_ERROR_LIMIT);
        assert_non_null(strstr(e.message, "outside"));
        assert_int_equal(sinew_arm_length(a, b, -0.1, &length, &e), SINEW_ERROR_INVALID_ARGUMENT);
        assert_int_equal(sinew_arm_length(a, b, NAN, &length, &e), SINEW_ERROR_INVALID_ARGUMENT);
    }
    double angle;
    assert_int_equal(sinew_arm_angle(0.0, 1.0, 1.0, &angle, NULL), SINEW_ERROR_INVALID_ARGUMENT);
}

/* The tube: rings at the node radii, unit normals pointing out, triangles wound outward,
 * and a closed surface whose enclosed volume approaches the cones' volume. */
static void test_surface(void **state)
{
    (void)state;
    const profile_case *c = &PROFILES[2];
    const uint32_t k = 256;
    uint32_t nv, ni;
    sinew_muscle_surface_size(c->n, k, &nv, &ni);
    assert_int_equal(nv, c->n * k + 2 * (k + 1));
    float *pos = malloc(nv * 12), *nrm = malloc(nv * 12);
    uint32_t *idx = malloc(ni * 4);
    sinew_muscle_surface_desc d = {.node_count = c->n,
                                   .radii = c->radii,
                                   .origin = {1, 2, 3},
                                   .insertion = {1, 2, 13},
                                   .segments = k,
                                   .out_positions = pos,
                                   .out_normals = nrm,
                                   .vertex_capacity = nv,
                                   .out_indices = idx,
                                   .index_capacity = ni};
    sinew_error e = {0};
    assert_int_equal(sinew_muscle_surface(&d, &e), SINEW_OK);
    for (uint32_t v = 0; v < c->n * k; v++) {
        double dx = pos[v * 3] - 1.0, dy = pos[v * 3 + 1] - 2.0;
        assert_near(sqrt(dx * dx + dy * dy), c->radii[v / k], 1e-5, "ring radius");
    }
    double volume = 0.0;
    for (uint32_t v = 0; v < nv; v++) {
        double len = sqrt(nrm[v * 3] * nrm[v * 3] + nrm[v * 3 + 1] * nrm[v * 3 + 1] + nrm[v * 3 + 2] * nrm[v * 3 + 2]);
        assert_near(len, 1.0, 1e-5, "unit normal");
    }
    for (uint32_t t = 0; t < ni; t += 3) {
        const float *a = &pos[idx[t] * 3], *b = &pos[idx[t + 1] * 3], *q = &pos[idx[t + 2] * 3];
        /* Signed tetrahedron volumes from the origin: positive in all for an outward-wound surface. */
        volume += (a[0] * (b[1] * q[2] - b[2] * q[1]) - a[1] * (b[0] * q[2] - b[2] * q[0]) +
                   a[2] * (b[0] * q[1] - b[1] * q[0])) /
                  6.0;
    }
    double cones = sinew_muscle_volume(c->n, c->radii, 10.0);
    printf("tube of %u segments: mesh volume %.6f, cones %.6f\n", k, volume, cones);
    assert_near(volume / cones, 1.0, 1e-3, "enclosed volume");
    d.vertex_capacity = nv - 1;
    assert_int_equal(sinew_muscle_surface(&d, &e), SINEW_ERROR_INVALID_ARGUMENT);
    d.vertex_capacity = nv;
    memcpy(d.insertion, d.origin, sizeof d.origin);
    assert_int_equal(sinew_muscle_surface(&d, &e), SINEW_ERROR_INVALID_ARGUMENT);
    free(pos);
    free(nrm);
    free(idx);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_volume_preserved_over_the_range),
        cmocka_unit_test(test_uniform_profile_closed_form),
        cmocka_unit_test(test_range_limits_are_exact),
        cmocka_unit_test(test_zero_coefficients_and_bad_profiles),
        cmocka_unit_test(test_law_of_cosines),
        cmocka_unit_test(test_surface),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
