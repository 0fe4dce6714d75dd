/* sinew's own glTF reader (src/import/gltf.c) on sinew's fixtures (tests/fixtures/make_gltf.py):
 * nodes by index whatever their names, each sampler's interpolation, KHR_mesh_quantization
 * and sparse accessors, KHR_texture_transform, and refusals that say where the file is wrong. */
#define _GNU_SOURCE /* memmem */
#include <math.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cjson/cJSON.h>

#include "helpers.h"
#include "core/internal.h"

static const sinew_track *track_of(const sinew_clip *clip, uint32_t node)
{
    for (uint32_t t = 0; t < clip->track_count; t++)
        if (clip->tracks[t].node == node)
            return &clip->tracks[t];
    return NULL;
}

static void sample(const sinew_model *m, float t, sinew_transform *locals)
{
    sinew_sample_desc desc = {
        .model = m, .clip = &m->clips[0], .time = t, .locals = locals, .local_count = m->node_count};
    assert_int_equal(sinew_sample(&desc, NULL), SINEW_OK);
}

/* No names at all: the tip joint is node 2 (the file's node 2), its rotation CUBICSPLINE,
 * translation LINEAR, scale STEP, exactly as in the named fixture. */
static void test_unnamed_nodes(void **state)
{
    (void)state;
    char path[1024];
    sinew_model *m = load_or_fail(fixture_path("two_bone_unnamed.gltf", path, sizeof path));
    assert_int_equal(m->node_count, 3);
    assert_string_equal(m->node_names[2], "nodes[2]");
    assert_int_equal(m->node_parents[2], 1);
    const sinew_track *track = track_of(&m->clips[0], 2);
    assert_non_null(track);
    assert_int_equal(track->channels[SINEW_CHANNEL_ROTATION].interp, SINEW_INTERP_CUBIC);
    assert_int_equal(track->channels[SINEW_CHANNEL_TRANSLATION].interp, SINEW_INTERP_LINEAR);
    assert_int_equal(track->channels[SINEW_CHANNEL_SCALE].interp, SINEW_INTERP_STEP);
    sinew_transform locals[3];
    sample(m, 0.25f, locals);
    double h = 0.15625, z = h * sqrt(0.5), w = (1 - h) + h * sqrt(0.5), len = sqrt(z * z + w * w);
    assert_near(locals[2].rotation[2], z / len, 1e-6, "cubic rotation z at 1/4");
    assert_near(locals[2].translation[1], 1.25, 1e-6, "linear translation at 1/4");
    assert_near(locals[2].scale[0], 1, 0, "step scale holds");
    /* the three samplers share one input: the clip keeps its two times once, and so does a
     * .sinew file of the model */
    for (int pass = 0; pass < 2; pass++) {
        const sinew_clip *clip = &m->clips[0];
        assert_int_equal(clip->time_count, 2);
        for (int k = 0; k < SINEW_CHANNEL_COUNT; k++)
            assert_int_equal(track_of(clip, 2)->channels[k].first_key, 0);
        void *bytes = NULL;
        size_t size = 0;
        sinew_model *back = NULL;
        assert_int_equal(sinew_model_write_blob(m, NULL, &bytes, &size, NULL), SINEW_OK);
        assert_int_equal(sinew_model_from_blob(bytes, size, "round trip", NULL, &back, NULL), SINEW_OK);
        free(bytes);
        sinew_model_free(m);
        m = back;
    }
    sinew_model_free(m);
}

/* Every node named "bone": the channels still land on node 2; rotation STEP, translation
 * CUBICSPLINE from 1 to 2 with slope 3 at both keys. */
