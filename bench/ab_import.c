/* Two builds of libsinew in one process, their imports alternated: A, B, B, A, A, B, ... on each
 * file's bytes (read once), so that a machine that swings between a fast and a slow mode (this
 * one's do within a second) slows both alike. Each library is loaded in a namespace of its own
 * (dlmopen), with its own globals. Prints each build's best import in milliseconds, the ratio of
 * the bests, and the median of each pair's own ratio. Two copies of one build give 0.98-1.02.
 *
 *     cc -O2 -Iinclude bench/ab_import.c -o /tmp/ab_import -ldl
 *     cp build/libsinew.so.0.3 /tmp/before.so     (then change and rebuild)
 *     /tmp/ab_import /tmp/before.so build/libsinew.so.0.3 RUNS FILE...
 */
#define _GNU_SOURCE
#include <dlfcn.h>
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#include "sinew/import.h"

typedef sinew_result (*import_fn)(const void *, size_t, const char *, const sinew_import_desc *, sinew_model **,
                                  sinew_error *);
typedef void (*free_fn)(sinew_model *);

static double now_ms(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec * 1e3 + (double)t.tv_nsec * 1e-6;
}

static int by_value(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

static void *read_all(const char *path, size_t *size)
{
    FILE *f = fopen(path, "rb");
    long n = f && fseek(f, 0, SEEK_END) == 0 ? ftell(f) : -1;
    void *bytes = n > 0 && fseek(f, 0, SEEK_SET) == 0 ? malloc((size_t)n) : NULL;
    if (bytes && fread(bytes, 1, (size_t)n, f) != (size_t)n) {
        free(bytes);
        bytes = NULL;
    }
    if (f)
        fclose(f);
    *size = bytes ? (size_t)n : 0;
    return bytes;
}

int main(int argc, char **argv)
{
    if (argc < 5) {
        fprintf(stderr, "usage: ab_import A.so B.so RUNS FILE...\n");
        return 2;
    }
    import_fn import[2];
    free_fn release[2];
    for (int v = 0; v < 2; v++) {
        void *h = dlmopen(LM_ID_NEWLM, argv[1 + v], RTLD_NOW | RTLD_LOCAL);
        if (!h) {
            fprintf(stderr, "ab_import: %s\n", dlerror());
            return 1;
        }
        import[v] = (import_fn)dlsym(h, "sinew_import_memory");
        release[v] = (free_fn)dlsym(h, "sinew_model_free");
        if (!import[v] || !release[v]) {
            fprintf(stderr, "ab_import: %s is not libsinew\n", argv[1 + v]);
            return 1;
        }
    }
    int runs = atoi(argv[3]);
    if (runs < 1)
        runs = 1;
    double *t[2] = {malloc(sizeof(double) * (size_t)runs), malloc(sizeof(double) * (size_t)runs)};
    double *pair = malloc(sizeof(double) * (size_t)runs);
    for (int fi = 4; fi < argc; fi++) {
        size_t size;
        void *bytes = read_all(argv[fi], &size);
        if (!bytes) {
            fprintf(stderr, "ab_import: cannot read %s\n", argv[fi]);
            return 1;
        }
        for (int i = -2; i < runs; i++) /* two rounds to warm up */
            for (int k = 0; k < 2; k++) {
                int v = (i & 1) ? 1 - k : k;
                sinew_import_desc desc = {.path = argv[fi]};
                sinew_model *model = NULL;
                sinew_error error = {0};
                double start = now_ms();
                if (import[v](bytes, size, NULL, &desc, &model, &error) != SINEW_OK) {
                    fprintf(stderr, "ab_import: %s: %s\n", v ? "B" : "A", error.message);
                    return 1;
                }
                release[v](model);
                if (i >= 0)
                    t[v][i] = now_ms() - start;
            }
        for (int i = 0; i < runs; i++)
            pair[i] = t[1][i] / t[0][i];
        qsort(t[0], (size_t)runs, sizeof(double), by_value);
        qsort(t[1], (size_t)runs, sizeof(double), by_value);
        qsort(pair, (size_t)runs, sizeof(double), by_value);
        printf("%-48s A %.4f ms  B %.4f ms (best)  B/A %.3f  paired median %.3f\n", argv[fi], t[0][0], t[1][0],
               t[1][0] / t[0][0], pair[runs / 2]);
        free(bytes);
    }
    free(t[0]);
    free(t[1]);
    free(pair);
    return 0;
}
