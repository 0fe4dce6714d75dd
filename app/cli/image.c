/* Writing frames: PNG files through stb_image_write, video by piping raw frames to ffmpeg. */
#include <errno.h>
#include <signal.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

#include "cli.h"

bool cli_write_image(const char *path, const uint8_t *rgba, int width, int height, bool alpha)
{
    sinew_error error = {0};
    if (app_write_image(path, rgba, width, height, false, alpha, &error) == SINEW_OK)
        return true;
    cli_error("%s", error.message);
    return false;
}

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

bool cli_video_open(cli_video *video, const char *path, int width, int height, double fps)
{
    memset(video, 0, sizeof *video);
    video->fd = -1;
    video->path = path;
    char program[4096];
    if (!find_program("ffmpeg", program, sizeof program)) {
        video->unavailable = true;
        cli_error("%s: writing video needs the ffmpeg program, which is not installed (Debian: apt-get install "
                  "ffmpeg); or write PNG frames with -o DIR/frame%%04d.png",
                  path);
        return false;
    }
    /* ffmpeg writes a temporary file beside the target, renamed into place when it succeeds */
    sinew_error error = {0};
    if (app_output_open(&video->output, path, &error) != SINEW_OK) {
        cli_error("%s", error.message);
        video->write_failed = true;
        return false;
    }
    app_output_release(&video->output);
    const char *target = app_output_temp_path(&video->output);
    int fds[2];
    if (pipe(fds) != 0) {
        cli_error("%s: cannot start ffmpeg: %s", path, strerror(errno));
        app_output_abort(&video->output);
        return false;
    }
    char size[32], rate[32];
    snprintf(size, sizeof size, "%dx%d", width, height);
    snprintf(rate, sizeof rate, "%.6g", fps);
    pid_t pid = fork();
    if (pid < 0) {
        cli_error("%s: cannot start ffmpeg: %s", path, strerror(errno));
        close(fds[0]);
        close(fds[1]);
        app_output_abort(&video->output);
        return false;
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
            args[n++] = "split[a][b];[a]palettegen[p];[b][p]paletteuse";
        } else {
            args[n++] = "-vf";
            args[n++] = "pad=ceil(iw/2)*2:ceil(ih/2)*2";
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
    return true;
}

bool cli_video_write(cli_video *video, const uint8_t *rgba)
{
    size_t done = 0;
    while (done < video->frame_bytes) {
        ssize_t n = write(video->fd, rgba + done, video->frame_bytes - done);
        if (n < 0 && errno == EINTR)
            continue;
        if (n <= 0) {
            cli_error("%s: ffmpeg stopped taking frames (%s)", video->path, strerror(errno));
            return false;
        }
        done += (size_t)n;
    }
    return true;
}

bool cli_video_close(cli_video *video, bool keep)
{
    if (video->fd > 0)
        close(video->fd);
    video->fd = -1;
    int status = 0;
    bool done = video->pid > 0 && waitpid(video->pid, &status, 0) == video->pid && WIFEXITED(status) &&
                WEXITSTATUS(status) == 0;
    if (!keep) {
        app_output_abort(&video->output);
        return false;
    }
    if (!done) {
        app_output_abort(&video->output);
        video->write_failed = true;
        cli_error("%s: ffmpeg failed (%s %d); nothing was written", video->path,
                  WIFEXITED(status) ? "exit status" : "signal",
                  WIFEXITED(status) ? WEXITSTATUS(status) : WTERMSIG(status));
        return false;
    }
    sinew_error error = {0};
    if (app_output_commit(&video->output, &error) != SINEW_OK) {
        video->write_failed = true;
        cli_error("%s", error.message);
        return false;
    }
    return true;
}

void cli_ignore_sigpipe(void)
{
    signal(SIGPIPE, SIG_IGN);
}
