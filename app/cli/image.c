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

bool cli_video_open(cli_video *video, const char *path, int width, int height, double fps)
{
    sinew_error error = {0};
    if (app_video_open(video, path, width, height, fps, false, &error) == SINEW_OK)
        return true;
    cli_error("%s", error.message);
    return false;
}

bool cli_video_write(cli_video *video, const uint8_t *rgba)
{
    sinew_error error = {0};
    if (app_video_write(video, rgba, &error) == SINEW_OK)
        return true;
    cli_error("%s", error.message);
    return false;
}

bool cli_video_close(cli_video *video, bool keep)
{
    sinew_error error = {0};
    if (app_video_close(video, keep, &error) == SINEW_OK)
        return true;
    if (error.kind != SINEW_OK)
        cli_error("%s", error.message);
    return false;
}

void cli_ignore_sigpipe(void)
{
    signal(SIGPIPE, SIG_IGN);
}
