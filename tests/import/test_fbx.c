/* sinew's FBX reader on its own fixtures (tests/fixtures/make_fbx.py writes them): the three
 * encodings of one scene agree, curves evaluate as FBX defines them, inherit types reach the
 * runtime, and bad files (every prefix, changed bytes, cycles, huge counts, other versions)
 * are refused with a message naming the file, in this process so that the sanitizers see the
 * reader itself. */
#define _GNU_SOURCE /* memmem */
#include <math.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "helpers.h"
#include "core/internal.h"
#include "import/internal.h"

/* One scene in every version and encoding sinew reads: FBX 7.4 ASCII first, then binary 7.4
 * and 7.5, then 6.1 binary and ASCII (make_fbx.py writes them to pose the same). */
static const char *const encodings[] = {"two_bone_ascii.fbx", "two_bone_7400.fbx", "two_bone_7500.fbx",
                                        "two_bone_6100.fbx", "two_bone_6100_ascii.fbx"};
#define ENCODINGS 5
/* Every file of the sweeps, with its ASCII-ness: those and FBX 5.0. */
static const struct {
    const char *file;
    bool ascii;
} sweep_files[] = {{"two_bone_ascii.fbx", true},      {"two_bone_7400.fbx", false}, {"two_bone_7500.fbx", false},
                   {"two_bone_6100_ascii.fbx", true}, {"two_bone_6100.fbx", false}, {"two_bone_5000.fbx", false}};

/* World matrices of `count` nodes agree element by element within `tol`. */
static void assert_worlds_near(const sinew_mat4 *a, const sinew_mat4 *b, uint32_t count, double tol, const char *what)
{
    for (uint32_t n = 0; n < count; n++)
        for (int e = 0; e < 16; e++)
            assert_near(a[n].m[e], b[n].m[e], tol, what);
}

/* The local transforms of a model's first clip at time t (malloc'd). */
static sinew_transform *sample_locals(const sinew_model *m, float t)
{
    sinew_transform *locals = calloc(m->node_count, sizeof *locals);
    sinew_sample_desc desc = {
        .model = m, .clip = &m->clips[0], .time = t, .locals = locals, .local_count = m->node_count};
    assert_int_equal(sinew_sample(&desc, NULL), SINEW_OK);
    return locals;
}

static void test_encodings_agree(void **state)
{
    (void)state;
    char path[1024];
    sinew_model *m[ENCODINGS];
    for (int i = 0; i < ENCODINGS; i++)
        m[i] = load_or_fail(fixture_path(encodings[i], path, sizeof path));
    for (int i = 1; i < ENCODINGS; i++) {
        assert_int_equal(m[i]->node_count, m[0]->node_count);
        assert_int_equal(m[i]->clip_count, 1);
        for (int k = 0; k <= 9; k++) {
            float t = k / 9.0f;
            sinew_mat4 *a = pose_worlds(m[0], &m[0]->clips[0], t), *b = pose_worlds(m[i], &m[i]->clips[0], t);
            assert_worlds_near(a, b, m[0]->node_count, 1e-6, encodings[i]);
            free(a);
            free(b);
        }
    }
    for (int i = 0; i < ENCODINGS; i++)
        sinew_model_free(m[i]);
}

static void quat_zx(double z_degrees, double x_degrees, double q[4])
{
    double z = z_degrees * M_PI / 360, x = x_degrees * M_PI / 360;
    q[0] = cos(z) * sin(x);
    q[1] = sin(z) * sin(x);
    q[2] = sin(z) * cos(x);
    q[3] = cos(z) * cos(x);
}

