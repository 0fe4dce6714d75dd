/* sinew_character (sinew/character.h): every part of the composition the apps use, each
 * checked against the jobs it is made of. Blended layers with a mask, additive layers, a
 * scheduled cross-fade in step, IK, root motion, palettes, morph weights and muscles; the
 * player and SoA paths against the local-transform path; advance against seek; fades started
 * at run time (what sinew_mixer did: a clip alone is the player, a cross-fade is the blend of
 * the two clips at the character's times and weights, weights continuous when a fade
 * interrupts another, phase sync keeps normalised times equal); many instances on the job
 * system; bad descriptions and calls refused with messages. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "helpers.h"
#include "sinew/blend.h"
#include "sinew/character.h"
#include "sinew/jobs.h"

static sinew_result step(sinew_character *c, float dt, sinew_mat4 *worlds, uint32_t n, sinew_error *error)
{
    sinew_result r = sinew_character_advance(c, dt, error);
    return r == SINEW_OK
               ? sinew_character_evaluate(c, &(sinew_character_output){.worlds = worlds, .world_count = n}, error)
               : r;
}

typedef struct instance {
    sinew_clip_layout *layouts[8];
    uint32_t layout_count;
    void *memory;
    sinew_character *c;
} instance;

static sinew_clip_layout *layout_of(instance *t, const sinew_model *m, int32_t clip)
{
    sinew_clip_layout_desc d = {.model = m, .clip = clip >= 0 ? &m->clips[clip] : NULL};
    assert_int_equal(sinew_clip_layout_create(&d, &t->layouts[t->layout_count], NULL), SINEW_OK);
    return t->layouts[t->layout_count++];
}

static sinew_character *make(instance *t, const sinew_character_desc *d)
{
    size_t size = sinew_character_size(d);
    assert_true(size > 0);
    t->memory = malloc(size);
    sinew_error error = {0};
    if (sinew_character_init(t->memory, size, d, &t->c, &error) != SINEW_OK)
        fail_msg("sinew_character_init: %s", error.message);
    return t->c;
}

static void release(instance *t)
{
    free(t->memory);
    for (uint32_t i = 0; i < t->layout_count; i++)
        sinew_clip_layout_free(t->layouts[i]);
    memset(t, 0, sizeof *t);
}

static uint32_t joint(const sinew_model *m, const char *name)
{
    int32_t j = sinew_model_find_joint(m, name);
    assert_true(j >= 0);
    return (uint32_t)j;
}

/* Blended layers (one masked to the upper body) and an additive layer, at several times,
 * against sinew_sample + sinew_additive_delta + sinew_blend + sinew_local_to_world. */
static void test_layers_are_the_jobs(void **state)
{
    (void)state;
    sinew_model *m = demo_humanoid(); /* walk 1 s, wave 2 s */
    const uint32_t n = m->node_count;
    instance t = {0};
    float *upper = malloc(n * sizeof *upper);
    assert_int_equal(sinew_character_subtree_mask(m, joint(m, "Chest"), upper, n, NULL), SINEW_OK);
    uint32_t covered = 0;
    for (uint32_t i = 0; i < n; i++)
        covered += upper[i] == 1.0f;
    assert_true(covered > 3 && covered < n);
    assert_float_equal(upper[joint(m, "Hips")], 0.0f, 0.0f);
    assert_float_equal(upper[joint(m, "LeftHand")], 1.0f, 0.0f);
    sinew_character_layer layers[3] = {{.layout = layout_of(&t, m, 0), .weight = 1.0f},
                                       {.layout = layout_of(&t, m, 1), .weight = 0.7f, .mask = upper},
                                       {.layout = layout_of(&t, m, 1), .weight = 0.5f, .additive = true}};
    sinew_character *c = make(&t, &(sinew_character_desc){.model = m, .layers = layers, .layer_count = 3});
    sinew_mat4 *worlds = malloc(n * sizeof *worlds), *expect = malloc(n * sizeof *expect);
    sinew_transform *locals = malloc(n * sizeof *locals), *out = malloc(n * sizeof *out);
    double worst = 0.0, worst_locals = 0.0;
    for (int k = 0; k < 7; k++) {
        float time = -0.4f + 0.61f * (float)k;
        assert_int_equal(sinew_character_seek(c, time, NULL), SINEW_OK);
        sinew_character_output o = {.worlds = worlds, .world_count = n, .locals = locals, .local_count = n};
        assert_int_equal(sinew_character_evaluate(c, &o, NULL), SINEW_OK);
        sinew_transform *walk = pose_locals(m, &m->clips[0], time, SINEW_WRAP_LOOP),
                        *wave = pose_locals(m, &m->clips[1], time, SINEW_WRAP_LOOP),
                        *first = pose_locals(m, &m->clips[1], 0.0f, SINEW_WRAP_CLAMP),
                        *delta = malloc(n * sizeof *delta);
        assert_int_equal(sinew_additive_delta(first, wave, delta, n, NULL), SINEW_OK);
        sinew_blend_layer bl[2] = {{walk, 1.0f, NULL}, {wave, 0.7f, upper}}, add = {delta, 0.5f, NULL};
        sinew_blend_desc bd = {.model = m,
                               .layers = bl,
                               .layer_count = 2,
                               .additive = &add,
                               .additive_count = 1,
                               .out = out,
                               .out_count = n};
        assert_int_equal(sinew_blend(&bd, NULL), SINEW_OK);
        assert_int_equal(sinew_local_to_world(m, out, n, NULL, expect, n, NULL), SINEW_OK);
        worst = fmax(worst, worlds_difference(worlds, expect, n));
        worst_locals = fmax(worst_locals, pose_difference(locals, out, n));
        free(walk), free(wave), free(first), free(delta);
    }
    print_message("character: walk + wave masked to the chest + additive wave vs the jobs: worlds %.1e, locals %.1e "
                  "(%u of %u nodes in the mask)\n",
                  worst, worst_locals, covered, n);
    assert_true(worst < 1e-5 && worst_locals < 1e-5);
    free(worlds), free(expect), free(locals), free(out), free(upper);
    release(&t);
    sinew_model_free(m);
}

