/* The import helper (sinew-import): a file that makes the reader hang or eat memory is
 * stopped at the desc's deadline or memory limit and reported as such; a helper killed from
 * outside, missing, or replying nonsense is an error that says so; nothing is left running. */
#define _GNU_SOURCE
#include <dirent.h>
#include <errno.h>
#include <pthread.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "helpers.h"

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

/* duck.dae with byte 245632 set to 0xC0: Assimp's COLLADA reader loops, allocating without
 * end (2.6 GB in 40 s); sinew's own reader refuses it at once. */
static bool hanging_file(char *path, size_t size)
{
    char source[1024];
    if (!testdata_path("assimp/Collada/duck.dae", source, sizeof source))
        return false;
    size_t n = 0;
    unsigned char *bytes = read_file(source, &n);
    assert_true(n > 245632);
    bytes[245632] = 0xC0;
    write_file(tmp_path("duck-hangs-assimp.dae", path, size), bytes, n);
    free(bytes);
    return true;
}

/* No child of this process is left, running or unreaped. */
static void assert_no_children(void)
{
    errno = 0;
    assert_int_equal(waitpid(-1, NULL, WNOHANG), -1);
    assert_int_equal(errno, ECHILD);
}

static sinew_result import_with(const sinew_import_desc *desc, sinew_error *error)
{
    sinew_model *m = (sinew_model *)1;
    sinew_result r = sinew_import(desc, &m, error);
    assert_true(r == SINEW_OK || m == NULL);
    sinew_model_free(r == SINEW_OK ? m : NULL);
    return r;
}

static void expect(sinew_result got, sinew_result want, const sinew_error *error, const char *path, const char *needle)
{
    if (got != want || !strstr(error->message, path) || !strstr(error->message, needle))
        fail_msg("expected %s naming %s and saying \"%s\"; got %s: %s", sinew_result_string(want), path, needle,
                 sinew_result_string(got), error->message);
}

static void test_hang_stops_at_the_deadline(void **state)
{
    (void)state;
    char path[1024];
    if (!hanging_file(path, sizeof path))
        skip();
    sinew_error error = {0};
    /* sinew's reader refuses it straight away */
    expect(import_with(&(sinew_import_desc){.path = path}, &error), SINEW_ERROR_FORMAT, &error, path, "UTF-8");
    double start = now();
    /* (with room enough that the deadline, not the default memory limit of a small file, stops it) */
    sinew_result r = import_with(
        &(sinew_import_desc){.path = path, .assimp = true, .timeout = 1.5, .memory_limit = (uint64_t)4 << 30}, &error);
    double took = now() - start;
    expect(r, SINEW_ERROR_LIMIT_TIME, &error, path, "1.5 s deadline");
    if (took > 10.0)
        fail_msg("stopped after %.1f s (deadline 1.5 s)", took);
    assert_no_children();
}

/* sinew's own readers, in process, keep the deadline too: they look at the clock as they go (and
 * every allocation past it fails), so the import stops with the same error and no helper runs. */
static void test_deadline_in_process(void **state)
{
    (void)state;
    static const char *files[] = {"ozz/pab/walk.fbx", "raylib/robot.glb", "blender/robot_walk.dae"};
    for (size_t i = 0; i < sizeof files / sizeof *files; i++) {
        char path[1024];
        if (!testdata_path(files[i], path, sizeof path))
            skip();
        sinew_error error = {0};
        double start = now();
        sinew_result r = import_with(&(sinew_import_desc){.path = path, .timeout = 1e-4}, &error);
        double took = now() - start;
        expect(r, SINEW_ERROR_LIMIT_TIME, &error, path, "0.0001 s deadline");
        print_message("%s: stopped after %.1f ms\n", files[i], took * 1e3);
        assert_no_children();
        assert_int_equal(import_with(&(sinew_import_desc){.path = path}, &error), SINEW_OK);
    }
}

typedef struct progress_log {
    double cancel_at; /* seconds from the start */
    double start;
    int calls, unknown;
    float last;
} progress_log;

static bool note_progress(float fraction, void *user)
{
    progress_log *log = user;
    log->calls++;
    log->unknown += fraction < 0.0f;
    if (fraction >= 0.0f)
        assert_true(fraction <= 1.0f && fraction >= log->last);
    log->last = fraction >= 0.0f ? fraction : log->last;
    return now() - log->start < log->cancel_at;
}

static bool stop_on_second_call(float fraction, void *user)
{
    (void)fraction;
    return ++*(int *)user < 2;
}

/* The progress callback hears from the helper every 50 ms or so; returning false stops it at
 * once with SINEW_ERROR_CANCELLED (the viewer's Cancel button); a file that reads in time
 * reports its reply's arrival up to 1. */
