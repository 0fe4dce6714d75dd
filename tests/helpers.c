#include "helpers.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <fcntl.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

static const char *env_path(const char *var, const char *rel, char *buf, size_t size)
{
    const char *dir = getenv(var);
    if (!dir)
        return NULL;
    snprintf(buf, size, "%s/%s", dir, rel);
    return buf;
}

const char *testdata_path(const char *rel, char *buf, size_t size)
{
    struct stat st;
    const char *p = env_path("SINEW_TESTDATA", rel, buf, size);
    if (!p || stat(p, &st) != 0) {
        print_message("skipping: shared test data not found (%s); set SINEW_TESTDATA to ../shared/testdata\n", rel);
        return NULL;
    }
    return p;
}

const char *fixture_path(const char *rel, char *buf, size_t size)
{
    const char *p = env_path("SINEW_FIXTURES", rel, buf, size);
    assert_non_null(p);
    return p;
}

const char *tmp_path(const char *name, char *buf, size_t size)
{
    const char *dir = getenv("SINEW_TMP");
    if (!dir)
        dir = "/tmp/sinew-tests";
    mkdir(dir, 0755);
    snprintf(buf, size, "%s/%s", dir, name);
    return buf;
}

sinew_model *load_or_fail(const char *path)
{
    sinew_model *model = NULL;
    sinew_error error = {0};
    sinew_import_desc desc = {.path = path};
    if (sinew_import(&desc, &model, &error) != SINEW_OK)
        fail_msg("import of %s failed: %s", path, error.message);
    return model;
}

void write_file(const char *path, const void *bytes, size_t size)
{
    FILE *f = fopen(path, "wb");
    assert_non_null(f);
    if (size)
        assert_int_equal(fwrite(bytes, 1, size, f), size);
    assert_int_equal(fclose(f), 0);
}

void *read_file(const char *path, size_t *size)
{
    FILE *f = fopen(path, "rb");
    if (!f)
        return NULL;
    fseek(f, 0, SEEK_END);
    long n = ftell(f);
    fseek(f, 0, SEEK_SET);
    char *buf = malloc((size_t)n + 1);
    assert_non_null(buf);
    assert_int_equal(fread(buf, 1, (size_t)n, f), (size_t)n);
    buf[n] = '\0';
    fclose(f);
    *size = (size_t)n;
    return buf;
}

void assert_near(double a, double b, double tol, const char *what)
{
    if (!(fabs(a - b) <= tol))
        fail_msg("%s: %.9g differs from %.9g by more than %g", what, a, b, tol);
}

double worlds_difference(const sinew_mat4 *a, const sinew_mat4 *b, uint32_t n)
{
    double worst = 0.0;
    for (uint32_t i = 0; i < n; i++)
        for (int k = 0; k < 16; k++)
            worst = fmax(worst, fabs(a[i].m[k] - b[i].m[k]));
    return worst;
}

double floats_difference(const float *a, const float *b, size_t n)
{
    double worst = 0.0;
    for (size_t i = 0; i < n; i++)
        worst = fmax(worst, fabs((double)a[i] - b[i]));
    return worst;
}

void influences_out_of_order(const sinew_mesh *mesh, uint16_t **joints, float **weights)
{
    uint32_t k = mesh->influence_count, n = mesh->vertex_count;
    *joints = malloc((size_t)n * k * sizeof **joints);
    *weights = malloc((size_t)n * k * sizeof **weights);
    assert_true(*joints && *weights);
    for (uint32_t v = 0; v < n; v++) {
        uint32_t from = (uint32_t)(((uint64_t)v * 7919u) % n);
        memcpy(*joints + (size_t)v * k, mesh->joints + (size_t)from * k, k * sizeof **joints);
        memcpy(*weights + (size_t)v * k, mesh->weights + (size_t)from * k, k * sizeof **weights);
    }
}

sinew_model *demo_humanoid(void)
{
    sinew_model *m = NULL;
    sinew_error error = {0};
    if (sinew_demo_humanoid(&m, &error) != SINEW_OK)
        fail_msg("the demo humanoid: %s", error.message);
    return m;
}

double pose_difference(const sinew_transform *a, const sinew_transform *b, uint32_t n)
{
    double worst = 0.0;
    for (uint32_t i = 0; i < n; i++) {
        double dot = 0.0, same = 0.0, flip = 0.0;
        for (int k = 0; k < 4; k++) {
            dot += a[i].rotation[k] * b[i].rotation[k];
            same = fmax(same, fabs(a[i].rotation[k] - b[i].rotation[k]));
            flip = fmax(flip, fabs(a[i].rotation[k] + b[i].rotation[k]));
        }
        worst = fmax(worst, dot >= 0.0 ? same : flip);
        for (int k = 0; k < 3; k++) {
            worst = fmax(worst, fabs(a[i].translation[k] - b[i].translation[k]) / fmax(1.0, fabs(b[i].translation[k])));
            worst = fmax(worst, fabs(a[i].scale[k] - b[i].scale[k]));
        }
    }
    return worst;
}

