/* Import as a library: sinew_import_memory() on every format sinew reads itself gives the model
 * the file gives (nodes, meshes, clips, and the pose at a time); external parts come through the
 * read_file callback (a glTF's .bin files served from memory, as from an archive, under a folder
 * that does not exist); sinew_import() with a callback reads nothing from the disk; bytes of a
 * format only Assimp reads, or an unknown format name, are SINEW_ERROR_UNSUPPORTED; a missing
 * part is an error naming it. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "helpers.h"

static sinew_model *from_file(const char *path)
{
    sinew_model *m = NULL;
    sinew_error error = {0};
    if (sinew_import(&(sinew_import_desc){.path = path}, &m, &error) != SINEW_OK)
        fail_msg("%s", error.message);
    return m;
}

/* The same model: counts, names and the first clip's pose at 0.4 s. */
static void same_model(const sinew_model *a, const sinew_model *b)
{
    assert_int_equal(a->node_count, b->node_count);
    assert_int_equal(a->mesh_count, b->mesh_count);
    assert_int_equal(a->clip_count, b->clip_count);
    for (uint32_t i = 0; i < a->mesh_count; i++)
        assert_int_equal(a->meshes[i].vertex_count, b->meshes[i].vertex_count);
    for (uint32_t i = 0; i < a->node_count; i++)
        assert_string_equal(a->node_names[i], b->node_names[i]);
    const sinew_clip *ca = a->clip_count ? &a->clips[0] : NULL, *cb = b->clip_count ? &b->clips[0] : NULL;
    sinew_mat4 *wa = pose_worlds(a, ca, 0.4f), *wb = pose_worlds(b, cb, 0.4f);
    assert_true(worlds_difference(wa, wb, a->node_count) == 0.0);
    free(wa), free(wb);
}

static void test_every_native_format(void **state)
{
    (void)state;
    static const struct {
        const char *file, *format;
        bool shared;
    } cases[] = {
        {"gltf-samples/Fox.glb", "glb", true},  {"two_bone_7400.fbx", "fbx", false},
        {"two_bone_ascii.fbx", NULL, false},    {"two_bone.dae", "dae", false},
        {"two_bone_anim.iqm", NULL, false},     {"two_bone_cubic.gltf", "gltf", false},
        {"blender/robot_walk.dae", NULL, true}, {"assimp/BVH/01_01.bvh", NULL, true},
        {"mixed_channels.bvh", "bvh", false},
    };
    for (size_t i = 0; i < sizeof cases / sizeof *cases; i++) {
        char path[1024];
        if (cases[i].shared ? !testdata_path(cases[i].file, path, sizeof path)
                            : !fixture_path(cases[i].file, path, sizeof path))
            fail_msg("missing %s", cases[i].file);
        size_t size = 0;
        void *bytes = read_file(path, &size);
        sinew_model *file = from_file(path), *memory = NULL;
        sinew_error error = {0};
        if (sinew_import_memory(bytes, size, cases[i].format, &(sinew_import_desc){.path = path}, &memory, &error) !=
            SINEW_OK)
            fail_msg("%s from memory: %s", cases[i].file, error.message);
        same_model(file, memory);
        /* and as a .sinew blob */
        void *blob = NULL;
        size_t blob_size = 0;
        assert_int_equal(sinew_model_write_blob(file, NULL, &blob, &blob_size, NULL), SINEW_OK);
        sinew_model *again = NULL;
        assert_int_equal(sinew_import_memory(blob, blob_size, NULL, NULL, &again, &error), SINEW_OK);
        same_model(file, again);
        print_message("%-24s from memory (%s): %u nodes, %u clips, as from the file\n", cases[i].file,
                      cases[i].format ? cases[i].format : "told from the bytes", memory->node_count,
                      memory->clip_count);
        sinew_model_free(file), sinew_model_free(memory), sinew_model_free(again);
        free(bytes), free(blob);
    }
}

/* An archive in memory: the files by name. */
typedef struct archive {
    const char *names[4];
    void *bytes[4];
    size_t sizes[4];
    int count;
    char asked[4][1024];
    int asked_count;
} archive;

static bool from_archive(const char *path, void **bytes, size_t *size, void *user)
{
    archive *a = user;
    if (a->asked_count < 4)
        snprintf(a->asked[a->asked_count++], sizeof a->asked[0], "%s", path);
    for (int i = 0; i < a->count; i++)
        if (strcmp(path, a->names[i]) == 0) {
            *bytes = malloc(a->sizes[i]);
            memcpy(*bytes, a->bytes[i], a->sizes[i]);
            *size = a->sizes[i];
            return true;
        }
    return false;
}