static void test_progress_and_cancel(void **state)
{
    (void)state;
    char path[1024];
    if (!hanging_file(path, sizeof path))
        skip();
    sinew_error error = {0};
    progress_log log = {.cancel_at = 0.4, .start = now()};
    /* (with room enough that the cancel, not the default memory limit of a small file, stops it:
     * Assimp allocates 65 MB/s on one machine here and 900 on another) */
    sinew_import_desc desc = {.path = path,
                              .assimp = true,
                              .memory_limit = (uint64_t)4 << 30,
                              .progress = note_progress,
                              .progress_user = &log};
    sinew_result r = import_with(&desc, &error);
    double took = now() - log.start;
    expect(r, SINEW_ERROR_CANCELLED, &error, path, "cancelled");
    if (took > 3.0)
        fail_msg("stopped %.1f s after the start (cancelled at 0.4 s)", took);
    assert_true(log.calls >= 3 && log.unknown == log.calls);
    assert_no_children();

    char good[1024];
    assert_non_null(testdata_path("assimp/Collada/duck.dae", good, sizeof good));
    log = (progress_log){.cancel_at = 1e9, .start = now()};
    desc.path = good;
    assert_int_equal(import_with(&desc, &error), SINEW_OK);
    assert_true(log.calls >= 1);
    /* sinew's own reader, in process: asked once before reading, and it may stop there */
    log = (progress_log){.cancel_at = -1.0, .start = now()};
    desc.assimp = false;
    expect(import_with(&desc, &error), SINEW_ERROR_CANCELLED, &error, good, "cancelled");
    assert_int_equal(log.calls, 1);
    assert_no_children();
    /* and asked again while it reads (the first time soon after it starts, then every 50 ms):
     * stopping then stops it too */
    char big[1024];
    if (testdata_path("ozz/pab/walk.fbx", big, sizeof big)) {
        int calls = 0;
        desc = (sinew_import_desc){.path = big, .progress = stop_on_second_call, .progress_user = &calls};
        expect(import_with(&desc, &error), SINEW_ERROR_CANCELLED, &error, big, "cancelled");
        assert_int_equal(calls, 2);
        calls = -1000; /* never stops: the import ends as usual */
        assert_int_equal(import_with(&desc, &error), SINEW_OK);
        assert_true(calls > -1000 + 1);
    }
}

static void test_memory_limit(void **state)
{
    (void)state;
    char path[1024];
    if (!hanging_file(path, sizeof path))
        skip();
    sinew_error error = {0};
    sinew_import_desc desc = {.path = path, .assimp = true, .timeout = 60, .memory_limit = (uint64_t)256 << 20};
    double start = now();
    sinew_result r = import_with(&desc, &error);
    expect(r, SINEW_ERROR_LIMIT_MEMORY, &error, path, "256 MiB memory limit");
    if (now() - start > 30.0)
        fail_msg("stopped after %.1f s", now() - start);
    assert_no_children();
    /* the default follows the file's size (256 MiB and 64 times it), not half the machine's memory:
     * the same file is stopped as soon, and the message says which limit it was */
    desc.memory_limit = 0;
    start = now();
    r = import_with(&desc, &error);
    expect(r, SINEW_ERROR_LIMIT_MEMORY, &error, path, "the default for a file of its size");
    printf("default limit: stopped after %.1f s: %s\n", now() - start, error.message);
    if (now() - start > 30.0)
        fail_msg("stopped after %.1f s", now() - start);
    assert_no_children();
}

/* Kills every child of this process after a moment, as a user or the OOM killer would. */
static void *kill_children(void *arg)
{
    (void)arg;
    nanosleep(&(struct timespec){.tv_nsec = 500 * 1000 * 1000}, NULL);
    DIR *proc = opendir("/proc");
    struct dirent *e;
    while (proc && (e = readdir(proc))) {
        char name[300], text[512];
        snprintf(name, sizeof name, "/proc/%s/stat", e->d_name);
        FILE *f = fopen(name, "r");
        if (!f)
            continue;
        size_t n = fread(text, 1, sizeof text - 1, f);
        fclose(f);
        text[n] = '\0';
        const char *close_paren = strrchr(text, ')');
        int pid = atoi(e->d_name), ppid = 0;
        char st;
        if (close_paren && sscanf(close_paren + 1, " %c %d", &st, &ppid) == 2 && ppid == getpid())
            kill(pid, SIGKILL);
    }
    if (proc)
        closedir(proc);
    return NULL;
}

