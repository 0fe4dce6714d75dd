/* `sinew bench crowd`: how many characters one frame can hold at 60 fps.
 *
 * A crowd (app_crowd: a grid, each character at its own time and clip) is posed on the CPU
 * by the job system and drawn by `sinew render --crowd`'s path: GPU skinning with instancing
 * (one draw a mesh for all characters) or CPU skinning (character after character). For each
 * skinning mode and multisampling setting the count is doubled from --count while a frame
 * (pose, palettes, draw, glFinish; no read-back) takes at most 1/60 s, then bisected to within
 * 5%: that is characters_at_60fps. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "cjson.h"
#include "cli.h"

static const char crowd_usage[] =
    "usage: sinew bench crowd [FILE] [--clip C] [--count N] [--most N] [--threads N] [--size WxH] [--samples N]\n"
    "                         [--skinning gpu|cpu] [--lod on|off] [--fps F] [--frames N] [--png OUT] [--json]\n"
    "                         [--verbose]\n"
    "\n"
    "  Characters of FILE (default: the demo humanoid, builtin:demo) drawn at 60 fps: for GPU skinning\n"
    "  (instanced, one draw a mesh) and CPU skinning, with 4x multisampling and without, the crowd\n"
    "  grows from --count (default 64) by doubling while a frame takes at most 1/60 s, then is bisected\n"
    "  to within 5% (--most N caps the count, default 100,000; --fps F holds F frames a second instead,\n"
    "  and the JSON key becomes characters_at_Ffps).\n"
    "  A frame: posing every character (sinew_character, on --threads threads, default: the cores),\n"
    "  palettes, the draw and glFinish; --frames N frames (default 20) after 5 warm-up frames, at --size\n"
    "  (default 1920x1080), the camera framing the grid (of at least 256, so that a small crowd does not\n"
    "  fill the screen). --samples N or --skinning M measures only those. Characters small on the\n"
    "  screen are drawn with simplified meshes (levels of detail: a quarter, a sixteenth, ... of the\n"
    "  triangles); --lod off draws every one whole. --png OUT writes the last\n"
    "  GPU-skinned crowd measured. --json prints characters_at_60fps (GPU skinning, no multisampling,\n"
    "  or the one setting asked for), renderer, and every run (frame_ms; pose_ms, posing alone;\n"
    "  submit_ms, the frame before glFinish: posing, palettes, uploads and GL calls, the CPU's share);\n"
    "  --verbose prints each count tried on stderr.\n";

typedef struct crowd_args {
    const char *path, *clip, *png;
    uint32_t count, threads, most;
    int width, height, frames, samples, skinning; /* skinning: -1 both, 0 GPU, 1 CPU */
    double fps;                                   /* the frame rate to hold (default 60) */
    bool json, verbose, no_lod;
} crowd_args;

typedef struct crowd_run {
    int samples, skinning;
    uint32_t characters; /* at 60 fps */
    double frame_ms;     /* at that count */
    double pose_ms;      /* of which posing on the CPU */
    double submit_ms;    /* of which before glFinish: posing, palettes, uploads, GL calls */
} crowd_run;

/* The camera frames a grid of at least this many characters: a small crowd is seen from as
 * far as a crowd of 256, so that fewer characters never cover more of the screen (on a
 * software renderer the pixels, not the vertices, would set the count). */
#define FRAMED 256

/* The scene's crowd made `count` characters (same spacing), framed. */
static bool resize_crowd(cli_scene *s, uint32_t count)
{
    sinew_error error = {0};
    s->crowd.frame_at_least = FRAMED;
    if (app_crowd_resize(&s->crowd, count, &error) != SINEW_OK) {
        cli_error("%s: %s", s->model->source, error.message);
        return false;
    }
    return cli_scene_frame_all(s, 0.0, 0.0);
}

/* Milliseconds a frame and of it posing, at the crowd's size. */
static bool time_crowd(cli_scene *s, int frames, double *frame_ms, double *pose_ms, double *submit_ms)
{
    double seconds = 0.0, submit = 0.0;
    if (!cli_scene_time_frames(s, 5, frames, &seconds, &submit))
        return false;
    *frame_ms = seconds * 1e3;
    *submit_ms = submit * 1e3;
    double t = (5 + frames) / 60.0, start = cli_now_seconds();
    for (int i = 0; i < frames; i++, t += 1.0 / 60.0)
        app_crowd_pose(&s->crowd, t);
    *pose_ms = (cli_now_seconds() - start) / frames * 1e3;
    return true;
}

