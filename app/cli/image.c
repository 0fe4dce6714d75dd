/* Writing frames: PNG files through stb_image_write, video by piping raw frames to ffmpeg. */
#include <errno.h>
#include <signal.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

#include <stb_image_write.h>

#include "cli.h"

bool cli_write_png(const char *path, const uint8_t *rgba, int width, int height)
{
    /* Alpha is always opaque: RGB keeps the files smaller. */
    size_t n = (size_t)width * (size_t)height;
    uint8_t *rgb = malloc(n * 3);
    if (!rgb) {
        cli_error("%s: out of memory", path);
        return false;
    }
    for (size_t i = 0; i < n; i++)
        memcpy(&rgb[i * 3], &rgba[i * 4], 3);
    errno = 0;
    int ok = stbi_write_png(path, width, height, 3, rgb, width * 3);
    free(rgb);
    if (!ok)
        cli_error("%s: cannot write the image (%s)", path, errno ? strerror(errno) : "encoder failed");
    return ok != 0;
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
    int fds[2];
    if (pipe(fds) != 0) {
        cli_error("%s: cannot start ffmpeg: %s", path, strerror(errno));
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
        return false;
    }
    if (pid == 0) {
        dup2(fds[0], STDIN_FILENO);
        close(fds[0]);
        close(fds[1]);
        /* yuv420p (what players expect) needs even sizes: pad odd ones by a pixel. */
        char *const args[] = {program,
                              "-hide_banner",
                              "-loglevel",
                              "error",
                              "-y",
                              "-f",
                              "rawvideo",
                              "-pix_fmt",
                              "rgba",
                              "-s",
                              size,
                              "-r",
                              rate,
                              "-i",
                              "-",
                              "-vf",
                              "pad=ceil(iw/2)*2:ceil(ih/2)*2",
                              "-pix_fmt",
                              "yuv420p",
                              "-movflags",
                              "+faststart",
                              (char *)path,
                              NULL};
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

bool cli_video_close(cli_video *video)
{
    if (video->fd > 0)
        close(video->fd);
    video->fd = -1;
    int status = 0;
    if (video->pid > 0 && waitpid(video->pid, &status, 0) == video->pid && WIFEXITED(status) &&
        WEXITSTATUS(status) == 0)
        return true;
    cli_error("%s: ffmpeg failed (%s %d); nothing usable was written", video->path,
              WIFEXITED(status) ? "exit status" : "signal", WIFEXITED(status) ? WEXITSTATUS(status) : WTERMSIG(status));
    return false;
}

void cli_ignore_sigpipe(void)
{
    signal(SIGPIPE, SIG_IGN);
}
