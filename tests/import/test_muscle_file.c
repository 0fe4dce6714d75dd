/* Muscle files: what a good file gives, and errors that name line, column and field. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "helpers.h"

static const char GOOD[] = "{\n"
                           "  \"muscles\": [\n"
                           "    {\n"
                           "      \"name\": \"biceps\",\n"
                           "      \"origin\": {\"joint\": \"upper\", \"offset\": [0, 0.02, 0.03]},\n"
                           "      \"insertion\": {\"joint\": \"lower\", \"offset\": [0, 0.05, 0.02]},\n"
                           "      \"rest_length\": 0.31,\n"
                           "      \"radii\": [0.008, 0.02, 0.03, 0.02, 0.008],\n"
                           "      \"coefficients\": [0, 0.5, 1, 0.5, 0],\n"
                           "      \"segments\": 24,\n"
                           "      \"color\": \"#ff8000\"\n"
                           "    },\n"
                           "    {\"name\": \"point\", \"origin\": {\"offset\": [1, 2, 3]}, \"insertion\": {},\n"
                           "     \"radii\": [1, 2], \"coefficients\": [0.5, 0.5], \"color\": [0.1, 0.2, 0.3]}\n"
                           "  ]\n"
                           "}\n";

static void test_good_file(void **state)
{
    (void)state;
    sinew_muscle_set *set = NULL;
    sinew_error e = {0};
    assert_int_equal(sinew_muscle_set_parse(GOOD, strlen(GOOD), "good.json", &set, &e), SINEW_OK);
    assert_int_equal(set->muscle_count, 2);
    const sinew_muscle_def *b = &set->muscles[0];
    assert_string_equal(b->name, "biceps");
    assert_string_equal(b->origin.joint, "upper");
    assert_string_equal(b->insertion.joint, "lower");
    assert_near(b->origin.offset[2], 0.03, 1e-7, "origin offset");
    assert_near(b->rest_length, 0.31, 1e-15, "rest length");
    assert_int_equal(b->node_count, 5);
    assert_near(b->radii[2], 0.03, 1e-15, "radius");
    assert_near(b->coefficients[1], 0.5, 1e-15, "coefficient");
    assert_int_equal(b->segments, 24);
    assert_near(b->color[1], 128.0 / 255.0, 1e-6, "colour");
    const sinew_muscle_def *p = &set->muscles[1];
    assert_null(p->origin.joint);
    assert_near(p->origin.offset[1], 2.0, 1e-7, "point");
    assert_near(p->rest_length, 0.0, 0.0, "rest length left to the pose");
    assert_int_equal(p->segments, 16);
    assert_int_equal(sinew_muscle_set_find(set, "point"), 1);
    assert_int_equal(sinew_muscle_set_find(set, "triceps"), -1);
    sinew_muscle_set_free(set);
}

/* Replaces the first `from` in GOOD with `to` and expects an error containing `message`. */
static void expect_error(const char *from, const char *to, sinew_result kind, const char *message)
{
    char text[2048];
    const char *at = strstr(GOOD, from);
    assert_non_null(at);
    snprintf(text, sizeof text, "%.*s%s%s", (int)(at - GOOD), GOOD, to, at + strlen(from));
    sinew_muscle_set *set = NULL;
    sinew_error e = {0};
    sinew_result r = sinew_muscle_set_parse(text, strlen(text), "m.json", &set, &e);
    if (r != kind || !strstr(e.message, message))
        fail_msg("\"%s\" -> \"%s\": got %d \"%s\", expected %d \"%s\"", from, to, r, e.message, kind, message);
    assert_null(set);
}

