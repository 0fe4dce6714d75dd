/* Image-based lighting on the CPU: an equirectangular HDR environment (a file, or the built-in
 * studio) prefiltered for physically based shading.
 *
 * Index: directions of texels - the raw pyramid (box-filtered halvings) - specular levels (the
 * GGX lobe of each level's roughness, integrated exactly over the texels of a finer raw level)
 * - diffuse irradiance (9 spherical-harmonic coefficients, cosine-convolved) - the dominant
 * light (shadows) - the split-sum BRDF table - the studio - reading an .hdr.
 *
 * Conventions: Y up; a direction d maps to u = 0.5 + atan2(d.x, -d.z) / 2pi, v = acos(d.y) / pi
 * (row 0 on top), so the image's centre lies along -Z, behind a model seen from the default
 * camera. The shaders (shaders.c) use the same mapping.
 */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <stb_image.h>

#include "internal.h"

#define PI_F 3.14159265358979f

/* The unit direction through the centre of texel (x, y) of a w x h equirectangular image. */
static void texel_direction(int x, int y, int w, int h, float d[3])
{
    float phi = ((float)x + 0.5f) / (float)w * 2.0f * PI_F - PI_F; /* atan2(d.x, -d.z) */
    float theta = ((float)y + 0.5f) / (float)h * PI_F;             /* acos(d.y) */
    d[0] = sinf(theta) * sinf(phi);
    d[1] = cosf(theta);
    d[2] = -sinf(theta) * cosf(phi);
}

/* Solid angle of a texel in row y. */
static float texel_solid_angle(int y, int w, int h)
{
    float t0 = (float)y / (float)h * PI_F, t1 = (float)(y + 1) / (float)h * PI_F;
    return (cosf(t0) - cosf(t1)) * 2.0f * PI_F / (float)w;
}

void render_env_free(render_env *env)
{
    free(env->memory);
    memset(env, 0, sizeof *env);
}

/* Halves a w x h RGB image (w, h even) into out, each texel the mean of four. */
static void halve(const float *in, int w, int h, float *out)
{
    for (int y = 0; y < h / 2; y++)
        for (int x = 0; x < w / 2; x++)
            for (int c = 0; c < 3; c++) {
                const float *p = in + ((size_t)(2 * y) * (size_t)w + (size_t)(2 * x)) * 3 + c;
                out[((size_t)y * (size_t)(w / 2) + (size_t)x) * 3 + c] =
                    0.25f * (p[0] + p[3] + p[(size_t)w * 3] + p[(size_t)w * 3 + 3]);
            }
}

/* Resamples any equirectangular image to RENDER_ENV_WIDTH x RENDER_ENV_WIDTH/2 by averaging the
 * source texels that fall in each target texel (nearest when the source is smaller). */
static void resample(const float *in, int w, int h, int channels, float *out)
{
    int W = RENDER_ENV_WIDTH, H = RENDER_ENV_WIDTH / 2;
    for (int y = 0; y < H; y++) {
        int y0 = y * h / H, y1 = (y + 1) * h / H;
        if (y1 <= y0)
            y1 = y0 + 1;
        for (int x = 0; x < W; x++) {
            int x0 = x * w / W, x1 = (x + 1) * w / W;
            if (x1 <= x0)
                x1 = x0 + 1;
            double sum[3] = {0, 0, 0};
            for (int sy = y0; sy < y1; sy++)
                for (int sx = x0; sx < x1; sx++)
                    for (int c = 0; c < 3; c++) {
                        float v = in[((size_t)sy * (size_t)w + (size_t)sx) * (size_t)channels +
                                     (size_t)(channels >= 3 ? c : 0)];
                        sum[c] += isfinite(v) && v > 0.0f ? (v < 65000.0f ? v : 65000.0f) : 0.0f;
                    }
            double n = (double)(y1 - y0) * (double)(x1 - x0);
            for (int c = 0; c < 3; c++)
                out[((size_t)y * (size_t)W + (size_t)x) * 3 + c] = (float)(sum[c] / n);
        }
    }
}

