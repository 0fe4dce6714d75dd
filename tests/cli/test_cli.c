/* The `sinew` command as a user runs it: exit codes, messages, the JSON interface of
 * `sinew pose` and `sinew info`, OBJ output. */
#include <math.h>
#include <stdio.h>
#include <sys/wait.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include <cjson/cJSON.h>
#include <stb_image.h>

#include "helpers.h"

/* Runs sinew, expects exit 0 and JSON on stdout; returns the parsed document. */
static cJSON *run_json(const char *const *args)
{
    run_result r = run_sinew(NULL, args);
    if (r.code != 0)
        fail_msg("%s %s: exit %d: %s", args[0], args[1], r.code, r.err);
    cJSON *root = cJSON_Parse(r.out);
    assert_non_null(root);
    run_free(&r);
    return root;
}

#define RUN_JSON(...) run_json((const char *const[]){__VA_ARGS__, NULL})

static void test_usage_and_help(void **state)
{
    (void)state;
    run_result r = run_sinew(NULL, (const char *const[]){NULL});
    assert_int_equal(r.code, 1);
    assert_non_null(strstr(r.err, "usage: sinew"));
    run_free(&r);
    r = RUN("--help");
    assert_int_equal(r.code, 0);
    assert_non_null(strstr(r.out, "info FILE"));
    assert_non_null(strstr(r.out, "pose FILE"));
    assert_non_null(strstr(r.out, "render FILE"));
    assert_non_null(strstr(r.out, "bench render"));
    run_free(&r);
    r = RUN("bench", "--help");
    assert_int_equal(r.code, 0);
    assert_non_null(strstr(r.out, "usage: sinew bench"));
    run_free(&r);
    /* bench muscle reads its options (it ran the benchmark whatever it was given) */
    r = RUN("bench", "muscle", "--help");
    assert_int_equal(r.code, 0);
    assert_non_null(strstr(r.out, "usage: sinew bench muscle"));
    assert_null(strstr(r.out, "volume drift"));
    run_free(&r);
    r = RUN("bench", "muscle", "--bogus");
    assert_int_equal(r.code, 1);
    assert_non_null(strstr(r.err, "unknown option --bogus"));
    run_free(&r);
    static const char *const commands[] = {"info", "pose", "render", "muscle"};
    for (int i = 0; i < 4; i++) {
        r = RUN(commands[i], "--help");
        assert_int_equal(r.code, 0);
        assert_non_null(strstr(r.out, "usage: sinew"));
        run_free(&r);
        r = RUN(commands[i]);
        assert_int_equal(r.code, 1);
        assert_non_null(strstr(r.err, "no FILE"));
        run_free(&r);
    }
    r = RUN("frobnicate");
    assert_int_equal(r.code, 1);
    assert_non_null(strstr(r.err, "unknown command"));
    assert_null(strstr(r.err, "did you mean"));
    run_free(&r);
    /* a misspelt command gets the nearest one */
    r = RUN("rendr", "x.fbx");
    assert_int_equal(r.code, 1);
    assert_non_null(strstr(r.err, "did you mean `sinew render`"));
    run_free(&r);
    r = RUN("poes");
    assert_non_null(strstr(r.err, "did you mean `sinew pose`"));
    run_free(&r);
}

/* f3d's camera placement: --camera-position and --camera-focal-point draw what the fly camera at
 * that eye, turned to face the point, draws (0 pixels differ); --fov changes the picture; bad
 * values are usage errors. */
static void test_camera_position_focal_point_fov(void **state)
{
    (void)state;
    char path[1024], a[1024], b[1024], c[1024];
    fixture_path("two_bone.dae", path, sizeof path);
    tmp_path("placed.png", a, sizeof a);
    tmp_path("fly.png", b, sizeof b);
    tmp_path("fov.png", c, sizeof c);
    run_result r = RUN("render", path, "--camera-position", "0.5,1.5,4", "--camera-focal-point", "0,1,0", "--no-grid",
                       "--size", "160x120", "--samples", "1", "-o", a);
    if (r.code == 3) { /* no EGL here */
        run_free(&r);
        skip();
    }
    assert_int_equal(r.code, 0);
    run_free(&r);
    /* the eye's yaw and pitch towards the point: atan2(0.5, 4) and asin(0.5 / |(-0.5,-0.5,-4)|) */
    r = RUN("render", path, "--camera", "fly:0.5,1.5,4,7.125016,7.070555", "--no-grid", "--size", "160x120",
            "--samples", "1", "-o", b);
    assert_int_equal(r.code, 0);
    run_free(&r);
    r = RUN("render", path, "--camera-position", "0.5,1.5,4", "--camera-focal-point", "0,1,0", "--no-grid", "--fov",
            "20", "--size", "160x120", "--samples", "1", "-o", c);
    assert_int_equal(r.code, 0);
    run_free(&r);
    int w, h, n;
    unsigned char *pa = stbi_load(a, &w, &h, &n, 3), *pb = stbi_load(b, &w, &h, &n, 3),
                  *pc = stbi_load(c, &w, &h, &n, 3);
    assert_true(pa && pb && pc);
    long same = 0, changed = 0;
    for (long i = 0; i < (long)w * h; i++) {
        int d = 0, e = 0;
        for (int k = 0; k < 3; k++) {
            d = abs(pa[i * 3 + k] - pb[i * 3 + k]) > d ? abs(pa[i * 3 + k] - pb[i * 3 + k]) : d;
            e = abs(pa[i * 3 + k] - pc[i * 3 + k]) > e ? abs(pa[i * 3 + k] - pc[i * 3 + k]) : e;
        }
        same += d > 32;
        changed += e > 32;
    }
    assert_true(same <= (long)w * h / 200);
    assert_true(changed > (long)w * h / 50); /* a narrower view: the model larger */
    stbi_image_free(pa);
    stbi_image_free(pb);
    stbi_image_free(pc);
    r = RUN("render", path, "--fov", "500", "-o", a);
    assert_int_equal(r.code, 1);
    assert_non_null(strstr(r.err, "--fov"));
    run_free(&r);
    r = RUN("render", path, "--camera-focal-point", "1,2", "-o", a);
    assert_int_equal(r.code, 1);
    assert_non_null(strstr(r.err, "expected X,Y,Z"));
    run_free(&r);
}