sinew_transform *pose_locals(const sinew_model *model, const sinew_clip *clip, float t, sinew_wrap wrap)
{
    uint32_t n = model->node_count;
    sinew_transform *locals = malloc((n + 1) * sizeof *locals);
    assert_non_null(locals);
    sinew_error error = {0};
    sinew_sample_desc desc = {
        .model = model, .clip = clip, .time = t, .wrap = wrap, .locals = locals, .local_count = n};
    if (sinew_sample(&desc, &error))
        fail_msg("sampling %s: %s", model->source, error.message);
    return locals;
}

sinew_mat4 *pose_worlds(const sinew_model *model, const sinew_clip *clip, float t)
{
    uint32_t n = model->node_count;
    sinew_transform *locals = pose_locals(model, clip, t, SINEW_WRAP_CLAMP);
    sinew_mat4 *worlds = malloc((n + 1) * sizeof *worlds);
    assert_non_null(worlds);
    sinew_error error = {0};
    if (sinew_local_to_world(model, locals, n, NULL, worlds, n, &error))
        fail_msg("posing %s: %s", model->source, error.message);
    free(locals);
    return worlds;
}

sinew_player *test_player_open(test_player *tp, const sinew_model *model, const sinew_clip *clip)
{
    sinew_error error = {0};
    memset(tp, 0, sizeof *tp);
    sinew_clip_layout_desc desc = {.model = model, .clip = clip};
    if (sinew_clip_layout_create(&desc, &tp->layout, &error) != SINEW_OK)
        fail_msg("layout of %s: %s", model->source, error.message);
    tp->player = test_player_another(tp, &tp->memory);
    return tp->player;
}

sinew_player *test_player_another(const test_player *tp, void **memory)
{
    sinew_error error = {0};
    size_t size = sinew_player_size(tp->layout);
    sinew_player *player = NULL;
    *memory = malloc(size);
    assert_non_null(*memory);
    if (sinew_player_init(*memory, size, tp->layout, &player, &error) != SINEW_OK)
        fail_msg("player: %s", error.message);
    return player;
}

void test_player_close(test_player *tp)
{
    free(tp->memory);
    sinew_clip_layout_free(tp->layout);
    memset(tp, 0, sizeof *tp);
}

float *posed_vertices(const sinew_model *model, const sinew_mat4 *worlds, uint32_t *count)
{
    return posed_vertices_at(model, worlds, NULL, 0.0f, count);
}

float *posed_vertices_at(const sinew_model *model, const sinew_mat4 *worlds, const sinew_clip *clip, float time,
                         uint32_t *count)
{
    size_t total = 0;
    for (uint32_t i = 0; i < model->instance_count; i++)
        total += model->meshes[model->instances[i].mesh].vertex_count;
    float *out = malloc((total + 1) * 3 * sizeof(float));
    size_t scratch_size = sinew_deform_scratch_size(model);
    void *scratch = aligned_alloc(16, (scratch_size + 15) & ~(size_t)15);
    float *weights = malloc((model->morph_channel_count + 1) * sizeof(float));
    assert_non_null(out);
    assert_non_null(scratch);
    assert_non_null(weights);
    sinew_error error = {0};
    if (sinew_sample_weights(model, clip, time, SINEW_WRAP_CLAMP, weights, model->morph_channel_count, &error))
        fail_msg("weights of %s: %s", model->source, error.message);
    float cache_time = clip ? clip->timeline + sinew_clip_time(clip, time, SINEW_WRAP_CLAMP) : 0.0f;
    size_t at = 0;
    for (uint32_t i = 0; i < model->instance_count; i++) {
        if (sinew_deform_instance(&(sinew_deform_desc){.model = model,
                                                       .instance = i,
                                                       .worlds = worlds,
                                                       .world_count = model->node_count,
                                                       .weights = weights,
                                                       .weight_count = model->morph_channel_count,
                                                       .cache_time = cache_time,
                                                       .scratch = scratch,
                                                       .scratch_size = scratch_size,
                                                       .out_positions = out + at * 3},
                                  &error))
            fail_msg("posing %s: %s", model->source, error.message);
        at += model->meshes[model->instances[i].mesh].vertex_count;
    }
    free(weights);
    free(scratch);
    *count = (uint32_t)total;
    return out;
}