/* GGX distribution of the half vector between a direction and the lobe's axis, for the split-sum's
 * n = v = r assumption, times the cosine of the sample (as the usual importance-sampled prefilter
 * weighs it). `cos_angle`: between the sample and the axis. */
static float lobe_weight(float cos_angle, float alpha)
{
    if (cos_angle <= 0.0f)
        return 0.0f;
    float cos_h2 = 0.5f * (1.0f + cos_angle); /* cos^2 of half the angle */
    float a2 = alpha * alpha;
    float q = cos_h2 * (a2 - 1.0f) + 1.0f;
    return a2 / (q * q) * cos_angle;
}

/* One specular level: each texel of an ow x oh image the GGX-weighted mean of the source texels
 * (sw x sh, with their directions and solid angles) within the lobe's reach. */
static void prefilter_level(const float *src, const float *src_dirs, const float *src_omega, int sw, int sh,
                            float alpha, float *out, int ow, int oh)
{
    /* the lobe reaches where its weight falls under 1e-4 of its peak: GGX's tail, about 11 alpha
     * for the half-angle's 1e-3 scaled by the texel size */
    float reach = 22.0f * alpha + 2.0f * PI_F / (float)sh;
    if (reach > PI_F)
        reach = PI_F;
    float cos_reach = cosf(reach);
    for (int y = 0; y < oh; y++) {
        float theta = ((float)y + 0.5f) / (float)oh * PI_F;
        int r0 = (int)floorf((theta - reach) / PI_F * (float)sh), r1 = (int)ceilf((theta + reach) / PI_F * (float)sh);
        if (r0 < 0)
            r0 = 0;
        if (r1 > sh)
            r1 = sh;
        for (int x = 0; x < ow; x++) {
            float d[3];
            texel_direction(x, y, ow, oh, d);
            double sum[3] = {0, 0, 0}, weight = 0.0;
            for (int sy = r0; sy < r1; sy++) {
                const float *dirs = src_dirs + (size_t)sy * (size_t)sw * 3;
                const float *pix = src + (size_t)sy * (size_t)sw * 3;
                float omega = src_omega[sy];
                for (int sx = 0; sx < sw; sx++) {
                    float c = d[0] * dirs[sx * 3] + d[1] * dirs[sx * 3 + 1] + d[2] * dirs[sx * 3 + 2];
                    if (c < cos_reach)
                        continue;
                    float wgt = lobe_weight(c, alpha) * omega;
                    sum[0] += wgt * pix[sx * 3];
                    sum[1] += wgt * pix[sx * 3 + 1];
                    sum[2] += wgt * pix[sx * 3 + 2];
                    weight += wgt;
                }
            }
            float *o = out + ((size_t)y * (size_t)ow + (size_t)x) * 3;
            for (int c = 0; c < 3; c++)
                o[c] = weight > 0.0 ? (float)(sum[c] / weight) : 0.0f;
        }
    }
}

/* The real spherical harmonics of bands 0..2 at a unit direction. */
static void sh9(const float d[3], float y[9])
{
    y[0] = 0.282095f;
    y[1] = 0.488603f * d[1];
    y[2] = 0.488603f * d[2];
    y[3] = 0.488603f * d[0];
    y[4] = 1.092548f * d[0] * d[1];
    y[5] = 1.092548f * d[1] * d[2];
    y[6] = 0.315392f * (3.0f * d[2] * d[2] - 1.0f);
    y[7] = 1.092548f * d[0] * d[2];
    y[8] = 0.546274f * (d[0] * d[0] - d[1] * d[1]);
}

void render_env_irradiance(const render_env *env, const float n[3], float out[3])
{
    float y[9];
    sh9(n, y);
    for (int c = 0; c < 3; c++) {
        out[c] = 0.0f;
        for (int k = 0; k < 9; k++)
            out[c] += env->sh[k][c] * y[k];
    }
}

