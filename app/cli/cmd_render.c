/* `sinew render FILE`: draws frames headless (EGL, no window) to PNG files or a video. */
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "cli.h"

static const char render_usage[] =
    "usage: sinew render FILE [--clip C] [--time T] [--size WxH] [--camera SPEC] [display options] -o OUT.png\n"
    "       sinew render FILE [--clip C] [--from A] [--to B] [--fps N] [...] -o DIR/frame%04d.png | -o OUT.mp4\n"
    "\n"
    "Renders FILE's animation off-screen with OpenGL (Mesa's llvmpipe without a GPU) and writes images (PNG,\n"
    "JPEG, BMP or TGA, by the extension) or a video (MP4, WebM, MKV, MOV or GIF) through the ffmpeg program.\n"
    "Missing output folders are made.\n"
    "\n"
    "  --clip C            clip by name or index (default: the first; none: the rest pose)\n"
    "  --time T            the moment in seconds for one image (default 0)\n"
    "  --from A --to B     a sequence from A to B seconds, both included (default: the whole clip)\n"
    "  --fps N             frames per second of the sequence (default 30)\n"
    "  --loop              wrap times outside the clip instead of clamping\n"
    "  --track             the camera follows the clip's root (a capture's hips) over the ground\n"
    "  --turntable [DEG]   the camera turns DEG degrees (default 360) around the model over a sequence\n"
    "  --size WxH          image size in pixels (default 1280x720)\n"
    "  --samples N         multisampling (default 4, 1 = off, at most 16; clamped to what OpenGL offers)\n"
    "  --camera SPEC       orbit:YAW,PITCH[,DISTANCE] or fly:X,Y,Z,YAW,PITCH, degrees and metres, or a view\n"
    "                      along an axis: front, back, left, right (side), top, bottom\n"
    "                      (default orbit:30,15: framed on the posed model over the frames drawn)\n"
    "  --ortho             orthographic (parallel) projection, framed as the perspective view\n"
    "  --camera-position X,Y,Z     the eye, in world metres (as f3d's); the camera looks at the focal point\n"
    "  --camera-focal-point X,Y,Z  the point looked at and orbited (default: the framed centre)\n"
    "  --fov DEG           vertical field of view (default 45; framing fits the model to it)\n"
    "  --up [+|-]X|Y|Z     which of the file's axes is up, as f3d's (default +Y; Z for files modelled Z up that\n"
    "                      do not say so)\n"
    "  --anim OTHER [--name-map M.json]  OTHER's clips retargeted onto FILE's skeleton (first in its clip list)\n"
    "  --blend C:W,C:W --additive C:W --crossfade A,B,T --ik JOINT:X,Y,Z --root-motion --morph MESH:TARGET=W\n"
    "                      combine clips, as `sinew pose --help` says\n"
    "  -o, --output PATH   OUT.png (.jpg .bmp .tga), a pattern with one %d (frame number), or OUT.mp4\n"
    "                      (.webm .mkv .mov .gif)\n"
    "\n"
    "display options (--NAME or --NAME on turns a switch on, --no-NAME or --NAME off turns it off):\n"
    "  --materials --lighting --grid           on by default\n"
    "  --skeleton (--bones) --joint-axes --joint-names --wireframe --normals --axes\n"
    "                                          off by default (a file without meshes shows its skeleton)\n"
    "  --meshes                                on by default; --no-meshes shows the skeleton alone\n"
    "  --shading phong|gouraud|flat|pbr        lit per pixel (default), per vertex, per triangle, or physically\n"
    "                                          based (glTF metallic-roughness, normal/occlusion/emissive maps,\n"
    "                                          image-based lighting, tone mapped)\n"

    "  --skinning gpu|cpu                      vertex shader (default) or the library's CPU skinning\n"
    "  --select JOINT                          highlight a joint (name) and show its name\n"
    "  --heatmap JOINT                         colour the mesh by that joint's skin weights\n"
    "  --background RRGGBB                     background colour (default 292b30)\n"
    "  --normal-length L                       length of drawn normals (default 3% of the model)\n"
    "  --gpu-joint-limit N                     skin larger skins on the CPU (tests the fallback)\n"
    "  --muscles [M.json]                      attach and draw muscles (M, or FILE's stem + .muscles.json);\n"
    "                                          --no-muscles hides them\n"
    "  --skinning-method file|lbs|dqs          each skin as its file asks (default: linear, dual quaternion, or\n"
    "                                          the two mixed per vertex), or linear blend / dual quaternions\n"
    "                                          for every skin\n";