run_result run_sinew(const char *const *env, const char *const *args)
{
    const char *exe = getenv("SINEW_EXE");
    assert_non_null(exe);
    char out_path[1024], err_path[1024], name[64];
    snprintf(name, sizeof name, "run-%d.out", (int)getpid());
    tmp_path(name, out_path, sizeof out_path);
    snprintf(name, sizeof name, "run-%d.err", (int)getpid());
    tmp_path(name, err_path, sizeof err_path);
    const char *argv[64] = {exe};
    int n = 1;
    for (; args[n - 1] && n < 63; n++)
        argv[n] = args[n - 1];
    argv[n] = NULL;
    pid_t pid = fork();
    assert_true(pid >= 0);
    if (pid == 0) {
        int o = open(out_path, O_WRONLY | O_CREAT | O_TRUNC, 0644),
            e = open(err_path, O_WRONLY | O_CREAT | O_TRUNC, 0644);
        dup2(o, 1);
        dup2(e, 2);
        for (int i = 0; env && env[i]; i++)
            putenv((char *)env[i]);
        execv(exe, (char *const *)argv);
        _exit(127);
    }
    int status = 0;
    waitpid(pid, &status, 0);
    run_result r = {.code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status)};
    r.out = read_file(out_path, &r.out_size);
    r.err = read_file(err_path, &r.err_size);
    return r;
}

void run_free(run_result *r)
{
    free(r->out);
    free(r->err);
}

long differing_pixels(const unsigned char *a, const unsigned char *b, long pixels, unsigned char *diff)
{
    long count = 0;
    for (long i = 0; i < pixels; i++) {
        int worst = 0;
        for (int c = 0; c < 3; c++) {
            int d = abs(a[i * 3 + c] - b[i * 3 + c]);
            worst = d > worst ? d : worst;
        }
        bool differs = worst > PIXEL_TOLERANCE;
        count += differs;
        if (diff)
            for (int c = 0; c < 3; c++)
                diff[i * 3 + c] = differs ? (c == 0 ? 255 : 0) : (unsigned char)(a[i * 3 + c] / 3);
    }
    return count;
}

double bezier_reference(const double p[4][2], double t)
{
    double lo = 0, hi = 1;
    for (int i = 0; i < 80; i++) {
        double s = (lo + hi) / 2, u = 1 - s;
        if (u * u * u * p[0][0] + 3 * u * u * s * p[1][0] + 3 * u * s * s * p[2][0] + s * s * s * p[3][0] < t)
            lo = s;
        else
            hi = s;
    }
    double s = (lo + hi) / 2, u = 1 - s;
    return u * u * u * p[0][1] + 3 * u * u * s * p[1][1] + 3 * u * s * s * p[2][1] + s * s * s * p[3][1];
}

uint32_t bitangents_along_v(const sinew_mesh *mesh, uint32_t *checked)
{
    uint32_t agree = 0;
    *checked = 0;
    for (uint32_t k = 0; mesh->uvs && mesh->tangents && k + 2 < mesh->index_count; k += 3) {
        const uint32_t *ix = &mesh->indices[k];
        const float *p0 = &mesh->positions[ix[0] * 3], *p1 = &mesh->positions[ix[1] * 3];
        const float *p2 = &mesh->positions[ix[2] * 3];
        const float *u0 = &mesh->uvs[ix[0] * 2], *u1 = &mesh->uvs[ix[1] * 2], *u2 = &mesh->uvs[ix[2] * 2];
        double e1[3], e2[3], du1 = u1[0] - u0[0], dv1 = u1[1] - u0[1], du2 = u2[0] - u0[0], dv2 = u2[1] - u0[1];
        for (int c = 0; c < 3; c++)
            e1[c] = p1[c] - p0[c], e2[c] = p2[c] - p0[c];
        double r = du1 * dv2 - du2 * dv1;
        if (fabs(r) < 1e-12)
            continue;
        double dpdv[3]; /* the surface's direction of increasing v */
        for (int c = 0; c < 3; c++)
            dpdv[c] = (du1 * e2[c] - du2 * e1[c]) / r;
        const float *t = &mesh->tangents[ix[0] * 4], *n = &mesh->normals[ix[0] * 3];
        double b[3] = {n[1] * t[2] - n[2] * t[1], n[2] * t[0] - n[0] * t[2], n[0] * t[1] - n[1] * t[0]};
        double along = t[3] * (b[0] * dpdv[0] + b[1] * dpdv[1] + b[2] * dpdv[2]);
        if (fabs(along) < 1e-6)
            continue; /* perpendicular: a sphere's poles */
        (*checked)++;
        agree += along > 0.0;
    }
    return agree;
}