/* A render of many frames shows its progress on a terminal (script(1) gives it one), and
 * nothing of it when stderr is a file. */
static void test_render_progress_on_a_terminal(void **state)
{
    (void)state;
    char path[1024], out[1024], command[4096];
    fixture_path("two_bone.dae", path, sizeof path);
    tmp_path("progress_%03d.png", out, sizeof out);
    if (system("command -v script >/dev/null 2>&1") != 0)
        skip();
    snprintf(command, sizeof command,
             "script -qec '%s render %s --from 0 --to 2 --fps 30 --size 64x48 -o %s' /dev/null", getenv("SINEW_EXE"),
             path, out);
    FILE *f = popen(command, "r");
    assert_non_null(f);
    char text[8192] = "";
    size_t n = fread(text, 1, sizeof text - 1, f);
    text[n] = '\0';
    int status = pclose(f);
    if (strstr(text, "EGL") && status != 0) /* no OpenGL here */
        skip();
    assert_int_equal(status, 0);
    assert_non_null(strstr(text, "/61 frames"));
    assert_non_null(strstr(text, "61 frames 64x48")); /* the summary after the line is cleared */
    run_result r = RUN("render", path, "--from", "0", "--to", "2", "--fps", "30", "--size", "64x48", "-o", out);
    assert_int_equal(r.code, 0);
    assert_null(strstr(r.err, "/61 frames"));
    run_free(&r);
}

/* Times outside the clip are said to be clamped (or wrapped with --loop), not silently moved;
 * --quiet hides the note. */
static void test_time_outside_the_clip(void **state)
{
    (void)state;
    char path[1024], png[1024];
    fixture_path("two_bone.dae", path, sizeof path);
    tmp_path("outside.png", png, sizeof png);
    run_result r = RUN("pose", path, "--time", "0.5,99,120");
    assert_int_equal(r.code, 0);
    assert_non_null(strstr(r.err, "99 s lies outside clip"));
    assert_non_null(strstr(r.err, "(and 1 more time): clamped to"));
    run_free(&r);
    r = RUN("pose", path, "--time", "0.5");
    assert_null(strstr(r.err, "outside"));
    run_free(&r);
    r = RUN("render", path, "--time", "99", "--loop", "--size", "32x24", "-o", png);
    if (r.code == 3) { /* no EGL here */
        run_free(&r);
        return;
    }
    assert_int_equal(r.code, 0);
    assert_non_null(strstr(r.err, "99 s lies outside clip"));
    assert_non_null(strstr(r.err, "wrapped to"));
    run_free(&r);
    r = RUN("render", path, "--time", "99", "--size", "32x24", "-o", png, "-q");
    assert_int_equal(r.code, 0);
    assert_null(strstr(r.err, "outside"));
    run_free(&r);
}

static void test_bad_input_exits_2(void **state)
{
    (void)state;
    char path[1024];
    run_result r = RUN("info", tmp_path("missing.dae", path, sizeof path));
    assert_int_equal(r.code, 2);
    assert_non_null(strstr(r.err, path));
    run_free(&r);
    tmp_path("half.dae", path, sizeof path);
    char src[1024];
    size_t size;
    char *bytes = read_file(fixture_path("two_bone.dae", src, sizeof src), &size);
    for (size_t n = 0; n < size - 1; n += 97) {
        write_file(path, bytes, n);
        r = RUN("pose", path, "--json");
        if (r.code != 2 || !strstr(r.err, path) || r.out_size != 0)
            fail_msg("prefix of %zu bytes: exit %d, stderr \"%s\"", n, r.code, r.err);
        run_free(&r);
    }
    free(bytes);
    fixture_path("two_bone.dae", path, sizeof path);
    static const char *const bad_usage[][4] = {
        {"pose", "--time", "abc", NULL},   {"pose", "--time", "", NULL},
        {"pose", "--time", "1e39", NULL},  {"pose", "--mesh", "/tmp/x.obj", "--time"},
        {"pose", "--time", "0,nan", NULL}, {"info", "--frob", NULL, NULL},
    };
    for (size_t i = 0; i < sizeof bad_usage / sizeof bad_usage[0]; i++) {
        const char *args[8] = {bad_usage[i][0], path};
        int n = 2;
        for (int k = 1; k < 4 && bad_usage[i][k]; k++)
            args[n++] = bad_usage[i][k];
        args[n] = NULL;
        r = run_sinew(NULL, args);
        if (r.code != 1 || r.err_size == 0)
            fail_msg("%s %s %s: exit %d", args[0], args[2], args[3] ? args[3] : "", r.code);
        run_free(&r);
    }
    r = RUN("pose", path, "--mesh", "/tmp/x.obj", "--time", "0,1");
    assert_int_equal(r.code, 1);
    assert_non_null(strstr(r.err, "single --time"));
    run_free(&r);
    /* a clip the file lacks is bad input (2) in every command */
    r = RUN("pose", path, "--clip", "nosuch");
    assert_int_equal(r.code, 2);
    assert_non_null(strstr(r.err, "no clip \"nosuch\""));
    run_free(&r);
    /* the message lists the clips, suggests a near name, names the index range; "none" is the rest pose */
    r = RUN("pose", "builtin:demo", "--clip", "Wlak");
    assert_int_equal(r.code, 2);
    assert_non_null(strstr(r.err, "did you mean \"walk\""));
    assert_non_null(strstr(r.err, "0 \"walk\", 1 \"wave\""));
    run_free(&r);
    r = RUN("pose", "builtin:demo", "--clip", "7");
    assert_int_equal(r.code, 2);
    assert_non_null(strstr(r.err, "no clip 7: the file's clips are 0..1"));
    run_free(&r);
    r = RUN("pose", "builtin:demo", "--clip", "none", "--json", "--time", "0");
    assert_int_equal(r.code, 0);
    assert_non_null(strstr(r.out, "\"clip\":null"));
    run_free(&r);
    r = RUN("bench", "muscle", "--bogus");
    assert_int_equal(r.code, 1);
    run_free(&r);
    /* the import helper's limits, on any command, anywhere after it */
    r = RUN("info", path, "--import-timeout", "soon");
    assert_int_equal(r.code, 1);
    assert_non_null(strstr(r.err, "--import-timeout"));
    run_free(&r);
    r = RUN("pose", "--import-memory", "64", path, "--import-timeout", "30", "--time", "0");
    assert_int_equal(r.code, 0);
    run_free(&r);
    char duck[1024], hangs[1024];
    if (testdata_path("assimp/Collada/duck.dae", duck, sizeof duck)) {
        char *d = read_file(duck, &size);
        d[245632] = (char)0xC0; /* Assimp's COLLADA reader loops on it */
        write_file(tmp_path("cli-hangs.dae", hangs, sizeof hangs), d, size);
        free(d);
        r = run_sinew((const char *const[]){"SINEW_IMPORTER=assimp", NULL},
                      (const char *const[]){"info", hangs, "--import-timeout", "0.5", "--import-memory", "4096",
                                            NULL}); /* the deadline, not a small file's memory default */
        assert_int_equal(r.code, 2);
        assert_non_null(strstr(r.err, "0.5 s deadline"));
        assert_non_null(strstr(r.err, "--import-timeout sets the deadline"));
        run_free(&r);
    }
    /* outputs (4): the OBJ over its own model, onto a full device; the model is untouched */
    size_t before = 0, after = 0;
    free(read_file(path, &before));
    r = RUN("pose", path, "--mesh", path);
    assert_int_equal(r.code, 4);
    assert_non_null(strstr(r.err, "the output is the input file"));
    run_free(&r);
    free(read_file(path, &after));
    assert_int_equal(before, after);
    r = RUN("pose", path, "--mesh", "/dev/full");
    assert_int_equal(r.code, 4);
    run_free(&r);
    r = RUN("pose", path, "--mesh", "/nonexistent-dir/x.obj", "--time", "0");
    assert_int_equal(r.code, 4);
    assert_non_null(strstr(r.err, "/nonexistent-dir/x.obj"));
    run_free(&r);
}

