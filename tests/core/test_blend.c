/* sinew/blend.h: blending (weights 1/0 give the first pose, a pose with itself is itself,
 * masks touch only their nodes, the rest pose fills missing weight), additive layers (the
 * reference pose adds nothing; reference + delta = pose), the exact two-pose slerp, the
 * player's local poses, cross-fade weights and phase sync, two-bone IK (reaches reachable
 * targets to 1e-5 m, keeps bone lengths to 1e-6, stretches straight at unreachable ones,
 * bends towards the pole, the seed arm's elbow equals the law of cosines), aim IK, and root
 * motion on a CMU mocap walk. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "helpers.h"
#include "sinew/blend.h"

static int32_t node_named(const sinew_model *m, const char *name)
{
    for (uint32_t i = 0; i < m->node_count; i++)
        if (strcmp(m->node_names[i], name) == 0)
            return (int32_t)i;
    fail_msg("no node \"%s\"", name);
    return -1;
}

static void test_blend_weights_masks_rest(void **state)
{
    (void)state;
    sinew_model *m = demo_humanoid();
    uint32_t n = m->node_count;
    sinew_transform *walk = pose_locals(m, &m->clips[0], 0.3f, SINEW_WRAP_LOOP),
                    *wave = pose_locals(m, &m->clips[1], 0.7f, SINEW_WRAP_LOOP);
    sinew_transform *out = malloc(n * sizeof *out);
    sinew_blend_layer layers[2] = {{walk, 1.0f, NULL}, {wave, 0.0f, NULL}};
    sinew_blend_desc d = {.model = m, .layers = layers, .layer_count = 2, .out = out, .out_count = n};
    assert_int_equal(sinew_blend(&d, NULL), SINEW_OK);
    double first = pose_difference(out, walk, n);
    /* a clip with itself at 0.5 each */
    layers[1] = (sinew_blend_layer){walk, 0.5f, NULL};
    layers[0].weight = 0.5f;
    assert_int_equal(sinew_blend(&d, NULL), SINEW_OK);
    double itself = pose_difference(out, walk, n);
    /* a mask: the wave only on the left arm, the walk elsewhere */
    float *mask = calloc(n, sizeof *mask);
    int32_t arm = node_named(m, "LeftUpperArm");
    mask[arm] = 1.0f;
    layers[0] = (sinew_blend_layer){walk, 1.0f, NULL};
    layers[1] = (sinew_blend_layer){wave, 1.0f, mask};
    assert_int_equal(sinew_blend(&d, NULL), SINEW_OK);
    double others = 0.0;
    for (uint32_t i = 0; i < n; i++)
        if ((int32_t)i != arm)
            others = fmax(others, pose_difference(&out[i], &walk[i], 1));
    double masked = pose_difference(&out[arm], &walk[arm], 1);
    /* no layer at all: the rest pose */
    d.layer_count = 0;
    assert_int_equal(sinew_blend(&d, NULL), SINEW_OK);
    double rest = pose_difference(out, m->node_rest, n);
    print_message("blend: weights 1/0 vs the first %.1e, a clip with itself %.1e, mask: other nodes %.1e, the "
                  "masked arm moved %.3f; no layer vs rest %.1e\n",
                  first, itself, others, masked, rest);
    assert_true(first < 1e-6 && itself < 1e-6 && others < 1e-6 && rest < 1e-6);
    assert_true(masked > 0.01);
    /* bad weights are refused */
    sinew_error error = {0};
    layers[0].weight = -1.0f;
    d.layer_count = 2;
    assert_int_equal(sinew_blend(&d, &error), SINEW_ERROR_INVALID_ARGUMENT);
    assert_non_null(strstr(error.message, "negative"));
    free(mask);
    free(out);
    free(walk);
    free(wave);
    sinew_model_free(m);
}

