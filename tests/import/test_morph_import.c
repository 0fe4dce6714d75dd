/* Morph targets and vertex caches as a user meets them: the glTF fixture morph_quad.gltf
 * (tests/fixtures/make_gltf.py) imported, its weights sampled with each interpolation, posed,
 * blended, saved as .sinew and read back; `sinew pose --morph`; bad data refused or warned
 * about, naming the file; and, from the shared test data, an FBX whose cache is missing and
 * an FBX blend shape moving a vertex its mesh lacks; the COLLADA fixture morph_skin.dae
 * (tests/fixtures/make_dae.py): morph controllers, under a skin and alone. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cjson/cJSON.h>

#include "helpers.h"
#include "sinew/character.h"

static const char *quad_path(char *buf, size_t size)
{
    return fixture_path("morph_quad.gltf", buf, size);
}

static void weights_at(const sinew_model *m, const char *clip, float t, float *out)
{
    int32_t c = sinew_model_find_clip(m, clip);
    assert_true(c >= 0);
    assert_int_equal(sinew_sample_weights(m, &m->clips[c], t, SINEW_WRAP_CLAMP, out, m->morph_channel_count, NULL),
                     SINEW_OK);
}

/* The targets as the file gives them: names, the sparse target's two vertices with normals,
 * the dense one's two moving vertices; a node's own weights over the mesh's. */
static void test_gltf_targets(void **state)
{
    (void)state;
    char path[1024];
    sinew_model *m = load_or_fail(quad_path(path, sizeof path));
    assert_int_equal(m->mesh_count, 1);
    const sinew_mesh *mesh = &m->meshes[0];
    assert_int_equal(mesh->target_count, 2);
    assert_string_equal(mesh->targets[0].name, "up");
    assert_string_equal(mesh->targets[1].name, "wide");
    assert_int_equal(mesh->targets[0].delta_count, 2);
    assert_int_equal(mesh->targets[0].vertices[0], 2);
    assert_non_null(mesh->targets[0].normals);
    assert_null(mesh->targets[1].normals); /* none given */
    assert_int_equal(mesh->targets[1].delta_count, 2);
    assert_int_equal(m->instance_count, 2);
    assert_int_equal(m->morph_channel_count, 4); /* each node its own */
    const sinew_instance *plain = &m->instances[0], *both = &m->instances[1];
    assert_float_equal(m->morph_channels[plain->morph_first].default_weight, 0.25f, 0.0);
    assert_float_equal(m->morph_channels[both->morph_first].default_weight, 1.0f, 0.0);
    assert_float_equal(m->morph_channels[both->morph_first + 1].default_weight, 1.0f, 0.0);
    sinew_model_free(m);
}

/* Weights at t = 0.5 of each clip as its sampler interpolates them; the other node's channels
 * keep their defaults; times clamp. */
static void test_gltf_weight_interpolation(void **state)
{
    (void)state;
    char path[1024];
    sinew_model *m = load_or_fail(quad_path(path, sizeof path));
    float w[4];
    weights_at(m, "linear", 0.5f, w);
    assert_float_equal(w[0], 0.5f, 1e-6);
    assert_float_equal(w[1], 0.25f, 1e-6);
    assert_float_equal(w[2], 1.0f, 0.0);
    assert_float_equal(w[3], 1.0f, 0.0);
    weights_at(m, "step", 0.5f, w);
    assert_float_equal(w[0], 0.0f, 0.0);
    assert_float_equal(w[1], 0.0f, 0.0);
    weights_at(m, "step", 1.0f, w);
    assert_float_equal(w[0], 1.0f, 0.0);
    weights_at(m, "cubic", 0.5f, w); /* Hermite with tangents 3 and 0: 0.375 + 0.5 */
    assert_float_equal(w[0], 0.875f, 1e-6);
    assert_float_equal(w[1], 0.25f, 1e-6);
    weights_at(m, "linear", 7.0f, w);
    assert_float_equal(w[0], 1.0f, 1e-6);
    /* a player of the clip gives the same */
    test_player tp;
    sinew_player *player = test_player_open(&tp, m, &m->clips[sinew_model_find_clip(m, "cubic")]);
    float pw[4];
    assert_int_equal(sinew_player_weights(player, 0.5f, SINEW_WRAP_CLAMP, pw, 4, NULL), SINEW_OK);
    weights_at(m, "cubic", 0.5f, w);
    for (int i = 0; i < 4; i++)
        assert_float_equal(pw[i], w[i], 0.0);
    test_player_close(&tp);
    sinew_model_free(m);
}

