/* The renderer as a library, without the CLI: a headless context, a renderer for a model, a
 * frame drawn and read back. The synthetic chain (a tube along +Y) drawn unlit in clay on a
 * plain background covers the middle of the picture and not the corners; its posed bounds
 * are where the chain stands; GPU and CPU skinning draw the same picture; bad frames are
 * refused with a message. Skips when this machine has no OpenGL 3.3 through EGL. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "helpers.h"

#define W 96
#define H 128

typedef struct fixture {
    sinew_headless *headless;
    sinew_model *model;
    sinew_renderer *renderer;
    sinew_mat4 *worlds;
    uint8_t pixels[W * H * 4];
} fixture;

static int setup(void **state)
{
    static fixture f;
    memset(&f, 0, sizeof f);
    sinew_error error = {0};
    if (sinew_headless_create(&(sinew_headless_desc){.width = W, .height = H, .samples = 1}, &f.headless, &error) !=
        SINEW_OK) {
        *state = NULL;
        return 0;
    }
    sinew_synthetic_desc sd = {.joints = 8, .vertices = 2000};
    assert_int_equal(sinew_synthetic_model(&sd, &f.model, &error), SINEW_OK);
    assert_int_equal(sinew_renderer_create(&(sinew_renderer_desc){.model = f.model}, &f.renderer, &error), SINEW_OK);
    f.worlds = pose_worlds(f.model, NULL, 0.0f);
    *state = &f;
    return 0;
}

static int teardown(void **state)
{
    fixture *f = *state;
    if (!f)
        return 0;
    free(f->worlds);
    sinew_renderer_free(f->renderer);
    sinew_model_free(f->model);
    sinew_headless_free(f->headless);
    return 0;
}

static void draw_with(fixture *f, const sinew_render_options *o, bool front);

/* Draws with clay, no lighting, no grid, on black, seen from the front at the chain. */
static void draw(fixture *f, sinew_skinning skinning)
{
    sinew_render_options o = sinew_render_options_default();
    o.clay = true;
    o.unlit = true;
    o.hide_grid = true;
    o.background_set = true;
    o.background[0] = o.background[1] = o.background[2] = 0.0f;
    o.skinning = skinning;
    draw_with(f, &o, true);
}

/* Draws the chain with `o`, framed (from the front, or from the default camera's angle), and
 * reads the picture back. */
static void draw_with(fixture *f, const sinew_render_options *o, bool front)
{
    float lo[3], hi[3];
    assert_true(sinew_renderer_bounds(f->renderer, f->worlds, f->model->node_count, lo, hi));
    sinew_camera camera = sinew_camera_default();
    if (front)
        camera.pitch = 0.0f;
    sinew_camera_frame(&camera, lo, hi, (float)W / (float)H);
    sinew_frame frame = {.worlds = f->worlds,
                         .world_count = f->model->node_count,
                         .camera = &camera,
                         .width = W,
                         .height = H,
                         .options = o};
    sinew_error error = {0};
    sinew_headless_bind(f->headless);
    assert_int_equal(sinew_renderer_draw(f->renderer, &frame, &error), SINEW_OK);
    assert_int_equal(sinew_headless_read(f->headless, f->pixels, &error), SINEW_OK);
}

static bool lit(const uint8_t *pixels, int x, int y)
{
    const uint8_t *p = &pixels[((size_t)y * W + (size_t)x) * 4];
    return p[0] + p[1] + p[2] > 60;
}

static void test_draw_and_read_back(void **state)
{
    fixture *f = *state;
    if (!f)
        skip();
    float lo[3], hi[3];
    assert_true(sinew_renderer_bounds(f->renderer, f->worlds, f->model->node_count, lo, hi));
    /* the chain stands 1.8 m tall on the origin */
    assert_near(lo[1], 0.0, 0.05, "bottom");
    assert_near(hi[1], 1.8, 0.1, "top");
    draw(f, SINEW_SKINNING_GPU);
    long covered = 0;
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++)
            covered += lit(f->pixels, x, y);
    print_message("the chain covers %ld of %d pixels\n", covered, W * H);
    assert_true(lit(f->pixels, W / 2, H / 2));
    assert_false(lit(f->pixels, 0, 0) || lit(f->pixels, W - 1, 0) || lit(f->pixels, 0, H - 1) ||
                 lit(f->pixels, W - 1, H - 1));
    assert_true(covered > W * H / 20 && covered < W * H / 2);
    assert_non_null(sinew_renderer_gl_name(f->renderer));
}