static bool measure(cli_scene *s, const crowd_args *a, uint32_t n, double *frame_ms, double *pose_ms, double *submit_ms)
{
    if (!resize_crowd(s, n) || !time_crowd(s, a->frames, frame_ms, pose_ms, submit_ms))
        return false;
    if (a->verbose)
        fprintf(stderr, "  %6u characters: %8.2f ms a frame, %6.2f ms posing, %6.2f ms before glFinish\n", n, *frame_ms,
                *pose_ms, *submit_ms);
    return true;
}

/* The largest count whose frame fits 1/60 s (0: not even one). */
static bool search(cli_scene *s, const crowd_args *a, crowd_run *run)
{
    const double budget = 1000.0 / a->fps;
    uint32_t good = 0, bad = 0, n = a->count;
    double ms = 0.0, pose = 0.0, submit = 0.0;
    while (true) { /* bracket: good fits, bad does not (0: not found yet) */
        if (!measure(s, a, n, &ms, &pose, &submit))
            return false;
        if (ms <= budget) {
            good = n, run->frame_ms = ms, run->pose_ms = pose, run->submit_ms = submit;
            if (bad || n >= a->most)
                break;
            n = n * 2 > a->most ? a->most : n * 2;
        } else {
            bad = n;
            if (good || n == 1)
                break;
            n /= 2;
        }
    }
    while (good && bad && bad - good > (good / 20 > 1 ? good / 20 : 1)) {
        n = good + (bad - good) / 2;
        if (!measure(s, a, n, &ms, &pose, &submit))
            return false;
        if (ms <= budget)
            good = n, run->frame_ms = ms, run->pose_ms = pose, run->submit_ms = submit;
        else
            bad = n;
    }
    run->characters = good;
    return true;
}

static int parse_crowd_args(int argc, char **argv, crowd_args *a)
{
    for (int i = 1; i < argc; i++) {
        const char *o = argv[i];
        bool v = i + 1 < argc;
        long n = 0;
        if (cli_is_help(o)) {
            fputs(crowd_usage, stdout);
            return EXIT_OK;
        } else if (strcmp(o, "--json") == 0) {
            a->json = true;
        } else if (strcmp(o, "--verbose") == 0 || strcmp(o, "-v") == 0) {
            a->verbose = true;
        } else if (strcmp(o, "--threads") == 0) {
            if (!cli_threads_arg(argc, argv, &i, 256, &a->threads))
                return EXIT_USAGE;
        } else if (strcmp(o, "--fps") == 0 && v) {
            if (!cli_parse_count("bench crowd", o, argv[++i], 1, 1000, &n))
                return EXIT_USAGE;
            a->fps = (double)n;
        } else if (strcmp(o, "--most") == 0 && v) {
            if (!cli_parse_count("bench crowd", o, argv[++i], 1, APP_CROWD_MAX, &n))
                return EXIT_USAGE;
            a->most = (uint32_t)n;
        } else if (strcmp(o, "--count") == 0 && v) {
            if (!cli_parse_count("bench crowd", o, argv[++i], 1, APP_CROWD_MAX, &n))
                return EXIT_USAGE;
            a->count = (uint32_t)n;
        } else if (strcmp(o, "--samples") == 0 && v) {
            if (!cli_parse_count("bench crowd", o, argv[++i], 1, CLI_MAX_SAMPLES, &n))
                return EXIT_USAGE;
            a->samples = (int)n;
        } else if (strcmp(o, "--frames") == 0 && v) {
            if (!cli_parse_count("bench crowd", o, argv[++i], 1, 100000, &n))
                return EXIT_USAGE;
            a->frames = (int)n;
        } else if (strcmp(o, "--skinning") == 0 && v) {
            const char *m = argv[++i];
            if (strcmp(m, "gpu") != 0 && strcmp(m, "cpu") != 0) {
                cli_error("bench crowd: --skinning \"%s\": expected gpu or cpu", m);
                return EXIT_USAGE;
            }
            a->skinning = m[0] == 'c';
        } else if (strcmp(o, "--lod") == 0 && v) {
            const char *m = argv[++i];
            if (strcmp(m, "on") != 0 && strcmp(m, "off") != 0) {
                cli_error("bench crowd: --lod \"%s\": expected on or off", m);
                return EXIT_USAGE;
            }
            a->no_lod = strcmp(m, "off") == 0;
        } else if (strcmp(o, "--size") == 0 && v) {
            if (!cli_parse_size("bench crowd", argv[++i], &a->width, &a->height))
                return EXIT_USAGE;
        } else if (strcmp(o, "--clip") == 0 && v) {
            a->clip = argv[++i];
        } else if (strcmp(o, "--png") == 0 && v) {
            a->png = argv[++i];
        } else if (o[0] == '-') {
            cli_error("bench crowd: unknown option or missing value \"%s\"\n%s", o, crowd_usage);
            return EXIT_USAGE;
        } else {
            a->path = o;
        }
    }
    return -1;
}

