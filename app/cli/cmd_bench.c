/* `sinew bench`: speed measurements, reported per unit and as ratios. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "cjson.h"
#include "cli.h"

#define MUSCLE_USAGE                                                                                                   \
    "usage: sinew bench muscle [--json]\n"                                                                             \
    "  muscle   time to solve the shipped biceps (9 nodes) at a length, and to build its tube surface.\n"

static const char bench_usage[] =
    "usage: sinew bench render [FILE] [--clip C] [--size WxH] [--samples N] [--frames N] [display options]\n"
    "                          [--hdri FILE.hdr] [--png OUT]\n"
    "                          [--json]\n"
    "\n"
    "  render   frames per second of `sinew render`'s drawing (pose, palette, draw, glFinish; no read-back)\n"
    "           with GPU skinning and with CPU skinning, at 1280x720 by default, with 4x multisampling\n"
    "           and without (--samples N measures only N); display options as `sinew render` takes them\n"
    "           (--shading pbr, --shadows, --ssao, --outline, --hdri-background, --tone-mapping ...).\n"
    "           FILE defaults to a generated 64-joint character of 10,016 vertices, 4 influences each.\n"
    "           The clip plays forward at 60 Hz from 0, looping; N frames (default 300) after 10 warm-up frames.\n"
    "           --png OUT writes the last GPU-skinned frame, to see what was measured.\n"
    "\n"
    "usage: sinew bench crowd [FILE] [--count N] [--threads N] [--size WxH] [--samples N] [--json]\n"
    "  crowd    characters drawn at 60 fps, GPU (instanced) and CPU skinning, with and without MSAA\n"
    "           (`sinew bench crowd --help` says how)\n"
    "\n"
    "usage: sinew bench eval [--json] [--threads N] [--collada FILE.dae] [--fbx FILE.fbx] [--quick]\n"
    "  eval     the runtime's speed: sampling + world matrices, skinning, 1000 characters, .sinew loading,\n"
    "           and with --fbx importing an FBX file by sinew's reader against Assimp\n"
    "           (`sinew bench eval --help` says what each figure is)\n"
    "\n" MUSCLE_USAGE;

typedef struct render_bench_args {
    const char *path, *clip, *png, *hdri;
    sinew_render_options options;
    char display[256]; /* the display options given, as typed */
    int width, height, frames, samples;
    bool json;
} render_bench_args;

/* Opens a scene (FILE, or the generated character) and times it with one skinning mode. */
static int run_render_bench(const render_bench_args *a, int samples, int mode, double *spf, char *source,
                            size_t source_size, char *gl_name, size_t gl_size, uint32_t *vertices, uint32_t *joints)
{
    cli_scene_desc d = {.scene = {.path = a->path, .clip = a->clip},
                        .width = a->width,
                        .height = a->height,
                        .samples = samples,
                        .loop = true,
                        .hdri = a->hdri,
                        .options = a->options};
    d.options.skinning = mode ? SINEW_SKINNING_CPU : SINEW_SKINNING_GPU;
    if (!a->path) {
        sinew_error error = {0};
        sinew_synthetic_desc sd = {.joints = 64, .vertices = 10000, .influences = 4};
        if (sinew_synthetic_model(&sd, &d.scene.model, &error) != SINEW_OK) {
            cli_error("%s", error.message);
            return EXIT_BAD_INPUT;
        }
    }
    cli_scene scene;
    int code = cli_scene_open(&scene, &d);
    if (code != EXIT_OK)
        return code;
    bool ok = cli_scene_frame_all(&scene, 0.0, scene.clip ? scene.clip->duration : 0.0) &&
              cli_scene_time_frames(&scene, 10, a->frames, spf, NULL);
    bool written = true;
    if (ok && a->png && mode == 0)
        ok = cli_scene_read(&scene) && (written = cli_write_image(a->png, scene.pixels, a->width, a->height, false));
    *vertices = app_vertex_count(scene.model);
    *joints = 0;
    for (uint32_t s = 0; s < scene.model->skin_count; s++)
        *joints += scene.model->skins[s].joint_count;
    snprintf(source, source_size, "%s", scene.model->source);
    snprintf(gl_name, gl_size, "%s", scene.gl_name);
    cli_scene_close(&scene);
    return ok ? EXIT_OK : !written ? EXIT_OUTPUT : EXIT_BAD_INPUT;
}

