/* `sinew bench eval`: the runtime's speed per unit, as an engine embedding it sees it.
 *
 * Every figure is the best of 5 batches of 0.02 to 0.2 s each (the machine is shared: the
 * best batch is the one least disturbed), per unit (one character update, one vertex).
 * Threads: sinew's job system (sinew/jobs.h) with 1 .. --threads threads; the work splits in
 * chunks of characters (crowd) or of vertex ranges (skinning). */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "cjson.h"
#include "cli.h"

static int batches = 5;         /* --quick: 1 */
static double unit_scale = 1.0; /* --quick: 0.02 */

/* Best seconds per unit over BATCHES batches of `units` calls of step(context, i). */
typedef void (*step_fn)(void *context, uint32_t i);

static double best_per_unit(step_fn step, void *context, uint32_t units)
{
    double best = 1e30;
    uint32_t i = 0;
    units = (uint32_t)(units * unit_scale) + 1;
    for (uint32_t w = 0; w < units / 4 + 1; w++)
        step(context, i++); /* warm caches and cursors */
    for (int b = 0; b < batches; b++) {
        double start = cli_now_seconds();
        for (uint32_t u = 0; u < units; u++)
            step(context, i++);
        double per = (cli_now_seconds() - start) / units;
        if (per < best)
            best = per;
    }
    return best;
}

/* ---- sampling + world matrices ------------------------------------------------------------ */

typedef struct sample_bench {
    const sinew_model *model;
    sinew_player *player;
    sinew_sample_context *context;
    sinew_transform *locals;
    sinew_mat4 *worlds;
    float times[1024]; /* random seek times */
    bool seek;
} sample_bench;

static void step_player(void *ctx, uint32_t i)
{
    sample_bench *b = ctx;
    float t = b->seek ? b->times[i & 1023] : (float)i * (1.0f / 60.0f);
    sinew_player_update(b->player, t, SINEW_WRAP_LOOP, NULL, b->worlds, b->model->node_count, NULL);
}

static void step_reference(void *ctx, uint32_t i)
{
    sample_bench *b = ctx;
    float t = b->seek ? b->times[i & 1023] : (float)i * (1.0f / 60.0f);
    sinew_sample_desc d = {.model = b->model,
                           .clip = &b->model->clips[0],
                           .time = t,
                           .wrap = SINEW_WRAP_LOOP,
                           .context = b->context,
                           .locals = b->locals,
                           .local_count = b->model->node_count};
    sinew_sample(&d, NULL);
    sinew_local_to_world(b->model, b->locals, b->model->node_count, NULL, b->worlds, b->model->node_count, NULL);
}

static sinew_model *character(uint32_t joints, uint32_t vertices)
{
    sinew_synthetic_desc d = {.joints = joints, .vertices = vertices, .influences = 4, .keyed_trs = true};
    sinew_model *model = NULL;
    sinew_error error = {0};
    if (sinew_synthetic_model(&d, &model, &error) != SINEW_OK)
        cli_error("%s", error.message);
    return model;
}

typedef struct sample_result {
    double forward_us, seek_us, reference_forward_us, reference_seek_us;
} sample_result;

static bool bench_sampling(uint32_t joints, sample_result *out)
{
    sample_bench b = {.model = character(joints, 256)};
    if (!b.model)
        return false;
    const sinew_clip *clip = &b.model->clips[0];
    size_t context_size = sinew_sample_context_size(clip);
    void *context_memory = malloc(context_size);
    b.locals = malloc(b.model->node_count * sizeof *b.locals);
    b.worlds = malloc(b.model->node_count * sizeof *b.worlds);
    app_player player = {0};
    bool ok = context_memory && b.locals && b.worlds && app_player_open(&player, b.model, clip, NULL) == SINEW_OK &&
              sinew_sample_context_init(context_memory, context_size, clip, &b.context, NULL) == SINEW_OK;
    uint32_t seed = 12345;
    for (int i = 0; i < 1024; i++) {
        seed = seed * 1664525u + 1013904223u;
        b.times[i] = clip->duration * (float)(seed >> 8) / 16777216.0f;
    }
    b.player = player.player;
    if (ok) {
        out->forward_us = 1e6 * best_per_unit(step_player, &b, 20000);
        out->reference_forward_us = 1e6 * best_per_unit(step_reference, &b, 5000);
        b.seek = true;
        out->seek_us = 1e6 * best_per_unit(step_player, &b, 20000);
        out->reference_seek_us = 1e6 * best_per_unit(step_reference, &b, 5000);
    }
    app_player_close(&player);
    free(context_memory);
    free(b.locals);
    free(b.worlds);
    sinew_model_free((sinew_model *)b.model);
    return ok;
}

/* ---- blending and IK (sinew/blend.h) ---------------------------------------------------------- */

typedef struct blend_bench {
    const sinew_model *model;
    sinew_transform *poses[4], *out;
    sinew_mat4 *worlds;
    uint32_t layers;
    uint32_t chain[3], aim_joint;
    /* the same poses as structures of arrays (one block: 4 poses, the output, the rest pose) */
    void *soa_memory;
    sinew_soa_pose soa[4], soa_out, soa_rest;
    bool soa_scalar;
    sinew_character *fading, *reaching, *stepping; /* a cross-fade alone; the same with two IK chains */
    void *character_memory[2];
    sinew_clip_layout *layout;
} blend_bench;

static void step_blend(void *ctx, uint32_t i)
{
    blend_bench *b = ctx;
    sinew_blend_layer layers[4];
    for (uint32_t k = 0; k < b->layers; k++)
        layers[k] = (sinew_blend_layer){b->poses[k], 0.25f + 0.1f * (float)((i + k) & 3), NULL};
    sinew_blend_desc d = {.model = b->model,
                          .layers = layers,
                          .layer_count = b->layers,
                          .out = b->out,
                          .out_count = b->model->node_count};
    sinew_blend(&d, NULL);
}

static void step_blend_soa(void *ctx, uint32_t i)
{
    blend_bench *b = ctx;
    sinew_blend_soa_layer layers[4];
    for (uint32_t k = 0; k < b->layers; k++)
        layers[k] = (sinew_blend_soa_layer){&b->soa[k], 0.25f + 0.1f * (float)((i + k) & 3), NULL};
    sinew_blend_soa_desc d = {
        .model = b->model, .rest = &b->soa_rest, .layers = layers, .layer_count = b->layers, .out = &b->soa_out};
    (b->soa_scalar ? sinew_blend_soa_scalar : sinew_blend_soa)(&d, NULL);
}

/* A character in the middle of a long cross-fade (b->stepping): two clips sampled, blended
 * (structures of arrays), world matrices; with two IK chains, the local-transform path and
 * world matrices made three times. */
static void step_character(void *ctx, uint32_t i)
{
    blend_bench *b = ctx;
    (void)i;
    sinew_character_advance(b->stepping, 1.0f / 60.0f, NULL);
    sinew_character_evaluate(b->stepping,
                             &(sinew_character_output){.worlds = b->worlds, .world_count = b->model->node_count}, NULL);
}

