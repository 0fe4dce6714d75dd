/* Bad input never crashes: each case returns an error (or, where sinew can repair the
 * data, a warning) whose message names the file and the problem. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "helpers.h"

static void expect_error(const char *path, sinew_result kind, const char *needle)
{
    sinew_model *m = (sinew_model *)1;
    sinew_error error = {0};
    sinew_import_desc desc = {.path = path};
    sinew_result r = sinew_import(&desc, &m, &error);
    if (r != kind)
        fail_msg("%s: expected %s, got %s: %s", path, sinew_result_string(kind), sinew_result_string(r), error.message);
    assert_null(m);
    if (!strstr(error.message, path) || !strstr(error.message, needle))
        fail_msg("message \"%s\" should name %s and say \"%s\"", error.message, path, needle);
    assert_string_equal(error.file, path); /* the error names its file as a field too */
}

/* Where in the file: a binary FBX cut short gives the byte offset, a COLLADA element the line,
 * broken glTF JSON the offset of the error; in process (the default) and through the helper. */
static void test_where_in_the_file(void **state)
{
    (void)state;
    char fbx[1024], dae[1024], gltf[1024];
    static const char dae_text[] = "<?xml version=\"1.0\"?>\n<COLLADA xmlns=\"http://www.collada.org/2005/11/"
                                   "COLLADASchema\" version=\"1.4.1\">\n<asset><up_axis>Y_UP</asset>\n"
                                   "</COLLADA>\n";
    static const char gltf_text[] = "{\"asset\": {\"version\": \"2.0\"},\n \"nodes\": [ {\"name\": } ]}";
    write_file(tmp_path("where.dae", dae, sizeof dae), dae_text, sizeof dae_text - 1);
    write_file(tmp_path("where.gltf", gltf, sizeof gltf), gltf_text, sizeof gltf_text - 1);
    /* a binary FBX header and a node record that runs past the end */
    unsigned char bin[64] = "Kaydara FBX Binary  \0\x1a\0";
    bin[23] = 0xE8, bin[24] = 0x1C; /* version 7400 */
    bin[27] = 0xFF, bin[28] = 0xFF; /* the first node ends at 65535 */
    write_file(tmp_path("where.fbx", fbx, sizeof fbx), bin, sizeof bin);
    for (int isolate = 0; isolate < 2; isolate++) {
        sinew_error error = {0};
        sinew_model *m = NULL;
        assert_int_equal(sinew_import(&(sinew_import_desc){.path = dae, .isolate = isolate}, &m, &error),
                         SINEW_ERROR_FORMAT);
        print_message("%s: line %u, offset %lld\n", error.message, error.line, (long long)error.offset);
        assert_string_equal(error.file, dae);
        assert_int_equal(error.line, 3);
        assert_int_equal(sinew_import(&(sinew_import_desc){.path = gltf, .isolate = isolate}, &m, &error),
                         SINEW_ERROR_FORMAT);
        print_message("%s: offset %lld\n", error.message, (long long)error.offset);
        assert_int_equal(error.offset, (int64_t)(strstr(gltf_text, "} ]") - gltf_text));
        assert_int_equal(sinew_import(&(sinew_import_desc){.path = fbx, .isolate = isolate}, &m, &error),
                         SINEW_ERROR_FORMAT);
        print_message("%s: offset %lld\n", error.message, (long long)error.offset);
        assert_true(error.offset >= 27 && error.offset < 64);
        assert_string_equal(error.file, fbx);
    }
    /* a missing file: the file, no offset or line */
    sinew_error error = {0};
    sinew_model *m = NULL;
    char missing[1024];
    tmp_path("where-not.glb", missing, sizeof missing);
    assert_int_equal(sinew_import(&(sinew_import_desc){.path = missing}, &m, &error), SINEW_ERROR_IO);
    assert_string_equal(error.file, missing);
    assert_true(error.offset == -1 && error.line == 0);
    assert_string_equal(sinew_result_name(SINEW_ERROR_LIMIT_MEMORY), "limit_memory");
    assert_string_equal(sinew_result_name(SINEW_RESULT_LAST), "internal");
}

static void test_missing_directory_empty(void **state)
{
    (void)state;
    char path[1024];
    expect_error(tmp_path("no-such-model.dae", path, sizeof path), SINEW_ERROR_IO, "No such file");
    tmp_path("a-directory.dae", path, sizeof path);
    mkdir(path, 0755);
    expect_error(path, SINEW_ERROR_IO, "directory");
    tmp_path("empty.dae", path, sizeof path);
    write_file(path, "", 0);
    expect_error(path, SINEW_ERROR_FORMAT, "empty");
    sinew_error error = {0};
    sinew_model *m;
    assert_int_equal(sinew_import(NULL, &m, &error), SINEW_ERROR_INVALID_ARGUMENT);
    assert_int_equal(sinew_import(&(sinew_import_desc){.path = NULL}, &m, &error), SINEW_ERROR_INVALID_ARGUMENT);
}