/* Posed vertices at t = 0.5 of "linear": node "plain" with weights (0.5, 0.25), node "both"
 * moved half way to (3, 1, 0) with its own (1, 1). */
static void test_gltf_posed(void **state)
{
    (void)state;
    char path[1024];
    sinew_model *m = load_or_fail(quad_path(path, sizeof path));
    const sinew_clip *clip = &m->clips[sinew_model_find_clip(m, "linear")];
    sinew_mat4 *w = pose_worlds(m, clip, 0.5f);
    uint32_t count;
    float *v = posed_vertices_at(m, w, clip, 0.5f, &count);
    assert_int_equal(count, 8);
    static const float want[8][3] = {{0, 0, 0},    {1.125f, 0, 0},  {0, 1.5f, 0}, {1.125f, 1.5f, 0},
                                     {3, 0.5f, 0}, {4.5f, 0.5f, 0}, {3, 2.5f, 0}, {4.5f, 2.5f, 0}};
    for (uint32_t i = 0; i < 8; i++)
        for (int c = 0; c < 3; c++)
            assert_float_equal(v[i * 3 + c], want[i][c], 1e-5);
    free(v);
    free(w);
    sinew_model_free(m);
}

/* Morph weights blend with the poses: two clips at weights 1 and 3, an additive layer; a
 * character's weights follow its layers' weights. */
static void test_weight_blending(void **state)
{
    (void)state;
    char path[1024];
    sinew_model *m = load_or_fail(quad_path(path, sizeof path));
    float a[4], b[4], out[4];
    weights_at(m, "linear", 0.5f, a);
    weights_at(m, "step", 1.0f, b);
    sinew_weight_layer layers[2] = {{a, 1.0f}, {b, 3.0f}};
    assert_int_equal(
        sinew_blend_weights(
            &(sinew_blend_weights_desc){.model = m, .layers = layers, .layer_count = 2, .out = out, .out_count = 4},
            NULL),
        SINEW_OK);
    for (int i = 0; i < 4; i++)
        assert_float_equal(out[i], (a[i] + 3.0f * b[i]) / 4.0f, 1e-6);
    /* nothing weighs: the defaults */
    layers[0].weight = layers[1].weight = 0.0f;
    assert_int_equal(
        sinew_blend_weights(
            &(sinew_blend_weights_desc){.model = m, .layers = layers, .layer_count = 2, .out = out, .out_count = 4},
            NULL),
        SINEW_OK);
    assert_float_equal(out[0], 0.25f, 1e-6);
    /* additive: deltas times their weight on top */
    float delta[4] = {0.1f, 0.2f, 0.0f, 0.0f};
    sinew_weight_layer one = {a, 1.0f}, add = {delta, 2.0f};
    assert_int_equal(sinew_blend_weights(&(sinew_blend_weights_desc){.model = m,
                                                                     .layers = &one,
                                                                     .layer_count = 1,
                                                                     .additive = &add,
                                                                     .additive_count = 1,
                                                                     .out = out,
                                                                     .out_count = 4},
                                         NULL),
                     SINEW_OK);
    assert_float_equal(out[0], a[0] + 0.2f, 1e-6);
    assert_float_equal(out[1], a[1] + 0.4f, 1e-6);
    sinew_error error = {0};
    layers[0].weight = -1.0f;
    assert_int_equal(
        sinew_blend_weights(
            &(sinew_blend_weights_desc){.model = m, .layers = layers, .layer_count = 2, .out = out, .out_count = 4},
            &error),
        SINEW_ERROR_INVALID_ARGUMENT);
    /* a character: "linear" playing alone, then fading into "step" */
    sinew_clip_layout *layouts[2];
    for (int i = 0; i < 2; i++)
        assert_int_equal(
            sinew_clip_layout_create(&(sinew_clip_layout_desc){.model = m, .clip = &m->clips[i]}, &layouts[i], NULL),
            SINEW_OK);
    sinew_character_layer cl[2] = {{.layout = layouts[0]}, {.layout = layouts[1]}};
    sinew_character_desc cd = {.model = m, .layers = cl, .layer_count = 2, .clamp = true};
    size_t size = sinew_character_size(&cd);
    void *memory = malloc(size);
    sinew_character *mx;
    assert_int_equal(sinew_character_init(memory, size, &cd, &mx, NULL), SINEW_OK);
    sinew_mat4 worlds[2];
    sinew_character_output o = {.worlds = worlds, .world_count = 2, .weights = out, .weight_count = 4};
    assert_int_equal(sinew_character_evaluate(mx, &o, NULL), SINEW_OK);
    assert_float_equal(out[0], 0.25f, 1e-6); /* nothing plays: the defaults */
    assert_int_equal(sinew_character_play(mx, 0, 0.0f, false, NULL), SINEW_OK);
    assert_int_equal(sinew_character_advance(mx, 0.5f, NULL), SINEW_OK);
    assert_int_equal(sinew_character_evaluate(mx, &o, NULL), SINEW_OK);
    assert_float_equal(out[0], 0.5f, 1e-6);
    assert_float_equal(out[1], 0.25f, 1e-6);
    free(memory);
    /* clip 1 added on top of clip 0, twice: its weights less those of its first frame */
    cl[0].weight = 1.0f;
    cl[1] = (sinew_character_layer){.layout = layouts[1], .weight = 2.0f, .additive = true};
    size = sinew_character_size(&cd);
    memory = malloc(size);
    assert_int_equal(sinew_character_init(memory, size, &cd, &mx, NULL), SINEW_OK);
    float added[4], first[4];
    for (int k = 0; k < 3; k++) {
        float t = 0.3f * (float)k + 0.2f;
        assert_int_equal(sinew_character_seek(mx, t, NULL), SINEW_OK);
        assert_int_equal(sinew_character_evaluate(mx, &o, NULL), SINEW_OK);
        weights_at(m, m->clips[0].name, t, a);
        weights_at(m, m->clips[1].name, t, added);
        weights_at(m, m->clips[1].name, 0.0f, first);
        for (int c = 0; c < 4; c++)
            assert_float_equal(out[c], a[c] + 2.0f * (added[c] - first[c]), 1e-6);
    }
    free(memory);
    for (int i = 0; i < 2; i++)
        sinew_clip_layout_free(layouts[i]);
    sinew_model_free(m);
}