static const cJSON *node_named(const cJSON *frame, const char *name)
{
    const cJSON *node;
    cJSON_ArrayForEach(node, cJSON_GetObjectItem(frame, "nodes"))
    {
        if (strcmp(cJSON_GetObjectItem(node, "name")->valuestring, name) == 0)
            return node;
    }
    fail_msg("no node %s", name);
    return NULL;
}

static double at(const cJSON *node, const char *key, int i)
{
    return cJSON_GetArrayItem(cJSON_GetObjectItem(node, key), i)->valuedouble;
}

/* The stable JSON interface: keys, default times, values on the hand-made fixture. */
static void test_pose_json(void **state)
{
    (void)state;
    char path[1024];
    fixture_path("two_bone.dae", path, sizeof path);
    cJSON *root = RUN_JSON("pose", path, "--json");
    assert_string_equal(cJSON_GetObjectItem(root, "file")->valuestring, path);
    const cJSON *clip = cJSON_GetObjectItem(root, "clip");
    assert_int_equal(cJSON_GetObjectItem(clip, "index")->valueint, 0);
    assert_non_null(cJSON_GetObjectItem(clip, "name")->valuestring);
    assert_near(cJSON_GetObjectItem(clip, "duration")->valuedouble, 1, 1e-6, "duration");
    const cJSON *frames = cJSON_GetObjectItem(root, "frames");
    assert_int_equal(cJSON_GetArraySize(frames), 10);
    for (int i = 0; i < 10; i++)
        assert_near(cJSON_GetObjectItem(cJSON_GetArrayItem(frames, i), "time")->valuedouble, i / 9.0, 1e-6, "time");
    const cJSON *last = cJSON_GetArrayItem(frames, 9);
    const cJSON *tip = node_named(last, "tip");
    assert_string_equal(cJSON_GetObjectItem(tip, "parent")->valuestring, "root");
    assert_true(cJSON_IsNull(cJSON_GetObjectItem(node_named(last, "scene"), "parent")));
    assert_near(at(tip, "translation", 1), 1, 1e-6, "tip y");
    assert_near(fabs(at(tip, "rotation", 2)), sqrt(0.5), 1e-6, "tip turned 90 degrees about z");
    assert_near(at(tip, "scale", 0), 1, 1e-6, "tip scale");
    cJSON_Delete(root);

    /* clamping and looping */
    root = RUN_JSON("pose", path, "--json", "--time", "0.5,7");
    frames = cJSON_GetObjectItem(root, "frames");
    assert_near(fabs(at(node_named(cJSON_GetArrayItem(frames, 0), "tip"), "rotation", 2)), sin(M_PI / 8), 1e-6,
                "t=0.5");
    assert_near(fabs(at(node_named(cJSON_GetArrayItem(frames, 1), "tip"), "rotation", 2)), sqrt(0.5), 1e-6,
                "t=7 clamps");
    cJSON_Delete(root);
    root = RUN_JSON("pose", path, "--json", "--time", "7.5", "--loop", "--clip", "0");
    frames = cJSON_GetObjectItem(root, "frames");
    assert_near(fabs(at(node_named(cJSON_GetArrayItem(frames, 0), "tip"), "rotation", 2)), sin(M_PI / 8), 1e-6,
                "t=7.5 loops to 0.5");
    cJSON_Delete(root);
}

static void test_pose_mesh_obj(void **state)
{
    (void)state;
    char path[1024], obj[1024];
    fixture_path("two_bone.dae", path, sizeof path);
    tmp_path("bent.obj", obj, sizeof obj);
    run_result r = RUN("pose", path, "--time", "1", "--mesh", obj);
    assert_int_equal(r.code, 0);
    run_free(&r);
    size_t size;
    char *text = read_file(obj, &size);
    assert_non_null(text);
    float v[4][3];
    int n = 0;
    for (char *line = strtok(text, "\n"); line && n < 4; line = strtok(NULL, "\n"))
        if (sscanf(line, "v %f %f %f", &v[n][0], &v[n][1], &v[n][2]) == 3)
            n++;
    assert_int_equal(n, 4);
    /* the top edge (0,2,0) and (1,2,0) turns 90 degrees about the tip joint at (0,1,0) */
    assert_near(v[2][0], -1, 1e-5, "x");
    assert_near(v[2][1], 1, 1e-5, "y");
    assert_near(v[3][0], -1, 1e-5, "x");
    assert_near(v[3][1], 2, 1e-5, "y");
    assert_near(v[1][0], 1, 1e-5, "bottom stays");
    free(text);
}