static int bench_render(int argc, char **argv)
{
    render_bench_args a = {.width = 1280, .height = 720, .frames = 300, .options = sinew_render_options_default()};
    for (int i = 1; i < argc; i++) {
        const char *o = argv[i];
        bool v = i + 1 < argc;
        sinew_error error = {0};
        int used = app_render_option_parse(&a.options, argc, argv, i, NULL, &error);
        if (used < 0) {
            cli_error("bench render: %s", error.message);
            return EXIT_USAGE;
        }
        if (used > 0) {
            for (int k = 0; k < used; k++) {
                size_t n = strlen(a.display);
                snprintf(a.display + n, sizeof a.display - n, "%s%s", n ? " " : "", argv[i + k]);
            }
            i += used - 1;
            continue;
        }
        if (cli_is_help(o)) {
            fputs(bench_usage, stdout);
            return EXIT_OK;
        } else if (strcmp(o, "--json") == 0) {
            a.json = true;
        } else if (strcmp(o, "--samples") == 0 && v) {
            long n = 0;
            if (!cli_parse_count("bench render", o, argv[++i], 1, CLI_MAX_SAMPLES, &n))
                return EXIT_USAGE;
            a.samples = (int)n;
        } else if (strcmp(o, "--png") == 0 && v) {
            a.png = argv[++i];
        } else if (strcmp(o, "--clip") == 0 && v) {
            a.clip = argv[++i];
        } else if (strcmp(o, "--hdri") == 0 && v) {
            a.hdri = argv[++i];
        } else if (strcmp(o, "--frames") == 0 && v) {
            long n = 0;
            if (!cli_parse_count("bench render", o, argv[++i], 1, 100000, &n))
                return EXIT_USAGE;
            a.frames = (int)n;
        } else if (strcmp(o, "--size") == 0 && v) {
            if (!cli_parse_size("bench render", argv[++i], &a.width, &a.height))
                return EXIT_USAGE;
        } else if (o[0] == '-') {
            cli_error("bench render: unknown option or missing value \"%s\"\n%s", o, bench_usage);
            return EXIT_USAGE;
        } else {
            a.path = o;
        }
    }
    /* Seconds a frame: [sample setting][0 GPU, 1 CPU skinning]. */
    int settings[2] = {a.samples ? a.samples : 4, 1};
    int setting_count = a.samples ? 1 : 2;
    double spf[2][2] = {{0, 0}, {0, 0}};
    char gl_name[320] = "", source[512] = "";
    uint32_t vertices = 0, joints = 0;
    for (int k = 0; k < setting_count; k++)
        for (int mode = 0; mode < 2; mode++) {
            int code = run_render_bench(&a, settings[k], mode, &spf[k][mode], source, sizeof source, gl_name,
                                        sizeof gl_name, &vertices, &joints);
            if (code != EXIT_OK)
                return code;
        }
    if (a.json) {
        cJSON *o = cJSON_CreateObject();
        cJSON_AddStringToObject(o, "model", source);
        cJSON_AddNumberToObject(o, "vertices", vertices);
        cJSON_AddNumberToObject(o, "joints", joints);
        cJSON_AddNumberToObject(o, "width", a.width);
        cJSON_AddNumberToObject(o, "height", a.height);
        cJSON_AddStringToObject(o, "gl", gl_name);
        cJSON_AddStringToObject(o, "display", a.display);
        cJSON_AddStringToObject(o, "hdri", a.hdri ? a.hdri : "");
        cJSON *runs = cJSON_AddArrayToObject(o, "runs");
        for (int k = 0; k < setting_count; k++) {
            cJSON *r = cJSON_CreateObject();
            cJSON_AddNumberToObject(r, "samples", settings[k]);
            cJSON_AddNumberToObject(r, "gpu_skinning_fps", 1.0 / spf[k][0]);
            cJSON_AddNumberToObject(r, "cpu_skinning_fps", 1.0 / spf[k][1]);
            cJSON_AddItemToArray(runs, r);
        }
        cli_json_print(o, true);
        return EXIT_OK;
    }
    printf("model:   %s (%u vertices, %u joints)\n", source, vertices, joints);
    printf("target:  %dx%d, %s, display: %s\n", a.width, a.height, gl_name, a.display[0] ? a.display : "defaults");
    for (int k = 0; k < setting_count; k++) {
        printf("%dx MSAA, GPU skinning: %8.1f fps  %7.3f ms/frame\n", settings[k], 1.0 / spf[k][0], spf[k][0] * 1e3);
        printf("%dx MSAA, CPU skinning: %8.1f fps  %7.3f ms/frame  (GPU/CPU time %.2f)\n", settings[k], 1.0 / spf[k][1],
               spf[k][1] * 1e3, spf[k][0] / spf[k][1]);
    }
    return EXIT_OK;
}

