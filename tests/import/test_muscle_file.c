/* Muscle files: what a good file gives, and errors that name line, column and field. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

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
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_good_file),
        cmocka_unit_test(test_errors_name_line_column_and_field),
        cmocka_unit_test(test_every_prefix_refused),
        cmocka_unit_test(test_files_and_paths),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