static void test_parts_through_the_callback(void **state)
{
    (void)state;
    char dir[1024], path[1100];
    if (!testdata_path("gltf-samples/SimpleMorph", dir, sizeof dir))
        fail_msg("missing gltf-samples/SimpleMorph");
    archive a = {.names = {"pack/SimpleMorph.gltf", "pack/simpleMorphGeometry.bin", "pack/simpleMorphAnimation.bin"},
                 .count = 3};
    static const char *const files[3] = {"SimpleMorph.gltf", "simpleMorphGeometry.bin", "simpleMorphAnimation.bin"};
    for (int i = 0; i < 3; i++) {
        snprintf(path, sizeof path, "%s/%s", dir, files[i]);
        a.bytes[i] = read_file(path, &a.sizes[i]);
    }
    snprintf(path, sizeof path, "%s/SimpleMorph.gltf", dir);
    sinew_model *file = from_file(path), *memory = NULL, *called = NULL;
    sinew_error error = {0};
    sinew_import_desc desc = {.path = "pack/SimpleMorph.gltf", .read_file = from_archive, .read_user = &a};
    if (sinew_import_memory(a.bytes[0], a.sizes[0], NULL, &desc, &memory, &error) != SINEW_OK)
        fail_msg("%s", error.message);
    same_model(file, memory);
    assert_int_equal(memory->morph_channel_count, file->morph_channel_count);
    assert_int_equal(a.asked_count, 2);
    assert_string_equal(a.asked[0], "pack/simpleMorphGeometry.bin");
    /* sinew_import() with the callback: the model itself from the archive too */
    a.asked_count = 0;
    if (sinew_import(&desc, &called, &error) != SINEW_OK)
        fail_msg("%s", error.message);
    same_model(file, called);
    assert_int_equal(a.asked_count, 3);
    assert_string_equal(a.asked[0], "pack/SimpleMorph.gltf");
    /* a part the archive lacks: an error naming it */
    a.count = 2;
    sinew_model *none = NULL;
    assert_int_not_equal(sinew_import_memory(a.bytes[0], a.sizes[0], "gltf", &desc, &none, &error), SINEW_OK);
    print_message("a missing part: %s\n", error.message);
    assert_null(none);
    assert_non_null(strstr(error.message, "simpleMorphAnimation.bin"));
    sinew_model_free(file), sinew_model_free(memory), sinew_model_free(called);
    for (int i = 0; i < 3; i++)
        free(a.bytes[i]);
}

static void test_what_memory_does_not_read(void **state)
{
    (void)state;
    char path[1024];
    sinew_error error = {0};
    sinew_model *m = NULL;
    static const char x[] =
        "xof 0303txt 0032\nFrame Root {\n FrameTransformMatrix { 1,0,0,0,0,1,0,0,0,0,1,0,0,0,0,1;; }\n}\n";
    assert_int_equal(sinew_import_memory(x, sizeof x - 1, NULL, NULL, &m, &error), SINEW_ERROR_UNSUPPORTED);
    assert_non_null(strstr(error.message, "(memory).model"));
    assert_int_equal(sinew_import_memory(x, sizeof x - 1, "x", NULL, &m, &error), SINEW_ERROR_UNSUPPORTED);
    assert_non_null(strstr(error.message, "\"x\""));
    assert_string_equal(error.file, "(memory).x");
    assert_int_equal(sinew_import_memory("", 0, "fbx", NULL, &m, &error), SINEW_ERROR_FORMAT);
    assert_int_equal(sinew_import_memory(NULL, 0, "fbx", NULL, NULL, &error), SINEW_ERROR_INVALID_ARGUMENT);
    /* garbage named as a format: that reader's refusal, naming the model */
    fixture_path("two_bone.dae", path, sizeof path);
    assert_int_equal(sinew_import_memory("Kaydara FBX Binary  \0\x1a\0", 23, "fbx",
                                         &(sinew_import_desc){.path = "cut.fbx"}, &m, &error),
                     SINEW_ERROR_FORMAT);
    assert_string_equal(error.file, "cut.fbx");
    assert_null(m);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_every_native_format),
        cmocka_unit_test(test_parts_through_the_callback),
        cmocka_unit_test(test_what_memory_does_not_read),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
