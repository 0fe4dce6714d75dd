/* Levels of detail for crowds: each mesh's triangles simplified (meshoptimizer) into shorter
 * index lists over the same vertices, so a character far away draws a quarter, a sixteenth
 * or less of its triangles and its skinning is unchanged; and the level a character gets
 * from its size on the screen.
 *
 * Each level (aiming at a quarter, a sixteenth, a sixty-fourth of the triangles) keeps the
 * mesh's topology (meshopt_simplify), its error bounded at 2% of the mesh's size: the demo
 * humanoid's 27,648 triangles become 6,911 (0.1% error), 1,727 (0.7%) and 1,027 (2%, where the
 * bound stops it). Where seams, borders or the bound stop a level before it takes away a
 * quarter of the level above, it is the level above again. The topology-free simplifier was
 * tried and left out: on the demo's segmented mannequin its shading went dark and noisy; and
 * with a 5% bound the last level collapsed the limbs to sticks. Each list is ordered for the vertex
 * cache. Meshes under LOD_MIN_TRIANGLES keep one level. A character gets the finest level
 * whose triangles cover two pixels or more each (its area on screen taken as 0.3 of its
 * bounding circle's, about what a standing figure fills).
 *
 * A fifth, far level is for characters too small for the fourth: the topology-free simplifier
 * (meshopt_simplifySloppy: vertices clustered on a grid, so the segments' seams that stop
 * the others do not stop it) aiming at a 256th of the triangles, its error bound at
 * LOD_FAR_ERROR; the demo's body becomes 150 triangles at 3.1% error. A character gets it only
 * where that error, measured, comes to under LOD_FAR_PIXELS on screen (a figure of about 32
 * pixels or less), where the shading faults that kept it from the nearer levels are lost. On
 * GPUs with few graphics units (NVIDIA's H100 and H200 draw about 0.6 G triangles a second)
 * the triangles of distant characters are what limits a crowd: 10,000 humanoids at 1920x1080
 * took 26 ms a frame on an H100 with four levels, 10 ms with five.
 */
#include <meshoptimizer.h>
#include <string.h>

#include "../core/internal.h"
#include "internal.h"

/* meshoptimizer is loaded when a crowd first needs its levels (it pulls in the C++ runtime,
 * which every other program start would pay for); without it every level is the full mesh. */
#ifndef SINEW_MESHOPTIMIZER_SONAME
#error "the build names meshoptimizer's soname (CMakeLists.txt: SINEW_MESHOPTIMIZER_SONAME)"
#endif
static union {
    struct {
        __typeof__(meshopt_simplify) *simplify;
        __typeof__(meshopt_optimizeVertexCache) *optimizeVertexCache;
        __typeof__(meshopt_optimizeVertexFetchRemap) *optimizeVertexFetchRemap;
        __typeof__(meshopt_remapIndexBuffer) *remapIndexBuffer;
        __typeof__(meshopt_remapVertexBuffer) *remapVertexBuffer;
        __typeof__(meshopt_simplifySloppy) *simplifySloppy;
    };
    void *symbol[6];
} meshopt;
static const char *const meshopt_names[6] = {
    "meshopt_simplify",         "meshopt_optimizeVertexCache", "meshopt_optimizeVertexFetchRemap",
    "meshopt_remapIndexBuffer", "meshopt_remapVertexBuffer",   "meshopt_simplifySloppy"};
static sinew_lazy_library meshoptimizer = {
    .soname = SINEW_MESHOPTIMIZER_SONAME, .names = meshopt_names, .symbols = meshopt.symbol, .count = 6};

#define LOD_MIN_TRIANGLES 1000u
#define LOD_ERROR 0.02f     /* of the mesh's size */
#define LOD_FAR_ERROR 0.10f /* the far level's bound */
#define LOD_FAR_PIXELS 1.0f /* the far level's error on screen at most */

static const float LOD_SHARE[RENDER_LOD_LEVELS] = {1.0f, 0.25f, 0.0625f, 0.015625f, 0.00390625f};

/* One simplified list into out (room for index_count), cache-ordered; its length, 0 when the
 * simplifier could not take away a quarter of what the level above has; *error: its error as
 * a fraction of the mesh's size. The far level is simplified without regard to topology. */
static size_t simplify(const sinew_mesh *mesh, const float *shape, int level, size_t above, uint32_t *out,
                       uint32_t *scratch, float *error)
{
    size_t target = (size_t)((float)mesh->index_count * LOD_SHARE[level]) / 3 * 3;
    size_t n = level == RENDER_LOD_LEVELS - 1
                   ? meshopt.simplifySloppy(scratch, mesh->indices, mesh->index_count, shape, mesh->vertex_count, 12,
                                            target, LOD_FAR_ERROR, error)
                   : meshopt.simplify(scratch, mesh->indices, mesh->index_count, shape, mesh->vertex_count, 12, target,
                                      LOD_ERROR, 0, error);
    if (n == 0 || n * 4 > above * 3)
        return 0;
    meshopt.optimizeVertexCache(out, scratch, n, mesh->vertex_count);
    return n;
}

