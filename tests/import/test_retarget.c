/* sinew_retarget (`--anim`): the demo's walk on a renamed (Mixamo names with the
 * "mixamorig:" prefix) and re-proportioned (1.3x) copy of itself gives the demo's joint
 * rotations, with the hips' motion scaled by the legs' ratio; CMU's 01_01.bvh drives the demo
 * humanoid with the mocap's posture; ozz's animation-only walk.fbx drives arnaud.fbx by name;
 * name maps are read and checked. (IQM animation files, matched by index: test_iqm.c.) */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "helpers.h"

static const char *mixamo_name(const char *unity)
{
    static const char *const map[][2] = {{"Chest", "Spine1"},
                                         {"UpperChest", "Spine2"},
                                         {"LeftUpperArm", "LeftArm"},
                                         {"LeftLowerArm", "LeftForeArm"},
                                         {"RightUpperArm", "RightArm"},
                                         {"RightLowerArm", "RightForeArm"},
                                         {"LeftUpperLeg", "LeftUpLeg"},
                                         {"LeftLowerLeg", "LeftLeg"},
                                         {"RightUpperLeg", "RightUpLeg"},
                                         {"RightLowerLeg", "RightLeg"},
                                         {"LeftToes", "LeftToeBase"},
                                         {"RightToes", "RightToeBase"},
                                         {"LeftFingers", "LeftHandIndex1"},
                                         {"RightFingers", "RightHandIndex1"}};
    for (size_t i = 0; i < sizeof map / sizeof map[0]; i++)
        if (strcmp(map[i][0], unity) == 0)
            return map[i][1];
    return unity;
}

static void test_renamed_reproportioned_copy(void **state)
{
    (void)state;
    sinew_model *demo = demo_humanoid();
    uint32_t n = demo->node_count;
    /* the copy: a skeleton only, every name as Mixamo's with its prefix, every offset 1.3x */
    char(*names)[64] = calloc(n, 64);
    const char **name_ptrs = calloc(n, sizeof *name_ptrs);
    sinew_transform *rest = malloc(n * sizeof *rest);
    for (uint32_t i = 0; i < n; i++) {
        snprintf(names[i], 64, "mixamorig:%s", mixamo_name(demo->node_names[i]));
        name_ptrs[i] = names[i];
        rest[i] = demo->node_rest[i];
        for (int k = 0; k < 3; k++)
            rest[i].translation[k] *= 1.3f;
    }
    sinew_model copy = {.source = "renamed copy",
                        .format = "test",
                        .node_count = n,
                        .node_names = name_ptrs,
                        .node_parents = demo->node_parents,
                        .node_rest = rest};
    int32_t *match = malloc(n * sizeof *match);
    uint32_t matched = sinew_retarget_matches(&copy, demo, match);
    sinew_model *out = NULL;
    sinew_error error = {0};
    assert_int_equal(sinew_retarget(&(sinew_retarget_desc){.target = &copy, .source = demo}, &out, &error), SINEW_OK);
    assert_int_equal(out->clip_count, demo->clip_count);
    assert_string_equal(out->clips[0].name, "walk");
    double worst = 0.0, worst_hips = 0.0;
    int32_t hips = sinew_model_find_node(demo, "Hips");
    for (float t = 0.0f; t <= 1.0f; t += 0.1f) {
        sinew_transform *a = pose_locals(demo, &demo->clips[0], t, SINEW_WRAP_CLAMP),
                        *b = pose_locals(out, &out->clips[0], t, SINEW_WRAP_CLAMP);
        for (uint32_t i = 0; i < n; i++) {
            if (match[i] < 0)
                continue;
            double dot = 0.0;
            for (int k = 0; k < 4; k++)
                dot += a[i].rotation[k] * b[i].rotation[k];
            worst = fmax(worst, 1.0 - fabs(dot));
        }
        for (int k = 0; k < 3; k++)
            worst_hips = fmax(worst_hips, fabs(b[hips].translation[k] - 1.3 * a[hips].translation[k]));
        free(a);
        free(b);
    }
    print_message("renamed, 1.3x copy: %u of %u joints matched; walk's rotations 1 - |dot| <= %.1e; hips at 1.3x the "
                  "demo's to %.1e m\n",
                  matched, n, worst, worst_hips);
    assert_true(matched >= 22);
    assert_true(worst < 1e-6);
    assert_true(worst_hips < 1e-4);
    free(match);
    sinew_model_free(out);
    free(names);
    free(name_ptrs);
    free(rest);
    sinew_model_free(demo);
}