/* Projects the radiance onto bands 0..2 and convolves with the clamped cosine (Ramamoorthi and
 * Hanrahan), divided by pi: evaluated at a normal, the result times the albedo is the diffuse
 * radiance leaving a Lambertian surface. The first band's direction is the dominant light's. */
static void project_sh(render_env *env, const float *img, const float *dirs, const float *omega, int w, int h)
{
    static const float BAND[9] = {1.0f, 2.0f / 3.0f, 2.0f / 3.0f, 2.0f / 3.0f, 0.25f, 0.25f, 0.25f, 0.25f, 0.25f};
    double acc[9][3] = {{0}};
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) {
            size_t i = (size_t)y * (size_t)w + (size_t)x;
            float coeff[9];
            sh9(dirs + i * 3, coeff);
            for (int k = 0; k < 9; k++)
                for (int c = 0; c < 3; c++)
                    acc[k][c] += (double)img[i * 3 + c] * coeff[k] * omega[y];
        }
    for (int k = 0; k < 9; k++)
        for (int c = 0; c < 3; c++)
            env->sh[k][c] = (float)(acc[k][c] * BAND[k]);
    /* luminance of band 1 (y, z, x order) points to the light */
    float l[3];
    for (int k = 0; k < 3; k++)
        l[k] = 0.2126f * env->sh[1 + k][0] + 0.7152f * env->sh[1 + k][1] + 0.0722f * env->sh[1 + k][2];
    float dir[3] = {l[2], l[0], l[1]};
    float len = sqrtf(dir[0] * dir[0] + dir[1] * dir[1] + dir[2] * dir[2]);
    float l0 = 0.2126f * env->sh[0][0] + 0.7152f * env->sh[0][1] + 0.0722f * env->sh[0][2];
    if (len > 1e-6f) {
        for (int k = 0; k < 3; k++)
            env->light_dir[k] = dir[k] / len;
    } else {
        env->light_dir[0] = env->light_dir[2] = 0.0f;
        env->light_dir[1] = 1.0f;
    }
    /* how directional the light is: 0 for a uniform sphere, towards 1 for one small source
     * (whose band-1 length over band 0 tends to 0.488603 / 0.282095 * 2/3 ~ 1.15) */
    float ratio = l0 > 1e-6f ? len / l0 / 1.155f : 0.0f;
    env->directionality = ratio > 1.0f ? 1.0f : ratio;
}

/* Builds every level from a RENDER_ENV_WIDTH-wide image already in env->level[0]. */
static bool prefilter(render_env *env)
{
    int W = RENDER_ENV_WIDTH, H = W / 2;
    /* raw pyramid: raw[0] is level 0 itself; raw[i] halves raw[i-1] */
    size_t total = 0;
    for (int i = 0; i < RENDER_ENV_LEVELS; i++)
        total += (size_t)(W >> i) * (size_t)(H >> i) * 3;
    size_t dir_floats = (size_t)W * (size_t)H * 3;
    float *scratch = malloc((total + dir_floats + (size_t)H) * sizeof(float));
    if (!scratch)
        return false;
    float *raw[RENDER_ENV_LEVELS];
    raw[0] = env->level[0];
    float *p = scratch;
    for (int i = 1; i < RENDER_ENV_LEVELS; i++) {
        raw[i] = p;
        p += (size_t)(W >> i) * (size_t)(H >> i) * 3;
        halve(raw[i - 1], W >> (i - 1), H >> (i - 1), raw[i]);
    }
    float *dirs = p, *omega = p + dir_floats;
    for (int i = 1; i < RENDER_ENV_LEVELS; i++) {
        /* the source: twice the level's resolution, or level 0 */
        int s = i - 1, sw = W >> s, sh = H >> s;
        for (int y = 0; y < sh; y++) {
            omega[y] = texel_solid_angle(y, sw, sh);
            for (int x = 0; x < sw; x++)
                texel_direction(x, y, sw, sh, dirs + ((size_t)y * (size_t)sw + (size_t)x) * 3);
        }
        float rough = (float)i / (float)(RENDER_ENV_LEVELS - 1);
        prefilter_level(raw[s], dirs, omega, sw, sh, rough * rough, env->level[i], W >> i, H >> i);
        if (i == 2) { /* 64 x 32 texels: enough for the harmonics */
            project_sh(env, raw[s], dirs, omega, sw, sh);
        }
    }
    free(scratch);
    return true;
}

