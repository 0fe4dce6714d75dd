/* The import helper: sinew_import() runs the readers in a separate program (sinew-import,
 * import_helper.c) so that a crash, a hang or a runaway allocation in Assimp or a reader
 * costs an error message, never the caller.
 *
 * Index: finding the helper - spawning it (posix_spawn: safe in a multithreaded host) -
 * watching it (reply and stderr pipes, deadline, memory) - what its end means - the reply.
 *
 * The helper writes one message to its stdout: a reply header (magic, status, payload size)
 * and then either the model blob or the error text. The parent checks the size in the
 * header against the memory limit before it allocates, so a lying helper cannot make it
 * allocate more than the helper itself was allowed.
 */
#define _GNU_SOURCE /* pipe2, dladdr, posix_spawn_file_actions_addclosefrom_np */
#include <dlfcn.h>
#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <poll.h>
#include <signal.h>
#include <spawn.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "../core/internal.h"
#include "internal.h"
#include "sinew/import.h"

extern char **environ;

#define HELPER_NAME "sinew-import"
#define DEFAULT_TIMEOUT 120.0
#define WATCH_MS 50    /* how often the helper's memory is looked at */
#define TAIL_SIZE 1536 /* the end of the helper's stderr kept for the error message */

/* ---- finding the helper ------------------------------------------------------------------ */

static bool is_program(const char *path)
{
    struct stat st;
    return stat(path, &st) == 0 && S_ISREG(st.st_mode) && access(path, X_OK) == 0;
}

/* The folder of a file path (in place). */
static void strip_name(char *path)
{
    char *slash = strrchr(path, '/');
    if (slash)
        *slash = '\0';
}

static bool try_in(const char *folder, const char *relative, char *out, size_t size, char *looked, size_t looked_size)
{
    char candidate[PATH_MAX + 64];
    snprintf(candidate, sizeof candidate, "%s/%s%s" HELPER_NAME, folder, relative, *relative ? "/" : "");
    size_t n = strlen(looked);
    snprintf(looked + n, looked_size - n, "%s%s", n ? ", " : "", candidate);
    if (!is_program(candidate))
        return false;
    snprintf(out, size, "%s", candidate);
    return true;
}

sinew_result sinew_import_helper_path(const sinew_import_desc *desc, char *out, size_t size, sinew_error *error)
{
    if (!out || size == 0)
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "sinew_import_helper_path: no output");
    const char *given = desc && desc->helper ? desc->helper : getenv("SINEW_IMPORT_HELPER");
    if (given && *given) {
        if (!is_program(given))
            return sinew_fail(error, SINEW_ERROR_IO, "the import helper %s is not an executable program%s", given,
                              desc && desc->helper ? "" : " ($SINEW_IMPORT_HELPER)");
        snprintf(out, size, "%s", given);
        return SINEW_OK;
    }
    char looked[4 * PATH_MAX] = "", folder[PATH_MAX];
    /* Beside the program (a build tree, or bin/ next to libexec/), then beside the library. */
    ssize_t n = readlink("/proc/self/exe", folder, sizeof folder - 1);
    if (n > 0) {
        folder[n] = '\0';
        strip_name(folder);
        if (try_in(folder, "", out, size, looked, sizeof looked) ||
            try_in(folder, SINEW_BIN_TO_LIBEXEC, out, size, looked, sizeof looked))
            return SINEW_OK;
    }
    static const char anchor = 0; /* an address inside this library */
    Dl_info info;
    if (dladdr(&anchor, &info) && info.dli_fname && strchr(info.dli_fname, '/')) {
        snprintf(folder, sizeof folder, "%s", info.dli_fname);
        strip_name(folder);
        /* the installed libexec folder, or the library's own (a build tree, where a program
         * elsewhere, such as Python, loads it) */
        if (!strstr(looked, folder) && (try_in(folder, SINEW_LIB_TO_LIBEXEC, out, size, looked, sizeof looked) ||
                                        try_in(folder, "", out, size, looked, sizeof looked)))
            return SINEW_OK;
    }
    if (try_in(SINEW_INSTALL_LIBEXEC, "", out, size, looked, sizeof looked))
        return SINEW_OK;
    return sinew_fail(error, SINEW_ERROR_IO,
                      "cannot find the import helper " HELPER_NAME " (looked for %s); install it beside sinew, "
                      "set $SINEW_IMPORT_HELPER, or import in process",
                      looked);
}

