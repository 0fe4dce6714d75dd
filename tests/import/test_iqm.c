/* sinew's IQM reader: the hand-made fixture (tests/fixtures/make_iqm.py) read exactly (the
 * turn from Z up, v flipped, winding, weights, a looping clip with its wrap segment), its
 * animation-only twin applied joint by joint, mrfixit.iqm's rest pose equal to what Assimp
 * reads of its meshes, raylib's guy.iqm played from guyanim.iqm equal to its own clips, and
 * broken files refused with a message. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "helpers.h"

static double rotation_angle_deg(const sinew_mat4 *m)
{
    sinew_transform t;
    sinew_mat4_decompose(m, &t);
    return 2.0 * acos(fmin(1.0, fabs((double)t.rotation[3]))) * 180.0 / M_PI;
}

static void test_fixture(void **state)
{
    (void)state;
    char path[1024];
    sinew_model *m = load_or_fail(fixture_path("two_bone.iqm", path, sizeof path));
    assert_int_equal(m->node_count, 3);
    assert_string_equal(m->node_names[1], "lower");
    assert_string_equal(m->node_names[2], "upper");
    assert_int_equal(m->node_parents[2], 1);
    assert_int_equal(m->mesh_count, 1);
    const sinew_mesh *mesh = &m->meshes[0];
    assert_int_equal(mesh->vertex_count, 4);
    /* at rest: the file's (x, 0, z) stands up as (x, z, 0); normals -Y face +Z */
    uint32_t count;
    sinew_mat4 *rest = pose_worlds(m, NULL, 0.0f);
    float *p = posed_vertices(m, rest, &count);
    static const float expect[4][3] = {{-0.5f, 0, 0}, {0.5f, 0, 0}, {-0.5f, 2, 0}, {0.5f, 2, 0}};
    double position = 0.0;
    for (uint32_t v = 0; v < 4; v++)
        for (int c = 0; c < 3; c++)
            position = fmax(position, fabs(p[v * 3 + c] - expect[v][c]));
    /* v flipped: IQM's images start at the top */
    assert_float_equal(mesh->uvs[0 * 2 + 1], 0.0f, 0.0f);
    assert_float_equal(mesh->uvs[2 * 2 + 1], 1.0f, 0.0f);
    /* counter-clockwise seen from the side the normals face (+Z after the turn) */
    for (uint32_t t = 0; t < mesh->index_count / 3; t++) {
        const float *a = &p[mesh->indices[t * 3] * 3], *b = &p[mesh->indices[t * 3 + 1] * 3],
                    *c = &p[mesh->indices[t * 3 + 2] * 3];
        double z = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
        assert_true(z > 0.0);
    }
    /* 128/255 and 127/255 on the top vertices */
    assert_float_equal(mesh->weights[2 * mesh->influence_count], 128.0f / 255.0f, 1e-6f);
    /* the loop: 3 frames at 2 a second last 1.5 s, the last half second back to frame 0 */
    assert_int_equal(m->clip_count, 1);
    assert_float_equal(m->clips[0].duration, 1.5f, 1e-6f);
    double angles[4];
    const float times[4] = {0.0f, 0.5f, 1.0f, 1.25f};
    for (int k = 0; k < 4; k++) {
        sinew_mat4 *w = pose_worlds(m, &m->clips[0], times[k]);
        /* relative to "lower", which stays turned by the root's -90 degrees */
        sinew_mat4 rel;
        sinew_transform lt, ut;
        sinew_mat4_decompose(&w[1], &lt);
        sinew_mat4_decompose(&w[2], &ut);
        float q[4] = {-lt.rotation[0], -lt.rotation[1], -lt.rotation[2], lt.rotation[3]}, r[4];
        r[0] = q[3] * ut.rotation[0] + q[0] * ut.rotation[3] + q[1] * ut.rotation[2] - q[2] * ut.rotation[1];
        r[1] = q[3] * ut.rotation[1] - q[0] * ut.rotation[2] + q[1] * ut.rotation[3] + q[2] * ut.rotation[0];
        r[2] = q[3] * ut.rotation[2] + q[0] * ut.rotation[1] - q[1] * ut.rotation[0] + q[2] * ut.rotation[3];
        r[3] = q[3] * ut.rotation[3] - q[0] * ut.rotation[0] - q[1] * ut.rotation[1] - q[2] * ut.rotation[2];
        sinew_transform_to_mat4(&(sinew_transform){{0, 0, 0}, {r[0], r[1], r[2], r[3]}, {1, 1, 1}}, &rel);
        angles[k] = rotation_angle_deg(&rel);
        free(w);
    }
    print_message("two_bone.iqm: rest positions within %.1e; \"upper\" turned %.2f, %.2f, %.2f, %.2f degrees at 0, "
                  "0.5, 1, 1.25 s (0, 90, 45, and 22.5 on the way back to frame 0)\n",
                  position, angles[0], angles[1], angles[2], angles[3]);
    assert_true(position < 1e-6);
    assert_true(fabs(angles[0]) < 0.01 && fabs(angles[1] - 90.0) < 0.01 && fabs(angles[2] - 45.0) < 0.01 &&
                fabs(angles[3] - 22.5) < 0.05);
    free(p);
    free(rest);
    sinew_model_free(m);
}

