/* Output files written whole or not at all: into a temporary file in the target's folder,
 * renamed over the target only once everything was written and closed without error. A
 * target that exists and is not a regular file (/dev/stdout, /dev/full, a FIFO) is written
 * in place, with every write checked. */
#define _GNU_SOURCE /* mkostemps */
#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <strings.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <signal.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <stb_image_write.h>

#include "app.h"

/* The folder part of a path ("." for a bare name). */
static void folder_of(const char *path, char *out, size_t size)
{
    const char *slash = strrchr(path, '/');
    if (!slash)
        snprintf(out, size, ".");
    else if (slash == path)
        snprintf(out, size, "/");
    else
        snprintf(out, size, "%.*s", (int)(slash - path), path);
}

/* The same file: by device and inode when both exist, else by real path. */
static bool same_file(const char *a, const char *b)
{
    struct stat sa, sb;
    if (stat(a, &sa) == 0 && stat(b, &sb) == 0)
        return sa.st_dev == sb.st_dev && sa.st_ino == sb.st_ino;
    char ra[PATH_MAX], rb[PATH_MAX];
    return realpath(a, ra) && realpath(b, rb) && strcmp(ra, rb) == 0;
}

sinew_result app_output_check(const char *output, const char *const *inputs, size_t input_count, sinew_error *error)
{
    for (size_t i = 0; i < input_count; i++) {
        if (inputs[i] && same_file(output, inputs[i]))
            return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT,
                              "%s: the output is the input file %s; refusing to write over it", output, inputs[i]);
    }
    return SINEW_OK;
}

/* Temporary files in the making, removed when SIGINT, SIGTERM or SIGHUP ends the program (their
 * names also say "sinew-tmp", for what SIGKILL leaves). The handler only reads these buffers and
 * calls unlink(), which is async-signal-safe. */
#define TEMP_SLOTS 16
static char temp_paths[TEMP_SLOTS][4096];
static volatile sig_atomic_t temp_used[TEMP_SLOTS];

static void remove_temporaries(int sig)
{
    for (int i = 0; i < TEMP_SLOTS; i++)
        if (temp_used[i])
            unlink(temp_paths[i]);
    signal(sig, SIG_DFL);
    raise(sig);
}

static void track_temporary(const char *path)
{
    static bool handlers;
    if (!handlers) {
        static const int SIGNALS[] = {SIGINT, SIGTERM, SIGHUP};
        for (size_t k = 0; k < sizeof SIGNALS / sizeof SIGNALS[0]; k++) {
            struct sigaction old;
            /* a signal the caller ignores (nohup) stays ignored */
            if (sigaction(SIGNALS[k], NULL, &old) == 0 && old.sa_handler == SIG_IGN)
                continue;
            struct sigaction sa = {0};
            sa.sa_handler = remove_temporaries;
            sigemptyset(&sa.sa_mask);
            sigaction(SIGNALS[k], &sa, NULL);
        }
        handlers = true;
    }
    for (int i = 0; i < TEMP_SLOTS; i++)
        if (!temp_used[i]) {
            snprintf(temp_paths[i], sizeof temp_paths[i], "%s", path);
            temp_used[i] = 1;
            return;
        }
}

static void untrack_temporary(const char *path)
{
    for (int i = 0; i < TEMP_SLOTS; i++)
        if (temp_used[i] && strcmp(temp_paths[i], path) == 0)
            temp_used[i] = 0;
}

