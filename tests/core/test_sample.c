/* Sampling against values worked out by hand: step, linear, slerp across a sign flip,
 * cubic spline, loop and clamp, tracks with their own key times, one-key tracks, times
 * before the first and after the last key, key cursors. */
#include <math.h>
#include <string.h>

#include "helpers.h"

#define S45 0.70710678f

/* A one-node model whose rest pose is translation (9,9,9), identity, scale 1. */
static const char *const node_names[] = {"n"};
static const int32_t node_parents[] = {-1};
static const sinew_transform node_rest[] = {{{9, 9, 9}, {0, 0, 0, 1}, {1, 1, 1}}};
static const sinew_model one_node = {
    .source = "test", .node_count = 1, .node_names = node_names, .node_parents = node_parents, .node_rest = node_rest};

/* A clip of one track over the given key arrays. */
static sinew_clip one_track_clip(const sinew_track *track, float duration, const float *times, uint32_t time_count,
                                 const float *values, uint32_t value_count)
{
    return (sinew_clip){.name = "test",
                        .duration = duration,
                        .track_count = 1,
                        .tracks = track,
                        .time_count = time_count,
                        .value_count = value_count,
                        .times = times,
                        .values = values};
}

static sinew_transform sample(const sinew_clip *clip, float t, sinew_wrap wrap, sinew_sample_context *context)
{
    sinew_transform out;
    sinew_error error = {0};
    sinew_sample_desc desc = {.model = &one_node,
                              .clip = clip,
                              .time = t,
                              .wrap = wrap,
                              .context = context,
                              .locals = &out,
                              .local_count = 1};
    assert_int_equal(sinew_sample(&desc, &error), SINEW_OK);
    return out;
}

/* Translation x keyed 0, 10, 20 at t = 0, 1, 2. */
static const float line_times[] = {0, 1, 2};
static const float line_values[] = {0, 0, 0, 10, 0, 0, 20, 0, 0};

static sinew_clip line_clip(sinew_interp interp, sinew_track *track)
{
    memset(track, 0, sizeof *track);
    track->channels[SINEW_CHANNEL_TRANSLATION] = (sinew_channel){3, interp, 0, 0};
    return one_track_clip(track, 2, line_times, 3, line_values, 9);
}

static void test_step(void **state)
{
    (void)state;
    sinew_track track;
    sinew_clip clip = line_clip(SINEW_INTERP_STEP, &track);
    assert_near(sample(&clip, 0.0f, SINEW_WRAP_CLAMP, NULL).translation[0], 0, 0, "step t=0");
    assert_near(sample(&clip, 0.99f, SINEW_WRAP_CLAMP, NULL).translation[0], 0, 0, "step t=0.99");
    assert_near(sample(&clip, 1.0f, SINEW_WRAP_CLAMP, NULL).translation[0], 10, 0, "step t=1");
    assert_near(sample(&clip, 1.5f, SINEW_WRAP_CLAMP, NULL).translation[0], 10, 0, "step t=1.5");
    assert_near(sample(&clip, 2.0f, SINEW_WRAP_CLAMP, NULL).translation[0], 20, 0, "step t=2");
}

static void test_linear_and_untracked_channels(void **state)
{
    (void)state;
    sinew_track track;
    sinew_clip clip = line_clip(SINEW_INTERP_LINEAR, &track);
    sinew_transform t = sample(&clip, 0.25f, SINEW_WRAP_CLAMP, NULL);
    assert_near(t.translation[0], 2.5, 1e-6, "linear t=0.25");
    assert_near(sample(&clip, 1.75f, SINEW_WRAP_CLAMP, NULL).translation[0], 17.5, 1e-5, "linear t=1.75");
    /* rotation and scale are not tracked: they keep the rest values */
    assert_near(t.rotation[3], 1, 0, "rest rotation w");
    assert_near(t.scale[1], 1, 0, "rest scale");
}