static void expect_rotation(const sinew_model *m, int32_t node, float t, double z, double x)
{
    sinew_transform *locals = sample_locals(m, t);
    double q[4];
    quat_zx(z, x, q);
    const float *r = locals[node].rotation;
    /* a float quaternion is unit to 6e-8, which alone moves acos(dot) by 3e-4: normalise */
    double len = sqrt((double)r[0] * r[0] + (double)r[1] * r[1] + (double)r[2] * r[2] + (double)r[3] * r[3]);
    double d = fabs(q[0] * r[0] + q[1] * r[1] + q[2] * r[2] + q[3] * r[3]) / len;
    if (!(d > 1 - 1e-10 || 2 * acos(fmin(d, 1.0)) < 2e-6))
        fail_msg("bone2 at t=%g: rotation (%g %g %g %g), expected Z %g X %g degrees", (double)t, (double)r[0],
                 (double)r[1], (double)r[2], (double)r[3], z, x);
    free(locals);
}

/* bone2's rotation: X steps from 0 to 30 degrees at 0.5 s (a constant key); Z is cubic with
 * automatic tangents through 20, 50, 10, 40 at 0, 0.25, 0.75, 1 s. */
static void test_curves(void **state)
{
    (void)state;
    char path[1024];
    sinew_model *m = load_or_fail(fixture_path("two_bone_7400.fbx", path, sizeof path));
    int32_t bone2 = sinew_model_find_node(m, "bone2");
    assert_true(bone2 > 0);
    expect_rotation(m, bone2, 0.0f, 20, 0);
    expect_rotation(m, bone2, 0.25f, 50, 0);
    expect_rotation(m, bone2, 0.75f, 10, 30);
    expect_rotation(m, bone2, 1.0f, 40, 30);
    /* Between keys: the Bezier of the keys with the automatic slopes of FBX 7.x, which are not
     * time-independent here (flags 0x108): half the secant through the neighbours, half the
     * neighbouring slopes blended by where the key lies between them. At 0.25 s: secant
     * (10 - 20) / 0.75, sides (50 - 20) / 0.25 and (10 - 50) / 0.5 at 1/3: slope 20; at 0.75 s
     * the same by symmetry. Handles a third of the way; checked off the middle (0.4 s), where
     * other slopes would give another value. */
    double t0 = 0.25, t1 = 0.75, v0 = 50, v1 = 10, dt = t1 - t0;
    double s0 = 0.5 * (10.0 - 20) / 0.75 + 0.5 * ((50.0 - 20) / 0.25 * (2.0 / 3) + (10.0 - 50) / 0.5 / 3);
    double s1 = 0.5 * (40.0 - 50) / 0.75 + 0.5 * ((10.0 - 50) / 0.5 / 3 + (40.0 - 10) / 0.25 * (2.0 / 3));
    assert_near(s0, 20.0, 1e-12, "slope at 0.25 s");
    assert_near(s1, 20.0, 1e-12, "slope at 0.75 s");
    double u = (0.4 - t0) / dt, w = 1 - u;
    double z =
        w * w * w * v0 + 3 * w * w * u * (v0 + s0 * dt / 3) + 3 * w * u * u * (v1 - s1 * dt / 3) + u * u * u * v1;
    expect_rotation(m, bone2, 0.4f, z, 0);
    /* The additive layer at 50 %: bone3's translation Y, 1 at rest, plays 1 + 0.5 * 2. */
    int32_t bone3 = sinew_model_find_node(m, "bone3");
    assert_near(m->node_rest[bone3].translation[1], 1.0, 1e-6, "bone3 at rest");
    sinew_transform *locals = sample_locals(m, 0.3f);
    assert_near(locals[bone3].translation[0], 5.0, 1e-5, "bone3 x");
    assert_near(locals[bone3].translation[1], 2.0, 1e-5, "bone3 y, base plus half the additive layer");
    free(locals);
    sinew_model_free(m);
}