static void test_repeated_names(void **state)
{
    (void)state;
    char path[1024];
    sinew_model *m = load_or_fail(fixture_path("two_bone_repeated.gltf", path, sizeof path));
    for (uint32_t i = 0; i < m->node_count; i++)
        assert_string_equal(m->node_names[i], "bone");
    assert_int_equal(m->clips[0].track_count, 1);
    assert_int_equal(m->clips[0].tracks[0].node, 2);
    sinew_transform locals[3];
    sample(m, 0.5f, locals);
    assert_near(locals[2].rotation[3], 1, 1e-7, "step rotation holds until the next key");
    /* Hermite at u = 1/4: h00 1 + h10 3 + h01 2 + h11 3 = 0.84375 + 0.421875 + 0.3125 - 0.140625 */
    sample(m, 0.25f, locals);
    assert_near(locals[2].translation[1], 1.4375, 1e-6, "cubic translation at 1/4");
    sample(m, 1.0f, locals);
    assert_near(locals[2].rotation[2], sqrt(0.5), 1e-6, "step rotation at the key");
    assert_near(locals[1].rotation[3], 1, 0, "the untracked node keeps its rest");
    sinew_model_free(m);
}

/* KHR_mesh_quantization (unsigned-short positions, normalised-byte normals, UVs and weights,
 * byte joints), the top positions from a sparse accessor, and the texture transform
 * (u' = 0.5 u + 0.5) applied to the UVs before v is turned up; the missing image is a warning. */
static void test_quantized_sparse_texture_transform(void **state)
{
    (void)state;
    char path[1024];
    sinew_model *m = load_or_fail(fixture_path("two_bone_quantized.gltf", path, sizeof path));
    assert_int_equal(m->mesh_count, 1);
    const sinew_mesh *mesh = &m->meshes[0];
    static const float positions[12] = {0, 0, 0, 1, 0, 0, 0, 2, 0, 1, 2, 0};
    static const float uvs[8] = {0.5f, 1, 1, 1, 0.5f, 0, 1, 0}; /* v up, as the runtime has it */
    for (int i = 0; i < 12; i++)
        assert_near(mesh->positions[i], positions[i], 0, "quantized + sparse position");
    for (int i = 0; i < 8; i++)
        assert_near(mesh->uvs[i], uvs[i], 1e-7, "transformed UV");
    for (uint32_t v = 0; v < 4; v++) {
        assert_near(mesh->normals[v * 3 + 2], 1, 1e-6, "normalised-byte normal");
        assert_near(mesh->weights[v * mesh->influence_count], 1, 1e-6, "normalised-byte weight");
        assert_int_equal(mesh->joints[v * mesh->influence_count], v < 2 ? 0 : 1);
    }
    assert_int_equal(m->material_count, 1);
    assert_near(m->materials[0].base_color[1], 0.5, 0, "base colour factor");
    assert_null(m->materials[0].maps[SINEW_MAP_BASE_COLOR].path);
    bool warned = false;
    for (uint32_t i = 0; i < m->warning_count; i++)
        warned |= strstr(m->warnings[i], "missing_atlas.png") != NULL;
    assert_true(warned);
    sinew_model_free(m);
}

/* The cubic fixture with one edit (a JSON path and a new value) must be refused with a
 * message that names the file and says `needle`. */
typedef struct edit {
    const char *what;
    const char *path[8]; /* object keys and array indices ("#2") */
    const char *json;    /* the new value; NULL removes it */
    const char *needle;
} edit;

static cJSON *walk(cJSON *at, const char *key)
{
    return key[0] == '#' ? cJSON_GetArrayItem(at, atoi(key + 1)) : cJSON_GetObjectItemCaseSensitive(at, key);
}

static void check_edit(const edit *e, const char *text)
{
    cJSON *doc = cJSON_Parse(text);
    cJSON *parent = doc;
    int depth = 0;
    while (e->path[depth + 1])
        parent = walk(parent, e->path[depth++]);
    assert_non_null(parent);
    const char *last = e->path[depth];
    cJSON *value = e->json ? cJSON_Parse(e->json) : NULL;
    if (last[0] == '#') {
        if (value)
            cJSON_ReplaceItemInArray(parent, atoi(last + 1), value);
        else
            cJSON_DeleteItemFromArray(parent, atoi(last + 1));
    } else if (value) {
        if (cJSON_GetObjectItemCaseSensitive(parent, last))
            cJSON_ReplaceItemInObjectCaseSensitive(parent, last, value);
        else
            cJSON_AddItemToObject(parent, last, value);
    } else {
        cJSON_DeleteItemFromObjectCaseSensitive(parent, last);
    }
    char *out = cJSON_Print(doc);
    char file[1024];
    tmp_path("edited.gltf", file, sizeof file);
    write_file(file, out, strlen(out));
    sinew_model *m = NULL;
    sinew_error error = {0};
    sinew_import_desc desc = {.path = file};
    sinew_result r = sinew_import(&desc, &m, &error);
    if (r == SINEW_OK)
        fail_msg("%s: accepted", e->what);
    if (!strstr(error.message, file) || !strstr(error.message, e->needle))
        fail_msg("%s: message \"%s\" should name the file and say \"%s\"", e->what, error.message, e->needle);
    print_message("%-40s %s\n", e->what, error.message + strlen(file) + 2);
    free(out);
    cJSON_Delete(doc);
}