/* The player path (one layer) and the SoA path (several) against the local-transform path
 * (the same description asked for its locals). */
static void test_paths_agree(void **state)
{
    (void)state;
    sinew_model *m = demo_humanoid();
    const uint32_t n = m->node_count;
    sinew_mat4 *fast = malloc(n * sizeof *fast), *slow = malloc(n * sizeof *slow);
    sinew_transform *locals = malloc(n * sizeof *locals);
    sinew_mat4 root = {{0, 0, -1, 0, 0, 1, 0, 0, 1, 0, 0, 0, 2, 0, 3, 1}}; /* a turn and a move */
    double worst[2] = {0}, lean_locals = 0.0;
    sinew_transform *lean = malloc(n * sizeof *lean);
    for (uint32_t count = 1; count <= 2; count++) {
        instance t = {0}, u = {0};
        sinew_character_layer layers[2] = {{.layout = layout_of(&t, m, 0), .weight = 0.8f},
                                           {.layout = layout_of(&t, m, 1), .weight = 0.3f}};
        /* an IK chain switched off: the description has the local-transform path, used only when
         * locals are asked for; the lean one (no chain) has no buffers for it */
        sinew_character_ik off = {.end = joint(m, "LeftHand")};
        sinew_character_desc full = {.model = m, .layers = layers, .layer_count = count, .ik = &off, .ik_count = 1},
                             lean_desc = {.model = m, .layers = layers, .layer_count = count};
        assert_true(sinew_character_size(&lean_desc) < sinew_character_size(&full));
        sinew_character *c = make(&t, &full), *l = make(&u, &lean_desc);
        assert_int_equal(sinew_character_set_target(c, 0, off.target, 0.0f, NULL), SINEW_OK);
        for (int k = 0; k < 9; k++) {
            assert_int_equal(sinew_character_seek(c, 0.23 * k, NULL), SINEW_OK);
            assert_int_equal(sinew_character_evaluate(
                                 c, &(sinew_character_output){.root = &root, .worlds = fast, .world_count = n}, NULL),
                             SINEW_OK);
            sinew_character_output o = {
                .root = &root, .worlds = slow, .world_count = n, .locals = locals, .local_count = n};
            assert_int_equal(sinew_character_evaluate(c, &o, NULL), SINEW_OK);
            worst[count - 1] = fmax(worst[count - 1], worlds_difference(fast, slow, n));
            assert_int_equal(sinew_character_seek(l, 0.23 * k, NULL), SINEW_OK);
            o.locals = lean;
            assert_int_equal(sinew_character_evaluate(l, &o, NULL), SINEW_OK);
            lean_locals = fmax(lean_locals, pose_difference(lean, locals, n));
            o.locals = locals;
        }
        if (count == 1) { /* the player path is the player */
            sinew_mat4 *ref = pose_worlds(m, &m->clips[0], fmodf(0.23f * 8, m->clips[0].duration));
            sinew_mat4 *plain = malloc(n * sizeof *plain);
            assert_int_equal(
                sinew_character_evaluate(c, &(sinew_character_output){.worlds = plain, .world_count = n}, NULL),
                SINEW_OK);
            assert_true(worlds_difference(plain, ref, n) < 1e-5);
            /* the clip alone under the threshold: the rest pose fills in (a lean character's blend
             * reads the rest pose from the model) */
            assert_int_equal(sinew_character_set_weight(l, 0, 0.05f, NULL), SINEW_OK);
            assert_int_equal(sinew_character_seek(l, 0.4, NULL), SINEW_OK);
            assert_int_equal(
                sinew_character_evaluate(l, &(sinew_character_output){.worlds = plain, .world_count = n}, NULL),
                SINEW_OK);
            sinew_transform *walk = pose_locals(m, &m->clips[0], 0.4f, SINEW_WRAP_LOOP);
            sinew_blend_layer faint = {walk, 0.05f, NULL};
            assert_int_equal(
                sinew_blend(
                    &(sinew_blend_desc){.model = m, .layers = &faint, .layer_count = 1, .out = walk, .out_count = n},
                    NULL),
                SINEW_OK);
            assert_int_equal(sinew_local_to_world(m, walk, n, NULL, ref, n, NULL), SINEW_OK);
            assert_true(worlds_difference(plain, ref, n) < 1e-5);
            free(ref), free(plain), free(walk);
        }
        release(&t), release(&u);
    }
    print_message("character: player path vs locals path %.1e; SoA blend vs locals path %.1e; a lean character's "
                  "locals (from the SoA blend) vs the locals path %.1e\n",
                  worst[0], worst[1], lean_locals);
    assert_true(worst[0] < 1e-5 && worst[1] < 1e-5 && lean_locals < 1e-5);
    free(fast), free(slow), free(locals), free(lean);
    sinew_model_free(m);
}