/* Saved as .sinew and read back: the same targets, channels, weight tracks and pose. */
static void test_sinew_round_trip(void **state)
{
    (void)state;
    char path[1024], saved[1024];
    sinew_model *m = load_or_fail(quad_path(path, sizeof path));
    tmp_path("morph_quad.sinew", saved, sizeof saved);
    sinew_error error = {0};
    assert_int_equal(sinew_model_save(m, NULL, saved, &error), SINEW_OK);
    sinew_model *back = NULL;
    assert_int_equal(sinew_model_load(saved, NULL, &back, &error), SINEW_OK);
    assert_int_equal(back->morph_channel_count, m->morph_channel_count);
    assert_int_equal(back->meshes[0].target_count, 2);
    assert_string_equal(back->meshes[0].targets[1].name, "wide");
    assert_int_equal(back->clips[2].weight_track_count, m->clips[2].weight_track_count);
    for (uint32_t c = 0; c < m->clip_count; c++) {
        float a[4], b[4];
        assert_int_equal(sinew_sample_weights(m, &m->clips[c], 0.3f, SINEW_WRAP_CLAMP, a, 4, NULL), SINEW_OK);
        assert_int_equal(sinew_sample_weights(back, &back->clips[c], 0.3f, SINEW_WRAP_CLAMP, b, 4, NULL), SINEW_OK);
        for (int i = 0; i < 4; i++)
            assert_float_equal(a[i], b[i], 0.0);
        sinew_mat4 *wa = pose_worlds(m, &m->clips[c], 0.3f), *wb = pose_worlds(back, &back->clips[c], 0.3f);
        uint32_t na, nb;
        float *va = posed_vertices_at(m, wa, &m->clips[c], 0.3f, &na);
        float *vb = posed_vertices_at(back, wb, &back->clips[c], 0.3f, &nb);
        assert_int_equal(na, nb);
        assert_memory_equal(va, vb, (size_t)na * 3 * sizeof(float));
        free(va);
        free(vb);
        free(wa);
        free(wb);
    }
    sinew_model_free(back);
    sinew_model_free(m);
}