static void test_refusals_say_where(void **state)
{
    (void)state;
    static const edit edits[] = {
        {"accessor count past its view",
         {"accessors", "#0", "count", NULL},
         "5",
         "accessors[0] (meshes[0].primitives[0] POSITION)"},
        {"indices not in threes", {"accessors", "#4", "count", NULL}, "4", "not a whole number of triangles"},
        {"attribute counts differ",
         {"accessors", "#0", "count", NULL},
         "3",
         "NORMAL has 4 elements for the primitive's 3 vertices"},
        {"indices of float", {"meshes", "#0", "primitives", "#0", "indices", NULL}, "6", "componentType 5126"},
        {"view past its buffer", {"bufferViews", "#0", "byteLength", NULL}, "100000", "bufferViews[0]"},
        {"stride smaller than an element", {"bufferViews", "#0", "byteStride", NULL}, "8", "byteStride 8"},
        {"child that is no node", {"nodes", "#1", "children", NULL}, "[7]", "nodes[1].children[0]"},
        {"a cycle of children", {"nodes", "#2", "children", NULL}, "[1]", "also a child"},
        {"a node that is its own child", {"nodes", "#2", "children", NULL}, "[2]", "more than one parent"},
        {"skin joint that is no node", {"skins", "#0", "joints", NULL}, "[1, 9]", "skins[0].joints[1]"},
        {"unknown interpolation",
         {"animations", "#0", "samplers", "#0", "interpolation", NULL},
         "\"SMOOTH\"",
         "SMOOTH"},
        {"cubic output of the wrong length",
         {"animations", "#0", "samplers", "#0", "interpolation", NULL},
         "\"LINEAR\"",
         "6 output values for 2 keys"},
        /* the places the animation reader writes only when a message needs them (place_label) */
        {"channel sampler out of range",
         {"animations", "#0", "channels", "#1", "sampler", NULL},
         "9",
         "animations[0].channels[1].sampler: not an integer from 0 to 2"},
        {"sampler output of the wrong type",
         {"accessors", "#8", "type", NULL},
         "\"SCALAR\"",
         "accessors[8] (animations[0].samplers[1] output): type \"SCALAR\""},
        {"sampler output past its view",
         {"bufferViews", "#8", "byteLength", NULL},
         "20",
         "accessors[8] (animations[0].samplers[1] output): 2 elements from byte 0 do not fit in bufferViews[8] (20 "
         "bytes)"},
        {"sampler input past its view",
         {"bufferViews", "#6", "byteStride", NULL},
         "3",
         "bufferViews[6].byteStride: not an integer from 4 to 252"},
        {"second channel for one path",
         {"animations", "#0", "channels", "#2", "target", "path", NULL},
         "\"translation\"",
         "animations[0].channels[2]: a second channel for the translation of node 2"},
        {"not glTF 2", {"asset", "version", NULL}, "\"1.0\"", "glTF 2.0"},
        {"compressed geometry", {"extensionsRequired", NULL}, "[\"KHR_draco_mesh_compression\"]", "draco"},
        {"mesh index out of range", {"nodes", "#0", "mesh", NULL}, "3", "nodes[0].mesh"},
        {"no POSITION", {"meshes", "#0", "primitives", "#0", "attributes", "POSITION", NULL}, NULL, "no POSITION"},
        {"matrix of 15 numbers", {"nodes", "#1", "matrix", NULL}, "[1,0,0,0,0,1,0,0,0,0,1,0,0,0,0]", "nodes[1].matrix"},
        {"bad base64", {"buffers", "#0", "uri", NULL}, "\"data:application/octet-stream;base64,@@@@\"", "base64"},
    };
    char src[1024];
    size_t size;
    char *text = read_file(fixture_path("two_bone_cubic.gltf", src, sizeof src), &size);
    assert_non_null(text); /* read_file ends it with a NUL */
    for (size_t i = 0; i < sizeof edits / sizeof edits[0]; i++)
        check_edit(&edits[i], text);
    free(text);
}

