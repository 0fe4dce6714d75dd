/* sinew/render.h — draws a posed model into the current OpenGL 3.3 core context.
 *
 * What: a renderer that uploads a model's meshes once and draws a pose (world matrices
 * from sinew_local_to_world) each frame. Skinning runs in the vertex shader with every
 * skin's palette in a texture buffer (up to SINEW_MAX_JOINTS joints, up to
 * SINEW_MAX_INFLUENCES influences, no mesh splitting), or on the CPU through the core's
 * sinew_skin_vertices() (same picture); each skin by its file's method (linear, dual quaternion,
 * mixed) unless the options force one; morph targets and vertex caches at the frame's weights
 * and time (see sinew_frame). Display switches: materials (base colour and
 * texture maps) or clay; lighting (key + fill) or unlit; flat, Gouraud or Phong shading,
 * or physically based shading (metallic-roughness, normal, occlusion and emissive maps, a
 * studio or HDR environment (image-based lighting); exposure and tone mapping; shadows from a
 * shadow map, screen-space ambient occlusion and outlines as switches; wireframe overlay; the skeleton drawn over the
 * mesh (bones, joint dots, one selected joint highlighted, optional axes and names); a joint's weight heat map; vertex
 * normals; ground grid and world axes; the caller's lines (sinew_frame.lines); background colour;
 * volume-preserving muscles
 * (sinew/muscle_rig.h) as Gouraud-shaded tubes.
 * What not: no windows and no context creation: a GtkGLArea, or sinew/headless.h for
 * an off-screen EGL context, makes the context current first. No input handling.
 * Memory: create allocates GL objects and CPU scratch for the model (textures decoded
 * with stb_image); sinew_renderer_draw() allocates nothing.
 * Errors: sinew_result values with a message (GL version too old, shader that does not
 * compile, model too big for a buffer). Textures that cannot be read are warnings
 * (sinew_renderer_warning()), the material then shows its base colour.
 * Threads: every call must come from the thread whose context is current.
 * Conventions: see sinew/model.h; the frame's pixels are not read back here.
 */
#ifndef SINEW_RENDER_H
#define SINEW_RENDER_H

#include <stdbool.h>
#include <stdint.h>

#include "sinew/anim.h"
#include "sinew/camera.h"
#include "sinew/jobs.h"
#include "sinew/model.h"
#include "sinew/muscle_rig.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum sinew_shading {
    SINEW_SHADING_PHONG = 0,   /* lit per pixel (the default) */
    SINEW_SHADING_GOURAUD = 1, /* lit per vertex, colours interpolated */
    SINEW_SHADING_FLAT = 2,    /* one normal a triangle */
    SINEW_SHADING_PBR = 3      /* physically based (glTF metallic-roughness with normal, occlusion and
                                * emissive maps), lit by the environment (sinew_renderer_set_environment),
                                * tone mapped */
} sinew_shading;

/* How linear light becomes a display colour (after the exposure). */
typedef enum sinew_tone_mapping {
    SINEW_TONE_MAPPING_AUTO = 0,   /* Khronos PBR Neutral for physically based shading, none for the others */
    SINEW_TONE_MAPPING_NONE = 1,   /* clipped at 1 */
    SINEW_TONE_MAPPING_ACES = 2,   /* ACES filmic (Narkowicz's fit), as three.js's ACESFilmic */
    SINEW_TONE_MAPPING_NEUTRAL = 3 /* Khronos PBR Neutral: base colours kept up to 0.8, highlights rolled off */
} sinew_tone_mapping;

typedef enum sinew_skinning {
    SINEW_SKINNING_GPU = 0, /* vertex shader, palette in a texture buffer (the default) */
    SINEW_SKINNING_CPU = 1  /* sinew_skin_vertices() each frame, vertices streamed */
} sinew_skinning;

/* Display switches. A zeroed struct is the defaults (sinew_render_options_default() returns one):
 * meshes drawn with their materials, lit, Phong shading, the grid and muscles shown, small crowd
 * characters simplified, nothing selected, the dark grey background. Switches that are on by
 * default are named for turning them off (clay, unlit, hide_*). */