/* `sinew pose --morph`: a target's weight by hand; an unknown one lists the model's. */
static void test_cli_morph(void **state)
{
    (void)state;
    char path[1024];
    quad_path(path, sizeof path);
    run_result r = RUN("pose", path, "--clip", "linear", "--time", "0.5", "--json", "--morph", "quad:wide=0.75");
    assert_int_equal(r.code, 0);
    cJSON *doc = cJSON_Parse(r.out);
    assert_non_null(doc);
    const cJSON *weights = cJSON_GetObjectItem(cJSON_GetArrayItem(cJSON_GetObjectItem(doc, "frames"), 0), "weights");
    assert_int_equal(cJSON_GetArraySize(weights), 4);
    assert_float_equal(cJSON_GetObjectItem(cJSON_GetArrayItem(weights, 0), "weight")->valuedouble, 0.5, 1e-6);
    /* both nodes' "wide" are that target's */
    assert_float_equal(cJSON_GetObjectItem(cJSON_GetArrayItem(weights, 1), "weight")->valuedouble, 0.75, 1e-6);
    assert_float_equal(cJSON_GetObjectItem(cJSON_GetArrayItem(weights, 3), "weight")->valuedouble, 0.75, 1e-6);
    cJSON_Delete(doc);
    run_free(&r);
    r = RUN("pose", path, "--morph", "quad:tall=1");
    assert_int_not_equal(r.code, 0);
    assert_non_null(strstr(r.err, "no such morph target"));
    assert_non_null(strstr(r.err, "quad:up"));
    run_free(&r);
}

/* The fixture with one edit (a JSON path of keys and #indices, the new value as JSON, NULL to
 * remove), imported: the result, and the error or warnings. */
static sinew_result import_edited(const char *const *keys, const char *value, sinew_model **out, char *message,
                                  size_t size)
{
    char path[1024], edited[1024];
    size_t n;
    char *text = read_file(quad_path(path, sizeof path), &n);
    cJSON *doc = cJSON_Parse(text);
    free(text);
    cJSON *at = doc, *parent = NULL;
    const char *last = NULL;
    for (int i = 0; keys[i]; i++) {
        parent = at, last = keys[i];
        at = keys[i][0] == '#' ? cJSON_GetArrayItem(at, atoi(keys[i] + 1)) : cJSON_GetObjectItem(at, keys[i]);
    }
    cJSON *replacement = cJSON_Parse(value);
    assert_non_null(replacement);
    if (last[0] == '#')
        cJSON_ReplaceItemInArray(parent, atoi(last + 1), replacement);
    else if (at)
        cJSON_ReplaceItemInObject(parent, last, replacement);
    else
        cJSON_AddItemToObject(parent, last, replacement);
    char *json = cJSON_Print(doc);
    cJSON_Delete(doc);
    /* beside the fixture's name, in the temporary folder (the buffer is a data: URI) */
    tmp_path("morph_edited.gltf", edited, sizeof edited);
    FILE *f = fopen(edited, "w");
    fputs(json, f);
    fclose(f);
    free(json);
    sinew_error error = {0};
    sinew_result r = sinew_import(&(sinew_import_desc){.path = edited}, out, &error);
    snprintf(message, size, "%s", error.message);
    return r;
}

/* Bad data: a target of another vertex count, a sparse index past the vertices, weights of
 * the wrong length are refused naming the file and where; weights beyond -10..10 are kept
 * and warned about. */
static void test_bad_targets(void **state)
{
    (void)state;
    sinew_model *m = NULL;
    char message[1024];
    /* the dense target's accessor says 3 elements */
    assert_int_equal(
        import_edited((const char *const[]){"accessors", "#5", "count", NULL}, "3", &m, message, sizeof message),
        SINEW_ERROR_FORMAT);
    assert_non_null(strstr(message, "morph_edited.gltf"));
    assert_non_null(strstr(message, "targets[1]"));
    assert_non_null(strstr(message, "POSITION has 3 elements for the primitive's 4 vertices"));
    /* the sparse target over an accessor of 2 elements: its indices 2 and 3 are past them */
    assert_int_equal(
        import_edited((const char *const[]){"accessors", "#3", "count", NULL}, "2", &m, message, sizeof message),
        SINEW_ERROR_FORMAT);
    assert_non_null(strstr(message, "sparse"));
    assert_non_null(strstr(message, "index 2 is not below the accessor's count 2"));
    /* node weights of one number for two targets */
    assert_int_equal(
        import_edited((const char *const[]){"nodes", "#1", "weights", NULL}, "[1]", &m, message, sizeof message),
        SINEW_ERROR_FORMAT);
    assert_non_null(strstr(message, "nodes[1].weights"));
    /* a weight of 20: kept, warned */
    assert_int_equal(
        import_edited((const char *const[]){"nodes", "#1", "weights", NULL}, "[20, 1]", &m, message, sizeof message),
        SINEW_OK);
    bool warned = false;
    for (uint32_t i = 0; i < m->warning_count; i++)
        warned |= strstr(m->warnings[i], "outside -10..10") != NULL;
    assert_true(warned);
    assert_float_equal(m->morph_channels[2].default_weight, 20.0f, 0.0);
    sinew_model_free(m);
}