bool render_lod_build(const sinew_mesh *mesh, const sinew_allocator *allocator, uint32_t **indices, render_lod *lod,
                      char *why, size_t why_size)
{
    *indices = NULL;
    for (int l = 0; l < RENDER_LOD_LEVELS; l++)
        lod->first[l] = 0, lod->count[l] = mesh->index_count;
    lod->far_error = 0.0f;
    if (mesh->index_count / 3 < LOD_MIN_TRIANGLES || !mesh->positions ||
        !sinew_lazy_load(&meshoptimizer, why, why ? why_size : 0))
        return true;
    /* the full list, then each level's, one after another */
    size_t room = (size_t)mesh->index_count * 2 + 1;
    uint32_t *all = allocator->alloc(room * sizeof *all, allocator->user);
    uint32_t *scratch = allocator->alloc(((size_t)mesh->index_count + 1) * sizeof *scratch, allocator->user);
    if (!all || !scratch) {
        if (all)
            allocator->free(all, allocator->user);
        if (scratch)
            allocator->free(scratch, allocator->user);
        return false;
    }
    memcpy(all, mesh->indices, (size_t)mesh->index_count * sizeof *all);
    /* A mesh with morph targets is simplified on its shape with every target whole (the levels
     * share its vertices, and the GPU morphs them): vertices that only a target bends out of a
     * flat or straight stretch are kept for it (a bulge, a smile). */
    float *shape = NULL;
    if (mesh->target_count && (shape = allocator->alloc((size_t)mesh->vertex_count * 12 + 16, allocator->user))) {
        memcpy(shape, mesh->positions, (size_t)mesh->vertex_count * 12);
        for (uint32_t t = 0; t < mesh->target_count; t++)
            for (uint32_t d = 0; d < mesh->targets[t].delta_count; d++)
                for (int k = 0; k < 3; k++)
                    shape[(size_t)mesh->targets[t].vertices[d] * 3 + (size_t)k] +=
                        mesh->targets[t].positions[d * 3 + k];
    }
    size_t used = mesh->index_count;
    for (int l = 1; l < RENDER_LOD_LEVELS; l++) {
        float error = 0.0f;
        size_t n = simplify(mesh, shape ? shape : mesh->positions, l, lod->count[l - 1], all + used, scratch, &error);
        if (n == 0 || used + n > room) { /* nothing came of it: the level above stands in */
            lod->first[l] = lod->first[l - 1], lod->count[l] = lod->count[l - 1];
            continue;
        }
        lod->first[l] = (uint32_t)used, lod->count[l] = (uint32_t)n;
        used += n;
        if (l == RENDER_LOD_LEVELS - 1)
            lod->far_error = error;
    }
    allocator->free(scratch, allocator->user);
    if (shape)
        allocator->free(shape, allocator->user);
    *indices = all;
    lod->total = (uint32_t)used;
    return true;
}

#define ALIGN16(x) (((x) + 15) & ~(size_t)15)

bool render_lod_compact(const sinew_mesh *mesh, const uint32_t *indices, uint32_t index_count,
                        const sinew_allocator *allocator, sinew_mesh *out, void **memory)
{
    *memory = NULL;
    size_t n = mesh->vertex_count, k = mesh->influence_count;
    uint32_t *remap = allocator->alloc(ALIGN16(n * sizeof *remap) + 16, allocator->user);
    if (!remap)
        return false;
    size_t used = meshopt.optimizeVertexFetchRemap(remap, indices, index_count, n);
    /* every array of the copy, 16-byte aligned, one after another */
    const size_t sizes[] = {(size_t)index_count * 4, 12,    12,    mesh->uvs ? 8 : 0,
                            mesh->tangents ? 16 : 0, k * 2, k * 4, mesh->colors ? 16 : 0};
    enum { ARRAYS = sizeof sizes / sizeof sizes[0] };
    size_t total = ALIGN16(sizes[0]);
    for (int a = 1; a < ARRAYS; a++)
        total += ALIGN16(used * sizes[a]);
    unsigned char *block = allocator->alloc(total + 16, allocator->user);
    if (!block) {
        allocator->free(remap, allocator->user);
        return false;
    }
    const void *from[ARRAYS] = {NULL,           mesh->positions, mesh->normals, mesh->uvs,
                                mesh->tangents, mesh->joints,    mesh->weights, mesh->colors};
    void *to[ARRAYS];
    unsigned char *at = block;
    to[0] = at;
    at += ALIGN16(sizes[0]);
    meshopt.remapIndexBuffer(to[0], indices, index_count, remap);
    for (int a = 1; a < ARRAYS; a++) {
        to[a] = sizes[a] && from[a] ? at : NULL;
        if (to[a])
            meshopt.remapVertexBuffer(to[a], from[a], n, sizes[a], remap);
        at += ALIGN16(used * sizes[a]);
    }
    allocator->free(remap, allocator->user);
    *out = *mesh;
    out->vertex_count = (uint32_t)used;
    out->index_count = index_count;
    out->indices = to[0];
    out->positions = to[1];
    out->normals = to[2];
    out->uvs = to[3];
    out->tangents = to[4];
    out->joints = to[5];
    out->weights = to[6];
    out->colors = to[7];
    *memory = block;
    return true;
}

int render_lod_level(float projected_radius, uint32_t triangles, float far_error)
{
    float area = 0.3f * 3.14159265f * projected_radius * projected_radius;
    for (int l = 0; l < RENDER_LOD_LEVELS - 1; l++)
        if ((float)triangles * LOD_SHARE[l] * 2.0f <= area)
            return l;
    /* a mesh's size is at most the character's bounding diameter */
    return far_error * 2.0f * projected_radius <= LOD_FAR_PIXELS ? RENDER_LOD_LEVELS - 1 : RENDER_LOD_LEVELS - 2;
}