/* IK corrects a copy of one pose each time (the copy is part of the cost, 64 x 40 bytes). */
static void step_two_bone(void *ctx, uint32_t i)
{
    blend_bench *b = ctx;
    memcpy(b->out, b->poses[0], b->model->node_count * sizeof *b->out);
    const float *s = b->worlds[b->chain[0]].m + 12;
    sinew_ik_two_bone_desc d = {.model = b->model,
                                .worlds = b->worlds,
                                .locals = b->out,
                                .node_count = b->model->node_count,
                                .start = b->chain[0],
                                .middle = b->chain[1],
                                .end = b->chain[2],
                                .target = {s[0] + 0.1f * (float)(i & 7), s[1] + 0.2f, s[2] + 0.1f},
                                .pole = {s[0], s[1], s[2] + 1.0f},
                                .weight = 1.0f};
    sinew_ik_two_bone(&d, NULL);
}

static void step_aim(void *ctx, uint32_t i)
{
    blend_bench *b = ctx;
    memcpy(b->out, b->poses[0], b->model->node_count * sizeof *b->out);
    const float *p = b->worlds[b->aim_joint].m + 12;
    sinew_ik_aim_desc d = {.model = b->model,
                           .worlds = b->worlds,
                           .locals = b->out,
                           .node_count = b->model->node_count,
                           .joint = b->aim_joint,
                           .forward = {0, 1, 0},
                           .up = {1, 0, 0},
                           .target = {p[0] + 1.0f, p[1] + 0.1f * (float)(i & 7), p[2] + 1.0f},
                           .pole_vector = {0, 1, 0},
                           .weight = 1.0f};
    sinew_ik_aim(&d, NULL);
}

typedef struct blend_result {
    double blend2_us, blend4_us, two_bone_us, aim_us;
    double soa2_us, soa4_us, soa2_scalar_us, soa4_scalar_us, fading_us, reaching_us;
} blend_result;

/* The structure-of-arrays copies of the bench's poses, and characters fading clip 0 into itself
 * (one with IK). */
static bool soa_setup(blend_bench *b)
{
    uint32_t n = b->model->node_count;
    size_t one = sinew_soa_pose_size(n);
    b->soa_memory = malloc(6 * one);
    if (!b->soa_memory)
        return false;
    sinew_soa_pose *all[6] = {&b->soa[0], &b->soa[1], &b->soa[2], &b->soa[3], &b->soa_out, &b->soa_rest};
    bool ok = true;
    for (int k = 0; k < 6; k++)
        ok = ok && sinew_soa_pose_init((char *)b->soa_memory + k * one, one, n, all[k], NULL) == SINEW_OK;
    for (int k = 0; k < 4; k++)
        ok = ok && sinew_soa_pose_from_locals(b->poses[k], n, &b->soa[k], NULL) == SINEW_OK;
    ok = ok && sinew_soa_pose_from_locals(b->model->node_rest, n, &b->soa_rest, NULL) == SINEW_OK;
    ok = ok && sinew_clip_layout_create(&(sinew_clip_layout_desc){.model = b->model, .clip = &b->model->clips[0]},
                                        &b->layout, NULL) == SINEW_OK;
    if (!ok)
        return false;
    sinew_character_layer layers[2] = {{.layout = b->layout, .weight = 1.0f}, {.layout = b->layout}};
    sinew_character_ik chains[2] = {{.end = b->chain[2], .target = {0.1f, 0.2f, 0.3f}},
                                    {.end = b->aim_joint, .target = {-0.1f, 0.2f, 0.3f}}};
    sinew_character **out[2] = {&b->fading, &b->reaching};
    for (int k = 0; k < 2; k++) {
        sinew_character_desc d = {
            .model = b->model, .layers = layers, .layer_count = 2, .ik = chains, .ik_count = k ? 2 : 0};
        size_t size = sinew_character_size(&d);
        b->character_memory[k] = size ? malloc(size) : NULL;
        ok = ok && b->character_memory[k] &&
             sinew_character_init(b->character_memory[k], size, &d, out[k], NULL) == SINEW_OK &&
             sinew_character_advance(*out[k], 0.4f, NULL) == SINEW_OK &&
             sinew_character_play(*out[k], 1, 1e6f, false, NULL) == SINEW_OK &&
             sinew_character_advance(*out[k], 1e5f, NULL) == SINEW_OK;
    }
    return ok;
}

/* Microseconds a 64-joint character: blending 2 and 4 poses, two-bone IK, aim. */
static bool bench_blend(blend_result *out)
{
    blend_bench b = {.model = character(64, 256)};
    if (!b.model)
        return false;
    uint32_t n = b.model->node_count;
    bool ok = true;
    for (int k = 0; k < 4; k++) {
        b.poses[k] = malloc(n * sizeof(sinew_transform));
        sinew_sample_desc d = {.model = b.model,
                               .clip = &b.model->clips[0],
                               .time = 0.3f * (float)k,
                               .wrap = SINEW_WRAP_LOOP,
                               .locals = b.poses[k],
                               .local_count = n};
        ok = ok && b.poses[k] && sinew_sample(&d, NULL) == SINEW_OK;
    }
    b.out = malloc(n * sizeof *b.out);
    b.worlds = malloc(n * sizeof *b.worlds);
    ok = ok && b.out && b.worlds && sinew_local_to_world(b.model, b.poses[0], n, NULL, b.worlds, n, NULL) == SINEW_OK;
    /* a chain down the middle of the generated skeleton (joints follow their parents) */
    uint32_t mid = n / 2;
    b.chain[2] = mid;
    b.chain[1] = (uint32_t)b.model->node_parents[mid];
    b.chain[0] = (uint32_t)b.model->node_parents[b.chain[1]];
    b.aim_joint = n - 1;
    if (ok) {
        b.layers = 2;
        out->blend2_us = 1e6 * best_per_unit(step_blend, &b, 20000);
        b.layers = 4;
        out->blend4_us = 1e6 * best_per_unit(step_blend, &b, 20000);
        out->two_bone_us = 1e6 * best_per_unit(step_two_bone, &b, 50000);
        out->aim_us = 1e6 * best_per_unit(step_aim, &b, 50000);
    }
    ok = ok && soa_setup(&b);
    if (ok) {
        for (int scalar = 0; scalar < 2; scalar++) {
            b.soa_scalar = scalar;
            b.layers = 2;
            (scalar ? &out->soa2_scalar_us : &out->soa2_us)[0] = 1e6 * best_per_unit(step_blend_soa, &b, 50000);
            b.layers = 4;
            (scalar ? &out->soa4_scalar_us : &out->soa4_us)[0] = 1e6 * best_per_unit(step_blend_soa, &b, 50000);
        }
        b.stepping = b.fading;
        out->fading_us = 1e6 * best_per_unit(step_character, &b, 20000);
        b.stepping = b.reaching;
        out->reaching_us = 1e6 * best_per_unit(step_character, &b, 20000);
    }
    free(b.soa_memory);
    free(b.character_memory[0]);
    free(b.character_memory[1]);
    sinew_clip_layout_free(b.layout);
    for (int k = 0; k < 4; k++)
        free(b.poses[k]);
    free(b.out);
    free(b.worlds);
    sinew_model_free((sinew_model *)b.model);
    return ok;
}

/* ---- skinning ------------------------------------------------------------------------------- */

