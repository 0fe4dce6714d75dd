/* Cameras and display options: pure math and parsing, no OpenGL needed. */
#include <math.h>
#include <string.h>

#include "app.h"
#include "helpers.h"

static void project(const sinew_camera *c, float aspect, const float p[3], float ndc[3])
{
    sinew_mat4 v, pr;
    sinew_camera_view(c, &v);
    sinew_camera_projection(c, aspect, &pr);
    float e[4], q[4];
    for (int r = 0; r < 4; r++)
        e[r] = v.m[r] * p[0] + v.m[4 + r] * p[1] + v.m[8 + r] * p[2] + v.m[12 + r];
    for (int r = 0; r < 4; r++)
        q[r] = pr.m[r] * e[0] + pr.m[4 + r] * e[1] + pr.m[8 + r] * e[2] + pr.m[12 + r] * e[3];
    for (int i = 0; i < 3; i++)
        ndc[i] = q[i] / q[3];
}

static void assert_same_view(const sinew_camera *a, const sinew_camera *b)
{
    sinew_mat4 va, vb;
    sinew_camera_view(a, &va);
    sinew_camera_view(b, &vb);
    for (int i = 0; i < 16; i++)
        assert_near(va.m[i], vb.m[i], 1e-4, "view matrix element");
}

static void test_default_looks_along_minus_z(void **state)
{
    (void)state;
    sinew_camera c = sinew_camera_default();
    c.pitch = 0.0f;
    float f[3], r[3], u[3], eye[3];
    sinew_camera_basis(&c, f, r, u);
    assert_near(f[2], -1.0, 1e-6, "forward z");
    assert_near(r[0], 1.0, 1e-6, "right x");
    assert_near(u[1], 1.0, 1e-6, "up y");
    sinew_camera_eye(&c, eye);
    assert_near(eye[2], 3.0, 1e-6, "eye on +z");
    /* Positive yaw swings the eye towards +X, positive pitch raises it. */
    sinew_camera_rotate(&c, 0.5f, 0.3f);
    sinew_camera_eye(&c, eye);
    assert_true(eye[0] > 0.0f && eye[1] > 0.0f);
}

static void test_mode_switch_keeps_the_view(void **state)
{
    (void)state;
    sinew_camera c = sinew_camera_default();
    c.target[0] = 1.0f, c.target[1] = 2.0f, c.target[2] = -3.0f;
    c.distance = 7.5f;
    sinew_camera_rotate(&c, 1.1f, -0.4f);
    sinew_camera before = c;
    sinew_camera_set_mode(&c, SINEW_CAMERA_FLY);
    assert_int_equal(c.mode, SINEW_CAMERA_FLY);
    assert_same_view(&before, &c);
    sinew_camera_move(&c, 1.0f, 0.5f, 0.25f);
    sinew_camera_rotate(&c, 0.3f, 0.1f);
    sinew_camera moved = c;
    sinew_camera_set_mode(&c, SINEW_CAMERA_ORBIT);
    assert_same_view(&moved, &c);
    sinew_camera_set_mode(&c, SINEW_CAMERA_FLY);
    assert_same_view(&moved, &c);
}

static void test_pitch_is_clamped(void **state)
{
    (void)state;
    sinew_camera c = sinew_camera_default();
    sinew_camera_rotate(&c, 0.0f, 10.0f);
    assert_true(c.pitch < 1.5708f);
    sinew_mat4 v;
    sinew_camera_view(&c, &v);
    for (int i = 0; i < 16; i++)
        assert_true(isfinite(v.m[i]));
}

/* Frame-all puts every corner of the box inside the picture and fills it (95% of its tighter
 * side, centred), at several aspects and angles, for a standing and a long model, in perspective
 * and parallel views. */
static void test_frame_all_shows_the_box(void **state)
{
    (void)state;
    const float boxes[2][2][3] = {{{-0.3f, 0.0f, -0.2f}, {0.4f, 1.8f, 0.25f}},
                                  {{-2.0f, 0.0f, -0.2f}, {2.0f, 0.6f, 0.2f}}};
    const float aspects[] = {16.0f / 9.0f, 1.0f, 0.5f};
    for (int b = 0; b < 4; b++)
        for (int a = 0; a < 3; a++) {
            const float *lo = boxes[b & 1][0], *hi = boxes[b & 1][1];
            for (int yaw = -180; yaw < 180; yaw += 45) {
                sinew_camera c = sinew_camera_default();
                c.orthographic = b >= 2;
                sinew_camera_rotate(&c, (float)yaw * 3.14159265f / 180.0f, 0.2f);
                sinew_camera_frame(&c, lo, hi, aspects[a]);
                float x0 = 1.0f, x1 = -1.0f, y0 = 1.0f, y1 = -1.0f;
                for (int k = 0; k < 8; k++) {
                    float p[3] = {k & 1 ? hi[0] : lo[0], k & 2 ? hi[1] : lo[1], k & 4 ? hi[2] : lo[2]}, ndc[3];
                    project(&c, aspects[a], p, ndc);
                    assert_true(fabsf(ndc[0]) <= 1.0f && fabsf(ndc[1]) <= 1.0f && ndc[2] > -1.0f && ndc[2] < 1.0f);
                    x0 = fminf(x0, ndc[0]), x1 = fmaxf(x1, ndc[0]), y0 = fminf(y0, ndc[1]), y1 = fmaxf(y1, ndc[1]);
                }
                /* tight on one side, centred on both */
                assert_true(x1 - x0 > 1.85f || y1 - y0 > 1.85f);
                assert_true(fabsf(x0 + x1) < 0.02f && fabsf(y0 + y1) < 0.02f);
            }
        }
    /* Degenerate boxes stay drawable. */
    sinew_camera c = sinew_camera_default();
    const float p[3] = {1.0f, 1.0f, 1.0f}, nan3[3] = {NAN, NAN, NAN};
    sinew_camera_frame(&c, p, p, 1.0f);
    assert_true(c.distance > 0.0f && isfinite(c.distance));
    sinew_camera_frame(&c, nan3, nan3, 1.0f);
    assert_true(c.distance > 0.0f && isfinite(c.distance));
}