static const char render_usage_look[] =
    "\n"
    "look (`sinew-view` takes the same; settings keep them):\n"
    "  --hdri FILE.hdr                         the environment lighting PBR (equirectangular; default: a\n"
    "                                          built-in neutral studio with key and fill lights)\n"
    "  --hdri-background                       the environment, blurred, behind the model\n"
    "  --tone-mapping auto|none|aces|neutral   auto: Khronos PBR Neutral for pbr, none for the others\n"
    "  --exposure EV                           brighter or darker by EV stops (default 0)\n"
    "  --shadows --ssao --outline              the key light's shadows (on the model and the ground),\n"
    "                                          ambient occlusion, dark edges; off by default\n"
    "  --fxaa                                  fast approximate anti-aliasing after drawing (where\n"
    "                                          multisampling is refused; on llvmpipe it costs more than it)\n";

static const char render_usage_crowds[] =
    "\n"
    "crowds:\n"
    "  --crowd N           N characters on a grid, each at its own time and clip (the --clip given, else\n"
    "                      the file's clips in turn); poses on the CPU, skinning on the GPU with instancing\n"
    "                      (one draw a mesh) or with --skinning cpu on the CPU; meshes and grid only;\n"
    "                      characters small on screen drawn with simplified meshes (--no-lod: whole)\n"
    "  --threads N         threads posing (and CPU-skinning) the crowd (default: the cores)\n";

#define MAX_FRAMES 100000

typedef struct render_args {
    const char *path, *clip, *out, *camera, *select, *heatmap, *muscles, *up, *anim, *name_map, *hdri;
    app_camera_placement placement;
    int width, height, samples;
    double time, from, to, fps, turntable;
    bool from_set, to_set, fps_set, loop, skeleton_set, track, orthographic;
    app_pose_spec ops;
    uint32_t gpu_joint_limit, crowd, threads;
    sinew_render_options options;
} render_args;

static bool parse_seconds(const char *option, const char *text, double *out)
{
    if (!app_parse_number(text, -APP_MAX_SECONDS, APP_MAX_SECONDS, out)) {
        cli_error("render: bad %s \"%s\": expected seconds (within +-%g)", option, text, APP_MAX_SECONDS);
        return false;
    }
    return true;
}

/* A display option (app_render_option_parse); returns the arguments used (0: not one). */
static int parse_display_option(int argc, char **argv, int i, render_args *a, bool *bad)
{
    const char *name = NULL;
    sinew_error error = {0};
    int used = app_render_option_parse(&a->options, argc, argv, i, &name, &error);
    if (used < 0) {
        cli_error("render: %s", error.message);
        *bad = true;
        return 1;
    }
    if (used > 0 && strcmp(name, "skeleton") == 0)
        a->skeleton_set = true;
    return used;
}