static void print_json(const crowd_args *a, const cli_scene *s, const crowd_run *runs, int run_count)
{
    cJSON *o = cJSON_CreateObject();
    cJSON_AddStringToObject(o, "model", s->model->source);
    cJSON_AddNumberToObject(o, "vertices", app_vertex_count(s->model));
    cJSON_AddNumberToObject(o, "joints", app_joint_count(s->model));
    cJSON_AddNumberToObject(o, "width", a->width);
    cJSON_AddNumberToObject(o, "height", a->height);
    cJSON_AddNumberToObject(o, "threads", sinew_jobs_threads(s->jobs));
    cJSON_AddStringToObject(o, "renderer", s->gl_name);
    cJSON_AddBoolToObject(o, "lod", !a->no_lod);
    char key[48];
    snprintf(key, sizeof key, "characters_at_%.0ffps", a->fps);
    cJSON_AddNumberToObject(o, key, runs[0].characters);
    cJSON_AddNumberToObject(o, "fps", a->fps);
    cJSON *list = cJSON_AddArrayToObject(o, "runs");
    for (int r = 0; r < run_count; r++) {
        cJSON *item = cJSON_CreateObject();
        cJSON_AddStringToObject(item, "skinning", runs[r].skinning ? "cpu" : "gpu");
        cJSON_AddNumberToObject(item, "samples", runs[r].samples);
        cJSON_AddNumberToObject(item, key, runs[r].characters);
        cJSON_AddNumberToObject(item, "frame_ms", runs[r].frame_ms);
        cJSON_AddNumberToObject(item, "pose_ms", runs[r].pose_ms);
        cJSON_AddNumberToObject(item, "submit_ms", runs[r].submit_ms);
        cJSON_AddItemToArray(list, item);
    }
    cli_json_print(o, true);
}

int bench_crowd(int argc, char **argv)
{
    crowd_args a = {
        .fps = 60.0, .count = 64, .most = APP_CROWD_MAX, .width = 1920, .height = 1080, .frames = 20, .skinning = -1};
    int code = parse_crowd_args(argc, argv, &a);
    if (code >= 0)
        return code;
    if (a.count > a.most)
        a.count = a.most;
    /* runs: GPU skinning first (the headline), no multisampling first */
    crowd_run runs[4];
    int run_count = 0;
    int samples[2] = {a.samples ? a.samples : 1, 4};
    for (int skinning = 0; skinning < 2; skinning++)
        for (int k = 0; k < (a.samples ? 1 : 2); k++)
            if (a.skinning < 0 || a.skinning == skinning)
                runs[run_count++] = (crowd_run){.samples = samples[k], .skinning = skinning};
    cli_scene last = {0};
    for (int r = 0; r < run_count; r++) {
        cli_scene_desc d = {.scene = {.path = a.path ? a.path : APP_BUILTIN_DEMO, .clip = a.clip},
                            .width = a.width,
                            .height = a.height,
                            .samples = runs[r].samples,
                            .loop = true,
                            .options = sinew_render_options_default(),
                            .crowd = 1,
                            .threads = a.threads};
        d.options.skinning = runs[r].skinning ? SINEW_SKINNING_CPU : SINEW_SKINNING_GPU;
        d.options.crowd_full_detail = a.no_lod;
        cli_scene s;
        code = cli_scene_open(&s, &d);
        if (code != EXIT_OK)
            return code;
        bool ok = search(&s, &a, &runs[r]);
        if (ok && !a.json)
            printf("%s skinning, %dx MSAA: %6u characters at %.0f fps (%.2f ms a frame, %.2f ms of it posing)\n",
                   runs[r].skinning ? "CPU" : "GPU", runs[r].samples, runs[r].characters, a.fps, runs[r].frame_ms,
                   runs[r].pose_ms);
        if (ok && a.png && r == 0 && runs[r].characters)
            ok = resize_crowd(&s, runs[r].characters) && cli_scene_draw(&s, 1.0) && cli_scene_read(&s) &&
                 cli_write_image(a.png, s.pixels, a.width, a.height, false);
        if (!ok) {
            cli_scene_close(&s);
            return EXIT_BAD_INPUT;
        }
        if (r == run_count - 1)
            last = s;
        else
            cli_scene_close(&s);
    }
    if (a.json)
        print_json(&a, &last, runs, run_count);
    else
        printf("(%s: %u vertices, %u joints; %dx%d; %u threads; %s)\n", last.model->source,
               app_vertex_count(last.model), app_joint_count(last.model), a.width, a.height,
               sinew_jobs_threads(last.jobs), last.gl_name);
    cli_scene_close(&last);
    return EXIT_OK;
}