static void test_errors_name_line_column_and_field(void **state)
{
    (void)state;
    expect_error("0.008, 0.02, 0.03", "0.008, -0.02, 0.03", SINEW_ERROR_DATA,
                 "m.json:8:24: muscles[0].radii[1]: radius -0.02 must be greater than 0");
    /* numbers whose squares and cubes overflow (a radius of 8e306 made the valid range NaN) */
    expect_error("0.008, 0.02, 0.03", "0.008, 8e306, 0.03", SINEW_ERROR_DATA,
                 "muscles[0].radii[1]: 8e+306 is out of range (at most 1e+06 either way)");
    expect_error("[0, 0.5, 1, 0.5, 0]", "[0, 0.5, -2e7, 0.5, 0]", SINEW_ERROR_DATA,
                 "muscles[0].coefficients[2]: -2e+07 is out of range");
    expect_error("\"coefficients\": [0, 0.5, 1, 0.5, 0]", "\"coefficients\": [0, 0.5, 1]", SINEW_ERROR_DATA,
                 "m.json:9:23: muscles[0].coefficients: expected 5 numbers, found 3");
    expect_error("[0.008, 0.02, 0.03, 0.02, 0.008]", "[0.008]", SINEW_ERROR_DATA,
                 "muscles[0].radii: expected 2 to 256 numbers (a muscle has at least 2 nodes), found 1");
    expect_error("\"name\": \"biceps\",", "", SINEW_ERROR_DATA, "m.json:3:5: muscles[0].name: missing");
    expect_error("\"name\": \"point\"", "\"name\": \"biceps\"", SINEW_ERROR_DATA,
                 "m.json:13:14: muscles[1].name: \"biceps\" is already the name of muscle 0");
    expect_error("\"segments\": 24", "\"segments\": 2.5", SINEW_ERROR_DATA, "muscles[0].segments: expected a whole");
    expect_error("\"#ff8000\"", "\"orange\"", SINEW_ERROR_DATA, "m.json:11:16: muscles[0].color");
    expect_error("\"offset\": [0, 0.02, 0.03]", "\"offset\": [0, \"up\", 0.03]", SINEW_ERROR_DATA,
                 "muscles[0].origin.offset[1]: expected a number");
    expect_error("\"rest_length\": 0.31", "\"rest_length\": -1", SINEW_ERROR_DATA, "muscles[0].rest_length");
    expect_error("\"joint\": \"upper\"", "\"joint\": 7", SINEW_ERROR_DATA, "muscles[0].origin.joint");
    expect_error("\"insertion\": {},", "", SINEW_ERROR_DATA, "muscles[1].insertion: missing");
    expect_error("\"muscles\": [", "\"muscle\": [", SINEW_ERROR_DATA, "m.json:1:1: muscles: expected");
    expect_error("\"segments\": 24,", "\"segments\": 24", SINEW_ERROR_FORMAT, "m.json:11:7: not valid JSON");
}

/* Every prefix of a good file is refused with a message (and nothing crashes or leaks). */
static void test_every_prefix_refused(void **state)
{
    (void)state;
    size_t n = strlen(GOOD);
    for (size_t i = 0; i + 2 < n; i++) {
        sinew_muscle_set *set = NULL;
        sinew_error e = {0};
        sinew_result r = sinew_muscle_set_parse(GOOD, i, "p.json", &set, &e);
        if (r == SINEW_OK)
            fail_msg("prefix of %zu bytes accepted", i);
        assert_non_null(strstr(e.message, "p.json"));
    }
}

static void test_files_and_paths(void **state)
{
    (void)state;
    char path[1024], out[1024];
    sinew_muscle_path_for("dir/walker.dae", out, sizeof out);
    assert_string_equal(out, "dir/walker.muscles.json");
    sinew_muscle_path_for("dir.v2/walker", out, sizeof out);
    assert_string_equal(out, "dir.v2/walker.muscles.json");
    tmp_path("good.muscles.json", path, sizeof path);
    write_file(path, GOOD, strlen(GOOD));
    sinew_muscle_set *set = NULL;
    sinew_error e = {0};
    assert_int_equal(sinew_muscle_set_read(path, &set, &e), SINEW_OK);
    assert_string_equal(set->source, path);
    sinew_muscle_set_free(set);
    assert_int_equal(sinew_muscle_set_read("/nonexistent/x.json", &set, &e), SINEW_ERROR_IO);
    assert_non_null(strstr(e.message, "/nonexistent/x.json"));
    /* a FIFO would block the reader for ever: refused by its kind */
    tmp_path("fifo.muscles.json", path, sizeof path);
    unlink(path);
    assert_int_equal(mkfifo(path, 0600), 0);
    assert_int_equal(sinew_muscle_set_read(path, &set, &e), SINEW_ERROR_IO);
    assert_non_null(strstr(e.message, "not a regular file"));
    unlink(path);
}