/* ---- the limits ------------------------------------------------------------------------------ */

/* The default's ceiling: half the machine's memory, within 1..16 GiB. */
static uint64_t memory_ceiling(void)
{
    long pages = sysconf(_SC_PHYS_PAGES), page = sysconf(_SC_PAGESIZE);
    uint64_t half = pages > 0 && page > 0 ? (uint64_t)pages * (uint64_t)page / 2 : (uint64_t)4 << 30;
    const uint64_t lo = (uint64_t)1 << 30, hi = (uint64_t)16 << 30;
    return half < lo ? lo : half > hi ? hi : half;
}

/* desc->memory_limit, or its default: from the file's size, IMPORT_MEMORY_BASE plus
 * IMPORT_MEMORY_FACTOR times the size (readers expand a file: compressed FBX arrays, Assimp's
 * text parsers), at most the ceiling; the ceiling for a file whose size is unknown (a session). */
static uint64_t memory_limit_of(const sinew_import_desc *desc)
{
    if (desc->memory_limit)
        return desc->memory_limit;
    struct stat st;
    if (!desc->path || stat(desc->path, &st) != 0 || !S_ISREG(st.st_mode))
        return memory_ceiling();
    uint64_t limit = import_default_memory_limit((uint64_t)st.st_size);
#if defined(__SANITIZE_ADDRESS__)
    /* AddressSanitizer's shadow, redzones and 256 MiB quarantine are not the file's */
    limit = limit * 4 + ((uint64_t)256 << 20);
#endif
    uint64_t ceiling = memory_ceiling();
    return limit < ceiling ? limit : ceiling;
}

uint64_t import_default_memory_limit(uint64_t size)
{
    uint64_t ceiling = memory_ceiling();
    if (!size)
        return ceiling;
    uint64_t limit = size > ceiling / SINEW_IMPORT_MEMORY_FACTOR
                         ? ceiling
                         : SINEW_IMPORT_MEMORY_BASE + size * SINEW_IMPORT_MEMORY_FACTOR;
    return limit < ceiling ? limit : ceiling;
}

double import_timeout_of(const sinew_import_desc *desc)
{
    return desc->timeout == 0.0 ? DEFAULT_TIMEOUT : desc->timeout;
}

static double now_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

static void format_bytes(uint64_t bytes, char *out, size_t size)
{
    if (bytes >= (uint64_t)1 << 30)
        snprintf(out, size, "%.1f GiB", (double)bytes / (double)((uint64_t)1 << 30));
    else
        snprintf(out, size, "%.0f MiB", (double)bytes / (double)(1 << 20));
}

/* ---- spawning --------------------------------------------------------------------------------- */

typedef struct helper_run {
    const char *path; /* the model file, for messages */
    pid_t pid;
    int reply_fd, err_fd; /* -1 once at end of file (err_fd: or not captured) */
    unsigned char *reply;
    size_t reply_size, reply_cap;
    uint64_t reply_limit;
    bool reply_too_big;
    char tail[TAIL_SIZE];
    size_t tail_len;
    uint64_t peak_rss, peak_vm, memory_limit;
    bool default_limit; /* memory_limit is the default from the file's size */
    bool killed_for_time, killed_for_memory, cancelled;
    bool (*progress)(float fraction, void *user);
    void *progress_user;
    bool serving;     /* a session's helper: it stays after a whole reply */
    bool header_seen; /* the reply's header arrived (reply_cap is then the whole reply's size) */
} helper_run;

/* Starts the helper on desc->path, or (request_fd not NULL) serving the paths written to
 * *request_fd, a socket (sends to a dead helper fail with EPIPE instead of raising SIGPIPE). */