sinew_result app_output_open(app_output *o, const char *path, sinew_error *error)
{
    memset(o, 0, sizeof *o);
    snprintf(o->path, sizeof o->path, "%s", path);
    struct stat st;
    bool exists = stat(path, &st) == 0;
    if (exists && S_ISDIR(st.st_mode))
        return sinew_fail(error, SINEW_ERROR_IO, "%s: is a folder, not a file", path);
    if (exists && !S_ISREG(st.st_mode)) {
        o->in_place = true;
        o->file = fopen(path, "wb");
        if (!o->file)
            return sinew_fail(error, SINEW_ERROR_IO, "%s: cannot write: %s", path, strerror(errno));
        return SINEW_OK;
    }
    char folder[PATH_MAX];
    folder_of(path, folder, sizeof folder);
    const char *name = strrchr(path, '/') ? strrchr(path, '/') + 1 : path;
    const char *ext = strrchr(name, '.');
    ext = ext && ext != name ? ext : "";
    /* .NAME.sinew-tmp-XXXXXX.EXT: hidden, recognisable, and with the target's extension (ffmpeg picks
     * its muxer by it). */
    int n = snprintf(o->temp, sizeof o->temp, "%s/.%s.sinew-tmp-XXXXXX%s", folder, name, ext);
    if (n < 0 || (size_t)n >= sizeof o->temp)
        return sinew_fail(error, SINEW_ERROR_IO, "%s: the path is too long", path);
    int fd = mkostemps(o->temp, (int)strlen(ext), O_CLOEXEC);
    if (fd < 0)
        return sinew_fail(error, SINEW_ERROR_IO, "%s: cannot write in %s: %s", path, folder, strerror(errno));
    track_temporary(o->temp);
    mode_t mask = umask(0); /* files get 0666 less the umask, as fopen's would */
    umask(mask);
    fchmod(fd, 0666 & ~mask);
    o->file = fdopen(fd, "wb");
    if (!o->file) {
        close(fd);
        unlink(o->temp);
        untrack_temporary(o->temp);
        return sinew_fail(error, SINEW_ERROR_IO, "%s: cannot write: %s", path, strerror(errno));
    }
    return SINEW_OK;
}

const char *app_output_temp_path(const app_output *o)
{
    return o->in_place ? o->path : o->temp;
}

bool app_output_write(app_output *o, const void *bytes, size_t size)
{
    if (o->failed || !o->file)
        return false;
    if (size && fwrite(bytes, 1, size, o->file) != size) {
        o->failed = true;
        o->saved_errno = errno ? errno : EIO;
    }
    return !o->failed;
}

sinew_result app_output_commit(app_output *o, sinew_error *error)
{
    if (!o->file && !o->external)
        return sinew_fail(error, SINEW_ERROR_IO, "%s: not open", o->path);
    if (o->file) {
        if (fflush(o->file) != 0 && !o->failed) {
            o->failed = true;
            o->saved_errno = errno;
        }
        if (ferror(o->file) && !o->failed) {
            o->failed = true;
            o->saved_errno = EIO;
        }
        if (fclose(o->file) != 0 && !o->failed) {
            o->failed = true;
            o->saved_errno = errno;
        }
        o->file = NULL;
    }
    if (o->failed) {
        int e = o->saved_errno;
        app_output_abort(o);
        return sinew_fail(error, SINEW_ERROR_IO, "%s: cannot write: %s; nothing was written", o->path, strerror(e));
    }
    if (!o->in_place && rename(o->temp, o->path) != 0) {
        int e = errno;
        app_output_abort(o);
        return sinew_fail(error, SINEW_ERROR_IO, "%s: cannot put the file in place: %s", o->path, strerror(e));
    }
    untrack_temporary(o->temp);
    o->temp[0] = '\0';
    return SINEW_OK;
}

void app_output_abort(app_output *o)
{
    if (o->file)
        fclose(o->file);
    o->file = NULL;
    if (!o->in_place && o->temp[0]) {
        unlink(o->temp);
        untrack_temporary(o->temp);
    }
    o->temp[0] = '\0';
}

void app_output_release(app_output *o)
{
    if (o->file)
        fclose(o->file);
    o->file = NULL;
    o->external = true;
}

static void image_sink(void *context, void *data, int size)
{
    app_output_write(context, data, (size_t)size);
}

bool app_has_extension(const char *path, const char *ext)
{
    size_t a = strlen(path), b = strlen(ext);
    return a > b && path[a - b - 1] == '.' && strcasecmp(path + a - b, ext) == 0;
}

app_image_format app_image_format_of(const char *path)
{
    static const struct {
        const char *ext;
        app_image_format format;
    } known[] = {{"png", APP_IMAGE_PNG}, {"jpg", APP_IMAGE_JPEG}, {"jpeg", APP_IMAGE_JPEG}, {"bmp", APP_IMAGE_BMP},
                 {"tga", APP_IMAGE_TGA}, {"mp4", APP_VIDEO},      {"m4v", APP_VIDEO},       {"mov", APP_VIDEO},
                 {"mkv", APP_VIDEO},     {"webm", APP_VIDEO},     {"gif", APP_VIDEO}};
    for (size_t i = 0; i < sizeof known / sizeof known[0]; i++)
        if (app_has_extension(path, known[i].ext))
            return known[i].format;
    const char *base = strrchr(path, '/');
    return strchr(base ? base + 1 : path, '.') ? APP_IMAGE_UNKNOWN : APP_IMAGE_PNG; /* no extension: PNG */
}