/* A zeroed sinew_render_options is the defaults: the mesh drawn, lit, with its grid, on the
 * default grey; and the option names read back what the inverted fields hold. */
static void test_zeroed_options_are_the_defaults(void **state)
{
    fixture *f = *state;
    if (!f)
        skip();
    sinew_render_options zero = {0}, named = sinew_render_options_default();
    assert_memory_equal(&zero, &named, sizeof zero);
    draw_with(f, &zero, false);
    long other = 0;
    const uint8_t *corner = f->pixels;
    for (size_t i = 0; i < (size_t)W * H; i++)
        other += abs(f->pixels[i * 4] - corner[0]) + abs(f->pixels[i * 4 + 1] - corner[1]) > 30;
    print_message("zeroed options: corner (%u, %u, %u), %ld pixels of the model\n", corner[0], corner[1], corner[2],
                  other);
    assert_true(other > W * H / 20);                                   /* the mesh is drawn */
    assert_true(abs(corner[0] - 41) <= 2 && abs(corner[2] - 48) <= 2); /* 0.16, 0.17, 0.19: the default grey */
    char value[32];
    assert_int_equal(sinew_render_option_get(&zero, "materials", value, sizeof value, NULL), SINEW_OK);
    assert_string_equal(value, "on");
    assert_int_equal(sinew_render_option_set(&zero, "grid", "off", NULL), SINEW_OK);
    assert_true(zero.hide_grid);
    assert_int_equal(sinew_render_option_get(&zero, "grid", value, sizeof value, NULL), SINEW_OK);
    assert_string_equal(value, "off");
    assert_int_equal(sinew_render_option_get(&zero, "background", value, sizeof value, NULL), SINEW_OK);
    assert_string_equal(value, "#292b30");
}

static void test_cpu_and_gpu_skinning_agree(void **state)
{
    fixture *f = *state;
    if (!f)
        skip();
    free(f->worlds);
    f->worlds = pose_worlds(f->model, &f->model->clips[0], 0.5f); /* swayed */
    draw(f, SINEW_SKINNING_GPU);
    uint8_t *gpu = malloc(sizeof f->pixels);
    memcpy(gpu, f->pixels, sizeof f->pixels);
    draw(f, SINEW_SKINNING_CPU);
    long differ = differing_pixels(gpu, f->pixels, W * H, NULL);
    print_message("GPU and CPU skinning: %ld of %d pixels differ\n", differ, W * H);
    assert_true(differ <= W * H / 200);
    free(gpu);
}

static void test_bad_frames(void **state)
{
    fixture *f = *state;
    if (!f)
        skip();
    sinew_camera camera = sinew_camera_default();
    sinew_render_options o = sinew_render_options_default();
    sinew_error error = {0};
    sinew_frame frame = {.worlds = f->worlds,
                         .world_count = f->model->node_count - 1, /* one short */
                         .camera = &camera,
                         .width = W,
                         .height = H,
                         .options = &o};
    assert_int_equal(sinew_renderer_draw(f->renderer, &frame, &error), SINEW_ERROR_INVALID_ARGUMENT);
    assert_true(error.message[0] != '\0');
    frame.world_count = f->model->node_count;
    frame.camera = NULL;
    assert_int_equal(sinew_renderer_draw(f->renderer, &frame, &error), SINEW_ERROR_INVALID_ARGUMENT);
    assert_int_equal(sinew_renderer_create(&(sinew_renderer_desc){.model = NULL}, &(sinew_renderer *){NULL}, &error),
                     SINEW_ERROR_INVALID_ARGUMENT);
}