static sinew_result spawn_helper(const sinew_import_desc *desc, const char *helper, helper_run *run, int *request_fd,
                                 sinew_error *error)
{
    int reply[2] = {-1, -1}, err[2] = {-1, -1}, request[2] = {-1, -1};
    const char *what = request_fd ? "the import session" : desc->path;
    if (pipe2(reply, O_CLOEXEC) != 0 || (desc->stderr_fd == 0 && pipe2(err, O_CLOEXEC) != 0) ||
        (request_fd && socketpair(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0, request) != 0)) {
        int e = errno;
        for (int i = 0; i < 2; i++) {
            if (reply[i] >= 0)
                close(reply[i]);
            if (err[i] >= 0)
                close(err[i]);
            if (request[i] >= 0)
                close(request[i]);
        }
        return sinew_fail(error, SINEW_ERROR_IO, "%s: cannot start the import helper: %s", what, strerror(e));
    }
    char limit[32], parent[32];
    snprintf(limit, sizeof limit, "%llu", (unsigned long long)run->memory_limit);
    snprintf(parent, sizeof parent, "%ld", (long)getpid());
    char *argv[10];
    int argc = 0;
    argv[argc++] = (char *)HELPER_NAME;
    if (desc->assimp)
        argv[argc++] = (char *)"--assimp";
    argv[argc++] = (char *)"--memory-limit";
    argv[argc++] = limit;
    argv[argc++] = (char *)"--parent";
    argv[argc++] = parent;
    if (request_fd) {
        argv[argc++] = (char *)"--serve";
    } else {
        argv[argc++] = (char *)"--";
        argv[argc++] = (char *)desc->path;
    }
    argv[argc] = NULL;

    posix_spawn_file_actions_t actions;
    posix_spawnattr_t attr;
    posix_spawn_file_actions_init(&actions);
    posix_spawnattr_init(&attr);
    if (request_fd)
        posix_spawn_file_actions_adddup2(&actions, request[1], STDIN_FILENO);
    else
        posix_spawn_file_actions_addopen(&actions, STDIN_FILENO, "/dev/null", O_RDONLY, 0);
    posix_spawn_file_actions_adddup2(&actions, reply[1], STDOUT_FILENO);
    posix_spawn_file_actions_adddup2(&actions, err[1] >= 0 ? err[1] : desc->stderr_fd, STDERR_FILENO);
#if defined(__GLIBC__) && (__GLIBC__ > 2 || (__GLIBC__ == 2 && __GLIBC_MINOR__ >= 34))
    posix_spawn_file_actions_addclosefrom_np(&actions, 3); /* the host's other descriptors */
#endif
    /* The host may block or ignore signals (a GUI, a job system); the helper starts clean. */
    sigset_t none, all;
    sigemptyset(&none);
    sigfillset(&all);
    posix_spawnattr_setsigmask(&attr, &none);
    posix_spawnattr_setsigdefault(&attr, &all);
    posix_spawnattr_setflags(&attr, POSIX_SPAWN_SETSIGMASK | POSIX_SPAWN_SETSIGDEF);
    int rc = posix_spawn(&run->pid, helper, &actions, &attr, argv, environ);
    posix_spawn_file_actions_destroy(&actions);
    posix_spawnattr_destroy(&attr);
    close(reply[1]);
    if (err[1] >= 0)
        close(err[1]);
    if (request[1] >= 0)
        close(request[1]);
    if (rc != 0) {
        close(reply[0]);
        if (err[0] >= 0)
            close(err[0]);
        if (request[0] >= 0)
            close(request[0]);
        return sinew_fail(error, SINEW_ERROR_IO, "%s: cannot start the import helper %s: %s", what, helper,
                          strerror(rc));
    }
    run->reply_fd = reply[0];
    run->err_fd = err[0];
    if (request_fd)
        *request_fd = request[0];
    return SINEW_OK;
}

/* ---- watching it ----------------------------------------------------------------------------- */

static void keep_tail(helper_run *run, const char *bytes, size_t n)
{
    if (n >= TAIL_SIZE - 1) {
        bytes += n - (TAIL_SIZE - 1);
        n = TAIL_SIZE - 1;
    }
    if (run->tail_len + n > TAIL_SIZE - 1) {
        size_t drop = run->tail_len + n - (TAIL_SIZE - 1);
        memmove(run->tail, run->tail + drop, run->tail_len - drop);
        run->tail_len -= drop;
    }
    memcpy(run->tail + run->tail_len, bytes, n);
    run->tail_len += n;
    run->tail[run->tail_len] = '\0';
}

/* Appends what arrived on the reply pipe; false when the reply is larger than its header
 * says or than the helper could have made (then nothing more is read). */