/* A .glb whose header lies about its length, and a .glb that is not binary glTF. */
/* Images embedded in the file reach the model as their encoded bytes (the renderer decodes
 * them, tests/render/test_render.c); broken ones are refused, saying which image. */
static void test_embedded_images(void **state)
{
    (void)state;
    char path[1024];
    const char *files[] = {"two_bone_textured.glb", "two_bone_textured.gltf"};
    for (int f = 0; f < 2; f++) {
        sinew_model *m = load_or_fail(fixture_path(files[f], path, sizeof path));
        assert_int_equal(m->material_count, 1);
        const sinew_material *mat = &m->materials[0];
        assert_null(mat->maps[SINEW_MAP_BASE_COLOR].path);
        assert_non_null(mat->maps[SINEW_MAP_BASE_COLOR].image);
        assert_int_equal(mat->maps[SINEW_MAP_BASE_COLOR].image_size, 141); /* the fixture's PNG */
        assert_memory_equal(mat->maps[SINEW_MAP_BASE_COLOR].image, "\x89PNG\r\n\x1a\n", 8);
        for (uint32_t w = 0; w < m->warning_count; w++)
            assert_null(strstr(m->warnings[w], "embedded"));
        sinew_model_free(m);
        /* Assimp's embedded textures ("*0") reach the model too (its other formats rely on it) */
        sinew_import_desc desc = {.path = path, .assimp = true};
        sinew_error error = {0};
        assert_int_equal(sinew_import(&desc, &m, &error), SINEW_OK);
        assert_int_equal(m->materials[0].maps[SINEW_MAP_BASE_COLOR].image_size, 141);
        sinew_model_free(m);
    }
    static const edit edits[] = {
        {"image of bad base64", {"images", "#0", "uri", NULL}, "\"data:image/png;base64,@@\"", "images[0].uri"},
        {"image data: URI not base64", {"images", "#0", "uri", NULL}, "\"data:image/png,abc\"", "not base64"},
        {"image with no uri or bufferView", {"images", "#0", NULL}, "{\"name\": \"nothing\"}", "neither a uri"},
        {"image bufferView out of range", {"images", "#0", NULL}, "{\"bufferView\": 99}", "images[0].bufferView"},
    };
    size_t size;
    char *text = read_file(fixture_path("two_bone_textured.gltf", path, sizeof path), &size);
    assert_non_null(text);
    for (size_t i = 0; i < sizeof edits / sizeof edits[0]; i++)
        check_edit(&edits[i], text);
    free(text);
}

static void test_glb_header(void **state)
{
    (void)state;
    char src[1024], file[1024];
    size_t size;
    unsigned char *bytes = read_file(fixture_path("two_bone_cubic.glb", src, sizeof src), &size);
    bytes[8] ^= 1;
    write_file(tmp_path("length.glb", file, sizeof file), bytes, size);
    sinew_model *m = NULL;
    sinew_error error = {0};
    assert_int_equal(sinew_import(&(sinew_import_desc){.path = file}, &m, &error), SINEW_ERROR_FORMAT);
    assert_non_null(strstr(error.message, "GLB header: length"));
    write_file(tmp_path("text.glb", file, sizeof file), "{\"asset\":{}}", 12);
    assert_int_equal(sinew_import(&(sinew_import_desc){.path = file}, &m, &error), SINEW_ERROR_FORMAT);
    assert_non_null(strstr(error.message, "not a binary glTF"));
    free(bytes);
}

/* A primitive without NORMAL: glTF asks for flat normals ("client implementations MUST calculate
 * flat normals", and ignore TANGENT): the mesh says so (flat_normals, kept by a .sinew file), its
 * normals are still there (smooth, unit length, for skinning), and it has no tangents. With
 * NORMAL it is as the file says. */
