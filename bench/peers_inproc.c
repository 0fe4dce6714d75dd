/* Imports without their process, each timed the same way: sinew (sinew_import_memory, the build's
 * libsinew), ufbx 0.23 (load from memory, and bake every stack) or cgltf 1.15 (parse from memory,
 * load buffers, validate; cgltf-decode also unpacks every accessor into floats, as sinew decodes
 * every accessor) on a file's bytes read once, RUNS times in one process after one that
 * warms up; prints the best run in milliseconds. bench/peers.py builds it against the build and
 * ../shared/peers (never linked into sinew) for its in-library column. It used to take sinew's
 * time through the Python binding (a third of it building the Model's numpy views) and a peer's
 * as its whole process less an empty one's (a difference of two noisy numbers near each other for
 * a small file, and page faults a warm process does not take).
 *
 *     peers_inproc sinew|ufbx|cgltf|cgltf-decode FILE RUNS */
#define _POSIX_C_SOURCE 200809L
#define CGLTF_IMPLEMENTATION
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "cgltf.h"
#include "sinew/import.h"
#include "ufbx.h"

static double now_ms(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec * 1e3 + (double)t.tv_nsec * 1e-6;
}

static int load_ufbx(const void *bytes, size_t size)
{
    ufbx_error error;
    ufbx_scene *scene = ufbx_load_memory(bytes, size, NULL, &error);
    if (!scene)
        return 1;
    for (size_t i = 0; i < scene->anim_stacks.count; i++) {
        ufbx_baked_anim *baked = ufbx_bake_anim(scene, scene->anim_stacks.data[i]->anim, NULL, &error);
        if (!baked) {
            ufbx_free_scene(scene);
            return 1;
        }
        ufbx_free_baked_anim(baked);
    }
    ufbx_free_scene(scene);
    return 0;
}

/* cgltf's parse, buffers and validation; with `decode`, every accessor unpacked into floats too
 * (cgltf_accessor_unpack_floats: strides, normalised integers, sparse), nearer what sinew does. */
static int load_cgltf(const void *bytes, size_t size, const char *path, int decode)
{
    cgltf_options options = {0};
    cgltf_data *data = NULL;
    int bad = cgltf_parse(&options, bytes, size, &data) != cgltf_result_success ||
              cgltf_load_buffers(&options, data, path) != cgltf_result_success ||
              cgltf_validate(data) != cgltf_result_success;
    for (cgltf_size i = 0; !bad && decode && i < data->accessors_count; i++) {
        cgltf_size n = cgltf_accessor_unpack_floats(&data->accessors[i], NULL, 0);
        float *out = malloc((n ? n : 1) * sizeof *out);
        bad = !out || cgltf_accessor_unpack_floats(&data->accessors[i], out, n) != n;
        free(out);
    }
    cgltf_free(data);
    return bad;
}

static int load_sinew(const void *bytes, size_t size, const char *path)
{
    sinew_import_desc desc = {.path = path};
    sinew_model *model = NULL;
    sinew_error error = {0};
    if (sinew_import_memory(bytes, size, NULL, &desc, &model, &error) != SINEW_OK)
        return 1;
    sinew_model_free(model);
    return 0;
}

int main(int argc, char **argv)
{
    const char *reader = argc == 4 ? argv[1] : "";
    if (strcmp(reader, "sinew") != 0 && strcmp(reader, "ufbx") != 0 && strcmp(reader, "cgltf") != 0 &&
        strcmp(reader, "cgltf-decode") != 0) {
        fprintf(stderr, "usage: peers_inproc sinew|ufbx|cgltf|cgltf-decode FILE RUNS\n");
        return 2;
    }
    FILE *f = fopen(argv[2], "rb");
    if (!f || fseek(f, 0, SEEK_END) != 0) {
        fprintf(stderr, "peers_inproc: cannot read %s\n", argv[2]);
        return 1;
    }
    long n = ftell(f);
    rewind(f);
    unsigned char *bytes = n >= 0 ? malloc((size_t)n + 1) : NULL;
    if (!bytes || fread(bytes, 1, (size_t)n, f) != (size_t)n) {
        fprintf(stderr, "peers_inproc: cannot read %s\n", argv[2]);
        return 1;
    }
    fclose(f);
    int runs = atoi(argv[3]);
    double best = -1;
    for (int r = 0; r <= runs; r++) { /* the first run warms the caches and the heap, and is left out */
        double t = now_ms();
        int bad = reader[0] == 's'   ? load_sinew(bytes, (size_t)n, argv[2])
                  : reader[0] == 'u' ? load_ufbx(bytes, (size_t)n)
                                     : load_cgltf(bytes, (size_t)n, argv[2], strcmp(reader, "cgltf-decode") == 0);
        t = now_ms() - t;
        if (bad) {
            fprintf(stderr, "peers_inproc: %s cannot load %s\n", reader, argv[2]);
            return 1;
        }
        if (r > 0 && (best < 0 || t < best))
            best = t;
    }
    printf("%.4f\n", best);
    free(bytes);
    return 0;
}
