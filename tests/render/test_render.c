/* `sinew render` as a user runs it, tested as pictures: golden images, GPU against CPU
 * skinning, animated against static models, skeleton-only files, video and frame
 * sequences, bad input.
 *
 * Golden images: tests/golden/NAME.png, 320x240, rendered headless by Mesa's llvmpipe.
 * A pixel differs when one channel differs by more than PIXEL_TOLERANCE; an image
 * matches when at most IMAGE_TOLERANCE of its pixels differ (anti-aliasing and
 * rasteriser rounding move a few edge pixels; a wrong pose, colour or camera moves
 * thousands, as test_tolerance_catches_a_wrong_pose shows). On a mismatch the actual
 * image and a diff (differing pixels red) are written beside the test's scratch files.
 * Refresh after an intended change: `make golden` (SINEW_UPDATE_GOLDEN=1), then look at
 * the new images before committing them. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <stb_image.h>
#include <stb_image_write.h>

#include <cjson/cJSON.h>

#include "helpers.h"

#define SIZE "320x240"

typedef struct image {
    int width, height;
    unsigned char *rgb;
} image;

static image load_image(const char *path)
{
    image im = {0};
    int channels = 0;
    im.rgb = stbi_load(path, &im.width, &im.height, &channels, 3);
    return im;
}

static long image_difference(const image *a, const image *b, unsigned char *diff)
{
    return differing_pixels(a->rgb, b->rgb, (long)a->width * a->height, diff);
}

static bool same_picture(const image *a, const image *b, long *differing)
{
    *differing = -1;
    if (!a->rgb || !b->rgb || a->width != b->width || a->height != b->height)
        return false;
    *differing = image_difference(a, b, NULL);
    return *differing <= (long)(IMAGE_TOLERANCE * a->width * a->height);
}

/* Renders with sinew into the scratch folder; fails the test on a non-zero exit. */
static image render(const char *out_name, const char *const *args)
{
    char out[1024];
    tmp_path(out_name, out, sizeof out);
    const char *argv[48] = {"render"};
    int n = 1;
    for (; args[n - 1] && n < 44; n++)
        argv[n] = args[n - 1];
    argv[n++] = "-o";
    argv[n++] = out;
    argv[n] = NULL;
    run_result r = run_sinew(NULL, argv);
    if (r.code != 0)
        fail_msg("sinew render %s: exit %d: %s", args[0], r.code, r.err);
    run_free(&r);
    image im = load_image(out);
    assert_non_null(im.rgb);
    return im;
}

#define RENDER(name, ...) render((name), (const char *const[]){__VA_ARGS__, NULL})

static void compare_with_golden(const char *name, const image *actual)
{
    const char *dir = getenv("SINEW_GOLDEN");
    assert_non_null(dir);
    char golden_path[1024];
    snprintf(golden_path, sizeof golden_path, "%s/%s.png", dir, name);
    if (getenv("SINEW_UPDATE_GOLDEN")) {
        assert_true(stbi_write_png(golden_path, actual->width, actual->height, 3, actual->rgb, actual->width * 3));
        printf("golden %s: refreshed %s\n", name, golden_path);
        return;
    }
    image golden = load_image(golden_path);
    if (!golden.rgb)
        fail_msg("golden %s: cannot read %s (refresh with `make golden`)", name, golden_path);
    long differing = 0;
    bool ok = same_picture(actual, &golden, &differing);
    printf("golden %-24s %ld of %d pixels differ (allowed %.1f%%)\n", name, differing, actual->width * actual->height,
           IMAGE_TOLERANCE * 100.0);
    if (!ok) {
        char actual_path[1024], diff_path[1024], file[256];
        snprintf(file, sizeof file, "%s-actual.png", name);
        tmp_path(file, actual_path, sizeof actual_path);
        snprintf(file, sizeof file, "%s-diff.png", name);
        tmp_path(file, diff_path, sizeof diff_path);
        stbi_write_png(actual_path, actual->width, actual->height, 3, actual->rgb, actual->width * 3);
        if (differing >= 0) {
            unsigned char *diff = malloc((size_t)actual->width * actual->height * 3);
            image_difference(actual, &golden, diff);
            stbi_write_png(diff_path, actual->width, actual->height, 3, diff, actual->width * 3);
            free(diff);
        }
        stbi_image_free(golden.rgb);
        fail_msg("golden %s: %ld pixels differ from %s; wrote %s and %s", name, differing, golden_path, actual_path,
                 diff_path);
    }
    stbi_image_free(golden.rgb);
}

static void free_image(image *im)
{
    stbi_image_free(im->rgb);
    im->rgb = NULL;
}

/* ---- golden images ------------------------------------------------------------------------ */

static void test_golden_fixture(void **state)
{
    (void)state;
    char path[1024];
    fixture_path("two_bone_cubic.gltf", path, sizeof path);
    image im = RENDER("g-fixture.png", path, "--time", "0.75", "--size", SIZE, "--wireframe", "--shading", "flat",
                      "--normals", "--axes", "--skeleton", "--camera", "orbit:40,20");
    compare_with_golden("two_bone_cubic-flat-wire-normals", &im);
    free_image(&im);
}

/* glTF's metallic-roughness materials on the fixture's four spheres: gold, red plastic, a
 * normal-mapped metal with occlusion and roughness from one image, a glowing half. */
static void test_golden_pbr(void **state)
{
    (void)state;
    char path[1024];
    fixture_path("pbr_spheres.glb", path, sizeof path);
    image im = RENDER("g-pbr.png", path, "--size", SIZE, "--shading", "pbr", "--camera", "orbit:0,8,10", "--no-grid");
    compare_with_golden("pbr_spheres-pbr", &im);
    image phong = RENDER("g-pbr-phong.png", path, "--size", SIZE, "--camera", "orbit:0,8,10", "--no-grid");
    long differing = 0;
    assert_false(same_picture(&im, &phong, &differing));
    printf("pbr vs phong: %ld pixels differ\n", differing);
    free_image(&im);
    free_image(&phong);
}

/* Muscles from the file beside the fixture, Gouraud-shaded over a bending two-bone strip. */
static void test_golden_muscles(void **state)
{
    (void)state;
    char path[1024];
    fixture_path("two_bone.dae", path, sizeof path);
    image with = RENDER("g-muscle.png", path, "--time", "1", "--size", SIZE, "--muscles", "--skeleton", "--camera",
                        "orbit:60,15");
    compare_with_golden("two_bone-muscle", &with);
    image without = RENDER("g-no-muscle.png", path, "--time", "1", "--size", SIZE, "--muscles", "--no-muscles",
                           "--skeleton", "--camera", "orbit:60,15");
    long differing = 0;
    assert_false(same_picture(&with, &without, &differing));
    printf("muscle drawn: %ld pixels differ from the same view without it\n", differing);
    free_image(&with);
    free_image(&without);
}

/* Pixels whose colour moved by 8 levels or more in some channel. */
static long changed_pixels(const image *a, const image *b)
{
    long changed = 0;
    for (long p = 0; p < (long)a->width * a->height; p++)
        for (int c = 0; c < 3; c++)
            if (abs((int)a->rgb[p * 3 + c] - (int)b->rgb[p * 3 + c]) >= 8) {
                changed++;
                break;
            }
    return changed;
}