/* Room for every level of the image. */
static bool env_alloc(render_env *env)
{
    int W = RENDER_ENV_WIDTH, H = W / 2;
    size_t total = 0;
    for (int i = 0; i < RENDER_ENV_LEVELS; i++)
        total += (size_t)(W >> i) * (size_t)(H >> i) * 3;
    env->memory = malloc(total * sizeof(float));
    if (!env->memory)
        return false;
    float *p = env->memory;
    for (int i = 0; i < RENDER_ENV_LEVELS; i++) {
        env->level[i] = p;
        p += (size_t)(W >> i) * (size_t)(H >> i) * 3;
    }
    return true;
}

bool render_env_from_pixels(const float *pixels, int width, int height, int channels, render_env *env)
{
    memset(env, 0, sizeof *env);
    if (!env_alloc(env))
        return false;
    resample(pixels, width, height, channels, env->level[0]);
    if (!prefilter(env)) {
        render_env_free(env);
        return false;
    }
    return true;
}

/* A smooth rectangle on the sphere: 1 inside the angular box around (yaw, pitch) of half-sizes
 * (half_yaw, half_pitch), falling off over `soft` radians. */
static float softbox(const float d[3], float yaw, float pitch, float half_yaw, float half_pitch, float soft)
{
    float py = asinf(d[1] < -1.0f ? -1.0f : d[1] > 1.0f ? 1.0f : d[1]);
    float ya = atan2f(d[0], d[2]) - yaw;
    while (ya > PI_F)
        ya -= 2.0f * PI_F;
    while (ya < -PI_F)
        ya += 2.0f * PI_F;
    float ex = fabsf(ya) * cosf(py) - half_yaw, ey = fabsf(py - pitch) - half_pitch;
    float e = ex > ey ? ex : ey;
    if (e <= 0.0f)
        return 1.0f;
    float t = e / soft;
    return t >= 1.0f ? 0.0f : (1.0f - t) * (1.0f - t) * (1.0f + 2.0f * t);
}

bool render_env_studio(render_env *env)
{
    memset(env, 0, sizeof *env);
    if (!env_alloc(env))
        return false;
    int W = RENDER_ENV_WIDTH, H = W / 2;
    /* a neutral grey room: a darker floor, a lighter ceiling, a key softbox above front-left, a
     * rim box behind right and a long fill strip on the right (yaw: from +Z towards +X) */
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            float d[3];
            texel_direction(x, y, W, H, d);
            float t = d[1];
            float base = t >= 0.0f ? 0.45f + 0.30f * sqrtf(t) : 0.45f - 0.33f * sqrtf(-t);
            float rgb[3] = {base * 0.98f, base, base * 1.03f};
            float key = 7.0f * softbox(d, -0.75f, 0.55f, 0.30f, 0.22f, 0.12f);
            float rim = 4.0f * softbox(d, 2.45f, 0.35f, 0.22f, 0.30f, 0.10f);
            float fill = 1.6f * softbox(d, 1.2f, 0.10f, 0.12f, 0.45f, 0.10f);
            float *o = env->level[0] + ((size_t)y * (size_t)W + (size_t)x) * 3;
            o[0] = rgb[0] + key * 1.00f + rim * 0.95f + fill * 0.92f;
            o[1] = rgb[1] + key * 0.98f + rim * 0.97f + fill * 0.96f;
            o[2] = rgb[2] + key * 0.94f + rim * 1.00f + fill * 1.00f;
        }
    if (!prefilter(env)) {
        render_env_free(env);
        return false;
    }
    return true;
}