static int parse_value_option(int argc, char **argv, int i, render_args *a, bool *bad)
{
    const char *o = argv[i];
    if (i + 1 >= argc)
        return 0;
    const char *v = argv[i + 1];
    sinew_error error = {0};
    int placed = 0;
    if (strcmp(o, "--clip") == 0)
        a->clip = v;
    else if (strcmp(o, "-o") == 0 || strcmp(o, "--output") == 0)
        a->out = v;
    else if (strcmp(o, "--camera") == 0)
        a->camera = v;
    else if ((placed = app_camera_placement_parse(&a->placement, o, v, &error)) != 0) {
        if (placed < 0) {
            cli_error("render: %s", error.message);
            *bad = true;
        }
    } else if (strcmp(o, "--anim") == 0)
        a->anim = v;
    else if (strcmp(o, "--hdri") == 0)
        a->hdri = v;
    else if (strcmp(o, "--name-map") == 0)
        a->name_map = v;
    else if (strcmp(o, "--up") == 0) {
        a->up = v;
        if (!app_up_axis(v, NULL)) {
            cli_error("render: --up \"%s\": expected [+|-]x, y or z", v);
            *bad = true;
        }
    } else if (strcmp(o, "--select") == 0)
        a->select = v;
    else if (strcmp(o, "--heatmap") == 0)
        a->heatmap = v;
    else if (strcmp(o, "--time") == 0)
        *bad = !parse_seconds(o, v, &a->time);
    else if (strcmp(o, "--from") == 0)
        *bad = !parse_seconds(o, v, &a->from), a->from_set = true;
    else if (strcmp(o, "--to") == 0)
        *bad = !parse_seconds(o, v, &a->to), a->to_set = true;
    else if (strcmp(o, "--fps") == 0) {
        a->fps_set = true;
        if (!parse_seconds(o, v, &a->fps) || !(a->fps > 0.0 && a->fps <= 1000.0)) {
            cli_error("render: --fps \"%s\": expected a rate in (0, 1000]", v);
            *bad = true;
        }
    } else if (strcmp(o, "--size") == 0) {
        *bad = !cli_parse_size("render", v, &a->width, &a->height);
    } else if (strcmp(o, "--crowd") == 0 || strcmp(o, "--threads") == 0) {
        long n = 0;
        *bad = !cli_parse_count("render", o, v, 1, o[2] == 'c' ? APP_CROWD_MAX : 256, &n);
        *(o[2] == 'c' ? &a->crowd : &a->threads) = (uint32_t)n;
    } else if (strcmp(o, "--samples") == 0 || strcmp(o, "--gpu-joint-limit") == 0) {
        long n = 0;
        *bad = !cli_parse_count("render", o, v, 1, o[2] == 's' ? CLI_MAX_SAMPLES : 1 << 20, &n);
        if (o[2] == 's')
            a->samples = (int)n;
        else
            a->gpu_joint_limit = (uint32_t)n;
    } else
        return 0;
    return 2;
}

/* Returns -1 to go on, or an exit code. */
static int parse_render_args(int argc, char **argv, render_args *a)
{
    for (int i = 1; i < argc;) {
        const char *arg = argv[i];
        bool bad = false;
        if (cli_is_help(arg)) {
            fputs(render_usage, stdout);
            fputs(render_usage_look, stdout);
            fputs(render_usage_crowds, stdout);
            return EXIT_OK;
        }
        int used = 0;
        if (strcmp(arg, "--loop") == 0)
            a->loop = true, used = 1;
        if (strcmp(arg, "--track") == 0)
            a->track = true, used = 1;
        if (strcmp(arg, "--ortho") == 0 || strcmp(arg, "--orthographic") == 0)
            a->orthographic = true, used = 1;
        if (strcmp(arg, "--turntable") == 0) {
            a->turntable = 360.0, used = 1;
            char *end = NULL;
            double degrees = i + 1 < argc ? strtod(argv[i + 1], &end) : 0.0;
            if (end && end != argv[i + 1] && !*end) {
                if (!isfinite(degrees) || fabs(degrees) > 36000.0) {
                    cli_error("render: --turntable \"%s\": expected degrees within +-36000", argv[i + 1]);
                    return EXIT_USAGE;
                }
                a->turntable = degrees, used = 2;
            }
        }
        if (!used && (used = app_pose_option_parse(&a->ops, argc, argv, i)) > 0) {
            i += used;
            continue;
        }
        if (strcmp(arg, "--muscles") == 0) {
            a->muscles = cli_muscles_arg(argc, argv, &i);
            used = 1;
        }
        if (!used)
            used = parse_value_option(argc, argv, i, a, &bad);
        if (!used && arg[0] == '-' && arg[1] == '-')
            used = parse_display_option(argc, argv, i, a, &bad);
        if (bad)
            return EXIT_USAGE;
        if (!used) {
            if (arg[0] == '-' && arg[1]) {
                cli_error("render: unknown option or missing value \"%s\" (see `sinew render --help`)", arg);
                return EXIT_USAGE;
            }
            if (a->path) {
                cli_error("render: one FILE only (got \"%s\" and \"%s\")", a->path, arg);
                return EXIT_USAGE;
            }
            a->path = arg;
            used = 1;
        }
        i += used;
    }
    if (!a->path || !a->out) {
        cli_error("render: %s (see `sinew render --help`)", !a->path ? "no FILE given" : "no -o OUTPUT given");
        return EXIT_USAGE;
    }
    return -1;
}