/* The look switches on the robot (PBR in the built-in studio, shadows on the ground, ambient
 * occlusion, outlines, the environment behind), and an environment file of a sky with a sun
 * (tests/fixtures/sky.hdr, made by scripts/sky-hdr.py --size 64). Each switch changes the
 * picture (FXAA too, over multisampling: it smooths what 4 samples leave); exposure brightens it;
 * ACES differs from Khronos PBR Neutral. */
static void test_golden_look(void **state)
{
    (void)state;
    char path[1024], hdr[1024];
    if (!testdata_path("raylib/robot.glb", path, sizeof path))
        skip();
    fixture_path("sky.hdr", hdr, sizeof hdr);
    const char *base[] = {path, "--clip", "Robot_Walking", "--time", "0.3", "--size", SIZE, "--shading", "pbr"};
#define LOOK(out, ...)                                                                                                 \
    render(out, (const char *const[]){base[0], base[1], base[2], base[3], base[4], base[5], base[6], base[7], base[8], \
                                      __VA_ARGS__, NULL})
    image all = LOOK("g-look.png", "--shadows", "--ssao", "--outline", "--hdri-background");
    compare_with_golden("robot-walk-look", &all);
    image sky = LOOK("g-sky.png", "--hdri", hdr, "--hdri-background", "--shadows");
    compare_with_golden("robot-walk-sky", &sky);
    image plain = LOOK("g-plain.png", "--no-grid");
    static const char *const switches[] = {"--shadows", "--ssao", "--outline", "--hdri-background", "--fxaa"};
    for (int i = 0; i < 5; i++) { /* pixels changed by 8 levels or more: occlusion is subtle */
        image one = LOOK("g-switch.png", "--no-grid", switches[i]);
        long changed = changed_pixels(&plain, &one);
        printf("%s changes %ld pixels\n", switches[i], changed);
        assert_true(changed > (long)plain.width * plain.height / 100);
        free_image(&one);
    }
    image bright = LOOK("g-bright.png", "--no-grid", "--exposure", "1");
    image aces = LOOK("g-aces.png", "--no-grid", "--tone-mapping", "aces");
    double sum_plain = 0.0, sum_bright = 0.0;
    for (long i = 0; i < (long)plain.width * plain.height * 3; i++)
        if (memcmp(plain.rgb + i / 3 * 3, plain.rgb, 3) != 0) /* the model, not the background */
            sum_plain += plain.rgb[i], sum_bright += bright.rgb[i];
    long differing = changed_pixels(&plain, &aces);
    assert_true(differing > (long)plain.width * plain.height / 100);
    printf("exposure +1: the model's levels %.3g -> %.3g; ACES vs neutral: %ld pixels differ\n", sum_plain, sum_bright,
           differing);
    assert_true(sum_bright > sum_plain * 1.15);
#undef LOOK
    free_image(&all);
    free_image(&sky);
    free_image(&plain);
    free_image(&bright);
    free_image(&aces);
}

typedef struct golden_case {
    const char *name;
    const char *model;
    const char *args[16];
} golden_case;

static const golden_case GOLDEN[] = {
    {"robot-walk-phong", "raylib/robot.glb", {"--clip", "Robot_Walking", "--time", "0.3"}},
    {"robot-walk-pbr", "raylib/robot.glb", {"--clip", "Robot_Walking", "--time", "0.3", "--shading", "pbr"}},
    {"robot-wave-heat-gouraud",
     "raylib/robot.glb",
     {"--clip", "Robot_Wave", "--time", "0.6", "--heatmap", "Head", "--skeleton", "--select", "UpperArm.R", "--shading",
      "gouraud", "--camera", "orbit:-20,10"}},
    {"wuson-clay-flat", "assimp/X/Testwuson.X", {"--time", "1", "--materials", "off", "--shading", "flat"}},
    {"bvh-skeleton-names",
     "assimp/BVH/01_01.bvh",
     {"--time", "1", "--select", "LeftForeArm", "--camera", "orbit:60,10"}},
    {"jointsinln-textured-unlit", "collada-cts/JointsInLN/JointsInLN.dae", {"--no-lighting", "--no-grid"}},
    {"arnaud-joint-axes", "ozz/pab/arnaud.fbx", {"--joint-axes", "--camera", "orbit:0,0", "--background", "ffffff"}},
};

static void test_golden_models(void **state)
{
    (void)state;
    for (size_t i = 0; i < sizeof GOLDEN / sizeof GOLDEN[0]; i++) {
        const golden_case *g = &GOLDEN[i];
        char path[1024];
        if (!testdata_path(g->model, path, sizeof path))
            skip();
        const char *argv[24] = {path, "--size", SIZE};
        int n = 3;
        for (int k = 0; g->args[k]; k++)
            argv[n++] = g->args[k];
        argv[n] = NULL;
        image im = render("g-model.png", argv);
        compare_with_golden(g->name, &im);
        free_image(&im);
    }
}

/* A pose a tenth of a second off must fail the comparison: the tolerance is not loose. */
static void test_tolerance_catches_a_wrong_pose(void **state)
{
    (void)state;
    char path[1024];
    if (!testdata_path("raylib/robot.glb", path, sizeof path))
        skip();
    image a = RENDER("tol-a.png", path, "--clip", "Robot_Walking", "--time", "0.3", "--size", SIZE);
    image b = RENDER("tol-b.png", path, "--clip", "Robot_Walking", "--time", "0.4", "--size", SIZE);
    long differing = 0;
    assert_false(same_picture(&a, &b, &differing));
    printf("robot walk 0.3 s vs 0.4 s: %ld pixels differ\n", differing);
    free_image(&a);
    free_image(&b);
}

/* ---- behaviour ---------------------------------------------------------------------------- */

static void test_gpu_and_cpu_skinning_agree(void **state)
{
    (void)state;
    char path[1024];
    if (!testdata_path("raylib/robot.glb", path, sizeof path))
        skip();
    const char *common[] = {"--clip", "Robot_Wave", "--time", "0.6",       "--size",
                            SIZE,     "--heatmap",  "Hips",   "--normals", "--skeleton"};
    image gpu = RENDER("skin-gpu.png", path, common[0], common[1], common[2], common[3], common[4], common[5],
                       common[6], common[7], common[8], common[9], "--skinning", "gpu");
    image cpu = RENDER("skin-cpu.png", path, common[0], common[1], common[2], common[3], common[4], common[5],
                       common[6], common[7], common[8], common[9], "--skinning", "cpu");
    long differing = 0;
    bool same = same_picture(&gpu, &cpu, &differing);
    printf("robot wave, GPU vs CPU skinning: %ld pixels differ\n", differing);
    assert_true(same);
    free_image(&gpu);
    free_image(&cpu);
}

/* Bright (tube) pixels in the narrowest row of the middle fifth of the picture. */
static int narrowest_middle_row(const image *im)
{
    int narrowest = im->width;
    for (int y = im->height * 2 / 5; y < im->height * 3 / 5; y++) {
        int bright = 0;
        for (int x = 0; x < im->width; x++) {
            const unsigned char *p = &im->rgb[((size_t)y * im->width + x) * 3];
            bright += p[0] + p[1] + p[2] > 3 * 120;
        }
        narrowest = bright < narrowest ? bright : narrowest;
    }
    return narrowest;
}