static void test_inherit_types_reach_the_runtime(void **state)
{
    (void)state;
    char path[1024];
    for (int i = 0; i < ENCODINGS; i++) {
        sinew_model *m = load_or_fail(fixture_path(encodings[i], path, sizeof path));
        assert_non_null(m->node_inherit);
        assert_int_equal(m->node_inherit[sinew_model_find_node(m, "bone1")], SINEW_INHERIT_NORMAL);
        assert_int_equal(m->node_inherit[sinew_model_find_node(m, "bone2")], SINEW_INHERIT_COMPONENTWISE_SCALE);
        assert_int_equal(m->node_inherit[sinew_model_find_node(m, "bone3")], SINEW_INHERIT_IGNORE_PARENT_SCALE);
        /* The player (SIMD and scalar) and sample + sinew_local_to_world agree. */
        test_player tp;
        sinew_player *p = test_player_open(&tp, m, &m->clips[0]);
        sinew_mat4 *w = calloc(m->node_count, sizeof *w);
        for (int k = 0; k <= 9; k++) {
            sinew_mat4 *ref = pose_worlds(m, &m->clips[0], k / 9.0f);
            assert_int_equal(sinew_player_update(p, k / 9.0f, SINEW_WRAP_CLAMP, NULL, w, m->node_count, NULL),
                             SINEW_OK);
            assert_worlds_near(w, ref, m->node_count, 1e-5, "player vs sample + world");
            free(ref);
        }
        free(w);
        test_player_close(&tp);
        sinew_model_free(m);
    }
}

/* Through .sinew: the inherit types are stored (section NINH) and the poses are the same. */
static void test_sinew_round_trip(void **state)
{
    (void)state;
    char path[1024];
    sinew_model *m = load_or_fail(fixture_path("two_bone_7500.fbx", path, sizeof path));
    void *bytes = NULL;
    size_t size = 0;
    assert_int_equal(sinew_model_write_blob(m, NULL, &bytes, &size, NULL), SINEW_OK);
    sinew_model *back = NULL;
    assert_int_equal(sinew_model_from_blob(bytes, size, "round trip", NULL, &back, NULL), SINEW_OK);
    assert_non_null(back->node_inherit);
    assert_memory_equal(back->node_inherit, m->node_inherit, m->node_count);
    for (int k = 0; k <= 9; k++) {
        sinew_mat4 *a = pose_worlds(m, &m->clips[0], k / 9.0f), *b = pose_worlds(back, &back->clips[0], k / 9.0f);
        assert_memory_equal(a, b, m->node_count * sizeof *a);
        free(a);
        free(b);
    }
    /* An inherit type out of range is refused. */
    unsigned char *edited = malloc(size);
    memcpy(edited, bytes, size);
    const unsigned char *at = memmem(edited, size, "NINH", 4);
    assert_non_null(at);
    uint32_t offset;
    memcpy(&offset, at + 4, 4);
    edited[offset] = 7;
    uint32_t checksum = sinew_blob_checksum(edited, size); /* so that the validation is what refuses it */
    memcpy(edited + offsetof(blob_file_header, checksum), &checksum, 4);
    sinew_error error = {0};
    sinew_model *bad = NULL;
    assert_int_equal(sinew_model_from_blob(edited, size, "edited", NULL, &bad, &error), SINEW_ERROR_FORMAT);
    assert_non_null(strstr(error.message, "inherit"));
    free(edited);
    free(bytes);
    /* COLLADA cannot say that a node ignores its parent's scale: refused, not written wrong. */
    char dae[1024];
    tmp_path("inherit.dae", dae, sizeof dae);
    assert_int_equal(sinew_model_write_collada(m, dae, &error), SINEW_ERROR_LIMIT);
    assert_non_null(strstr(error.message, "bone2"));
    sinew_model_free(back);
    sinew_model_free(m);
}

/* ---- bad files ---------------------------------------------------------------------------- */

static sinew_result read_bytes(const char *name, const unsigned char *bytes, size_t size, char *message)
{
    raw_model raw;
    sinew_error error = {0};
    sinew_result r = raw_model_from_fbx(name, bytes, size, &raw, &error);
    if (r == SINEW_OK) {
        void *blob = NULL;
        size_t blob_size = 0;
        r = raw_model_build(&raw, &blob, &blob_size, &error);
        free(blob);
        raw_model_free(&raw);
    }
    if (message)
        strcpy(message, error.message);
    return r;
}