static bool take_reply(helper_run *run, const unsigned char *bytes, size_t n)
{
    if (!run->reply) {
        run->reply = malloc(sizeof(reply_header));
        run->reply_cap = run->reply ? sizeof(reply_header) : 0;
    }
    if (run->reply_size + n > run->reply_cap) { /* more than the header announced */
        run->reply_too_big = true;
        return false;
    }
    memcpy(run->reply + run->reply_size, bytes, n);
    run->reply_size += n;
    /* The header arrives alone (drain() reads no further): room for exactly what it
     * announces, once, when that fits the limit. */
    if (run->reply_size == sizeof(reply_header) && run->reply_cap == sizeof(reply_header)) {
        reply_header h;
        memcpy(&h, run->reply, sizeof h);
        unsigned char *whole = h.size <= run->reply_limit && h.size <= SIZE_MAX - sizeof h
                                   ? realloc(run->reply, sizeof h + (size_t)h.size)
                                   : NULL;
        if (!whole) {
            run->reply_too_big = true;
            return false;
        }
        run->reply = whole;
        run->reply_cap = sizeof h + (size_t)h.size;
        run->header_seen = true;
    }
    return true;
}

/* Reads what is ready on one pipe; closes it at end of file. */
static void drain(helper_run *run, int *fd, bool is_reply)
{
    unsigned char buf[65536];
    size_t ask = sizeof buf;
    if (is_reply && run->reply_size < sizeof(reply_header))
        ask = sizeof(reply_header) - run->reply_size; /* the header alone first */
    ssize_t n = read(*fd, buf, ask);
    if (n < 0 && (errno == EINTR || errno == EAGAIN))
        return;
    if (n <= 0 || (is_reply && !take_reply(run, buf, (size_t)n))) {
        close(*fd);
        *fd = -1;
        return;
    }
    if (!is_reply)
        keep_tail(run, (const char *)buf, (size_t)n);
}

/* The helper's virtual size and resident memory, from /proc. */
static void sample_memory(helper_run *run)
{
    char name[64];
    snprintf(name, sizeof name, "/proc/%ld/statm", (long)run->pid);
    FILE *f = fopen(name, "r");
    if (!f)
        return;
    unsigned long long vm = 0, rss = 0;
    if (fscanf(f, "%llu %llu", &vm, &rss) == 2) {
        uint64_t page = (uint64_t)sysconf(_SC_PAGESIZE);
        if (vm * page > run->peak_vm)
            run->peak_vm = vm * page;
        if (rss * page > run->peak_rss)
            run->peak_rss = rss * page;
    }
    fclose(f);
}

/* Until both pipes close, the deadline passes or resident memory passes the limit (the
 * address-space limit the helper sets on itself does not hold under AddressSanitizer). */
static void watch(helper_run *run, double deadline)
{
    double next_sample = 0.0;
    while (run->reply_fd >= 0 || run->err_fd >= 0) {
        struct pollfd fds[2];
        nfds_t count = 0;
        if (run->reply_fd >= 0)
            fds[count++] = (struct pollfd){.fd = run->reply_fd, .events = POLLIN};
        if (run->err_fd >= 0)
            fds[count++] = (struct pollfd){.fd = run->err_fd, .events = POLLIN};
        int ready = poll(fds, count, WATCH_MS);
        for (nfds_t i = 0; ready > 0 && i < count; i++) {
            if (!fds[i].revents)
                continue;
            bool is_reply = fds[i].fd == run->reply_fd;
            drain(run, is_reply ? &run->reply_fd : &run->err_fd, is_reply);
        }
        /* every WATCH_MS, not after every read: a large reply arrives in many reads */
        double now = now_seconds();
        if (now >= next_sample) {
            sample_memory(run);
            next_sample = now + WATCH_MS * 1e-3;
            float fraction =
                run->reply_cap > sizeof(reply_header) ? (float)run->reply_size / (float)run->reply_cap : -1.0f;
            if (run->progress && !run->progress(fraction, run->progress_user)) {
                run->cancelled = true;
                break;
            }
        }
        if (run->memory_limit != UINT64_MAX && run->peak_rss > run->memory_limit) {
            run->killed_for_memory = true;
            break;
        }
        if (deadline > 0.0 && now > deadline) {
            run->killed_for_time = true;
            break;
        }
        if (run->reply_too_big)
            break;
        if (run->serving && run->header_seen && run->reply_size == run->reply_cap)
            return; /* a whole reply: the session's helper waits for the next file */
    }
    if (run->reply_fd >= 0 || run->err_fd >= 0)
        kill(run->pid, SIGKILL);
    if (run->reply_fd >= 0)
        close(run->reply_fd);
    if (run->err_fd >= 0)
        close(run->err_fd);
}