typedef struct skin_bench {
    const sinew_mesh *mesh;
    sinew_mat4 *palette;
    uint32_t palette_count;
    sinew_dq_joint *dq_palette;
    float *positions, *normals;
    bool scalar, positions_only, dqs;
    sinew_jobs *jobs; /* NULL: the calling thread alone */
    uint32_t grain;   /* vertices a job; 0: SKIN_GRAIN */
} skin_bench;

#define SKIN_GRAIN 2048 /* vertices a chunk */

static void skin_range(void *ctx, uint32_t first, uint32_t count, uint32_t thread)
{
    (void)thread;
    skin_bench *b = ctx;
    sinew_skin_desc d = {.mesh = b->mesh,
                         .palette = b->palette,
                         .palette_count = b->palette_count,
                         .first = first,
                         .count = count,
                         .method = b->dqs ? SINEW_SKIN_DUAL_QUATERNION : SINEW_SKIN_LINEAR,
                         .dq_palette = b->dq_palette,
                         .out_positions = b->positions,
                         .out_normals = b->positions_only ? NULL : b->normals};
    (b->scalar ? sinew_skin_vertices_scalar : sinew_skin_vertices)(&d, NULL);
}

static void step_skin(void *ctx, uint32_t i)
{
    (void)i;
    skin_bench *b = ctx;
    sinew_jobs_run(b->jobs, b->mesh->vertex_count, b->grain ? b->grain : SKIN_GRAIN, skin_range, b);
}

#define MAX_BENCH_THREADS 64

/* A job system of `threads` threads for a scaling step (NULL for one: the caller alone). */
static bool open_jobs(uint32_t threads, sinew_jobs **out)
{
    *out = NULL;
    sinew_error error = {0};
    if (threads > 1 && sinew_jobs_create(&(sinew_jobs_desc){.threads = threads}, out, &error) != SINEW_OK) {
        cli_error("bench eval: %s", error.message);
        return false;
    }
    return true;
}

typedef struct skin_result {
    uint32_t vertices;
    double mverts_scalar, mverts_posonly, mverts_dqs, mverts_dqs_scalar;
    double mverts_mixed, mverts_posonly_mixed; /* the influences dealt out of order: no runs of shared joints */
    double mverts[MAX_BENCH_THREADS + 1];      /* by thread count, 1 .. threads */
    /* the memory-bound case: the mesh tiled to LARGE_VERTICES (10x a 32 MiB L3), against a
     * STREAM triad's bandwidth on this machine, by thread count */
    double large_mverts[MAX_BENCH_THREADS + 1], triad_gbps[MAX_BENCH_THREADS + 1];
} skin_result;

static bool bench_large_skinning(skin_bench *small, uint32_t threads, skin_result *out);

static bool bench_skinning(uint32_t threads, skin_result *out)
{
    sinew_model *model = character(64, 50000);
    if (!model)
        return false;
    const sinew_mesh *mesh = &model->meshes[0];
    const sinew_skin *skin = &model->skins[mesh->skin];
    sinew_mat4 *worlds = malloc(model->node_count * sizeof *worlds);
    skin_bench b = {.mesh = mesh,
                    .palette = malloc(skin->joint_count * sizeof(sinew_mat4)),
                    .dq_palette = malloc(skin->joint_count * sizeof(sinew_dq_joint)),
                    .palette_count = skin->joint_count,
                    .positions = malloc((size_t)mesh->vertex_count * 12),
                    .normals = malloc((size_t)mesh->vertex_count * 12)};
    app_player player = {0};
    bool ok =
        worlds && b.palette && b.positions && b.normals &&
        app_player_open(&player, model, &model->clips[0], NULL) == SINEW_OK &&
        sinew_player_update(player.player, 0.5f, SINEW_WRAP_LOOP, NULL, worlds, model->node_count, NULL) == SINEW_OK &&
        sinew_skin_palette(skin, worlds, model->node_count, b.palette, b.palette_count, NULL) == SINEW_OK &&
        b.dq_palette && sinew_skin_dq_palette(b.palette, b.palette_count, b.dq_palette, NULL) == SINEW_OK;
    if (ok) {
        double n = mesh->vertex_count * 1e-6;
        out->vertices = mesh->vertex_count;
        out->mverts[1] = n / best_per_unit(step_skin, &b, 100);
        b.positions_only = true;
        out->mverts_posonly = n / best_per_unit(step_skin, &b, 100);
        b.positions_only = false, b.dqs = true;
        out->mverts_dqs = n / best_per_unit(step_skin, &b, 100);
        b.scalar = true;
        out->mverts_dqs_scalar = n / best_per_unit(step_skin, &b, 20);
        b.dqs = false;
        out->mverts_scalar = n / best_per_unit(step_skin, &b, 20);
        b.scalar = false;
        /* the same mesh with each vertex's influences taken from vertex v * 7919 mod n: no block
         * of 16 shares its joints, as in meshes whose vertices are not in runs (arnaud.fbx) */
        sinew_mesh mixed = *mesh;
        uint32_t k = mesh->influence_count, count = mesh->vertex_count;
        uint16_t *joints = malloc((size_t)count * k * sizeof *joints);
        float *weights = malloc((size_t)count * k * sizeof *weights);
        ok = joints && weights;
        for (uint32_t v = 0; ok && v < count; v++) {
            uint32_t from = (uint32_t)(((uint64_t)v * 7919u) % count);
            memcpy(joints + (size_t)v * k, mesh->joints + (size_t)from * k, k * sizeof *joints);
            memcpy(weights + (size_t)v * k, mesh->weights + (size_t)from * k, k * sizeof *weights);
        }
        if (ok) {
            mixed.joints = joints, mixed.weights = weights;
            b.mesh = &mixed;
            out->mverts_mixed = n / best_per_unit(step_skin, &b, 100);
            b.positions_only = true;
            out->mverts_posonly_mixed = n / best_per_unit(step_skin, &b, 100);
            b.positions_only = false;
            b.mesh = mesh;
        }
        free(joints);
        free(weights);
        for (uint32_t t = 2; ok && t <= threads; t++) {
            ok = open_jobs(t, &b.jobs);
            if (ok)
                out->mverts[t] = n / best_per_unit(step_skin, &b, 100 * t);
            sinew_jobs_free(b.jobs);
            b.jobs = NULL;
        }
        ok = ok && bench_large_skinning(&b, threads, out);
    }
    app_player_close(&player);
    free(worlds);
    free(b.palette);
    free(b.dq_palette);
    free(b.positions);
    free(b.normals);
    sinew_model_free(model);
    return ok;
}

/* ---- skinning at the memory's speed ------------------------------------------------------------ */

/* Ten times the 32 MiB L3 of an EPYC core complex at 72 bytes a vertex (positions and normals
 * in and out, 4 joints and weights): no vertex is in a cache when its turn comes. (This VM says
 * its L3 is 512 MiB: the host's, shared with others.) */
#define LARGE_VERTICES (10u * (32u << 20) / 72u)
#define LARGE_BYTES_A_VERTEX 72.0
#define TRIAD_COUNT ((size_t)16 << 20) /* doubles an array: 3 x 128 MiB */

typedef struct triad_bench {
    double *a, *b, *c;
    sinew_jobs *jobs;
} triad_bench;