/* A cross-fade scheduled on the clock, in step: each layer's time and weight as
 * sinew_crossfade_at() gives them; advance is seek to the clock + dt. */
static void test_scheduled_fade(void **state)
{
    (void)state;
    sinew_model *m = demo_humanoid();
    const uint32_t n = m->node_count;
    instance t = {0}, u = {0};
    sinew_character_layer layers[2] = {{.layout = layout_of(&t, m, 0), .weight = 1.0f},
                                       {.layout = layout_of(&t, m, 1)}};
    sinew_character_desc d = {.model = m,
                              .layers = layers,
                              .layer_count = 2,
                              .fade = {.from = 0, .to = 1, .start = 0.25f, .duration = 0.5f, .sync = true}};
    sinew_character *c = make(&t, &d), *v = make(&u, &d);
    sinew_crossfade f = {
        .from = &m->clips[0], .to = &m->clips[1], .from_time = 0.25f, .start = 0.25f, .duration = 0.5f, .sync = true};
    sinew_mat4 *a = malloc(n * sizeof *a), *b = malloc(n * sizeof *b);
    double times = 0.0, advanced = 0.0;
    for (int k = 0; k <= 40; k++) {
        float clock = 0.025f * (float)k, from_t, to_t, w;
        sinew_crossfade_at(&f, clock, &from_t, &to_t, &w);
        assert_int_equal(sinew_character_seek(c, clock, NULL), SINEW_OK);
        times = fmax(times, fabs(sinew_character_time(c, 0) - from_t) + fabs(sinew_character_time(c, 1) - to_t) +
                                fabs(sinew_character_weight(c, 1) - w) + fabs(sinew_character_weight(c, 0) - (1 - w)));
        assert_int_equal(sinew_character_evaluate(c, &(sinew_character_output){.worlds = a, .world_count = n}, NULL),
                         SINEW_OK);
        assert_int_equal(step(v, k ? 0.025f : 0.0f, b, n, NULL), SINEW_OK);
        advanced = fmax(advanced, worlds_difference(a, b, n));
    }
    assert_float_equal(sinew_character_weight(c, 1), 1.0f, 0.0f);
    print_message("character: scheduled fade vs sinew_crossfade_at %.1e; 40 advances vs seeks %.1e\n", times, advanced);
    assert_true(times < 1e-6 && advanced < 1e-5);
    free(a), free(b);
    release(&t), release(&u);
    sinew_model_free(m);
}

/* IK: the hand reaches a target in reach, and a weight of 0 is no IK. Root motion: the root
 * stays in place and what was taken out is the clip's motion. */