static void test_killed_from_outside(void **state)
{
    (void)state;
    char path[1024];
    if (!hanging_file(path, sizeof path))
        skip();
    pthread_t killer;
    pthread_create(&killer, NULL, kill_children, NULL);
    sinew_error error = {0};
    sinew_result r = import_with(
        &(sinew_import_desc){.path = path, .assimp = true, .timeout = 30, .memory_limit = (uint64_t)4 << 30}, &error);
    pthread_join(killer, NULL);
    expect(r, SINEW_ERROR_IMPORTER, &error, path, "killed from outside (signal 9");
    assert_no_children();
}

static void test_missing_helper(void **state)
{
    (void)state;
    char path[1024], found[4096];
    fixture_path("two_bone.dae", path, sizeof path);
    sinew_error error = {0};
    sinew_import_desc desc = {.path = path, .isolate = true, .helper = "/nonexistent/sinew-import"};
    expect(import_with(&desc, &error), SINEW_ERROR_IO, &error, "/nonexistent/sinew-import", "not an executable");
    /* the tests name the build's helper in $SINEW_IMPORT_HELPER */
    assert_int_equal(sinew_import_helper_path(NULL, found, sizeof found, &error), SINEW_OK);
    assert_string_equal(found, getenv("SINEW_IMPORT_HELPER"));
    /* without it, a program in a folder with no helper beside it finds none and says where it looked */
    char saved[4096];
    snprintf(saved, sizeof saved, "%s", getenv("SINEW_IMPORT_HELPER"));
    unsetenv("SINEW_IMPORT_HELPER");
    sinew_result r = sinew_import_helper_path(NULL, found, sizeof found, &error);
    setenv("SINEW_IMPORT_HELPER", saved, 1);
    if (r == SINEW_OK)
        fail_msg("found a helper at %s without being told", found);
    assert_non_null(strstr(error.message, "looked for"));
    /* sinew's own formats need no helper unless isolated */
    assert_int_equal(import_with(&(sinew_import_desc){.path = path, .helper = "/nonexistent"}, &error), SINEW_OK);
}

/* A stand-in helper: a shell script doing what `body` says. */
static const char *fake_helper(const char *name, const char *body, char *path, size_t size)
{
    tmp_path(name, path, size);
    char text[1024];
    int n = snprintf(text, sizeof text, "#!/bin/sh\n%s\n", body);
    write_file(path, text, (size_t)n);
    chmod(path, 0755);
    return path;
}

static void test_bad_replies(void **state)
{
    (void)state;
    static const struct {
        const char *name, *body;
        sinew_result kind;
        const char *says;
    } cases[] = {
        {"helper-silent.sh", "exit 0", SINEW_ERROR_IMPORTER, "cut short"},
        {"helper-fails.sh", "echo 'reader: boom' >&2; exit 3", SINEW_ERROR_IMPORTER,
         "exit status 3); its last words: reader: boom"},
        {"helper-crashes.sh", "echo 'ERROR: AddressSanitizer: heap-buffer-overflow' >&2; kill -SEGV $$",
         SINEW_ERROR_IMPORTER,
         "crashed while reading this file (signal 11, Segmentation fault); the file is probably malformed; its last "
         "words: ERROR: AddressSanitizer"},
        /* a header that claims 2^63 bytes: refused before anything is allocated */
        {"helper-huge.sh", "printf 'PERS\\000\\000\\000\\000\\377\\377\\377\\377\\377\\377\\377\\177'; sleep 5",
         SINEW_ERROR_IMPORTER, "larger than it announced or than its"},
        {"helper-more.sh", "printf 'PERS\\000\\000\\000\\000\\002\\000\\000\\000\\000\\000\\000\\000abc'",
         SINEW_ERROR_IMPORTER, "larger than it announced"},
        {"helper-kind.sh", "printf 'PERS\\143\\000\\000\\000\\002\\000\\000\\000\\000\\000\\000\\000x\\000'",
         SINEW_ERROR_IMPORTER, "error reply is malformed"},
        {"helper-error.sh", "printf 'PERS\\005\\000\\000\\000\\004\\000\\000\\000\\000\\000\\000\\000bad\\000'",
         SINEW_ERROR_DATA, "bad"},
        {"helper-garbage.sh", "printf 'PERS\\000\\000\\000\\000\\004\\000\\000\\000\\000\\000\\000\\000abcd'",
         SINEW_ERROR_FORMAT, ""},
    };
    char model[1024], helper[1024];
    fixture_path("two_bone.dae", model, sizeof model);
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        sinew_error error = {0};
        sinew_import_desc desc = {.path = model,
                                  .isolate = true,
                                  .helper = fake_helper(cases[i].name, cases[i].body, helper, sizeof helper),
                                  .timeout = 20};
        sinew_result r = import_with(&desc, &error);
        if (r != cases[i].kind || !strstr(error.message, cases[i].says))
            fail_msg("%s: expected %s saying \"%s\"; got %s: %s", cases[i].name, sinew_result_string(cases[i].kind),
                     cases[i].says, sinew_result_string(r), error.message);
        if (cases[i].kind != SINEW_ERROR_DATA && !strstr(error.message, model))
            fail_msg("%s: the message does not name the model: %s", cases[i].name, error.message);
    }
    assert_no_children();
}

