/* Internals of the renderer shared between its files; no promise outside src/render. */
#ifndef SINEW_RENDER_INTERNAL_H
#define SINEW_RENDER_INTERNAL_H

#include "gl.h" /* libepoxy, loaded when the first context is made */

#include "../core/internal.h"
#include "sinew/render.h"

/* The mesh program's variants: which effects its fragment stage has compiled in. */
#define RENDER_WITH_SHADOWS 1u
#define RENDER_WITH_AO 2u
#define RENDER_WITH_TONE 4u
#define RENDER_MESH_VARIANTS 8
typedef struct render_programs {
    GLuint mesh;                               /* surfaces, wireframe, depth-only passes: the variant of the frame */
    GLuint mesh_variant[RENDER_MESH_VARIANTS]; /* made when first needed; [0] at creation */
    GLuint normals;                            /* vertex normals as lines (geometry stage) */
    GLuint overlay;                            /* skeleton, grid, axes, text */
    GLuint background;                         /* the environment behind the scene (a full-screen triangle) */
    GLuint ground;                             /* the shadow catcher: shadows and occlusion on the ground plane */
    GLuint outline;                            /* edges found in the depth pre-pass, over the frame */
    GLuint fxaa;  /* the frame's texture smoothed along its edges into the caller's framebuffer */
    GLuint depth; /* the mesh vertex stage with an empty fragment stage: shadow map, depth pre-pass */
} render_programs;

sinew_result render_programs_create(render_programs *programs, sinew_error *error);
GLuint render_mesh_variant(render_programs *programs, unsigned flags, sinew_error *error);
void render_programs_free(render_programs *programs);

/* Image-based lighting (environment.c): an equirectangular environment, RENDER_ENV_WIDTH x
 * RENDER_ENV_WIDTH/2 RGB floats at level 0 (mirror), each next level half the size and the GGX
 * lobe of roughness level / (RENDER_ENV_LEVELS - 1) integrated over it; `sh`: the diffuse
 * irradiance over pi as 9 spherical-harmonic coefficients (times the albedo: the diffuse
 * radiance); the dominant light's direction (towards it) and how directional it is (0..1). */
#define RENDER_ENV_WIDTH 256
#define RENDER_ENV_LEVELS 6
typedef struct render_env {
    float *level[RENDER_ENV_LEVELS];
    float sh[9][3];
    float light_dir[3];
    float directionality;
    float *memory;
} render_env;

/* An environment from an image of any size (1 to 4 channels; NaN, infinite and negative
 * texels read as 0), from an .hdr file (stb_image), or the built-in studio. */
bool render_env_from_pixels(const float *pixels, int width, int height, int channels, render_env *env);
sinew_result render_env_load(const char *path, render_env *env, sinew_error *error);
bool render_env_studio(render_env *env);
void render_env_free(render_env *env);
/* The diffuse radiance over albedo the harmonics give for normal n. */
void render_env_irradiance(const render_env *env, const float n[3], float out[3]);
/* The split-sum BRDF table: size x size (x: n.v, y: roughness, texel centres), scale and bias
 * of F0 (two floats a texel). */
void render_brdf_table(int size, float *rg);

/* Frame effects (effects.c): the environment on the GPU, the shadow map, the depth pre-pass
 * (occlusion, outlines), and the passes that draw no model: background, ground, outline.
 * Texture units they take: 7 environment, 8 BRDF table, 9 shadow map, 10 depth pre-pass. */
#define RENDER_SHADOW_SIZE 1024
typedef struct render_effects {
    GLuint env_texture, brdf_texture;
    float sh[9][3], light_dir[3], directionality;
    bool env_ready, env_custom;
    GLuint shadow_fbo, shadow_texture;
    GLuint depth_fbo, depth_texture;
    int depth_width, depth_height;
    GLuint empty_vao, ground_vao, ground_buffer;
    GLuint aa_fbo, aa_color, aa_depth; /* FXAA: what the frame is drawn into first */
    int aa_width, aa_height;
} render_effects;

/* One frame's effects, worked out before its passes. */
typedef struct render_effect_frame {
    float view_proj[16], inv_view_proj[16];
    float light_view_proj[16], shadow_matrix[16];
    float shadow_strength, shadow_bias;
    bool shadows, depth_pass, ao, outline, background, ground;
    float exposure; /* linear scale */
    int tone;       /* 0 none, 1 ACES, 2 neutral */
    float env_direct;
    float center[3], radius, ground_height;
    float near_plane, far_plane;
    bool orthographic;
    int width, height;
} render_effect_frame;