/* Draws `model` physically shaded into `pixels` (W x H), looking at the box lo..hi from the front. */
static void draw_pbr(sinew_headless *headless, const sinew_model *model, const float lo[3], const float hi[3],
                     uint8_t *pixels)
{
    sinew_error error = {0};
    sinew_renderer *renderer = NULL;
    sinew_headless_bind(headless);
    assert_int_equal(sinew_renderer_create(&(sinew_renderer_desc){.model = model}, &renderer, &error), SINEW_OK);
    assert_int_equal(sinew_renderer_warning_count(renderer), 0);
    sinew_mat4 *worlds = pose_worlds(model, NULL, 0.0f);
    sinew_render_options o = sinew_render_options_default();
    o.shading = SINEW_SHADING_PBR;
    o.hide_grid = true;
    sinew_camera camera = sinew_camera_default();
    camera.pitch = 0.0f;
    sinew_camera_frame(&camera, lo, hi, (float)W / (float)H);
    sinew_frame frame = {
        .worlds = worlds, .world_count = model->node_count, .camera = &camera, .width = W, .height = H, .options = &o};
    assert_int_equal(sinew_renderer_draw(renderer, &frame, &error), SINEW_OK);
    assert_int_equal(sinew_headless_read(headless, pixels, &error), SINEW_OK);
    free(worlds);
    sinew_renderer_free(renderer);
}

/* Pixels where some channel differs by more than 24 levels. */
static int differing(const uint8_t *a, const uint8_t *b)
{
    int n = 0;
    for (int i = 0; i < W * H; i++) {
        int most = 0;
        for (int c = 0; c < 3; c++) {
            int d = abs((int)a[i * 4 + c] - (int)b[i * 4 + c]);
            most = d > most ? d : most;
        }
        n += most > 24;
    }
    return n;
}

/* pbr_spheres.glb's "bumps" sphere carries glTF tangents (w = +1: bitangent up the image,
 * where normal maps put +Y). Drawn with them, and again with them removed (the shader then
 * builds the frame from the UVs' derivatives, which cannot get the handedness wrong), the
 * pictures nearly agree (the derivative frame is coarser at this size, and the studio
 * environment's softboxes, reflected, show every small turn of the normal); with the handedness
 * turned, or without the normal map, they clearly do not (2.5 times as many pixels or more). */
static void test_normal_map_frames_agree(void **state)
{
    fixture *f = *state;
    if (!f)
        skip();
    char path[1024];
    sinew_model *model = load_or_fail(fixture_path("pbr_spheres.glb", path, sizeof path));
    assert_non_null(model->meshes[2].tangents);
    assert_non_null(model->materials[2].maps[SINEW_MAP_NORMAL].image);
    static uint8_t with[W * H * 4], derived[W * H * 4], flat[W * H * 4];
    const float lo[3] = {0.1f, -1.0f, -1.0f}, hi[3] = {2.1f, 1.0f, 1.0f};
    draw_pbr(f->headless, model, lo, hi, with);

    sinew_mesh meshes[4];
    sinew_material materials[4];
    memcpy(meshes, model->meshes, sizeof meshes);
    memcpy(materials, model->materials, sizeof materials);
    sinew_model copy = *model;
    copy.meshes = meshes;
    copy.materials = materials;
    meshes[2].tangents = NULL;
    draw_pbr(f->headless, &copy, lo, hi, derived);
    meshes[2].tangents = model->meshes[2].tangents;
    materials[2].maps[SINEW_MAP_NORMAL] = (sinew_texture){0};
    draw_pbr(f->headless, &copy, lo, hi, flat);

    /* and with the handedness turned (what reading glTF's bitangent as pointing down the image gives) */
    uint32_t nv = model->meshes[2].vertex_count;
    float *turned = malloc((size_t)nv * 16);
    memcpy(turned, model->meshes[2].tangents, (size_t)nv * 16);
    for (uint32_t v = 0; v < nv; v++)
        turned[v * 4 + 3] = -turned[v * 4 + 3];
    meshes[2].tangents = turned;
    materials[2] = model->materials[2];
    static uint8_t wrong[W * H * 4];
    draw_pbr(f->headless, &copy, lo, hi, wrong);
    free(turned);

    int frames = differing(with, derived), bumps = differing(with, flat), handedness = differing(wrong, derived);
    printf("normal map (%d pixels differ by > 24 levels): vertex tangents vs derivative frame %d; the same with "
           "the handedness turned %d; with vs without the map %d\n",
           W * H, frames, handedness, bumps);
    assert_true(bumps > 400);
    assert_true(frames * 5 < bumps * 2);
    assert_true(frames * 5 < handedness * 2);
    sinew_model_free(model);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_draw_and_read_back),         cmocka_unit_test(test_zeroed_options_are_the_defaults),
        cmocka_unit_test(test_cpu_and_gpu_skinning_agree), cmocka_unit_test(test_bad_frames),
        cmocka_unit_test(test_normal_map_frames_agree),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