static void test_additive_and_slerp(void **state)
{
    (void)state;
    sinew_model *m = demo_humanoid();
    uint32_t n = m->node_count;
    sinew_transform *ref = pose_locals(m, &m->clips[1], 0.0f, SINEW_WRAP_LOOP),
                    *pose = pose_locals(m, &m->clips[1], 0.9f, SINEW_WRAP_LOOP);
    sinew_transform *delta = malloc(n * sizeof *delta), *out = malloc(n * sizeof *out);
    sinew_transform *base = pose_locals(m, &m->clips[0], 0.4f, SINEW_WRAP_LOOP);
    /* the reference's own delta adds nothing */
    assert_int_equal(sinew_additive_delta(ref, ref, delta, n, NULL), SINEW_OK);
    sinew_blend_layer layer = {base, 1.0f, NULL}, add = {delta, 1.0f, NULL};
    sinew_blend_desc d = {.model = m,
                          .layers = &layer,
                          .layer_count = 1,
                          .additive = &add,
                          .additive_count = 1,
                          .out = out,
                          .out_count = n};
    assert_int_equal(sinew_blend(&d, NULL), SINEW_OK);
    double identity = pose_difference(out, base, n);
    /* reference + (pose - reference) = pose */
    assert_int_equal(sinew_additive_delta(ref, pose, delta, n, NULL), SINEW_OK);
    layer.locals = ref;
    assert_int_equal(sinew_blend(&d, NULL), SINEW_OK);
    double back = pose_difference(out, pose, n);
    /* slerp: the ends, and halfway between a pose and itself */
    assert_int_equal(sinew_pose_slerp(ref, pose, 0.0f, out, n, NULL), SINEW_OK);
    double at0 = pose_difference(out, ref, n);
    assert_int_equal(sinew_pose_slerp(ref, pose, 1.0f, out, n, NULL), SINEW_OK);
    double at1 = pose_difference(out, pose, n);
    assert_int_equal(sinew_pose_slerp(pose, pose, 0.5f, out, n, NULL), SINEW_OK);
    double half = pose_difference(out, pose, n);
    print_message("additive: the reference's delta %.1e, reference + delta vs pose %.1e; slerp ends %.1e %.1e, "
                  "itself %.1e\n",
                  identity, back, at0, at1, half);
    assert_true(identity < 1e-6 && back < 1e-5 && at0 < 1e-6 && at1 < 1e-6 && half < 1e-6);
    free(ref);
    free(pose);
    free(base);
    free(delta);
    free(out);
    sinew_model_free(m);
}

/* The player's local poses are sinew_sample()'s. */
static void test_player_sample(void **state)
{
    (void)state;
    sinew_model *m = demo_humanoid();
    test_player tp;
    sinew_player *player = test_player_open(&tp, m, &m->clips[1]);
    sinew_transform *fast = malloc(m->node_count * sizeof *fast);
    double worst = 0.0;
    for (float t = 0.0f; t < 4.0f; t += 0.13f) {
        assert_int_equal(sinew_player_sample(player, t, SINEW_WRAP_LOOP, fast, m->node_count, NULL), SINEW_OK);
        sinew_transform *ref = pose_locals(m, &m->clips[1], t, SINEW_WRAP_LOOP);
        worst = fmax(worst, pose_difference(fast, ref, m->node_count));
        free(ref);
    }
    print_message("player's local poses vs sinew_sample: %.1e\n", worst);
    assert_true(worst < 1e-5);
    free(fast);
    test_player_close(&tp);
    sinew_model_free(m);
}

static void test_crossfade(void **state)
{
    (void)state;
    sinew_clip a = {.duration = 1.0f}, b = {.duration = 1.6f};
    sinew_crossfade f = {.from = &a, .to = &b, .from_time = 0.25f, .start = 10.0f, .duration = 0.5f, .sync = true};
    float ta, tb, w;
    sinew_crossfade_at(&f, 9.9f, &ta, &tb, &w);
    assert_float_equal(w, 0.0f, 0.0f);
    sinew_crossfade_at(&f, 10.25f, &ta, &tb, &w);
    assert_float_equal(w, 0.5f, 1e-6f);
    double worst = 0.0;
    for (float c = 10.0f; c < 12.0f; c += 0.05f) {
        sinew_crossfade_at(&f, c, &ta, &tb, &w);
        worst = fmax(worst, fabs(ta / a.duration - tb / b.duration));
    }
    sinew_crossfade_at(&f, 11.0f, &ta, &tb, &w);
    assert_float_equal(w, 1.0f, 0.0f);
    print_message("cross-fade with sync: phases differ by at most %.1e\n", worst);
    assert_true(worst < 1e-5);
    f.sync = false;
    f.to_time = 0.0f;
    sinew_crossfade_at(&f, 10.3f, &ta, &tb, &w);
    assert_float_equal(ta, 0.55f, 1e-5f);
    assert_float_equal(tb, 0.3f, 1e-5f);
}