sinew_result app_make_parent_folders(const char *path, sinew_error *error)
{
    char dir[4096];
    if (snprintf(dir, sizeof dir, "%s", path) >= (int)sizeof dir)
        return sinew_fail(error, SINEW_ERROR_IO, "%.64s...: path too long", path);
    char *slash = strrchr(dir, '/');
    if (!slash || slash == dir)
        return SINEW_OK;
    *slash = '\0';
    for (char *p = dir + 1;; p++) {
        bool end = *p == '\0';
        if (*p == '/' || end) {
            char keep = *p;
            *p = '\0';
            struct stat st;
            if (stat(dir, &st) != 0) {
                if (mkdir(dir, 0777) != 0 && errno != EEXIST)
                    return sinew_fail(error, SINEW_ERROR_IO, "%s: cannot make the folder %s: %s", path, dir,
                                      strerror(errno));
            } else if (!S_ISDIR(st.st_mode)) {
                return sinew_fail(error, SINEW_ERROR_IO, "%s: %s is not a folder", path, dir);
            }
            *p = keep;
        }
        if (end)
            break;
    }
    return SINEW_OK;
}

sinew_result app_write_image(const char *path, const unsigned char *rgba, int width, int height, bool flip, bool alpha,
                             sinew_error *error)
{
    app_image_format format = app_image_format_of(path);
    if (format == APP_IMAGE_UNKNOWN || format == APP_VIDEO)
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT,
                          "%s: an image is written as PNG, JPEG, BMP or TGA (.png, .jpg, .jpeg, .bmp, .tga)", path);
    /* RGB unless alpha is asked for (a transparent background) and the format keeps it (PNG, TGA);
     * an opaque picture is smaller without it */
    int c = alpha && (format == APP_IMAGE_PNG || format == APP_IMAGE_TGA) ? 4 : 3;
    size_t n = (size_t)width * (size_t)height;
    unsigned char *rgb = malloc(n * (size_t)c + 1);
    if (!rgb)
        return sinew_fail(error, SINEW_ERROR_OUT_OF_MEMORY, "%s: out of memory", path);
    for (size_t i = 0; i < n; i++) {
        unsigned char *p = &rgb[i * (size_t)c];
        memcpy(p, &rgba[i * 4], (size_t)c);
        if (c == 4 && p[3] > 0 && p[3] < 255) /* edges over a cleared (0, 0, 0, 0) background: un-premultiply */
            for (int k = 0; k < 3; k++)
                p[k] = (unsigned char)(p[k] * 255u / p[3] > 255u ? 255u : p[k] * 255u / p[3]);
    }
    app_output o;
    sinew_result result = app_output_open(&o, path, error);
    if (result == SINEW_OK) {
        stbi_flip_vertically_on_write(flip);
        int ok = format == APP_IMAGE_PNG    ? stbi_write_png_to_func(image_sink, &o, width, height, c, rgb, width * c)
                 : format == APP_IMAGE_JPEG ? stbi_write_jpg_to_func(image_sink, &o, width, height, c, rgb, 92)
                 : format == APP_IMAGE_BMP  ? stbi_write_bmp_to_func(image_sink, &o, width, height, c, rgb)
                                            : stbi_write_tga_to_func(image_sink, &o, width, height, c, rgb);
        stbi_flip_vertically_on_write(0);
        if (!ok) {
            app_output_abort(&o);
            result = sinew_fail(error, SINEW_ERROR_IO, "%s: cannot encode the image", path);
        } else {
            result = app_output_commit(&o, error);
        }
    }
    free(rgb);
    return result;
}

/* ---- video through ffmpeg ---- */

/* The ffmpeg program on PATH, or false. */
static bool find_program(const char *name, char *out, size_t size)
{
    const char *path = getenv("PATH");
    if (!path)
        return false;
    while (*path) {
        size_t len = strcspn(path, ":");
        if (len > 0 && (size_t)snprintf(out, size, "%.*s/%s", (int)len, path, name) < size && access(out, X_OK) == 0)
            return true;
        path += len + (path[len] == ':');
    }
    return false;
}