sinew_result render_env_load(const char *path, render_env *env, sinew_error *error)
{
    int w = 0, h = 0, channels = 0;
    float *pixels = stbi_loadf(path, &w, &h, &channels, 0);
    if (!pixels) {
        FILE *f = fopen(path, "rb");
        if (!f)
            return sinew_fail(error, SINEW_ERROR_IO, "%s: cannot open the environment image: %s", path,
                              strerror(errno));
        fclose(f);
        return sinew_fail(error, SINEW_ERROR_FORMAT, "%s: not an image stb_image reads (%s); expected a Radiance .hdr",
                          path, stbi_failure_reason());
    }
    if (w < 2 || h < 1 || w > 65536 || h > 32768) {
        stbi_image_free(pixels);
        return sinew_fail(error, SINEW_ERROR_FORMAT,
                          "%s: an environment of %dx%d texels; expected an equirectangular image", path, w, h);
    }
    bool ok = render_env_from_pixels(pixels, w, h, channels, env);
    stbi_image_free(pixels);
    if (!ok)
        return sinew_fail(error, SINEW_ERROR_OUT_OF_MEMORY, "%s: out of memory prefiltering the environment", path);
    return SINEW_OK;
}

/* Van der Corput radical inverse in base 2. */
static float radical_inverse(uint32_t bits)
{
    bits = (bits << 16u) | (bits >> 16u);
    bits = ((bits & 0x55555555u) << 1u) | ((bits & 0xAAAAAAAAu) >> 1u);
    bits = ((bits & 0x33333333u) << 2u) | ((bits & 0xCCCCCCCCu) >> 2u);
    bits = ((bits & 0x0F0F0F0Fu) << 4u) | ((bits & 0xF0F0F0F0u) >> 4u);
    bits = ((bits & 0x00FF00FFu) << 8u) | ((bits & 0xFF00FF00u) >> 8u);
    return (float)bits * 2.3283064365386963e-10f;
}

void render_brdf_table(int size, float *rg)
{
    enum { SAMPLES = 256 };
    for (int j = 0; j < size; j++) {
        float rough = ((float)j + 0.5f) / (float)size, alpha = rough * rough, a2 = alpha * alpha;
        for (int i = 0; i < size; i++) {
            float nv = ((float)i + 0.5f) / (float)size;
            float v[3] = {sqrtf(1.0f - nv * nv), 0.0f, nv};
            double a = 0.0, b = 0.0;
            for (uint32_t s = 0; s < SAMPLES; s++) {
                float u1 = (float)s / (float)SAMPLES, u2 = radical_inverse(s);
                /* GGX half vector around +Z */
                float phi = 2.0f * PI_F * u1;
                float cos_t = sqrtf((1.0f - u2) / (1.0f + (a2 - 1.0f) * u2));
                float sin_t = sqrtf(1.0f - cos_t * cos_t);
                float hv[3] = {sin_t * cosf(phi), sin_t * sinf(phi), cos_t};
                float vh = v[0] * hv[0] + v[1] * hv[1] + v[2] * hv[2];
                float lz = 2.0f * vh * hv[2] - v[2];
                if (lz <= 0.0f)
                    continue;
                float nl = lz, nh = hv[2] > 0.0f ? hv[2] : 0.0f;
                vh = vh > 0.0f ? vh : 0.0f;
                /* Smith-GGX height-correlated visibility, times 4 nl vh / nh for the pdf */
                float vis = 0.5f / (nl * sqrtf(nv * nv * (1.0f - a2) + a2) + nv * sqrtf(nl * nl * (1.0f - a2) + a2));
                float g = vis * 4.0f * nl * vh / (nh > 1e-6f ? nh : 1e-6f);
                float fc = powf(1.0f - vh, 5.0f);
                a += (1.0f - fc) * g;
                b += fc * g;
            }
            rg[(j * size + i) * 2] = (float)(a / SAMPLES);
            rg[(j * size + i) * 2 + 1] = (float)(b / SAMPLES);
        }
    }
}
