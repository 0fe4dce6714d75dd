/* The allocation-failure sweep, as ufbx's test runner does it: every shared model sinew reads
 * itself (FBX, glTF, COLLADA, IQM, BVH under ../shared/testdata, with the fixtures), imported in process
 * once to count its allocations, then again failing allocation k for a sample of k (every k for a
 * small count; else the first few, the last few and evenly spaced ones between, within a budget
 * of 40,000 failing imports shared by the files, 12,000 under AddressSanitizer;
 * SINEW_SWEEP_IMPORTS sets another). Each failed import must be a clean
 * SINEW_ERROR_OUT_OF_MEMORY naming the file (never a crash, another error, or a model); under
 * AddressSanitizer nothing leaks. Also: the import's own byte limit stops a file in process with
 * SINEW_ERROR_LIMIT_MEMORY saying which limit. */
#include <dirent.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>

#include "helpers.h"
#include "import/internal.h"

#define MAX_FILES 512

static int compare(const void *a, const void *b)
{
    return strcmp(*(char *const *)a, *(char *const *)b);
}

static bool native(const char *name)
{
    static const char *const ext[] = {".fbx", ".glb", ".gltf", ".dae", ".iqm", ".bvh"};
    size_t n = strlen(name);
    for (size_t i = 0; i < sizeof ext / sizeof *ext; i++) {
        size_t e = strlen(ext[i]);
        if (n > e && strcasecmp(name + n - e, ext[i]) == 0)
            return true;
    }
    return false;
}

static void collect(const char *dir, char **files, int *count)
{
    DIR *d = opendir(dir);
    if (!d)
        return;
    for (struct dirent *e; (e = readdir(d)) && *count < MAX_FILES;) {
        if (e->d_name[0] == '.' || strcmp(e->d_name, "reference") == 0)
            continue;
        char path[2048];
        snprintf(path, sizeof path, "%s/%s", dir, e->d_name);
        struct stat st;
        if (stat(path, &st) != 0)
            continue;
        if (S_ISDIR(st.st_mode))
            collect(path, files, count);
        else if (native(e->d_name) && st.st_size < (4 << 20))
            files[(*count)++] = strdup(path);
    }
    closedir(d);
}

static double now(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

/* One import in process with allocation `k` failed (0: none): the result, checked. */
static sinew_result import_failing(const char *path, uint64_t k, uint64_t *count)
{
    sinew_model *m = NULL;
    sinew_error error = {0};
    import_alloc_sweep(k);
    sinew_result r = sinew_import(&(sinew_import_desc){.path = path}, &m, &error);
    import_alloc_sweep(0);
    if (count)
        *count = import_alloc_last_count();
    if (k == 0) {
        sinew_model_free(m);
        return r;
    }
    if (r == SINEW_OK)
        fail_msg("%s: allocation %llu failed and the import still succeeded", path, (unsigned long long)k);
    if (r != SINEW_ERROR_OUT_OF_MEMORY || !strstr(error.message, path))
        fail_msg("%s: allocation %llu failed: %s \"%s\" (expected out of memory, naming the file)", path,
                 (unsigned long long)k, sinew_result_string(r), error.message);
    sinew_model_free(m);
    return r;
}

static void test_every_allocation_may_fail(void **state)
{
    (void)state;
    char *files[MAX_FILES];
    int count = 0;
    char dir[1024];
    if (testdata_path("", dir, sizeof dir))
        collect(dir, files, &count);
    fixture_path("", dir, sizeof dir);
    collect(dir, files, &count);
    qsort(files, (size_t)count, sizeof *files, compare);
    const char *budget_env = getenv("SINEW_SWEEP_IMPORTS");
#if defined(__SANITIZE_ADDRESS__)
    long budget = budget_env ? atol(budget_env) : 12000; /* about 50 s under AddressSanitizer */
#else
    long budget = budget_env ? atol(budget_env) : 40000; /* about 20 s */
#endif
    uint64_t counts[MAX_FILES] = {0};
    int readable = 0;
    double start = now();
    for (int i = 0; i < count; i++) /* the successful imports: how many allocations each makes */
        if (import_failing(files[i], 0, &counts[i]) == SINEW_OK)
            readable++;
        else
            counts[i] = 0;
    /* the budget shared among the files, each its first and last allocations and a spread between */
    long per_file = readable ? budget / readable : 0, imports = 0, every_k = 0;
    uint64_t most = 0;
    for (int i = 0; i < count; i++) {
        uint64_t n = counts[i];
        if (!n)
            continue;
        most = n > most ? n : most;
        if ((long)n <= per_file) {
            for (uint64_t k = 1; k <= n; k++, imports++)
                import_failing(files[i], k, NULL);
            every_k++;
            continue;
        }
        /* the first allocations (headers, tables), the last (the builder), and an even spread
         * between, shifted by a fraction of a step that differs from file to file */
        uint64_t first = (uint64_t)(per_file / 4 < 24 ? per_file / 4 : 24),
                 last = (uint64_t)(per_file / 8 < 8 ? per_file / 8 : 8);
        long spread = per_file - (long)(first + last);
        double step = (double)(n - first - last) / (double)(spread > 0 ? spread : 1), shift = 0.618 * (i % 13) / 13.0;
        for (uint64_t k = 1; k <= first; k++, imports++)
            import_failing(files[i], k, NULL);
        for (long s = 0; s < spread; s++, imports++)
            import_failing(files[i], first + 1 + (uint64_t)(step * ((double)s + shift)), NULL);
        for (uint64_t k = n - last + 1; k <= n; k++, imports++)
            import_failing(files[i], k, NULL);
    }
    print_message("allocation sweep: %d files (%d read), %ld failing imports in %.1f s; every allocation failed "
                  "in turn for %ld files, sampled for the rest (at most %llu allocations in one import)\n",
                  count, readable, imports, now() - start, every_k, (unsigned long long)most);
    assert_true(readable > 20);
    for (int i = 0; i < count; i++)
        free(files[i]);
}

/* In process, the import's own byte limit: a 1 MiB limit stops a 1.6 MB glTF. */
static void test_own_byte_limit(void **state)
{
    (void)state;
    char path[1024];
    if (!testdata_path("raylib/robot.glb", path, sizeof path))
        fail_msg("missing raylib/robot.glb");
    sinew_model *m = NULL;
    sinew_error error = {0};
    sinew_import_desc desc = {.path = path, .memory_limit = 1 << 20};
    assert_int_equal(sinew_import(&desc, &m, &error), SINEW_ERROR_LIMIT_MEMORY);
    print_message("%s\n", error.message);
    assert_non_null(strstr(error.message, "1 MiB memory limit"));
    assert_string_equal(error.file, path);
    assert_null(m);
    desc.memory_limit = 0; /* the default for its size is room enough */
    assert_int_equal(sinew_import(&desc, &m, &error), SINEW_OK);
    sinew_model_free(m);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_own_byte_limit),
        cmocka_unit_test(test_every_allocation_may_fail),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