/* The candy wrapper: a tube twisted 170 degrees pinches under linear blend skinning and
 * keeps its width under dual quaternions; GPU and CPU dual-quaternion skinning draw the same
 * picture, on the fixture and on the robot. */
static void test_dual_quaternion_skinning(void **state)
{
    (void)state;
    char tube[1024], robot[1024];
    fixture_path("twist_tube.glb", tube, sizeof tube);
    image lbs = RENDER("twist-lbs.png", tube, "--time", "2", "--size", SIZE, "--no-grid");
    image dqs = RENDER("twist-dqs.png", tube, "--time", "2", "--size", SIZE, "--no-grid", "--skinning-method", "dqs");
    image dqs_cpu = RENDER("twist-dqs-cpu.png", tube, "--time", "2", "--size", SIZE, "--no-grid", "--skinning-method",
                           "dqs", "--skinning", "cpu");
    int narrow_lbs = narrowest_middle_row(&lbs), narrow_dqs = narrowest_middle_row(&dqs);
    long differing = 0;
    bool same = same_picture(&dqs, &dqs_cpu, &differing);
    printf("twisted tube: narrowest middle row %d pixels (linear blend), %d (dual quaternion); DQS GPU vs CPU %ld "
           "pixels differ\n",
           narrow_lbs, narrow_dqs, differing);
    assert_true(narrow_dqs > 20);
    assert_true(narrow_lbs * 4 < narrow_dqs);
    assert_true(same);
    free_image(&lbs);
    free_image(&dqs);
    free_image(&dqs_cpu);
    if (!testdata_path("raylib/robot.glb", robot, sizeof robot))
        return;
    image gpu = RENDER("robot-dqs-gpu.png", robot, "--clip", "Robot_Wave", "--time", "0.6", "--size", SIZE,
                       "--skinning-method", "dqs");
    image cpu = RENDER("robot-dqs-cpu.png", robot, "--clip", "Robot_Wave", "--time", "0.6", "--size", SIZE,
                       "--skinning-method", "dqs", "--skinning", "cpu");
    same = same_picture(&gpu, &cpu, &differing);
    printf("robot wave, dual quaternions, GPU vs CPU: %ld pixels differ\n", differing);
    assert_true(same);
    free_image(&gpu);
    free_image(&cpu);
}

/* Pixels brighter than near-black: what was drawn over --background 000000 without a grid. */
static long lit_pixels(const image *im)
{
    long lit = 0;
    for (long i = 0; i < (long)im->width * im->height; i++)
        lit += im->rgb[i * 3] + im->rgb[i * 3 + 1] + im->rgb[i * 3 + 2] > 60;
    return lit;
}

/* The demo's crowd of 100 at `size` with levels of detail against it drawn whole (coverage
 * within 3/4 .. 21/20) and against CPU skinning (the same picture). */
static void demo_crowd_levels(const char *size, const char *name)
{
    char names[3][64];
    snprintf(names[0], sizeof names[0], "%s.png", name);
    snprintf(names[1], sizeof names[1], "%s-whole.png", name);
    snprintf(names[2], sizeof names[2], "%s-cpu.png", name);
    image lod = RENDER(names[0], "builtin:demo", "--crowd", "100", "--time", "0.3", "--size", size, "--no-grid",
                       "--background", "000000");
    image whole = RENDER(names[1], "builtin:demo", "--crowd", "100", "--time", "0.3", "--size", size, "--no-grid",
                         "--background", "000000", "--no-lod");
    image cpu = RENDER(names[2], "builtin:demo", "--crowd", "100", "--time", "0.3", "--size", size, "--no-grid",
                       "--background", "000000", "--skinning", "cpu");
    long differing = 0, cpu_differing = 0;
    same_picture(&lod, &whole, &differing);
    bool cpu_same = same_picture(&lod, &cpu, &cpu_differing);
    long covered = lit_pixels(&lod), whole_covered = lit_pixels(&whole);
    printf("demo crowd of 100 at %s: with levels of detail vs whole %ld pixels differ (%ld vs %ld covered); GPU vs "
           "CPU skinning with levels %ld\n",
           size, differing, covered, whole_covered, cpu_differing);
    assert_true(cpu_same);
    assert_true(covered > whole_covered * 3 / 4 && covered <= whole_covered * 21 / 20);
    free_image(&lod);
    free_image(&whole);
    free_image(&cpu);
}

/* A crowd: GPU skinning (instanced) and CPU skinning draw the same picture, linear blend
 * and dual quaternions alike; the crowd is not one character (more of the image is covered
 * than by the single model framed the same way); bad counts are refused. */
static void test_crowd(void **state)
{
    (void)state;
    char robot[1024];
    if (!testdata_path("raylib/robot.glb", robot, sizeof robot))
        skip();
    image gpu = RENDER("crowd-gpu.png", robot, "--crowd", "12", "--time", "0.5", "--size", SIZE, "--no-grid",
                       "--background", "000000");
    image cpu = RENDER("crowd-cpu.png", robot, "--crowd", "12", "--time", "0.5", "--size", SIZE, "--no-grid",
                       "--background", "000000", "--skinning", "cpu", "--threads", "2");
    image dqs = RENDER("crowd-dqs.png", robot, "--crowd", "12", "--time", "0.5", "--size", SIZE, "--no-grid",
                       "--background", "000000", "--skinning-method", "dqs");
    long differing = 0, differing_dqs = 0;
    bool same = same_picture(&gpu, &cpu, &differing);
    bool same_dqs = same_picture(&gpu, &dqs, &differing_dqs);
    long covered = lit_pixels(&gpu);
    printf("robot crowd of 12: GPU vs CPU skinning %ld pixels differ, LBS vs DQS %ld; %ld pixels covered\n", differing,
           differing_dqs, covered);
    assert_true(same);
    assert_true(same_dqs);
    assert_true(covered > 2000);
    free_image(&gpu);
    free_image(&cpu);
    free_image(&dqs);
    /* levels of detail: the demo humanoid's crowd, small on screen (figures some 15 pixels
     * high: the coarsest level, limbs a little thinner), drawn with its simplified meshes
     * covers nearly what the crowd drawn whole covers, by GPU and CPU skinning alike; and at
     * 320x180 (figures some 10 pixels high) with the far level, where its error is under a pixel */
    demo_crowd_levels("640x360", "crowd-lod");
    demo_crowd_levels("320x180", "crowd-far");
    /* a file without meshes: a crowd of skeletons */
    char bvh[1024];
    if (testdata_path("assimp/BVH/01_01.bvh", bvh, sizeof bvh)) {
        image bones = RENDER("crowd-bvh.png", bvh, "--crowd", "9", "--time", "3", "--size", SIZE, "--no-grid",
                             "--background", "000000");
        long drawn = lit_pixels(&bones);
        printf("BVH crowd of 9 skeletons: %ld pixels drawn\n", drawn);
        assert_true(drawn > 300);
        free_image(&bones);
    }
    char out[1024];
    tmp_path("crowd-bad.png", out, sizeof out);
    run_result r = RUN("render", robot, "--crowd", "0", "-o", out);
    assert_int_equal(r.code, 1);
    assert_non_null(strstr(r.err, "--crowd"));
    run_free(&r);
}