/* ---- sessions: one helper for many files -------------------------------------------------------- */

static void assert_same_model(const sinew_model *a, const sinew_model *b)
{
    const void *x, *y;
    size_t nx, ny;
    sinew_model_blob(a, &x, &nx);
    sinew_model_blob(b, &y, &ny);
    assert_int_equal(nx, ny);
    assert_memory_equal(x, y, nx);
}

static void test_session_many_files_one_helper(void **state)
{
    (void)state;
    const char *names[] = {"two_bone.dae", "two_bone_7500.fbx",       "two_bone_cubic.glb",
                           "two_bone.iqm", "two_bone_6100_ascii.fbx", "no_ticks.x",
                           "two_bone.dae"};
    sinew_import_session *session = NULL;
    sinew_error error = {0};
    assert_int_equal(
        sinew_import_session_create(&(sinew_import_desc){.isolate = true, .timeout = 30}, &session, &error), SINEW_OK);
    assert_int_equal(sinew_import_session_helper_pid(session), 0);
    int pid = 0;
    for (size_t i = 0; i < sizeof names / sizeof names[0]; i++) {
        char path[1024];
        fixture_path(names[i], path, sizeof path);
        sinew_model *a = NULL, *b = NULL;
        assert_int_equal(sinew_import(&(sinew_import_desc){.path = path}, &a, &error), SINEW_OK);
        if (sinew_import_session_load(session, path, &b, &error) != SINEW_OK)
            fail_msg("%s: %s", names[i], error.message);
        assert_same_model(a, b);
        sinew_model_free(a);
        sinew_model_free(b);
        /* one helper for sinew's own formats; Assimp's (.x) go to a helper of their own */
        if (!pid)
            pid = sinew_import_session_helper_pid(session);
        assert_true(pid > 0);
        assert_int_equal(sinew_import_session_helper_pid(session), pid);
    }
    sinew_model *m = (sinew_model *)1;
    assert_int_equal(sinew_import_session_load(session, "/nonexistent/x.fbx", &m, &error), SINEW_ERROR_IO);
    assert_null(m);
    sinew_import_session_free(session);
    assert_no_children();
}

static void test_session_deadline_and_kill(void **state)
{
    (void)state;
    char a[1024], b[1024];
    fixture_path("two_bone.dae", a, sizeof a);
    fixture_path("two_bone_7500.fbx", b, sizeof b);
    sinew_import_session *session = NULL;
    sinew_error error = {0};
    assert_int_equal(
        sinew_import_session_create(&(sinew_import_desc){.isolate = true, .timeout = 1.0}, &session, &error), SINEW_OK);
    sinew_model *m = NULL;
    assert_int_equal(sinew_import_session_load(session, a, &m, &error), SINEW_OK);
    sinew_model_free(m);
    /* a helper that stops answering: the file's deadline, then a fresh helper */
    int pid = sinew_import_session_helper_pid(session);
    kill(pid, SIGSTOP);
    double t = now();
    expect(sinew_import_session_load(session, b, &m, &error), SINEW_ERROR_LIMIT_TIME, &error, b, "deadline");
    assert_true(now() - t < 10.0);
    assert_int_equal(sinew_import_session_helper_pid(session), 0);
    assert_int_equal(sinew_import_session_load(session, b, &m, &error), SINEW_OK);
    sinew_model_free(m);
    /* killed while it waited (as when the thread that started it ends): the next file still loads */
    int second = sinew_import_session_helper_pid(session);
    assert_true(second > 0 && second != pid);
    kill(second, SIGKILL);
    assert_int_equal(sinew_import_session_load(session, a, &m, &error), SINEW_OK);
    sinew_model_free(m);
    assert_true(sinew_import_session_helper_pid(session) != second);
    sinew_import_session_free(session);
    assert_no_children();
    assert_int_equal(sinew_import_session_load(NULL, a, &m, &error), SINEW_ERROR_INVALID_ARGUMENT);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_hang_stops_at_the_deadline),
        cmocka_unit_test(test_deadline_in_process),
        cmocka_unit_test(test_progress_and_cancel),
        cmocka_unit_test(test_memory_limit),
        cmocka_unit_test(test_killed_from_outside),
        cmocka_unit_test(test_missing_helper),
        cmocka_unit_test(test_bad_replies),
        cmocka_unit_test(test_session_many_files_one_helper),
        cmocka_unit_test(test_session_deadline_and_kill),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