/* Whether an ASCII prefix ends right after a complete top-level node (braces outside strings
 * balanced, a '}' last): a shorter document, which may load. */
static bool ends_on_top_level_node(const unsigned char *text, size_t n)
{
    int depth = 0;
    bool in_string = false;
    unsigned char last = 0;
    for (size_t i = 0; i < n; i++) {
        unsigned char c = text[i];
        if (c == '"')
            in_string = !in_string;
        else if (!in_string && c == '{')
            depth++;
        else if (!in_string && c == '}')
            depth--;
        if (c != ' ' && c != '\t' && c != '\r' && c != '\n')
            last = c;
    }
    return depth == 0 && !in_string && last == '}';
}

/* Every prefix of every fixture is refused with the file named, except an ASCII document cut
 * between two top-level nodes (then it loads or is refused; never a crash). */
static void test_every_prefix_refused(void **state)
{
    (void)state;
    char path[1024], message[SINEW_ERROR_MESSAGE_SIZE];
    for (size_t i = 0; i < sizeof sweep_files / sizeof sweep_files[0]; i++) {
        size_t size;
        unsigned char *bytes = read_file(fixture_path(sweep_files[i].file, path, sizeof path), &size);
        assert_int_equal(read_bytes("whole.fbx", bytes, size, NULL), SINEW_OK);
        /* What may go without loss: a binary file's null record and 140-byte footer (both
         * after the last record), ASCII's closing brace's newline. */
        bool wide = strstr(sweep_files[i].file, "7500") != NULL;
        size_t complete = sweep_files[i].ascii ? size - 3 : size - 140 - (wide ? 25 : 13);
        uint32_t shorter = 0;
        for (size_t n = 0; n < complete; n++) {
            unsigned char *copy = malloc(n + 1);
            memcpy(copy, bytes, n);
            copy[n] = 0;
            sinew_result r = read_bytes("cut.fbx", copy, n, message);
            bool whole_nodes = sweep_files[i].ascii && ends_on_top_level_node(copy, n);
            shorter += whole_nodes && r == SINEW_OK;
            if ((r == SINEW_OK && !whole_nodes) || (r != SINEW_OK && !strstr(message, "cut.fbx")))
                fail_msg("%s cut to %zu of %zu bytes: %s (%s)", sweep_files[i].file, n, size, sinew_result_string(r),
                         message);
            free(copy);
        }
        print_message("%s: %zu prefixes refused, %u ending between top-level nodes loaded\n", sweep_files[i].file,
                      complete - shorter, shorter);
        free(bytes);
    }
}

/* Every byte of the binary files changed (a different bit each time): refused or read,
 * never a crash, a hang or a sanitizer report. */
static void test_changed_bytes(void **state)
{
    (void)state;
    char path[1024];
    for (size_t i = 0; i < sizeof sweep_files / sizeof sweep_files[0]; i++) {
        if (sweep_files[i].ascii)
            continue;
        size_t size;
        unsigned char *bytes = read_file(fixture_path(sweep_files[i].file, path, sizeof path), &size);
        uint32_t refused = 0;
        for (size_t k = 0; k < size; k++) {
            unsigned char *copy = malloc(size);
            memcpy(copy, bytes, size);
            copy[k] ^= (unsigned char)(1u << (k % 8));
            refused += read_bytes("changed.fbx", copy, size, NULL) != SINEW_OK;
            free(copy);
        }
        print_message("%s: %zu bytes changed one at a time, %u refused\n", sweep_files[i].file, size, refused);
        free(bytes);
    }
}

static char *replaced(const char *fixture, const char *from, const char *to, size_t *size)
{
    char path[1024];
    size_t n;
    char *text = read_file(fixture_path(fixture, path, sizeof path), &n);
    char *at = strstr(text, from);
    assert_non_null(at);
    char *out = malloc(n + strlen(to) + 1);
    size_t head = (size_t)(at - text);
    memcpy(out, text, head);
    strcpy(out + head, to);
    strcat(out, at + strlen(from));
    *size = strlen(out);
    free(text);
    return out;
}

