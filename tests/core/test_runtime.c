/* The fast paths against their references: sinew_player (AVX2 and scalar) against
 * sinew_sample + sinew_local_to_world, forward and seeking, on generated characters and real
 * files; SIMD skinning against the scalar reference. */
#include <math.h>
#include <stdatomic.h>
#include <unistd.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/internal.h"
#include "helpers.h"
#include "sinew/jobs.h"

/* Largest difference of matrix elements, relative to the element where it is over 1 (files
 * in centimetres have translations in the hundreds). */
static double matrix_difference(const sinew_mat4 *a, const sinew_mat4 *b, uint32_t n)
{
    double worst = 0.0;
    for (uint32_t i = 0; i < n; i++)
        for (int e = 0; e < 16; e++)
            worst = fmax(worst, fabs(a[i].m[e] - b[i].m[e]) / fmax(1.0, fabs(b[i].m[e])));
    return worst;
}

/* Plays every clip forward at 60 Hz (looping past the end) and then at scattered times;
 * returns the largest difference from the reference, SIMD and scalar players both. */
static double check_player(const sinew_model *m, double tolerance)
{
    uint32_t n = m->node_count;
    sinew_mat4 *fast = malloc((n + 1) * sizeof *fast), *slow = malloc((n + 1) * sizeof *slow);
    double worst = 0.0, simd_vs_scalar = 0.0;
    for (uint32_t c = 0; c <= m->clip_count; c++) {
        const sinew_clip *clip = c < m->clip_count ? &m->clips[c] : NULL;
        sinew_error error = {0};
        test_player tp;
        void *simd_memory, *scalar_memory;
        sinew_player *first = test_player_open(&tp, m, clip);
        assert_int_equal(sinew_player_update(first, 0.3f, SINEW_WRAP_LOOP, NULL, fast, n, &error), SINEW_OK);
        /* players of one layout share its keys and keep their own pose and cursors */
        sinew_player *simd = test_player_another(&tp, &simd_memory);
        sinew_player *scalar = test_player_another(&tp, &scalar_memory);
        sinew_player_set_simd(scalar, false);
        float duration = clip ? clip->duration : 1.0f;
        for (int i = 0; i < 160; i++) {
            /* forward frames first, then jumps back and forth */
            float t = i < 100 ? (float)i / 60.0f : duration * (float)((i * 7919) % 101) / 100.0f;
            assert_int_equal(sinew_player_update(simd, t, SINEW_WRAP_LOOP, NULL, fast, n, &error), SINEW_OK);
            sinew_transform *locals = malloc((n + 1) * sizeof *locals);
            sinew_sample_desc d = {
                .model = m, .clip = clip, .time = t, .wrap = SINEW_WRAP_LOOP, .locals = locals, .local_count = n};
            assert_int_equal(sinew_sample(&d, &error), SINEW_OK);
            assert_int_equal(sinew_local_to_world(m, locals, n, NULL, slow, n, &error), SINEW_OK);
            free(locals);
            worst = fmax(worst, matrix_difference(fast, slow, n));
            assert_int_equal(sinew_player_update(scalar, t, SINEW_WRAP_LOOP, NULL, slow, n, &error), SINEW_OK);
            simd_vs_scalar = fmax(simd_vs_scalar, matrix_difference(fast, slow, n));
        }
        free(simd_memory);
        free(scalar_memory);
        test_player_close(&tp);
    }
    print_message("%s: player vs reference %.2e, SIMD vs scalar player %.2e\n", m->source, worst, simd_vs_scalar);
    assert_true(worst <= tolerance);
    assert_true(simd_vs_scalar <= 1e-5);
    free(fast);
    free(slow);
    return worst;
}

static void test_player_generated(void **state)
{
    (void)state;
    sinew_synthetic_desc d = {.joints = 64, .vertices = 500, .influences = 4, .keyed_trs = true};
    sinew_model *m = NULL;
    assert_int_equal(sinew_synthetic_model(&d, &m, NULL), SINEW_OK);
    check_player(m, 1e-5);
    sinew_model_free(m);
    d.joints = 13; /* not a multiple of 8 */
    assert_int_equal(sinew_synthetic_model(&d, &m, NULL), SINEW_OK);
    check_player(m, 1e-5);
    sinew_model_free(m);
    assert_int_equal(sinew_demo_humanoid(&m, NULL), SINEW_OK);
    check_player(m, 1e-5);
    sinew_model_free(m);
}