static void triad_range(void *ctx, uint32_t first, uint32_t count, uint32_t thread)
{
    (void)thread;
    triad_bench *t = ctx;
    double *restrict a = t->a;
    const double *restrict b = t->b, *restrict c = t->c;
    for (size_t i = first; i < (size_t)first + count; i++)
        a[i] = b[i] + 3.0 * c[i];
}

static void step_triad(void *ctx, uint32_t i)
{
    (void)i;
    triad_bench *t = ctx;
    sinew_jobs_run(t->jobs, (uint32_t)TRIAD_COUNT, 1u << 16, triad_range, t);
}

/* STREAM's triad (a = b + s c, 24 bytes an element as STREAM counts them) with `threads`. */
static bool triad_gbps(uint32_t threads, double *gbps)
{
    triad_bench t = {malloc(TRIAD_COUNT * 8), malloc(TRIAD_COUNT * 8), malloc(TRIAD_COUNT * 8), NULL};
    bool ok = t.a && t.b && t.c && open_jobs(threads, &t.jobs);
    if (ok) {
        for (size_t i = 0; i < TRIAD_COUNT; i++)
            t.a[i] = 0.0, t.b[i] = 1.0, t.c[i] = 2.0;
        *gbps = TRIAD_COUNT * 24.0 / best_per_unit(step_triad, &t, 4) * 1e-9;
    }
    sinew_jobs_free(t.jobs);
    free(t.a);
    free(t.b);
    free(t.c);
    return ok;
}

/* The benchmark mesh tiled to LARGE_VERTICES and skinned with 1 .. threads threads. */
static bool bench_large_skinning(skin_bench *small, uint32_t threads, skin_result *out)
{
    const sinew_mesh *m = small->mesh;
    uint32_t n = LARGE_VERTICES, k = m->influence_count, count = m->vertex_count;
    sinew_mesh large = *m;
    float *positions = malloc((size_t)n * 12), *normals = malloc((size_t)n * 12), *weights = malloc((size_t)n * k * 4);
    uint16_t *joints = malloc((size_t)n * k * 2);
    skin_bench b = *small;
    b.grain = 1u << 15; /* a job's share of a large mesh: 2.3 MiB of vertices */
    b.positions = malloc((size_t)n * 12);
    b.normals = malloc((size_t)n * 12);
    b.jobs = NULL;
    bool ok = positions && normals && weights && joints && b.positions && b.normals;
    for (uint32_t v = 0; ok && v < n; v += count) {
        uint32_t c = n - v < count ? n - v : count;
        memcpy(positions + (size_t)v * 3, m->positions, (size_t)c * 12);
        memcpy(normals + (size_t)v * 3, m->normals, (size_t)c * 12);
        memcpy(weights + (size_t)v * k, m->weights, (size_t)c * k * 4);
        memcpy(joints + (size_t)v * k, m->joints, (size_t)c * k * 2);
    }
    if (ok) {
        memset(b.positions, 0, (size_t)n * 12);
        memset(b.normals, 0, (size_t)n * 12);
        large.vertex_count = n;
        large.positions = positions, large.normals = normals, large.weights = weights, large.joints = joints;
        b.mesh = &large;
    }
    /* the triad and the skinning in turn, three times, the best of each: other tenants' traffic
     * on a shared machine then weighs on both alike */
    for (uint32_t t = 1; ok && t <= threads; t++) {
        ok = open_jobs(t, &b.jobs);
        for (int round = 0; ok && round < 3; round++) {
            double gbps = 0.0, mverts;
            ok = triad_gbps(t, &gbps);
            mverts = n * 1e-6 / best_per_unit(step_skin, &b, 2 * t);
            out->triad_gbps[t] = gbps > out->triad_gbps[t] ? gbps : out->triad_gbps[t];
            out->large_mverts[t] = mverts > out->large_mverts[t] ? mverts : out->large_mverts[t];
        }
        sinew_jobs_free(b.jobs);
        b.jobs = NULL;
    }
    free(positions);
    free(normals);
    free(weights);
    free(joints);
    free(b.positions);
    free(b.normals);
    return ok;
}

/* ---- morph targets -------------------------------------------------------------------------- */

/* A face-sized morph: MORPH_VERTICES vertices, MORPH_TARGETS targets each moving a run of
 * MORPH_SPAN consecutive vertices (regions of a face overlap), MORPH_WEIGHTED of them weighted
 * (as a face rig plays a few shapes at a time). Positions and normals out. */
#define MORPH_VERTICES 50000
#define MORPH_TARGETS 50
#define MORPH_WEIGHTED 5
#define MORPH_SPAN 10000
#define MORPH_GRAIN 4096

typedef struct morph_bench {
    sinew_mesh mesh;
    sinew_morph_target targets[MORPH_TARGETS];
    float weights[MORPH_TARGETS];
    float *positions, *normals;
    bool scalar;
    sinew_jobs *jobs;
    unsigned char *copy_from, *copy_to; /* the bandwidth measure */
} morph_bench;

static void morph_range(void *ctx, uint32_t first, uint32_t count, uint32_t thread)
{
    (void)thread;
    morph_bench *b = ctx;
    sinew_morph_desc d = {.mesh = &b->mesh,
                          .target_weights = b->weights,
                          .first = first,
                          .count = count,
                          .out_positions = b->positions,
                          .out_normals = b->normals};
    (b->scalar ? sinew_morph_vertices_scalar : sinew_morph_vertices)(&d, NULL);
}

static void step_morph(void *ctx, uint32_t i)
{
    (void)i;
    morph_bench *b = ctx;
    sinew_jobs_run(b->jobs, MORPH_VERTICES, MORPH_GRAIN, morph_range, b);
}

#define COPY_BYTES (64u << 20) /* far past the caches */

static void step_copy(void *ctx, uint32_t i)
{
    morph_bench *b = ctx;
    memcpy(b->copy_to, b->copy_from, COPY_BYTES);
    b->copy_to[i % COPY_BYTES] ^= 1;
}

typedef struct morph_result {
    double mverts[MAX_BENCH_THREADS + 1]; /* by thread count */
    double mverts_scalar;
    double bytes_a_vertex; /* read and written, averaged over the mesh */
    double copy_gbps;      /* memcpy of 64 MiB: read + write bytes a second */
} morph_result;