static void expect_refused(const char *what, const void *bytes, size_t size, const char *needle)
{
    char message[SINEW_ERROR_MESSAGE_SIZE];
    sinew_result r = read_bytes("bad.fbx", bytes, size, message);
    if (r == SINEW_OK || !strstr(message, "bad.fbx") || !strstr(message, needle))
        fail_msg("%s: %s, \"%s\" (expected a refusal saying \"%s\")", what, sinew_result_string(r), message, needle);
}

static void test_refusals(void **state)
{
    (void)state;
    size_t n;
    /* bone1 under bone3, which is under bone1. */
    char *text = replaced("two_bone_ascii.fbx", "C: \"OO\", 101, 100", "C: \"OO\", 101, 103", &n);
    expect_refused("a cycle of models", text, n, "cycle");
    free(text);
    /* Found by fuzz_fbx: a model connected to its parent twice was added twice (a heap
     * overflow); it is one node. */
    text = replaced("two_bone_ascii.fbx", "C: \"OO\", 103, 102", "C: \"OO\", 103, 102\n\tC: \"OO\", 103, 102", &n);
    assert_int_equal(read_bytes("twice.fbx", (const unsigned char *)text, n, NULL), SINEW_OK);
    free(text);
    /* Found by fuzz_fbx: numbers out of an int's range where the reader wants one (a cast
     * would be undefined) are read as absent; a material index of two billion is one mesh,
     * read at once (the slots were walked from 0 to the largest). */
    text = replaced("two_bone_ascii.fbx", "P: \"RotationOrder\", \"enum\", \"\", \"\", 4",
                    "P: \"RotationOrder\", \"enum\", \"\", \"\", 7.8e15", &n);
    assert_int_equal(read_bytes("huge-order.fbx", (const unsigned char *)text, n, NULL), SINEW_OK);
    free(text);
    text =
        replaced("two_bone_ascii.fbx", "Materials: *1 {\n\t\t\t\ta: 0", "Materials: *1 {\n\t\t\t\ta: 2000000000", &n);
    raw_model raw;
    assert_int_equal(raw_model_from_fbx("huge-slot.fbx", (const unsigned char *)text, n, &raw, NULL), SINEW_OK);
    assert_int_equal(raw.mesh_count, 1);
    assert_int_equal(raw.meshes[0].material, -1); /* the model has one material, slot 0 */
    raw_model_free(&raw);
    free(text);
    text = replaced("two_bone_ascii.fbx", "FBXVersion: 7400", "FBXVersion: 8100", &n);
    expect_refused("FBX 8.1", text, n, "version 8.1 is newer than sinew reads");
    free(text);
    /* A document is read by its layout: objects with ids are FBX 7.x whatever the header says. */
    text = replaced("two_bone_ascii.fbx", "FBXVersion: 7400", "FBXVersion: 6100", &n);
    assert_int_equal(read_bytes("labelled-6100.fbx", (const unsigned char *)text, n, NULL), SINEW_OK);
    free(text);
    text = replaced("two_bone_ascii.fbx", "a: 0,1,4,-4,1,2,5,-5", "a: 0,1,4,-4,1,2,5,-9", &n);
    expect_refused("a corner outside the vertices", text, n, "outside its vertex array");
    free(text);
    text = replaced("two_bone_ascii.fbx", "Indexes: *4 {\n\t\t\ta: 0,1,3,4", "Indexes: *4 {\n\t\t\ta: 0,1,3,400", &n);
    expect_refused("a cluster index outside the mesh", text, n, "outside its mesh");
    free(text);
    text =
        replaced("two_bone_ascii.fbx", "KeyTime: *3 {\n\t\t\ta: 0,23093079000,", "KeyTime: *3 {\n\t\t\ta: 0,-5,", &n);
    expect_refused("key times going back", text, n, "backwards");
    free(text);
    /* A binary array claiming 2^31 - 1 elements: refused from its sizes, nothing allocated. */
    char path[1024];
    size_t size;
    unsigned char *bytes = read_file(fixture_path("two_bone_7400.fbx", path, sizeof path), &size);
    unsigned char *at = memmem(bytes, size, "Vertices", 8);
    assert_non_null(at);
    at += 8 + 1; /* the name, then the array's type byte */
    memcpy(at, "\xff\xff\xff\x7f", 4);
    expect_refused("a huge array count", bytes, size, "array");
    free(bytes);
    bytes = read_file(fixture_path("two_bone_7500.fbx", path, sizeof path), &size);
    at = memmem(bytes, size, "Vertices", 8);
    at += 8 + 1;
    memcpy(at, "\xff\xff\xff\x0f", 4); /* zlib data that inflates to far less than claimed */
    expect_refused("a compressed array shorter than its count", bytes, size, "array");
    free(bytes);
}

