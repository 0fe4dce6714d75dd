/* The builder (raw -> blob) and the blob reader: round trip, repairs with warnings,
 * refusals of bad data, every prefix and every flipped byte of a blob refused. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "helpers.h"
#include "import/internal.h"

static void *dup_bytes(const void *src, size_t n)
{
    void *p = malloc(n ? n : 1);
    assert_non_null(p);
    memcpy(p, src, n);
    return p;
}

/* Two nodes (root, joint), one triangle skinned to the joint with `k` influence slots,
 * one material, one clip with a 3-key rotation track on the joint. */
static void make_raw(raw_model *m, uint32_t k)
{
    memset(m, 0, sizeof *m);
    m->source = raw_strdup("hand-made");
    m->format = raw_strdup("test");
    m->node_count = 2;
    m->node_names = calloc(2, sizeof(char *));
    m->node_names[0] = raw_strdup("root");
    m->node_names[1] = raw_strdup("joint");
    const int32_t parents[] = {-1, 0};
    const sinew_transform rest[] = {{{0, 0, 0}, {0, 0, 0, 1}, {1, 1, 1}}, {{0, 1, 0}, {0, 0, 0, 1}, {1, 1, 1}}};
    m->node_parents = dup_bytes(parents, sizeof parents);
    m->node_rest = dup_bytes(rest, sizeof rest);

    m->skin_count = 1;
    m->skins = calloc(1, sizeof *m->skins);
    m->skins[0].joint_count = 1;
    m->skins[0].joints = calloc(1, sizeof(uint32_t));
    m->skins[0].joints[0] = 1;
    const sinew_mat4 ibm = {{1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, -1, 0, 1}};
    m->skins[0].inverse_bind = dup_bytes(&ibm, sizeof ibm);

    m->mesh_count = 1;
    m->meshes = calloc(1, sizeof *m->meshes);
    raw_mesh *mesh = &m->meshes[0];
    mesh->name = raw_strdup("tri");
    mesh->vertex_count = 3;
    const float positions[] = {0, 1, 0, 1, 1, 0, 0, 2, 0};
    mesh->positions = dup_bytes(positions, sizeof positions);
    const uint32_t indices[] = {0, 1, 2};
    mesh->indices = dup_bytes(indices, sizeof indices);
    mesh->index_count = 3;
    mesh->skin = 0;
    mesh->material = 0;
    mesh->influence_count = k;
    mesh->joints = malloc(3 * k * sizeof(uint32_t));
    mesh->weights = calloc(3 * k, sizeof(float));
    for (uint32_t i = 0; i < 3 * k; i++)
        mesh->joints[i] = UINT32_MAX;
    for (uint32_t v = 0; v < 3; v++) {
        mesh->joints[v * k] = 0;
        mesh->weights[v * k] = 1.0f;
    }

    m->instance_count = 1;
    m->instances = calloc(1, sizeof *m->instances);
    m->instances[0] = (sinew_instance){0, 0, 0};
    m->material_count = 1;
    m->materials = calloc(1, sizeof *m->materials);
    m->materials[0].name = raw_strdup("clay");
    for (int i = 0; i < 4; i++)
        m->materials[0].base_color[i] = 0.5f;

    m->clip_count = 1;
    m->clips = calloc(1, sizeof *m->clips);
    m->clips[0].name = raw_strdup("turn");
    m->clips[0].duration = 2;
    m->clips[0].track_count = 1;
    m->clips[0].tracks = calloc(1, sizeof(raw_track));
    m->clips[0].tracks[0].node = 1;
    raw_channel *rot = &m->clips[0].tracks[0].channels[SINEW_CHANNEL_ROTATION];
    rot->interp = SINEW_INTERP_LINEAR;
    rot->count = 3;
    const float times[] = {0, 1, 2};
    const float quats[] = {0, 0, 0, 1, 0, 0, 0.70710678f, 0.70710678f, 0, 0, 1, 0};
    rot->times = dup_bytes(times, sizeof times);
    rot->values = dup_bytes(quats, sizeof quats);
}

static sinew_model *build_and_load(raw_model *raw, void **blob, size_t *size)
{
    sinew_error error = {0};
    if (raw_model_build(raw, blob, size, &error) != SINEW_OK)
        fail_msg("build failed: %s", error.message);
    sinew_model *model = NULL;
    if (sinew_model_from_blob(*blob, *size, "blob", NULL, &model, &error) != SINEW_OK)
        fail_msg("load failed: %s", error.message);
    return model;
}