typedef struct sinew_render_options {
    bool clay;                   /* no base colour or diffuse texture: clay (default: materials) */
    bool unlit;                  /* no key and fill light: unlit colour (default: lit) */
    sinew_shading shading;       /* used when lit */
    bool wireframe;              /* triangle edges over the surface */
    bool hide_meshes;            /* draw no meshes (default: drawn) */
    bool skeleton;               /* bones and joint dots over the mesh */
    bool joint_axes;             /* each joint's local X/Y/Z axes (red/green/blue) */
    bool joint_names;            /* joint names next to the dots */
    bool normals;                /* vertex normals as short lines */
    bool hide_grid;              /* no ground grid (default: a grid at grid_height) */
    bool axes;                   /* world X/Y/Z axes at the origin */
    bool hide_muscles;           /* no muscles (default: the frame's muscles, Gouraud-shaded in their colours) */
    bool crowd_full_detail;      /* crowds: every character with its full meshes (default: characters small on
                                  * screen drawn with simplified meshes) */
    bool shadows;                /* the key light's shadows on the model and the ground (a shadow map); with an
                                  * environment file and PBR, the environment's dominant light casts them */
    bool ssao;                   /* screen-space ambient occlusion (from a depth pre-pass), on the model and the
                                  * ground */
    bool outline;                /* dark lines where depth jumps: silhouettes and creases */
    bool environment_background; /* the environment (sinew_renderer_set_environment) behind the scene,
                                  * blurred, instead of the background colour */
    bool fxaa; /* fast approximate anti-aliasing: the frame is drawn into a texture, then smoothed along
                * its edges into the bound framebuffer (cheap where multisampling is slow: llvmpipe) */
    sinew_tone_mapping tone_mapping;
    float exposure;    /* stops: the linear colour is scaled by 2^exposure before tone mapping (0 by default) */
    bool select_joint; /* highlight node selected_joint (default: none) */
    uint32_t selected_joint;
    bool heatmap; /* colour the mesh by node heatmap_joint's skin weights (default: off) */
    uint32_t heatmap_joint;
    bool background_set; /* background below instead of the default dark grey (0.16, 0.17, 0.19) */
    float background[3]; /* 0..1 RGB as displayed (sRGB) */
    bool transparent;    /* the background is cleared to (0, 0, 0, 0): edges come out premultiplied */
    float normal_length; /* world units; 0 = 3% of the scene radius */
    float grid_height;   /* world y of the ground grid (0 by default; sinew's apps put it under the
                          * model's lowest point over the frames they frame) */
    sinew_skinning skinning;
    bool skin_method_set;          /* false (the default): each skin skins as its file asks (sinew_skin.blend:
                                    * linear, dual quaternion, or the two mixed per vertex); true: skin_method */
    sinew_skin_method skin_method; /* with skin_method_set: linear blend or dual quaternions for every skin */
    const bool *hidden_instances;  /* instance_count flags, true = hidden; NULL = all shown */
} sinew_render_options;

/* The defaults: a zeroed struct, kept for code that asks for them by name. */
sinew_render_options sinew_render_options_default(void);
/* The background a frame with these options clears to (the default's grey when not set). */
void sinew_render_options_background(const sinew_render_options *options, float rgb[3]);

/* Display switches by name, for settings files and command lines. Names: materials,
 * lighting, wireframe, meshes, skeleton, joint-axes, joint-names, normals, grid, axes,
 * muscles, lod, shadows, ssao, outline, hdri-background, fxaa (booleans: on/off, true/false, yes/no,
 * 1/0; a NULL value means on), shading (phong|gouraud|flat|pbr), skinning (gpu|cpu),
 * skinning-method (file|lbs|dqs), tone-mapping (auto|none|aces|neutral), exposure (stops, -10..10),
 * background (RRGGBB, #RRGGBB, r,g,b in 0..1, or transparent), normal-length (world units, 0 =
 * automatic). Joint choices are node indices and are set
 * directly. An unknown name or a bad value gives SINEW_ERROR_INVALID_ARGUMENT. */
sinew_result sinew_render_option_set(sinew_render_options *options, const char *name, const char *value,
                                     sinew_error *error);
/* The value as sinew_render_option_set() reads it ("on", "phong", "#2a2b30", ...). */
sinew_result sinew_render_option_get(const sinew_render_options *options, const char *name, char *out, size_t size,
                                     sinew_error *error);
/* The names above, NULL-terminated; and whether one is a boolean switch. */
const char *const *sinew_render_option_names(void);

/* Whether a name is a boolean switch (materials, grid, ...) rather than a valued option. */
bool sinew_render_option_is_switch(const char *name);

typedef struct sinew_renderer sinew_renderer;

typedef struct sinew_renderer_desc {
    const sinew_model *model; /* kept by pointer: must outlive the renderer */
    /* Joints a skin may have for GPU skinning; 0 = what the GL texture-buffer limit
     * allows (SINEW_MAX_JOINTS or more). Larger skins are skinned on the CPU. */
    uint32_t max_gpu_joints;
    const sinew_allocator *allocator; /* NULL for malloc/free */
    /* The muscles frames will carry (NULL: none), to size the surface buffers once. */
    const sinew_muscle_set *muscles;
} sinew_renderer_desc;