/* The direction from node a to node b in a posed model. */
static void direction(const sinew_model *m, const sinew_mat4 *w, const char *a, const char *b, double out[3])
{
    int32_t i = sinew_model_find_node(m, a), j = sinew_model_find_node(m, b);
    assert_true(i >= 0 && j >= 0);
    double len = 0.0;
    for (int k = 0; k < 3; k++)
        out[k] = w[j].m[12 + k] - w[i].m[12 + k], len += out[k] * out[k];
    for (int k = 0; k < 3; k++)
        out[k] /= sqrt(len);
}

/* The angle (radians) between bone a0 -> a1 of one posed model and b0 -> b1 of another. */
static double bone_angle(const sinew_model *ma, const sinew_mat4 *wa, const char *a0, const char *a1,
                         const sinew_model *mb, const sinew_mat4 *wb, const char *b0, const char *b1)
{
    double u[3], v[3];
    direction(ma, wa, a0, a1, u);
    direction(mb, wb, b0, b1, v);
    return acos(fmin(1.0, u[0] * v[0] + u[1] * v[1] + u[2] * v[2]));
}

static void test_cmu_bvh_drives_the_demo(void **state)
{
    (void)state;
    char path[1024];
    if (!testdata_path("assimp/BVH/01_01.bvh", path, sizeof path))
        skip();
    sinew_model *bvh = load_or_fail(path), *demo = demo_humanoid(), *out = NULL;
    int32_t *match = malloc(demo->node_count * sizeof *match);
    uint32_t matched = sinew_retarget_matches(demo, bvh, match);
    sinew_error error = {0};
    assert_int_equal(sinew_retarget(&(sinew_retarget_desc){.target = demo, .source = bvh}, &out, &error), SINEW_OK);
    assert_int_equal(out->clip_count, demo->clip_count + bvh->clip_count);
    assert_string_equal(out->clips[0].name, bvh->clips[0].name);
    /* the same posture: back, upper arms and thighs point the same way */
    static const char *const bones[][4] = {{"Hips", "Head", "Hips", "Head"},
                                           {"LeftUpperArm", "LeftLowerArm", "LeftArm", "LeftForeArm"},
                                           {"RightUpperLeg", "RightLowerLeg", "RightUpLeg", "RightLeg"},
                                           {"LeftLowerLeg", "LeftFoot", "LeftLeg", "LeftFoot"}};
    double worst = 0.0;
    for (float t = 0.5f; t < bvh->clips[0].duration; t += 1.0f) {
        sinew_mat4 *a = pose_worlds(out, &out->clips[0], t), *b = pose_worlds(bvh, &bvh->clips[0], t);
        for (size_t i = 0; i < sizeof bones / sizeof bones[0]; i++)
            worst = fmax(worst, bone_angle(out, a, bones[i][0], bones[i][1], bvh, b, bones[i][2], bones[i][3]));
        free(a);
        free(b);
    }
    print_message("01_01.bvh on the demo: %u joints matched; back, arm and leg directions within %.1f degrees of the "
                  "mocap's\n",
                  matched, worst * 180.0 / M_PI);
    assert_true(matched >= 14);
    assert_true(worst * 180.0 / M_PI < 20.0);
    free(match);
    sinew_model_free(out);
    sinew_model_free(demo);
    sinew_model_free(bvh);
}

/* ozz's walk.fbx (animation only: a skeleton and a clip, no mesh) on arnaud.fbx (a character of
 * the same skeleton family in bind pose), joints by name: the limbs point as the walk's do. */