static void test_unknown_format_and_garbage(void **state)
{
    (void)state;
    char path[1024];
    tmp_path("notes.xyz", path, sizeof path);
    write_file(path, "hello, world\n", 13);
    expect_error(path, SINEW_ERROR_IMPORTER, "No suitable reader");
    unsigned char junk[4096];
    uint32_t x = 12345;
    for (size_t i = 0; i < sizeof junk; i++) {
        x = x * 1103515245u + 12345u;
        junk[i] = (unsigned char)(x >> 16);
    }
    static const char *const names[] = {"junk.dae", "junk.gltf",    "junk.glb", "junk.fbx", "junk.x",
                                        "junk.bvh", "junk.md5mesh", "junk.smd", "junk.iqm"};
    for (size_t i = 0; i < sizeof names / sizeof names[0]; i++) {
        tmp_path(names[i], path, sizeof path);
        write_file(path, junk, sizeof junk);
        sinew_model *m = NULL;
        sinew_error error = {0};
        sinew_import_desc desc = {.path = path};
        sinew_result r = sinew_import(&desc, &m, &error);
        print_message("%-12s -> %s: %s\n", names[i], sinew_result_string(r), error.message);
        if (r == SINEW_OK) { /* some readers make an empty scene of anything; then it must be valid */
            sinew_model_free(m);
            continue;
        }
        assert_non_null(strstr(error.message, path));
    }
}

/* Every prefix of a small COLLADA and a small glTF file: an error naming the file, unless
 * all that is missing is trailing white space. */
static void check_every_prefix(const char *fixture, const char *name)
{
    char src[1024], path[1024];
    size_t size;
    char *bytes = read_file(fixture_path(fixture, src, sizeof src), &size);
    assert_non_null(bytes);
    tmp_path(name, path, sizeof path);
    size_t complete = size;
    while (complete > 0 && strchr(" \t\r\n", bytes[complete - 1]))
        complete--;
    uint32_t refused = 0;
    for (size_t n = 0; n < size; n++) {
        write_file(path, bytes, n);
        sinew_model *m = NULL;
        sinew_error error = {0};
        /* In process: a reader's crash is this test's (and the sanitizers see it), and
         * thousands of imports do not each start the helper. */
        sinew_import_desc desc = {.path = path};
        sinew_result r = sinew_import(&desc, &m, &error);
        if (r == SINEW_OK) {
            if (n < complete)
                fail_msg("%s cut to %zu of %zu bytes was accepted", fixture, n, size);
            sinew_model_free(m);
            continue;
        }
        refused++;
        if (!strstr(error.message, path))
            fail_msg("%s cut to %zu bytes: message \"%s\" does not name the file", fixture, n, error.message);
    }
    print_message("%s: %u of %zu prefixes refused with a message\n", fixture, refused, size);
    free(bytes);
}

static void test_every_prefix_of_collada(void **state)
{
    (void)state;
    check_every_prefix("two_bone.dae", "prefix.dae");
}

static void test_every_prefix_of_gltf(void **state)
{
    (void)state;
    check_every_prefix("two_bone_cubic.gltf", "prefix.gltf");
}

static void test_every_prefix_of_iqm(void **state)
{
    (void)state;
    check_every_prefix("two_bone.iqm", "prefix.iqm");
}

/* The fixture with one string replaced. */
static void write_edited(const char *fixture, const char *from, const char *to, const char *name, char *path,
                         size_t size)
{
    char src[1024];
    size_t n;
    char *text = read_file(fixture_path(fixture, src, sizeof src), &n);
    char *at = strstr(text, from);
    assert_non_null(at);
    FILE *f = fopen(tmp_path(name, path, size), "w");
    assert_non_null(f);
    fwrite(text, 1, (size_t)(at - text), f);
    fputs(to, f);
    fputs(at + strlen(from), f);
    fclose(f);
    free(text);
}

static void test_nan_and_inf(void **state)
{
    (void)state;
    char path[1024];
    write_edited("two_bone.dae", "0 0 0 1 0 0 0 2 0 1 2 0", "0 0 0 1 nan 0 0 2 0 1 2 0", "nan.dae", path, sizeof path);
    expect_error(path, SINEW_ERROR_DATA, "not finite");
    write_edited("two_bone.dae", "0 0 0 1 0 0 0 2 0 1 2 0", "0 0 0 1 0 0 0 2 0 1 inf 0", "inf.dae", path, sizeof path);
    expect_error(path, SINEW_ERROR_DATA, "not finite");
    write_edited("two_bone.dae", "0 -1 0 0 1 0 0 1", "0 -1 0 0 1 0 0 nan", "nan-key.dae", path, sizeof path);
    expect_error(path, SINEW_ERROR_DATA, "not finite");
}