static void test_info_json_and_text(void **state)
{
    (void)state;
    char path[1024];
    fixture_path("two_bone_cubic.gltf", path, sizeof path);
    cJSON *root = RUN_JSON("info", path, "--json");
    const cJSON *counts = cJSON_GetObjectItem(root, "counts");
    assert_int_equal(cJSON_GetObjectItem(counts, "joints")->valueint, 2);
    assert_int_equal(cJSON_GetObjectItem(counts, "meshes")->valueint, 1);
    const cJSON *clip = cJSON_GetArrayItem(cJSON_GetObjectItem(root, "clips"), 0);
    assert_string_equal(cJSON_GetObjectItem(clip, "name")->valuestring, "bend");
    assert_int_equal(cJSON_GetObjectItem(cJSON_GetObjectItem(clip, "keys"), "rotation")->valueint, 2);
    cJSON_Delete(root);
    run_result r = RUN("info", path);
    assert_int_equal(r.code, 0);
    assert_non_null(strstr(r.out, "tip_joint  [joint]"));
    assert_non_null(strstr(r.out, "\"bend\""));
    run_free(&r);
}

/* cJSON is loaded when a command first writes JSON: text output never needs it, and a libcjson
 * that lacks its functions stops --json with a message and exit 3. */
static void test_json_library_loaded_on_use(void **state)
{
    (void)state;
    char path[1024];
    fixture_path("two_bone_cubic.gltf", path, sizeof path);
    const char *const env[] = {"LD_LIBRARY_PATH=" NO_CJSON_DIR, NULL};
    run_result r = RUN_ENV(env, "info", path);
    assert_int_equal(r.code, 0);
    assert_non_null(strstr(r.out, "tip_joint  [joint]"));
    run_free(&r);
    r = RUN_ENV(env, "info", path, "--json");
    assert_int_equal(r.code, 3);
    assert_non_null(strstr(r.err, "libcjson.so.1, which --json output needs, lacks cJSON_"));
    assert_int_equal(r.out_size, 0);
    run_free(&r);
}

/* An FBX file's inherit types, in JSON and in the tree; SINEW_IMPORTER=assimp reads it
 * through Assimp instead (which has no inherit types). */
static void test_info_fbx_inherit(void **state)
{
    (void)state;
    char path[1024];
    fixture_path("two_bone_7400.fbx", path, sizeof path);
    cJSON *root = RUN_JSON("info", path, "--json");
    assert_string_equal(cJSON_GetObjectItem(root, "format")->valuestring, "fbx");
    const cJSON *node;
    int componentwise = 0, ignoring = 0;
    cJSON_ArrayForEach(node, cJSON_GetObjectItem(root, "nodes"))
    {
        const char *inherit = cJSON_GetObjectItem(node, "inherit")->valuestring;
        componentwise += strcmp(inherit, "componentwise_scale") == 0;
        ignoring += strcmp(inherit, "ignore_parent_scale") == 0;
    }
    assert_int_equal(componentwise, 1);
    assert_int_equal(ignoring, 1);
    cJSON_Delete(root);
    run_result r = RUN("info", path);
    assert_non_null(strstr(r.out, "bone2  [joint]  [componentwise scale: RrSs]"));
    run_free(&r);
    r = run_sinew((const char *const[]){"SINEW_IMPORTER=assimp", NULL}, (const char *const[]){"info", path, NULL});
    assert_int_equal(r.code, 0);
    assert_null(strstr(r.out, "RrSs"));
    run_free(&r);
}

/* A model without clips poses at rest: clip null, one frame. */
static void test_pose_without_animation(void **state)
{
    (void)state;
    char path[1024];
    if (!testdata_path("collada-cts/SkinController.dae", path, sizeof path))
        skip();
    cJSON *root = RUN_JSON("pose", path, "--json");
    assert_true(cJSON_IsNull(cJSON_GetObjectItem(root, "clip")));
    assert_int_equal(cJSON_GetArraySize(cJSON_GetObjectItem(root, "frames")), 1);
    cJSON_Delete(root);
}

/* `sinew pose` on the two files of one scene gives the same joint positions. */
static void test_pose_pairs_agree(void **state)
{
    (void)state;
    char a[1024], b[1024];
    if (!testdata_path("ufbx/maya_transformed_skin_7700_ascii.fbx", a, sizeof a))
        skip();
    testdata_path("ufbx/maya_transformed_skin_7700_binary.fbx", b, sizeof b);
    cJSON *ja = RUN_JSON("pose", a, "--json"), *jb = RUN_JSON("pose", b, "--json");
    const cJSON *fa = cJSON_GetObjectItem(ja, "frames"), *fb = cJSON_GetObjectItem(jb, "frames");
    assert_int_equal(cJSON_GetArraySize(fa), 10);
    for (int f = 0; f < 10; f++) {
        const cJSON *na, *nb = cJSON_GetObjectItem(cJSON_GetArrayItem(fb, f), "nodes")->child;
        cJSON_ArrayForEach(na, cJSON_GetObjectItem(cJSON_GetArrayItem(fa, f), "nodes"))
        {
            assert_string_equal(cJSON_GetObjectItem(na, "name")->valuestring,
                                cJSON_GetObjectItem(nb, "name")->valuestring);
            for (int i = 0; i < 3; i++)
                assert_near(at(na, "translation", i), at(nb, "translation", i), 1e-6, "pair translation");
            nb = nb->next;
        }
    }
    cJSON_Delete(ja);
    cJSON_Delete(jb);
}