/* Morph targets drawn by the GPU (offsets in a buffer texture, weights as uniforms) give the
 * CPU's picture: the glTF fixture, the COLLADA fixture (a skin over a morph), the glTF and FBX
 * samples (AnimatedMorphCube; Maya's blended dual-quaternion skin); builtin:morph (64 joints,
 * 50 targets, 5 animated) alone and as a crowd, whose levels of detail morph too (the crowd's
 * bounds once cleared the frame's weights and every character showed its base shape). */
static void test_morph_gpu_equals_cpu(void **state)
{
    (void)state;
    char quad[1024], dae[1024], cube[1024], dq[1024];
    const char *files[4][3] = {
        {fixture_path("morph_quad.gltf", quad, sizeof quad), "0.5", "m-quad"},
        {fixture_path("morph_skin.dae", dae, sizeof dae), "0.75", "m-dae"},
        {testdata_path("gltf-samples/AnimatedMorphCube.glb", cube, sizeof cube), "1.2", "m-cube"},
        {testdata_path("ufbx/maya_dq_weights_7500_binary.fbx", dq, sizeof dq), "0.5", "m-dq"}};
    for (int f = 0; f < 4; f++) {
        if (!files[f][0])
            continue;
        char gpu_name[64], cpu_name[64];
        snprintf(gpu_name, sizeof gpu_name, "%s-gpu.png", files[f][2]);
        snprintf(cpu_name, sizeof cpu_name, "%s-cpu.png", files[f][2]);
        image gpu = RENDER(gpu_name, files[f][0], "--time", files[f][1], "--size", SIZE);
        image cpu = RENDER(cpu_name, files[f][0], "--time", files[f][1], "--size", SIZE, "--skinning", "cpu");
        long differing = 0;
        bool same = same_picture(&gpu, &cpu, &differing);
        printf("%s at %s s: GPU vs CPU %ld pixels differ\n", files[f][0], files[f][1], differing);
        assert_true(same);
        free_image(&gpu);
        free_image(&cpu);
    }
    const char *crowd[] = {"--crowd", "9", "--time", "0.4", "--size", "480x320", "--no-grid", "--background", "000000"};
#define CROWD_ARGS crowd[0], crowd[1], crowd[2], crowd[3], crowd[4], crowd[5], crowd[6], crowd[7], crowd[8]
    image lod = RENDER("m-crowd.png", "builtin:morph", CROWD_ARGS);
    image whole = RENDER("m-crowd-whole.png", "builtin:morph", CROWD_ARGS, "--no-lod");
    image cpu = RENDER("m-crowd-cpu.png", "builtin:morph", CROWD_ARGS, "--no-lod", "--skinning", "cpu");
    image flat = RENDER("m-crowd-flat.png", "builtin:morph", CROWD_ARGS, "--morph", "0=0", "--morph", "10=0", "--morph",
                        "20=0", "--morph", "30=0", "--morph", "40=0");
#undef CROWD_ARGS
    long lod_differing = 0, cpu_differing = 0, flat_differing = 0;
    same_picture(&lod, &whole, &lod_differing);
    bool cpu_same = same_picture(&whole, &cpu, &cpu_differing);
    same_picture(&lod, &flat, &flat_differing);
    long covered = lit_pixels(&whole);
    printf("builtin:morph crowd of 9: levels vs whole %ld pixels differ, GPU vs CPU %ld, morphed vs not %ld (of %ld "
           "covered)\n",
           lod_differing, cpu_differing, flat_differing, covered);
    assert_true(cpu_same);
    assert_true(lod_differing * 4 < flat_differing); /* the levels keep the bulges */
    assert_true(flat_differing > covered / 10);
    free_image(&lod);
    free_image(&whole);
    free_image(&cpu);
    free_image(&flat);
}

/* Skins over the GPU limit go to the CPU with a warning, and the picture is the same. */
static void test_gpu_joint_limit_falls_back_to_cpu(void **state)
{
    (void)state;
    char path[1024], out[1024];
    if (!testdata_path("raylib/robot.glb", path, sizeof path))
        skip();
    tmp_path("limit.png", out, sizeof out);
    run_result r = RUN("render", path, "--clip", "Robot_Wave", "--time", "0.6", "--size", SIZE, "--gpu-joint-limit",
                       "16", "-o", out);
    assert_int_equal(r.code, 0);
    assert_non_null(strstr(r.err, "skinned on the CPU"));
    run_free(&r);
    image fallback = load_image(out);
    image gpu = RENDER("limit-gpu.png", path, "--clip", "Robot_Wave", "--time", "0.6", "--size", SIZE);
    long differing = 0;
    assert_true(same_picture(&fallback, &gpu, &differing));
    free_image(&fallback);
    free_image(&gpu);
}

static void test_animated_frames_differ_static_do_not(void **state)
{
    (void)state;
    char fixture[1024], duck[1024];
    fixture_path("two_bone.dae", fixture, sizeof fixture);
    image a = RENDER("anim-a.png", fixture, "--time", "0", "--size", SIZE);
    image b = RENDER("anim-b.png", fixture, "--time", "1", "--size", SIZE);
    long differing = 0;
    assert_false(same_picture(&a, &b, &differing));
    assert_true(differing > 500);
    free_image(&a);
    free_image(&b);
    if (!testdata_path("assimp/Collada/duck.dae", duck, sizeof duck))
        skip();
    a = RENDER("static-a.png", duck, "--time", "0", "--size", SIZE);
    b = RENDER("static-b.png", duck, "--time", "1", "--size", SIZE);
    assert_int_equal(image_difference(&a, &b, NULL), 0);
    free_image(&a);
    free_image(&b);
}

/* A glTF mesh without normals is drawn flat, as glTF asks ("client implementations MUST calculate
 * flat normals"): Phong shading draws what --shading flat draws. */
static void test_missing_normals_drawn_flat(void **state)
{
    (void)state;
    char glb[1024];
    if (!testdata_path("gltf-samples/RecursiveSkeletons.glb", glb, sizeof glb))
        skip();
    image phong = RENDER("no-normals.png", glb, "--size", SIZE);
    image flat = RENDER("no-normals-flat.png", glb, "--size", SIZE, "--shading", "flat");
    long differing = 0;
    assert_true(same_picture(&phong, &flat, &differing));
    free_image(&phong);
    free_image(&flat);
}

/* Vertex colours multiply the base colour (kwxport_test_vcolors.dae: a white cube painted red,
 * green and yellow at corners): red pixels where the file paints red; none in clay
 * (--no-materials), which shows the shape alone. */