static void test_ik_and_root_motion(void **state)
{
    (void)state;
    sinew_model *m = demo_humanoid();
    const uint32_t n = m->node_count, hand = joint(m, "LeftHand");
    sinew_mat4 *worlds = malloc(n * sizeof *worlds), *plain = malloc(n * sizeof *plain);
    instance t = {0}, u = {0};
    sinew_character_layer walk = {.layout = layout_of(&t, m, 0), .weight = 1.0f};
    sinew_character *p = make(&u, &(sinew_character_desc){.model = m, .layers = &walk, .layer_count = 1});
    assert_int_equal(sinew_character_seek(p, 0.3, NULL), SINEW_OK);
    assert_int_equal(sinew_character_evaluate(p, &(sinew_character_output){.worlds = plain, .world_count = n}, NULL),
                     SINEW_OK);
    /* a target a little in front of where the hand is */
    sinew_character_ik ik = {.end = hand};
    for (int k = 0; k < 3; k++)
        ik.target[k] = plain[hand].m[12 + k] + (k == 2 ? 0.12f : k == 1 ? 0.05f : 0.0f);
    sinew_character *c =
        make(&t, &(sinew_character_desc){
                     .model = m, .layers = &walk, .layer_count = 1, .ik = &ik, .ik_count = 1, .root_motion = true});
    assert_int_equal(sinew_character_seek(c, 0.3, NULL), SINEW_OK);
    assert_int_equal(sinew_character_evaluate(c, &(sinew_character_output){.worlds = worlds, .world_count = n}, NULL),
                     SINEW_OK);
    double miss = 0.0;
    for (int k = 0; k < 3; k++)
        miss += fabs(worlds[hand].m[12 + k] - ik.target[k]);
    float moved[3], yaw;
    const sinew_root_motion *motion = sinew_character_root_motion(c, moved, &yaw);
    assert_non_null(motion);
    /* the root stays where the clip starts, horizontally */
    double stays = 0.0, taken = 0.0;
    for (int s = 0; s < 5; s++) {
        double time = 0.17 * s;
        assert_int_equal(sinew_character_seek(c, time, NULL), SINEW_OK);
        sinew_transform *locals = malloc(n * sizeof *locals);
        sinew_character_output o = {.worlds = worlds, .world_count = n, .locals = locals, .local_count = n};
        assert_int_equal(sinew_character_evaluate(c, &o, NULL), SINEW_OK);
        sinew_character_root_motion(c, moved, &yaw);
        stays = fmax(stays, fabs(locals[motion->node].translation[0] - motion->start[0]) +
                                fabs(locals[motion->node].translation[2] - motion->start[2]));
        sinew_transform *raw = pose_locals(m, &m->clips[0], (float)time, SINEW_WRAP_LOOP);
        float expect[3], expect_yaw;
        sinew_root_motion_extract(motion, raw, expect, &expect_yaw);
        taken = fmax(taken, fabs(expect[0] - moved[0]) + fabs(expect[2] - moved[2]) + fabs(expect_yaw - yaw));
        free(locals), free(raw);
    }
    /* weight 0: no IK (root motion still on, so compare with root motion alone) */
    assert_int_equal(sinew_character_set_target(c, 0, ik.target, 0.0f, NULL), SINEW_OK);
    assert_int_equal(sinew_character_seek(c, 0.3, NULL), SINEW_OK);
    assert_int_equal(sinew_character_evaluate(c, &(sinew_character_output){.worlds = worlds, .world_count = n}, NULL),
                     SINEW_OK);
    double off = fabs(worlds[hand].m[12] - ik.target[0]) + fabs(worlds[hand].m[13] - ik.target[1]) +
                 fabs(worlds[hand].m[14] - ik.target[2]);
    print_message("character: IK hand off its target by %.1e (without IK %.3f); root motion: the root moves %.1e "
                  "horizontally, what was taken vs sinew_root_motion_extract %.1e\n",
                  miss, off, stays, taken);
    assert_true(miss < 1e-3 && off > 0.05);
    assert_true(stays < 1e-5 && taken < 1e-5);
    assert_null(sinew_character_root_motion(p, NULL, NULL));
    free(worlds), free(plain);
    release(&t), release(&u);
    sinew_model_free(m);
}