/* Largest difference between two models' world matrices over a clip of each. */
static double clip_difference(const sinew_model *a, const sinew_clip *ca, const sinew_model *b, const sinew_clip *cb)
{
    double worst = 0.0;
    for (float t = 0.0f; t <= ca->duration; t += ca->duration / 16.0f) {
        sinew_mat4 *x = pose_worlds(a, ca, t), *y = pose_worlds(b, cb, t);
        worst = fmax(worst, worlds_difference(x, y, a->node_count));
        free(x);
        free(y);
    }
    return worst;
}

/* An animation-only file (poses without joint names) on the model of the same hierarchy. */
static void check_animation_file(const char *model_path, const char *anim_path, double *difference, uint32_t *matched)
{
    sinew_model *model = load_or_fail(model_path), *anim = load_or_fail(anim_path), *out = NULL;
    int32_t *match = malloc(model->node_count * sizeof *match);
    *matched = sinew_retarget_matches(model, anim, match);
    sinew_error error = {0};
    assert_int_equal(sinew_retarget(&(sinew_retarget_desc){.target = model, .source = anim}, &out, &error), SINEW_OK);
    assert_int_equal(out->clip_count, model->clip_count + anim->clip_count);
    *difference = 0.0;
    for (uint32_t c = 0; c < anim->clip_count; c++) {
        assert_string_equal(out->clips[c].name, model->clips[c].name);
        *difference = fmax(*difference, clip_difference(out, &out->clips[c], model, &model->clips[c]));
    }
    free(match);
    sinew_model_free(out);
    sinew_model_free(anim);
    sinew_model_free(model);
}

static void test_animation_only_files(void **state)
{
    (void)state;
    char a[1024], b[1024];
    double diff;
    uint32_t matched;
    check_animation_file(fixture_path("two_bone.iqm", a, sizeof a), fixture_path("two_bone_anim.iqm", b, sizeof b),
                         &diff, &matched);
    print_message("two_bone_anim.iqm on two_bone.iqm: %u nodes matched by index, clips within %.1e of its own\n",
                  matched, diff);
    assert_int_equal(matched, 3);
    assert_true(diff < 1e-6);
    if (!testdata_path("raylib/guy.iqm", a, sizeof a) || !testdata_path("raylib/guyanim.iqm", b, sizeof b))
        skip();
    check_animation_file(a, b, &diff, &matched);
    print_message("raylib's guyanim.iqm on guy.iqm: %u nodes matched by index, \"jump\" and \"dance\" within %.1e of "
                  "guy.iqm's own\n",
                  matched, diff);
    assert_int_equal(matched, 15);
    assert_true(diff < 1e-6);
}