/* `sinew muscle` on the arm's shipped muscle file and on bad ones. */
static void test_muscle_command(void **state)
{
    (void)state;
    const char *data = getenv("SINEW_DATA");
    assert_non_null(data);
    char arm[1024];
    snprintf(arm, sizeof arm, "%s/arm.muscles.json", data);
    cJSON *root = RUN_JSON("muscle", arm, "--name", "biceps", "--length", "0.22", "--json");
    static const char *const keys[] = {"muscle",      "length",     "rest_length",  "delta", "volume",
                                       "rest_volume", "rest_radii", "coefficients", "radii", "valid_length"};
    for (size_t i = 0; i < sizeof keys / sizeof keys[0]; i++)
        if (!cJSON_GetObjectItemCaseSensitive(root, keys[i]))
            fail_msg("muscle --json lacks \"%s\"", keys[i]);
    double volume = cJSON_GetObjectItem(root, "volume")->valuedouble;
    double rest = cJSON_GetObjectItem(root, "rest_volume")->valuedouble;
    assert_near(volume / rest, 1.0, 1e-9, "volume kept");
    assert_near(cJSON_GetObjectItem(root, "length")->valuedouble, 0.22, 0.0, "length");
    assert_true(cJSON_GetObjectItem(root, "delta")->valuedouble > 0.0); /* shorter: the belly grows */
    assert_int_equal(cJSON_GetArraySize(cJSON_GetObjectItem(root, "radii")), 9);
    cJSON_Delete(root);

    char path[1024];
    tmp_path("mixed.muscles.json", path, sizeof path);
    const char *mixed = "{\"muscles\": [{\"name\": \"m\", \"origin\": {}, \"insertion\": {}, \"rest_length\": 10,"
                        " \"radii\": [1, 1.5, 2, 2, 1.5, 1], \"coefficients\": [-0.5, 0.2, 1, 1, 0.2, -0.5]}]}";
    write_file(path, mixed, strlen(mixed));
    run_result r = RUN("muscle", path, "--length", "2");
    assert_int_equal(r.code, 2);
    assert_non_null(strstr(r.err, "outside the valid range (3.6"));
    run_free(&r);
    tmp_path("bad.muscles.json", path, sizeof path);
    const char *bad = "{\"muscles\": [{\"name\": \"m\",\n \"radii\": [1, -1]}]}";
    write_file(path, bad, strlen(bad));
    r = RUN("muscle", path);
    assert_int_equal(r.code, 2);
    assert_non_null(strstr(r.err, ":1:14: muscles[0].origin: missing"));
    run_free(&r);
    r = RUN("muscle", arm, "--name", "triceps");
    assert_int_equal(r.code, 2);
    assert_non_null(strstr(r.err, "no muscle \"triceps\""));
    run_free(&r);
    r = RUN("muscle", arm, "--length", "-1");
    assert_int_equal(r.code, 1);
    run_free(&r);
}

/* `sinew pose --muscles`: the file beside the model, lengths and volumes per frame. */
static void test_pose_with_muscles(void **state)
{
    (void)state;
    char fixture[1024], model[1024], beside[1024];
    fixture_path("two_bone.dae", fixture, sizeof fixture);
    tmp_path("walker.dae", model, sizeof model);
    tmp_path("walker.muscles.json", beside, sizeof beside);
    size_t size = 0;
    void *bytes = read_file(fixture, &size);
    assert_non_null(bytes);
    write_file(model, bytes, size);
    free(bytes);
    remove(beside);
    run_result r = RUN("pose", model, "--muscles");
    assert_int_equal(r.code, 2);
    assert_non_null(strstr(r.err, "no muscle file beside the model"));
    run_free(&r);
    /* the built-in models carry their biceps: --muscles alone attaches them */
    cJSON *demo = RUN_JSON("pose", "builtin:demo", "--clip", "wave", "--time", "1", "--muscles", "--json");
    cJSON *muscles = cJSON_GetObjectItem(cJSON_GetArrayItem(cJSON_GetObjectItem(demo, "frames"), 0), "muscles");
    assert_int_equal(cJSON_GetArraySize(muscles), 2);
    assert_string_equal(cJSON_GetObjectItem(cJSON_GetArrayItem(muscles, 0), "name")->valuestring, "LeftBiceps");
    cJSON_Delete(demo);
    cJSON *arm = RUN_JSON("pose", "builtin:arm", "--time", "1", "--muscles", "--json");
    muscles = cJSON_GetObjectItem(cJSON_GetArrayItem(cJSON_GetObjectItem(arm, "frames"), 0), "muscles");
    assert_int_equal(cJSON_GetArraySize(muscles), 1);
    cJSON_Delete(arm);
    const char *json = "{\"muscles\": [{\"name\": \"m\", \"origin\": {\"joint\": \"root\", \"offset\": [0.1, 0.3, 0]},"
                       " \"insertion\": {\"joint\": \"tip\", \"offset\": [0.1, 0.4, 0]},"
                       " \"radii\": [0.02, 0.05, 0.02], \"coefficients\": [0, 1, 0]}]}";
    write_file(beside, json, strlen(json));
    cJSON *root = RUN_JSON("pose", model, "--muscles", "--json");
    cJSON *frames = cJSON_GetObjectItem(root, "frames");
    assert_int_equal(cJSON_GetArraySize(frames), 10);
    cJSON *frame;
    cJSON_ArrayForEach(frame, frames)
    {
        cJSON *m = cJSON_GetArrayItem(cJSON_GetObjectItem(frame, "muscles"), 0);
        assert_non_null(m);
        assert_string_equal(cJSON_GetObjectItem(m, "name")->valuestring, "m");
        double v = cJSON_GetObjectItem(m, "volume")->valuedouble,
               v0 = cJSON_GetObjectItem(m, "rest_volume")->valuedouble;
        assert_near(v / v0, 1.0, 1e-9, "volume");
        assert_non_null(cJSON_GetObjectItem(m, "delta"));
        assert_non_null(cJSON_GetObjectItem(m, "length"));
        assert_int_equal(cJSON_GetArraySize(cJSON_GetObjectItem(m, "radii")), 3);
    }
    cJSON_Delete(root);
    r = RUN("pose", model, "--muscles", beside, "--time", "0.5");
    assert_int_equal(r.code, 0);
    assert_non_null(strstr(r.out, "muscle m"));
    run_free(&r);
}