sinew_result app_video_open(app_video *video, const char *path, int width, int height, double fps, bool flip,
                            sinew_error *error)
{
    memset(video, 0, sizeof *video);
    video->fd = -1;
    video->path = path;
    char program[4096];
    if (!find_program("ffmpeg", program, sizeof program)) {
        video->unavailable = true;
        return sinew_fail(error, SINEW_ERROR_IO,
                          "%s: writing video needs the ffmpeg program, which is not installed (Debian: apt-get "
                          "install ffmpeg); or write PNG frames with -o DIR/frame%%04d.png",
                          path);
    }
    /* ffmpeg writes a temporary file beside the target, renamed into place when it succeeds */
    if (app_output_open(&video->output, path, error) != SINEW_OK) {
        video->write_failed = true;
        return error ? error->kind : SINEW_ERROR_IO;
    }
    app_output_release(&video->output);
    const char *target = app_output_temp_path(&video->output);
    int fds[2];
    if (pipe(fds) != 0) {
        app_output_abort(&video->output);
        return sinew_fail(error, SINEW_ERROR_IO, "%s: cannot start ffmpeg: %s", path, strerror(errno));
    }
    char size[32], rate[32];
    snprintf(size, sizeof size, "%dx%d", width, height);
    snprintf(rate, sizeof rate, "%.6g", fps);
    pid_t pid = fork();
    if (pid < 0) {
        close(fds[0]);
        close(fds[1]);
        app_output_abort(&video->output);
        return sinew_fail(error, SINEW_ERROR_IO, "%s: cannot start ffmpeg: %s", path, strerror(errno));
    }
    if (pid == 0) {
        dup2(fds[0], STDIN_FILENO);
        close(fds[0]);
        close(fds[1]);
        /* yuv420p (what players expect) needs even sizes: pad odd ones by a pixel. A GIF gets a
         * palette made for its frames instead; MP4 and MOV their index at the front. */
        bool gif = app_has_extension(path, "gif");
        bool faststart =
            app_has_extension(path, "mp4") || app_has_extension(path, "mov") || app_has_extension(path, "m4v");
        char *args[32] = {program, "-hide_banner", "-loglevel", "error", "-y", "-f", "rawvideo", "-pix_fmt",
                          "rgba",  "-s",           size,        "-r",    rate, "-i", "-"};
        int n = 15;
        if (gif) {
            args[n++] = "-vf";
            args[n++] = flip ? "vflip,split[a][b];[a]palettegen[p];[b][p]paletteuse"
                             : "split[a][b];[a]palettegen[p];[b][p]paletteuse";
        } else {
            args[n++] = "-vf";
            args[n++] = flip ? "vflip,pad=ceil(iw/2)*2:ceil(ih/2)*2" : "pad=ceil(iw/2)*2:ceil(ih/2)*2";
            args[n++] = "-pix_fmt";
            args[n++] = "yuv420p";
        }
        if (faststart) {
            args[n++] = "-movflags";
            args[n++] = "+faststart";
        }
        args[n++] = (char *)target;
        args[n] = NULL;
        execv(program, args);
        _exit(127);
    }
    close(fds[0]);
    video->fd = fds[1];
    video->pid = pid;
    video->frame_bytes = (size_t)width * (size_t)height * 4;
    return SINEW_OK;
}

sinew_result app_video_write(app_video *video, const uint8_t *rgba, sinew_error *error)
{
    size_t done = 0;
    while (done < video->frame_bytes) {
        ssize_t n = write(video->fd, rgba + done, video->frame_bytes - done);
        if (n < 0 && errno == EINTR)
            continue;
        if (n <= 0)
            return sinew_fail(error, SINEW_ERROR_IO, "%s: ffmpeg stopped taking frames (%s)", video->path,
                              strerror(errno));
        done += (size_t)n;
    }
    return SINEW_OK;
}

sinew_result app_video_close(app_video *video, bool keep, sinew_error *error)
{
    if (video->fd > 0)
        close(video->fd);
    video->fd = -1;
    int status = 0;
    bool done = video->pid > 0 && waitpid(video->pid, &status, 0) == video->pid && WIFEXITED(status) &&
                WEXITSTATUS(status) == 0;
    if (!keep) {
        app_output_abort(&video->output);
        return SINEW_ERROR_CANCELLED; /* nothing to say: the caller chose not to keep it */
    }
    if (!done) {
        app_output_abort(&video->output);
        video->write_failed = true;
        return sinew_fail(error, SINEW_ERROR_IO, "%s: ffmpeg failed (%s %d); nothing was written", video->path,
                          WIFEXITED(status) ? "exit status" : "signal",
                          WIFEXITED(status) ? WEXITSTATUS(status) : WTERMSIG(status));
    }
    if (app_output_commit(&video->output, error) != SINEW_OK) {
        video->write_failed = true;
        return error ? error->kind : SINEW_ERROR_IO;
    }
    return SINEW_OK;
}