/* Weights of zero: Assimp drops zero weights, so the vertex arrives without influences.
 * sinew loads the file, binds the vertex to its mesh's node and says so in a warning
 * naming the mesh (the builder refuses influences that are listed but sum to zero; see
 * test_blob). */
static void test_zero_weights(void **state)
{
    (void)state;
    char path[1024];
    write_edited("two_bone.dae", "<v>0 0 0 0 1 1 1 1</v>", "<v>0 0 0 0 1 1 1 2</v>", "zero-weights.dae", path,
                 sizeof path);
    /* weight index 2 does not exist: Assimp's reaction decides; then a real zero weight */
    sinew_model *m = NULL;
    sinew_error error = {0};
    sinew_import_desc desc = {.path = path};
    sinew_result r = sinew_import(&desc, &m, &error);
    if (r == SINEW_OK)
        sinew_model_free(m);
    else
        assert_non_null(strstr(error.message, path));

    write_edited("two_bone.dae", "count=\"2\">1 1</float_array>", "count=\"2\">1 0</float_array>", "zero-weight.dae",
                 path, sizeof path);
    m = load_or_fail(path);
    bool warned = false;
    for (uint32_t i = 0; i < m->warning_count; i++)
        warned |= strstr(m->warnings[i], "no skin weights") && strstr(m->warnings[i], "quad");
    assert_true(warned);
    sinew_mat4 *w = pose_worlds(m, &m->clips[0], 1);
    uint32_t n;
    float *v = posed_vertices(m, w, &n);
    for (uint32_t i = 0; i < n * 3; i++)
        assert_true(isfinite(v[i]));
    /* the unweighted vertices stay where the mesh's node puts them: (0,2,0) and (1,2,0) */
    assert_near(v[2 * 3 + 1], 2, 1e-6, "unweighted vertex stays");
    free(v);
    free(w);
    sinew_model_free(m);
}

/* A COLLADA chain of `joints` joints, each weighting one vertex of a strip. */
static void write_many_joints(const char *path, uint32_t joints)
{
    FILE *f = fopen(path, "w");
    assert_non_null(f);
    uint32_t verts = joints + (3 - joints % 3) % 3;
    fprintf(f,
            "<?xml version=\"1.0\"?>\n<COLLADA xmlns=\"http://www.collada.org/2005/11/COLLADASchema\" "
            "version=\"1.4.1\"><asset><up_axis>Y_UP</up_axis></asset>\n<library_geometries><geometry id=\"g\"><mesh>"
            "<source id=\"p\"><float_array id=\"pa\" count=\"%u\">",
            verts * 3);
    for (uint32_t i = 0; i < verts; i++)
        fprintf(f, "%u %u 0 ", i % 2, i);
    fprintf(f,
            "</float_array><technique_common><accessor source=\"#pa\" count=\"%u\" stride=\"3\"><param name=\"X\" "
            "type=\"float\"/><param name=\"Y\" type=\"float\"/><param name=\"Z\" type=\"float\"/></accessor>"
            "</technique_common></source><vertices id=\"v\"><input semantic=\"POSITION\" source=\"#p\"/></vertices>"
            "<triangles count=\"%u\"><input semantic=\"VERTEX\" source=\"#v\" offset=\"0\"/><p>",
            verts, verts / 3);
    for (uint32_t i = 0; i < verts; i++)
        fprintf(f, "%u ", i);
    fprintf(f,
            "</p></triangles></mesh></geometry></library_geometries>\n<library_controllers><controller id=\"c\"><skin "
            "source=\"#g\"><source id=\"j\"><Name_array id=\"ja\" count=\"%u\">",
            joints);
    for (uint32_t i = 0; i < joints; i++)
        fprintf(f, "j%u ", i);
    fprintf(f,
            "</Name_array><technique_common><accessor source=\"#ja\" count=\"%u\"><param name=\"JOINT\" type=\"name\"/>"
            "</accessor></technique_common></source><source id=\"m\"><float_array id=\"ma\" count=\"%u\">",
            joints, joints * 16);
    for (uint32_t i = 0; i < joints; i++)
        fprintf(f, "1 0 0 0 0 1 0 %d 0 0 1 0 0 0 0 1 ", -(int)i);
    fprintf(f,
            "</float_array><technique_common><accessor source=\"#ma\" count=\"%u\" stride=\"16\"><param name=\"T\" "
            "type=\"float4x4\"/></accessor></technique_common></source><source id=\"w\"><float_array id=\"wa\" "
            "count=\"1\">1</float_array><technique_common><accessor source=\"#wa\" count=\"1\"><param name=\"W\" "
            "type=\"float\"/></accessor></technique_common></source><joints><input semantic=\"JOINT\" source=\"#j\"/>"
            "<input semantic=\"INV_BIND_MATRIX\" source=\"#m\"/></joints><vertex_weights count=\"%u\"><input "
            "semantic=\"JOINT\" source=\"#j\" offset=\"0\"/><input semantic=\"WEIGHT\" source=\"#w\" "
            "offset=\"1\"/><vcount>",
            joints, verts);
    for (uint32_t i = 0; i < verts; i++)
        fprintf(f, "1 ");
    fprintf(f, "</vcount><v>");
    for (uint32_t i = 0; i < verts; i++)
        fprintf(f, "%u 0 ", i < joints ? i : joints - 1);
    fprintf(f, "</v></vertex_weights></skin></controller></library_controllers>\n<library_visual_scenes><visual_scene "
               "id=\"s\">");
    for (uint32_t i = 0; i < joints; i++)
        fprintf(f, "<node id=\"j%u\" sid=\"j%u\" name=\"j%u\" type=\"JOINT\"><translate>0 %d 0</translate>", i, i, i,
                i ? 1 : 0);
    for (uint32_t i = 0; i < joints; i++)
        fprintf(f, "</node>");
    fprintf(f, "<node id=\"n\" name=\"strip\"><instance_controller url=\"#c\"><skeleton>#j0</skeleton>"
               "</instance_controller></node></visual_scene></library_visual_scenes><scene><instance_visual_scene "
               "url=\"#s\"/></scene></COLLADA>\n");
    fclose(f);
}