/* Palettes are sinew_skin_palette() of the worlds; muscles are the rig's on them. */
static void test_palettes_and_muscles(void **state)
{
    (void)state;
    sinew_model *m = demo_humanoid();
    const uint32_t n = m->node_count, p = sinew_character_palette_count(m);
    assert_true(m->skin_count > 0 && p > 0);
    instance t = {0};
    sinew_character_layer walk = {.layout = layout_of(&t, m, 0), .weight = 1.0f};
    sinew_character *c = make(&t, &(sinew_character_desc){.model = m, .layers = &walk, .layer_count = 1});
    sinew_muscle_set *set;
    const char *text = sinew_demo_humanoid_muscles();
    assert_int_equal(sinew_muscle_set_parse(text, strlen(text), "demo", &set, NULL), SINEW_OK);
    sinew_muscle_rig *rig, *ref_rig;
    assert_int_equal(sinew_muscle_rig_create(m, set, &rig, NULL), SINEW_OK);
    assert_int_equal(sinew_muscle_rig_create(m, set, &ref_rig, NULL), SINEW_OK);
    uint32_t mc = sinew_muscle_rig_count(rig);
    sinew_muscle_pose *muscles = malloc(mc * sizeof *muscles), *ref = malloc(mc * sizeof *ref);
    sinew_mat4 *worlds = malloc(n * sizeof *worlds), *palettes = malloc(p * sizeof *palettes),
               *expect = malloc(p * sizeof *expect);
    assert_int_equal(sinew_character_seek(c, 0.4, NULL), SINEW_OK);
    sinew_character_output o = {.worlds = worlds,
                                .world_count = n,
                                .palettes = palettes,
                                .palette_count = p,
                                .muscle_rig = rig,
                                .muscles = muscles,
                                .muscle_count = mc};
    assert_int_equal(sinew_character_evaluate(c, &o, NULL), SINEW_OK);
    for (uint32_t s = 0, at = 0; s < m->skin_count; at += m->skins[s++].joint_count)
        assert_int_equal(sinew_skin_palette(&m->skins[s], worlds, n, expect + at, m->skins[s].joint_count, NULL),
                         SINEW_OK);
    assert_memory_equal(palettes, expect, p * sizeof *expect);
    assert_int_equal(sinew_muscle_rig_update(ref_rig, worlds, n, ref, mc, NULL), SINEW_OK);
    for (uint32_t i = 0; i < mc; i++)
        assert_true(fabs(muscles[i].distance - ref[i].distance) < 1e-9);
    sinew_error error = {0};
    o.palette_count = p - 1;
    assert_int_equal(sinew_character_evaluate(c, &o, &error), SINEW_ERROR_INVALID_ARGUMENT);
    assert_non_null(strstr(error.message, "palette"));
    print_message("character: %u palette matrices of %u skins and %u muscles as the jobs give them\n", p, m->skin_count,
                  mc);
    free(muscles), free(ref), free(worlds), free(palettes), free(expect);
    sinew_muscle_rig_free(rig), sinew_muscle_rig_free(ref_rig), sinew_muscle_set_free(set);
    release(&t);
    sinew_model_free(m);
}

/* A crowd: instances of one description on the job system, each at its own clock, equal to
 * the same instances evaluated one by one. */
typedef struct crowd {
    sinew_character **members;
    sinew_mat4 *worlds;
    uint32_t n;
    int failures;
} crowd;

static void crowd_job(void *user, uint32_t first, uint32_t count, uint32_t thread)
{
    (void)thread;
    crowd *cr = user;
    for (uint32_t i = first; i < first + count; i++) {
        sinew_character_output o = {.worlds = cr->worlds + (size_t)i * cr->n, .world_count = cr->n};
        if (sinew_character_advance(cr->members[i], 0.01f * (float)(i % 7), NULL) != SINEW_OK ||
            sinew_character_evaluate(cr->members[i], &o, NULL) != SINEW_OK)
            __atomic_add_fetch(&cr->failures, 1, __ATOMIC_RELAXED);
    }
}

static void test_crowd_on_jobs(void **state)
{
    (void)state;
    enum { COUNT = 48 };
    sinew_model *m = demo_humanoid();
    const uint32_t n = m->node_count;
    instance t = {0};
    sinew_character_layer layers[2] = {{.layout = layout_of(&t, m, 0), .weight = 0.6f},
                                       {.layout = layout_of(&t, m, 1), .weight = 0.4f}};
    sinew_character_desc d = {.model = m, .layers = layers, .layer_count = 2};
    size_t size = sinew_character_size(&d);
    unsigned char *memory = malloc(size * COUNT * 2);
    sinew_character *members[COUNT * 2];
    for (uint32_t i = 0; i < COUNT * 2; i++) {
        assert_int_equal(sinew_character_init(memory + size * i, size, &d, &members[i], NULL), SINEW_OK);
        assert_int_equal(sinew_character_seek(members[i], 0.031 * (i % COUNT), NULL), SINEW_OK);
    }
    sinew_jobs *jobs;
    assert_int_equal(sinew_jobs_create(&(sinew_jobs_desc){.threads = 2}, &jobs, NULL), SINEW_OK);
    crowd parallel = {members, malloc(sizeof(sinew_mat4) * n * COUNT), n, 0},
          serial = {members + COUNT, malloc(sizeof(sinew_mat4) * n * COUNT), n, 0};
    for (int frame = 0; frame < 5; frame++) {
        sinew_jobs_run(jobs, COUNT, 4, crowd_job, &parallel);
        crowd_job(&serial, 0, COUNT, 0);
    }
    assert_int_equal(parallel.failures + serial.failures, 0);
    assert_memory_equal(parallel.worlds, serial.worlds, sizeof(sinew_mat4) * n * COUNT);
    sinew_jobs_free(jobs);
    free(parallel.worlds), free(serial.worlds), free(memory);
    release(&t);
    sinew_model_free(m);
}