/* Waits for the helper's end; one that closed its pipes and lingers past the deadline is killed. */
static int reap(helper_run *run, double deadline)
{
    int status = 0;
    long pause_ns = 50 * 1000; /* the helper closed its pipes and is exiting: look again soon, then less often */
    for (;;) {
        pid_t done = waitpid(run->pid, &status, deadline > 0.0 ? WNOHANG : 0);
        if (done == run->pid)
            return status;
        if (done < 0 && errno != EINTR)
            return 0;
        if (done == 0 && now_seconds() > deadline) {
            run->killed_for_time = true;
            kill(run->pid, SIGKILL);
            deadline = 0.0;
        } else if (done == 0) {
            nanosleep(&(struct timespec){.tv_nsec = pause_ns}, NULL);
            pause_ns = pause_ns * 2 > 5 * 1000 * 1000 ? 5 * 1000 * 1000 : pause_ns * 2;
        }
    }
}

/* ---- what its end means ---------------------------------------------------------------------- */

/* The helper's last words, for a message: its stderr's last lines on one line. */
static const char *last_words(helper_run *run)
{
    char *t = run->tail;
    while (*t == '\n' || *t == ' ')
        t++;
    for (char *c = t; *c; c++)
        if (*c == '\n' || *c == '\t')
            *c = ' ';
    size_t n = strlen(t);
    while (n && t[n - 1] == ' ')
        t[--n] = '\0';
    return t;
}

/* Whether the helper came within a tenth of its memory limit (a failure then is the limit's). */
static bool near_memory_limit(const helper_run *run)
{
#if defined(__SANITIZE_ADDRESS__)
    uint64_t peak = run->peak_rss; /* the sanitizer reserves terabytes of address space */
#else
    uint64_t peak = run->peak_vm;
#endif
    /* (a limit of 0: no helper was started) */
    return run->memory_limit != 0 && run->memory_limit != UINT64_MAX && peak >= run->memory_limit / 10 * 9;
}

static sinew_result memory_failure(const helper_run *run, const char *said, sinew_error *error)
{
    char limit[32], seen[32];
    format_bytes(run->memory_limit, limit, sizeof limit);
    format_bytes(run->peak_rss > run->peak_vm ? run->peak_rss : run->peak_vm, seen, sizeof seen);
    return sinew_fail(error, SINEW_ERROR_LIMIT_MEMORY,
                      "%s: the import needed more than its %s memory limit and was stopped (%s in use when last "
                      "measured; %s; sinew_import_desc.memory_limit sets another)%s%s",
                      run->path, limit, seen,
                      run->default_limit ? "the default for a file of its size: 256 MiB and 64 times the size, at "
                                           "most half the memory"
                                         : "the limit asked for",
                      *said ? "; the reader said: " : "", said);
}

static sinew_result helper_failed(helper_run *run, const sinew_import_desc *desc, int status, sinew_error *error)
{
    char limit[32];
    format_bytes(run->memory_limit, limit, sizeof limit);
    const char *words = last_words(run);
    const char *lead = *words ? "; its last words: " : "";
    if (run->cancelled)
        return sinew_fail(error, SINEW_ERROR_CANCELLED, "%s: the import was cancelled", run->path);
    if (run->killed_for_time)
        return sinew_fail(error, SINEW_ERROR_LIMIT_TIME,
                          "%s: the import took longer than its %.3g s deadline and was stopped (the file may make "
                          "the reader loop; sinew_import_desc.timeout sets the deadline)",
                          run->path, import_timeout_of(desc));
    if (run->killed_for_memory || near_memory_limit(run))
        return memory_failure(run, words, error);
    if (run->reply_too_big)
        return sinew_fail(error, SINEW_ERROR_IMPORTER,
                          "%s: the import helper's reply is larger than it announced or than its %s memory limit "
                          "allows",
                          run->path, limit);
    if (WIFSIGNALED(status)) {
        int sig = WTERMSIG(status);
        if (sig == SIGKILL || sig == SIGTERM || sig == SIGINT || sig == SIGHUP)
            return sinew_fail(error, SINEW_ERROR_IMPORTER,
                              "%s: the import helper was killed from outside (signal %d, %s): by a user, or by the "
                              "system when memory ran out%s%s",
                              run->path, sig, strsignal(sig), lead, words);
        return sinew_fail(error, SINEW_ERROR_IMPORTER,
                          "%s: the importer (%s) crashed while reading this file (signal %d, %s); the file is "
                          "probably malformed%s%s",
                          run->path, import_reader_name(run->path, desc->assimp), sig, strsignal(sig), lead, words);
    }
    return sinew_fail(error, SINEW_ERROR_IMPORTER, "%s: the import helper failed (exit status %d)%s%s", run->path,
                      WIFEXITED(status) ? WEXITSTATUS(status) : -1, lead, words);
}