static void test_mrfixit_rest_matches_assimp(void **state)
{
    (void)state;
    char path[1024];
    if (!testdata_path("assimp/IQM/mrfixit.iqm", path, sizeof path))
        skip();
    sinew_model *own = load_or_fail(path), *assimp = NULL;
    sinew_error error = {0};
    assert_int_equal(sinew_import(&(sinew_import_desc){.path = path, .assimp = true}, &assimp, &error), SINEW_OK);
    uint32_t na, nb;
    sinew_mat4 *wa = pose_worlds(own, NULL, 0.0f), *wb = pose_worlds(assimp, NULL, 0.0f);
    float *pa = posed_vertices(own, wa, &na), *pb = posed_vertices(assimp, wb, &nb);
    assert_int_equal(na, nb);
    double worst = 0.0, size = 0.0;
    for (uint32_t i = 0; i < na * 3; i++) {
        worst = fmax(worst, fabs(pa[i] - pb[i]));
        size = fmax(size, fabs(pb[i]));
    }
    double uv = 0.0;
    for (uint32_t k = 0; k < own->mesh_count; k++)
        for (uint32_t i = 0; i < own->meshes[k].vertex_count * 2; i++)
            uv = fmax(uv, fabs(own->meshes[k].uvs[i] - assimp->meshes[k].uvs[i]));
    /* posed by its own clip it moves, and stays finite */
    sinew_mat4 *wc = pose_worlds(own, &own->clips[0], 2.0f);
    uint32_t nc;
    float *pc = posed_vertices(own, wc, &nc);
    double moved = 0.0;
    for (uint32_t i = 0; i < nc * 3; i++) {
        assert_true(isfinite(pc[i]));
        moved = fmax(moved, fabs(pc[i] - pa[i]));
    }
    print_message("mrfixit.iqm: %u joints; skinned at rest vs Assimp's unskinned meshes: %u vertices within %.1e "
                  "(size %.1f), UVs within %.1e; at 2 s of \"idle\" vertices move up to %.2f\n",
                  own->skins[0].joint_count, na, worst, size, uv, moved);
    assert_true(worst < 1e-4 * size && uv < 1e-6 && moved > 0.01);
    free(pa);
    free(pb);
    free(pc);
    free(wa);
    free(wb);
    free(wc);
    sinew_model_free(own);
    sinew_model_free(assimp);
}

/* The fixture with one 32-bit field at `offset` set to `value`. */
static sinew_result import_edited(uint32_t offset, uint32_t value, sinew_error *error)
{
    char src[1024], path[1024];
    size_t size;
    unsigned char *bytes = read_file(fixture_path("two_bone.iqm", src, sizeof src), &size);
    assert_non_null(bytes);
    memcpy(bytes + offset, &value, 4);
    write_file(tmp_path("edited.iqm", path, sizeof path), bytes, size);
    free(bytes);
    sinew_model *m = NULL;
    sinew_result r = sinew_import(&(sinew_import_desc){.path = path}, &m, error);
    sinew_model_free(m);
    if (r != SINEW_OK)
        assert_non_null(strstr(error->message, "edited.iqm"));
    return r;
}

static void test_broken_files(void **state)
{
    (void)state;
    sinew_error error = {0};
    assert_int_equal(import_edited(16, 1, &error), SINEW_ERROR_FORMAT); /* version 1 */
    assert_non_null(strstr(error.message, "version 1"));
    assert_int_equal(import_edited(16 + 4 * 14, 0x7ffffff0u, &error), SINEW_ERROR_FORMAT); /* joints past the end */
    assert_non_null(strstr(error.message, "joint table"));
    assert_int_equal(import_edited(16 + 4 * 5, 9, &error), SINEW_ERROR_FORMAT); /* 9 meshes */
    print_message("broken IQM: %s\n", error.message);
    /* a name outside the text block */
    char src[1024];
    size_t size;
    unsigned char *bytes = read_file(fixture_path("two_bone.iqm", src, sizeof src), &size);
    uint32_t ofs_joints;
    memcpy(&ofs_joints, bytes + 16 + 4 * 14, 4);
    free(bytes);
    assert_int_equal(import_edited(ofs_joints, 5000, &error), SINEW_ERROR_FORMAT);
    assert_non_null(strstr(error.message, "text block"));
    /* a position that is not a number (what libFuzzer found first: the builder then wrote a blob
     * its reader refused) */
    uint32_t ofs_arrays, position_offset;
    bytes = read_file(fixture_path("two_bone.iqm", src, sizeof src), &size);
    memcpy(&ofs_arrays, bytes + 16 + 4 * 9, 4);
    memcpy(&position_offset, bytes + ofs_arrays + 16, 4);
    free(bytes);
    assert_int_equal(import_edited(position_offset + 4, 0x7fc00000u, &error), SINEW_ERROR_DATA);
    assert_non_null(strstr(error.message, "not finite"));
    /* a joint whose parent comes after it */
    assert_int_equal(import_edited(ofs_joints + 4, 1, &error), SINEW_ERROR_FORMAT);
    assert_non_null(strstr(error.message, "parent"));
    /* the same file named .iqm that is not one */
    char path[1024];
    write_file(tmp_path("not.iqm", path, sizeof path), "hello, world", 12);
    sinew_model *m = NULL;
    assert_int_equal(sinew_import(&(sinew_import_desc){.path = path}, &m, &error), SINEW_ERROR_FORMAT);
    assert_non_null(strstr(error.message, "INTERQUAKEMODEL"));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_fixture),
        cmocka_unit_test(test_animation_only_files),
        cmocka_unit_test(test_mrfixit_rest_matches_assimp),
        cmocka_unit_test(test_broken_files),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
