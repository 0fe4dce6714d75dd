/* What the fuzz targets do with a model that loaded: use it the way a player does (sample
 * every clip, and play it with sinew_player, world matrices, palettes, skin every mesh, read
 * embedded images), which must stay in bounds. */
#include <stdlib.h>

#include "exercise.h"

void fuzz_exercise(const sinew_model *m)
{
    sinew_transform *locals = malloc((m->node_count + 1) * sizeof *locals);
    sinew_mat4 *worlds = malloc((m->node_count + 1) * sizeof *worlds);
    sinew_mat4 *palette = malloc(SINEW_MAX_JOINTS * sizeof *palette);
    for (uint32_t c = 0; c <= m->clip_count; c++) {
        const sinew_clip *clip = c < m->clip_count ? &m->clips[c] : NULL;
        float duration = clip ? clip->duration : 0.0f;
        for (int step = 0; step < 3; step++) {
            sinew_sample_desc desc = {.model = m,
                                      .clip = clip,
                                      .time = duration * ((float)step * 0.5f), /* finite for any duration */
                                      .locals = locals,
                                      .local_count = m->node_count};
            if (sinew_sample(&desc, NULL) != SINEW_OK ||
                sinew_local_to_world(m, locals, m->node_count, NULL, worlds, m->node_count, NULL) != SINEW_OK)
                abort(); /* a model that loaded must sample */
        }
        sinew_clip_layout *layout = NULL;
        sinew_player *player = NULL;
        if (sinew_clip_layout_create(&(sinew_clip_layout_desc){.model = m, .clip = clip}, &layout, NULL) != SINEW_OK)
            abort();
        size_t size = sinew_player_size(layout);
        void *memory = malloc(size);
        if (!memory || sinew_player_init(memory, size, layout, &player, NULL) != SINEW_OK)
            abort();
        for (int step = 0; step < 3; step++)
            if (sinew_player_update(player, duration * ((float)step * 0.5f), SINEW_WRAP_CLAMP, NULL, worlds,
                                    m->node_count, NULL) != SINEW_OK)
                abort();
        free(memory);
        sinew_clip_layout_free(layout);
    }
    /* embedded images: every byte readable */
    volatile unsigned sum = 0;
    for (uint32_t i = 0; i < m->material_count; i++)
        for (int k = 0; k < SINEW_MAP_COUNT; k++)
            for (uint32_t b = 0; b < m->materials[i].maps[k].image_size; b++)
                sum += m->materials[i].maps[k].image[b];
    (void)sum;
    for (uint32_t i = 0; i < m->mesh_count; i++) {
        const sinew_mesh *mesh = &m->meshes[i];
        float *out = malloc(((size_t)mesh->vertex_count + 1) * 3 * sizeof(float));
        float *normals = malloc(((size_t)mesh->vertex_count + 1) * 3 * sizeof(float));
        if (mesh->skin >= 0) {
            const sinew_skin *skin = &m->skins[mesh->skin];
            if (sinew_skin_palette(skin, worlds, m->node_count, palette, SINEW_MAX_JOINTS, NULL) != SINEW_OK)
                abort();
            sinew_skin_desc sd = {.mesh = mesh,
                                  .palette = palette,
                                  .palette_count = skin->joint_count,
                                  .out_positions = out,
                                  .out_normals = normals};
            if (sinew_skin_vertices(&sd, NULL) != SINEW_OK)
                abort();
        } else if (sinew_transform_vertices(mesh, &worlds[0], out, normals, 0, NULL) != SINEW_OK && m->node_count) {
            abort();
        }
        free(out);
        free(normals);
    }
    free(locals);
    free(worlds);
    free(palette);
}