static void test_player_real_files(void **state)
{
    (void)state;
    /* glTF with step and cubic keys (sinew's own), a COLLADA with channels at different
     * times, Blender's glTF robot with 14 clips, a BVH */
    const char *fixtures[] = {"two_bone_cubic.gltf", "two_bone.dae"};
    char path[4096];
    for (size_t i = 0; i < 2; i++) {
        sinew_model *m = load_or_fail(fixture_path(fixtures[i], path, sizeof path));
        check_player(m, 1e-5);
        sinew_model_free(m);
    }
    const char *files[] = {"raylib/robot.glb", "ozz/pab/walk.dae", "assimp/BVH/01_01.bvh"};
    for (size_t i = 0; i < 3; i++) {
        if (!testdata_path(files[i], path, sizeof path))
            continue;
        FILE *f = fopen(path, "rb");
        if (!f) {
            print_message("%s is not in the shared test data; skipped\n", files[i]);
            continue;
        }
        fclose(f);
        sinew_model *m = load_or_fail(path);
        /* tolerance relative to the model's size: nlerp against slerp between keys */
        check_player(m, 1e-5);
        sinew_model_free(m);
    }
}

typedef struct counting {
    int allocations, live;
} counting;

static void *count_alloc(size_t size, void *user)
{
    counting *c = user;
    c->allocations++;
    c->live++;
    return malloc(size);
}

static void count_free(void *ptr, void *user)
{
    counting *c = user;
    c->live--;
    free(ptr);
}

static void test_player_arguments(void **state)
{
    (void)state;
    sinew_model *m = NULL;
    assert_int_equal(sinew_demo_humanoid(&m, NULL), SINEW_OK);
    sinew_clip_layout *layout = NULL;
    sinew_player *p = NULL;
    sinew_error error = {0};
    assert_int_equal(sinew_clip_layout_create(NULL, &layout, &error), SINEW_ERROR_INVALID_ARGUMENT);
    sinew_allocator half = {.alloc = count_alloc};
    sinew_clip_layout_desc desc = {.model = m, .clip = &m->clips[0], .allocator = &half};
    assert_int_equal(sinew_clip_layout_create(&desc, &layout, &error), SINEW_ERROR_INVALID_ARGUMENT);
    /* the layout and its scratch come from the allocator, and all go back to it */
    counting count = {0};
    sinew_allocator allocator = {count_alloc, count_free, &count};
    desc.allocator = &allocator;
    assert_int_equal(sinew_clip_layout_create(&desc, &layout, &error), SINEW_OK);
    assert_int_equal(count.allocations, 2);
    assert_int_equal(count.live, 1);

    /* the state: too little memory is refused; any alignment is taken */
    size_t size = sinew_player_size(layout);
    unsigned char *memory = malloc(size + 3);
    assert_int_equal(sinew_player_init(memory, size - 1, layout, &p, &error), SINEW_ERROR_INVALID_ARGUMENT);
    assert_non_null(strstr(error.message, "sinew_player_size"));
    assert_int_equal(sinew_player_init(memory + 3, size, layout, &p, &error), SINEW_OK);
    sinew_mat4 worlds[4];
    assert_int_equal(sinew_player_update(p, 0.0f, SINEW_WRAP_CLAMP, NULL, worlds, 4, &error),
                     SINEW_ERROR_INVALID_ARGUMENT);
    assert_non_null(strstr(error.message, "nodes"));
    uint32_t n = m->node_count;
    sinew_mat4 *all = malloc(n * sizeof *all), *again = malloc(n * sizeof *again);
    assert_int_equal(sinew_player_update(p, NAN, SINEW_WRAP_CLAMP, NULL, all, n, &error), SINEW_ERROR_INVALID_ARGUMENT);
    /* init again on the same memory starts over: the same worlds as a fresh player */
    assert_int_equal(sinew_player_update(p, 0.7f, SINEW_WRAP_LOOP, NULL, all, n, &error), SINEW_OK);
    assert_int_equal(sinew_player_init(memory + 3, size, layout, &p, &error), SINEW_OK);
    assert_int_equal(sinew_player_update(p, 0.7f, SINEW_WRAP_LOOP, NULL, again, n, &error), SINEW_OK);
    assert_memory_equal(all, again, n * sizeof *all);
    free(all);
    free(again);
    free(memory);
    sinew_clip_layout_free(layout);
    assert_int_equal(count.live, 0);

    /* a clip that animates a node the model lacks (another model's) is refused */
    sinew_track track = {.node = m->node_count};
    sinew_clip foreign = {.name = "foreign", .duration = 1.0f, .track_count = 1, .tracks = &track};
    desc = (sinew_clip_layout_desc){.model = m, .clip = &foreign};
    assert_int_equal(sinew_clip_layout_create(&desc, &layout, &error), SINEW_ERROR_INVALID_ARGUMENT);
    assert_non_null(strstr(error.message, "foreign"));
    sinew_model_free(m);
}