static void test_clamp_and_loop(void **state)
{
    (void)state;
    sinew_track track;
    sinew_clip clip = line_clip(SINEW_INTERP_LINEAR, &track);
    assert_near(sample(&clip, -1.0f, SINEW_WRAP_CLAMP, NULL).translation[0], 0, 0, "clamp before");
    assert_near(sample(&clip, 3.0f, SINEW_WRAP_CLAMP, NULL).translation[0], 20, 0, "clamp after");
    assert_near(sample(&clip, 2.5f, SINEW_WRAP_LOOP, NULL).translation[0], 5, 1e-5, "loop 2.5 -> 0.5");
    assert_near(sample(&clip, -0.5f, SINEW_WRAP_LOOP, NULL).translation[0], 15, 1e-5, "loop -0.5 -> 1.5");
    assert_near(sample(&clip, 4.25f, SINEW_WRAP_LOOP, NULL).translation[0], 2.5, 1e-5, "loop 4.25 -> 0.25");
    assert_near(sinew_clip_time(&clip, 7.0f, SINEW_WRAP_CLAMP), 2, 0, "clip time clamp");
    assert_near(sinew_clip_time(&clip, INFINITY, SINEW_WRAP_LOOP), 0, 0, "clip time of inf");
}

/* Rotation keys: identity at t=0, then 90 degrees about Z stored with the opposite sign. */
static const float flip_times[] = {0, 1};
static const float flip_values[] = {0, 0, 0, 1, 0, 0, -S45, -S45};

static void assert_quat_near(const float *q, float x, float y, float z, float w, const char *what)
{
    float dot = q[0] * x + q[1] * y + q[2] * z + q[3] * w;
    float sign = dot < 0 ? -1.0f : 1.0f; /* q and -q are the same rotation */
    assert_near(q[0] * sign, x, 1e-5, what);
    assert_near(q[1] * sign, y, 1e-5, what);
    assert_near(q[2] * sign, z, 1e-5, what);
    assert_near(q[3] * sign, w, 1e-5, what);
}

static void test_slerp_across_sign_flip(void **state)
{
    (void)state;
    sinew_track track = {0};
    track.channels[SINEW_CHANNEL_ROTATION] = (sinew_channel){2, SINEW_INTERP_LINEAR, 0, 0};
    sinew_clip clip = one_track_clip(&track, 1, flip_times, 2, flip_values, 8);
    assert_quat_near(sample(&clip, 0, SINEW_WRAP_CLAMP, NULL).rotation, 0, 0, 0, 1, "slerp 0");
    /* the short way: 45 degrees about +Z, not 135 degrees the long way round */
    assert_quat_near(sample(&clip, 0.5f, SINEW_WRAP_CLAMP, NULL).rotation, 0, 0, sinf((float)M_PI / 8),
                     cosf((float)M_PI / 8), "slerp 1/2");
    assert_quat_near(sample(&clip, 0.25f, SINEW_WRAP_CLAMP, NULL).rotation, 0, 0, sinf((float)M_PI / 16),
                     cosf((float)M_PI / 16), "slerp 1/4");
    assert_quat_near(sample(&clip, 1, SINEW_WRAP_CLAMP, NULL).rotation, 0, 0, S45, S45, "slerp 1");
}

/* Cubic translation x: value 0 -> 1 over 2 s, out-tangent of key 0 is 1 (per second),
 * in-tangent of key 1 is 0. p(s) = h00*0 + h10*dt*1 + h01*1 + h11*dt*0. */
static const float cubic_times[] = {0, 2};
static const float cubic_values[] = {
    /* key 0: in, value, out */ 5, 5, 5, 0, 0, 0, 1, 0, 0,
    /* key 1: in, value, out */ 0, 0, 0, 1, 0, 0, 7, 7, 7};

static void test_cubic_spline(void **state)
{
    (void)state;
    sinew_track track = {0};
    track.channels[SINEW_CHANNEL_TRANSLATION] = (sinew_channel){2, SINEW_INTERP_CUBIC, 0, 0};
    sinew_clip clip = one_track_clip(&track, 2, cubic_times, 2, cubic_values, 18);
    /* s = 0.5: h10 = 0.125, dt = 2 -> 0.25; h01 = 0.5 */
    assert_near(sample(&clip, 1, SINEW_WRAP_CLAMP, NULL).translation[0], 0.75, 1e-6, "cubic s=1/2");
    /* s = 0.25: h10 = 0.140625 -> 0.28125; h01 = 0.15625 */
    assert_near(sample(&clip, 0.5f, SINEW_WRAP_CLAMP, NULL).translation[0], 0.4375, 1e-6, "cubic s=1/4");
    /* the ends are the values, never the tangents */
    assert_near(sample(&clip, 0, SINEW_WRAP_CLAMP, NULL).translation[0], 0, 0, "cubic start");
    assert_near(sample(&clip, 2, SINEW_WRAP_CLAMP, NULL).translation[0], 1, 0, "cubic end");
    assert_near(sample(&clip, 5, SINEW_WRAP_CLAMP, NULL).translation[1], 0, 0, "cubic after end");
}