/* World positions of nodes after correcting locals. */
static void worlds_of(const sinew_model *m, const sinew_transform *locals, sinew_mat4 *worlds)
{
    assert_int_equal(sinew_local_to_world(m, locals, m->node_count, NULL, worlds, m->node_count, NULL), SINEW_OK);
}

static double distance(const sinew_mat4 *a, const sinew_mat4 *b)
{
    double d[3] = {a->m[12] - b->m[12], a->m[13] - b->m[13], a->m[14] - b->m[14]};
    return sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
}

static double distance_to(const sinew_mat4 *a, const double p[3])
{
    double d[3] = {a->m[12] - p[0], a->m[13] - p[1], a->m[14] - p[2]};
    return sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
}

static void test_two_bone_ik(void **state)
{
    (void)state;
    sinew_model *m = demo_humanoid();
    uint32_t n = m->node_count;
    uint32_t s = (uint32_t)node_named(m, "LeftUpperArm"), mid = (uint32_t)node_named(m, "LeftLowerArm"),
             e = (uint32_t)node_named(m, "LeftHand");
    sinew_transform *pose = pose_locals(m, &m->clips[0], 0.2f, SINEW_WRAP_LOOP), *locals = malloc(n * sizeof *locals);
    sinew_mat4 *rest = malloc(n * sizeof *rest), *worlds = malloc(n * sizeof *worlds);
    worlds_of(m, pose, rest);
    double a = distance(&rest[s], &rest[mid]), b = distance(&rest[mid], &rest[e]);
    double worst_reach = 0.0, worst_length = 0.0, worst_line = 0.0, worst_pole = 1.0;
    srand(7);
    for (int i = 0; i < 200; i++) {
        memcpy(locals, pose, n * sizeof *locals);
        /* a random target: within reach for the first 150, beyond it after */
        double dir[3], len = 0.0;
        for (int k = 0; k < 3; k++)
            dir[k] = rand() / (double)RAND_MAX * 2.0 - 1.0, len += dir[k] * dir[k];
        len = sqrt(len);
        double r = i < 150 ? (fabs(a - b) + 0.02 + (a + b - fabs(a - b) - 0.04) * (rand() / (double)RAND_MAX))
                           : (a + b) * (1.2 + rand() / (double)RAND_MAX);
        double target[3];
        for (int k = 0; k < 3; k++)
            target[k] = rest[s].m[12 + k] + dir[k] / len * r;
        double pole[3] = {rest[mid].m[12], rest[mid].m[13] - 0.3, rest[mid].m[14] - 0.5};
        sinew_ik_two_bone_desc d = {.model = m,
                                    .worlds = rest,
                                    .locals = locals,
                                    .node_count = n,
                                    .start = s,
                                    .middle = mid,
                                    .end = e,
                                    .weight = 1.0f};
        for (int k = 0; k < 3; k++)
            d.target[k] = (float)target[k], d.pole[k] = (float)pole[k];
        bool reached = false;
        d.reached = &reached;
        assert_int_equal(sinew_ik_two_bone(&d, NULL), SINEW_OK);
        worlds_of(m, locals, worlds);
        worst_length = fmax(worst_length, fabs(distance(&worlds[s], &worlds[mid]) - a));
        worst_length = fmax(worst_length, fabs(distance(&worlds[mid], &worlds[e]) - b));
        if (i < 150) {
            worst_reach = fmax(worst_reach, distance_to(&worlds[e], target));
            assert_true(reached);
            /* the elbow leans to the pole's side of the start-target line */
            double axis[3], em[3], pm[3], dot = 0.0, ne = 0.0, np = 0.0;
            for (int k = 0; k < 3; k++)
                axis[k] = (target[k] - rest[s].m[12 + k]) / r;
            double te = 0.0, tp = 0.0;
            for (int k = 0; k < 3; k++)
                te += (worlds[mid].m[12 + k] - rest[s].m[12 + k]) * axis[k],
                    tp += (pole[k] - rest[s].m[12 + k]) * axis[k];
            for (int k = 0; k < 3; k++) {
                em[k] = worlds[mid].m[12 + k] - rest[s].m[12 + k] - te * axis[k];
                pm[k] = pole[k] - rest[s].m[12 + k] - tp * axis[k];
                dot += em[k] * pm[k], ne += em[k] * em[k], np += pm[k] * pm[k];
            }
            if (ne > 1e-8 && np > 1e-8)
                worst_pole = fmin(worst_pole, dot / sqrt(ne * np));
        } else { /* straight at the target: the hand a + b from the shoulder, on the line */
            double along = 0.0, off = 0.0;
            for (int k = 0; k < 3; k++)
                along += (worlds[e].m[12 + k] - rest[s].m[12 + k]) * dir[k] / len;
            for (int k = 0; k < 3; k++) {
                double p = worlds[e].m[12 + k] - rest[s].m[12 + k] - along * dir[k] / len;
                off += p * p;
            }
            worst_line = fmax(worst_line, fmax(fabs(along - (a + b)), sqrt(off)));
            assert_false(reached);
        }
    }
    print_message("two-bone IK on the demo's left arm (a %.3f m, b %.3f m): reachable targets missed by <= %.1e m, "
                  "bone lengths kept to %.1e, unreachable: straight to %.1e, elbow towards the pole: cos >= %.3f\n",
                  a, b, worst_reach, worst_length, worst_line, worst_pole);
    assert_true(worst_reach < 1e-5);
    assert_true(worst_length < 1e-6);
    assert_true(worst_line < 1e-5);
    assert_true(worst_pole > 0.99);
    free(pose);
    free(locals);
    free(rest);
    free(worlds);
    sinew_model_free(m);
}

