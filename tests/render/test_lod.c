/* Crowds' levels of detail (src/render/lod.c), without OpenGL: the demo humanoid's body
 * simplified to about a quarter, a sixteenth and as far towards a sixty-fourth as a 2% error
 * allows, every level's triangles made of the body's own vertices; a level on its own
 * vertices draws the same triangles; small meshes keep one level; a character's level
 * follows its size on screen (two pixels a triangle). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "helpers.h"
#include "render/internal.h"

static void *lod_alloc(size_t size, void *user)
{
    (void)user;
    return aligned_alloc(16, (size + 15) & ~(size_t)15);
}

static void lod_free(void *ptr, void *user)
{
    (void)user;
    free(ptr);
}

static const sinew_allocator ALLOCATOR = {lod_alloc, lod_free, NULL};

static void test_levels_of_the_demo(void **state)
{
    (void)state;
    sinew_model *m = demo_humanoid();
    const sinew_mesh *body = NULL, *staff = NULL;
    for (uint32_t i = 0; i < m->mesh_count; i++)
        if (m->meshes[i].index_count / 3 >= 1000)
            body = &m->meshes[i];
        else
            staff = &m->meshes[i];
    assert_non_null(body);
    assert_non_null(staff);
    uint32_t *indices = NULL;
    render_lod lod;
    assert_true(render_lod_build(body, &ALLOCATOR, &indices, &lod, NULL, 0));
    assert_non_null(indices);
    print_message("demo body: %u triangles; levels %u, %u, %u\n", lod.count[0] / 3, lod.count[1] / 3, lod.count[2] / 3,
                  lod.count[3] / 3);
    assert_int_equal(lod.count[0], body->index_count);
    assert_int_equal(memcmp(indices, body->indices, body->index_count * 4), 0);
    for (int l = 1; l < RENDER_LOD_LEVELS; l++) {
        assert_true(lod.count[l] * 4 <= lod.count[l - 1] * 3); /* each takes away a quarter or more */
        assert_int_equal(lod.count[l] % 3, 0);
        for (uint32_t i = 0; i < lod.count[l]; i++)
            assert_true(indices[lod.first[l] + i] < body->vertex_count);
        /* on its own vertices: the same triangles, fewer vertices */
        sinew_mesh own;
        void *memory;
        assert_true(render_lod_compact(body, indices + lod.first[l], lod.count[l], &ALLOCATOR, &own, &memory));
        assert_int_equal(own.index_count, lod.count[l]);
        assert_true(own.vertex_count < body->vertex_count);
        for (uint32_t i = 0; i < own.index_count; i++) {
            uint32_t a = own.indices[i], b = indices[lod.first[l] + i];
            assert_memory_equal(&own.positions[a * 3], &body->positions[b * 3], 12);
            assert_memory_equal(&own.normals[a * 3], &body->normals[b * 3], 12);
            assert_memory_equal(&own.weights[a * own.influence_count], &body->weights[b * body->influence_count],
                                4 * body->influence_count);
            assert_memory_equal(&own.joints[a * own.influence_count], &body->joints[b * body->influence_count],
                                2 * body->influence_count);
        }
        lod_free(memory, NULL);
    }
    assert_true(lod.count[1] / 3 <= 7000 && lod.count[2] / 3 <= 1800);
    /* the far level, simplified across the segments' seams: a few hundred triangles at most,
     * its error measured (a few percent of the figure's height) */
    assert_true(lod.count[RENDER_LOD_LEVELS - 1] / 3 <= 400);
    assert_true(lod.far_error > 0.0f && lod.far_error <= 0.1f);
    lod_free(indices, NULL);
    /* a small mesh keeps one level */
    assert_true(render_lod_build(staff, &ALLOCATOR, &indices, &lod, NULL, 0));
    assert_null(indices);
    for (int l = 0; l < RENDER_LOD_LEVELS; l++)
        assert_int_equal(lod.count[l], staff->index_count);
    assert_true(lod.far_error == 0.0f);
    sinew_model_free(m);
}

static void test_level_by_size(void **state)
{
    (void)state;
    /* 27,904 triangles: full detail needs 55,808 pixels of figure (0.3 of the circle): r >= 243 */
    assert_int_equal(render_lod_level(250.0f, 27904, 0.03f), 0);
    assert_int_equal(render_lod_level(200.0f, 27904, 0.03f), 1);
    assert_int_equal(render_lod_level(70.0f, 27904, 0.03f), 2);
    assert_int_equal(render_lod_level(30.0f, 27904, 0.03f), 3);
    /* the far level where its error (3% of a 2r-pixel figure) is under a pixel: r <= 16.7 */
    assert_int_equal(render_lod_level(17.0f, 27904, 0.03f), 3);
    assert_int_equal(render_lod_level(16.0f, 27904, 0.03f), 4);
    assert_int_equal(render_lod_level(0.0f, 27904, 0.03f), RENDER_LOD_LEVELS - 1);
    assert_int_equal(render_lod_level(20.0f, 100, 0.0f), 0); /* a small model stays whole */
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_levels_of_the_demo),
        cmocka_unit_test(test_level_by_size),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
