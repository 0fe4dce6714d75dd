/* sinew's BVH reader: the hand-made fixture (tests/fixtures/mixed_channels.bvh: channels in mixed orders,
 * position channels on a joint below the root, a joint that does not move, End Sites) posed at
 * each frame against rotation matrices multiplied here in the channels' order; what files in the
 * wild do (lower case, CRLF, a byte order mark, braces on the joint's line, names with spaces,
 * several roots, a truncated or over-long MOTION, bytes from memory with no newline at the end);
 * broken files refused with the line; every prefix refused or warned about, never a crash; and a
 * file that claims a billion frames not allocated for. CMU's 01_01.bvh is test_reference's
 * (three.js) and test_models'. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "helpers.h"

/* 3x3 row-major rotation of `deg` degrees about axis 0, 1 or 2. */
static void axis_matrix(int axis, double deg, double r[9])
{
    double a = deg * M_PI / 180.0, c = cos(a), s = sin(a);
    memset(r, 0, 9 * sizeof *r);
    int i = (axis + 1) % 3, j = (axis + 2) % 3;
    r[axis * 3 + axis] = 1.0;
    r[i * 3 + i] = c, r[i * 3 + j] = -s;
    r[j * 3 + i] = s, r[j * 3 + j] = c;
}

static void mul3(const double a[9], const double b[9], double out[9])
{
    double t[9];
    for (int r = 0; r < 3; r++)
        for (int c = 0; c < 3; c++)
            t[r * 3 + c] = a[r * 3] * b[c] + a[r * 3 + 1] * b[3 + c] + a[r * 3 + 2] * b[6 + c];
    memcpy(out, t, sizeof t);
}

/* The fixture's joints as written: parent, offset, channels (0..2 position, 3..5 rotation). */
static const struct {
    int parent;
    double offset[3];
    int channels[6], count;
} JOINTS[6] = {
    {-1, {1, 2, 3}, {0, 1, 2, 5, 3, 4}, 6},   /* hips: Xpos Ypos Zpos Zrot Xrot Yrot */
    {0, {0, -1, 0}, {4, 3, 5}, 3},            /* thigh: Yrot Xrot Zrot */
    {1, {0, -2, 0.5}, {3, 1, 5, 0, 4, 2}, 6}, /* shin: Xrot Ypos Zrot Xpos Yrot Zpos */
    {2, {0, -1.5, 0}, {0}, 0},                /* EndSite_shin */
    {0, {0.5, 0, 0}, {5, 4, 3}, 3},           /* still: Zrot Yrot Xrot */
    {4, {0.25, 0, 0}, {0}, 0},                /* EndSite_still */
};
static const double FRAMES[3][18] = {
    {0, 2, 0, 0, 0, 0, 0, 0, 0, 0, -2, 0, 0, 0.5, 0, 10, 20, 30},
    {1, 2.5, -1, 90, 0, 0, 0, 45, 0, 30, -2.5, 0, 0.25, 0.5, 0, 10, 20, 30},
    {2, 2, -2, 45, 30, -60, 20, -10, 5, -15, -2, 40, 0, 0.75, 25, 10, 20, 30},
};

/* The joints' world positions at frame f, from the file's numbers (position channels in place of
 * the offset's coordinates, rotations multiplied in the order written). */
static void expected_positions(int f, double out[6][3])
{
    double world_r[6][9];
    int value = 0;
    for (int j = 0; j < 6; j++) {
        double t[3] = {JOINTS[j].offset[0], JOINTS[j].offset[1], JOINTS[j].offset[2]};
        double r[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1}, turn[9];
        for (int c = 0; c < JOINTS[j].count; c++) {
            double v = FRAMES[f][value++];
            int ch = JOINTS[j].channels[c];
            if (ch < 3) {
                t[ch] = v;
            } else {
                axis_matrix(ch - 3, v, turn);
                mul3(r, turn, r);
            }
        }
        int p = JOINTS[j].parent;
        if (p < 0) {
            memcpy(world_r[j], r, sizeof r);
            memcpy(out[j], t, sizeof t);
            continue;
        }
        mul3(world_r[p], r, world_r[j]);
        for (int i = 0; i < 3; i++)
            out[j][i] =
                out[p][i] + world_r[p][i * 3] * t[0] + world_r[p][i * 3 + 1] * t[1] + world_r[p][i * 3 + 2] * t[2];
    }
}