/* The seed's arm (upper rod, elbow, lower rod) with a hand node at the lower rod's free end:
 * IK to a point d from the shoulder bends the elbow to the law of cosines' angle. */
static void test_arm_elbow_is_law_of_cosines(void **state)
{
    (void)state;
    sinew_arm_desc ad = {.free_to_origin = 0.05,
                         .origin_to_elbow = 0.25,
                         .elbow_to_insertion = 0.04,
                         .insertion_to_free = 0.26,
                         .elbow_angle = 2.5};
    sinew_model *arm = NULL;
    assert_int_equal(sinew_arm_model(&ad, &arm, NULL), SINEW_OK);
    /* the same model with a "hand" at the lower rod's end (x along the rod) */
    const char *names[4] = {arm->node_names[0], arm->node_names[1], arm->node_names[2], "hand"};
    int32_t parents[4] = {arm->node_parents[0], arm->node_parents[1], arm->node_parents[2], 2};
    sinew_transform rest[4] = {
        arm->node_rest[0],
        arm->node_rest[1],
        arm->node_rest[2],
        {{(float)(ad.elbow_to_insertion + ad.insertion_to_free), 0, 0}, {0, 0, 0, 1}, {1, 1, 1}}};
    sinew_model m = *arm;
    m.node_count = 4, m.node_names = names, m.node_parents = parents, m.node_rest = rest, m.node_inherit = NULL;
    m.skin_count = 0, m.mesh_count = 0, m.instance_count = 0, m.clip_count = 0;
    double a = ad.free_to_origin + ad.origin_to_elbow, b = ad.elbow_to_insertion + ad.insertion_to_free;
    double worst = 0.0;
    for (double d = fabs(a - b) + 0.01; d < a + b - 0.005; d += 0.02) {
        sinew_transform locals[4];
        sinew_mat4 worlds[4];
        memcpy(locals, rest, sizeof locals);
        worlds_of(&m, locals, worlds);
        sinew_ik_two_bone_desc desc = {.model = &m,
                                       .worlds = worlds,
                                       .locals = locals,
                                       .node_count = 4,
                                       .start = 1,
                                       .middle = 2,
                                       .end = 3,
                                       .weight = 1.0f};
        /* the target at distance d along a slanted line from the shoulder; the pole above */
        double dir[3] = {0.6, 0.48, 0.64};
        for (int k = 0; k < 3; k++)
            desc.target[k] = (float)(worlds[1].m[12 + k] + d * dir[k]);
        desc.pole[1] = 1.0f;
        assert_int_equal(sinew_ik_two_bone(&desc, NULL), SINEW_OK);
        worlds_of(&m, locals, worlds);
        double u[3], v[3], dot = 0.0;
        for (int k = 0; k < 3; k++)
            u[k] = worlds[1].m[12 + k] - worlds[2].m[12 + k], v[k] = worlds[3].m[12 + k] - worlds[2].m[12 + k];
        for (int k = 0; k < 3; k++)
            dot += u[k] * v[k];
        double elbow =
            acos(dot / (sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]) * sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2])));
        double cosines = acos((a * a + b * b - d * d) / (2.0 * a * b));
        worst = fmax(worst, fabs(elbow - cosines));
    }
    print_message("seed arm: the elbow from IK vs the law of cosines: %.1e rad at worst\n", worst);
    assert_true(worst < 1e-5);
    sinew_model_free(arm);
}