/* Bezier translation, keys at t = 0, 1, 3, each component its own curve:
 * x 0 -> 1 -> 0 eased (control times pulled towards the segment's ends, so it starts and
 * ends slowly), y 0 -> 3 -> 3 with control points at a third and two thirds of the way
 * (on the straight line, then level: y = 3 t, then 3), z constant 5. Layout of a key:
 * value[3], in time[3], in value[3], out time[3], out value[3]. */
static const float bezier_times[] = {0, 1, 3};
static const float bezier_values[] = {
    /* key 0 */ 0,
    0,
    5,
    0,
    0,
    0,
    0,
    0,
    5,
    0.9f,
    1.0f / 3,
    1.0f / 3,
    0,
    1,
    5,
    /* key 1 */ 1,
    3,
    5,
    0.1f,
    2.0f / 3,
    2.0f / 3,
    1,
    2,
    5,
    1.5f,
    1 + 2.0f / 3,
    1 + 2.0f / 3,
    1,
    3,
    5,
    /* key 2 */ 0,
    3,
    5,
    2.5f,
    1 + 4.0f / 3,
    1 + 4.0f / 3,
    0,
    3,
    5,
    3,
    3,
    3,
    0,
    3,
    5};

static void test_bezier(void **state)
{
    (void)state;
    sinew_track track = {0};
    track.channels[SINEW_CHANNEL_TRANSLATION] = (sinew_channel){3, SINEW_INTERP_BEZIER, 0, 0};
    sinew_clip clip = one_track_clip(&track, 3, bezier_times, 3, bezier_values, 45);
    test_player tp;
    sinew_player *player = test_player_open(&tp, &one_node, &clip);
    double most = 0, most_player = 0;
    for (int i = 0; i <= 300; i++) {
        float t = 3.0f * (float)i / 300;
        sinew_transform got = sample(&clip, t, SINEW_WRAP_CLAMP, NULL);
        int k = t < 1 ? 0 : 1;
        const float *a = bezier_values + k * 15, *b = a + 15;
        for (int c = 0; c < 3; c++) {
            const double points[4][2] = {
                {bezier_times[k], a[c]}, {a[9 + c], a[12 + c]}, {b[3 + c], b[6 + c]}, {bezier_times[k + 1], b[c]}};
            double want = bezier_reference(points, t);
            most = fmax(most, fabs(got.translation[c] - want));
        }
        /* y: control points evenly spaced in time and on a line make that line */
        assert_near(got.translation[1], k == 0 ? 3.0 * t : 3.0, 2e-6, "Bezier control points on a line");
        assert_near(got.translation[2], 5, 0, "a constant component");
        sinew_mat4 world;
        assert_int_equal(sinew_player_update(player, t, SINEW_WRAP_CLAMP, NULL, &world, 1, NULL), SINEW_OK);
        for (int c = 0; c < 3; c++)
            most_player = fmax(most_player, fabs(world.m[12 + c] - got.translation[c]));
    }
    print_message("Bezier: largest difference from the double-precision curve %.2g, player from sinew_sample %.2g\n",
                  most, most_player);
    assert_true(most < 1e-6);
    assert_true(most_player < 1e-6);
    /* eased: a tenth of the way in time, x has moved far less than a tenth */
    assert_true(sample(&clip, 0.1f, SINEW_WRAP_CLAMP, NULL).translation[0] < 0.05f);
    test_player_close(&tp);
}

/* Translation: 2 keys at 0 and 2. Rotation: 3 keys at 0.5, 1, 1.5 (starts late, ends early).
 * Scale: one key. */
static const float mixed_times[] = {0, 2, 0.5f, 1, 1.5f, 0.7f};
static const float mixed_values[] = {0, 0, 0, 4, 0, 0,                       /* translation */
                                     0, 0, 0, 1, 0, 0, S45, S45, 0, 0, 1, 0, /* rotation: 0, 90, 180 degrees about Z */
                                     3, 3, 3};                               /* scale */