static void test_fixture(void **state)
{
    (void)state;
    char path[1024];
    sinew_model *m = load_or_fail(fixture_path("mixed_channels.bvh", path, sizeof path));
    static const char *const names[6] = {"hips", "thigh", "shin", "EndSite_shin", "still", "EndSite_still"};
    assert_int_equal(m->node_count, 6);
    for (int j = 0; j < 6; j++) {
        assert_string_equal(m->node_names[j], names[j]);
        assert_int_equal(m->node_parents[j], JOINTS[j].parent);
    }
    /* every node a joint of the skeleton; no mesh, no material */
    assert_int_equal(m->skin_count, 1);
    assert_int_equal(m->skins[0].joint_count, 6);
    assert_int_equal(m->mesh_count, 0);
    assert_int_equal(m->material_count, 0);
    /* the rest pose: the OFFSETs */
    sinew_mat4 *rest = pose_worlds(m, NULL, 0.0f);
    assert_near(rest[0].m[12], 1.0, 1e-6, "hips rest x");
    assert_near(rest[3].m[13], 2.0 - 1.0 - 2.0 - 1.5, 1e-6, "the shin's End Site at rest");
    free(rest);
    /* one clip: 3 frames half a second apart; "still" is one rotation key */
    assert_int_equal(m->clip_count, 1);
    const sinew_clip *clip = &m->clips[0];
    assert_string_equal(clip->name, "Motion");
    assert_float_equal(clip->duration, 1.0f, 0.0f);
    assert_float_equal(clip->frame_rate, 2.0f, 0.0f);
    for (int f = 0; f < 3; f++) {
        double expect[6][3];
        expected_positions(f, expect);
        sinew_mat4 *w = pose_worlds(m, clip, 0.5f * (float)f);
        double worst = 0.0;
        for (int j = 0; j < 6; j++)
            for (int i = 0; i < 3; i++)
                worst = fmax(worst, fabs(w[j].m[12 + i] - expect[j][i]));
        print_message("frame %d: joints within %.2g of the file's numbers\n", f, worst);
        assert_true(worst < 2e-5);
        free(w);
    }
    sinew_model_free(m);
}

/* Imports `text` from memory as a .bvh: the result, the model (or NULL) and the error. */
static sinew_result from_text(const char *text, size_t size, sinew_model **m, sinew_error *error)
{
    memset(error, 0, sizeof *error);
    *m = NULL;
    return sinew_import_memory(text, size, "bvh", &(sinew_import_desc){.path = "text.bvh"}, m, error);
}

static bool warned(const sinew_model *m, const char *part)
{
    for (uint32_t i = 0; i < m->warning_count; i++)
        if (strstr(m->warnings[i], part))
            return true;
    return false;
}

static const char SMALL[] = "HIERARCHY\nROOT a\n{\nOFFSET 0 0 0\nCHANNELS 3 Xposition Yposition Zposition\n"
                            "JOINT b\n{\nOFFSET 0 1 0\nCHANNELS 1 Zrotation\nEnd Site\n{\nOFFSET 0 1 0\n}\n}\n}\n"
                            "MOTION\nFrames: 2\nFrame Time: 0.1\n0 0 0 0\n1 0 0 90\n";