/* Tangents for a test mesh: perpendicular to the normal, handedness alternating. */
static float *test_tangents(const sinew_mesh *mesh)
{
    float *t = malloc((size_t)mesh->vertex_count * 4 * sizeof(float));
    for (uint32_t v = 0; v < mesh->vertex_count; v++) {
        const float *n = &mesh->normals[(size_t)v * 3];
        float a[3] = {fabsf(n[0]) < 0.9f ? 1.0f : 0.0f, fabsf(n[0]) < 0.9f ? 0.0f : 1.0f, 0.0f};
        float x = a[1] * n[2] - a[2] * n[1], y = a[2] * n[0] - a[0] * n[2], z = a[0] * n[1] - a[1] * n[0];
        float len = sqrtf(x * x + y * y + z * z);
        t[v * 4 + 0] = x / len, t[v * 4 + 1] = y / len, t[v * 4 + 2] = z / len;
        t[v * 4 + 3] = (v & 1) ? -1.0f : 1.0f;
    }
    return t;
}

/* Largest difference of `width` floats a vertex at stride 12 floats, offset `at`. */
static double worst_difference(const float *a, const float *b, size_t n, int at, int width)
{
    double worst = 0.0;
    for (size_t v = 0; v < n; v++)
        for (int e = 0; e < width; e++)
            worst = fmax(worst, fabs(a[v * 12 + at + e] - b[v * 12 + at + e]));
    return worst;
}

/* Every SIMD path (AVX-512, AVX2+FMA, as far as the processor has them) equals the scalar
 * reference for linear blend and dual quaternions, positions, normals and tangents, with
 * interleaved and packed outputs and ranges that do not fill a block, on the synthetic mesh
 * as made (runs of vertices bound to the same joints: AVX-512's shared-joint blocks) and with
 * its influences dealt out of order (every block mixed); a joint index past the palette is
 * refused. */
