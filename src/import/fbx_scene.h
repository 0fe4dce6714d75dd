/* The FBX scene between the document and the raw model, shared by the reader's files: fbx.c
 * indexes FBX 7.x documents into it and builds the raw model from it, fbx_legacy.c indexes
 * FBX 5.x and 6.x documents into the same shape. No promise to library users.
 *
 * Objects are the document's nodes that take part (models, geometries, deformers, materials,
 * ...), each with an id (the file's, or made up for files before 7.0 that name objects
 * instead), and links between them in the file's order. Animation is stacks (clips), each
 * with its layers in order, and bindings: the curves that animate one transform property of
 * one model in one layer.
 */
#ifndef SINEW_IMPORT_FBX_SCENE_H
#define SINEW_IMPORT_FBX_SCENE_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "fbx_curve.h"
#include "fbx_internal.h"
#include "internal.h"

#define FBX_TICKS_PER_SECOND 46186158000.0 /* FBX's time unit since 7.0 (FbxTime) */
#define FBX_OLD_TICKS_PER_SECOND 141120000.0

enum {
    K_OTHER,
    K_MODEL,
    K_GEOMETRY,
    K_SKIN,
    K_CLUSTER,
    K_BLEND_SHAPE,
    K_BLEND_CHANNEL, /* BlendShapeChannel; before 7.2 a Shape of a geometry (fbx_legacy.c makes one) */
    K_SHAPE,         /* Geometry "Shape": a blend shape's offsets */
    K_CACHE_DEFORMER,
    K_CACHE,
    K_STACK,
    K_LAYER,
    K_CURVE_NODE,
    K_CURVE,
    K_MATERIAL,
    K_TEXTURE,
    K_VIDEO
};

typedef struct fbx_object {
    int64_t id;
    const fbx_node *node;
    const char *name;
    size_t name_len;
    int kind;
    const fbx_node *props;                 /* Properties70 / Properties60, or NULL */
    const fbx_node *defaults;              /* the template's Properties70, or NULL */
    uint32_t first_parent, parent_count;   /* in scene.up */
    uint32_t first_child, child_count;     /* in scene.down */
    uint32_t first_binding, binding_count; /* models: in scene.bindings */
    uint32_t order;                        /* place in the file */
    int32_t raw_node;                      /* models: raw node index */
    int32_t raw_material;
    int32_t curve; /* curves: index in scene.curves, else -1 */
} fbx_object;

typedef struct fbx_link {
    uint32_t child, parent; /* object indices */
    uint32_t order;         /* in the file */
    const fbx_value *prop;  /* "OP" connections: the property, else NULL */
} fbx_link;

/* The properties of a node's transform, in the order node_local() takes them. */
enum {
    P_TRANSLATION,
    P_ROTATION,
    P_SCALING,
    P_ROTATION_OFFSET,
    P_ROTATION_PIVOT,
    P_SCALING_OFFSET,
    P_SCALING_PIVOT,
    P_PRE_ROTATION,
    P_POST_ROTATION,
    P_COUNT
};

/* A binding's prop for a blend channel's DeformPercent (fbx_binding.model is the channel). */
#define P_DEFORM_PERCENT P_COUNT

/* A clip: an AnimationStack, or a take of a file before 7.0. */
typedef struct fbx_stack {
    const char *name;
    size_t name_len;
    double start, stop; /* seconds; stop <= start: the span of its keys */
    uint32_t order;     /* in the file */
    uint32_t first_layer, layer_count;
} fbx_stack;

/* A layer of a stack (stack.first_layer + index). */
typedef struct fbx_layer {
    uint32_t stack, index;
    double weight;        /* 0..1 */
    int32_t weight_curve; /* the layer's own animated weight (percent), or -1 */
    bool additive, blended, compose_rotation, compose_scale;
} fbx_layer;

/* One animated transform property of one model in one layer: the curve of each component
 * (an index in scene.curves, or -1) and the values of components without one (NaN: the
 * property's own value). */
typedef struct fbx_binding {
    uint32_t model, layer, stack, index; /* index: the layer's place in its stack */
    int prop;                            /* P_* */
    int32_t curves[3];
    double defaults[3];
} fbx_binding;

/* A node's transform properties without animation, read once. */
typedef struct fbx_static {
    double value[P_COUNT][3];
    int order; /* rotation order */
    /* value[]'s pre-rotation and inverse post-rotation quaternions, made once: node_local()
     * takes them while the animated values are the same (nearly always: they are rarely
     * animated) */
    double pre[4], post_inverse[4];
} fbx_static;

typedef struct scene {
    const char *path;
    sinew_error *error;
    raw_model *model;
    fbx_doc doc;
    bool legacy; /* a document before 7.0 (fbx_legacy.c indexed it) */
    double ticks_per_second;
    fbx_object *objects;
    uint32_t object_count;
    fbx_link *up, *down; /* links sorted by child / by parent */
    uint32_t link_count;
    fbx_curve *curves;
    uint32_t curve_count, curve_capacity;
    fbx_stack *stacks;
    uint32_t stack_count;
    fbx_layer *layers;
    uint32_t layer_count;
    fbx_binding *bindings;
    uint32_t binding_count, binding_capacity;
    uint32_t *models;    /* model object of each raw node (root: UINT32_MAX) */
    fbx_static *statics; /* one an object (used for K_MODEL) */
    sinew_mat4 convert;  /* file axes and unit -> Y-up metres: the root node */
    double diagonal;     /* of the rest pose's node positions, file units */
    uint32_t model_count;
    const fbx_node *global_settings; /* GlobalSettings' properties, or NULL */
    sinew_mat4 *rest_worlds;         /* made on first use (fbx.c) */
    bool blender;                    /* written by Blender's exporter (its FullWeights are vertex weights) */
    double frame_rate;               /* GlobalSettings' time mode, frames a second (3ds Max point caches) */
    int32_t *geometry_channel;       /* one an object: a geometry's first model morph channel, or -1 */
    int32_t *channel_object;         /* one a model morph channel: its BlendShapeChannel object, or -1 */
} scene;