/* 20,000 muscles, the last named as the 7th: the duplicate is found (sorted, not pairwise),
 * and the message names both. */
static void test_duplicate_names_among_many(void **state)
{
    (void)state;
    const uint32_t count = 20000;
    const char *one = "{\"name\": \"m%u\", \"origin\": {\"offset\": [0, 0, 0]}, \"insertion\": "
                      "{\"offset\": [0.3, 0, 0]}, \"radii\": [0.01, 0.02], \"coefficients\": [0, 1]}";
    size_t cap = (size_t)count * 160 + 64, n = 0;
    char *text = malloc(cap);
    assert_non_null(text);
    n += (size_t)snprintf(text + n, cap - n, "{\"muscles\": [");
    for (uint32_t i = 0; i < count; i++) {
        n += (size_t)snprintf(text + n, cap - n, i ? ", " : "");
        n += (size_t)snprintf(text + n, cap - n, one, i + 1 == count ? 6u : i);
    }
    n += (size_t)snprintf(text + n, cap - n, "]}");
    sinew_muscle_set *set = NULL;
    sinew_error e = {0};
    assert_int_equal(sinew_muscle_set_parse(text, n, "many.json", &set, &e), SINEW_ERROR_DATA);
    assert_non_null(strstr(e.message, "muscles[19999].name: \"m6\" is already the name of muscle 6"));
    /* the same without the duplicate reads */
    char *last = strstr(text + n - 200, "\"m6\"");
    assert_non_null(last);
    memcpy(last, "\"mX\"", 4);
    assert_int_equal(sinew_muscle_set_parse(text, n, "many.json", &set, &e), SINEW_OK);
    assert_int_equal(set->muscle_count, count);
    sinew_muscle_set_free(set);
    free(text);
}

/* On animated models, muscle ends are the joints' world matrices applied to the offsets,
 * at ten times through a clip, and every muscle keeps its volume. */
static void check_rig(const char *model_path, const char *clip_name, const char *muscles_json)
{
    sinew_model *model = load_or_fail(model_path);
    sinew_muscle_set *set = NULL;
    sinew_muscle_rig *rig = NULL;
    sinew_error e = {0};
    assert_int_equal(sinew_muscle_set_parse(muscles_json, strlen(muscles_json), "rig.json", &set, &e), SINEW_OK);
    if (sinew_muscle_rig_create(model, set, &rig, &e) != SINEW_OK)
        fail_msg("%s", e.message);
    int32_t clip = clip_name ? sinew_model_find_clip(model, clip_name) : 0;
    assert_true(clip >= 0 && (uint32_t)clip < model->clip_count);
    const sinew_clip *c = &model->clips[clip];
    sinew_muscle_pose poses[4];
    double moved = 0.0, worst = 0.0;
    for (int i = 0; i < 10; i++) {
        float t = c->duration * (float)i / 9.0f;
        sinew_mat4 *w = pose_worlds(model, c, t);
        assert_int_equal(sinew_muscle_rig_update(rig, w, model->node_count, poses, 4, &e), SINEW_OK);
        for (uint32_t m = 0; m < set->muscle_count; m++) {
            const sinew_muscle_def *d = &set->muscles[m];
            const sinew_muscle_attachment *ends[2] = {&d->origin, &d->insertion};
            const float *got[2] = {poses[m].origin, poses[m].insertion};
            for (int end = 0; end < 2; end++) {
                int32_t node = sinew_model_find_joint(model, ends[end]->joint);
                assert_true(node >= 0 && sinew_model_node_is_joint(model, (uint32_t)node));
                const float *x = w[node].m, *o = ends[end]->offset;
                for (int k = 0; k < 3; k++) {
                    double expected = x[k] * o[0] + x[4 + k] * o[1] + x[8 + k] * o[2] + x[12 + k];
                    worst = fmax(worst, fabs(expected - got[end][k]));
                }
            }
            assert_true(poses[m].in_range);
            assert_near(poses[m].state.volume / poses[m].state.rest_volume, 1.0, 1e-9, "volume on the rig");
            moved = fmax(moved, fabs(poses[m].distance - poses[m].state.rest_length));
        }
        free(w);
    }
    printf("%s: muscle ends within %.2g of the transformed offsets; length changed by up to %.3g\n", model_path, worst,
           moved);
    assert_true(worst < 1e-5);
    assert_true(moved > 1e-3); /* the clip really bends the muscle */
    sinew_muscle_rig_free(rig);
    sinew_muscle_set_free(set);
    sinew_model_free(model);
}