static void test_skin_simd_matches_scalar(void **state)
{
    (void)state;
    sinew_synthetic_desc d = {.joints = 64, .vertices = 20000, .influences = 4, .keyed_trs = true};
    for (uint32_t influences = 1; influences <= 8; influences++) {
        if (influences > 4 && influences != 5 && influences != 8)
            continue;
        d.influences = influences;
        sinew_model *m = NULL;
        assert_int_equal(sinew_synthetic_model(&d, &m, NULL), SINEW_OK);
        sinew_mesh mesh = m->meshes[0];
        float *tangents = test_tangents(&mesh);
        mesh.tangents = tangents;
        uint16_t *mixed_joints;
        float *mixed_weights;
        influences_out_of_order(&mesh, &mixed_joints, &mixed_weights);
        const sinew_skin *skin = &m->skins[0];
        sinew_mat4 *worlds = pose_worlds(m, &m->clips[0], 0.37f);
        sinew_mat4 *palette = malloc(skin->joint_count * sizeof *palette);
        sinew_dq_joint *dq = malloc(skin->joint_count * sizeof *dq);
        assert_int_equal(sinew_skin_palette(skin, worlds, m->node_count, palette, skin->joint_count, NULL), SINEW_OK);
        /* a mirrored joint and a squashed one: normals go through the cofactor */
        palette[3].m[0] = -palette[3].m[0], palette[3].m[1] = -palette[3].m[1], palette[3].m[2] = -palette[3].m[2];
        for (int e = 4; e < 7; e++)
            palette[5].m[e] *= 0.3f;
        assert_int_equal(sinew_skin_dq_palette(palette, skin->joint_count, dq, NULL), SINEW_OK);
        size_t n = mesh.vertex_count;
        float *a = calloc(n * 12, sizeof(float)), *b = calloc(n * 12, sizeof(float));
        float *packed = calloc(n * 3, sizeof(float)), *packed_ref = calloc(n * 3, sizeof(float));
        for (int order = 0; order < 2; order++) {
            mesh.joints = order ? mixed_joints : m->meshes[0].joints;
            mesh.weights = order ? mixed_weights : m->meshes[0].weights;
            for (int method = 0; method < 2; method++)
                for (sinew_isa isa = SINEW_ISA_AVX512; isa > SINEW_ISA_SCALAR; isa--) {
                    sinew_skin_set_isa_limit(isa);
                    /* interleaved output: position, normal, tangent, 2 floats of padding (stride 48) */
                    memset(a, 0, n * 12 * sizeof(float));
                    memset(b, 0, n * 12 * sizeof(float));
                    sinew_skin_desc sd = {.mesh = &mesh,
                                          .palette = palette,
                                          .palette_count = skin->joint_count,
                                          .method = (sinew_skin_method)method,
                                          .dq_palette = dq,
                                          .first = 7,
                                          .count = (uint32_t)n - 20,
                                          .out_positions = a,
                                          .out_normals = a + 3,
                                          .out_tangents = a + 6,
                                          .out_stride = 48};
                    assert_int_equal(sinew_skin_vertices(&sd, NULL), SINEW_OK);
                    sd.out_positions = b, sd.out_normals = b + 3, sd.out_tangents = b + 6;
                    assert_int_equal(sinew_skin_vertices_scalar(&sd, NULL), SINEW_OK);
                    double worst_p = worst_difference(a, b, n, 0, 3), worst_n = worst_difference(a, b, n, 3, 3);
                    double worst_t = worst_difference(a, b, n, 6, 4);
                    for (size_t v = 0; v < n; v++)
                        assert_true(a[v * 12 + 10] == 0.0f && a[v * 12 + 11] == 0.0f); /* padding untouched */
                    assert_true(a[0] == 0.0f && a[(n - 1) * 12] == 0.0f);              /* outside the range untouched */
                    /* packed positions only, a range ending mid-block */
                    sinew_skin_desc pd = {.mesh = &mesh,
                                          .palette = palette,
                                          .palette_count = skin->joint_count,
                                          .method = (sinew_skin_method)method,
                                          .dq_palette = dq,
                                          .first = 16,
                                          .count = (uint32_t)n - 16 - 3,
                                          .out_positions = packed};
                    assert_int_equal(sinew_skin_vertices(&pd, NULL), SINEW_OK);
                    pd.out_positions = packed_ref;
                    assert_int_equal(sinew_skin_vertices_scalar(&pd, NULL), SINEW_OK);
                    double worst_packed = 0.0;
                    for (size_t i = 0; i < n * 3; i++)
                        worst_packed = fmax(worst_packed, fabs(packed[i] - packed_ref[i]));
                    print_message("%s, %u influences, %s, %s: SIMD vs scalar %.2e positions, %.2e normals, %.2e "
                                  "tangents, %.2e packed\n",
                                  method ? "DQS" : "LBS", influences, isa == SINEW_ISA_AVX512 ? "avx512" : "avx2",
                                  order ? "mixed" : "in runs", worst_p, worst_n, worst_t, worst_packed);
                    assert_true(worst_p <= 2e-6 && worst_packed <= 2e-6);
                    assert_true(worst_n <= 2e-6);
                    assert_true(worst_t <= 2e-6);
                }
        }
        /* the SIMD paths copy a palette that is not 64-byte aligned before skinning out-of-order
         * influences: the same records, so the same bits as from an aligned palette */
        {
            size_t bytes = skin->joint_count * sizeof *palette;
            char *block = aligned_alloc(64, bytes + 64);
            sinew_mat4 *aligned = (sinew_mat4 *)block, *offset = (sinew_mat4 *)(block + 16);
            memcpy(aligned, palette, bytes);
            memset(a, 0, n * 12 * sizeof(float));
            memset(b, 0, n * 12 * sizeof(float));
            sinew_skin_desc sd = {.mesh = &mesh,
                                  .palette = aligned,
                                  .palette_count = skin->joint_count,
                                  .out_positions = a,
                                  .out_normals = a + 3,
                                  .out_stride = 48};
            assert_int_equal(sinew_skin_vertices(&sd, NULL), SINEW_OK);
            memmove(offset, palette, bytes);
            sd.palette = offset, sd.out_positions = b, sd.out_normals = b + 3;
            assert_int_equal(sinew_skin_vertices(&sd, NULL), SINEW_OK);
            assert_memory_equal(a, b, n * 12 * sizeof(float));
            free(block);
        }
        mesh.joints = m->meshes[0].joints;
        mesh.weights = m->meshes[0].weights;
        free(mixed_joints);
        free(mixed_weights);
        sinew_skin_set_isa_limit(SINEW_ISA_AVX512);
        sinew_skin_desc sd = {.mesh = &mesh, .palette = palette, .palette_count = 2, .out_positions = a};
        sinew_error error = {0};
        assert_int_equal(sinew_skin_vertices(&sd, &error), SINEW_ERROR_INVALID_ARGUMENT);
        assert_non_null(strstr(error.message, "the palette has 2"));
        free(a);
        free(b);
        free(packed);
        free(packed_ref);
        free(tangents);
        free(worlds);
        free(palette);
        free(dq);
        sinew_model_free(m);
    }
}