static void test_missing_normals_are_flat(void **state)
{
    (void)state;
    char src[1024], file[1024], saved[1024];
    size_t size = 0;
    char *text = (char *)read_file(fixture_path("two_bone_cubic.gltf", src, sizeof src), &size);
    cJSON *doc = cJSON_ParseWithLength(text, size);
    free(text);
    assert_non_null(doc);
    cJSON *prim = cJSON_GetArrayItem(
        cJSON_GetObjectItem(cJSON_GetArrayItem(cJSON_GetObjectItem(doc, "meshes"), 0), "primitives"), 0);
    cJSON *attrs = cJSON_GetObjectItem(prim, "attributes");
    cJSON_DeleteItemFromObject(attrs, "NORMAL");
    /* tangents to ignore: WEIGHTS_0's accessor is of VEC4 floats, one a vertex */
    cJSON_AddNumberToObject(attrs, "TANGENT", cJSON_GetObjectItem(attrs, "WEIGHTS_0")->valueint);
    char *out = cJSON_PrintUnformatted(doc);
    write_file(tmp_path("no_normals.gltf", file, sizeof file), out, strlen(out));
    free(out);
    cJSON_Delete(doc);

    sinew_model *with = load_or_fail(src), *without = load_or_fail(file);
    assert_false(with->meshes[0].flat_normals);
    const sinew_mesh *mesh = &without->meshes[0];
    assert_true(mesh->flat_normals);
    assert_null(mesh->tangents);
    assert_non_null(mesh->normals);
    for (uint32_t v = 0; v < mesh->vertex_count; v++) {
        const float *n = &mesh->normals[v * 3];
        assert_float_equal(n[0] * n[0] + n[1] * n[1] + n[2] * n[2], 1.0f, 1e-5f);
    }
    sinew_error error = {0};
    assert_int_equal(sinew_model_save(without, NULL, tmp_path("no_normals.sinew", saved, sizeof saved), &error),
                     SINEW_OK);
    sinew_model *back = load_or_fail(saved);
    assert_true(back->meshes[0].flat_normals);
    sinew_model_free(back);
    /* a flag other than 0 or 1 is refused */
    unsigned char *bytes = read_file(saved, &size);
    const unsigned char *tag = memmem(bytes, size, "MFLT", 4);
    assert_non_null(tag);
    uint32_t offset;
    memcpy(&offset, tag + 4, 4);
    bytes[offset] = 2;
    uint32_t checksum = sinew_blob_checksum(bytes, size); /* so that the validation is what refuses it */
    memcpy(bytes + offsetof(blob_file_header, checksum), &checksum, 4);
    back = NULL;
    assert_int_equal(sinew_model_from_blob(bytes, size, "edited", NULL, &back, &error), SINEW_ERROR_FORMAT);
    assert_non_null(strstr(error.message, "flat normals"));
    free(bytes);
    assert_int_equal(sinew_model_save(with, NULL, saved, &error), SINEW_OK);
    back = load_or_fail(saved);
    assert_false(back->meshes[0].flat_normals);
    sinew_model_free(back);
    sinew_model_free(with);
    sinew_model_free(without);
}

/* COLOR_0, which multiplies the base colour: RGBA floats as they are (glTF's are linear), RGB
 * unsigned bytes normalised (a 4-byte stride, as glTF aligns them) with alpha 1; kept by a
 * .sinew file. Without COLOR_0 a mesh has none. */
