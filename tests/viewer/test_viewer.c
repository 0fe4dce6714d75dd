/* sinew-view under Xvfb: a screenshot equals `sinew render` of the same view; a broken file
 * shows its error while the demo stays and the viewer leaves normally on --quit; the settings
 * file is read, overridden by the command line for one run, and written back. Skipped when
 * Xvfb is not installed. Every run has its own $XDG_CONFIG_HOME under the build's scratch. */
#include <signal.h>
#include <stdio.h>
#include <time.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <stb_image.h>

#include "helpers.h"

static pid_t xvfb;
static char display[16];

static int start_xvfb(void **state)
{
    (void)state;
    if (system("command -v Xvfb >/dev/null 2>&1") != 0) {
        print_message("Xvfb is not installed (scripts/deps.sh installs it): the sinew-view tests are skipped\n");
        return 0;
    }
    for (int n = 90 + getpid() % 50; n < 200; n++) {
        char lock[64];
        snprintf(lock, sizeof lock, "/tmp/.X%d-lock", n);
        if (access(lock, F_OK) == 0)
            continue;
        snprintf(display, sizeof display, ":%d", n);
        xvfb = fork();
        if (xvfb == 0) {
            freopen("/dev/null", "w", stderr);
            execlp("Xvfb", "Xvfb", display, "-screen", "0", "1280x800x24", "-nolisten", "tcp", (char *)NULL);
            _exit(127);
        }
        char socket_path[64];
        snprintf(socket_path, sizeof socket_path, "/tmp/.X11-unix/X%d", n);
        for (int tries = 0; tries < 100 && access(socket_path, F_OK) != 0; tries++)
            usleep(50000);
        return 0;
    }
    return 0;
}

static int stop_xvfb(void **state)
{
    (void)state;
    if (xvfb > 0) {
        kill(xvfb, SIGTERM);
        waitpid(xvfb, NULL, 0);
    }
    return 0;
}

/* GTK's renderer for the viewer's own widgets: software cairo, or NULL for GTK's choice. */
static const char *gsk_renderer = "cairo";

/* Starts sinew-view with DISPLAY set and its stderr to $SINEW_TMP/view.err; finish_view() waits. */
static pid_t start_view(const char *const *args)
{
    char errfile[4096];
    tmp_path("view.err", errfile, sizeof errfile);
    pid_t pid = fork();
    if (pid == 0) {
        setenv("DISPLAY", display, 1);
        char config[4096];
        setenv("XDG_CONFIG_HOME", tmp_path("view-config", config, sizeof config), 1);
        if (gsk_renderer) /* GTK's own drawing in software; the GL area is sinew's */
            setenv("GSK_RENDERER", gsk_renderer, 1);
        /* GTK and fontconfig keep allocations to the end of the process: not leaks of sinew's */
        setenv("ASAN_OPTIONS", "detect_leaks=0:abort_on_error=1", 1);
        freopen(errfile, "w", stderr);
        const char *argv[32] = {getenv("SINEW_VIEW")};
        for (int i = 0; args[i] && i < 30; i++)
            argv[i + 1] = args[i];
        execv(argv[0], (char *const *)argv);
        _exit(127);
    }
    return pid;
}