/* The payload of a whole reply: SINEW_OK with the blob, else the helper's error (or the reply's
 * fault) in `error`. */
static sinew_result reply_blob(const unsigned char *bytes, size_t size, const char *path, const unsigned char **blob,
                               size_t *blob_size, sinew_error *error)
{
    reply_header reply;
    if (size < sizeof reply)
        return sinew_fail(error, SINEW_ERROR_IMPORTER, "%s: the import helper's reply is cut short (%zu bytes)", path,
                          size);
    memcpy(&reply, bytes, sizeof reply);
    if (reply.magic != REPLY_MAGIC || reply.size != size - sizeof reply)
        return sinew_fail(error, SINEW_ERROR_IMPORTER,
                          "%s: the import helper's reply is malformed (%zu bytes, header says %llu)", path, size,
                          (unsigned long long)reply.size);
    const unsigned char *payload = bytes + sizeof reply;
    if (reply.kind == SINEW_OK) {
        *blob = payload;
        *blob_size = (size_t)reply.size;
        return SINEW_OK;
    }
    const unsigned char *nul = reply.size ? memchr(payload, 0, (size_t)reply.size) : NULL;
    size_t text = nul ? (size_t)(nul - payload) + 1 : 0;
    if (reply.kind > SINEW_RESULT_LAST || !nul || (text != reply.size && text + REPLY_ERROR_TRAILER != reply.size))
        return sinew_fail(error, SINEW_ERROR_IMPORTER, "%s: the import helper's error reply is malformed", path);
    int64_t offset = -1;
    uint32_t line = 0;
    if (text != reply.size) {
        uint64_t o = 0;
        for (int i = 7; i >= 0; i--)
            o = o << 8 | payload[text + (size_t)i];
        for (int i = 3; i >= 0; i--)
            line = line << 8 | payload[text + 8 + (size_t)i];
        offset = (int64_t)o;
    }
    return sinew_fail_at(error, (sinew_result)reply.kind, path, offset < -1 ? -1 : offset, line, "%s",
                         (const char *)payload);
}

sinew_result import_reply_decode(const unsigned char *bytes, size_t size, const char *path,
                                 const sinew_allocator *allocator, sinew_model **out, sinew_error *error)
{
    const unsigned char *blob = NULL;
    size_t blob_size = 0;
    sinew_result result = reply_blob(bytes, size, path, &blob, &blob_size, error);
    return result ? result : sinew_model_from_blob(blob, blob_size, path, allocator, out, error);
}

void import_reply_put_where(unsigned char *out, int64_t offset, uint32_t line)
{
    uint64_t o = (uint64_t)offset;
    for (int i = 0; i < 8; i++)
        out[i] = (unsigned char)(o >> (8 * i));
    for (int i = 0; i < 4; i++)
        out[8 + i] = (unsigned char)(line >> (8 * i));
}

/* A reader in the helper that gave up for want of memory (Assimp's std::bad_alloc), or came
 * near the limit before failing, failed for the limit. */
static sinew_result starved_is_limit(const helper_run *run, sinew_result result, sinew_error *error)
{
    reply_header reply = {0};
    if (run->reply_size >= sizeof reply)
        memcpy(&reply, run->reply, sizeof reply);
    bool starved = reply.kind == SINEW_ERROR_OUT_OF_MEMORY ||
                   (reply.kind != SINEW_OK && error && strstr(error->message, "bad_alloc"));
    if (result != SINEW_OK && result != SINEW_ERROR_LIMIT_TIME && result != SINEW_ERROR_LIMIT_MEMORY &&
        !run->cancelled && (starved || near_memory_limit(run))) {
        char said[SINEW_ERROR_MESSAGE_SIZE] = "";
        if (error)
            snprintf(said, sizeof said, "%s", error->message);
        result = memory_failure(run, said, error);
    }
    return result;
}