/* The COLLADA fixture morph_skin.dae with `from` replaced by `to` (once), imported. */
static sinew_result import_dae_edited(const char *from, const char *to, sinew_model **out, char *message, size_t size)
{
    char path[1024], edited[1024];
    size_t n;
    char *text = read_file(fixture_path("morph_skin.dae", path, sizeof path), &n);
    char *at = strstr(text, from);
    assert_non_null(at);
    size_t head = (size_t)(at - text), grown = n - strlen(from) + strlen(to);
    char *changed = malloc(grown + 1);
    memcpy(changed, text, head);
    memcpy(changed + head, to, strlen(to));
    memcpy(changed + head + strlen(to), at + strlen(from), n - head - strlen(from));
    write_file(tmp_path("morph_edited.dae", edited, sizeof edited), changed, grown);
    free(changed);
    free(text);
    sinew_error error = {0};
    sinew_result r = sinew_import(&(sinew_import_desc){.path = edited}, out, &error);
    snprintf(message, size, "%s", error.message);
    return r;
}

/* COLLADA morph controllers by sinew's reader: a skin over a NORMALIZED morph (a target of
 * whole triangles, one of <vertices> only) and a RELATIVE morph of its own; the MORPH_WEIGHT
 * defaults; weights animated LINEAR, STEP and BEZIER; the posed vertices. */
static void test_collada_morph(void **state)
{
    (void)state;
    char path[1024];
    sinew_model *m = load_or_fail(fixture_path("morph_skin.dae", path, sizeof path));
    assert_int_equal(m->mesh_count, 2);
    assert_int_equal(m->morph_channel_count, 3);
    assert_string_equal(m->morph_channels[0].name, "quad-up");
    assert_string_equal(m->morph_channels[1].name, "quad-wide");
    assert_float_equal(m->morph_channels[0].default_weight, 0.25f, 0.0);
    assert_float_equal(m->morph_channels[2].default_weight, 0.0f, 0.0);
    const sinew_mesh *quad = &m->meshes[m->instances[0].mesh];
    assert_int_equal(quad->target_count, 2);
    assert_true(quad->skin >= 0);
    const sinew_morph_target *wide = &quad->targets[1];
    assert_int_equal(wide->delta_count, 2); /* the right edge */
    for (uint32_t d = 0; d < 2; d++) {
        assert_true(wide->vertices[d] == 1 || wide->vertices[d] == 3);
        assert_float_equal(wide->positions[d * 3], 1.0f, 0.0);
    }
    assert_int_equal(m->meshes[m->instances[1].mesh].target_count, 1);
    assert_int_equal(m->instances[1].morph_first, 2);
    float w[3];
    weights_at(m, "clip 0", 0.25f, w);
    assert_float_equal(w[0], 0.25f, 1e-6);
    assert_float_equal(w[1], 0.0f, 0.0);
    assert_float_equal(w[2], 0.15625f, 2e-3); /* the Bezier cut in 32 linear pieces a segment */
    weights_at(m, "clip 0", 0.5f, w);
    assert_float_equal(w[0], 0.5f, 1e-6);
    assert_float_equal(w[1], 1.0f, 0.0);
    assert_float_equal(w[2], 0.5f, 1e-6);
    const sinew_clip *clip = &m->clips[0];
    sinew_mat4 *worlds = pose_worlds(m, clip, 0.5f);
    uint32_t count;
    float *v = posed_vertices_at(m, worlds, clip, 0.5f, &count);
    assert_int_equal(count, 8);
    static const float want[8][3] = {{0, 0, 0}, {2, 0, 0}, {0, 2.5f, 0}, {2, 2.5f, 0},
                                     {3, 0, 0}, {4, 0, 0}, {3, 2.5f, 0}, {4, 2.5f, 0}};
    for (uint32_t i = 0; i < 8; i++)
        for (int c = 0; c < 3; c++)
            assert_float_equal(v[i * 3 + c], want[i][c], 1e-5);
    free(v);
    free(worlds);
    sinew_model_free(m);
}