/* The foot-on-ground example: through the demo's walk, whenever an ankle is within 4 cm of its
 * height in the rest pose (the foot flat on the ground) and the leg can reach that height
 * there, two-bone IK of thigh, shin and foot puts it exactly there, the knee in front; the
 * legs keep their lengths. (A foot the leg cannot reach would need the hips lowered.) */
static void test_feet_on_the_ground(void **state)
{
    (void)state;
    sinew_model *m = demo_humanoid();
    uint32_t n = m->node_count;
    static const char *const legs[2][3] = {{"LeftUpperLeg", "LeftLowerLeg", "LeftFoot"},
                                           {"RightUpperLeg", "RightLowerLeg", "RightFoot"}};
    sinew_mat4 *worlds = malloc(n * sizeof *worlds);
    worlds_of(m, m->node_rest, worlds);
    float ground = worlds[node_named(m, "LeftFoot")].m[13]; /* the ankle's height with the foot down */
    double worst = 0.0, worst_length = 0.0;
    int planted = 0;
    for (float t = 0.0f; t < 1.0f; t += 0.05f) {
        sinew_transform *locals = pose_locals(m, &m->clips[0], t, SINEW_WRAP_LOOP);
        worlds_of(m, locals, worlds);
        for (int l = 0; l < 2; l++) {
            uint32_t s = (uint32_t)node_named(m, legs[l][0]), k = (uint32_t)node_named(m, legs[l][1]),
                     f = (uint32_t)node_named(m, legs[l][2]);
            double thigh = distance(&worlds[s], &worlds[k]), shin = distance(&worlds[k], &worlds[f]);
            double reach = sqrt(pow(worlds[f].m[12] - worlds[s].m[12], 2) + pow(ground - worlds[s].m[13], 2) +
                                pow(worlds[f].m[14] - worlds[s].m[14], 2));
            if (worlds[f].m[13] > ground + 0.04f || reach > thigh + shin - 1e-4)
                continue;
            sinew_ik_two_bone_desc d = {.model = m,
                                        .worlds = worlds,
                                        .locals = locals,
                                        .node_count = n,
                                        .start = s,
                                        .middle = k,
                                        .end = f,
                                        .weight = 1.0f};
            d.target[0] = worlds[f].m[12], d.target[1] = ground, d.target[2] = worlds[f].m[14];
            for (int c = 0; c < 3; c++) /* the pole: in front of the knee */
                d.pole[c] = worlds[k].m[12 + c] + (c == 2 ? 0.5f : 0.0f);
            assert_int_equal(sinew_ik_two_bone(&d, NULL), SINEW_OK);
            worlds_of(m, locals, worlds);
            worst = fmax(worst, fabs(worlds[f].m[13] - ground));
            worst_length = fmax(worst_length, fmax(fabs(distance(&worlds[s], &worlds[k]) - thigh),
                                                   fabs(distance(&worlds[k], &worlds[f]) - shin)));
            planted++;
        }
        free(locals);
    }
    print_message("feet on the ground: %d planted feet, ankles at the rest height (%.3f m) to %.1e m, legs kept to "
                  "%.1e\n",
                  planted, ground, worst, worst_length);
    assert_true(planted >= 5);
    assert_true(worst < 1e-5 && worst_length < 1e-6);
    free(worlds);
    sinew_model_free(m);
}