/* `sinew arm`: angle and length agree through the law of cosines; the biceps keeps its volume. */
static void test_arm_command(void **state)
{
    (void)state;
    cJSON *root = RUN_JSON("arm", "--angle", "60", "--json");
    cJSON *m = cJSON_GetObjectItem(root, "muscle");
    double length = cJSON_GetObjectItem(m, "length")->valuedouble;
    double v = cJSON_GetObjectItem(m, "volume")->valuedouble, v0 = cJSON_GetObjectItem(m, "rest_volume")->valuedouble;
    assert_near(v / v0, 1.0, 1e-9, "volume");
    /* data/arm.muscles.json: origin 0.28 from the elbow, insertion 0.05. */
    double exact = sqrt(0.28 * 0.28 + 0.05 * 0.05 - 2 * 0.28 * 0.05 * cos(M_PI / 3));
    assert_near(length, exact, 1e-6, "length at 60 (measured between float world positions)");
    cJSON_Delete(root);
    char text[32];
    snprintf(text, sizeof text, "%.17g", exact);
    root = RUN_JSON("arm", "--length", text, "--json");
    assert_near(cJSON_GetObjectItem(root, "elbow_angle")->valuedouble, 60.0, 1e-9, "angle back");
    cJSON_Delete(root);
    root = RUN_JSON("arm", "--contract", "0.1", "--json");
    m = cJSON_GetObjectItem(root, "muscle");
    assert_near(cJSON_GetObjectItem(m, "length")->valuedouble, 0.27, 1e-6, "contracted by a tenth");
    assert_true(cJSON_GetObjectItem(m, "delta")->valuedouble > 0.0);
    cJSON_Delete(root);
    run_result r = RUN("arm", "--length", "0.5");
    assert_int_equal(r.code, 2);
    assert_non_null(strstr(r.err, "outside"));
    run_free(&r);
    r = RUN("arm", "--angle", "200");
    assert_int_equal(r.code, 1);
    run_free(&r);
    r = RUN("arm", "--angle", "60", "--length", "0.3");
    assert_int_equal(r.code, 1);
    run_free(&r);
    r = RUN("pose", "builtin:arm", "--muscles", "--time", "0,1");
    assert_int_equal(r.code, 0);
    assert_non_null(strstr(r.out, "muscle biceps"));
    run_free(&r);
}

/* `sinew demo`, `sinew convert` and every command on the .sinew file it writes. */
static void test_demo_convert_and_sinew_files(void **state)
{
    (void)state;
    char dir[2048], dae[4096], out[4096], muscles[4096];
    tmp_path("demo", dir, sizeof dir);
    static const char *const names[] = {"humanoid.dae", "humanoid.muscles.json", "arm.dae", "arm.muscles.json"};
    for (int i = 0; i < 4; i++) { /* from an earlier run */
        snprintf(dae, sizeof dae, "%s/%s", dir, names[i]);
        unlink(dae);
    }
    run_result r = RUN("demo", dir);
    assert_int_equal(r.code, 0);
    assert_non_null(strstr(r.out, "humanoid.dae"));
    run_free(&r);
    /* again: the files are there, nothing is replaced without --force */
    r = RUN("demo", dir);
    assert_int_equal(r.code, 4);
    assert_non_null(strstr(r.err, "exists; nothing was written (--force"));
    run_free(&r);
    r = RUN("demo", dir, "--force");
    assert_int_equal(r.code, 0);
    run_free(&r);
    snprintf(dae, sizeof dae, "%s/humanoid.dae", dir);
    snprintf(muscles, sizeof muscles, "%s/humanoid.muscles.json", dir);
    tmp_path("humanoid.sinew", out, sizeof out);
    r = RUN("convert", dae, out);
    assert_int_equal(r.code, 0);
    assert_non_null(strstr(r.out, "2 clips, 2 muscles from"));
    run_free(&r);
    r = RUN("info", out, "--json");
    assert_int_equal(r.code, 0);
    cJSON *info = cJSON_Parse(r.out);
    assert_non_null(info);
    assert_string_equal(cJSON_GetObjectItem(info, "format")->valuestring, "sinew");
    assert_string_equal(cJSON_GetObjectItem(info, "converted_from")->valuestring, dae);
    cJSON *counts = cJSON_GetObjectItem(info, "counts");
    assert_int_equal(cJSON_GetObjectItem(counts, "joints")->valueint, 24);
    assert_int_equal(cJSON_GetObjectItem(counts, "muscles")->valueint, 2);
    cJSON_Delete(info);
    run_free(&r);
    /* the stored muscles are used with no file beside the .sinew; poses equal the COLLADA's */
    run_result a = RUN("pose", out, "--clip", "wave", "--time", "0.5", "--muscles", "--json");
    run_result b = RUN("pose", dae, "--clip", "wave", "--time", "0.5", "--muscles", muscles, "--json");
    assert_int_equal(a.code, 0);
    assert_int_equal(b.code, 0);
    const char *fa = strstr(a.out, "\"frames\""), *fb = strstr(b.out, "\"frames\"");
    assert_non_null(fa);
    assert_non_null(fb);
    assert_string_equal(fa, fb);
    assert_non_null(strstr(a.out, "RightBiceps"));
    run_free(&a);
    run_free(&b);
    /* refusals */
    r = RUN("convert", dae, "out.obj");
    assert_int_equal(r.code, 1);
    assert_non_null(strstr(r.err, "must be a .sinew file"));
    run_free(&r);
    char broken[4096];
    tmp_path("broken.sinew", broken, sizeof broken);
    size_t size = 0;
    unsigned char *bytes = read_file(out, &size);
    write_file(broken, bytes, size / 2);
    free(bytes);
    r = RUN("info", broken);
    assert_int_equal(r.code, 2);
    assert_non_null(strstr(r.err, broken));
    assert_non_null(strstr(r.err, "truncated"));
    run_free(&r);
    r = RUN("convert", dae, out, "--no-muscles");
    assert_int_equal(r.code, 0);
    assert_non_null(strstr(r.out, "0 muscles"));
    run_free(&r);
}