/* Bad COLLADA morphs: a target with fewer positions than its base is refused, naming the file
 * and the target; a channel of a weight the morph lacks is warned about and not played. */
static void test_collada_bad_morph(void **state)
{
    (void)state;
    sinew_model *m = NULL;
    char message[1024];
    assert_int_equal(import_dae_edited("count=\"12\">0 0 0 2 0 0 0 2 0 2 2 0</float_array>\n"
                                       "   <technique_common><accessor source=\"#quad-wide-pos-a\" count=\"4\"",
                                       "count=\"9\">0 0 0 2 0 0 0 2 0</float_array>\n"
                                       "   <technique_common><accessor source=\"#quad-wide-pos-a\" count=\"3\"",
                                       &m, message, sizeof message),
                     SINEW_ERROR_FORMAT);
    assert_non_null(strstr(message, "morph_edited.dae"));
    assert_non_null(strstr(message, "morph target \"quad-wide\" has 3 positions where its base mesh has 4"));
    assert_int_equal(import_dae_edited("quad-morph/quad-morph-weights(1)", "quad-morph/quad-morph-weights(5)", &m,
                                       message, sizeof message),
                     SINEW_OK);
    bool warned = false;
    for (uint32_t i = 0; i < m->warning_count; i++)
        warned |= strstr(m->warnings[i], "the morph has 2 targets") != NULL;
    assert_true(warned);
    sinew_model_free(m);
}

/* An FBX whose vertex cache is not beside it: a warning naming the cache, the mesh at its base
 * shape. An FBX blend shape moving a vertex its mesh lacks: refused, naming the file and the
 * shape. */
static void test_fbx_bad_deformers(void **state)
{
    (void)state;
    char src[1024], copy[1024];
    if (!testdata_path("ufbx/maya_cache_sine_7500_ascii.fbx", src, sizeof src))
        skip();
    size_t n;
    char *text = read_file(src, &n);
    tmp_path("cache_alone.fbx", copy, sizeof copy);
    FILE *f = fopen(copy, "wb");
    fwrite(text, 1, n, f);
    fclose(f);
    free(text);
    sinew_model *m = load_or_fail(copy);
    bool warned = false;
    for (uint32_t i = 0; i < m->warning_count; i++)
        warned |= strstr(m->warnings[i], "vertex cache") && strstr(m->warnings[i], "missing") &&
                  strstr(m->warnings[i], "pCubeShape1.xml");
    assert_true(warned);
    for (uint32_t i = 0; i < m->mesh_count; i++)
        assert_null(m->meshes[i].cache);
    sinew_model_free(m);

    if (!testdata_path("ufbx/maya_blend_inbetween_7500_ascii.fbx", src, sizeof src))
        skip();
    text = read_file(src, &n);
    char *at = strstr(text, "a: 6,7,9,10\n"); /* the first shape's Indexes */
    assert_non_null(at);
    memcpy(at, "a: 6,7,9,99", 11);
    tmp_path("blend_bad_index.fbx", copy, sizeof copy);
    f = fopen(copy, "wb");
    fwrite(text, 1, n, f);
    fclose(f);
    free(text);
    sinew_error error = {0};
    m = NULL;
    assert_int_equal(sinew_import(&(sinew_import_desc){.path = copy}, &m, &error), SINEW_ERROR_DATA);
    assert_non_null(strstr(error.message, "blend_bad_index.fbx"));
    assert_non_null(strstr(error.message, "moves vertex 99"));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_gltf_targets),     cmocka_unit_test(test_gltf_weight_interpolation),
        cmocka_unit_test(test_gltf_posed),       cmocka_unit_test(test_weight_blending),
        cmocka_unit_test(test_sinew_round_trip), cmocka_unit_test(test_cli_morph),
        cmocka_unit_test(test_bad_targets),      cmocka_unit_test(test_fbx_bad_deformers),
        cmocka_unit_test(test_collada_morph),    cmocka_unit_test(test_collada_bad_morph),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