static void test_aim(void **state)
{
    (void)state;
    sinew_model *m = demo_humanoid();
    uint32_t n = m->node_count, head = (uint32_t)node_named(m, "Head");
    sinew_transform *locals = pose_locals(m, &m->clips[0], 0.5f, SINEW_WRAP_LOOP);
    sinew_mat4 *worlds = malloc(n * sizeof *worlds);
    worlds_of(m, locals, worlds);
    float target[3] = {worlds[head].m[12] + 1.0f, worlds[head].m[13] + 0.5f, worlds[head].m[14] + 2.0f};
    sinew_ik_aim_desc d = {.model = m,
                           .worlds = worlds,
                           .locals = locals,
                           .node_count = n,
                           .joint = head,
                           .forward = {0, 0, 1},
                           .up = {0, 1, 0},
                           .pole_vector = {0, 1, 0},
                           .weight = 1.0f};
    memcpy(d.target, target, sizeof target);
    assert_int_equal(sinew_ik_aim(&d, NULL), SINEW_OK);
    worlds_of(m, locals, worlds);
    /* the head's +Z (its third column) towards the target, its +Y leaning up */
    double f[3] = {worlds[head].m[8], worlds[head].m[9], worlds[head].m[10]}, to[3], fl = 0.0, tl = 0.0, dot = 0.0;
    for (int k = 0; k < 3; k++)
        to[k] = target[k] - worlds[head].m[12 + k];
    for (int k = 0; k < 3; k++)
        fl += f[k] * f[k], tl += to[k] * to[k], dot += f[k] * to[k];
    double c = dot / sqrt(fl * tl);
    double up = worlds[head].m[5] / sqrt(worlds[head].m[4] * worlds[head].m[4] + worlds[head].m[5] * worlds[head].m[5] +
                                         worlds[head].m[6] * worlds[head].m[6]);
    print_message("aim: the head's forward vs the target direction: cos %.8f; its up's y %.3f\n", c, up);
    assert_true(c > 1.0 - 1e-6);
    assert_true(up > 0.8);
    free(locals);
    free(worlds);
    sinew_model_free(m);
}

/* CMU 01_01.bvh walks: the hips' horizontal motion comes out, the hips stay in place. */
static void test_root_motion(void **state)
{
    (void)state;
    char path[1024];
    if (!testdata_path("assimp/BVH/01_01.bvh", path, sizeof path))
        skip();
    sinew_model *m = load_or_fail(path);
    const sinew_clip *clip = &m->clips[0];
    sinew_root_motion rm;
    assert_int_equal(sinew_root_motion_init(m, clip, -1, &rm, NULL), SINEW_OK);
    double moved = 0.0, in_place = 0.0;
    for (float t = 0.0f; t <= clip->duration; t += clip->duration / 20.0f) {
        sinew_transform *locals = pose_locals(m, clip, t, SINEW_WRAP_LOOP);
        sinew_transform before = locals[rm.node];
        float tr[3], yaw;
        sinew_root_motion_extract(&rm, locals, tr, &yaw);
        in_place = fmax(in_place, fabs(locals[rm.node].translation[0] - rm.start[0]) +
                                      fabs(locals[rm.node].translation[2] - rm.start[2]));
        assert_float_equal(tr[0], before.translation[0] - rm.start[0], 1e-5f);
        assert_float_equal(locals[rm.node].translation[1], before.translation[1], 0.0f);
        moved = fmax(moved, sqrt(tr[0] * tr[0] + tr[2] * tr[2]));
        free(locals);
    }
    print_message("root motion of \"%s\" on %s: up to %.2f units taken out over the clip (%.2f a cycle, yaw %.1f deg a "
                  "cycle); left in place to %.1e\n",
                  m->node_names[rm.node], clip->name, moved,
                  sqrt(rm.cycle[0] * rm.cycle[0] + rm.cycle[2] * rm.cycle[2]), rm.cycle_yaw * 180.0 / M_PI, in_place);
    assert_true(moved > 0.5);
    assert_true(in_place < 1e-6);
    sinew_model_free(m);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_blend_weights_masks_rest),
        cmocka_unit_test(test_additive_and_slerp),
        cmocka_unit_test(test_player_sample),
        cmocka_unit_test(test_crossfade),
        cmocka_unit_test(test_two_bone_ik),
        cmocka_unit_test(test_arm_elbow_is_law_of_cosines),
        cmocka_unit_test(test_feet_on_the_ground),
        cmocka_unit_test(test_aim),
        cmocka_unit_test(test_root_motion),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