static void test_vertex_colours(void **state)
{
    (void)state;
    char src[1024], file[1024], bin[1024], saved[1024];
    size_t size = 0;
    char *text = (char *)read_file(fixture_path("two_bone_cubic.gltf", src, sizeof src), &size);
    cJSON *doc = cJSON_ParseWithLength(text, size);
    free(text);
    assert_non_null(doc);
    cJSON *accessors = cJSON_GetObjectItem(doc, "accessors"), *views = cJSON_GetObjectItem(doc, "bufferViews");
    uint32_t n = (uint32_t)cJSON_GetObjectItem(cJSON_GetArrayItem(accessors, 0), "count")->valueint;
    /* the colours' buffer: n RGBA floats, then n RGB bytes each padded to 4 */
    size_t bytes = (size_t)n * 16 + (size_t)n * 4;
    unsigned char *data = calloc(1, bytes);
    for (uint32_t v = 0; v < n; v++) {
        float rgba[4] = {(float)v / (float)n, 0.5f, 1.0f - (float)v / (float)n, 0.25f};
        memcpy(data + (size_t)v * 16, rgba, sizeof rgba);
        data[(size_t)n * 16 + (size_t)v * 4] = (unsigned char)(v * 37);
        data[(size_t)n * 16 + (size_t)v * 4 + 1] = 128;
        data[(size_t)n * 16 + (size_t)v * 4 + 2] = 255;
    }
    write_file(tmp_path("colors.bin", bin, sizeof bin), data, bytes);
    cJSON *buffer = cJSON_CreateObject();
    cJSON_AddStringToObject(buffer, "uri", "colors.bin");
    cJSON_AddNumberToObject(buffer, "byteLength", (double)bytes);
    cJSON_AddItemToArray(cJSON_GetObjectItem(doc, "buffers"), buffer);
    int buffer_index = cJSON_GetArraySize(cJSON_GetObjectItem(doc, "buffers")) - 1;
    int first_view = cJSON_GetArraySize(views), first_accessor = cJSON_GetArraySize(accessors);
    for (int k = 0; k < 2; k++) {
        cJSON *view = cJSON_CreateObject(), *accessor = cJSON_CreateObject();
        cJSON_AddNumberToObject(view, "buffer", buffer_index);
        cJSON_AddNumberToObject(view, "byteOffset", k ? (double)n * 16 : 0);
        cJSON_AddNumberToObject(view, "byteLength", k ? (double)n * 4 : (double)n * 16);
        if (k)
            cJSON_AddNumberToObject(view, "byteStride", 4);
        cJSON_AddItemToArray(views, view);
        cJSON_AddNumberToObject(accessor, "bufferView", first_view + k);
        cJSON_AddNumberToObject(accessor, "componentType", k ? 5121 : 5126);
        if (k)
            cJSON_AddTrueToObject(accessor, "normalized");
        cJSON_AddNumberToObject(accessor, "count", n);
        cJSON_AddStringToObject(accessor, "type", k ? "VEC3" : "VEC4");
        cJSON_AddItemToArray(accessors, accessor);
    }
    cJSON *attrs = cJSON_GetObjectItem(
        cJSON_GetArrayItem(cJSON_GetObjectItem(cJSON_GetArrayItem(cJSON_GetObjectItem(doc, "meshes"), 0), "primitives"),
                           0),
        "attributes");
    sinew_model *plain = load_or_fail(src);
    assert_null(plain->meshes[0].colors);
    sinew_model_free(plain);
    for (int k = 0; k < 2; k++) {
        cJSON_DeleteItemFromObject(attrs, "COLOR_0");
        cJSON_AddNumberToObject(attrs, "COLOR_0", first_accessor + k);
        char *out = cJSON_PrintUnformatted(doc);
        write_file(tmp_path("colors.gltf", file, sizeof file), out, strlen(out));
        free(out);
        sinew_model *m = load_or_fail(file);
        sinew_error error = {0};
        assert_int_equal(sinew_model_save(m, NULL, tmp_path("colors.sinew", saved, sizeof saved), &error), SINEW_OK);
        sinew_model *back = load_or_fail(saved);
        for (int pass = 0; pass < 2; pass++) {
            const sinew_mesh *mesh = &(pass ? back : m)->meshes[0];
            assert_non_null(mesh->colors);
            for (uint32_t v = 0; v < n; v++) {
                const float *c = &mesh->colors[v * 4];
                if (k == 0) {
                    assert_memory_equal(c, data + (size_t)v * 16, 16);
                } else {
                    assert_float_equal(c[0], (float)(unsigned char)(v * 37) / 255.0f, 1e-7f);
                    assert_float_equal(c[1], 128.0f / 255.0f, 1e-7f);
                    assert_float_equal(c[2], 1.0f, 0.0f);
                    assert_float_equal(c[3], 1.0f, 0.0f);
                }
            }
        }
        sinew_model_free(back);
        sinew_model_free(m);
    }
    cJSON_Delete(doc);
    free(data);
}