static void test_bench_eval_json(void **state)
{
    (void)state;
    run_result r = RUN("bench", "eval", "--json", "--quick");
    assert_int_equal(r.code, 0);
    cJSON *o = cJSON_Parse(r.out);
    assert_non_null(o);
    static const char *const keys[] = {"sample_world_us_64",
                                       "sample_world_us_128",
                                       "seek_us_64",
                                       "skin_mverts_1t",
                                       "skin_mverts_1t_posonly",
                                       "skin_mverts_dqs_1t",
                                       "threads",
                                       "skin_mverts_nt",
                                       "crowd1000_speedup_nt",
                                       "load_speedup_vs_assimp",
                                       "blend2_us_64",
                                       "blend4_us_64",
                                       "ik_two_bone_us_64",
                                       "ik_aim_us_64",
                                       "blend2_soa_us_64",
                                       "blend4_soa_us_64",
                                       "blend2_soa_scalar_us_64",
                                       "character_crossfade_us_64",
                                       "character_ik_us_64"};
    for (size_t i = 0; i < sizeof keys / sizeof keys[0]; i++) {
        cJSON *v = cJSON_GetObjectItem(o, keys[i]);
        if (!cJSON_IsNumber(v) || !(v->valuedouble > 0.0))
            fail_msg("bench eval --json: %s missing or not positive", keys[i]);
    }
    assert_true(cJSON_IsString(cJSON_GetObjectItem(o, "machine")));
    /* scaling: one entry a thread count, 1 .. threads, the first at speed-up 1 */
    cJSON *scaling = cJSON_GetObjectItem(o, "scaling");
    int threads = cJSON_GetObjectItem(o, "threads")->valueint;
    assert_int_equal(cJSON_GetArraySize(scaling), threads);
    assert_float_equal(cJSON_GetObjectItem(cJSON_GetArrayItem(scaling, 0), "crowd_speedup")->valuedouble, 1.0, 1e-9);
    cJSON_Delete(o);
    run_free(&r);
    /* --threads is checked */
    r = RUN("bench", "eval", "--threads", "0");
    assert_int_equal(r.code, 1);
    assert_non_null(strstr(r.err, "--threads"));
    run_free(&r);
    r = RUN("bench", "eval", "--json", "--quick", "--threads", "3");
    assert_int_equal(r.code, 0);
    o = cJSON_Parse(r.out);
    assert_int_equal(cJSON_GetObjectItem(o, "threads")->valueint, 3);
    assert_int_equal(cJSON_GetArraySize(cJSON_GetObjectItem(o, "scaling")), 3);
    cJSON_Delete(o);
    run_free(&r);
}

/* Component k of `what` of a node in a pose's first frame (node_named and at, above). */
static double node_component(const cJSON *root, const char *name, const char *what, int k)
{
    return at(node_named(cJSON_GetArrayItem(cJSON_GetObjectItem(root, "frames"), 0), name), what, k);
}

/* --blend walk:1,wave:0 is the walk, and with the wave masked to the chest the legs still walk;
 * --ik puts the hand on its target; --crossfade at its
 * start is the first clip and after its end the second; --root-motion keeps the hips in place;
 * bad specs name the option. */
static void test_pose_blend_ik_root_motion(void **state)
{
    (void)state;
    cJSON *walk = RUN_JSON("pose", "builtin:demo", "--clip", "walk", "--time", "0.3", "--json");
    cJSON *blend = RUN_JSON("pose", "builtin:demo", "--blend", "walk:1,wave:0", "--time", "0.3", "--json");
    double worst = 0.0;
    static const char *const nodes[] = {"Hips", "LeftHand", "RightFoot", "Head"};
    for (int i = 0; i < 4; i++)
        for (int k = 0; k < 3; k++)
            worst = fmax(worst, fabs(node_component(walk, nodes[i], "translation", k) -
                                     node_component(blend, nodes[i], "translation", k)));
    cJSON_Delete(blend);
    /* a mask: the wave moves the chest and what is below it; legs and hips walk as before */
    cJSON *masked = RUN_JSON("pose", "builtin:demo", "--blend", "walk:1,wave:1@Chest", "--time", "0.3", "--json");
    double legs = 0.0, arm = 0.0;
    for (int k = 0; k < 3; k++) {
        legs = fmax(legs, fabs(node_component(walk, "RightFoot", "translation", k) -
                               node_component(masked, "RightFoot", "translation", k)));
        arm = fmax(arm, fabs(node_component(walk, "LeftHand", "translation", k) -
                             node_component(masked, "LeftHand", "translation", k)));
    }
    print_message("pose: --blend walk:1,wave:1@Chest: the foot off the walk's by %.1e, the hand by %.3f\n", legs, arm);
    assert_true(legs < 1e-5 && arm > 0.01);
    cJSON_Delete(masked);
    cJSON *wave = RUN_JSON("pose", "builtin:demo", "--clip", "wave", "--time", "1.3", "--json");
    cJSON *start = RUN_JSON("pose", "builtin:demo", "--crossfade", "walk,wave,1", "--time", "0.3", "--json");
    cJSON *after = RUN_JSON("pose", "builtin:demo", "--crossfade", "walk,wave,1", "--time", "1.3", "--json");
    double fade_end = 0.0;
    for (int k = 0; k < 3; k++)
        fade_end = fmax(fade_end, fabs(node_component(wave, "LeftHand", "translation", k) -
                                       node_component(after, "LeftHand", "translation", k)));
    cJSON *ik =
        RUN_JSON("pose", "builtin:demo", "--clip", "walk", "--time", "0.3", "--ik", "LeftHand:0.25,1.7,0.35", "--json");
    double target[3] = {0.25, 1.7, 0.35}, miss = 0.0;
    for (int k = 0; k < 3; k++)
        miss = fmax(miss, fabs(node_component(ik, "LeftHand", "translation", k) - target[k]));
    print_message("pose: --blend walk:1,wave:0 vs --clip walk %.1e; --crossfade walk,wave,1 at 1.3 s vs wave %.1e; "
                  "--ik LeftHand missed by %.1e\n",
                  worst, fade_end, miss);
    assert_true(worst < 1e-5 && fade_end < 1e-5 && miss < 1e-4);
    /* the start of the fade is mostly the walk: its hand is not the wave's */
    assert_true(fabs(node_component(start, "LeftHand", "translation", 1) -
                     node_component(wave, "LeftHand", "translation", 1)) > 0.01);
    cJSON_Delete(walk);
    cJSON_Delete(wave);
    cJSON_Delete(start);
    cJSON_Delete(after);
    cJSON_Delete(ik);
    char bvh[1024];
    if (testdata_path("assimp/BVH/01_01.bvh", bvh, sizeof bvh)) {
        cJSON *moved = RUN_JSON("pose", bvh, "--time", "0,3", "--root-motion", "--json");
        const cJSON *frames = cJSON_GetObjectItem(moved, "frames");
        const cJSON *motion = cJSON_GetObjectItem(cJSON_GetArrayItem(frames, 1), "root_motion");
        assert_non_null(motion);
        double z = cJSON_GetArrayItem(cJSON_GetObjectItem(motion, "translation"), 2)->valuedouble;
        print_message("01_01.bvh --root-motion: %.1f units taken out by 3 s\n", z);
        assert_true(fabs(z) > 5.0);
        cJSON_Delete(moved);
    }
    /* --anim: another file's clips, first in the list */
    if (testdata_path("assimp/BVH/01_01.bvh", bvh, sizeof bvh)) {
        cJSON *anim = RUN_JSON("pose", "builtin:demo", "--anim", bvh, "--time", "1", "--json");
        const cJSON *clip = cJSON_GetObjectItem(anim, "clip");
        assert_string_equal(cJSON_GetObjectItem(clip, "name")->valuestring, "Motion");
        assert_true(cJSON_GetObjectItem(clip, "duration")->valuedouble > 5.0);
        cJSON_Delete(anim);
    }
    static const struct {
        int code;
        const char *says, *args[8];
    } bad[] = {{2, "/nonexistent/walk.bvh", {"pose", "builtin:demo", "--anim", "/nonexistent/walk.bvh"}},
               {1, "--ik \"Nose\"", {"pose", "builtin:demo", "--ik", "Nose:0,1,0"}},
               {1, "--blend", {"render", "builtin:demo", "--blend", "walk:x", "-o", "/tmp/never.png"}},
               {1, "no node \"Nose\" to mask", {"pose", "builtin:demo", "--additive", "wave:1@Nose"}}};
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        run_result r = run_sinew(NULL, bad[i].args);
        if (r.code != bad[i].code || !strstr(r.err, bad[i].says))
            fail_msg("sinew %s %s %s: exit %d, \"%s\" (expected %d and \"%s\")", bad[i].args[0], bad[i].args[1],
                     bad[i].args[2], r.code, r.err, bad[i].code, bad[i].says);
        run_free(&r);
    }
}