/* Runs the helper on desc->path; its whole reply (malloc'd) in run->reply, or the error. */
static sinew_result run_helper(const sinew_import_desc *desc, helper_run *run, sinew_error *error)
{
    char helper[PATH_MAX];
    sinew_result result = sinew_import_helper_path(desc, helper, sizeof helper, error);
    if (result)
        return result;
    *run = (helper_run){.path = desc->path,
                        .reply_fd = -1,
                        .err_fd = -1,
                        .memory_limit = memory_limit_of(desc),
                        .default_limit = desc->memory_limit == 0,
                        .progress = desc->progress,
                        .progress_user = desc->progress_user};
    run->reply_limit = run->memory_limit;
    if ((result = spawn_helper(desc, helper, run, NULL, error)))
        return result;
    double timeout = import_timeout_of(desc), deadline = timeout > 0.0 ? now_seconds() + timeout : 0.0;
    watch(run, deadline);
    int status = reap(run, deadline);
    if (run->cancelled || run->killed_for_time || run->killed_for_memory || run->reply_too_big ||
        !(WIFEXITED(status) && WEXITSTATUS(status) == 0))
        result = helper_failed(run, desc, status, error);
    return result;
}

sinew_result import_in_helper(const sinew_import_desc *desc, sinew_model **out, sinew_error *error)
{
    helper_run run = {0};
    sinew_result result = run_helper(desc, &run, error);
    if (result == SINEW_OK)
        result = import_reply_decode(run.reply, run.reply_size, desc->path, desc->allocator, out, error);
    result = starved_is_limit(&run, result, error);
    free(run.reply);
    return result;
}

sinew_result import_blob_in_helper(const sinew_import_desc *desc, void **bytes, size_t *size, sinew_error *error)
{
    helper_run run = {0};
    const unsigned char *blob = NULL;
    size_t blob_size = 0;
    sinew_result result = run_helper(desc, &run, error);
    if (result == SINEW_OK)
        result = reply_blob(run.reply, run.reply_size, desc->path, &blob, &blob_size, error);
    if (result == SINEW_OK) { /* the blob, moved to the front of the reply, is the caller's */
        memmove(run.reply, blob, blob_size);
        *bytes = run.reply;
        *size = blob_size;
        return SINEW_OK;
    }
    result = starved_is_limit(&run, result, error);
    free(run.reply);
    return result;
}

/* ---- a session: one helper for many files ----------------------------------------------------- */

struct sinew_import_session {
    sinew_import_desc desc; /* path unused; helper kept in `helper` */
    char helper[PATH_MAX];
    pid_t pid; /* 0: none running */
    int request_fd, reply_fd, err_fd;
    uint64_t memory_limit;
};

/* Ends the helper (killed, or told its requests are over) and closes its pipes; `reaped`: it has
 * ended and been waited for already. */
static void session_stop(sinew_import_session *s, bool kill_it, bool reaped)
{
    if (!s->pid)
        return;
    if (s->request_fd >= 0)
        close(s->request_fd); /* end of requests: the helper exits */
    if (kill_it && !reaped)
        kill(s->pid, SIGKILL);
    if (s->reply_fd >= 0)
        close(s->reply_fd);
    if (s->err_fd >= 0)
        close(s->err_fd);
    if (!reaped) {
        helper_run run = {.pid = s->pid};
        reap(&run, now_seconds() + 2.0);
    }
    s->pid = 0;
    s->request_fd = s->reply_fd = s->err_fd = -1;
}

sinew_result sinew_import_session_create(const sinew_import_desc *desc, sinew_import_session **out, sinew_error *error)
{
    if (!out)
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "sinew_import_session_create: no output");
    *out = NULL;
    sinew_import_desc d = desc ? *desc : (sinew_import_desc){0};
    d.path = NULL;
    char helper[PATH_MAX] = "";
    if (d.isolate) {
        sinew_result r = sinew_import_helper_path(&d, helper, sizeof helper, error);
        if (r)
            return r;
    }
    sinew_import_session *s = calloc(1, sizeof *s);
    if (!s)
        return sinew_fail(error, SINEW_ERROR_OUT_OF_MEMORY, "out of memory for an import session");
    s->desc = d;
    s->desc.helper = s->helper;
    snprintf(s->helper, sizeof s->helper, "%s", helper);
    s->memory_limit = memory_limit_of(&d);
    s->request_fd = s->reply_fd = s->err_fd = -1;
    *out = s;
    return SINEW_OK;
}

void sinew_import_session_free(sinew_import_session *session)
{
    if (!session)
        return;
    session_stop(session, false, false);
    free(session);
}

