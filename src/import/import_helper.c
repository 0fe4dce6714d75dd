/* sinew-import: the helper program sinew_import() starts (isolate.c). Not meant to be run by
 * hand; its interface is private to libsinew and may change with it.
 *
 *   sinew-import [--assimp] [--memory-limit BYTES] [--parent PID] -- MODEL
 *   sinew-import [--assimp] [--memory-limit BYTES] [--parent PID] --serve   (paths on stdin)
 *
 * Two builds of it: sinew-import has sinew's own readers only and starts in a few milliseconds;
 * for a file that needs Assimp it execs sinew-import-assimp (the same program with Assimp linked)
 * with the same arguments, keeping its pid, limits and pipes.
 *
 * It dies with the thread that started it (PR_SET_PDEATHSIG, and a check that the parent is
 * still the one named), limits its own address space, imports MODEL and writes the reply
 * (reply_header, then the blob or the error text) to stdout. Anything else that writes to
 * stdout (a library's stray print) is sent to stderr, which the parent keeps or passes on.
 */
#define _GNU_SOURCE
#include <errno.h>
#include <limits.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/prctl.h>
#include <sys/resource.h>
#include <unistd.h>

#include "internal.h"
#include "sinew/import.h"

static bool write_all(int fd, const void *data, size_t size)
{
    const char *p = data;
    while (size > 0) {
        ssize_t n = write(fd, p, size);
        if (n < 0 && errno == EINTR)
            continue;
        if (n <= 0)
            return false;
        p += n;
        size -= (size_t)n;
    }
    return true;
}

static bool read_all(int fd, void *data, size_t size)
{
    char *p = data;
    while (size > 0) {
        ssize_t n = read(fd, p, size);
        if (n < 0 && errno == EINTR)
            continue;
        if (n <= 0)
            return false;
        p += n;
        size -= (size_t)n;
    }
    return true;
}

/* Imports the file and writes the reply: the blob, or the error. */
static bool reply_to(const sinew_import_desc *desc, int reply_fd)
{
    sinew_error error = {0};
    void *bytes = NULL;
    size_t size = 0;
    sinew_result result = sinew_import_blob_desc(desc, &bytes, &size, &error);
    reply_header reply = {.magic = REPLY_MAGIC, .kind = result};
    const void *payload = bytes;
    unsigned char said[sizeof error.message + REPLY_ERROR_TRAILER];
    if (result) { /* the message, its NUL, then where: offset (8 bytes) and line (4), little-endian */
        size_t n = strlen(error.message) + 1;
        memcpy(said, error.message, n);
        import_reply_put_where(said + n, error.offset, error.line);
        payload = said;
        size = n + REPLY_ERROR_TRAILER;
    }
    reply.size = size;
    bool ok = write_all(reply_fd, &reply, sizeof reply) && write_all(reply_fd, payload, size);
    free(bytes);
    return ok;
}

/* --serve (a session): paths arrive on stdin (a 32-bit length, then the bytes), a reply goes
 * out for each, until stdin ends. */
static int serve_requests(sinew_import_desc *desc, int reply_fd)
{
    static char path[PATH_MAX];
    for (;;) {
        uint32_t length = 0;
        if (!read_all(STDIN_FILENO, &length, sizeof length))
            return close(reply_fd) == 0 ? 0 : 67;
        if (length == 0 || length >= sizeof path || !read_all(STDIN_FILENO, path, length))
            return 68;
        path[length] = '\0';
        desc->path = path;
        if (!reply_to(desc, reply_fd))
            return 67;
    }
}

static int usage(void)
{
    fprintf(stderr, "usage: sinew-import [--assimp] [--memory-limit BYTES] [--parent PID] (-- MODEL | --serve)\n"
                    "(the import helper of libsinew: sinew_import() runs it; see sinew/import.h)\n");
    return 64;
}

/* The address-space limit; not under AddressSanitizer, which reserves terabytes of it (the
 * parent watches resident memory instead). */
static void limit_memory(unsigned long long bytes)
{
#if !defined(__SANITIZE_ADDRESS__)
    if (bytes && bytes != (unsigned long long)UINT64_MAX) {
        struct rlimit limit = {.rlim_cur = (rlim_t)bytes, .rlim_max = (rlim_t)bytes};
        setrlimit(RLIMIT_AS, &limit);
    }
#else
    (void)bytes;
#endif
}

int main(int argc, char **argv)
{
    sinew_import_desc desc = {0};
    unsigned long long memory = 0;
    long parent = 0;
    bool serve = false;
    int i = 1;
    for (; i < argc && strcmp(argv[i], "--") != 0; i++) {
        char *end = NULL;
        if (strcmp(argv[i], "--assimp") == 0)
            desc.assimp = true;
        else if (strcmp(argv[i], "--memory-limit") == 0 && i + 1 < argc)
            memory = strtoull(argv[++i], &end, 10);
        else if (strcmp(argv[i], "--serve") == 0)
            serve = true;
        else if (strcmp(argv[i], "--parent") == 0 && i + 1 < argc)
            parent = strtol(argv[++i], &end, 10);
        else
            return usage();
        if (end && *end)
            return usage();
    }
    if (serve ? i != argc : i + 2 != argc)
        return usage();
    if (!serve)
        desc.path = argv[i + 1];
    desc.timeout = -1.0; /* the parent keeps the deadline: it kills a helper past it */
    import_assimp_reader = raw_model_from_assimp;

    prctl(PR_SET_PDEATHSIG, SIGKILL);
    if (parent && getppid() != (pid_t)parent)
        return 65; /* the parent died before the line above */
    limit_memory(memory);
    int reply_fd = dup(STDOUT_FILENO);
    if (reply_fd < 0 || dup2(STDERR_FILENO, STDOUT_FILENO) < 0)
        return 66;
    if (serve)
        return serve_requests(&desc, reply_fd);
#ifdef SINEW_LEAN_HELPER
    import_helper_set_exec(argv, reply_fd);
#endif

    bool ok = reply_to(&desc, reply_fd);
    return ok && close(reply_fd) == 0 ? 0 : 67;
}