/* Waits for the viewer start_view() started; returns its exit code, stderr in *err (malloc'd). */
static int finish_view(pid_t pid, char **err)
{
    char errfile[4096];
    tmp_path("view.err", errfile, sizeof errfile);
    int status = 0;
    waitpid(pid, &status, 0);
    size_t size = 0;
    *err = read_file(errfile, &size);
    return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

/* Runs sinew-view to its end. */
static int run_view(const char *const *args, char **err)
{
    return finish_view(start_view(args), err);
}

static const char *demo_file(char *dae, size_t size)
{
    char dir[2048];
    tmp_path("view-demo", dir, sizeof dir);
    snprintf(dae, size, "%s/humanoid.dae", dir);
    if (access(dae, F_OK) != 0) {
        run_result r = RUN("demo", dir);
        assert_int_equal(r.code, 0);
        run_free(&r);
    }
    return dae;
}

/* The share of pixels that differ between the viewer's screenshot with `view_args` and `sinew
 * render` with `render_args` (both anti-aliased with 4 samples, or as the viewer's --samples says). */
static double differ_from_render(const char *const *view_args, const char *const *render_args)
{
    char shot[4096], rendered[4096], size[32];
    tmp_path("view-shot.png", shot, sizeof shot);
    tmp_path("view-render.png", rendered, sizeof rendered);
    const char *args[40];
    int k = 0;
    for (int i = 0; view_args[i]; i++)
        args[k++] = view_args[i];
    args[k++] = "--screenshot", args[k++] = shot, args[k++] = "--quit", args[k] = NULL;
    char *err = NULL;
    int code = run_view(args, &err);
    if (code != 0)
        fail_msg("sinew-view exited %d: %s", code, err ? err : "");
    free(err);
    int w, h, n;
    unsigned char *a = stbi_load(shot, &w, &h, &n, 3);
    assert_non_null(a);
    snprintf(size, sizeof size, "%dx%d", w, h);
    const char *rargs[40] = {"render"};
    k = 1;
    for (int i = 0; render_args[i]; i++)
        rargs[k++] = render_args[i];
    const char *samples = "4";
    for (int i = 0; view_args[i]; i++)
        if (strcmp(view_args[i], "--samples") == 0 && view_args[i + 1])
            samples = view_args[i + 1];
    rargs[k++] = "--samples", rargs[k++] = samples, rargs[k++] = "--size", rargs[k++] = size;
    rargs[k++] = "-o", rargs[k++] = rendered, rargs[k] = NULL;
    run_result r = run_sinew(NULL, rargs);
    assert_int_equal(r.code, 0);
    run_free(&r);
    int w2, h2;
    unsigned char *b = stbi_load(rendered, &w2, &h2, &n, 3);
    assert_non_null(b);
    assert_int_equal(w, w2);
    assert_int_equal(h, h2);
    long count = (long)w * h, differ = differing_pixels(a, b, count, NULL);
    print_message("viewer %dx%d vs sinew render: %ld of %ld pixels differ by more than %d levels\n", w, h, differ,
                  count, PIXEL_TOLERANCE);
    stbi_image_free(a);
    stbi_image_free(b);
    return (double)differ / (double)count;
}

/* The same view: the viewer's screenshot and `sinew render`'s picture match. */
static void compare_with_render(const char *const *view_args, const char *const *render_args)
{
    assert_true(differ_from_render(view_args, render_args) <= IMAGE_TOLERANCE);
}

static double now_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

/* Habits: Page Down opens the next file of the folder that sinew reads, at its start and framed on
 * its own; Right steps from
 * the frame the time is in (0.52 s at 30 keys a second is in frame 15: on to 16, not 17); Escape
 * quits (as f3d and GTK apps do). */
static void test_next_file_frame_step_and_escape(void **state)
{
    (void)state;
    if (!xvfb)
        skip();
    char dir[4096], a[4200], b[4200], src[1024];
    tmp_path("view-folder", dir, sizeof dir);
    mkdir(dir, 0700);
    snprintf(a, sizeof a, "%s/a.dae", dir);
    snprintf(b, sizeof b, "%s/b.glb", dir);
    size_t n = 0;
    unsigned char *bytes = read_file(fixture_path("two_bone.dae", src, sizeof src), &n);
    write_file(a, bytes, n);
    free(bytes);
    bytes = read_file(fixture_path("twist_tube.glb", src, sizeof src), &n); /* looks unlike a.dae */
    write_file(b, bytes, n);
    free(bytes);
    /* ... from its start and framed on its own (not at the old file's paused time and orbit) */
    compare_with_render(
        (const char *const[]){a, "--time", "0.7", "--camera", "orbit:60,20,9", "--press", "Page_Down", NULL},
        (const char *const[]){b, "--time", "0", "--camera", "orbit:60,20", NULL});

    char dae[4096];
    demo_file(dae, sizeof dae);
    /* (keys are pressed once the file is drawn, as by hand: the camera stays where it was placed) */
    compare_with_render((const char *const[]){dae, "--clip", "walk", "--time", "0.52", "--camera-position", "2,1.5,4",
                                              "--camera-focal-point", "0,1,0", "--press", "Right", NULL},
                        (const char *const[]){dae, "--clip", "walk", "--time", "0.533333", "--camera-position",
                                              "2,1.5,4", "--camera-focal-point", "0,1,0", NULL});
    compare_with_render((const char *const[]){dae, "--clip", "walk", "--time", "0.52", "--camera-position", "2,1.5,4",
                                              "--camera-focal-point", "0,1,0", "--press", "Left", NULL},
                        (const char *const[]){dae, "--clip", "walk", "--time", "0.466667", "--camera-position",
                                              "2,1.5,4", "--camera-focal-point", "0,1,0", NULL});

    /* f3d's camera placement, as `sinew render` takes it (a model without muscles, which the
     * viewer would show and render would not) */
    compare_with_render((const char *const[]){b, "--time", "0.5", "--camera-position", "1,1.5,3",
                                              "--camera-focal-point", "0,1,0", "--fov", "30", NULL},
                        (const char *const[]){b, "--time", "0.5", "--camera-position", "1,1.5,3",
                                              "--camera-focal-point", "0,1,0", "--fov", "30", NULL});

    char *err = NULL;
    double t = now_seconds();
    assert_int_equal(run_view((const char *const[]){dae, "--press", "Escape", "--quit-after", "60", NULL}, &err), 0);
    assert_true(now_seconds() - t < 45.0);
    free(err);
}

/* --watch: a new version of the file without the shown clip's name opens at the clip in the same
 * place (or the first), with a note, instead of being refused. The file changes every 3 s between
 * a version whose clip is "bend" and one whose clip is "flex", so that a change from the first to
 * the second happens while the viewer watches, however long it takes to start. */
static void test_watch_keeps_going_when_the_clip_is_renamed(void **state)
{
    (void)state;
    if (!xvfb)
        skip();
    char src[1024], path[4096], next[4200];
    size_t n = 0;
    char *bend = (char *)read_file(fixture_path("two_bone.dae", src, sizeof src), &n);
    char *flex = malloc(n + 1);
    memcpy(flex, bend, n);
    flex[n] = '\0';
    char *id = strstr(flex, "id=\"bend\"");
    assert_non_null(id);
    memcpy(id, "id=\"flex\"", 9);
    tmp_path("view-watch.dae", path, sizeof path);
    snprintf(next, sizeof next, "%s.new", path);
    write_file(path, bend, n);
    pid_t pid = start_view((const char *const[]){path, "--watch", "--quit-after", "16", NULL});
    for (int i = 1; i <= 4; i++) {
        sleep(3);
        write_file(next, i % 2 ? flex : bend, n); /* replaced by rename, as editors and exporters do */
        rename(next, path);
    }
    char *err = NULL;
    assert_int_equal(finish_view(pid, &err), 0);
    if (!strstr(err, "has no clip \"bend\" now; showing flex"))
        fail_msg("no note of the renamed clip; stderr: %s", err);
    assert_null(strstr(err, "the clips:")); /* the refusal's text */
    free(err);
    free(flex);
    free(bend);
}

static void test_screenshot_equals_headless_render(void **state)
{
    (void)state;
    if (!xvfb)
        skip();
    char dae[4096];
    demo_file(dae, sizeof dae);
    compare_with_render((const char *const[]){dae, "--clip", "wave", "--time", "0.6", "--skeleton", "--no-grid",
                                              "--shading", "flat", "--camera", "orbit:40,20", NULL},
                        (const char *const[]){dae, "--clip", "wave", "--time", "0.6", "--skeleton", "--no-grid",
                                              "--shading", "flat", "--camera", "orbit:40,20", NULL});
    /* --clip takes an index as `sinew` does: clip 1 of the demo is "wave" */
    compare_with_render((const char *const[]){dae, "--clip", "1", "--time", "0.6", NULL},
                        (const char *const[]){dae, "--clip", "wave", "--time", "0.6", NULL});
    /* --clip none: the rest pose (the clip list's last entry), as `sinew render` draws it */
    compare_with_render((const char *const[]){dae, "--clip", "none", "--time", "0.6", NULL},
                        (const char *const[]){dae, "--clip", "none", NULL});
    /* a selected joint with its heat map */
    compare_with_render((const char *const[]){dae, "--clip", "wave", "--time", "0.3", "--select", "RightLowerArm",
                                              "--heatmap", "RightLowerArm", NULL},
                        (const char *const[]){dae, "--clip", "wave", "--time", "0.3", "--select", "RightLowerArm",
                                              "--heatmap", "RightLowerArm", NULL});
}

static char *settings_file(char *path, size_t size);

/* Anti-aliasing (--samples, 4 by default) as `render --samples`: without it the picture is the
 * jagged one; the look options (shadows, occlusion, outlines, an environment file shown behind)
 * draw as `sinew render` draws them. */
static void test_samples_and_look(void **state)
{
    (void)state;
    if (!xvfb)
        skip();
    char dae[4096], hdr[4096];
    demo_file(dae, sizeof dae);
    compare_with_render((const char *const[]){dae, "--clip", "walk", "--time", "0.5", "--samples", "1", NULL},
                        (const char *const[]){dae, "--clip", "walk", "--time", "0.5", NULL});
    compare_with_render(
        (const char *const[]){dae, "--clip", "walk", "--time", "0.5", "--shadows", "--ssao", "--outline", NULL},
        (const char *const[]){dae, "--clip", "walk", "--time", "0.5", "--shadows", "--ssao", "--outline", NULL});
    fixture_path("sky.hdr", hdr, sizeof hdr);
    compare_with_render((const char *const[]){dae, "--clip", "walk", "--time", "0.5", "--shading", "pbr", "--hdri", hdr,
                                              "--hdri-background", NULL},
                        (const char *const[]){dae, "--clip", "walk", "--time", "0.5", "--shading", "pbr", "--hdri", hdr,
                                              "--hdri-background", NULL});
    /* a missing environment file: said, and the studio lights the model */
    char *err = NULL, shot[4096];
    tmp_path("view-no-hdri.png", shot, sizeof shot);
    assert_int_equal(run_view((const char *const[]){dae, "--shading", "pbr", "--hdri", "/nonexistent/sky.hdr",
                                                    "--screenshot", shot, "--quit", NULL},
                              &err),
                     0);
    assert_non_null(err);
    assert_non_null(strstr(err, "/nonexistent/sky.hdr"));
    free(err);
}

/* Follow (--track, key T): a capture that walks away stays where the camera was framed on it.
 * The skeleton here moves 3 m along x in its 1 s and does nothing else, so at its end, followed,
 * it looks as it did framed at its start; unfollowed it has left that view. Key T turns Follow on
 * from where the model is at the time, and is saved in the settings. */
static void test_follow(void **state)
{
    (void)state;
    if (!xvfb)
        skip();
    char bvh[4096], ini[4096];
    tmp_path("walk-away.bvh", bvh, sizeof bvh);
    const char *text = "HIERARCHY\nROOT Hips\n{\n  OFFSET 0 0 0\n"
                       "  CHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation\n"
                       "  JOINT Chest\n  {\n    OFFSET 0 50 0\n    CHANNELS 3 Zrotation Xrotation Yrotation\n"
                       "    JOINT Arm\n    {\n      OFFSET 20 30 0\n      CHANNELS 3 Zrotation Xrotation Yrotation\n"
                       "      End Site\n      {\n        OFFSET 30 0 0\n      }\n    }\n  }\n}\n"
                       "MOTION\nFrames: 2\nFrame Time: 1.0\n"
                       "0 90 0 0 0 0 0 0 0 0 0 0\n300 90 0 0 0 0 0 0 0 0 0 0\n";
    write_file(bvh, text, strlen(text));
    const char *const at_start[] = {bvh, "--time", "0", "--no-grid", "--skeleton", "--camera", "orbit:20,15", NULL};
    compare_with_render((const char *const[]){bvh, "--track", "--no-grid", "--skeleton", "--camera", "orbit:20,15",
                                              "--press", "End", NULL},
                        at_start);
    assert_true(differ_from_render((const char *const[]){bvh, "--no-grid", "--skeleton", "--camera", "orbit:20,15",
                                                         "--press", "End", NULL},
                                   at_start) > 0.01);
    /* turned on by its key at the end, then back to the start */
    settings_file(ini, sizeof ini);
    unlink(ini);
    compare_with_render(
        (const char *const[]){bvh, "--time", "1", "--no-grid", "--skeleton", "--camera", "orbit:20,15", "--press",
                              "t,Home", NULL},
        (const char *const[]){bvh, "--time", "1", "--no-grid", "--skeleton", "--camera", "orbit:20,15", NULL});
    size_t size = 0;
    char *saved = read_file(ini, &size);
    assert_non_null(saved);
    assert_non_null(strstr(saved, "follow=true"));
    free(saved);
    unlink(ini);
}

/* Blender's key map (--key-map blender, or [view] key-map=blender in the settings): Home
 * frames all (sinew's Home goes to the first frame), Shift+Left goes to the first frame. */
static void test_blender_key_map(void **state)
{
    (void)state;
    if (!xvfb)
        skip();
    char dae[4096], ini[4096];
    demo_file(dae, sizeof dae);
    compare_with_render((const char *const[]){dae, "--clip", "walk", "--time", "0.5", "--key-map", "blender",
                                              "--camera", "orbit:40,20,0.4", "--press", "Home", NULL},
                        (const char *const[]){dae, "--clip", "walk", "--time", "0.5", "--camera", "orbit:40,20", NULL});
    compare_with_render((const char *const[]){dae, "--clip", "walk", "--time", "0.5", "--key-map", "blender", "--press",
                                              "shift+Left", NULL},
                        (const char *const[]){dae, "--clip", "walk", "--time", "0", NULL});
    compare_with_render((const char *const[]){dae, "--clip", "walk", "--time", "0.5", "--press", "Home", NULL},
                        (const char *const[]){dae, "--clip", "walk", "--time", "0", NULL});
    /* from the settings file, and kept there */
    settings_file(ini, sizeof ini);
    const char *text = "[view]\nkey-map=blender\n";
    write_file(ini, text, strlen(text));
    compare_with_render((const char *const[]){dae, "--clip", "walk", "--time", "0.5", "--camera", "orbit:40,20,0.4",
                                              "--press", "Home", NULL},
                        (const char *const[]){dae, "--clip", "walk", "--time", "0.5", "--camera", "orbit:40,20", NULL});
    size_t size = 0;
    char *saved = read_file(ini, &size);
    assert_non_null(saved);
    assert_non_null(strstr(saved, "key-map=blender"));
    assert_null(strstr(saved, "frame-all=")); /* Home is the map's own, not a rebinding */
    free(saved);
    unlink(ini);
}

/* The file opens on a worker thread after the demo: --time applies to the file's clip (a
 * 1 s demo walk used to clamp 15 s of a mocap take to 0). */
static void test_time_past_the_demo_clip(void **state)
{
    (void)state;
    char bvh[4096];
    if (!xvfb || !testdata_path("assimp/BVH/01_01.bvh", bvh, sizeof bvh))
        skip();
    compare_with_render((const char *const[]){bvh, "--time", "15", NULL},
                        (const char *const[]){bvh, "--time", "15", NULL});
}

/* A file that makes the reader loop is stopped at --import-timeout (with memory enough that the
 * default limit of a file its size does not stop it first); meanwhile and after, the demo is on
 * screen, and the run says the file failed. */
static void test_hanging_file_keeps_the_demo(void **state)
{
    (void)state;
    char source[4096], hangs[4096], shot[4096];
    if (!xvfb || !testdata_path("assimp/Collada/duck.dae", source, sizeof source))
        skip();
    size_t n = 0;
    unsigned char *bytes = read_file(source, &n);
    bytes[245632] = 0xC0; /* Assimp's COLLADA reader loops on it, allocating */
    write_file(tmp_path("view-hangs.dae", hangs, sizeof hangs), bytes, n);
    free(bytes);
    tmp_path("view-hangs.png", shot, sizeof shot);
    unlink(shot);
    setenv("SINEW_IMPORTER", "assimp", 1);
    char *err = NULL;
    int code = run_view((const char *const[]){hangs, "--import-timeout", "1", "--import-memory", "4096", "--screenshot",
                                              shot, "--quit", NULL},
                        &err);
    unsetenv("SINEW_IMPORTER");
    assert_int_equal(code, 2);
    if (!err || !strstr(err, hangs) || !strstr(err, "1 s deadline"))
        fail_msg("expected the deadline named: %s", err ? err : "");
    struct stat st;
    assert_int_equal(stat(shot, &st), 0); /* the demo was drawn */
    assert_true(st.st_size > 10000);
    free(err);
    /* a bad value is a usage error */
    assert_int_equal(run_view((const char *const[]){"--import-timeout", "soon", NULL}, &err), 1);
    free(err);
}

static char *settings_file(char *path, size_t size)
{
    char dir[2048];
    tmp_path("view-config/sinew", dir, sizeof dir);
    mkdir(tmp_path("view-config", path, size), 0700);
    mkdir(dir, 0700);
    snprintf(path, size, "%s/settings.ini", dir);
    return path;
}

static void test_settings_round_trip(void **state)
{
    (void)state;
    if (!xvfb)
        skip();
    char dae[4096], ini[4096];
    demo_file(dae, sizeof dae);
    settings_file(ini, sizeof ini);
    /* meshes=h: what earlier versions wrote for every user (h is the key cheat sheet now) */
    const char *text =
        "[display]\ngrid=off\nshading=flat\n\n[window]\nwidth=900\nheight=620\n\n[keys]\nplay=p\nmeshes=h\n";
    write_file(ini, text, strlen(text));
    /* the file's settings are used */
    compare_with_render(
        (const char *const[]){dae, "--clip", "walk", "--time", "0.5", NULL},
        (const char *const[]){dae, "--clip", "walk", "--time", "0.5", "--no-grid", "--shading", "flat", NULL});
    size_t size = 0;
    char *saved = read_file(ini, &size);
    assert_non_null(saved);
    assert_non_null(strstr(saved, "grid=off"));
    assert_non_null(strstr(saved, "shading=flat"));
    assert_non_null(strstr(saved, "play=p"));
    assert_non_null(strstr(saved, "width=900"));
    assert_null(strstr(saved, "next-frame=")); /* only bindings the user changed are written */
    assert_null(strstr(saved, "meshes=h"));
    free(saved);
    /* the command line overrides them for its run only */
    compare_with_render((const char *const[]){dae, "--clip", "walk", "--time", "0.5", "--grid", NULL},
                        (const char *const[]){dae, "--clip", "walk", "--time", "0.5", "--shading", "flat", NULL});
    saved = read_file(ini, &size);
    assert_non_null(strstr(saved, "grid=off"));
    free(saved);
    /* a bad value is reported and the rest still used */
    text = "[display]\ngrid=sideways\nshading=flat\n";
    write_file(ini, text, strlen(text));
    char *err = NULL, shot[4096];
    tmp_path("view-bad-settings.png", shot, sizeof shot);
    assert_int_equal(run_view((const char *const[]){dae, "--screenshot", shot, "--quit", NULL}, &err), 0);
    assert_non_null(err);
    assert_non_null(strstr(err, "settings.ini"));
    assert_non_null(strstr(err, "grid"));
    free(err);
    /* a file without meshes shows its skeleton without writing skeleton=on (issue 16) */
    char bvh[4096];
    if (testdata_path("assimp/BVH/01_01.bvh", bvh, sizeof bvh)) {
        text = "[display]\nskeleton=off\n";
        write_file(ini, text, strlen(text));
        assert_int_equal(run_view((const char *const[]){bvh, "--screenshot", shot, "--quit", NULL}, &err), 0);
        free(err);
        saved = read_file(ini, &size);
        assert_non_null(strstr(saved, "skeleton=off"));
        free(saved);
    }
    unlink(ini);
}

/* Playing for 3 s draws every widget every frame: no "Trying to snapshot GtkBox without a
 * current allocation" (the status label was set from inside the GL area's draw, so the lower
 * control row went undrawn in some frames: 8-13 warnings in 5 s before), and no GTK-CRITICAL
 * on leaving from another panel page or with a joint selected. */
static void test_widgets_drawn_while_playing(void **state)
{
    (void)state;
    if (!xvfb)
        skip();
    char robot[4096];
    if (!testdata_path("raylib/robot.glb", robot, sizeof robot))
        skip();
    char *err = NULL;
    gsk_renderer = NULL; /* GTK's own choice, as a user gets it */
    int code = run_view(
        (const char *const[]){robot, "--quit-after", "3", "--panel", "display", "--select", "Hips", NULL}, &err);
    gsk_renderer = "cairo";
    assert_int_equal(code, 0);
    if (err && (strstr(err, "snapshot") || strstr(err, "CRITICAL")))
        fail_msg("GTK complained while playing: %s", err);
    free(err);
}

/* Keys pressed in the window (--press): keypad 1 looks from the front as `sinew render
 * --camera front`, keypad 5 makes it parallel as --ortho; F12 writes FILE-001.png, then
 * FILE-002.png, into --screenshot-dir; an unbound key name is reported; F9 records an MP4. */
static void test_keys(void **state)
{
    (void)state;
    if (!xvfb)
        skip();
    char dae[4096];
    demo_file(dae, sizeof dae);
    compare_with_render((const char *const[]){dae, "--clip", "walk", "--time", "0.5", "--press", "KP_1", NULL},
                        (const char *const[]){dae, "--clip", "walk", "--time", "0.5", "--camera", "front", NULL});
    compare_with_render(
        (const char *const[]){dae, "--clip", "walk", "--time", "0.5", "--press", "KP_5,KP_7", NULL},
        (const char *const[]){dae, "--clip", "walk", "--time", "0.5", "--camera", "top", "--ortho", NULL});
    char dir[4096], first[4200], second[4200];
    tmp_path("view-shots", dir, sizeof dir);
    mkdir(dir, 0700);
    snprintf(first, sizeof first, "%s/humanoid-001.png", dir);
    snprintf(second, sizeof second, "%s/humanoid-002.png", dir);
    unlink(first);
    unlink(second);
    char *err = NULL;
    for (int run = 0; run < 2; run++) {
        assert_int_equal(run_view((const char *const[]){dae, "--screenshot-dir", dir, "--press", "F12,nokey",
                                                        "--quit-after", "2", NULL},
                                  &err),
                         0);
        assert_non_null(strstr(err, "--press: \"nokey\""));
        free(err);
    }
    int w = 0, h = 0, c = 0;
    unsigned char *px = stbi_load(first, &w, &h, &c, 3);
    assert_non_null(px);
    assert_true(w > 100 && h > 100);
    stbi_image_free(px);
    assert_int_equal(access(second, F_OK), 0);
    /* F9 records one pass of the clip (the demo's 1 s walk) to humanoid-001.mp4 */
    if (system("command -v ffmpeg >/dev/null 2>&1") == 0) {
        char video[4200];
        snprintf(video, sizeof video, "%s/humanoid-001.mp4", dir);
        unlink(video);
        assert_int_equal(run_view((const char *const[]){dae, "--clip", "walk", "--screenshot-dir", dir, "--press", "F9",
                                                        "--quit-after", "4", NULL},
                                  &err),
                         0);
        if (err && strstr(err, "snapshot"))
            fail_msg("GTK complained while recording: %s", err);
        free(err);
        size_t size = 0;
        unsigned char *bytes = read_file(video, &size);
        assert_non_null(bytes);
        assert_true(size > 1000 && memcmp(bytes + 4, "ftyp", 4) == 0);
        free(bytes);
    }
}

/* --version answers without opening a window. */
static void test_version(void **state)
{
    (void)state;
    char *err = NULL;
    assert_int_equal(run_view((const char *const[]){"--version", NULL}, &err), 0);
    free(err);
}

static void test_broken_file_keeps_the_demo(void **state)
{
    (void)state;
    if (!xvfb)
        skip();
    char broken[4096], shot[4096];
    tmp_path("view-broken.dae", broken, sizeof broken);
    write_file(broken, "<COLLADA><library_geometries>", 29);
    tmp_path("view-broken.png", shot, sizeof shot);
    unlink(shot);
    char *err = NULL;
    int code = run_view((const char *const[]){broken, "--screenshot", shot, "--quit", NULL}, &err);
    assert_int_equal(code, 2); /* the file failed: said in the exit status too */
    assert_non_null(err);
    assert_non_null(strstr(err, broken));
    struct stat st;
    assert_int_equal(stat(shot, &st), 0); /* the demo was drawn */
    assert_true(st.st_size > 10000);
    free(err);
}

/* --anim with a FILE applies to the file, not to the demo shown while it opens (an IQM
 * animation file fits two_bone.iqm and not the demo: this crashed the viewer); with no FILE an
 * --anim that does not fit the demo is reported and the demo plays without it. */
static void test_anim_files(void **state)
{
    (void)state;
    if (!xvfb)
        skip();
    char model[4096], anim[4096], shot[4096];
    fixture_path("two_bone.iqm", model, sizeof model);
    fixture_path("two_bone_anim.iqm", anim, sizeof anim);
    tmp_path("view-anim.png", shot, sizeof shot);
    unlink(shot);
    char *err = NULL;
    int code = run_view(
        (const char *const[]){model, "--anim", anim, "--time", "0.5", "--screenshot", shot, "--quit", NULL}, &err);
    assert_int_equal(code, 0);
    struct stat st;
    assert_int_equal(stat(shot, &st), 0);
    free(err);
    unlink(shot);
    err = NULL;
    code = run_view((const char *const[]){"--anim", model, "--screenshot", shot, "--quit", NULL}, &err);
    assert_true(code == 0 || code == 2);
    assert_non_null(err);
    assert_non_null(strstr(err, "two_bone.iqm"));
    assert_int_equal(stat(shot, &st), 0); /* the demo was drawn */
    assert_true(st.st_size > 10000);
    free(err);
}

/* The Shape keys panel: a slider set as a hand sets it (the SINEW_VIEW_SLIDERS hook) draws what
 * `sinew render --morph` draws with that weight (from one camera: a slider moves no camera); --panel shape-keys opens
 * on the page, and the whole window can be written. */
static void test_shape_key_slider(void **state)
{
    (void)state;
    if (!xvfb)
        skip();
    char quad[4096], window[4096];
    fixture_path("morph_quad.gltf", quad, sizeof quad);
    setenv("SINEW_VIEW_SLIDERS", "1=0.8", 1);
    compare_with_render(
        (const char *const[]){quad, "--clip", "none", "--camera", "fly:1,0.5,4,0,-5", "--panel", "shape-keys", NULL},
        (const char *const[]){quad, "--clip", "none", "--camera", "fly:1,0.5,4,0,-5", "--morph", "1=0.8", NULL});
    unsetenv("SINEW_VIEW_SLIDERS");
    /* --morph on the command line is the file's (the demo shown meanwhile has no such target) */
    compare_with_render((const char *const[]){quad, "--camera", "orbit:30,15,5", "--morph", "1=0.8", NULL},
                        (const char *const[]){quad, "--camera", "orbit:30,15,5", "--morph", "1=0.8", NULL});
    tmp_path("view-window.png", window, sizeof window);
    unlink(window);
    char *err = NULL;
    assert_int_equal(
        run_view((const char *const[]){quad, "--panel", "shape-keys", "--screenshot-window", window, "--quit", NULL},
                 &err),
        0);
    free(err);
    int w, h, n;
    unsigned char *pixels = stbi_load(window, &w, &h, &n, 3);
    assert_non_null(pixels);
    assert_true(w > 300 && h > 200);
    stbi_image_free(pixels);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_screenshot_equals_headless_render),
        cmocka_unit_test(test_version),
        cmocka_unit_test(test_broken_file_keeps_the_demo),
        cmocka_unit_test(test_time_past_the_demo_clip),
        cmocka_unit_test(test_hanging_file_keeps_the_demo),
        cmocka_unit_test(test_settings_round_trip),
        cmocka_unit_test(test_widgets_drawn_while_playing),
        cmocka_unit_test(test_keys),
        cmocka_unit_test(test_next_file_frame_step_and_escape),
        cmocka_unit_test(test_watch_keeps_going_when_the_clip_is_renamed),
        cmocka_unit_test(test_anim_files),
        cmocka_unit_test(test_shape_key_slider),
        cmocka_unit_test(test_samples_and_look),
        cmocka_unit_test(test_blender_key_map),
        cmocka_unit_test(test_follow),
    };
    return cmocka_run_group_tests(tests, start_xvfb, stop_xvfb);
}