static void test_files_in_the_wild(void **state)
{
    (void)state;
    sinew_model *m;
    sinew_error error;
    /* lower case keywords, CRLF, a byte order mark, braces on the joint's line, a name with spaces,
     * "Frames :" apart, two roots, numbers as C writes them, and no newline at the end (the
     * bytes from memory are not NUL-terminated: the reader copies them) */
    static const char wild[] = "\xEF\xBB\xBF"
                               "hierarchy\r\nroot Left Hip {\r\n offset 0 0 0\r\n channels 1 xrotation\r\n"
                               " end site {\r\n  offset +1 .5 1.\r\n }\r\n}\r\nROOT other\r\n{\r\nOFFSET 2 0 0\r\n"
                               "CHANNELS 0\r\n}\r\nmotion\r\nFrames : 2\r\nframe time : 0.25\r\n0\r\n90";
    char *exact = malloc(sizeof wild - 1);
    memcpy(exact, wild, sizeof wild - 1); /* the heap block ends where the text does (ASan sees a read past it) */
    if (from_text(exact, sizeof wild - 1, &m, &error) != SINEW_OK)
        fail_msg("%s", error.message);
    free(exact);
    assert_int_equal(m->node_count, 3);
    assert_string_equal(m->node_names[0], "Left Hip");
    assert_string_equal(m->node_names[1], "EndSite_Left Hip");
    assert_int_equal(m->node_parents[2], -1);
    assert_float_equal(m->clips[0].duration, 0.25f, 0.0f);
    sinew_mat4 *w = pose_worlds(m, &m->clips[0], 0.25f); /* 90 degrees about x: (1, .5, 1) -> (1, -1, .5) */
    assert_near(w[1].m[13], -1.0, 1e-6, "the End Site turned");
    assert_near(w[1].m[14], 0.5, 1e-6, "the End Site turned");
    free(w);
    sinew_model_free(m);

    /* scale channels (some exporters write them) and a joint with two End Sites, each named (the
     * second's brace on its line) */
    static const char scaled[] = "HIERARCHY\nROOT s\n{\nOFFSET 0 0 0\nCHANNELS 2 Yrotation Xscale\n"
                                 "End Site\n{\nOFFSET 1 0 0\n}\nEnd Site{\nOFFSET 0 1 0\n}\n}\n"
                                 "MOTION\nFrames: 2\nFrame Time: 1\n0 1\n90 2\n";
    if (from_text(scaled, sizeof scaled - 1, &m, &error) != SINEW_OK)
        fail_msg("%s", error.message);
    assert_string_equal(m->node_names[1], "EndSite_s");
    assert_string_equal(m->node_names[2], "EndSite_s_2");
    w = pose_worlds(m, &m->clips[0], 1.0f); /* x scaled by 2, then turned 90 degrees about y: (2, 0, 0) -> (0, 0, -2) */
    assert_near(w[1].m[12], 0.0, 1e-6, "the scaled End Site turned");
    assert_near(w[1].m[14], -2.0, 1e-6, "the scaled End Site turned");
    assert_near(w[2].m[13], 1.0, 1e-6, "the End Site above, not scaled");
    free(w);
    sinew_model_free(m);

    /* a MOTION cut short: the whole frames kept, with a warning; numbers past the last frame: a warning */
    char text[512];
    snprintf(text, sizeof text, "%s", SMALL);
    strstr(text, "Frames: 2")[8] = '5';
    assert_int_equal(from_text(text, strlen(text), &m, &error), SINEW_OK);
    assert_true(warned(m, "ends after 2 of its 5 frames"));
    assert_float_equal(m->clips[0].duration, 0.1f, 1e-7f);
    sinew_model_free(m);
    snprintf(text, sizeof text, "%s2 0 0 0\n", SMALL);
    assert_int_equal(from_text(text, strlen(text), &m, &error), SINEW_OK);
    assert_true(warned(m, "line 21: numbers after the last of the 2 frames"));
    sinew_model_free(m);
    /* no frames, or no time between them */
    snprintf(text, sizeof text, "%.*sFrames: 0\nFrame Time: 0.1\n", (int)(strstr(SMALL, "Frames") - SMALL), SMALL);
    assert_int_equal(from_text(text, strlen(text), &m, &error), SINEW_OK);
    assert_int_equal(m->clip_count, 0);
    assert_int_equal(m->node_count, 3);
    sinew_model_free(m);
    snprintf(text, sizeof text, "%s", SMALL);
    memcpy(strstr(text, "0.1"), "0.0", 3);
    assert_int_equal(from_text(text, strlen(text), &m, &error), SINEW_OK);
    assert_true(warned(m, "played at 30 frames a second"));
    sinew_model_free(m);
}

static void test_broken_files(void **state)
{
    (void)state;
    static const struct {
        const char *from, *to, *message;
        uint32_t line;
    } cases[] = {
        {"HIERARCHY", "HIERARCHX", "a BVH file starts with HIERARCHY", 1},
        {"CHANNELS 1 Zrotation", "CHANNELS 1 Wrotation", "\"Wrotation\" is not a BVH channel (Xposition", 9},
        {"CHANNELS 1 Zrotation", "CHANNELS 1.5 Zrotation", "not a whole number from 0 to 64", 9},
        {"CHANNELS 1 Zrotation", "CHANNELS 99 Zrotation", "not a whole number from 0 to 64", 9},
        {"OFFSET 0 1 0\nCH", "OFFSET 0 1x 0\nCH", "\"1x\" is not a number", 8},
        {"OFFSET 0 1 0\nCH", "OFFSET 0 1e99 0\nCH", "not a finite number a float holds", 8},
        {"1 0 0 90", "1 0 nan 90", "\"nan\" is not a finite number", 20},
        {"}\n}\nMOTION", "}\nMOTION", "MOTION before the joint \"a\" is closed", 15},
        {"}\nMOTION", "}\n}\nMOTION", "a '}' that closes no joint", 16},
        {"JOINT b\n{", "JOINT b\n(", "\"(\" where a '{' should open the joint", 7},
        {"ROOT a", "JOINT a", "a JOINT outside every ROOT", 2},
        {"ROOT a", "ROOT ", "ROOT without a name", 2},
        {"End Site", "End Sight", "\"End Sight\" where \"End Site\" should be", 10},
        {"End Site", "End", "\"End\" where \"End Site\" should be", 10},
        {"MOTION", "MOTIONS", "\"MOTIONS\" in the HIERARCHY", 16},
        {"MOTION\nFrames: 2\nFrame Time: 0.1\n0 0 0 0\n1 0 0 90\n", "", "the file ends in its HIERARCHY", 16},
        {"Frames: 2", "Frames: -2", "not a whole number of frames", 17},
        {"Frames: 2", "Frame: 2", "\"Frame:\" where \"Frames:\" should follow MOTION", 17},
        {"Frame Time", "Frame Rate", "\"Frame Rate:\" where \"Frame Time:\" should be", 18},
    };
    for (size_t i = 0; i < sizeof cases / sizeof *cases; i++) {
        char text[512];
        const char *at = strstr(SMALL, cases[i].from);
        assert_non_null(at);
        snprintf(text, sizeof text, "%.*s%s%s", (int)(at - SMALL), SMALL, cases[i].to, at + strlen(cases[i].from));
        sinew_model *m;
        sinew_error error;
        sinew_result r = from_text(text, strlen(text), &m, &error);
        print_message("%-22s -> %s\n", cases[i].to, error.message);
        assert_int_equal(r, SINEW_ERROR_FORMAT);
        assert_null(m);
        if (!strstr(error.message, cases[i].message) || !strstr(error.message, "text.bvh"))
            fail_msg("case %zu: \"%s\"", i, error.message);
        assert_int_equal(error.line, cases[i].line);
        assert_string_equal(error.file, "text.bvh");
    }
}