static void test_vertex_colours_drawn(void **state)
{
    (void)state;
    char dae[1024];
    if (!testdata_path("assimp/Collada/kwxport_test_vcolors.dae", dae, sizeof dae))
        skip();
    image painted = RENDER("vcolors.png", dae, "--size", SIZE);
    image clay = RENDER("vcolors-clay.png", dae, "--size", SIZE, "--no-materials");
    long red[2] = {0, 0};
    const image *both[2] = {&painted, &clay};
    for (int k = 0; k < 2; k++)
        for (long i = 0; i < (long)both[k]->width * both[k]->height; i++) {
            const unsigned char *p = &both[k]->rgb[i * 3];
            red[k] += p[0] > 150 && p[1] < 80 && p[2] < 80;
        }
    print_message("red pixels: painted %ld, clay %ld\n", red[0], red[1]);
    assert_true(red[0] > 500);
    assert_int_equal(red[1], 0);
    free_image(&painted);
    free_image(&clay);
}

/* glTF's alpha modes on a red mesh (two_bone_cubic.gltf with a material): opaque ignores alpha;
 * a mask leaves out what is below its cutoff and keeps the rest whole; a blend of alpha 0.5 is
 * drawn as half the coverage of each multisampled pixel (red mixed with the background), and one
 * of alpha 0 not at all. */
static long red_pixels(const char *name, const char *mode, double alpha, bool pure)
{
    char src[1024], file[1024];
    size_t size = 0;
    char *text = (char *)read_file(fixture_path("two_bone_cubic.gltf", src, sizeof src), &size);
    cJSON *doc = cJSON_ParseWithLength(text, size);
    free(text);
    cJSON *material = cJSON_CreateObject(), *pbr = cJSON_AddObjectToObject(material, "pbrMetallicRoughness");
    const double color[4] = {1, 0, 0, alpha};
    cJSON_AddItemToObject(pbr, "baseColorFactor", cJSON_CreateDoubleArray(color, 4));
    cJSON_AddStringToObject(material, "alphaMode", mode);
    cJSON_AddItemToArray(cJSON_AddArrayToObject(doc, "materials"), material);
    cJSON *prim = cJSON_GetArrayItem(
        cJSON_GetObjectItem(cJSON_GetArrayItem(cJSON_GetObjectItem(doc, "meshes"), 0), "primitives"), 0);
    cJSON_AddNumberToObject(prim, "material", 0);
    char *out = cJSON_PrintUnformatted(doc);
    char gltf_name[64];
    snprintf(gltf_name, sizeof gltf_name, "%s.gltf", name);
    write_file(tmp_path(gltf_name, file, sizeof file), out, strlen(out));
    free(out);
    cJSON_Delete(doc);
    char png[64];
    snprintf(png, sizeof png, "%s.png", name);
    image im = RENDER(png, file, "--size", SIZE, "--no-grid", "--lighting", "off");
    long count = 0;
    for (long i = 0; i < (long)im.width * im.height; i++) {
        const unsigned char *p = &im.rgb[i * 3];
        count += pure ? p[0] > 200 && p[1] < 40 : p[0] > p[1] + 40;
    }
    free_image(&im);
    return count;
}

static void test_alpha_modes(void **state)
{
    (void)state;
    long opaque = red_pixels("alpha-opaque", "OPAQUE", 0.25, true);
    long masked = red_pixels("alpha-mask-out", "MASK", 0.25, false);
    long kept = red_pixels("alpha-mask-in", "MASK", 0.75, true);
    long half_pure = red_pixels("alpha-blend", "BLEND", 0.5, true),
         half = red_pixels("alpha-blend", "BLEND", 0.5, false);
    long none = red_pixels("alpha-blend-none", "BLEND", 0.0, false);
    print_message("red pixels: opaque %ld, mask 0.25 %ld, mask 0.75 %ld, blend 0.5 %ld pure of %ld, blend 0 %ld\n",
                  opaque, masked, kept, half_pure, half, none);
    assert_true(opaque > 1000);
    assert_int_equal(masked, 0);
    assert_true(labs(kept - opaque) < opaque / 20);
    assert_true(half > opaque / 2 && half_pure < opaque / 5);
    assert_int_equal(none, 0);
}

/* A skeleton-only file shows bones without being asked: bone-coloured pixels appear. */
static void test_bone_only_file_shows_bones(void **state)
{
    (void)state;
    char path[1024];
    if (!testdata_path("assimp/BVH/01_01.bvh", path, sizeof path))
        skip();
    image im = RENDER("bvh.png", path, "--time", "1", "--size", SIZE, "--no-grid", "--background", "000000");
    long lit = lit_pixels(&im);
    printf("BVH skeleton: %ld lit pixels of %d\n", lit, im.width * im.height);
    assert_true(lit > 300);
    free_image(&im);
    image off = RENDER("bvh-off.png", path, "--time", "1", "--size", SIZE, "--no-grid", "--background", "000000",
                       "--no-skeleton");
    assert_int_equal(lit_pixels(&off), 0);
    free_image(&off);
}

/* Pixels of one pure colour (each channel within 60 of it) and where they are on average. */
typedef struct colour_patch {
    long count;
    double x, y;
} colour_patch;

static colour_patch find_colour(const image *im, int r, int g, int b)
{
    colour_patch p = {0};
    for (int y = 0; y < im->height; y++)
        for (int x = 0; x < im->width; x++) {
            const unsigned char *c = &im->rgb[((size_t)y * im->width + x) * 3];
            if (abs(c[0] - r) < 60 && abs(c[1] - g) < 60 && abs(c[2] - b) < 60)
                p.count++, p.x += x, p.y += y;
        }
    if (p.count)
        p.x /= p.count, p.y /= p.count;
    return p;
}

/* A texture embedded in the file (a GLB's bufferView, a .gltf's data: URI, and a .sinew
 * converted from the GLB) is drawn: the strip shows the image's four quadrants where glTF's
 * UVs put them (uv (0, 0) is the image's top left, at the strip's bottom left). */
static void test_embedded_texture(void **state)
{
    (void)state;
    char glb[1024], gltf[1024], converted[1024];
    fixture_path("two_bone_textured.glb", glb, sizeof glb);
    fixture_path("two_bone_textured.gltf", gltf, sizeof gltf);
    tmp_path("two_bone_textured.sinew", converted, sizeof converted);
    run_result r = RUN("convert", glb, converted);
    assert_int_equal(r.code, 0);
    run_free(&r);
    const char *files[] = {glb, gltf, converted};
    image first = {0};
    for (int f = 0; f < 3; f++) {
        image im =
            RENDER("textured.png", files[f], "--size", SIZE, "--no-grid", "--no-skeleton", "--background", "000000");
        colour_patch red = find_colour(&im, 255, 0, 0), green = find_colour(&im, 0, 255, 0),
                     blue = find_colour(&im, 0, 0, 255), white = find_colour(&im, 235, 235, 235);
        printf("embedded texture (%s): red %ld, green %ld, blue %ld, white %ld pixels\n", strrchr(files[f], '/') + 1,
               red.count, green.count, blue.count, white.count);
        assert_true(red.count > 500 && green.count > 500 && blue.count > 500 && white.count > 500);
        assert_true(red.y > blue.y && green.y > white.y); /* the image's top row at the strip's bottom */
        assert_true(green.x > red.x && white.x > blue.x); /* u to the right */
        if (f == 0) {
            first = im;
            continue;
        }
        long differing;
        assert_true(same_picture(&first, &im, &differing));
        free_image(&im);
    }
    free_image(&first);
}