/* two_bone_ascii.fbx with `objects` added before its deformer and `connections` before its
 * first connection, written as `name` in the scratch folder (into path). */
static void write_with(const char *name, const char *objects, const char *connections, char *path, size_t size)
{
    size_t n;
    char before[512];
    snprintf(before, sizeof before, "%s\tDeformer: 400,", objects);
    char *text = replaced("two_bone_ascii.fbx", "\tDeformer: 400,", before, &n);
    char *linked = malloc(n + strlen(connections) + 1);
    char *at = strstr(text, "\tC: \"OO\", 100, 0");
    assert_non_null(at);
    size_t head = (size_t)(at - text);
    memcpy(linked, text, head);
    strcpy(linked + head, connections);
    strcat(linked, at);
    write_file(tmp_path(name, path, size), linked, strlen(linked));
    free(linked);
    free(text);
}

/* A texture stored with the path of the machine that wrote the file is found by its name
 * beside the model. */
static void test_texture_by_name(void **state)
{
    (void)state;
    char path[1024], image[1024];
    write_with("textured.fbx",
               "\tTexture: 600, \"Texture::skin\", \"\" {\n"
               "\t\tRelativeFilename: \"..\\..\\art\\skin_diffuse.png\"\n"
               "\t\tFileName: \"C:\\art\\skin_diffuse.png\"\n\t}\n",
               "\tC: \"OP\", 600, 300, \"DiffuseColor\"\n", path, sizeof path);
    write_file(tmp_path("skin_diffuse.png", image, sizeof image), "png", 3);
    sinew_model *m = load_or_fail(path);
    assert_int_equal(m->material_count, 1);
    assert_non_null(m->materials[0].maps[SINEW_MAP_BASE_COLOR].path);
    const char *found = strrchr(m->materials[0].maps[SINEW_MAP_BASE_COLOR].path, '/');
    assert_string_equal(found, "/skin_diffuse.png");
    sinew_model_free(m);
}

/* A texture embedded in the file (its Video's Content) whose file is not there: the image is
 * carried (base64 in ASCII, here in two pieces padded one by one; bytes in binary), with no
 * "not found" warning. maya_slime's binary and ASCII exports carry the same PNG. */