static bool bench_morph(uint32_t threads, morph_result *out)
{
    morph_bench b = {.positions = malloc(MORPH_VERTICES * 12u), .normals = malloc(MORPH_VERTICES * 12u)};
    float *base = malloc(MORPH_VERTICES * 24u), *deltas = malloc((size_t)MORPH_TARGETS * MORPH_SPAN * 24u);
    uint32_t *indices = malloc((size_t)MORPH_TARGETS * MORPH_SPAN * 4u);
    b.copy_from = malloc(COPY_BYTES), b.copy_to = malloc(COPY_BYTES);
    bool ok = b.positions && b.normals && base && deltas && indices && b.copy_from && b.copy_to;
    for (uint32_t v = 0; ok && v < MORPH_VERTICES; v++) {
        float a = (float)v * 0.001f;
        float *p = base + (size_t)v * 3, *n = base + (size_t)MORPH_VERTICES * 3 + (size_t)v * 3;
        p[0] = cosf(a), p[1] = (float)v * 1e-4f, p[2] = sinf(a);
        n[0] = cosf(a), n[1] = 0.0f, n[2] = sinf(a);
    }
    for (uint32_t t = 0; ok && t < MORPH_TARGETS; t++) {
        uint32_t start = (uint32_t)(((uint64_t)t * (MORPH_VERTICES - MORPH_SPAN)) / (MORPH_TARGETS - 1));
        uint32_t *vi = indices + (size_t)t * MORPH_SPAN;
        float *d = deltas + (size_t)t * MORPH_SPAN * 6;
        for (uint32_t k = 0; k < MORPH_SPAN; k++) {
            vi[k] = start + k;
            for (int c = 0; c < 6; c++)
                d[(c < 3 ? 0 : (size_t)MORPH_SPAN * 3) + (size_t)k * 3 + (size_t)(c % 3)] =
                    0.01f * sinf((float)(k * 7 + (uint32_t)c + t));
        }
        b.targets[t] = (sinew_morph_target){.name = "shape",
                                            .channel = t,
                                            .full_weight = 1.0f,
                                            .delta_count = MORPH_SPAN,
                                            .vertices = vi,
                                            .positions = d,
                                            .normals = d + (size_t)MORPH_SPAN * 3};
        b.weights[t] = t % (MORPH_TARGETS / MORPH_WEIGHTED) == 3 ? 0.3f + 0.1f * (float)(t % 4) : 0.0f;
    }
    if (ok) {
        b.mesh = (sinew_mesh){.name = "face",
                              .vertex_count = MORPH_VERTICES,
                              .positions = base,
                              .normals = base + (size_t)MORPH_VERTICES * 3,
                              .target_count = MORPH_TARGETS,
                              .targets = b.targets,
                              .morph_channel_count = MORPH_TARGETS};
        double n = MORPH_VERTICES * 1e-6;
        out->mverts[1] = n / best_per_unit(step_morph, &b, 200);
        b.scalar = true;
        out->mverts_scalar = n / best_per_unit(step_morph, &b, 100);
        b.scalar = false;
        for (uint32_t t = 2; ok && t <= threads; t++) {
            ok = open_jobs(t, &b.jobs);
            if (ok)
                out->mverts[t] = n / best_per_unit(step_morph, &b, 200 * t);
            sinew_jobs_free(b.jobs);
            b.jobs = NULL;
        }
        /* base positions and normals read, results written (24 + 24 bytes a vertex), and each
         * weighted target's index and two offsets (28 bytes a delta) read */
        out->bytes_a_vertex = 48.0 + (double)MORPH_WEIGHTED * MORPH_SPAN * 28.0 / MORPH_VERTICES;
        memset(b.copy_from, 1, COPY_BYTES);
        memset(b.copy_to, 0, COPY_BYTES);
        out->copy_gbps = 2.0 * COPY_BYTES * 1e-9 / best_per_unit(step_copy, &b, 10);
    }
    free(b.positions);
    free(b.normals);
    free(base);
    free(deltas);
    free(indices);
    free(b.copy_from);
    free(b.copy_to);
    return ok;
}

/* ---- a crowd ------------------------------------------------------------------------------- */

#define CROWD 1000
#define CROWD_GRAIN 16 /* characters a chunk */

typedef struct crowd_bench {
    const sinew_model *model;
    sinew_clip_layout *layout; /* one clip, laid out once: every character plays it */
    sinew_player *players[CROWD];
    unsigned char *states; /* CROWD players' memory */
    sinew_mat4 *worlds;    /* node_count a thread: world matrices are scratch */
    sinew_mat4 *palette;   /* joint_count a character: what goes to the GPU */
    float time;
    sinew_jobs *jobs;
} crowd_bench;

static void crowd_range(void *ctx, uint32_t first, uint32_t count, uint32_t thread)
{
    crowd_bench *b = ctx;
    const sinew_skin *skin = &b->model->skins[0];
    uint32_t n = b->model->node_count, j = skin->joint_count;
    sinew_mat4 *worlds = b->worlds + (size_t)thread * n;
    for (uint32_t c = first; c < first + count; c++) {
        sinew_player_update(b->players[c], b->time + (float)c * 0.013f, SINEW_WRAP_LOOP, NULL, worlds, n, NULL);
        sinew_skin_palette(skin, worlds, n, b->palette + (size_t)c * j, j, NULL);
    }
}

static void step_crowd(void *ctx, uint32_t i)
{
    crowd_bench *b = ctx;
    b->time = (float)i / 60.0f;
    sinew_jobs_run(b->jobs, CROWD, CROWD_GRAIN, crowd_range, b);
}

typedef struct crowd_result {
    double ms[MAX_BENCH_THREADS + 1]; /* a frame, by thread count */
} crowd_result;

static bool bench_crowd_eval(uint32_t threads, crowd_result *out)
{
    crowd_bench *b = calloc(1, sizeof *b);
    sinew_model *model = character(64, 256);
    bool ok = b && model;
    if (ok) {
        b->model = model;
        b->worlds = malloc((size_t)threads * model->node_count * sizeof(sinew_mat4));
        b->palette = malloc((size_t)CROWD * model->skins[0].joint_count * sizeof(sinew_mat4));
        ok = b->worlds && b->palette;
        sinew_clip_layout_desc desc = {.model = model, .clip = &model->clips[0]};
        ok = ok && sinew_clip_layout_create(&desc, &b->layout, NULL) == SINEW_OK;
        size_t size = ok ? sinew_player_size(b->layout) : 0;
        ok = ok && (b->states = malloc(size * CROWD));
        for (int c = 0; ok && c < CROWD; c++)
            ok = sinew_player_init(b->states + size * c, size, b->layout, &b->players[c], NULL) == SINEW_OK;
    }
    for (uint32_t t = 1; ok && t <= threads; t++) {
        ok = open_jobs(t, &b->jobs);
        if (ok)
            out->ms[t] = 1e3 * best_per_unit(step_crowd, b, 60 * t);
        sinew_jobs_free(b->jobs);
        b->jobs = NULL;
    }
    if (b) {
        free(b->states);
        sinew_clip_layout_free(b->layout);
        free(b->worlds);
        free(b->palette);
    }
    free(b);
    sinew_model_free(model);
    return ok;
}

/* ---- loading ------------------------------------------------------------------------------- */

typedef struct load_result {
    double sinew_ms, assimp_ms;
    long sinew_bytes, source_bytes;
} load_result;

static long file_size(const char *path)
{
    FILE *f = fopen(path, "rb");
    long n = -1;
    if (f && fseek(f, 0, SEEK_END) == 0)
        n = ftell(f);
    if (f)
        fclose(f);
    return n;
}

/* The best of three imports of `path` in this process (one for --quick), by sinew's own reader
 * for the formats it has one for or by Assimp; `keep` (when not NULL) gets the first model.
 * The file is first imported once in the helper, so that a file that crashes the reader is
 * an error here too, not a dead benchmark. */