/* alphaMode and alphaCutoff (0.5 by default) reach the material, kept by a .sinew file; an
 * unknown mode is drawn opaque with a warning. */
static void test_alpha_modes(void **state)
{
    (void)state;
    char src[1024], file[1024], saved[1024];
    size_t size = 0;
    char *text = (char *)read_file(fixture_path("two_bone_cubic.gltf", src, sizeof src), &size);
    static const struct {
        const char *mode;
        double cutoff; /* < 0: none given */
        sinew_alpha_mode want;
        float want_cutoff;
    } cases[] = {{"MASK", 0.3, SINEW_ALPHA_MASK, 0.3f},
                 {"MASK", -1, SINEW_ALPHA_MASK, 0.5f},
                 {"BLEND", -1, SINEW_ALPHA_BLEND, 0.5f},
                 {"OPAQUE", 0.9, SINEW_ALPHA_OPAQUE, 0.5f},
                 {"CUTOUT", -1, SINEW_ALPHA_OPAQUE, 0.5f}};
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) {
        cJSON *doc = cJSON_ParseWithLength(text, size), *material = cJSON_CreateObject();
        cJSON_AddStringToObject(material, "alphaMode", cases[k].mode);
        if (cases[k].cutoff >= 0)
            cJSON_AddNumberToObject(material, "alphaCutoff", cases[k].cutoff);
        cJSON_AddItemToArray(cJSON_AddArrayToObject(doc, "materials"), material);
        char *out = cJSON_PrintUnformatted(doc);
        write_file(tmp_path("alpha.gltf", file, sizeof file), out, strlen(out));
        free(out);
        cJSON_Delete(doc);
        sinew_model *m = load_or_fail(file);
        sinew_error error = {0};
        assert_int_equal(sinew_model_save(m, NULL, tmp_path("alpha.sinew", saved, sizeof saved), &error), SINEW_OK);
        sinew_model *back = load_or_fail(saved);
        for (int pass = 0; pass < 2; pass++) {
            const sinew_material *mat = &(pass ? back : m)->materials[0];
            assert_int_equal(mat->alpha_mode, cases[k].want);
            assert_float_equal(mat->alpha_cutoff, cases[k].want_cutoff, 1e-7f);
        }
        bool warned = false;
        for (uint32_t w = 0; w < m->warning_count; w++)
            warned |= strstr(m->warnings[w], "CUTOUT") != NULL;
        assert_int_equal(warned, strcmp(cases[k].mode, "CUTOUT") == 0);
        sinew_model_free(back);
        sinew_model_free(m);
    }
    free(text);
}

static void check_pbr_spheres(const sinew_model *m)
{
    assert_int_equal(m->material_count, 4);
    const sinew_material *gold = &m->materials[0], *plastic = &m->materials[1], *bumps = &m->materials[2],
                         *glow = &m->materials[3];
    assert_true(gold->metallic_roughness);
    assert_float_equal(gold->metallic, 1.0f, 0.0f);
    assert_float_equal(gold->roughness, 0.25f, 0.0f);
    assert_float_equal(gold->base_color[2], 0.336f, 1e-6f);
    assert_float_equal(plastic->metallic, 0.0f, 0.0f);
    assert_float_equal(plastic->roughness, 0.6f, 1e-6f);
    for (int k = 0; k < SINEW_MAP_COUNT; k++)
        assert_true(!gold->maps[k].path && !gold->maps[k].image);
    /* factors default to 1; one image serves as metallic-roughness and occlusion map */
    assert_float_equal(bumps->metallic, 1.0f, 0.0f);
    assert_float_equal(bumps->roughness, 1.0f, 0.0f);
    assert_float_equal(bumps->normal_scale, 1.0f, 0.0f);
    assert_float_equal(bumps->occlusion_strength, 1.0f, 0.0f);
    assert_non_null(bumps->maps[SINEW_MAP_NORMAL].image);
    assert_non_null(bumps->maps[SINEW_MAP_METALLIC_ROUGHNESS].image);
    assert_int_equal(bumps->maps[SINEW_MAP_OCCLUSION].image_size, bumps->maps[SINEW_MAP_METALLIC_ROUGHNESS].image_size);
    assert_memory_equal(bumps->maps[SINEW_MAP_OCCLUSION].image, bumps->maps[SINEW_MAP_METALLIC_ROUGHNESS].image,
                        bumps->maps[SINEW_MAP_OCCLUSION].image_size);
    assert_null(bumps->maps[SINEW_MAP_BASE_COLOR].image);
    assert_null(bumps->maps[SINEW_MAP_EMISSIVE].image);
    /* emissiveFactor (1, 0.5, 0.1) times KHR_materials_emissive_strength 2 */
    assert_float_equal(glow->emissive[0], 2.0f, 1e-6f);
    assert_float_equal(glow->emissive[1], 1.0f, 1e-6f);
    assert_float_equal(glow->emissive[2], 0.2f, 1e-6f);
    assert_float_equal(glow->normal_scale, 0.5f, 0.0f);
    assert_non_null(glow->maps[SINEW_MAP_EMISSIVE].image);
    assert_int_equal(glow->maps[SINEW_MAP_NORMAL].image_size, bumps->maps[SINEW_MAP_NORMAL].image_size);
}