static void test_zoom_and_pan(void **state)
{
    (void)state;
    sinew_camera c = sinew_camera_default();
    sinew_camera_zoom(&c, 0.5f);
    assert_near(c.distance, 1.5, 1e-6, "zoom halves the distance");
    sinew_camera_zoom(&c, -1.0f);
    assert_near(c.distance, 1.5, 1e-6, "a bad factor is ignored");
    c.pitch = 0.0f;
    sinew_camera_pan(&c, 1.0f, 2.0f);
    assert_near(c.target[0], 1.0, 1e-6, "pan right");
    assert_near(c.target[1], 2.0, 1e-6, "pan up");
}

static void test_parse(void **state)
{
    (void)state;
    sinew_camera c = sinew_camera_default();
    bool frame_all = false;
    sinew_error e = {0};
    assert_int_equal(app_camera_parse("orbit:90,-30,4.5", &c, &frame_all, &e), SINEW_OK);
    assert_int_equal(c.mode, SINEW_CAMERA_ORBIT);
    assert_near(c.yaw, M_PI / 2, 1e-6, "yaw");
    assert_near(c.pitch, -M_PI / 6, 1e-6, "pitch");
    assert_near(c.distance, 4.5, 1e-6, "distance");
    assert_false(frame_all);
    assert_int_equal(app_camera_parse("orbit:10,20", &c, &frame_all, &e), SINEW_OK);
    assert_true(frame_all);
    assert_int_equal(app_camera_parse("orbit:10,20,auto", &c, &frame_all, &e), SINEW_OK);
    assert_true(frame_all);
    assert_int_equal(app_camera_parse("fly:1,2,3,45,0", &c, &frame_all, &e), SINEW_OK);
    assert_int_equal(c.mode, SINEW_CAMERA_FLY);
    assert_near(c.position[2], 3.0, 1e-6, "fly z");
    static const char *const bad[] = {
        "",          "orbit:",      "orbit:1",         "orbit:1,2,0",     "orbit:1,2,-3", "orbit:1,2,3,4",
        "orbit:a,b", "fly:1,2,3,4", "fly:1,2,3,4,5,6", "fly:1,2,3,4,nan", "spin:1,2"};
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        if (app_camera_parse(bad[i], &c, &frame_all, &e) != SINEW_ERROR_INVALID_ARGUMENT)
            fail_msg("camera \"%s\" was accepted", bad[i]);
        assert_non_null(strstr(e.message, "expected"));
    }
}

static void test_options_round_trip(void **state)
{
    (void)state;
    sinew_render_options o = sinew_render_options_default();
    sinew_error e = {0};
    assert_true(!o.clay && !o.unlit && !o.hide_grid && !o.hide_meshes && !o.skeleton);
    assert_int_equal(sinew_render_option_set(&o, "skeleton", NULL, &e), SINEW_OK);
    assert_int_equal(sinew_render_option_set(&o, "grid", "off", &e), SINEW_OK);
    assert_int_equal(sinew_render_option_set(&o, "shading", "Gouraud", &e), SINEW_OK);
    assert_int_equal(sinew_render_option_set(&o, "skinning", "cpu", &e), SINEW_OK);
    assert_int_equal(sinew_render_option_set(&o, "background", "#ff8000", &e), SINEW_OK);
    assert_int_equal(sinew_render_option_set(&o, "normal-length", "0.05", &e), SINEW_OK);
    sinew_render_options copy = sinew_render_options_default();
    for (const char *const *n = sinew_render_option_names(); *n; n++) {
        char value[64];
        assert_int_equal(sinew_render_option_get(&o, *n, value, sizeof value, &e), SINEW_OK);
        assert_int_equal(sinew_render_option_set(&copy, *n, value, &e), SINEW_OK);
    }
    assert_memory_equal(&copy, &o, sizeof o);
    char value[64];
    sinew_render_option_get(&o, "background", value, sizeof value, &e);
    assert_string_equal(value, "#ff8000");
    static const char *const bad[][2] = {{"grid", "maybe"},     {"shading", "toon"},     {"skinning", "tpu"},
                                         {"background", "red"}, {"background", "2,0,0"}, {"normal-length", "-1"},
                                         {"colour", "on"},      {"shading", NULL}};
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++)
        assert_int_equal(sinew_render_option_set(&o, bad[i][0], bad[i][1], &e), SINEW_ERROR_INVALID_ARGUMENT);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_default_looks_along_minus_z),
        cmocka_unit_test(test_mode_switch_keeps_the_view),
        cmocka_unit_test(test_pitch_is_clamped),
        cmocka_unit_test(test_frame_all_shows_the_box),
        cmocka_unit_test(test_zoom_and_pan),
        cmocka_unit_test(test_parse),
        cmocka_unit_test(test_options_round_trip),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