static bool time_import(const char *path, bool assimp, double *best_ms, sinew_model **keep)
{
    sinew_error error = {0};
    *best_ms = 1e30;
    sinew_model *probe = NULL;
    sinew_import_desc probe_desc = {.path = path,
                                    .assimp = assimp,
                                    .stderr_fd = STDERR_FILENO,
                                    .timeout = cli_import.timeout,
                                    .memory_limit = cli_import.memory_limit};
    if (sinew_import(&probe_desc, &probe, &error) != SINEW_OK) {
        cli_error("%s%s", assimp ? "(through Assimp) " : "", error.message);
        return false;
    }
    sinew_model_free(probe);
    for (int i = 0; i < (batches > 1 ? 3 : 1); i++) {
        sinew_model *m = NULL;
        sinew_import_desc d = {.path = path, .assimp = assimp};
        double start = cli_now_seconds();
        if (sinew_import(&d, &m, &error) != SINEW_OK) {
            cli_error("%s%s", assimp ? "(through Assimp) " : "", error.message);
            return false;
        }
        double t = (cli_now_seconds() - start) * 1e3;
        *best_ms = t < *best_ms ? t : *best_ms;
        if (keep && i == 0)
            *keep = m;
        else
            sinew_model_free(m);
    }
    return true;
}

static bool bench_load(const char *collada, const char *converted, load_result *out)
{
    sinew_error error = {0};
    double best_assimp, best_sinew = 1e30;
    sinew_model *first = NULL;
    if (!time_import(collada, true, &best_assimp, &first)) {
        /* no Assimp here (its helper not installed, a machine the program was copied to): the
         * .sinew file's load is still timed, from sinew's own reading of the COLLADA file */
        cli_error("bench eval: the load is timed without Assimp's import to compare");
        double own;
        if (!time_import(collada, false, &own, &first))
            return false;
        best_assimp = NAN;
    }
    sinew_result saved = sinew_model_save(first, NULL, converted, &error);
    sinew_model_free(first);
    if (saved != SINEW_OK) {
        cli_error("%s", error.message);
        return false;
    }
    for (int i = 0; i < (batches > 1 ? 50 : 2); i++) {
        sinew_model *m = NULL;
        double start = cli_now_seconds();
        if (sinew_model_load(converted, NULL, &m, &error) != SINEW_OK) {
            cli_error("%s", error.message);
            return false;
        }
        double t = cli_now_seconds() - start;
        best_sinew = t < best_sinew ? t : best_sinew;
        sinew_model_free(m);
    }
    *out = (load_result){best_sinew * 1e3, best_assimp, file_size(converted), file_size(collada)};
    return true;
}

/* Import time of a file sinew reads itself (FBX, glTF, COLLADA) by sinew's reader and by
 * Assimp (parse, evaluation, build). */
typedef struct import_result {
    double sinew_ms, assimp_ms;
    long bytes;
} import_result;

static bool bench_import(const char *path, import_result *out)
{
    out->bytes = file_size(path);
    return time_import(path, false, &out->sinew_ms, NULL) && time_import(path, true, &out->assimp_ms, NULL);
}

/* ---- the command ---------------------------------------------------------------------------- */

static void machine_name(char *out, size_t size)
{
    char model[256] = "unknown processor";
    FILE *f = fopen("/proc/cpuinfo", "r");
    char line[512];
    while (f && fgets(line, sizeof line, f)) {
        if (strncmp(line, "model name", 10) == 0) {
            const char *colon = strchr(line, ':');
            if (colon) {
                snprintf(model, sizeof model, "%s", colon + 2);
                model[strcspn(model, "\n")] = 0;
            }
            break;
        }
    }
    if (f)
        fclose(f);
    snprintf(out, size, "%s, %ld cores, skinning %s", model, sysconf(_SC_NPROCESSORS_ONLN), sinew_simd_name());
}

static const char eval_usage[] =
    "usage: sinew bench eval [--json] [--threads N] [--collada FILE.dae] [--import FILE] [--quick]\n"
    "\n"
    "The runtime's speed per unit (best of 5 batches), against the goals of the evaluation:\n"
    "  sampling + world matrices of one character, 64 and 128 joints, a 2 s clip keyed 30 times a second\n"
    "    on translation, rotation and scale of every joint: forward play at 60 Hz and random seeking\n"
    "    (sinew_player; the reference sinew_sample + sinew_local_to_world beside it);\n"
    "  skinning 50,000 vertices of 4 influences, positions and normals: Mvertices/s on one thread (and\n"
    "    the scalar reference), positions only, dual quaternions, and on 1 .. N threads;\n"
    "  morph targets applied to a 50,000-vertex mesh of 50 targets (each moving 10,000 vertices in a\n"
    "    run), 5 of them weighted, positions and normals (sinew_morph_vertices; the scalar reference\n"
    "    beside it) on 1 .. N threads, against what a memcpy of 64 MiB measured here would allow;\n"
    "  1000 characters of 64 joints updated a frame (sampling, world matrices, skinning palettes) on\n"
    "    1 .. N threads: the speed-up and efficiency (speed-up / threads) at each;\n"
    "  loading a .sinew file against Assimp importing the COLLADA file it came from (in this process):\n"
    "    FILE.dae, or the demo humanoid that `sinew demo` writes (made in a temporary folder); where\n"
    "    Assimp cannot run (no import helper), the .sinew load alone, load_ms_assimp null;\n"
    "  with --import, importing FILE (FBX, glTF or COLLADA) by sinew's own reader against Assimp's (in\n"
    "    this process; --fbx FILE is the same).\n"
    "--threads N: the most threads (sinew's job system; default: the cores this process may use).\n"
    "--quick runs one short batch of each (a smoke test; the figures mean little).\n"
    "--json prints one object with sample_world_us_64, sample_world_us_128, seek_us_64, skin_mverts_1t,\n"
    "skin_mverts_1t_posonly, skin_mverts_dqs_1t, skin_mverts_1t_mixed and skin_mverts_1t_posonly_mixed (the\n"
    "influences out of order: no runs of vertices sharing joints), threads, skin_mverts_nt, crowd1000_speedup_nt,\n"
    "scaling\n"
    "([{threads, crowd_ms, crowd_speedup, crowd_efficiency, skin_mverts, skin_speedup}]), simd,\n"
    "morph_mverts_1t, morph_mverts_scalar_1t, morph_mverts_nt, morph_gbps_1t, memcpy_gbps,\n"
    "morph_mverts_bandwidth_bound, load_speedup_vs_assimp, machine and the other figures (with 2 threads\n"
    "or more also skin_mverts_2t, morph_mverts_2t and crowd1000_speedup_2t)\n"
    "(with --import also import_ms_sinew, import_ms_assimp and import_file).\n";