static void test_frame_sequence_and_video(void **state)
{
    (void)state;
    char fixture[1024], pattern[1024], first[1024], last[1024], beyond[1024];
    fixture_path("two_bone_cubic.gltf", fixture, sizeof fixture);
    tmp_path("seq-%03d.png", pattern, sizeof pattern);
    tmp_path("seq-005.png", beyond, sizeof beyond);
    remove(beyond);
    run_result r =
        RUN("render", fixture, "--from", "0", "--to", "0.4", "--fps", "10", "--size", "64x48", "-o", pattern);
    assert_int_equal(r.code, 0);
    run_free(&r);
    tmp_path("seq-000.png", first, sizeof first);
    tmp_path("seq-004.png", last, sizeof last);
    size_t size = 0;
    void *bytes = read_file(first, &size);
    assert_non_null(bytes);
    free(bytes);
    bytes = read_file(last, &size);
    assert_non_null(bytes);
    free(bytes);
    assert_null(read_file(beyond, &size));

    char video[1024];
    tmp_path("clip.mp4", video, sizeof video);
    remove(video);
    static const char *const no_path[] = {"PATH=/nonexistent", NULL};
    r = RUN_ENV(no_path, "render", fixture, "--fps", "10", "--size", "64x48", "-o", video);
    assert_int_equal(r.code, 3);
    assert_non_null(strstr(r.err, "ffmpeg"));
    run_free(&r);
    if (system("command -v ffmpeg >/dev/null 2>&1") != 0) {
        printf("ffmpeg is not installed: the MP4 path is not tested\n");
        return;
    }
    r = RUN("render", fixture, "--fps", "10", "--size", "65x47", "-o", video);
    if (r.code != 0)
        fail_msg("mp4: %s", r.err);
    run_free(&r);
    unsigned char *mp4 = read_file(video, &size);
    assert_non_null(mp4);
    assert_true(size > 100);
    assert_memory_equal(mp4 + 4, "ftyp", 4);
    free(mp4);
    /* the container follows the extension: a GIF (its own palette) and a WebM */
    static const struct {
        const char *name, *magic;
        size_t at;
    } kinds[] = {{"clip.gif", "GIF89a", 0}, {"clip.webm", "\x1a\x45\xdf\xa3", 0}};
    for (size_t k = 0; k < sizeof kinds / sizeof kinds[0]; k++) {
        tmp_path(kinds[k].name, video, sizeof video);
        r = RUN("render", fixture, "--fps", "10", "--size", "65x47", "-o", video);
        if (r.code != 0)
            fail_msg("%s: %s", kinds[k].name, r.err);
        run_free(&r);
        unsigned char *bytes_out = read_file(video, &size);
        assert_non_null(bytes_out);
        assert_memory_equal(bytes_out + kinds[k].at, kinds[k].magic, strlen(kinds[k].magic));
        free(bytes_out);
    }
}

/* --track: the camera follows the clip's root over the ground. A skeleton whose hips walk 3 m
 * along x and that does nothing else looks the same at the sequence's end as at its start;
 * untracked it has left the view. The demo's wave does not move its hips: tracked, its frames
 * are the untracked ones (the camera does not sway with the arm). */
static void test_track(void **state)
{
    (void)state;
    char bvh[1024], pattern[1024], first[1024], last[1024], dae[1100], dir[1024];
    tmp_path("walk-away.bvh", bvh, sizeof bvh);
    const char *text = "HIERARCHY\nROOT Hips\n{\n  OFFSET 0 0 0\n"
                       "  CHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation\n"
                       "  JOINT Chest\n  {\n    OFFSET 0 50 0\n    CHANNELS 3 Zrotation Xrotation Yrotation\n"
                       "    End Site\n    {\n      OFFSET 0 40 0\n    }\n  }\n}\n"
                       "MOTION\nFrames: 2\nFrame Time: 1.0\n"
                       "0 90 0 0 0 0 0 0 0\n300 90 50 0 0 0 0 0 0\n";
    write_file(bvh, text, strlen(text));
    tmp_path("track-%d.png", pattern, sizeof pattern);
    tmp_path("track-0.png", first, sizeof first);
    tmp_path("track-2.png", last, sizeof last);
    for (int tracked = 1; tracked >= 0; tracked--) {
        const char *args[] = {
            "render", bvh,  "--from",    "0",        "--to",        "1",  "--fps", "2",
            "--size", SIZE, "--no-grid", "--camera", "orbit:20,15", "-o", pattern, tracked ? "--track" : NULL,
            NULL};
        run_result r = run_sinew(NULL, args);
        assert_int_equal(r.code, 0);
        run_free(&r);
        image a = load_image(first), b = load_image(last);
        long differing = 0;
        /* tracked: the same picture (z moved too: x and z are the ground) */
        assert_true(same_picture(&a, &b, &differing) == (tracked == 1));
        free_image(&a);
        free_image(&b);
    }
    /* in place, from the same camera: tracked or not, the same frames */
    tmp_path("track-demo", dir, sizeof dir);
    run_result r = RUN("demo", dir, "--force");
    assert_int_equal(r.code, 0);
    run_free(&r);
    snprintf(dae, sizeof dae, "%s/humanoid.dae", dir);
    image frames[2];
    for (int tracked = 0; tracked < 2; tracked++) {
        tmp_path(tracked ? "wave-t%d.png" : "wave-%d.png", pattern, sizeof pattern);
        const char *args[] = {"render",    dae,
                              "--clip",    "wave",
                              "--from",    "0",
                              "--to",      "1",
                              "--fps",     "2",
                              "--size",    SIZE,
                              "--no-grid", "--camera-position",
                              "1,1.5,4",   "--camera-focal-point",
                              "0,1,0",     "-o",
                              pattern,     tracked ? "--track" : NULL,
                              NULL};
        r = run_sinew(NULL, args);
        assert_int_equal(r.code, 0);
        run_free(&r);
        tmp_path(tracked ? "wave-t2.png" : "wave-2.png", last, sizeof last);
        frames[tracked] = load_image(last);
    }
    long differing = 0;
    bool same = same_picture(&frames[0], &frames[1], &differing);
    print_message("wave, tracked against untracked: %ld pixels differ\n", differing);
    assert_true(same); /* (a pixel or two: the depth range follows the framing, over the start alone when tracked) */
    free_image(&frames[0]);
    free_image(&frames[1]);
}

/* -o chooses the format by its extension (JPEG here, not PNG bytes in a .jpg) and makes the
 * folders that are missing, for a frame pattern too (issue 16). */
static void test_output_formats_and_folders(void **state)
{
    (void)state;
    char fixture[1024], dir[1024], jpg[1200], pattern[1200], first[1200];
    fixture_path("two_bone_cubic.gltf", fixture, sizeof fixture);
    tmp_path("made/by/render", dir, sizeof dir);
    snprintf(jpg, sizeof jpg, "%s/still.jpg", dir);
    snprintf(pattern, sizeof pattern, "%s/seq/f%%02d.bmp", dir);
    snprintf(first, sizeof first, "%s/seq/f00.bmp", dir);
    run_result r = RUN("render", fixture, "--size", "32x24", "-o", jpg);
    assert_int_equal(r.code, 0);
    run_free(&r);
    size_t size = 0;
    unsigned char *bytes = read_file(jpg, &size);
    assert_non_null(bytes);
    assert_true(size > 4 && bytes[0] == 0xff && bytes[1] == 0xd8); /* a JPEG's start-of-image */
    free(bytes);
    r = RUN("render", fixture, "--size", "32x24", "--from", "0", "--to", "0.1", "--fps", "10", "-o", pattern);
    assert_int_equal(r.code, 0);
    run_free(&r);
    bytes = read_file(first, &size);
    assert_non_null(bytes);
    assert_true(size > 2 && bytes[0] == 'B' && bytes[1] == 'M');
    free(bytes);
}