typedef enum output_kind { OUTPUT_PNG, OUTPUT_PATTERN, OUTPUT_VIDEO } output_kind;

/* A pattern has exactly one %d, %Nd or %0Nd (N up to 9) and no other conversion (%% is a
 * percent sign). */
static bool is_frame_pattern(const char *path, bool *malformed)
{
    int conversions = 0;
    *malformed = false;
    for (const char *p = path; (p = strchr(p, '%')); p++) {
        if (p[1] == '%') {
            p++;
            continue;
        }
        const char *q = p + 1;
        while (*q >= '0' && *q <= '9')
            q++;
        long width = q > p + 1 ? strtol(p + 1, NULL, 10) : 0;
        if (*q != 'd' || q - (p + 1) > 2 || width > 9)
            *malformed = true;
        conversions++;
    }
    if (conversions > 1)
        *malformed = true;
    return conversions > 0;
}

int cmd_render(int argc, char **argv)
{
    render_args a = {.width = 1280, .height = 720, .fps = 30.0, .options = sinew_render_options_default()};
    int code = parse_render_args(argc, argv, &a);
    if (code >= 0)
        return code;
    bool malformed = false;
    app_image_format format = app_image_format_of(a.out);
    output_kind kind = format == APP_VIDEO                   ? OUTPUT_VIDEO
                       : is_frame_pattern(a.out, &malformed) ? OUTPUT_PATTERN
                                                             : OUTPUT_PNG;
    if (malformed) {
        cli_error("render: -o \"%s\": a frame pattern takes one %%d (or %%04d, up to %%09d) for the frame number",
                  a.out);
        return EXIT_USAGE;
    }
    if (format == APP_IMAGE_UNKNOWN) {
        cli_error("render: -o \"%s\": write images as .png, .jpg, .bmp or .tga, video as .mp4, .webm, .mkv, .mov or "
                  ".gif (through ffmpeg)",
                  a.out);
        return EXIT_USAGE;
    }
    bool sequence = a.from_set || a.to_set || a.fps_set;
    if (sequence && kind == OUTPUT_PNG) {
        cli_error("render: --from/--to/--fps write several frames: give -o DIR/frame%%04d.png or -o OUT.mp4");
        return EXIT_USAGE;
    }
    cli_scene_desc desc = {
        .scene = {.path = a.path, .clip = a.clip, .anim = a.anim, .name_map = a.name_map, .up = a.up, .pose = &a.ops},
        .width = a.width,
        .height = a.height,
        .samples = a.samples,
        .camera = a.camera,
        .placement = a.placement,
        .hdri = a.hdri,
        .select = a.select,
        .heatmap = a.heatmap,
        .loop = a.loop,
        .skeleton_set = a.skeleton_set,
        .orthographic = a.orthographic,
        .gpu_joint_limit = a.gpu_joint_limit,
        .muscles = a.muscles,
        .options = a.options,
        .crowd = a.crowd,
        .threads = a.threads};
    /* Never over an input: the model, or the muscle file. */
    const char *inputs[5] = {a.path, a.muscles && *a.muscles ? a.muscles : NULL, a.hdri, a.anim, a.name_map};
    sinew_error error = {0};
    if (kind != OUTPUT_PATTERN && app_output_check(a.out, inputs, 5, &error) != SINEW_OK) {
        cli_error("render: %s", error.message);
        return EXIT_OUTPUT;
    }
    /* Missing output folders are made, as other renderers and encoders do. */
    if (app_make_parent_folders(a.out, &error) != SINEW_OK) {
        cli_error("render: %s", error.message);
        return EXIT_OUTPUT;
    }
    cli_scene scene;
    code = cli_scene_open(&scene, &desc);
    if (code != EXIT_OK)
        return code;

    double from = a.time, to = a.time, step = 1.0;
    uint32_t frames = 1;
    if (kind != OUTPUT_PNG) {
        from = a.from_set ? a.from : 0.0;
        to = a.to_set ? a.to : (scene.clip ? scene.clip->duration : 0.0);
        if (to < from) {
            cli_error("render: --to %g is before --from %g", to, from);
            cli_scene_close(&scene);
            return EXIT_USAGE;
        }
        step = 1.0 / a.fps;
        double count = floor((to - from) * a.fps + 1e-6) + 1.0;
        if (count > MAX_FRAMES) {
            cli_error("render: %.0f frames is more than %d; lower --fps or shorten --from/--to", count, MAX_FRAMES);
            cli_scene_close(&scene);
            return EXIT_USAGE;
        }
        frames = (uint32_t)count;
    }
    cli_note_times(scene.clip, (const double[]){from, to}, from == to ? 1 : 2, a.loop);
    code = cli_scene_frame_all(&scene, from, a.track ? from : to) ? EXIT_OK : EXIT_BAD_INPUT;
    cli_video video = {.fd = -1};
    if (code == EXIT_OK && kind == OUTPUT_VIDEO) {
        cli_ignore_sigpipe();
        if (!cli_video_open(&video, a.out, a.width, a.height, a.fps))
            code = video.unavailable ? EXIT_UNAVAILABLE : video.write_failed ? EXIT_OUTPUT : EXIT_BAD_INPUT;
    }
    float yaw0 = scene.camera.yaw;
    cli_progress progress;
    cli_progress_start(&progress, a.out, frames);
    for (uint32_t f = 0; f < frames && code == EXIT_OK; f++) {
        cli_progress_update(&progress, f);
        double t = from + step * f;
        if (a.turntable != 0.0) /* a whole turn over the sequence ends where it started: the last frame stops short */
            scene.camera.yaw = yaw0 + (float)(a.turntable * 3.14159265358979 / 180.0 * f / (frames > 1 ? frames : 1));
        if ((a.track && !scene.crowd.count && !cli_scene_track(&scene, t)) || !cli_scene_draw(&scene, t) ||
            !cli_scene_read(&scene)) {
            code = EXIT_BAD_INPUT;
            break;
        }
        if (kind == OUTPUT_VIDEO) {
            if (!cli_video_write(&video, scene.pixels))
                code = EXIT_OUTPUT;
            continue;
        }
        char path[4096];
        if (kind == OUTPUT_PATTERN)
            snprintf(path, sizeof path, a.out, (int)f);
        else
            snprintf(path, sizeof path, "%s", a.out);
        if (kind == OUTPUT_PATTERN && app_output_check(path, inputs, 5, &error) != SINEW_OK) {
            cli_error("render: %s", error.message);
            code = EXIT_OUTPUT;
        } else if (!cli_write_image(path, scene.pixels, a.width, a.height, a.options.transparent)) {
            code = EXIT_OUTPUT;
        }
    }
    cli_progress_end(&progress);
    if (kind == OUTPUT_VIDEO && video.pid > 0 && !cli_video_close(&video, code == EXIT_OK) && code == EXIT_OK)
        code = EXIT_OUTPUT;
    if (code == EXIT_OK)
        printf("%s: %u frame%s %dx%d, t = %g..%g s, %s skinning, %s\n", a.out, frames, frames == 1 ? "" : "s", a.width,
               a.height, from, from + step * (frames - 1),
               scene.frame_options.skinning == SINEW_SKINNING_CPU ? "CPU" : "GPU", scene.gl_name);
    cli_scene_close(&scene);
    return code;
}