static void test_embedded_texture(void **state)
{
    (void)state;
    char path[1024];
    write_with("embedded.fbx",
               "\tTexture: 600, \"Texture::skin\", \"\" {\n"
               "\t\tRelativeFilename: \"skin_gone.png\"\n\t}\n"
               "\tVideo: 700, \"Video::skin\", \"Clip\" {\n"
               "\t\tContent: , \"iVBORw==\", \"DQoaCg==\"\n\t}\n",
               "\tC: \"OP\", 600, 300, \"DiffuseColor\"\n\tC: \"OO\", 700, 600\n", path, sizeof path);
    sinew_model *m = load_or_fail(path);
    const sinew_texture *map = &m->materials[0].maps[SINEW_MAP_BASE_COLOR];
    assert_null(map->path);
    assert_int_equal(map->image_size, 8);
    assert_memory_equal(map->image, "\x89PNG\r\n\x1a\n", 8);
    for (uint32_t w = 0; w < m->warning_count; w++)
        assert_null(strstr(m->warnings[w], "not found"));
    sinew_model_free(m);

    char ascii[1024], binary[1024];
    if (!testdata_path("ufbx/maya_slime_7500_ascii.fbx", ascii, sizeof ascii) ||
        !testdata_path("ufbx/maya_slime_7500_binary.fbx", binary, sizeof binary))
        return;
    sinew_model *a = load_or_fail(ascii), *b = load_or_fail(binary);
    const sinew_texture *ta = &a->materials[0].maps[SINEW_MAP_BASE_COLOR],
                        *tb = &b->materials[0].maps[SINEW_MAP_BASE_COLOR];
    assert_non_null(ta->image);
    assert_int_equal(ta->image_size, tb->image_size);
    assert_memory_equal(ta->image, tb->image, ta->image_size);
    assert_memory_equal(ta->image, "\x89PNG", 4);
    sinew_model_free(a);
    sinew_model_free(b);
}

/* Through sinew_import: a file named .fbx that is not FBX is not handed to Assimp. */
static void test_not_fbx(void **state)
{
    (void)state;
    char path[1024];
    tmp_path("not-really.fbx", path, sizeof path);
    write_file(path, "solid cube\nendsolid cube\n", 25);
    sinew_model *m = NULL;
    sinew_error error = {0};
    assert_int_equal(sinew_import(&(sinew_import_desc){.path = path}, &m, &error), SINEW_ERROR_FORMAT);
    assert_non_null(strstr(error.message, "not an FBX file"));
    assert_non_null(strstr(error.message, path));
}

/* FBX 5.0 (make_fbx.py): models at the top level with their children by name, transforms
 * from their channels' defaults, a skin of Link clusters, a take that moves bone1 2 -> 6 cm. */
static void test_fbx5(void **state)
{
    (void)state;
    char path[1024];
    sinew_model *m = load_or_fail(fixture_path("two_bone_5000.fbx", path, sizeof path));
    int32_t bone1 = sinew_model_find_node(m, "bone1"), bone3 = sinew_model_find_node(m, "bone3");
    assert_true(bone1 > 0 && bone3 > 0);
    assert_int_equal(m->node_parents[bone1], sinew_model_find_node(m, "root"));
    assert_int_equal(m->node_parents[bone3], sinew_model_find_node(m, "bone2"));
    assert_int_equal(m->clip_count, 1);
    assert_string_equal(m->clips[0].name, "bend");
    assert_near(m->clips[0].duration, 1.0, 1e-6, "take length");
    assert_int_equal(m->skin_count, 1);
    assert_int_equal(m->skins[0].joint_count, 2);
    sinew_transform *at0 = sample_locals(m, 0.0f), *at1 = sample_locals(m, 1.0f);
    assert_near(at0[bone1].translation[0], 2.0, 1e-6, "bone1 x at 0 s");
    assert_near(at1[bone1].translation[0], 6.0, 1e-6, "bone1 x at 1 s");
    assert_near(at1[bone3].translation[0], 5.0, 1e-6, "bone3 x, its channel default");
    assert_near(at1[bone3].scale[0], 1.5, 1e-6, "bone3 scale x, its channel default");
    free(at0);
    free(at1);
    sinew_model_free(m);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_encodings_agree),  cmocka_unit_test(test_fbx5),
        cmocka_unit_test(test_curves),           cmocka_unit_test(test_inherit_types_reach_the_runtime),
        cmocka_unit_test(test_sinew_round_trip), cmocka_unit_test(test_texture_by_name),
        cmocka_unit_test(test_embedded_texture), cmocka_unit_test(test_every_prefix_refused),
        cmocka_unit_test(test_changed_bytes),    cmocka_unit_test(test_refusals),
        cmocka_unit_test(test_not_fbx),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