extern const char *const fbx_transform_props[P_COUNT];

/* fbx.c: errors naming the file (and the object). */
sinew_result fbx_fail_data(scene *s, const char *what, const fbx_object *o);
sinew_result fbx_oom(scene *s);
/* "Name\0\1Class" (binary) or "Class::Name" (ASCII): the name part. */
void fbx_object_name(const fbx_value *v, const char **name, size_t *len);
bool fbx_value_is(const fbx_value *v, const char *text);
/* Sorts links both ways and fills each object's link ranges (the links are in s->up). */
void fbx_sort_links(scene *s);
/* Appends a curve to s->curves; its index, or -1 when out of memory. */
int32_t fbx_add_curve(scene *s, const fbx_curve *c);
/* Appends a binding (growing the array); false when out of memory. */
bool fbx_add_binding(scene *s, const fbx_binding *b);
/* Sorts the bindings by model, stack and layer, and fills each model's range. */
void fbx_sort_bindings(scene *s);

/* fbx.c: links, properties. */
const fbx_link *fbx_parent_link(const scene *s, const fbx_object *o, uint32_t k);
const fbx_link *fbx_child_link(const scene *s, const fbx_object *o, uint32_t k);
/* The first object of `kind` connected to `o` either way (children first), or NULL. */
fbx_object *fbx_linked(const scene *s, const fbx_object *o, int kind, bool children, bool parents);
/* A property of a Properties70 or Properties60 block, of an object (or its template). */
const fbx_node *fbx_find_p(const fbx_node *props, const char *name);
const fbx_node *fbx_prop(const fbx_object *o, const char *name);
double fbx_prop_num(const fbx_object *o, const char *name, double fallback);
/* A property's string value (the first after its type and flags), or NULL. */
const fbx_value *fbx_prop_string(const fbx_object *o, const char *name);
/* Property `prop` of object `o` (a blend channel's DeformPercent) at time t (seconds) of
 * `stack`: the layers' curves combined, `value` where none animates it. */
double fbx_animated_value(const scene *s, uint32_t o, int prop, int32_t stack, double t, double clip_start,
                          double value);
/* Extends a list of clip times with the key times of every curve that animates object `o` in
 * `stack` (fbx.c's sample_times for any object). */
sinew_result fbx_object_key_times(const scene *s, uint32_t o, int32_t stack, double start, float duration,
                                  float **times, uint32_t *count);

/* fbx_deform.c: what deforms a geometry besides its skin, read once for every mesh cut from it. */
typedef struct fbx_shape_source {
    const fbx_node *node; /* Indexes, Vertices, Normals */
    const char *name;
    size_t name_len;
    double full_weight;         /* percent */
    const double *vertex_scale; /* Blender: a weight an offset (its FullWeights), or NULL */
    uint32_t channel;           /* the geometry's channel */
} fbx_shape_source;

typedef struct fbx_deform {
    uint32_t point_count;
    uint32_t channel_count;
    int32_t first_channel; /* model morph channel of the geometry's channel 0 */
    uint32_t shape_count;
    fbx_shape_source *shapes;
    uint32_t blend;       /* sinew_skin_blend of its skin */
    float *dq;            /* SINEW_SKIN_BLEND_MIXED: a weight a control point, or NULL */
    uint32_t frame_count; /* vertex cache frames, 0 for none */
    float *frame_times;   /* seconds on the file's timeline */
    float *frames;        /* frame_count * point_count * 3, geometry space */
} fbx_deform;

/* Reads the blend shapes, skinning method and vertex cache of geometry `g` (skin: its Skin
 * deformer, or NULL) with `point_count` control points, adding the model morph channels its
 * channels need (once a geometry). */
sinew_result fbx_deform_read(scene *s, const fbx_object *g, const fbx_object *skin, uint32_t point_count,
                             fbx_deform *out);
/* The targets, DQ weights and cache of one mesh cut from the geometry: points[v] is the
 * control point of its vertex v; `place` takes geometry space to the mesh's (the geometric
 * transform of a rigid mesh, else identity). */
sinew_result fbx_deform_emit(scene *s, const fbx_deform *d, const uint32_t *points, const dmat *place, raw_mesh *mesh);
void fbx_deform_free(fbx_deform *d);
/* Every morph channel's weight over `stack` as a weight track of `clip` (keys where the
 * channel's curves have them, more where linear keys would stray). */
sinew_result fbx_weight_tracks(scene *s, uint32_t stack, double start, raw_clip *clip);

/* fbx_cache.c: the positions channel of a geometry cache file. */
typedef struct fbx_cache_data {
    uint32_t frame_count, point_count;
    float *times;     /* seconds */
    float *positions; /* frame_count * point_count * 3 */
} fbx_cache_data;

/* Reads a Maya cache (its .xml description with the .mc/.mcx data it names, one file or one a
 * frame) or a 3ds Max .pc2, picking the channel named `channel` (NULL or not found: the first
 * positions channel). frame_rate gives a .pc2's frames in seconds. A message in `why` (naming
 * the file) when it cannot. */
sinew_result fbx_cache_read(const char *path, const char *channel, double frame_rate, fbx_cache_data *out, char *why,
                            size_t why_size);
void fbx_cache_free(fbx_cache_data *c);

/* fbx_legacy.c: a document before FBX 7.0 as objects, links, curves, stacks, layers and
 * bindings (s->doc parsed, s->ticks_per_second set). */
sinew_result fbx_legacy_index(scene *s);

#endif