/* A tube along x of radius 1 skinned by two joints blending across the middle; the second
 * joint twisted 170 degrees about x. Linear blend collapses the middle ring (the candy
 * wrapper); dual quaternions keep its radius. With one influence a vertex (and with mirrored
 * and squashed joints) the two methods agree: the dual-quaternion joints are exact. */
static void test_skin_dual_quaternion_twist(void **state)
{
    (void)state;
    enum { RINGS = 21, AROUND = 24, N = RINGS * AROUND };
    static float positions[N * 3], normals[N * 3], weights[N * 2], lbs[N * 3], dqs[N * 3];
    static uint16_t joints[N * 2];
    for (int r = 0; r < RINGS; r++)
        for (int a = 0; a < AROUND; a++) {
            int v = r * AROUND + a;
            float x = -1.0f + 2.0f * (float)r / (RINGS - 1), angle = 6.2831853f * (float)a / AROUND;
            positions[v * 3] = x, positions[v * 3 + 1] = cosf(angle), positions[v * 3 + 2] = sinf(angle);
            normals[v * 3] = 0.0f, normals[v * 3 + 1] = cosf(angle), normals[v * 3 + 2] = sinf(angle);
            float w1 = fminf(fmaxf((x + 0.5f), 0.0f), 1.0f); /* 0 at x <= -0.5, 1 at x >= 0.5 */
            bool second_first = w1 > 0.5f;
            joints[v * 2] = second_first ? 1 : 0, joints[v * 2 + 1] = second_first ? 0 : 1;
            weights[v * 2] = second_first ? w1 : 1.0f - w1, weights[v * 2 + 1] = second_first ? 1.0f - w1 : w1;
        }
    sinew_mesh mesh = {.name = "tube",
                       .vertex_count = N,
                       .positions = positions,
                       .normals = normals,
                       .influence_count = 2,
                       .joints = joints,
                       .weights = weights};
    float c = cosf(170.0f * 3.14159265f / 180.0f), s = sinf(170.0f * 3.14159265f / 180.0f);
    sinew_mat4 palette[2] = {{{1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1}},
                             {{1, 0, 0, 0, 0, c, s, 0, 0, -s, c, 0, 0.1f, 0, 0, 1}}};
    sinew_dq_joint dq[2];
    assert_int_equal(sinew_skin_dq_palette(palette, 2, dq, NULL), SINEW_OK);
    sinew_skin_desc d = {.mesh = &mesh, .palette = palette, .palette_count = 2, .out_positions = lbs};
    assert_int_equal(sinew_skin_vertices(&d, NULL), SINEW_OK);
    d.method = SINEW_SKIN_DUAL_QUATERNION, d.dq_palette = dq, d.out_positions = dqs;
    assert_int_equal(sinew_skin_vertices(&d, NULL), SINEW_OK);
    double radius_lbs = 0.0, radius_dqs = 0.0;
    int middle = RINGS / 2;
    for (int a = 0; a < AROUND; a++) {
        int v = middle * AROUND + a;
        radius_lbs += hypot(lbs[v * 3 + 1], lbs[v * 3 + 2]) / AROUND;
        radius_dqs += hypot(dqs[v * 3 + 1], dqs[v * 3 + 2]) / AROUND;
    }
    print_message("170-degree twist, middle ring radius: linear blend %.3f, dual quaternion %.3f (rest 1)\n",
                  radius_lbs, radius_dqs);
    assert_true(radius_lbs < 0.1);
    assert_true(fabs(radius_dqs - 1.0) < 1e-4);
    /* the rigid ends move the same under both */
    for (int v = 0; v < AROUND; v++)
        for (int e = 0; e < 3; e++) {
            assert_float_equal(lbs[v * 3 + e], dqs[v * 3 + e], 1e-5);
            assert_float_equal(lbs[(N - 1 - v) * 3 + e], dqs[(N - 1 - v) * 3 + e], 1e-5);
        }

    /* one influence: DQS equals LBS for rotated, translated, mirrored, squashed and sheared joints */
    sinew_synthetic_desc sd = {.joints = 16, .vertices = 2000, .influences = 1, .keyed_trs = true};
    sinew_model *m = NULL;
    assert_int_equal(sinew_synthetic_model(&sd, &m, NULL), SINEW_OK);
    const sinew_skin *skin = &m->skins[0];
    sinew_mat4 *worlds = pose_worlds(m, &m->clips[0], 0.61f);
    sinew_mat4 *pal = malloc(skin->joint_count * sizeof *pal);
    sinew_dq_joint *dqp = malloc(skin->joint_count * sizeof *dqp);
    assert_int_equal(sinew_skin_palette(skin, worlds, m->node_count, pal, skin->joint_count, NULL), SINEW_OK);
    pal[3].m[0] = -pal[3].m[0], pal[3].m[1] = -pal[3].m[1], pal[3].m[2] = -pal[3].m[2];
    for (int e = 4; e < 7; e++)
        pal[5].m[e] *= 0.3f;
    pal[7].m[4] += 0.4f * pal[7].m[0]; /* shear */
    assert_int_equal(sinew_skin_dq_palette(pal, skin->joint_count, dqp, NULL), SINEW_OK);
    size_t n = m->meshes[0].vertex_count;
    float *a = malloc(n * 6 * sizeof(float)), *b = malloc(n * 6 * sizeof(float));
    sinew_skin_desc one = {.mesh = &m->meshes[0],
                           .palette = pal,
                           .palette_count = skin->joint_count,
                           .out_positions = a,
                           .out_normals = a + 3,
                           .out_stride = 24};
    assert_int_equal(sinew_skin_vertices_scalar(&one, NULL), SINEW_OK);
    one.method = SINEW_SKIN_DUAL_QUATERNION, one.dq_palette = dqp, one.out_positions = b, one.out_normals = b + 3;
    assert_int_equal(sinew_skin_vertices_scalar(&one, NULL), SINEW_OK);
    double worst = 0.0;
    for (size_t i = 0; i < n * 6; i++)
        worst = fmax(worst, fabs(a[i] - b[i]));
    print_message("one influence: dual quaternion vs linear blend %.2e\n", worst);
    assert_true(worst < 2e-5);
    free(a);
    free(b);
    free(pal);
    free(dqp);
    free(worlds);
    sinew_model_free(m);
}