void render_effects_free(render_effects *fx);
sinew_result render_effects_set_environment(render_effects *fx, const char *path, sinew_error *error);
/* Works out the frame's effects (the camera's matrices, the key light towards `key`, the scene's
 * centre and radius) and makes what they need: the studio environment the first time, the
 * shadow map, the depth pre-pass's target at the viewport's size. `crowd`: a crowd frame (its
 * characters cast no shadows and have no pre-pass). */
sinew_result render_effects_prepare(render_effects *fx, render_effect_frame *ef, const sinew_frame *frame,
                                    const float key[3], const float view[16], const float proj[16], bool crowd,
                                    sinew_error *error);
/* Binds the shadow map's or the pre-pass's framebuffer, its viewport, and clears its depth. */
void render_effects_begin_shadow(render_effects *fx);
void render_effects_begin_depth(render_effects *fx, const render_effect_frame *ef);
/* Binds the effects' textures (units 7..10) and sets their uniforms on `program` (in use). */
void render_effects_bind(const render_effects *fx);
void render_effects_uniforms(const render_effects *fx, GLuint program, const render_effect_frame *ef);
void render_effects_background(const render_effects *fx, const render_programs *programs,
                               const render_effect_frame *ef);
void render_effects_ground(const render_effects *fx, const render_programs *programs, const render_effect_frame *ef);
void render_effects_outline(const render_effects *fx, const render_programs *programs, const render_effect_frame *ef);
/* FXAA: binds a framebuffer of the frame's size to draw into (false when GL refuses one), then
 * smooths it into `target` (the caller's draw framebuffer, bound again after). */
bool render_effects_begin_fxaa(render_effects *fx, int width, int height);
void render_effects_fxaa(const render_effects *fx, const render_programs *programs, GLuint target, int width,
                         int height);

/* Levels of detail (lod.c): index lists of a mesh, full then simplified, over the same
 * vertices. first/count: where each level's indices start in the list and how many; total:
 * the whole list's length; far_error: how far the last level (the far one) strays from the
 * mesh, as a fraction of the mesh's largest extent (0 when it has no such level). */
#define RENDER_LOD_LEVELS 5
typedef struct render_lod {
    uint32_t first[RENDER_LOD_LEVELS], count[RENDER_LOD_LEVELS];
    uint32_t total;
    float far_error;
} render_lod;

/* The levels of a mesh: *indices gets the whole list (through the allocator; NULL when the
 * mesh is too small to simplify, every level then the full list). False when out of memory.
 * When meshoptimizer cannot be loaded every level is the full list too, and `why` (may be NULL)
 * says so; else it is left as it is. */
bool render_lod_build(const sinew_mesh *mesh, const sinew_allocator *allocator, uint32_t **indices, render_lod *lod,
                      char *why, size_t why_size);
/* A level on its own vertices: the mesh's vertices its triangles use, in the order they are
 * first used, every array remapped (positions, normals, UVs, tangents, joints, weights), so
 * that a renderer which shades every vertex of a draw (Mesa's llvmpipe does) shades only
 * those. *memory holds the arrays (through the allocator); false when out of memory. */
bool render_lod_compact(const sinew_mesh *mesh, const uint32_t *indices, uint32_t index_count,
                        const sinew_allocator *allocator, sinew_mesh *out, void **memory);
/* The level for a character of `triangles` (its meshes' at full detail) whose bounding
 * sphere's radius spans this many pixels on screen: the finest whose triangles cover two
 * pixels or more each; past the others, the far level only where its error (far_error, the
 * largest of the character's meshes') comes to less than a pixel. */
int render_lod_level(float projected_radius, uint32_t triangles, float far_error);

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

/* The options' joint choices as node indices, -1 for none. */
static inline int32_t options_selected(const sinew_render_options *o)
{
    return o->select_joint ? (int32_t)o->selected_joint : -1;
}
static inline int32_t options_heatmap(const sinew_render_options *o)
{
    return o->heatmap ? (int32_t)o->heatmap_joint : -1;
}

#endif