/* A transparent background: PNG with alpha, the corners clear and the model opaque. */
static void test_transparent_background(void **state)
{
    (void)state;
    char fixture[1024], out[1024];
    fixture_path("pbr_spheres.glb", fixture, sizeof fixture);
    tmp_path("transparent.png", out, sizeof out);
    run_result r = RUN("render", fixture, "--size", "160x120", "--background", "transparent", "--no-grid", "--camera",
                       "front", "-o", out);
    assert_int_equal(r.code, 0);
    run_free(&r);
    int w = 0, h = 0, channels = 0;
    unsigned char *px = stbi_load(out, &w, &h, &channels, 4);
    assert_non_null(px);
    assert_int_equal(channels, 4);
    assert_int_equal(px[3], 0);                             /* top left */
    assert_int_equal(px[((h - 1) * w + w - 1) * 4 + 3], 0); /* bottom right */
    long opaque = 0, clear = 0;
    for (int i = 0; i < w * h; i++)
        opaque += px[i * 4 + 3] == 255, clear += px[i * 4 + 3] == 0;
    printf("transparent background: %ld opaque, %ld clear of %d pixels\n", opaque, clear, w * h);
    assert_true(opaque > w * h / 20 && clear > w * h / 3);
    stbi_image_free(px);
}

/* Views along the axes and the orthographic projection: the front view of the spheres (one
 * row along X at y = 0) puts them on the middle row; from the top they are still in a row;
 * a parallel projection draws the outer spheres as large as the inner ones, which the
 * perspective view does not. A turntable sequence turns the camera: its frames differ. */
static void test_camera_views_and_turntable(void **state)
{
    (void)state;
    char fixture[1024];
    fixture_path("pbr_spheres.glb", fixture, sizeof fixture);
    image front = RENDER("view-front.png", fixture, "--size", "320x120", "--camera", "front", "--no-grid", "--ortho",
                         "--background", "000000", "--no-lighting", "--materials", "off");
    /* in the middle row, the runs of lit pixels: four spheres of equal width */
    int runs[8], run_count = 0, width = 0, y = front.height / 2;
    for (int x = 0; x <= front.width; x++) {
        bool lit = x < front.width && front.rgb[(y * front.width + x) * 3] > 40;
        if (lit)
            width++;
        else if (width) {
            if (run_count < 8)
                runs[run_count++] = width;
            width = 0;
        }
    }
    printf("front, orthographic: %d spheres on the middle row, widths %d %d %d %d\n", run_count, runs[0], runs[1],
           runs[2], runs[3]);
    assert_int_equal(run_count, 4);
    assert_true(abs(runs[0] - runs[1]) <= 1 && abs(runs[0] - runs[3]) <= 1);
    free_image(&front);
    /* the twist tube stands along +Y: tall from the front, round from the top */
    char tube[1024];
    fixture_path("twist_tube.glb", tube, sizeof tube);
    /* and with --up z, the file's Z is up: the tube lies along -Z, round from the front */
    /* with f3d's +X: the file's X is up, the tube lies across the picture */
    const char *views[4] = {"front", "top", "front", "front"}, *ups[4] = {"y", "y", "z", "+X"};
    int box[4][2];
    for (int v = 0; v < 4; v++) {
        image im = RENDER("view-tube.png", tube, "--size", "160x160", "--camera", views[v], "--up", ups[v], "--no-grid",
                          "--background", "000000", "--no-lighting", "--materials", "off");
        int x0 = im.width, x1 = -1, y0 = im.height, y1 = -1;
        for (int row = 0; row < im.height; row++)
            for (int col = 0; col < im.width; col++)
                if (im.rgb[(row * im.width + col) * 3] > 40) {
                    x0 = col < x0 ? col : x0, x1 = col > x1 ? col : x1;
                    y0 = row < y0 ? row : y0, y1 = row > y1 ? row : y1;
                }
        box[v][0] = x1 - x0 + 1, box[v][1] = y1 - y0 + 1;
        free_image(&im);
    }
    printf("twist tube: %dx%d pixels from the front, %dx%d from the top, %dx%d from the front with --up z\n", box[0][0],
           box[0][1], box[1][0], box[1][1], box[2][0], box[2][1]);
    assert_true(box[0][1] > 3 * box[0][0]);
    assert_true(abs(box[1][0] - box[1][1]) <= 2);
    assert_true(abs(box[2][0] - box[2][1]) <= 2);
    printf("twist tube with --up +X: %dx%d pixels from the front\n", box[3][0], box[3][1]);
    assert_true(box[3][0] > 3 * box[3][1]);
    long differing = 0;

    char pattern[1024], first[1100], later[1100];
    tmp_path("turntable/f%02d.png", pattern, sizeof pattern);
    run_result r = RUN("render", fixture, "--size", "80x60", "--turntable", "--from", "0", "--to", "0.3", "--fps", "10",
                       "-o", pattern);
    assert_int_equal(r.code, 0);
    run_free(&r);
    tmp_path("turntable/f00.png", first, sizeof first);
    tmp_path("turntable/f02.png", later, sizeof later);
    image a = load_image(first), b = load_image(later);
    assert_false(same_picture(&a, &b, &differing));
    printf("turntable: frame 0 vs frame 2 (180 degrees on): %ld pixels differ\n", differing);
    free_image(&a);
    free_image(&b);
}

static void expect_failure(int code, const char *message, const char *const *args)
{
    run_result r = run_sinew(NULL, args);
    if (r.code != code || !strstr(r.err, message))
        fail_msg("sinew %s %s: exit %d (expected %d), stderr \"%s\" (expected \"%s\")", args[0], args[1], r.code, code,
                 r.err, message);
    run_free(&r);
}

#define EXPECT_FAILURE(code, message, ...) expect_failure((code), (message), (const char *const[]){__VA_ARGS__, NULL})