/* No silent failures: what a command prints must reach standard output (a full disk: exit 4 with a
 * message, not 0), and -o / --mesh may not overwrite --anim or --name-map inputs. */
static void test_output_failures_are_said(void **state)
{
    (void)state;
    char dae[1024], cmd[4096];
    fixture_path("two_bone.dae", dae, sizeof dae);
    const char *exe = getenv("SINEW_EXE");
    assert_non_null(exe);
    snprintf(cmd, sizeof cmd, "'%s' info '%s' > /dev/full 2>/dev/null", exe, dae);
    int status = system(cmd);
    assert_true(WIFEXITED(status));
    assert_int_equal(WEXITSTATUS(status), 4);
    snprintf(cmd, sizeof cmd, "'%s' --help > /dev/full 2>/dev/null", exe);
    status = system(cmd);
    assert_int_equal(WEXITSTATUS(status), 4);
    /* the output named as an input */
    char anim[1024];
    tmp_path("anim-as-output.dae", anim, sizeof anim);
    size_t n = 0;
    unsigned char *bytes = read_file(dae, &n);
    write_file(anim, bytes, n);
    free(bytes);
    run_result r = RUN("pose", dae, "--anim", anim, "--mesh", anim);
    assert_int_not_equal(r.code, 0);
    assert_non_null(strstr(r.err, "anim-as-output.dae"));
    run_free(&r);
    r = RUN("render", dae, "--anim", anim, "-o", anim);
    assert_int_not_equal(r.code, 0);
    run_free(&r);
    bytes = read_file(anim, &n); /* untouched */
    assert_non_null(bytes);
    assert_non_null(strstr((char *)bytes, "COLLADA"));
    free(bytes);
}

/* A render stopped by SIGTERM or SIGINT (Ctrl+C) leaves no temporary file beside its output (their
 * names say "sinew-tmp" for what SIGKILL would leave). */
static void test_stopped_render_leaves_nothing(void **state)
{
    (void)state;
    if (system("command -v ffmpeg >/dev/null 2>&1 && command -v timeout >/dev/null 2>&1") != 0)
        skip();
    char dae[1024], dir[1024], cmd[8192];
    fixture_path("two_bone.dae", dae, sizeof dae);
    tmp_path("stopped-render", dir, sizeof dir);
    const char *exe = getenv("SINEW_EXE");
    assert_non_null(exe);
    static const char *const SIGNALS[] = {"TERM", "INT"};
    for (int k = 0; k < 2; k++) {
        snprintf(cmd, sizeof cmd,
                 "rm -rf '%s' && mkdir -p '%s' && timeout -s %s 3 '%s' render '%s' --from 0 --to 200 --fps 30 "
                 "--size 320x240 -o '%s/out.mp4' 2>/dev/null; ls -A '%s' | grep -c . || true",
                 dir, dir, SIGNALS[k], exe, dae, dir, dir);
        FILE *p = popen(cmd, "r");
        assert_non_null(p);
        int files = -1;
        assert_int_equal(fscanf(p, "%d", &files), 1);
        pclose(p);
        printf("render stopped by SIG%s: %d files left in its folder\n", SIGNALS[k], files);
        assert_int_equal(files, 0);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_usage_and_help),
        cmocka_unit_test(test_bad_input_exits_2),
        cmocka_unit_test(test_pose_json),
        cmocka_unit_test(test_pose_mesh_obj),
        cmocka_unit_test(test_info_json_and_text),
        cmocka_unit_test(test_json_library_loaded_on_use),
        cmocka_unit_test(test_info_fbx_inherit),
        cmocka_unit_test(test_pose_without_animation),
        cmocka_unit_test(test_pose_pairs_agree),
        cmocka_unit_test(test_muscle_command),
        cmocka_unit_test(test_pose_with_muscles),
        cmocka_unit_test(test_arm_command),
        cmocka_unit_test(test_demo_convert_and_sinew_files),
        cmocka_unit_test(test_bench_eval_json),
        cmocka_unit_test(test_pose_blend_ik_root_motion),
        cmocka_unit_test(test_time_outside_the_clip),
        cmocka_unit_test(test_render_progress_on_a_terminal),
        cmocka_unit_test(test_camera_position_focal_point_fov),
        cmocka_unit_test(test_output_failures_are_said),
        cmocka_unit_test(test_stopped_render_leaves_nothing),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
