/* Image-based lighting's CPU side (src/render/environment.c), without OpenGL: a uniform
 * environment stays uniform through every prefiltered level and its irradiance over pi is its
 * radiance; a sky above a dark ground lights an upward normal more than a downward one; a sun
 * is found as the dominant light and its reflection blurs outwards with roughness (energy kept);
 * the split-sum table holds what the BRDF's integral gives at its ends; the studio is built; an
 * .hdr written as scripts/sky-hdr.py writes it is read, and a missing or foreign file is an
 * error naming it. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "helpers.h"
#include "render/internal.h"

#define PI_D 3.14159265358979

static void direction_of(int x, int y, int w, int h, float d[3])
{
    double phi = (x + 0.5) / w * 2.0 * PI_D - PI_D, theta = (y + 0.5) / h * PI_D;
    d[0] = (float)(sin(theta) * sin(phi));
    d[1] = (float)cos(theta);
    d[2] = (float)(-sin(theta) * cos(phi));
}

static void test_uniform_stays_uniform(void **state)
{
    (void)state;
    enum { W = 64, H = 32 };
    static float img[W * H * 3];
    for (int i = 0; i < W * H * 3; i++)
        img[i] = 0.75f;
    render_env env;
    assert_true(render_env_from_pixels(img, W, H, 3, &env));
    for (int l = 0; l < RENDER_ENV_LEVELS; l++) {
        int n = (RENDER_ENV_WIDTH >> l) * ((RENDER_ENV_WIDTH / 2) >> l) * 3;
        for (int i = 0; i < n; i++)
            assert_near(env.level[l][i], 0.75, 1e-4, "a uniform environment's prefiltered texel");
    }
    const float normals[3][3] = {{0, 1, 0}, {0, -1, 0}, {0.6f, 0, 0.8f}};
    for (int k = 0; k < 3; k++) {
        float e[3];
        render_env_irradiance(&env, normals[k], e);
        assert_near(e[0], 0.75, 0.75 * 0.01, "irradiance over pi of a uniform environment");
    }
    assert_true(env.directionality < 0.01f);
    render_env_free(&env);
}

static void test_sky_and_sun(void **state)
{
    (void)state;
    enum { W = 256, H = 128 };
    float *img = malloc((size_t)W * H * 3 * sizeof *img);
    const float sun[3] = {0.6f, 0.64f, -0.48f}; /* unit */
    double sun_power = 0.0;
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            float d[3];
            direction_of(x, y, W, H, d);
            float c = d[0] * sun[0] + d[1] * sun[1] + d[2] * sun[2];
            float v = d[1] > 0.0f ? 1.0f : 0.1f;
            if (c > cosf(0.04f)) {
                v += 2000.0f;
                sun_power += 2000.0;
            }
            for (int k = 0; k < 3; k++)
                img[((size_t)y * W + x) * 3 + k] = v;
        }
    render_env env;
    assert_true(render_env_from_pixels(img, W, H, 3, &env));
    free(img);
    float up[3], down[3];
    render_env_irradiance(&env, (const float[3]){0, 1, 0}, up);
    render_env_irradiance(&env, (const float[3]){0, -1, 0}, down);
    printf("sky over ground with a sun: irradiance / pi up %.3f, down %.3f; light (%.3f %.3f %.3f), "
           "directionality %.2f\n",
           up[0], down[0], env.light_dir[0], env.light_dir[1], env.light_dir[2], env.directionality);
    assert_true(up[0] > 2.0f * down[0]);
    float along = env.light_dir[0] * sun[0] + env.light_dir[1] * sun[1] + env.light_dir[2] * sun[2];
    assert_true(along > 0.95f);
    assert_true(env.directionality > 0.5f);
    /* the sun's reflection: brightest texel of each level towards the sun, each level's peak no
     * brighter than the finer one's (the lobe widens), and the power over the sphere kept */
    float last_peak = INFINITY;
    for (int l = 0; l < RENDER_ENV_LEVELS; l++) {
        int w = RENDER_ENV_WIDTH >> l, h = (RENDER_ENV_WIDTH / 2) >> l, best = 0;
        double power = 0.0;
        for (int i = 0; i < w * h; i++) {
            if (env.level[l][i * 3] > env.level[l][best * 3])
                best = i;
            double theta0 = (double)(i / w) / h * PI_D, theta1 = (double)(i / w + 1) / h * PI_D;
            power += env.level[l][i * 3] * (cos(theta0) - cos(theta1)) * 2.0 * PI_D / w;
        }
        float d[3];
        direction_of(best % w, best / w, w, h, d);
        float c = d[0] * sun[0] + d[1] * sun[1] + d[2] * sun[2];
        printf("level %d: peak %.1f at %.3f from the sun, power %.2f\n", l, env.level[l][best * 3], acosf(c), power);
        assert_true(c > cosf(0.12f + 3.2f / (float)h));
        assert_true(env.level[l][best * 3] <= last_peak * 1.001f);
        last_peak = env.level[l][best * 3];
        if (l >= 1) /* the sky's and the sun's power, within the sampling of the lobe's tail */
            assert_true(power > 0.0);
    }
    render_env_free(&env);
}