const sinew_import_desc *import_session_desc(const sinew_import_session *session)
{
    return &session->desc;
}

int sinew_import_session_helper_pid(const sinew_import_session *session)
{
    return session ? (int)session->pid : 0;
}

/* Sends the path; false when the helper is gone (it is then stopped). */
static bool session_request(sinew_import_session *s, const char *path)
{
    size_t n = strlen(path);
    uint32_t length = (uint32_t)n;
    unsigned char head[4];
    memcpy(head, &length, 4);
    const unsigned char *parts[2] = {head, (const unsigned char *)path};
    size_t sizes[2] = {4, n};
    for (int i = 0; i < 2; i++) {
        size_t done = 0;
        while (done < sizes[i]) {
            ssize_t w = send(s->request_fd, parts[i] + done, sizes[i] - done, MSG_NOSIGNAL);
            if (w < 0 && errno == EINTR)
                continue;
            if (w <= 0)
                return false;
            done += (size_t)w;
        }
    }
    return true;
}

static sinew_result session_try(sinew_import_session *s, const char *path, sinew_model **out, bool *stale,
                                sinew_error *error);

sinew_result import_in_session(sinew_import_session *s, const char *path, sinew_model **out, sinew_error *error)
{
    /* a helper killed from outside while it waited (with the thread that started it, or by a
     * user) is found dead only once the file is sent: that file is tried once more, in a fresh one */
    bool stale = false;
    sinew_result r = session_try(s, path, out, &stale, error);
    if (stale)
        r = session_try(s, path, out, &stale, error);
    return r;
}

static sinew_result session_try(sinew_import_session *s, const char *path, sinew_model **out, bool *stale,
                                sinew_error *error)
{
    sinew_import_desc desc = s->desc;
    bool waiting = s->pid != 0; /* started before this file */
    desc.path = path;
    if (strlen(path) >= PATH_MAX)
        return sinew_fail(error, SINEW_ERROR_IO, "%.200s...: the path is too long", path);
    /* a helper that died between files (killed, or with the thread that started it) is replaced */
    if (s->pid && waitpid(s->pid, NULL, WNOHANG) == s->pid)
        session_stop(s, false, true);
    for (int attempt = 0;; attempt++) {
        if (!s->pid) {
            helper_run start = {.path = path, .reply_fd = -1, .err_fd = -1, .memory_limit = s->memory_limit};
            sinew_result r = spawn_helper(&desc, s->helper, &start, &s->request_fd, error);
            if (r)
                return r;
            s->pid = start.pid;
            s->reply_fd = start.reply_fd;
            s->err_fd = start.err_fd;
        }
        if (session_request(s, path))
            break;
        session_stop(s, true, false);
        if (attempt > 0)
            return sinew_fail(error, SINEW_ERROR_IMPORTER, "%s: the import helper does not take requests", path);
    }
    helper_run run = {.path = path,
                      .pid = s->pid,
                      .reply_fd = s->reply_fd,
                      .err_fd = s->err_fd,
                      .memory_limit = s->memory_limit,
                      .progress = desc.progress,
                      .progress_user = desc.progress_user,
                      .serving = true};
    run.reply_limit = run.memory_limit;
    double timeout = import_timeout_of(&desc), deadline = timeout > 0.0 ? now_seconds() + timeout : 0.0;
    watch(&run, deadline);
    sinew_result result;
    if (run.header_seen && run.reply_size == run.reply_cap && !run.reply_too_big && !run.cancelled &&
        !run.killed_for_time && !run.killed_for_memory) {
        result = import_reply_decode(run.reply, run.reply_size, path, desc.allocator, out, error);
        /* memory a long-lived process keeps is memory the next file cannot have: past half the
         * limit, the next file gets a fresh helper */
        if (run.peak_rss > s->memory_limit / 2)
            session_stop(s, false, false);
    } else {
        /* watch() killed it and closed its pipes, or it died: the reason, then a fresh helper next time */
        s->reply_fd = s->err_fd = -1;
        int status = reap(&run, now_seconds() + 5.0);
        session_stop(s, false, true);
        *stale = !*stale && waiting && run.reply_size == 0 && !run.cancelled && !run.killed_for_time &&
                 !run.killed_for_memory && WIFSIGNALED(status) && WTERMSIG(status) == SIGKILL;
        result = helper_failed(&run, &desc, status, error);
    }
    result = starved_is_limit(&run, result, error);
    free(run.reply);
    return result;
}