/* Needs a current OpenGL >= 3.3 core context. */
sinew_result sinew_renderer_create(const sinew_renderer_desc *desc, sinew_renderer **out, sinew_error *error);
void sinew_renderer_free(sinew_renderer *renderer);

/* Image-based lighting for physically based shading (and the hdri-background option): an
 * equirectangular environment image (a Radiance .hdr, or any image stb_image reads, taken as
 * linear when it is HDR), prefiltered on the CPU into a GGX mip chain and 9 spherical-harmonic
 * coefficients of irradiance (about 0.1 s). NULL: the built-in neutral studio (made at the
 * first frame that needs it), lit together with the key and fill lights; a file's
 * environment lights alone. Errors (SINEW_ERROR_IO, SINEW_ERROR_FORMAT naming the file) keep
 * the environment in use. */
sinew_result sinew_renderer_set_environment(sinew_renderer *renderer, const char *path, sinew_error *error);

/* Warnings from create (unreadable textures, skins skinned on the CPU), and from the first
 * crowd drawn when its levels of detail cannot be made (meshoptimizer not installed): the
 * count grows then, so a program that printed them may look again after drawing. */
uint32_t sinew_renderer_warning_count(const sinew_renderer *renderer);
const char *sinew_renderer_warning(const sinew_renderer *renderer, uint32_t index);

/* The GL_RENDERER and GL_VERSION strings of the context it was created in. */
const char *sinew_renderer_gl_name(const sinew_renderer *renderer);

typedef struct sinew_frame {
    const sinew_mat4 *worlds; /* model->node_count world matrices */
    uint32_t world_count;
    const sinew_camera *camera;
    int width, height; /* viewport in pixels */
    const sinew_render_options *options;
    const sinew_muscle_pose *muscles; /* from sinew_muscle_rig_update(), or NULL */
    uint32_t muscle_count;
    /* A crowd: crowd_count characters of the model in one frame, each posed and placed by its
     * own world matrices (crowd_worlds: crowd_count * node_count, character after character;
     * a player's `root` places one). Meshes, grid, axes, and with the skeleton switch each
     * character's bones and joints (no names, joint axes, normals, muscles or heat map). GPU
     * skinning draws each mesh once for all characters
     * (instancing: the palettes of every character in one texture buffer); CPU skinning skins
     * and draws character after character. 0: the one character of `worlds`.
     * Levels of detail (unless options->crowd_full_detail): each character is drawn with all of its meshes'
     * triangles, or about a quarter, a sixteenth or a sixty-fourth of them (as far as a 2% error
     * allows), the finest level whose triangles cover two pixels or more each on screen
     * (meshoptimizer's simplifier; the same skinning, the levels on their own vertices; made
     * the first time a crowd needs them; meshes under 1,000 triangles keep theirs). */
    uint32_t crowd_count;
    const sinew_mat4 *crowd_worlds;
    sinew_jobs *jobs; /* optional: a crowd's palettes and CPU skinning on several threads */
    /* Lines of the caller's (a root-motion path, a target), drawn with the grid: line_count
     * segments of two world-space points (6 floats each), at most SINEW_MAX_FRAME_LINES, in
     * line_color (0..1 sRGB). */
    const float *lines;
    uint32_t line_count;
    float line_color[3];
    /* Morph targets and vertex caches (sinew/morph.h): the model's morph channel weights
     * (sinew_sample_weights(); NULL: their defaults), shared by a crowd's characters; where on
     * the file's timeline vertex caches are read (a clip's time plus its timeline), or none
     * with no_cache. Up to 16 targets with weight a draw morph on the GPU (the targets' offsets
     * in a buffer texture, the weights as uniforms); more, or a vertex cache, on the CPU. */
    const float *weights;
    uint32_t weight_count;
    float cache_time;
    bool no_cache;
} sinew_frame;

#define SINEW_MAX_FRAME_LINES 1024u

/* Clears the bound framebuffer's viewport and draws the frame. */
sinew_result sinew_renderer_draw(sinew_renderer *renderer, const sinew_frame *frame, sinew_error *error);

/* Bounds of the posed model's vertices (skinned and rigid instances, hidden ones too)
 * from world matrices, computed on the CPU; the box of the joints when no mesh has a
 * vertex (skeleton-only files). Returns false when the model has nothing with a position. */
bool sinew_renderer_bounds(sinew_renderer *renderer, const sinew_mat4 *worlds, uint32_t world_count, float min[3],
                           float max[3]);
/* The same for a whole frame: its worlds with its morph weights, vertex cache time and skin
 * methods (frame->options; the camera and viewport are not read). */
bool sinew_renderer_frame_bounds(sinew_renderer *renderer, const sinew_frame *frame, float min[3], float max[3]);

#ifdef __cplusplus
}
#endif
#endif