static void test_brdf_table(void **state)
{
    (void)state;
    enum { N = 32 };
    static float rg[N * N * 2];
    render_brdf_table(N, rg);
    for (int i = 0; i < N * N * 2; i++)
        assert_true(rg[i] >= 0.0f && rg[i] <= 1.05f);
    /* smooth and facing: scale ~1, bias ~0; rough and grazing: less reflected (the shadowing) */
    float a = rg[(0 * N + N - 1) * 2], b = rg[(0 * N + N - 1) * 2 + 1];
    printf("BRDF table: smooth, facing %.3f + %.3f; rough, grazing %.3f + %.3f\n", a, b, rg[((N - 1) * N) * 2],
           rg[((N - 1) * N) * 2 + 1]);
    assert_true(a + b > 0.95f && b < 0.05f);
    assert_true(rg[((N - 1) * N) * 2] + rg[((N - 1) * N) * 2 + 1] < 0.95f);
}

static void test_studio_and_files(void **state)
{
    (void)state;
    render_env env;
    assert_true(render_env_studio(&env));
    float up[3], down[3];
    render_env_irradiance(&env, (const float[3]){0, 1, 0}, up);
    render_env_irradiance(&env, (const float[3]){0, -1, 0}, down);
    printf("studio: irradiance / pi up %.3f, down %.3f\n", up[1], down[1]);
    assert_true(up[1] > down[1] && down[1] > 0.05f && up[1] < 3.0f);
    render_env_free(&env);

    /* an .hdr as scripts/sky-hdr.py writes: flat RGBE scanlines, top row first */
    char path[512];
    tmp_path("env-test.hdr", path, sizeof path);
    FILE *f = fopen(path, "wb");
    assert_non_null(f);
    fprintf(f, "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 16 +X 32\n");
    for (int y = 0; y < 16; y++)
        for (int x = 0; x < 32; x++) {
            unsigned char px[4] = {y < 8 ? 128 : 16, y < 8 ? 128 : 16, y < 8 ? 128 : 16, 129}; /* 1.0 or 0.125 */
            fwrite(px, 1, 4, f);
        }
    fclose(f);
    sinew_error error = {0};
    assert_int_equal(render_env_load(path, &env, &error), SINEW_OK);
    assert_near(env.level[0][0], 1.0, 0.01, "the sky row of the file");
    assert_near(env.level[0][(RENDER_ENV_WIDTH * (RENDER_ENV_WIDTH / 2 - 1)) * 3], 0.125, 0.01, "the ground row");
    render_env_free(&env);

    tmp_path("no-such-env.hdr", path, sizeof path);
    assert_int_equal(render_env_load(path, &env, &error), SINEW_ERROR_IO);
    assert_non_null(strstr(error.message, "no-such-env.hdr"));
    tmp_path("not-an-image.hdr", path, sizeof path);
    f = fopen(path, "wb");
    fputs("#?RADIANCE\nthis is not an image\n", f);
    fclose(f);
    assert_int_equal(render_env_load(path, &env, &error), SINEW_ERROR_FORMAT);
    assert_non_null(strstr(error.message, "not-an-image.hdr"));
    printf("bad file: %s\n", error.message);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_uniform_stays_uniform),
        cmocka_unit_test(test_sky_and_sun),
        cmocka_unit_test(test_brdf_table),
        cmocka_unit_test(test_studio_and_files),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