static void test_bad_input(void **state)
{
    (void)state;
    char fixture[1024], out[1024], garbage[1024];
    fixture_path("two_bone_cubic.gltf", fixture, sizeof fixture);
    tmp_path("bad.png", out, sizeof out);
    tmp_path("garbage.dae", garbage, sizeof garbage);
    write_file(garbage, "<COLLADA>not really", 19);
    EXPECT_FAILURE(2, "garbage.dae", "render", garbage, "-o", out);
    EXPECT_FAILURE(2, "no-such-file.glb", "render", "no-such-file.glb", "-o", out);
    EXPECT_FAILURE(1, "--size", "render", fixture, "--size", "0x100", "-o", out);
    EXPECT_FAILURE(1, "--size", "render", fixture, "--size", "wide", "-o", out);
    EXPECT_FAILURE(1, "--up \"w\": expected [+|-]x, y or z", "render", fixture, "--up", "w", "-o", out);
    EXPECT_FAILURE(1, "exposure", "render", fixture, "--exposure", "11", "-o", out);
    EXPECT_FAILURE(1, "--samples \"1048576\"", "render", fixture, "--samples", "1048576", "-o", out);
    EXPECT_FAILURE(1, "more than 67 (8192x8192)", "render", fixture, "--size", "16384x16384", "-o", out);
    EXPECT_FAILURE(1, "tone-mapping", "render", fixture, "--tone-mapping", "filmic", "-o", out);
    EXPECT_FAILURE(2, "no-such-sky.hdr", "render", fixture, "--hdri", "no-such-sky.hdr", "--shading", "pbr", "-o", out);
    EXPECT_FAILURE(1, "orbit:YAW,PITCH", "render", fixture, "--camera", "orbit:abc", "-o", out);
    EXPECT_FAILURE(1, "fly:X,Y,Z,YAW,PITCH", "render", fixture, "--camera", "fly:1,2,3", "-o", out);
    EXPECT_FAILURE(1, "shading", "render", fixture, "--shading", "toon", "-o", out);
    EXPECT_FAILURE(1, "background", "render", fixture, "--background", "purple", "-o", out);
    EXPECT_FAILURE(1, "no -o", "render", fixture);
    EXPECT_FAILURE(1, "frame%04d.png", "render", fixture, "--fps", "10", "-o", "frames.png");
    EXPECT_FAILURE(1, "one %d", "render", fixture, "--fps", "10", "-o", "frame%s%d.png");
    EXPECT_FAILURE(2, "no clip \"nope\"", "render", fixture, "--clip", "nope", "-o", out);
    EXPECT_FAILURE(2, "no node of that name", "render", fixture, "--select", "nope", "-o", out);
    /* outputs (exit 4): a folder that is not there, a full device, the input itself; nothing half written */
    /* a folder that cannot be made: a file is in the way */
    char blocker[1024], under[1100];
    tmp_path("not-a-folder", blocker, sizeof blocker);
    write_file(blocker, "x", 1);
    snprintf(under, sizeof under, "%s/x.png", blocker);
    EXPECT_FAILURE(4, "is not a folder", "render", fixture, "--size", "8x8", "-o", under);
    EXPECT_FAILURE(1, "write images as .png, .jpg", "render", fixture, "--size", "8x8", "-o", "x.xyz");
    EXPECT_FAILURE(4, "/dev/full: cannot write: No space left on device", "render", fixture, "--size", "8x8", "-o",
                   "/dev/full");
    /* never over an input: a model named like an output (no extension: PNG) */
    char model[1024];
    tmp_path("model-without-extension", model, sizeof model);
    size_t model_size = 0;
    char *bytes = read_file(fixture, &model_size);
    write_file(model, bytes, model_size);
    free(bytes);
    EXPECT_FAILURE(4, "the output is the input file", "render", model, "--size", "8x8", "-o", model);
    EXPECT_FAILURE(1, "write images as .png", "render", fixture, "--size", "8x8", "-o", fixture);
    EXPECT_FAILURE(1, "up to %09d", "render", fixture, "--fps", "10", "-o", "x.png%2147483648d");
    EXPECT_FAILURE(1, "bad --time \"1e39\"", "render", fixture, "--time", "1e39", "-o", out);
    EXPECT_FAILURE(1, "bad --time \"nan\"", "render", fixture, "--time", "nan", "-o", out);
    EXPECT_FAILURE(1, "bad --fps", "render", fixture, "--fps", "1e400", "-o", "f%d.png");
    static const char *const no_egl[] = {"SINEW_EGL_PLATFORM=none", NULL};
    run_result r = RUN_ENV(no_egl, "render", fixture, "-o", out);
    assert_int_equal(r.code, 3);
    assert_non_null(strstr(r.err, "no OpenGL 3.3 core context through EGL"));
    run_free(&r);
}

/* The benchmark runs and reports (its numbers are not judged here: never a timed test). */
static void test_bench_render_reports(void **state)
{
    (void)state;
    run_result r = RUN("bench", "render", "--frames", "2", "--size", "64x48", "--json");
    if (r.code != 0)
        fail_msg("bench render: exit %d: %s", r.code, r.err);
    assert_non_null(strstr(r.out, "\"vertices\":\t10016"));
    assert_non_null(strstr(r.out, "\"gpu_skinning_fps\""));
    assert_non_null(strstr(r.out, "\"cpu_skinning_fps\""));
    run_free(&r);
    r = RUN("bench", "muscle", "--json");
    assert_int_equal(r.code, 0);
    assert_non_null(strstr(r.out, "\"solve_ns\""));
    run_free(&r);
    EXPECT_FAILURE(1, "whole number", "bench", "render", "--frames", "12x");
    EXPECT_FAILURE(1, "bad --size", "bench", "render", "--size", "64x48junk");
    EXPECT_FAILURE(1, "bad --size", "arm", "--size", "0x5", "-o", "arm.png");
    EXPECT_FAILURE(1, "unknown benchmark", "bench", "fly");
    r = RUN("bench", "crowd", "--size", "64x48", "--frames", "1", "--count", "1", "--most", "4", "--samples", "1",
            "--skinning", "gpu", "--json");
    if (r.code != 0)
        fail_msg("bench crowd: exit %d: %s", r.code, r.err);
    assert_non_null(strstr(r.out, "\"characters_at_60fps\""));
    assert_non_null(strstr(r.out, "\"renderer\""));
    assert_non_null(strstr(r.out, "\"pose_ms\""));
    run_free(&r);
    EXPECT_FAILURE(1, "--threads", "bench", "crowd", "--threads", "0");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_golden_fixture),
        cmocka_unit_test(test_golden_models),
        cmocka_unit_test(test_golden_muscles),
        cmocka_unit_test(test_golden_pbr),
        cmocka_unit_test(test_golden_look),
        cmocka_unit_test(test_tolerance_catches_a_wrong_pose),
        cmocka_unit_test(test_gpu_and_cpu_skinning_agree),
        cmocka_unit_test(test_dual_quaternion_skinning),
        cmocka_unit_test(test_crowd),
        cmocka_unit_test(test_morph_gpu_equals_cpu),
        cmocka_unit_test(test_output_formats_and_folders),
        cmocka_unit_test(test_transparent_background),
        cmocka_unit_test(test_camera_views_and_turntable),
        cmocka_unit_test(test_gpu_joint_limit_falls_back_to_cpu),
        cmocka_unit_test(test_animated_frames_differ_static_do_not),
        cmocka_unit_test(test_bone_only_file_shows_bones),
        cmocka_unit_test(test_embedded_texture),
        cmocka_unit_test(test_frame_sequence_and_video),
        cmocka_unit_test(test_track),
        cmocka_unit_test(test_missing_normals_drawn_flat),
        cmocka_unit_test(test_vertex_colours_drawn),
        cmocka_unit_test(test_alpha_modes),
        cmocka_unit_test(test_bad_input),
        cmocka_unit_test(test_bench_render_reports),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