/* Bad descriptions are refused by size (0) and by init with a message naming the problem. */
static void test_bad_descriptions(void **state)
{
    (void)state;
    sinew_model *m = demo_humanoid();
    instance t = {0};
    sinew_character_layer layers[2] = {{.layout = layout_of(&t, m, 0), .weight = 1.0f},
                                       {.layout = layout_of(&t, m, 1), .weight = 0.5f, .additive = true}};
    sinew_character_ik hips = {.end = joint(m, "Hips")};
    struct {
        sinew_character_desc d;
        const char *says;
    } cases[] = {
        {{.model = NULL}, "no model"},
        {{.model = m, .layers = layers, .layer_count = 17}, "0 to 16 layers"},
        {{.model = m,
          .layers = (sinew_character_layer[]){{.layout = layers[0].layout, .weight = -1}},
          .layer_count = 1},
         "negative"},
        {{.model = m, .layers = layers, .layer_count = 2, .fade = {.from = 0, .to = 1}}, "blended layers"},
        {{.model = m, .layers = layers, .layer_count = 1, .ik = &hips, .ik_count = 1}, "grandparent"},
        {{.model = m, .layers = layers + 1, .layer_count = 1, .root_motion = true}, "root motion"},
        {{.model = m, .layers = layers, .layer_count = 1, .threshold = NAN}, "threshold"},
    };
    for (size_t i = 0; i < sizeof cases / sizeof *cases; i++) {
        sinew_error error = {0};
        sinew_character *c;
        char memory[64];
        assert_int_equal(sinew_character_size(&cases[i].d), 0);
        assert_int_equal(sinew_character_init(memory, sizeof memory, &cases[i].d, &c, &error),
                         SINEW_ERROR_INVALID_ARGUMENT);
        if (!strstr(error.message, cases[i].says))
            fail_msg("case %zu: \"%s\" does not say \"%s\"", i, error.message, cases[i].says);
    }
    /* too little memory */
    sinew_character_desc good = {.model = m, .layers = layers, .layer_count = 2};
    sinew_error error = {0};
    sinew_character *c;
    char memory[64];
    assert_int_equal(sinew_character_init(memory, sizeof memory, &good, &c, &error), SINEW_ERROR_INVALID_ARGUMENT);
    assert_non_null(strstr(error.message, "sinew_character_size"));
    release(&t);
    sinew_model_free(m);
}

/* ---- clips fading into each other at run time (what sinew_mixer was) ------------------------- */

typedef struct test_char {
    sinew_clip_layout *layouts[3];
    uint32_t count;
    void *memory;
    sinew_character *c;
} test_char;

static sinew_character *char_open(test_char *t, const sinew_model *m, uint32_t count)
{
    memset(t, 0, sizeof *t);
    t->count = count;
    for (uint32_t i = 0; i < count; i++) {
        sinew_clip_layout_desc ld = {.model = m, .clip = i < m->clip_count ? &m->clips[i] : NULL};
        assert_int_equal(sinew_clip_layout_create(&ld, &t->layouts[i], NULL), SINEW_OK);
    }
    sinew_character_layer layers[3] = {{0}};
    for (uint32_t i = 0; i < count; i++)
        layers[i].layout = t->layouts[i];
    /* the weights add up to 1 in a fade: a threshold of 1e-6 blends as the expectations do */
    sinew_character_desc d = {.model = m, .layers = layers, .layer_count = count, .threshold = 1e-6f};
    size_t size = sinew_character_size(&d);
    assert_true(size > 0);
    t->memory = malloc(size);
    assert_int_equal(sinew_character_init(t->memory, size, &d, &t->c, NULL), SINEW_OK);
    return t->c;
}

static void char_close(test_char *t)
{
    free(t->memory);
    for (uint32_t i = 0; i < t->count; i++)
        sinew_clip_layout_free(t->layouts[i]);
}