/* Tangents read from a glTF file (TANGENT, w flipped for sinew's v-up UVs) survive a .sinew
 * round trip and are skinned: under the twist they stay unit length, perpendicular to the
 * skinned normals and turned about the tube's axis like the surface (SIMD = scalar). */
static void test_tangents_read_and_skinned(void **state)
{
    (void)state;
    char path[1024], saved[1024];
    sinew_model *m = load_or_fail(fixture_path("twist_tube.glb", path, sizeof path));
    const sinew_mesh *mesh = &m->meshes[0];
    assert_non_null(mesh->tangents);
    assert_float_equal(mesh->tangents[3], 1.0f, 0.0f);  /* +1 in the file: glTF's bitangent is sinew's +v */
    assert_float_equal(mesh->tangents[2], 1.0f, 1e-6f); /* vertex 0 at angle 0: tangent +z */
    tmp_path("twist_tube.sinew", saved, sizeof saved);
    assert_int_equal(sinew_model_save(m, NULL, saved, NULL), SINEW_OK);
    sinew_model *back = load_or_fail(saved);
    assert_non_null(back->meshes[0].tangents);
    assert_memory_equal(back->meshes[0].tangents, mesh->tangents, mesh->vertex_count * 16);
    sinew_model_free(back);
    sinew_mat4 *worlds = pose_worlds(m, &m->clips[0], 2.0f);
    sinew_mat4 palette[2];
    assert_int_equal(sinew_skin_palette(&m->skins[0], worlds, m->node_count, palette, 2, NULL), SINEW_OK);
    size_t n = mesh->vertex_count;
    float *out = malloc(n * 12 * sizeof(float)), *ref = malloc(n * 12 * sizeof(float));
    sinew_skin_desc d = {.mesh = mesh,
                         .palette = palette,
                         .palette_count = 2,
                         .out_positions = out,
                         .out_normals = out + 3,
                         .out_tangents = out + 6,
                         .out_stride = 48};
    assert_int_equal(sinew_skin_vertices(&d, NULL), SINEW_OK);
    d.out_positions = ref, d.out_normals = ref + 3, d.out_tangents = ref + 6;
    assert_int_equal(sinew_skin_vertices_scalar(&d, NULL), SINEW_OK);
    double worst_dot = 0.0, worst_len = 0.0, worst_ref = 0.0;
    for (size_t v = 0; v < n; v++) {
        const float *nv = out + v * 12 + 3, *t = out + v * 12 + 6;
        worst_dot = fmax(worst_dot, fabs(nv[0] * t[0] + nv[1] * t[1] + nv[2] * t[2]));
        worst_len = fmax(worst_len, fabs(sqrt(t[0] * t[0] + t[1] * t[1] + t[2] * t[2]) - 1.0));
        for (int e = 0; e < 10; e++)
            worst_ref = fmax(worst_ref, fabs(out[v * 12 + e] - ref[v * 12 + e]));
        assert_float_equal(t[3], 1.0f, 0.0f);
    }
    /* the top ring turned 170 degrees about y: its first tangent (+z at rest) points near -z */
    const float *top = out + (n - 24) * 12 + 6;
    print_message(
        "skinned tangents: |n.t| <= %.1e, | |t| - 1 | <= %.1e, SIMD vs scalar %.1e; top ring (%.3f %.3f %.3f)\n",
        worst_dot, worst_len, worst_ref, top[0], top[1], top[2]);
    assert_true(worst_dot < 1e-5 && worst_len < 1e-5 && worst_ref < 2e-6);
    assert_true(top[2] < -0.98f);
    free(out);
    free(ref);
    free(worlds);
    sinew_model_free(m);
}