/* Solve and surface cost of one muscle (the shipped biceps: 9 nodes, 24 segments). */
static const char muscle_usage[] = MUSCLE_USAGE;

static int bench_muscle(int argc, char **argv)
{
    bool json = false;
    for (int i = 1; i < argc; i++) {
        if (cli_is_help(argv[i])) {
            fputs(muscle_usage, stdout);
            return EXIT_OK;
        } else if (strcmp(argv[i], "--json") == 0) {
            json = true;
        } else {
            cli_error("bench muscle: unknown option %s\n%s", argv[i], muscle_usage);
            return EXIT_USAGE;
        }
    }
    char path[4096];
    sinew_muscle_set *set = NULL;
    sinew_error error = {0};
    if (sinew_muscle_set_read(app_data_path("arm.muscles.json", path, sizeof path), &set, &error) != SINEW_OK) {
        cli_error("%s", error.message);
        return EXIT_BAD_INPUT;
    }
    const sinew_muscle_def *m = &set->muscles[0];
    sinew_muscle_profile profile = {m->node_count, m->radii, m->coefficients, m->rest_length};
    double radii[SINEW_MUSCLE_MAX_NODES], drift = 0.0, sink = 0.0;
    const int solves = 2000000;
    double start = cli_now_seconds();
    for (int i = 0; i < solves; i++) {
        double length = m->rest_length * (0.75 + 0.5 * (double)(i % 1000) / 1000.0);
        sinew_muscle_state st;
        if (sinew_muscle_solve(&profile, length, radii, SINEW_MUSCLE_MAX_NODES, &st, NULL) != SINEW_OK)
            continue;
        sink += radii[m->node_count / 2];
        if (i < 1000)
            drift = fmax(drift, fabs(st.volume - st.rest_volume) / st.rest_volume);
    }
    double solve_ns = (cli_now_seconds() - start) / solves * 1e9;
    uint32_t nv, ni;
    sinew_muscle_surface_size(m->node_count, m->segments, &nv, &ni);
    float *vertices = malloc((size_t)nv * 24);
    uint32_t *indices = malloc((size_t)ni * 4);
    const int surfaces = 20000;
    start = cli_now_seconds();
    for (int i = 0; vertices && indices && i < surfaces; i++) {
        sinew_muscle_surface_desc d = {.node_count = m->node_count,
                                       .radii = radii,
                                       .insertion = {0.0f, 0.0f, 0.3f},
                                       .segments = m->segments,
                                       .out_positions = vertices,
                                       .out_normals = vertices + 3,
                                       .out_stride = 24,
                                       .vertex_capacity = nv,
                                       .out_indices = indices,
                                       .index_capacity = ni};
        sinew_muscle_surface(&d, NULL);
    }
    double surface_us = (cli_now_seconds() - start) / surfaces * 1e6;
    free(vertices);
    free(indices);
    if (json)
        printf("{\"muscle\": \"%s\", \"nodes\": %u, \"solve_ns\": %.1f, \"surface_us\": %.2f, "
               "\"surface_vertices\": %u, \"volume_drift\": %.3g}\n",
               m->name, m->node_count, solve_ns, surface_us, nv, drift);
    else
        printf("muscle %s (%u nodes): solve %.1f ns (volume drift %.2g); surface of %u vertices %.2f us%s\n", m->name,
               m->node_count, solve_ns, drift, nv, surface_us, sink < 0.0 ? " " : "");
    sinew_muscle_set_free(set);
    return EXIT_OK;
}

int cmd_bench(int argc, char **argv)
{
    if (argc < 2 || cli_is_help(argv[1])) {
        fputs(bench_usage, argc < 2 ? stderr : stdout);
        return argc < 2 ? EXIT_USAGE : EXIT_OK;
    }
    if (strcmp(argv[1], "render") == 0)
        return bench_render(argc - 1, argv + 1);
    if (strcmp(argv[1], "crowd") == 0)
        return bench_crowd(argc - 1, argv + 1);
    if (strcmp(argv[1], "eval") == 0)
        return bench_eval(argc - 1, argv + 1);
    if (strcmp(argv[1], "muscle") == 0)
        return bench_muscle(argc - 1, argv + 1);
    cli_error("bench: unknown benchmark \"%s\"\n%s", argv[1], bench_usage);
    return EXIT_USAGE;
}