static void test_channels_have_their_own_keys(void **state)
{
    (void)state;
    sinew_track track = {0};
    track.channels[SINEW_CHANNEL_TRANSLATION] = (sinew_channel){2, SINEW_INTERP_LINEAR, 0, 0};
    track.channels[SINEW_CHANNEL_ROTATION] = (sinew_channel){3, SINEW_INTERP_LINEAR, 2, 6};
    track.channels[SINEW_CHANNEL_SCALE] = (sinew_channel){1, SINEW_INTERP_LINEAR, 5, 18};
    sinew_clip clip = one_track_clip(&track, 2, mixed_times, 6, mixed_values, 21);
    sinew_transform t = sample(&clip, 0.75f, SINEW_WRAP_CLAMP, NULL);
    assert_near(t.translation[0], 1.5, 1e-6, "translation at 0.75");
    assert_quat_near(t.rotation, 0, 0, sinf((float)M_PI / 8), cosf((float)M_PI / 8), "rotation at 0.75");
    assert_near(t.scale[0], 3, 0, "one-key scale");
    /* before the first rotation key: the first key; after the last: the last */
    assert_quat_near(sample(&clip, 0.1f, SINEW_WRAP_CLAMP, NULL).rotation, 0, 0, 0, 1, "before first key");
    assert_quat_near(sample(&clip, 1.9f, SINEW_WRAP_CLAMP, NULL).rotation, 0, 0, 1, 0, "after last key");
    assert_near(sample(&clip, 1.9f, SINEW_WRAP_CLAMP, NULL).scale[2], 3, 0, "one-key scale late");
}

static void test_cursor_forward_and_back(void **state)
{
    (void)state;
    static const float times[] = {0, 0.1f, 0.2f, 0.3f, 0.4f, 0.5f, 0.6f, 0.7f, 0.8f, 0.9f, 1.0f};
    float values[33];
    for (int i = 0; i < 11; i++)
        values[i * 3] = (float)(i * i), values[i * 3 + 1] = 0, values[i * 3 + 2] = 0;
    sinew_track track = {0};
    track.channels[SINEW_CHANNEL_TRANSLATION] = (sinew_channel){11, SINEW_INTERP_LINEAR, 0, 0};
    sinew_clip clip = one_track_clip(&track, 1, times, 11, values, 33);
    unsigned char memory[256];
    sinew_sample_context *context = NULL;
    assert_true(sinew_sample_context_size(&clip) <= sizeof memory);
    assert_int_equal(sinew_sample_context_init(memory, sizeof memory, &clip, &context, NULL), SINEW_OK);
    const float sequence[] = {0, 0.05f, 0.33f, 0.34f, 0.95f, 0.12f, 0.0f, 0.99f, 0.5f, 0.5f, 2.5f, 0.61f};
    for (size_t i = 0; i < sizeof sequence / sizeof sequence[0]; i++) {
        float with = sample(&clip, sequence[i], SINEW_WRAP_LOOP, context).translation[0];
        float without = sample(&clip, sequence[i], SINEW_WRAP_LOOP, NULL).translation[0];
        assert_near(with, without, 0, "cursor result equals a fresh search");
    }
    /* a context made for another clip is refused */
    sinew_clip other = clip;
    sinew_transform out;
    sinew_error error = {0};
    sinew_sample_desc desc = {.model = &one_node, .clip = &other, .context = context, .locals = &out, .local_count = 1};
    assert_int_equal(sinew_sample(&desc, &error), SINEW_ERROR_INVALID_ARGUMENT);
    assert_non_null(strstr(error.message, "another clip"));
}

static void test_bad_spans(void **state)
{
    (void)state;
    sinew_transform out;
    sinew_error error = {0};
    sinew_sample_desc desc = {.model = &one_node, .locals = &out, .local_count = 0};
    assert_int_equal(sinew_sample(&desc, &error), SINEW_ERROR_INVALID_ARGUMENT);
    assert_non_null(strstr(error.message, "1 nodes"));
    desc.local_count = 1;
    desc.time = NAN;
    assert_int_equal(sinew_sample(&desc, &error), SINEW_ERROR_INVALID_ARGUMENT);
    desc.time = 0;
    assert_int_equal(sinew_sample(&desc, &error), SINEW_OK);
    assert_near(out.translation[0], 9, 0, "no clip: rest pose");
    unsigned char small[4];
    sinew_sample_context *context;
    assert_int_equal(sinew_sample_context_init(small, sizeof small, NULL, &context, &error),
                     SINEW_ERROR_INVALID_ARGUMENT);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_step),
        cmocka_unit_test(test_linear_and_untracked_channels),
        cmocka_unit_test(test_clamp_and_loop),
        cmocka_unit_test(test_slerp_across_sign_flip),
        cmocka_unit_test(test_cubic_spline),
        cmocka_unit_test(test_bezier),
        cmocka_unit_test(test_channels_have_their_own_keys),
        cmocka_unit_test(test_cursor_forward_and_back),
        cmocka_unit_test(test_bad_spans),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