/* FBX tangents (LayerElementTangent, handedness from LayerElementBinormal) on Maya's and
 * Blender's exports: unit length, perpendicular to the normals, handedness +-1 and agreeing
 * with the file's binormals (checked through normal x tangent against the v direction of the
 * UVs on each triangle). */
static void test_fbx_tangents(void **state)
{
    (void)state;
    static const char *const files[] = {"ufbx/maya_transformed_skin_7700_binary.fbx",
                                        "ufbx/maya_instanced_skin_7700_ascii.fbx", "assimp/FBX/huesitos.fbx"};
    for (size_t f = 0; f < sizeof files / sizeof files[0]; f++) {
        char path[1024];
        if (!testdata_path(files[f], path, sizeof path))
            skip();
        sinew_model *m = load_or_fail(path);
        for (uint32_t i = 0; i < m->mesh_count; i++) {
            const sinew_mesh *mesh = &m->meshes[i];
            assert_non_null(mesh->tangents);
            double worst_dot = 0.0, worst_len = 0.0;
            for (uint32_t v = 0; v < mesh->vertex_count; v++) {
                const float *t = &mesh->tangents[v * 4], *n = &mesh->normals[v * 3];
                worst_dot = fmax(worst_dot, fabs(t[0] * n[0] + t[1] * n[1] + t[2] * n[2]));
                worst_len = fmax(worst_len, fabs(sqrt(t[0] * t[0] + t[1] * t[1] + t[2] * t[2]) - 1.0));
                assert_true(t[3] == 1.0f || t[3] == -1.0f);
            }
            /* the bitangent w * n x t points along +v on every triangle with a UV gradient */
            uint32_t triangles = 0, agree = bitangents_along_v(mesh, &triangles);
            print_message("%s mesh %u: %u vertices, |n.t| <= %.1e, | |t| - 1 | <= %.1e, bitangent along +v on %u of "
                          "%u triangles\n",
                          files[f], i, mesh->vertex_count, worst_dot, worst_len, agree, triangles);
            assert_true(worst_len < 1e-5);
            assert_true(worst_dot < 1e-3);
            assert_true(agree * 10 >= triangles * 9);
        }
        sinew_model_free(m);
    }
}