static void test_rig_follows_joints(void **state)
{
    (void)state;
    char path[1024];
    fixture_path("two_bone.dae", path, sizeof path);
    check_rig(path, NULL,
              "{\"muscles\": [{\"name\": \"m\", \"origin\": {\"joint\": \"root\", \"offset\": [0.1, 0.3, 0]},"
              " \"insertion\": {\"joint\": \"tip\", \"offset\": [0.1, 0.4, 0]},"
              " \"radii\": [0.02, 0.05, 0.02], \"coefficients\": [0, 1, 0]}]}");
    if (!testdata_path("raylib/robot.glb", path, sizeof path))
        skip();
    check_rig(path, "Robot_Wave",
              "{\"muscles\": [{\"name\": \"biceps.R\", \"origin\": {\"joint\": \"UpperArm.R\", \"offset\": "
              "[0, 0.15, 0.12]}, \"insertion\": {\"joint\": \"LowerArm.R\", \"offset\": [0, 0.25, 0.1]},"
              " \"radii\": [0.03, 0.08, 0.12, 0.08, 0.03], \"coefficients\": [0, 0.5, 1, 0.5, 0]},"
              " {\"name\": \"biceps.L\", \"origin\": {\"joint\": \"UpperArm.L\", \"offset\": [0, 0.15, 0.12]},"
              " \"insertion\": {\"joint\": \"LowerArm.L\", \"offset\": [0, 0.25, 0.1]},"
              " \"radii\": [0.03, 0.08, 0.12, 0.08, 0.03], \"coefficients\": [0, 0.5, 1, 0.5, 0]}]}");
}

/* Binding `json` to `model` fails with SINEW_ERROR_DATA and a message containing `message`. */
static void expect_rig_error(const sinew_model *model, const char *json, const char *message)
{
    sinew_muscle_set *set = NULL;
    sinew_muscle_rig *rig = NULL;
    sinew_error e = {0};
    assert_int_equal(sinew_muscle_set_parse(json, strlen(json), "u.json", &set, &e), SINEW_OK);
    assert_int_equal(sinew_muscle_rig_create(model, set, &rig, &e), SINEW_ERROR_DATA);
    if (!strstr(e.message, message))
        fail_msg("got \"%s\", expected \"%s\"", e.message, message);
    assert_null(rig);
    sinew_muscle_set_free(set);
}

static void test_rig_errors(void **state)
{
    (void)state;
    char path[1024];
    fixture_path("two_bone.dae", path, sizeof path);
    sinew_model *model = load_or_fail(path);
    expect_rig_error(model,
                     "{\"muscles\": [{\"name\": \"m\", \"origin\": {\"joint\": \"elbow\"}, \"insertion\": "
                     "{\"joint\": \"tip\"}, \"radii\": [1, 1], \"coefficients\": [1, 1]}]}",
                     "u.json: muscle \"m\": origin joint \"elbow\" is not a node of");
    expect_rig_error(model,
                     "{\"muscles\": [{\"name\": \"m\", \"origin\": {\"joint\": \"tip\"}, \"insertion\": "
                     "{\"joint\": \"tip\"}, \"radii\": [1, 1], \"coefficients\": [1, 1]}]}",
                     "no rest length");
    sinew_model_free(model);
}

