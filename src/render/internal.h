/* Internals of the renderer shared between its files; no promise outside src/render. */
#ifndef SINEW_RENDER_INTERNAL_H
#define SINEW_RENDER_INTERNAL_H

#include <epoxy/gl.h>

#include "../core/internal.h"
#include "sinew/render.h"

typedef struct render_programs {
    GLuint mesh;    /* surfaces, wireframe */
    GLuint normals; /* vertex normals as lines (geometry stage) */
    GLuint overlay; /* skeleton, grid, axes, text */
} render_programs;

sinew_result render_programs_create(render_programs *programs, sinew_error *error);
void render_programs_destroy(render_programs *programs);

/* Levels of detail (lod.c): index lists of a mesh, full then simplified, over the same
 * vertices. first/count: where each level's indices start in the list and how many; total:
 * the whole list's length. */
#define RENDER_LOD_LEVELS 4
typedef struct render_lod {
    uint32_t first[RENDER_LOD_LEVELS], count[RENDER_LOD_LEVELS];
    uint32_t total;
} render_lod;

/* The levels of a mesh: *indices gets the whole list (through the allocator; NULL when the
 * mesh is too small to simplify, every level then the full list). False when out of memory. */
bool render_lod_build(const sinew_mesh *mesh, const sinew_allocator *allocator, uint32_t **indices, render_lod *lod);
/* A level on its own vertices: the mesh's vertices its triangles use, in the order they are
 * first used, every array remapped (positions, normals, UVs, tangents, joints, weights), so
 * that a renderer which shades every vertex of a draw (Mesa's llvmpipe does) shades only
 * those. *memory holds the arrays (through the allocator); false when out of memory. */
bool render_lod_compact(const sinew_mesh *mesh, const uint32_t *indices, uint32_t index_count,
                        const sinew_allocator *allocator, sinew_mesh *out, void **memory);
/* The level for a character of `triangles` (its meshes' at full detail) whose bounding
 * sphere's radius spans this many pixels on screen: the finest whose triangles cover two
 * pixels or more each. */
int render_lod_level(float projected_radius, uint32_t triangles);

/* Reverses the order of `rows` rows of `row_bytes` each, in place (images store the top row
 * first, OpenGL the bottom one). */
void render_flip_rows(unsigned char *pixels, size_t row_bytes, int rows);

/* One vertex of the overlay: position and sRGB colour (the layout stb_easy_font writes). */
typedef struct overlay_vertex {
    float position[3];
    uint8_t color[4];
} overlay_vertex;

/* Growing list of overlay vertices in a buffer sized once at creation. */
typedef struct overlay_list {
    overlay_vertex *vertices;
    uint32_t count, capacity;
} overlay_list;

/* The per-frame facts the overlay needs. */
typedef struct overlay_frame {
    const sinew_model *model;
    const bool *skeleton_nodes; /* node_count flags: drawn as part of the skeleton */
    const sinew_mat4 *worlds;
    const sinew_render_options *options;
    const sinew_camera *camera;
    const float *view_proj; /* 16 floats */
    int width, height;
    float scene_radius;
    const float *lines; /* the frame's own segments */
    uint32_t line_count;
    const float *line_color;
} overlay_frame;

/* Fill `list` with world-space geometry; each returns false when the list is full. */
void overlay_add_grid(overlay_list *list, const overlay_frame *frame);
void overlay_add_axes(overlay_list *list, const overlay_frame *frame);
void overlay_add_lines(overlay_list *list, const overlay_frame *frame);
void overlay_add_bones(overlay_list *list, const overlay_frame *frame);
void overlay_add_joint_axes(overlay_list *list, const overlay_frame *frame);
void overlay_add_joints(overlay_list *list, const overlay_frame *frame, bool selected_only);
/* Pixel-space quads of joint names (4 vertices a quad). */
void overlay_add_names(overlay_list *list, const overlay_frame *frame);

/* Vertices the overlay may need for a model with `node_count` nodes. */
uint32_t overlay_capacity(uint32_t node_count);
/* Vertices reserved for text quads. */
#define OVERLAY_TEXT_VERTICES (64u * 1024u)

#endif