/* ---- the job system ---- */

typedef struct job_check {
    _Atomic uint32_t *visits;
    _Atomic uint32_t bad_thread;
    uint32_t threads;
} job_check;

static void count_visits(void *user, uint32_t first, uint32_t count, uint32_t thread)
{
    job_check *c = user;
    if (thread >= c->threads)
        atomic_fetch_add(&c->bad_thread, 1);
    for (uint32_t i = first; i < first + count; i++)
        atomic_fetch_add(&c->visits[i], 1);
}

/* Every item is visited exactly once, by a thread index in range, for any thread count
 * (more threads than processors too), grain and total; thousands of back-to-back runs lose
 * nothing (a late worker cannot take a chunk of the next run); runs after the workers went
 * to sleep still finish; NULL jobs runs inline. */
static void test_jobs(void **state)
{
    (void)state;
    enum { MAX = 5000 };
    static _Atomic uint32_t visits[MAX];
    const uint32_t thread_counts[] = {1, 2, 3, 8};
    const uint32_t totals[] = {0, 1, 17, MAX};
    const uint32_t grains[] = {0, 1, 7, 64, MAX};
    for (size_t t = 0; t < 4; t++) {
        sinew_jobs *jobs = NULL;
        sinew_jobs_desc desc = {.threads = thread_counts[t], .spin_us = 20};
        assert_int_equal(sinew_jobs_create(&desc, &jobs, NULL), SINEW_OK);
        assert_int_equal(sinew_jobs_threads(jobs), thread_counts[t]);
        job_check c = {.visits = visits, .threads = thread_counts[t]};
        for (size_t n = 0; n < 4; n++)
            for (size_t g = 0; g < 5; g++) {
                for (uint32_t i = 0; i < MAX; i++)
                    atomic_store(&visits[i], 0);
                sinew_jobs_run(jobs, totals[n], grains[g], count_visits, &c);
                for (uint32_t i = 0; i < MAX; i++)
                    assert_int_equal(atomic_load(&visits[i]), i < totals[n] ? 1 : 0);
            }
        /* back to back: 3000 runs of 40 items in chunks of 1 */
        for (uint32_t i = 0; i < 40; i++)
            atomic_store(&visits[i], 0);
        for (int run = 0; run < 3000; run++)
            sinew_jobs_run(jobs, 40, 1, count_visits, &c);
        for (uint32_t i = 0; i < 40; i++)
            assert_int_equal(atomic_load(&visits[i]), 3000);
        /* after the workers slept */
        usleep(3000);
        sinew_jobs_run(jobs, 40, 1, count_visits, &c);
        assert_int_equal(atomic_load(&visits[39]), 3001);
        assert_int_equal(atomic_load(&c.bad_thread), 0);
        sinew_jobs_free(jobs);
    }
    job_check inline_check = {.visits = visits, .threads = 1};
    atomic_store(&visits[3], 0);
    sinew_jobs_run(NULL, 10, 3, count_visits, &inline_check);
    assert_int_equal(atomic_load(&visits[3]), 1);
    sinew_jobs *jobs = NULL;
    sinew_error error = {0};
    assert_int_equal(sinew_jobs_create(&(sinew_jobs_desc){.threads = 257}, &jobs, &error),
                     SINEW_ERROR_INVALID_ARGUMENT);
    assert_non_null(strstr(error.message, "at most 256"));
    assert_true(sinew_cpu_count() >= 1);
    sinew_jobs_free(NULL);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_player_generated),
        cmocka_unit_test(test_player_real_files),
        cmocka_unit_test(test_player_arguments),
        cmocka_unit_test(test_skin_simd_matches_scalar),
        cmocka_unit_test(test_skin_dual_quaternion_twist),
        cmocka_unit_test(test_tangents_read_and_skinned),
        cmocka_unit_test(test_fbx_tangents),
        cmocka_unit_test(test_jobs),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
