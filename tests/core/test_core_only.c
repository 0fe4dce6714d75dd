/* Linked with sinew_core alone (no import, no render, no Assimp, cJSON or libxml2): the
 * runtime's muscles, their rig and the camera are usable by an engine that links the core. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "sinew/anim.h"
#include "sinew/camera.h"
#include "sinew/muscle_rig.h"

static void test_muscle_rig_without_a_model(void **state)
{
    (void)state;
    static const double radii[3] = {0.01, 0.02, 0.01}, coefficients[3] = {0.0, 1.0, 0.0};
    const sinew_muscle_def def = {.name = "biceps",
                                  .origin = {.offset = {0, 0, 0}},
                                  .insertion = {.offset = {0.3f, 0, 0}},
                                  .node_count = 3,
                                  .radii = radii,
                                  .coefficients = coefficients,
                                  .segments = 8};
    const sinew_muscle_set set = {.source = "hand-made", .muscle_count = 1, .muscles = &def};
    sinew_muscle_rig *rig = NULL;
    sinew_error error = {0};
    assert_int_equal(sinew_muscle_rig_create(NULL, &set, &rig, &error), SINEW_OK);
    assert_int_equal(sinew_muscle_rig_count(rig), 1);
    sinew_muscle_pose pose;
    assert_int_equal(sinew_muscle_rig_update(rig, NULL, 0, &pose, 1, &error), SINEW_OK);
    assert_true(pose.in_range);
    assert_true(fabs(pose.distance - 0.3) < 1e-6);
    assert_true(fabs(pose.state.volume - pose.state.rest_volume) < 1e-12);
    assert_int_equal(sinew_muscle_set_find(&set, "biceps"), 0);
    sinew_muscle_rig_free(rig);
}

static void test_camera_frames_a_box(void **state)
{
    (void)state;
    sinew_camera camera = sinew_camera_default();
    const float lo[3] = {-1, 0, -1}, hi[3] = {1, 2, 1};
    sinew_camera_frame(&camera, lo, hi, 1.0f);
    /* the target in the box (moved off its centre only to centre the perspective picture) */
    for (int i = 0; i < 3; i++)
        assert_true(camera.target[i] >= lo[i] && camera.target[i] <= hi[i]);
    assert_true(camera.distance > 0.0f && isfinite(camera.distance));
    sinew_mat4 view;
    sinew_camera_view(&camera, &view);
    assert_true(isfinite(view.m[14]));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_muscle_rig_without_a_model),
        cmocka_unit_test(test_camera_frames_a_box),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