/* glTF's metallic-roughness materials: factors, the four other maps (embedded), emissive
 * strength; kept by a .sinew file; the "bumps" sphere's bitangent (w * normal x tangent)
 * points the way its UVs' v grows (up the image, where normal maps put +Y). */
static void test_pbr_materials(void **state)
{
    (void)state;
    char path[1024], saved[1024];
    sinew_model *m = load_or_fail(fixture_path("pbr_spheres.glb", path, sizeof path));
    check_pbr_spheres(m);
    assert_int_equal(m->warning_count, 0);
    const sinew_mesh *mesh = &m->meshes[2];
    assert_non_null(mesh->tangents);
    assert_null(m->meshes[3].tangents);
    uint32_t checked = 0, agree = bitangents_along_v(mesh, &checked);
    print_message("pbr_spheres bumps: bitangent along +v on %u of %u triangles\n", agree, checked);
    assert_true(checked > 2000);
    assert_int_equal(agree, checked);

    tmp_path("pbr_spheres.sinew", saved, sizeof saved);
    assert_int_equal(sinew_model_save(m, NULL, saved, NULL), SINEW_OK);
    sinew_model *back = load_or_fail(saved);
    check_pbr_spheres(back);
    /* one copy of the shared image in the file */
    assert_ptr_equal(back->materials[2].maps[SINEW_MAP_OCCLUSION].image,
                     back->materials[2].maps[SINEW_MAP_METALLIC_ROUGHNESS].image);
    assert_ptr_equal(back->materials[3].maps[SINEW_MAP_NORMAL].image, back->materials[2].maps[SINEW_MAP_NORMAL].image);
    sinew_model_free(back);
    sinew_model_free(m);

    /* Assimp's glTF reader gives the factors through its PBR keys */
    sinew_import_desc desc = {.path = path, .assimp = true};
    sinew_error error = {0};
    assert_int_equal(sinew_import(&desc, &m, &error), SINEW_OK);
    assert_true(m->materials[0].metallic_roughness);
    assert_float_equal(m->materials[0].metallic, 1.0f, 1e-6f);
    assert_float_equal(m->materials[0].roughness, 0.25f, 1e-6f);
    assert_non_null(m->materials[2].maps[SINEW_MAP_NORMAL].image);
    sinew_model_free(m);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_unnamed_nodes),
        cmocka_unit_test(test_repeated_names),
        cmocka_unit_test(test_quantized_sparse_texture_transform),
        cmocka_unit_test(test_refusals_say_where),
        cmocka_unit_test(test_embedded_images),
        cmocka_unit_test(test_pbr_materials),
        cmocka_unit_test(test_glb_header),
        cmocka_unit_test(test_missing_normals_are_flat),
        cmocka_unit_test(test_vertex_colours),
        cmocka_unit_test(test_alpha_modes),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