static void test_round_trip(void **state)
{
    (void)state;
    raw_model raw;
    make_raw(&raw, 1);
    void *blob;
    size_t size;
    sinew_model *m = build_and_load(&raw, &blob, &size);
    assert_int_equal(m->node_count, 2);
    assert_string_equal(m->node_names[1], "joint");
    assert_int_equal(m->node_parents[1], 0);
    assert_near(m->node_rest[1].translation[1], 1, 0, "rest translation");
    assert_int_equal(m->mesh_count, 1);
    assert_int_equal(m->meshes[0].vertex_count, 3);
    assert_int_equal(m->meshes[0].influence_count, 1);
    assert_near(m->meshes[0].normals[2], 1, 1e-6, "computed normal faces +z");
    assert_near(m->skins[0].inverse_bind[0].m[13], -1, 0, "inverse bind");
    assert_string_equal(m->materials[0].name, "clay");
    assert_null(m->materials[0].maps[SINEW_MAP_BASE_COLOR].path);
    assert_int_equal(m->clip_count, 1);
    assert_string_equal(m->clips[0].name, "turn");
    assert_int_equal(m->clips[0].tracks[0].channels[SINEW_CHANNEL_ROTATION].key_count, 3);
    assert_int_equal(m->clips[0].tracks[0].channels[SINEW_CHANNEL_TRANSLATION].key_count, 0);
    const void *own;
    size_t own_size;
    sinew_model_blob(m, &own, &own_size);
    assert_int_equal(own_size, size);
    assert_memory_equal(own, blob, size);
    sinew_model_free(m);
    free(blob);
    raw_model_free(&raw);
}

static void test_every_prefix_and_flip_refused(void **state)
{
    (void)state;
    raw_model raw;
    make_raw(&raw, 2);
    void *blob;
    size_t size;
    sinew_model *m = build_and_load(&raw, &blob, &size);
    sinew_model_free(m);
    raw_model_free(&raw);
    sinew_error error;
    for (size_t n = 0; n < size; n++) {
        memset(&error, 0, sizeof error);
        m = (sinew_model *)1;
        assert_int_equal(sinew_model_from_blob(blob, n, "prefix", NULL, &m, &error), SINEW_ERROR_FORMAT);
        assert_null(m);
        assert_non_null(strstr(error.message, "prefix"));
    }
    unsigned char *bytes = blob;
    for (size_t i = 0; i < size; i++) {
        for (int bit = 0; bit < 8; bit += 3) {
            bytes[i] ^= (unsigned char)(1u << bit);
            sinew_result r = sinew_model_from_blob(blob, size, "flipped", NULL, &m, &error);
            if (r == SINEW_OK)
                fail_msg("a flip of bit %d in byte %zu was not noticed", bit, i);
            bytes[i] ^= (unsigned char)(1u << bit);
        }
    }
    free(blob);
}

static void test_influences_sorted_limited_normalised(void **state)
{
    (void)state;
    raw_model raw;
    make_raw(&raw, 10);
    /* vertex 0: ten influences, unsorted, summing to 5.5 (weights 0.1 .. 1.0) on one joint
     * index each; the skin gets ten joints */
    raw_skin *skin = &raw.skins[0];
    skin->joint_count = 10;
    skin->joints = realloc(skin->joints, 10 * sizeof(uint32_t));
    skin->inverse_bind = realloc(skin->inverse_bind, 10 * sizeof(sinew_mat4));
    for (uint32_t j = 0; j < 10; j++) {
        skin->joints[j] = 1;
        skin->inverse_bind[j] = skin->inverse_bind[0];
    }
    raw_mesh *mesh = &raw.meshes[0];
    for (uint32_t i = 0; i < 10; i++) {
        mesh->joints[i] = i;
        mesh->weights[i] = 0.1f * (float)(i + 1);
    }
    /* vertex 1: no influences at all */
    mesh->joints[10] = UINT32_MAX;
    mesh->weights[10] = 0;
    void *blob;
    size_t size;
    sinew_model *m = build_and_load(&raw, &blob, &size);
    const sinew_mesh *out = &m->meshes[0];
    assert_int_equal(out->influence_count, 8);
    float sum = 0;
    for (int i = 0; i < 8; i++) {
        sum += out->weights[i];
        if (i)
            assert_true(out->weights[i] <= out->weights[i - 1]);
    }
    assert_near(sum, 1, 1e-6, "weights sum to 1");
    assert_int_equal(out->joints[0], 9);
    assert_near(out->weights[0], 1.0 / 5.2, 1e-6, "largest weight renormalised over the kept 8");
    /* vertex 1 follows the mesh's node (root) through an added joint */
    assert_int_equal(m->skins[0].joint_count, 11);
    assert_int_equal(m->skins[0].joints[out->joints[8]], 0);
    assert_near(out->weights[8], 1, 0, "fallback weight");
    bool warned_truncated = false, warned_unweighted = false;
    for (uint32_t i = 0; i < m->warning_count; i++) {
        warned_truncated |= strstr(m->warnings[i], "more than 8 influences") != NULL;
        warned_unweighted |= strstr(m->warnings[i], "no skin weights") != NULL;
    }
    assert_true(warned_truncated);
    assert_true(warned_unweighted);
    sinew_model_free(m);
    free(blob);
    raw_model_free(&raw);
}