/* Every prefix of the fixture: refused with a message naming the file, or read with a warning
 * that frames are missing; only a cut inside the last number (which reads as a shorter number)
 * or in the white space after it passes unremarked. */
static void test_every_prefix(void **state)
{
    (void)state;
    char src[1024];
    size_t size;
    char *bytes = read_file(fixture_path("mixed_channels.bvh", src, sizeof src), &size);
    size_t last = size;
    while (last > 0 && strchr(" \t\r\n", bytes[last - 1]))
        last--;
    while (last > 0 && !strchr(" \t\r\n", bytes[last - 1]))
        last--;
    uint32_t refused = 0, warned_about = 0;
    for (size_t n = 0; n < size; n++) {
        sinew_model *m = NULL;
        sinew_error error = {0};
        sinew_result r = sinew_import_memory(bytes, n, "bvh", &(sinew_import_desc){.path = "cut.bvh"}, &m, &error);
        if (r != SINEW_OK) {
            refused++;
            if (!strstr(error.message, "cut.bvh"))
                fail_msg("cut to %zu bytes: \"%s\" does not name the file", n, error.message);
            continue;
        }
        bool said = false;
        for (uint32_t w = 0; w < m->warning_count; w++)
            said = said || (strstr(m->warnings[w], "cut.bvh") && strstr(m->warnings[w], " of its "));
        if (!said && n <= last)
            fail_msg("cut to %zu of %zu bytes: read without a word", n, size);
        warned_about += said;
        sinew_model_free(m);
    }
    print_message("mixed_channels.bvh: %u of %zu prefixes refused, %u read with a warning\n", refused, size,
                  warned_about);
    free(bytes);
}

/* Hostile counts: a billion frames claimed for two, joints nested 5000 deep. */
static void test_hostile(void **state)
{
    (void)state;
    char text[512];
    snprintf(text, sizeof text, "%s", SMALL);
    char *frames = strstr(text, "Frames: 2");
    memmove(frames + 17, frames + 9, strlen(frames + 9) + 1);
    memcpy(frames, "Frames: 999999999", 17);
    sinew_model *m;
    sinew_error error = {0};
    /* a 4 MiB limit: the billion frames are not allocated for */
    assert_int_equal(sinew_import_memory(text, strlen(text), "bvh",
                                         &(sinew_import_desc){.path = "many.bvh", .memory_limit = 4 << 20}, &m, &error),
                     SINEW_OK);
    assert_true(warned(m, "ends after 2 of its 999999999 frames"));
    sinew_model_free(m);
    size_t depth = 5000, cap = depth * 24 + 64, n = 0;
    char *deep = malloc(cap);
    n += (size_t)snprintf(deep + n, cap - n, "HIERARCHY\n");
    for (size_t i = 0; i < depth; i++)
        n += (size_t)snprintf(deep + n, cap - n, "%s j%zu {\n", i ? "JOINT" : "ROOT", i);
    assert_int_equal(sinew_import_memory(deep, n, "bvh", NULL, &m, &error), SINEW_ERROR_FORMAT);
    assert_non_null(strstr(error.message, "nested more than 1024 deep"));
    free(deep);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_fixture),      cmocka_unit_test(test_files_in_the_wild),
        cmocka_unit_test(test_broken_files), cmocka_unit_test(test_every_prefix),
        cmocka_unit_test(test_hostile),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
