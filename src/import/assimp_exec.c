/* The lean import helper's Assimp: sinew-import links sinew's own readers only (FBX, glTF,
 * COLLADA, IQM, BVH, .sinew), so that it starts in a few milliseconds; a file that needs Assimp
 * makes it become sinew-import-assimp (beside it) with the same arguments. exec keeps the
 * process: its pid (the parent's deadline), its memory limit, its parent-death signal and its
 * pipes stay, so the parent sees one helper either way. */
#define _GNU_SOURCE
#include <errno.h>
#include <limits.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>

#include "internal.h"

static char **helper_argv;
static int helper_reply_fd = -1;

void import_helper_set_exec(char **argv, int reply_fd)
{
    helper_argv = argv;
    helper_reply_fd = reply_fd;
}

sinew_result raw_model_from_assimp(const char *path, raw_model *model, sinew_error *error)
{
    (void)model;
    char self[PATH_MAX], target[PATH_MAX + 32];
    ssize_t n = readlink("/proc/self/exe", self, sizeof self - 1);
    if (n <= 0 || !helper_argv)
        return sinew_fail(error, SINEW_ERROR_IMPORTER,
                          "%s: needs Assimp, and the import helper cannot find its own "
                          "folder to start sinew-import-assimp",
                          path);
    self[n] = '\0';
    char *slash = strrchr(self, '/');
    if (slash)
        *slash = '\0';
    snprintf(target, sizeof target, "%s/sinew-import-assimp", self);
    /* the reply goes to stdout again, as a freshly started helper expects */
    if (helper_reply_fd >= 0 && dup2(helper_reply_fd, STDOUT_FILENO) < 0)
        return sinew_fail(error, SINEW_ERROR_IMPORTER, "%s: cannot hand over to %s: %s", path, target, strerror(errno));
    helper_argv[0] = target;
    execv(target, helper_argv);
    int saved = errno;
    if (helper_reply_fd >= 0)
        dup2(STDERR_FILENO, STDOUT_FILENO);
    return sinew_fail(error, SINEW_ERROR_IMPORTER, "%s: needs Assimp, and %s cannot be run: %s", path, target,
                      strerror(saved));
}