/* World matrices of the AoS blend of the clips at the character's times and weights. */
static void expected_worlds(const sinew_model *m, const sinew_character *mx, uint32_t count, sinew_mat4 *worlds)
{
    sinew_blend_layer layers[3];
    sinew_transform *locals[3], *out = malloc(m->node_count * sizeof *out);
    uint32_t used = 0;
    for (uint32_t i = 0; i < count; i++) {
        locals[i] = pose_locals(m, &m->clips[i], sinew_character_time(mx, i), SINEW_WRAP_LOOP);
        if (sinew_character_weight(mx, i) > 0.0f)
            layers[used++] = (sinew_blend_layer){locals[i], sinew_character_weight(mx, i), NULL};
    }
    sinew_blend_desc d = {
        .model = m, .layers = layers, .layer_count = used, .threshold = 1e-6f, .out = out, .out_count = m->node_count};
    assert_int_equal(sinew_blend(&d, NULL), SINEW_OK);
    assert_int_equal(sinew_local_to_world(m, out, m->node_count, NULL, worlds, m->node_count, NULL), SINEW_OK);
    for (uint32_t i = 0; i < count; i++)
        free(locals[i]);
    free(out);
}

static void test_fades_at_run_time(void **state)
{
    (void)state;
    sinew_model *m = demo_humanoid();
    const uint32_t n = m->node_count;
    test_char t;
    sinew_character *mx = char_open(&t, m, 2);
    sinew_mat4 *worlds = malloc(n * sizeof *worlds), *expect = malloc(n * sizeof *expect);
    /* nothing playing: the rest pose */
    assert_int_equal(step(mx, 0.1f, worlds, n, NULL), SINEW_OK);
    sinew_mat4 *rest = pose_worlds(m, NULL, 0.0f);
    double at_rest = worlds_difference(worlds, rest, n);
    free(rest);
    /* the walk alone is the walk's player */
    assert_int_equal(sinew_character_play(mx, 0, 0.0f, false, NULL), SINEW_OK);
    double alone = 0.0, clock = 0.0;
    for (int f = 0; f < 40; f++) {
        float dt = f == 0 ? 0.0f : 1.0f / 30.0f;
        clock += dt;
        assert_int_equal(step(mx, dt, worlds, n, NULL), SINEW_OK);
        sinew_mat4 *ref = pose_worlds(m, &m->clips[0], (float)fmod(clock, m->clips[0].duration));
        alone = fmax(alone, worlds_difference(worlds, ref, n));
        free(ref);
    }
    /* into the wave over 0.5 s: each frame the blend of both at the character's times and weights */
    assert_int_equal(sinew_character_play(mx, 1, 0.5f, false, NULL), SINEW_OK);
    assert_float_equal(sinew_character_time(mx, 1), 0.0f, 0.0f);
    double fading = 0.0, sum = 0.0, largest = 0.0;
    float last = 0.0f;
    for (int f = 0; f < 24; f++) {
        assert_int_equal(step(mx, 1.0f / 30.0f, worlds, n, NULL), SINEW_OK);
        expected_worlds(m, mx, 2, expect);
        fading = fmax(fading, worlds_difference(worlds, expect, n));
        float w = sinew_character_weight(mx, 1);
        sum = fmax(sum, fabs(w + sinew_character_weight(mx, 0) - 1.0));
        largest = fmax(largest, fabs(w - last));
        assert_true(w >= last);
        last = w;
    }
    assert_float_equal(sinew_character_weight(mx, 0), 0.0f, 0.0f);
    assert_float_equal(sinew_character_weight(mx, 1), 1.0f, 0.0f);
    /* back to the walk, interrupted half-way by the wave again: no jump in the weights */
    assert_int_equal(sinew_character_play(mx, 0, 0.4f, false, NULL), SINEW_OK);
    for (int f = 0; f < 6; f++)
        assert_int_equal(step(mx, 1.0f / 30.0f, worlds, n, NULL), SINEW_OK);
    float before = sinew_character_weight(mx, 1);
    assert_int_equal(sinew_character_play(mx, 1, 0.4f, false, NULL), SINEW_OK);
    float after = sinew_character_weight(mx, 1);
    assert_int_equal(step(mx, 1.0f / 30.0f, worlds, n, NULL), SINEW_OK);
    expected_worlds(m, mx, 2, expect);
    double interrupted = worlds_difference(worlds, expect, n);
    print_message(
        "run-time fades: nothing playing vs rest %.1e; the walk alone vs its player %.1e; fading into the wave vs "
        "the blend at its times and weights %.1e (weights sum to 1 within %.1e, largest step a frame "
        "%.3f); interrupted fade: the wave's weight %.4f before, %.4f after, pose %.1e\n",
        at_rest, alone, fading, sum, largest, before, after, interrupted);
    assert_true(at_rest < 1e-6 && alone < 1e-5 && fading < 1e-5 && interrupted < 1e-5);
    assert_true(sum < 1e-6 && largest < 0.11);
    assert_float_equal(before, after, 0.0f);
    free(worlds);
    free(expect);
    char_close(&t);
    sinew_model_free(m);
}