/* The built-in arm: the distance between origin and insertion is the law of cosines' length
 * at every elbow angle, wherever the arm is put; scale multiplies it. */
static void test_arm_model(void **state)
{
    (void)state;
    const char *data = getenv("SINEW_DATA");
    assert_non_null(data);
    char path[1024];
    snprintf(path, sizeof path, "%s/arm.muscles.json", data);
    sinew_arm_desc desc = {0};
    sinew_error e = {0};
    assert_int_equal(sinew_arm_read(path, &desc, &e), SINEW_OK);
    assert_true(desc.origin_to_elbow > 0.0 && desc.elbow_to_insertion > 0.0);
    double worst = 0.0;
    for (int deg = 0; deg <= 180; deg += 15) {
        for (int placed = 0; placed < 2; placed++) {
            desc.elbow_angle = deg * M_PI / 180.0;
            desc.place = placed ? (sinew_transform){{0.3f, -1.0f, 2.0f}, {0.2f, 0.5f, -0.1f, 0.83f}, {2.5f, 2.5f, 2.5f}}
                                : (sinew_transform){0};
            if (placed) {
                float *q = desc.place.rotation, n = sqrtf(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
                for (int k = 0; k < 4; k++)
                    q[k] /= n;
            }
            sinew_model *model = NULL;
            assert_int_equal(sinew_arm_model(&desc, &model, &e), SINEW_OK);
            assert_int_equal(model->node_count, 3);
            sinew_mat4 *w = pose_worlds(model, NULL, 0.0f);
            const float *up = w[1].m, *low = w[2].m;
            /* Origin: free_to_origin along the upper rod; insertion: elbow_to_insertion along the lower. */
            float o[3], in[3];
            for (int k = 0; k < 3; k++) {
                o[k] = up[k] * (float)desc.free_to_origin + up[12 + k];
                in[k] = low[k] * (float)desc.elbow_to_insertion + low[12 + k];
            }
            double d = sqrt((o[0] - in[0]) * (o[0] - in[0]) + (o[1] - in[1]) * (o[1] - in[1]) +
                            (o[2] - in[2]) * (o[2] - in[2]));
            double expected;
            assert_int_equal(
                sinew_arm_length(desc.origin_to_elbow, desc.elbow_to_insertion, desc.elbow_angle, &expected, NULL),
                SINEW_OK);
            double scale = placed ? 2.5 : 1.0;
            worst = fmax(worst, fabs(d / scale - expected));
            free(w);
            sinew_model_free(model);
        }
    }
    printf("arm: muscle ends match the law of cosines to %.2g at 0..180 degrees, placed or not\n", worst);
    assert_true(worst < 1e-6);
    desc.elbow_angle = 4.0;
    sinew_model *model = NULL;
    assert_int_equal(sinew_arm_model(&desc, &model, &e), SINEW_ERROR_INVALID_ARGUMENT);
    assert_non_null(strstr(e.message, "outside 0..180"));
    char bad[1024];
    tmp_path("arm-bad.json", bad, sizeof bad);
    const char *text = "{\"arm\": {\"free_to_origin\": 0.04,\n \"origin_to_elbow\": -1}}";
    write_file(bad, text, strlen(text));
    assert_int_equal(sinew_arm_read(bad, &desc, &e), SINEW_ERROR_DATA);
    assert_non_null(strstr(e.message, "arm-bad.json:2:21: arm.origin_to_elbow: expected a distance greater than 0"));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_good_file),
        cmocka_unit_test(test_errors_name_line_column_and_field),
        cmocka_unit_test(test_every_prefix_refused),
        cmocka_unit_test(test_files_and_paths),
        cmocka_unit_test(test_duplicate_names_among_many),
        cmocka_unit_test(test_rig_follows_joints),
        cmocka_unit_test(test_rig_errors),
        cmocka_unit_test(test_arm_model),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