static void test_animation_only_fbx(void **state)
{
    (void)state;
    char a[1024], b[1024];
    if (!testdata_path("ozz/pab/arnaud.fbx", a, sizeof a) || !testdata_path("ozz/pab/walk.fbx", b, sizeof b))
        skip();
    sinew_model *arnaud = load_or_fail(a), *walk = load_or_fail(b), *out = NULL;
    int32_t *match = malloc(arnaud->node_count * sizeof *match);
    uint32_t matched = sinew_retarget_matches(arnaud, walk, match);
    sinew_error error = {0};
    assert_int_equal(sinew_retarget(&(sinew_retarget_desc){.target = arnaud, .source = walk}, &out, &error), SINEW_OK);
    assert_float_equal(out->clips[0].duration, walk->clips[0].duration, 1e-5f);
    static const char *const bones[][2] = {{"LeftArm", "LeftForeArm"},
                                           {"RightForeArm", "RightHand"},
                                           {"LeftUpLeg", "LeftLeg"},
                                           {"RightLeg", "RightFoot"},
                                           {"Spine", "Neck"}};
    double worst = 0.0, swing = 0.0;
    sinew_mat4 *first = malloc(out->node_count * sizeof *first);
    for (float t = 0.0f; t <= walk->clips[0].duration; t += walk->clips[0].duration / 8.0f) {
        sinew_mat4 *x = pose_worlds(out, &out->clips[0], t), *y = pose_worlds(walk, &walk->clips[0], t);
        for (size_t i = 0; i < sizeof bones / sizeof bones[0]; i++)
            worst = fmax(worst, bone_angle(out, x, bones[i][0], bones[i][1], walk, y, bones[i][0], bones[i][1]));
        /* the left thigh swings through the walk */
        if (t == 0.0f)
            memcpy(first, x, out->node_count * sizeof *first);
        swing = fmax(swing, bone_angle(out, x, "LeftUpLeg", "LeftLeg", out, first, "LeftUpLeg", "LeftLeg"));
        free(x);
        free(y);
    }
    free(first);
    print_message("walk.fbx on arnaud.fbx: %u of %u nodes matched by name; arms, legs and back within %.2f degrees "
                  "of the walk's; the left thigh swings %.0f degrees\n",
                  matched, arnaud->node_count, worst * 180.0 / M_PI, swing * 180.0 / M_PI);
    assert_true(matched >= 50);
    assert_true(worst * 180.0 / M_PI < 2.0);
    assert_true(swing * 180.0 / M_PI > 20.0);
    free(match);
    sinew_model_free(out);
    sinew_model_free(walk);
    sinew_model_free(arnaud);
}

static void test_name_maps(void **state)
{
    (void)state;
    sinew_model *demo = demo_humanoid(), *out = NULL;
    char map[1024];
    tmp_path("names.json", map, sizeof map);
    const char *good = "{\"Head\": \"Neck\"}";
    write_file(map, good, strlen(good));
    sinew_error error = {0};
    assert_int_equal(
        sinew_retarget(&(sinew_retarget_desc){.target = demo, .source = demo, .name_map = map}, &out, &error),
        SINEW_OK);
    sinew_model_free(out);
    const char *bad = "{\"Head\": \"Tail\"}";
    write_file(map, bad, strlen(bad));
    assert_int_equal(
        sinew_retarget(&(sinew_retarget_desc){.target = demo, .source = demo, .name_map = map}, &out, &error),
        SINEW_ERROR_DATA);
    assert_non_null(strstr(error.message, "Tail"));
    assert_non_null(strstr(error.message, "names.json:1:2: \"Head\" -> \"Tail\""));
    write_file(map, "[1,2]", 5);
    assert_int_equal(
        sinew_retarget(&(sinew_retarget_desc){.target = demo, .source = demo, .name_map = map}, &out, &error),
        SINEW_ERROR_FORMAT);
    assert_non_null(strstr(error.message, "a name map is a JSON object"));
    /* broken JSON and a member that is not a string: where, as muscle files say it */
    const char *broken = "{\n  \"Head\": \"Neck\"\n  \"Neck\": \"Head\"\n}";
    write_file(map, broken, strlen(broken));
    assert_int_equal(
        sinew_retarget(&(sinew_retarget_desc){.target = demo, .source = demo, .name_map = map}, &out, &error),
        SINEW_ERROR_FORMAT);
    assert_non_null(strstr(error.message, "names.json:3:3: not valid JSON here: a comma missing"));
    const char *number = "{\"Head\": \"Neck\",\n \"Neck\": 7}";
    write_file(map, number, strlen(number));
    assert_int_equal(
        sinew_retarget(&(sinew_retarget_desc){.target = demo, .source = demo, .name_map = map}, &out, &error),
        SINEW_ERROR_FORMAT);
    assert_non_null(strstr(error.message, "names.json:2:2: \"Neck\": the target name is not a string"));
    sinew_model_free(demo);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_renamed_reproportioned_copy),
        cmocka_unit_test(test_cmu_bvh_drives_the_demo),
        cmocka_unit_test(test_animation_only_fbx),
        cmocka_unit_test(test_name_maps),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