static void test_joint_limit(void **state)
{
    (void)state;
    char path[1024];
    write_many_joints(tmp_path("1024-joints.dae", path, sizeof path), SINEW_MAX_JOINTS);
    sinew_model *m = load_or_fail(path);
    assert_int_equal(m->skins[0].joint_count, SINEW_MAX_JOINTS);
    sinew_model_free(m);
    write_many_joints(tmp_path("1100-joints.dae", path, sizeof path), 1100);
    expect_error(path, SINEW_ERROR_LIMIT, "1100 joints");
}

/* Assimp itself dies on this file (SIGSEGV): sinew reports it and goes on. */
static void test_assimp_crash_is_an_error(void **state)
{
    (void)state;
    char path[1024];
    if (!testdata_path("assimp/X/malformed_skinweights_oob.x", path, sizeof path))
        skip();
    expect_error(path, SINEW_ERROR_IMPORTER, "crashed");
    /* and the process is fine: the next import works */
    char good[1024];
    sinew_model_free(load_or_fail(fixture_path("two_bone.dae", good, sizeof good)));
}

/* Loading through a caller's allocator, and every allocation failure it can produce. */
typedef struct counting {
    int calls, fail_at;
} counting;

static void *counting_alloc(size_t size, void *user)
{
    counting *c = user;
    if (c->calls++ == c->fail_at)
        return NULL;
    return aligned_alloc(16, (size + 15) & ~(size_t)15);
}

static void counting_free(void *ptr, void *user)
{
    (void)user;
    free(ptr);
}

static void test_allocator(void **state)
{
    (void)state;
    char path[1024];
    counting c = {0, -1};
    sinew_allocator a = {counting_alloc, counting_free, &c};
    sinew_model *m = NULL;
    sinew_error error = {0};
    sinew_import_desc desc = {.path = fixture_path("two_bone.dae", path, sizeof path), .allocator = &a};
    assert_int_equal(sinew_import(&desc, &m, &error), SINEW_OK);
    assert_int_equal(c.calls, 1); /* one block */
    sinew_model_free(m);
    c = (counting){0, 0};
    assert_int_equal(sinew_import(&desc, &m, &error), SINEW_ERROR_OUT_OF_MEMORY);
    assert_non_null(strstr(error.message, "out of memory"));
    assert_null(m);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_missing_directory_empty),
        cmocka_unit_test(test_where_in_the_file),
        cmocka_unit_test(test_unknown_format_and_garbage),
        cmocka_unit_test(test_every_prefix_of_collada),
        cmocka_unit_test(test_every_prefix_of_gltf),
        cmocka_unit_test(test_every_prefix_of_iqm),
        cmocka_unit_test(test_nan_and_inf),
        cmocka_unit_test(test_zero_weights),
        cmocka_unit_test(test_joint_limit),
        cmocka_unit_test(test_assimp_crash_is_an_error),
        cmocka_unit_test(test_allocator),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