static void test_fades_in_step_and_errors(void **state)
{
    (void)state;
    sinew_model *m = demo_humanoid(); /* walk 1 s, wave 2 s */
    const uint32_t n = m->node_count;
    test_char t;
    sinew_character *mx = char_open(&t, m, 2);
    sinew_mat4 *worlds = malloc(n * sizeof *worlds), *expect = malloc(n * sizeof *expect);
    assert_int_equal(sinew_character_play(mx, 0, 0.0f, false, NULL), SINEW_OK);
    for (int f = 0; f < 10; f++)
        assert_int_equal(step(mx, 0.03f, worlds, n, NULL), SINEW_OK);
    float phase0 = sinew_character_time(mx, 0) / m->clips[0].duration;
    assert_int_equal(sinew_character_play(mx, 1, 1.0f, true, NULL), SINEW_OK);
    double apart = fabs(sinew_character_time(mx, 1) / m->clips[1].duration - phase0), pose = 0.0;
    float mid_rate = 0.0f;
    for (int f = 0; f < 60; f++) {
        float p0 = sinew_character_time(mx, 1) / m->clips[1].duration;
        assert_int_equal(step(mx, 0.025f, worlds, n, NULL), SINEW_OK);
        if (sinew_character_weight(mx, 0) > 0.0f) {
            double a = sinew_character_time(mx, 0) / m->clips[0].duration,
                   b = sinew_character_time(mx, 1) / m->clips[1].duration;
            apart = fmax(apart, fabs(a - b));
        }
        if (f == 20) /* mid-fade the shared cycle is between 1 s and 2 s long */
            mid_rate = (sinew_character_time(mx, 1) / m->clips[1].duration - p0) / 0.025f;
        expected_worlds(m, mx, 2, expect);
        pose = fmax(pose, worlds_difference(worlds, expect, n));
    }
    print_message("run-time fades in step: normalised times apart by at most %.1e; mid-fade %.2f cycles a second "
                  "(walk 1.00, wave 0.50); pose vs the blend %.1e\n",
                  apart, mid_rate, pose);
    assert_true(apart < 1e-5 && pose < 1e-5);
    assert_true(mid_rate > 0.5f && mid_rate < 1.0f);
    sinew_error error = {0};
    assert_int_equal(sinew_character_play(mx, 2, 0.0f, false, &error), SINEW_ERROR_INVALID_ARGUMENT);
    assert_non_null(strstr(error.message, "layer 2 of 2"));
    assert_int_equal(sinew_character_play(mx, 0, -1.0f, false, &error), SINEW_ERROR_INVALID_ARGUMENT);
    assert_int_equal(step(mx, NAN, worlds, n, &error), SINEW_ERROR_INVALID_ARGUMENT);
    assert_int_equal(step(mx, 0.1f, worlds, n - 1, &error), SINEW_ERROR_INVALID_ARGUMENT);
    /* clips of two models do not mix */
    sinew_model *other = demo_humanoid();
    sinew_clip_layout *foreign;
    assert_int_equal(
        sinew_clip_layout_create(&(sinew_clip_layout_desc){.model = other, .clip = &other->clips[0]}, &foreign, NULL),
        SINEW_OK);
    sinew_character_layer mixed[2] = {{.layout = t.layouts[0]}, {.layout = foreign}};
    sinew_character_desc bad = {.model = m, .layers = mixed, .layer_count = 2};
    assert_int_equal(sinew_character_size(&bad), 0);
    sinew_character *no;
    assert_int_equal(sinew_character_init(t.memory, 1u << 20, &bad, &no, &error), SINEW_ERROR_INVALID_ARGUMENT);
    assert_non_null(strstr(error.message, "another model"));
    sinew_clip_layout_free(foreign);
    sinew_model_free(other);
    free(worlds);
    free(expect);
    char_close(&t);
    sinew_model_free(m);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_layers_are_the_jobs),      cmocka_unit_test(test_paths_agree),
        cmocka_unit_test(test_scheduled_fade),           cmocka_unit_test(test_ik_and_root_motion),
        cmocka_unit_test(test_palettes_and_muscles),     cmocka_unit_test(test_crowd_on_jobs),
        cmocka_unit_test(test_bad_descriptions),         cmocka_unit_test(test_fades_at_run_time),
        cmocka_unit_test(test_fades_in_step_and_errors),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