static void test_keys_sorted_and_short_way(void **state)
{
    (void)state;
    raw_model raw;
    make_raw(&raw, 1);
    raw_channel *rot = &raw.clips[0].tracks[0].channels[SINEW_CHANNEL_ROTATION];
    /* out of order: t = 2, 0, 1; and the 90 degree key stored with the other sign */
    const float times[] = {2, 0, 1};
    const float quats[] = {0, 0, 1, 0, 0, 0, 0, 1, 0, 0, -0.70710678f, -0.70710678f};
    memcpy(rot->times, times, sizeof times);
    memcpy(rot->values, quats, sizeof quats);
    void *blob;
    size_t size;
    sinew_model *m = build_and_load(&raw, &blob, &size);
    const sinew_clip *clip = &m->clips[0];
    const sinew_channel *ch = &clip->tracks[0].channels[SINEW_CHANNEL_ROTATION];
    const float *t = clip->times + ch->first_key;
    assert_true(t[0] == 0 && t[1] == 1 && t[2] == 2);
    const float *q = clip->values + ch->first_value;
    for (int k = 1; k < 3; k++) {
        float dot = 0;
        for (int i = 0; i < 4; i++)
            dot += q[k * 4 + i] * q[(k - 1) * 4 + i];
        assert_true(dot >= 0);
    }
    bool warned = false;
    for (uint32_t i = 0; i < m->warning_count; i++)
        warned |= strstr(m->warnings[i], "out of time order") != NULL;
    assert_true(warned);
    sinew_model_free(m);
    free(blob);
    raw_model_free(&raw);
}

static void expect_build_error(raw_model *raw, sinew_result kind, const char *needle)
{
    void *blob = NULL;
    size_t size = 0;
    sinew_error error = {0};
    assert_int_equal(raw_model_build(raw, &blob, &size, &error), kind);
    if (!strstr(error.message, needle))
        fail_msg("message \"%s\" does not mention \"%s\"", error.message, needle);
    assert_non_null(strstr(error.message, "hand-made"));
    raw_model_free(raw);
}

static void test_bad_data_refused(void **state)
{
    (void)state;
    raw_model raw;
    make_raw(&raw, 1);
    raw.meshes[0].positions[4] = NAN;
    expect_build_error(&raw, SINEW_ERROR_DATA, "not finite");

    make_raw(&raw, 1);
    raw.meshes[0].weights[1] = 0; /* listed, but weight 0 */
    expect_build_error(&raw, SINEW_ERROR_DATA, "sum to zero");

    make_raw(&raw, 1);
    raw.meshes[0].indices[2] = 7;
    expect_build_error(&raw, SINEW_ERROR_DATA, "names vertex 7");

    make_raw(&raw, 1);
    raw.clips[0].tracks[0].channels[SINEW_CHANNEL_ROTATION].values[5] = INFINITY;
    expect_build_error(&raw, SINEW_ERROR_DATA, "rotation keys");

    make_raw(&raw, 1);
    memset(raw.clips[0].tracks[0].channels[SINEW_CHANNEL_ROTATION].values, 0, 4 * sizeof(float));
    expect_build_error(&raw, SINEW_ERROR_DATA, "zero-length rotation");

    make_raw(&raw, 1);
    raw_skin *skin = &raw.skins[0];
    skin->joint_count = SINEW_MAX_JOINTS + 1;
    skin->joints = realloc(skin->joints, skin->joint_count * sizeof(uint32_t));
    skin->inverse_bind = realloc(skin->inverse_bind, skin->joint_count * sizeof(sinew_mat4));
    for (uint32_t j = 0; j < skin->joint_count; j++) {
        skin->joints[j] = 1;
        skin->inverse_bind[j] = skin->inverse_bind[0];
    }
    expect_build_error(&raw, SINEW_ERROR_LIMIT, "1025 joints");
}

static void test_reader_arguments(void **state)
{
    (void)state;
    sinew_model *m = NULL;
    sinew_error error = {0};
    assert_int_equal(sinew_model_from_blob(NULL, 0, "x", NULL, NULL, &error), SINEW_ERROR_INVALID_ARGUMENT);
    assert_int_equal(sinew_model_from_blob("garbage!", 8, "x.sinew", NULL, &m, &error), SINEW_ERROR_FORMAT);
    assert_non_null(strstr(error.message, "x.sinew"));
    sinew_model_free(NULL);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_round_trip),
        cmocka_unit_test(test_every_prefix_and_flip_refused),
        cmocka_unit_test(test_influences_sorted_limited_normalised),
        cmocka_unit_test(test_keys_sorted_and_short_way),
        cmocka_unit_test(test_bad_data_refused),
        cmocka_unit_test(test_reader_arguments),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