int bench_eval(int argc, char **argv)
{
    bool json = false;
    const char *collada = NULL, *import = NULL;
    uint32_t threads = sinew_cpu_count();
    for (int i = 1; i < argc; i++) {
        if (cli_is_help(argv[i])) {
            fputs(eval_usage, stdout);
            return EXIT_OK;
        } else if (strcmp(argv[i], "--json") == 0) {
            json = true;
        } else if (strcmp(argv[i], "--threads") == 0) {
            if (!cli_threads_arg(argc, argv, &i, MAX_BENCH_THREADS, &threads))
                return EXIT_USAGE;
        } else if (strcmp(argv[i], "--quick") == 0) {
            batches = 1;
            unit_scale = 0.02;
        } else if (strcmp(argv[i], "--collada") == 0 && i + 1 < argc) {
            collada = argv[++i];
        } else if ((strcmp(argv[i], "--import") == 0 || strcmp(argv[i], "--fbx") == 0) && i + 1 < argc) {
            import = argv[++i];
        } else {
            cli_error("bench eval: unknown option %s\n%s", argv[i], eval_usage);
            return EXIT_USAGE;
        }
    }
    char dir[] = "/tmp/sinew-bench-XXXXXX";
    if (!mkdtemp(dir)) {
        cli_error("bench eval: cannot make a temporary folder in /tmp");
        return EXIT_UNAVAILABLE;
    }
    char demo_dae[512], converted[512];
    snprintf(converted, sizeof converted, "%s/model.sinew", dir);
    if (!collada) {
        if (cli_demo_write(dir, false, true) != EXIT_OK)
            return EXIT_BAD_INPUT;
        snprintf(demo_dae, sizeof demo_dae, "%s/%s", dir, CLI_DEMO_HUMANOID);
        collada = demo_dae;
    }
    sample_result s64 = {0}, s128 = {0};
    skin_result skin = {0};
    crowd_result crowd = {0};
    load_result load = {0};
    import_result import_times = {0};
    blend_result blend = {0};
    morph_result morph = {0};
    bool ok = bench_sampling(64, &s64) && bench_sampling(128, &s128) && bench_blend(&blend) &&
              bench_skinning(threads, &skin) && bench_morph(threads, &morph) && bench_crowd_eval(threads, &crowd) &&
              bench_load(collada, converted, &load) && (!import || bench_import(import, &import_times));
    cli_remove_tree(dir);
    if (!ok)
        return EXIT_BAD_INPUT;

    char machine[384];
    machine_name(machine, sizeof machine);
    double load_speedup = load.assimp_ms / load.sinew_ms;
    if (json) {
        cJSON *o = cJSON_CreateObject();
        cJSON_AddNumberToObject(o, "sample_world_us_64", s64.forward_us);
        cJSON_AddNumberToObject(o, "sample_world_us_128", s128.forward_us);
        cJSON_AddNumberToObject(o, "seek_us_64", s64.seek_us);
        cJSON_AddNumberToObject(o, "seek_us_128", s128.seek_us);
        cJSON_AddNumberToObject(o, "reference_sample_world_us_64", s64.reference_forward_us);
        cJSON_AddNumberToObject(o, "reference_seek_us_64", s64.reference_seek_us);
        cJSON_AddNumberToObject(o, "blend2_us_64", blend.blend2_us);
        cJSON_AddNumberToObject(o, "blend4_us_64", blend.blend4_us);
        cJSON_AddNumberToObject(o, "blend2_soa_us_64", blend.soa2_us);
        cJSON_AddNumberToObject(o, "blend4_soa_us_64", blend.soa4_us);
        cJSON_AddNumberToObject(o, "blend2_soa_scalar_us_64", blend.soa2_scalar_us);
        cJSON_AddNumberToObject(o, "blend4_soa_scalar_us_64", blend.soa4_scalar_us);
        cJSON_AddNumberToObject(o, "character_crossfade_us_64", blend.fading_us);
        cJSON_AddNumberToObject(o, "character_ik_us_64", blend.reaching_us);
        cJSON_AddNumberToObject(o, "ik_two_bone_us_64", blend.two_bone_us);
        cJSON_AddNumberToObject(o, "ik_aim_us_64", blend.aim_us);
        cJSON_AddNumberToObject(o, "skin_vertices", skin.vertices);
        cJSON_AddNumberToObject(o, "skin_mverts_1t", skin.mverts[1]);
        cJSON_AddNumberToObject(o, "skin_mverts_scalar_1t", skin.mverts_scalar);
        cJSON_AddNumberToObject(o, "skin_mverts_1t_posonly", skin.mverts_posonly);
        cJSON_AddNumberToObject(o, "skin_mverts_1t_mixed", skin.mverts_mixed);
        cJSON_AddNumberToObject(o, "skin_mverts_1t_posonly_mixed", skin.mverts_posonly_mixed);
        cJSON_AddNumberToObject(o, "skin_large_vertices", LARGE_VERTICES);
        cJSON_AddNumberToObject(o, "skin_large_mverts_1t", skin.large_mverts[1]);
        cJSON_AddNumberToObject(o, "triad_gbps_1t", skin.triad_gbps[1]);
        cJSON_AddNumberToObject(o, "skin_mverts_dqs_1t", skin.mverts_dqs);
        cJSON_AddNumberToObject(o, "skin_mverts_dqs_scalar_1t", skin.mverts_dqs_scalar);
        cJSON_AddNumberToObject(o, "morph_vertices", MORPH_VERTICES);
        cJSON_AddNumberToObject(o, "morph_targets", MORPH_TARGETS);
        cJSON_AddNumberToObject(o, "morph_weighted", MORPH_WEIGHTED);
        cJSON_AddNumberToObject(o, "morph_mverts_1t", morph.mverts[1]);
        cJSON_AddNumberToObject(o, "morph_mverts_scalar_1t", morph.mverts_scalar);
        cJSON_AddNumberToObject(o, "morph_mverts_nt", morph.mverts[threads]);
        if (threads >= 2)
            cJSON_AddNumberToObject(o, "morph_mverts_2t", morph.mverts[2]);
        cJSON_AddNumberToObject(o, "morph_bytes_a_vertex", morph.bytes_a_vertex);
        cJSON_AddNumberToObject(o, "morph_gbps_1t", morph.mverts[1] * 1e6 * morph.bytes_a_vertex * 1e-9);
        cJSON_AddNumberToObject(o, "memcpy_gbps", morph.copy_gbps);
        cJSON_AddNumberToObject(o, "morph_mverts_bandwidth_bound", morph.copy_gbps * 1e9 / morph.bytes_a_vertex * 1e-6);
        cJSON_AddStringToObject(o, "simd", sinew_simd_name());
        cJSON_AddNumberToObject(o, "threads", threads);
        cJSON_AddNumberToObject(o, "skin_mverts_nt", skin.mverts[threads]);
        cJSON_AddNumberToObject(o, "crowd1000_ms_1t", crowd.ms[1]);
        cJSON_AddNumberToObject(o, "crowd1000_ms_nt", crowd.ms[threads]);
        cJSON_AddNumberToObject(o, "crowd1000_speedup_nt", crowd.ms[1] / crowd.ms[threads]);
        if (threads >= 2) {
            cJSON_AddNumberToObject(o, "skin_mverts_2t", skin.mverts[2]);
            cJSON_AddNumberToObject(o, "crowd1000_ms_2t", crowd.ms[2]);
            cJSON_AddNumberToObject(o, "crowd1000_speedup_2t", crowd.ms[1] / crowd.ms[2]);
        }
        cJSON *scaling = cJSON_AddArrayToObject(o, "scaling");
        for (uint32_t t = 1; t <= threads; t++) {
            cJSON *step = cJSON_CreateObject();
            cJSON_AddNumberToObject(step, "threads", t);
            cJSON_AddNumberToObject(step, "crowd_ms", crowd.ms[t]);
            cJSON_AddNumberToObject(step, "crowd_speedup", crowd.ms[1] / crowd.ms[t]);
            cJSON_AddNumberToObject(step, "crowd_efficiency", crowd.ms[1] / crowd.ms[t] / t);
            cJSON_AddNumberToObject(step, "skin_mverts", skin.mverts[t]);
            cJSON_AddNumberToObject(step, "skin_speedup", skin.mverts[t] / skin.mverts[1]);
            cJSON_AddNumberToObject(step, "skin_large_mverts", skin.large_mverts[t]);
            cJSON_AddNumberToObject(step, "triad_gbps", skin.triad_gbps[t]);
            cJSON_AddItemToArray(scaling, step);
        }
        cJSON_AddNumberToObject(o, "load_ms_sinew", load.sinew_ms);
        if (isnan(load.assimp_ms)) { /* not measured: Assimp could not be run */
            cJSON_AddNullToObject(o, "load_ms_assimp");
            cJSON_AddNullToObject(o, "load_speedup_vs_assimp");
        } else {
            cJSON_AddNumberToObject(o, "load_ms_assimp", load.assimp_ms);
            cJSON_AddNumberToObject(o, "load_speedup_vs_assimp", load_speedup);
        }
        cJSON_AddStringToObject(o, "load_collada", collada == demo_dae ? "sinew demo humanoid" : collada);
        if (import) {
            cJSON_AddNumberToObject(o, "import_ms_sinew", import_times.sinew_ms);
            cJSON_AddNumberToObject(o, "import_ms_assimp", import_times.assimp_ms);
            cJSON_AddStringToObject(o, "import_file", import);
        }
        cJSON_AddStringToObject(o, "machine", machine);
        cli_json_print(o, true);
        return EXIT_OK;
    }
    printf("machine: %s\n\n", machine);
    printf("%-44s %12s %12s %10s\n", "", "sinew", "reference", "goal");
    printf("%-44s %9.3f us %9.3f us %10s\n", "sample + world, 64 joints, forward 60 Hz", s64.forward_us,
           s64.reference_forward_us, "<= 0.75 us");
    printf("%-44s %9.3f us %9.3f us\n", "sample + world, 64 joints, random seek", s64.seek_us, s64.reference_seek_us);
    printf("%-44s %9.3f us %9.3f us\n", "sample + world, 128 joints, forward 60 Hz", s128.forward_us,
           s128.reference_forward_us);
    printf("%-44s %9.3f us %9.3f us\n", "sample + world, 128 joints, random seek", s128.seek_us,
           s128.reference_seek_us);
    printf("%-44s %9.3f us %9.3f us\n", "blend 2 | 4 poses, 64 joints", blend.blend2_us, blend.blend4_us);
    printf("%-44s %9.3f us %9.3f us\n", "blend 2 poses, SoA (player's pose), 64 j.", blend.soa2_us,
           blend.soa2_scalar_us);
    printf("%-44s %9.3f us %9.3f us\n", "blend 4 poses, SoA, 64 joints", blend.soa4_us, blend.soa4_scalar_us);
    printf("%-44s %9.3f us\n", "character mid-fade: 2 clips, blend, worlds", blend.fading_us);
    printf("%-44s %9.3f us\n", "character mid-fade with 2 IK chains", blend.reaching_us);
    printf("%-44s %9.3f us %9.3f us\n", "IK: two-bone | aim (with a 64-joint pose copy)", blend.two_bone_us,
           blend.aim_us);
    printf("%-44s %6.0f Mv/s %6.0f Mv/s %10s\n", "skinning (pos + normal, 4 infl), 1 thread", skin.mverts[1],
           skin.mverts_scalar, ">= 350");
    printf("%-44s %6.0f Mv/s %12s %10s\n", "skinning, positions only, 1 thread", skin.mverts_posonly, "", ">= 500");
    printf("%-44s %6.0f Mv/s %6.0f Mv/s\n", "influences out of order: pos.+nor. | pos.", skin.mverts_mixed,
           skin.mverts_posonly_mixed);
    for (uint32_t t = 1; t <= threads; t++) {
        char label[64];
        double ceiling = skin.triad_gbps[t] * 1e9 / LARGE_BYTES_A_VERTEX * 1e-6;
        snprintf(label, sizeof label, "%.1fM vertices (10x L3), %u thread%s | ceiling", LARGE_VERTICES * 1e-6, t,
                 t > 1 ? "s" : "");
        printf("%-44s %6.0f Mv/s %6.0f Mv/s %9.0f%%\n", label, skin.large_mverts[t], ceiling,
               100.0 * skin.large_mverts[t] / ceiling);
        snprintf(label, sizeof label, "  STREAM triad, %u thread%s", t, t > 1 ? "s" : "");
        printf("%-44s %6.1f GB/s (72 bytes a vertex)\n", label, skin.triad_gbps[t]);
    }
    printf("%-44s %6.0f Mv/s %6.0f Mv/s %10s\n", "skinning, dual quaternions, 1 thread", skin.mverts_dqs,
           skin.mverts_dqs_scalar, "");
    printf("%-44s %6.0f Mv/s %6.0f Mv/s\n", "morph: 50k verts, 5 of 50 targets, 1 thread", morph.mverts[1],
           morph.mverts_scalar);
    for (uint32_t t = 2; t <= threads; t++) {
        char label[64];
        snprintf(label, sizeof label, "  morph, %u threads | speed-up", t);
        printf("%-44s %6.0f Mv/s %11.2fx\n", label, morph.mverts[t], morph.mverts[t] / morph.mverts[1]);
    }
    printf("%-44s %6.1f GB/s %6.1f GB/s\n", "  morph traffic, 1 thread | memcpy 64 MiB",
           morph.mverts[1] * 1e6 * morph.bytes_a_vertex * 1e-9, morph.copy_gbps);
    printf("%-44s %6.0f Mv/s (%.0f bytes a vertex)\n", "  morph bound by that bandwidth",
           morph.copy_gbps * 1e9 / morph.bytes_a_vertex * 1e-6, morph.bytes_a_vertex);
    printf("%-44s %9.3f ms %12s %10s\n", "1000 characters a frame, 1 thread", crowd.ms[1], "", "");
    for (uint32_t t = 2; t <= threads; t++) {
        char label[64];
        snprintf(label, sizeof label, "  %u threads: frame | speed-up | efficiency", t);
        printf("%-44s %9.3f ms %11.2fx %9.0f%%\n", label, crowd.ms[t], crowd.ms[1] / crowd.ms[t],
               100.0 * crowd.ms[1] / crowd.ms[t] / t);
    }
    for (uint32_t t = 2; t <= threads; t++) {
        char label[64];
        snprintf(label, sizeof label, "skinning, %u threads | speed-up", t);
        printf("%-44s %6.0f Mv/s %11.2fx\n", label, skin.mverts[t], skin.mverts[t] / skin.mverts[1]);
    }
    printf("%-44s %9.3f ms %9.3f ms %10s\n", "load .sinew | Assimp COLLADA", load.sinew_ms, load.assimp_ms, "");
    printf("%-44s %11.0fx %12s %10s\n", "  .sinew load speed-up", load_speedup, "", ">= 100x");
    if (import)
        printf("%-44s %9.3f ms %9.3f ms %10s\n", "import: sinew's reader | Assimp", import_times.sinew_ms,
               import_times.assimp_ms, "");
    printf("\n(%ld-byte COLLADA file, %ld-byte .sinew; skinning over %u vertices)\n", load.source_bytes,
           load.sinew_bytes, skin.vertices);
    if (import)
        printf("(imported: %s, %ld bytes)\n", import, import_times.bytes);
    return EXIT_OK;
}
