/* sinew's FBX reader: an FBX 7.x document (fbx_parse.c) evaluated as Maya, 3ds Max and
 * MotionBuilder evaluate it, into a raw model (internal.h).
 *
 *   objects ........... Objects, Connections and Definitions' property templates, indexed
 *   properties ........ Properties70 lookups with the templates' defaults
 *   transforms ........ a node's local transform (offsets, pivots, pre/post rotation, rotation
 *                       order), its inherit type, its geometric transform
 *   animation ......... stacks, their layers in order, and the curves that animate each
 *                       model property in a layer (curves themselves: fbx_curve.c)
 *   layers ............ a property over time: each layer's value replaces, adds to (by
 *                       quaternion for rotations, by product for scales) or blends with the
 *                       layers below, by the layer's weight and its weight curve
 *   nodes ............. the hierarchy under a root that converts axes and unit to Y-up metres
 *   meshes ............ polygons triangulated per material, attributes split where they differ
 *   skins ............. clusters with every influence, inverse binds with geometric transforms
 *   materials ......... diffuse colour and texture
 *   clips ............. each animation stack baked to keys (below), with its time span
 *
 * Baking. sinew's runtime plays translation/rotation/scale keys; FBX animates Euler angles
 * per axis in the node's rotation order, through pivots, pre- and post-rotations, with Bezier
 * tangents. Each animated node's local transform is evaluated exactly (doubles) at every key
 * time of its curves, the stack's start and end, and just before every step of a constant
 * key; each interval is then halved until linear (translation, scale) and spherical (rotation)
 * interpolation of the neighbouring samples is within FBX_BAKE_TOLERANCE of the exact
 * transform at a quarter, half and three quarters of the way (rotations in radians,
 * translations relative to the scene's size). So the baked clip equals the file's curves at
 * every key and within the tolerance in between.
 */
#define _GNU_SOURCE /* qsort_r */
#include <math.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../core/internal.h"
#include "fbx_internal.h"
#include "fbx_scene.h"
#include "internal.h"
#include "alloc.h" /* last: the readers' allocations are the import's (alloc.h) */

/* How far a baked clip may stray from the file's curves: radians, relative scale, and of the
 * scene's size for translations. 1e-6 keeps poses ten times inside the 1e-5 of "the same pose"
 * (at most 1.6e-6 from an exact bake over the shared FBX files, 200 times each); 2e-7 took 16%
 * more evaluations on walk.fbx for digits a float key barely holds. */
#define FBX_BAKE_TOLERANCE 1e-6
#define FBX_MAX_NODES (1u << 20)
/* Key times a curve may add to a node's bake through its extrapolated cycles. */
#define FBX_MAX_CYCLE_KEYS 100000u

const char *const fbx_transform_props[P_COUNT] = {"Lcl Translation", "Lcl Rotation",  "Lcl Scaling",
                                                  "RotationOffset",  "RotationPivot", "ScalingOffset",
                                                  "ScalingPivot",    "PreRotation",   "PostRotation"};

/* ---- small double-precision math ------------------------------------------------------- */

/* Determinant of the 3x3 part (negative: the matrix mirrors). */
static double dmat_det3(const dmat *a)
{
    const double *m = a->m;
    return m[0] * (m[5] * m[10] - m[9] * m[6]) + m[4] * (m[9] * m[2] - m[1] * m[10]) +
           m[8] * (m[1] * m[6] - m[5] * m[2]);
}

static void dmat_point(const dmat *a, const double p[3], double out[3])
{
    for (int r = 0; r < 3; r++)
        out[r] = a->m[r] * p[0] + a->m[4 + r] * p[1] + a->m[8 + r] * p[2] + a->m[12 + r];
}

/* The axes of FBX's rotation orders, in the order they are applied (0 XYZ = X first, then Y,
 * then Z; 1 XZY, 2 YZX, 3 YXZ, 4 ZXY, 5 ZYX; 6 spheric XYZ and anything else is taken as XYZ). */
static const int *euler_axes(int order)
{
    static const int axes[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 2, 0}, {1, 0, 2}, {2, 0, 1}, {2, 1, 0}};
    return axes[order < 0 || order > 5 ? 0 : order];
}

/* Rotation matrix of Euler angles in degrees applied in `order` (euler_axes()). */
static dmat euler_matrix(const double degrees[3], int order)
{
    const int *axes = euler_axes(order);
    double r[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1}; /* 3x3, column-major */
    for (int k = 0; k < 3; k++) {
        int axis = axes[k];
        if (degrees[axis] == 0.0)
            continue;
        double a = degrees[axis] * (M_PI / 180.0), c = cos(a), sn = sin(a);
        int i = (axis + 1) % 3, j = (axis + 2) % 3;
        /* r = E * r, where E rotates about `axis`: only rows i and j change. */
        for (int col = 0; col < 3; col++) {
            double ri = r[col * 3 + i], rj = r[col * 3 + j];
            r[col * 3 + i] = c * ri - sn * rj;
            r[col * 3 + j] = sn * ri + c * rj;
        }
    }
    dmat m = dmat_identity();
    for (int col = 0; col < 3; col++)
        for (int row = 0; row < 3; row++)
            m.m[col * 4 + row] = r[col * 3 + row];
    return m;
}

/* The Euler angles (degrees, applied in `order`) of the rotation of a unit quaternion
 * (x, y, z, w); in gimbal lock the first angle is 0. */
static void quat_euler(const double q[4], int order, double out[3])
{
    const int *axes = euler_axes(order);
    double r[3][3]; /* r[row][col] */
    dmat m = dmat_from_trs((double[3]){0, 0, 0}, q, (double[3]){1, 1, 1});
    for (int row = 0; row < 3; row++)
        for (int col = 0; col < 3; col++)
            r[row][col] = m.m[col * 4 + row];
    /* R = R_k(c) R_j(b) R_i(a), i applied first; e: +1 for an even permutation of XYZ */
    int i = axes[0], j = axes[1], k = axes[2];
    double e = (j == (i + 1) % 3) ? 1.0 : -1.0;
    double sb = -e * r[k][i];
    double a, b, c;
    if (fabs(sb) < 0.9999999999) {
        b = asin(sb);
        a = atan2(e * r[k][j], r[k][k]);
        c = atan2(e * r[j][i], r[i][i]);
    } else {
        b = sb > 0 ? M_PI / 2 : -M_PI / 2;
        a = 0;
        c = atan2(-e * r[i][j], r[j][j]);
    }
    double angles[3];
    angles[i] = a;
    angles[j] = b;
    angles[k] = c;
    for (int n = 0; n < 3; n++)
        out[n] = angles[n] * (180.0 / M_PI);
}

static void quat_mul(const double a[4], const double b[4], double out[4])
{
    double r[4] = {
        a[3] * b[0] + a[0] * b[3] + a[1] * b[2] - a[2] * b[1], a[3] * b[1] - a[0] * b[2] + a[1] * b[3] + a[2] * b[0],
        a[3] * b[2] + a[0] * b[1] - a[1] * b[0] + a[2] * b[3], a[3] * b[3] - a[0] * b[0] - a[1] * b[1] - a[2] * b[2]};
    memcpy(out, r, sizeof r);
}

/* The unit quaternion (x, y, z, w) of Euler angles in degrees applied in `order`, as
 * euler_matrix() rotates: each axis's half-angle quaternion multiplied on the left (the product
 * written out for a quaternion with one axis: half of quat_mul's work, the same numbers). */
static void euler_rotation(const double degrees[3], int order, double q[4])
{
    const int *axes = euler_axes(order);
    q[0] = q[1] = q[2] = 0.0, q[3] = 1.0;
    for (int k = 0; k < 3; k++) {
        int i = axes[k], j = (i + 1) % 3, l = (i + 2) % 3;
        if (degrees[i] == 0.0)
            continue;
        double half = degrees[i] * (M_PI / 360.0), c = cos(half), sn = sin(half);
        double qi = q[i], qj = q[j], ql = q[l], qw = q[3];
        q[i] = c * qi + sn * qw;
        q[j] = c * qj - sn * ql;
        q[l] = c * ql + sn * qj;
        q[3] = c * qw - sn * qi;
    }
}

/* The inverse of a post-rotation (XYZ Euler angles in degrees): its quaternion's conjugate. */
static void post_rotation_inverse(const double degrees[3], double q[4])
{
    euler_rotation(degrees, 0, q);
    for (int c = 0; c < 3; c++)
        q[c] = -q[c];
}

/* q with the sign dmat_quat() gives the rotation (w positive where the matrix's trace is,
 * else the component of the largest diagonal element), normalised. */
static void quat_canonical(double q[4])
{
    double xx = q[0] * q[0], yy = q[1] * q[1], zz = q[2] * q[2], ww = q[3] * q[3];
    double n = xx + yy + zz + ww;
    double m00 = n - 2 * (yy + zz), m11 = n - 2 * (xx + zz), m22 = n - 2 * (xx + yy);
    int pick = m00 + m11 + m22 > 0 ? 3 : m00 > m11 && m00 > m22 ? 0 : m11 > m22 ? 1 : 2;
    double scale = n > 0 ? 1.0 / sqrt(n) : 0.0;
    if (q[pick] < 0)
        scale = -scale;
    for (int c = 0; c < 4; c++)
        q[c] *= scale;
    if (n <= 0)
        q[3] = 1.0;
}

/* Spherical interpolation from a to b (the shorter way), unit quaternions. */
static void quat_slerp(const double a[4], const double b[4], double t, double out[4])
{
    double d = a[0] * b[0] + a[1] * b[1] + a[2] * b[2] + a[3] * b[3], sign = d < 0 ? -1.0 : 1.0;
    d = fabs(d);
    double wa = 1 - t, wb = t;
    if (d < 0.9999999) {
        double angle = acos(d), sn = sin(angle);
        wa = sin((1 - t) * angle) / sn;
        wb = sin(t * angle) / sn;
    }
    double len = 0;
    for (int c = 0; c < 4; c++) {
        out[c] = wa * a[c] + sign * wb * b[c];
        len += out[c] * out[c];
    }
    len = len > 0 ? sqrt(len) : 1;
    for (int c = 0; c < 4; c++)
        out[c] /= len;
}

/* ---- objects ------------------------------------------------------------------------- */

sinew_result fbx_fail_data(scene *s, const char *what, const fbx_object *o)
{
    if (o && !s->legacy)
        return sinew_fail(s->error, SINEW_ERROR_FORMAT, "%s: %.*s \"%.*s\" (id %lld): %s", s->path,
                          (int)o->node->name_len, o->node->name, (int)o->name_len, o->name, (long long)o->id, what);
    if (o)
        return sinew_fail(s->error, SINEW_ERROR_FORMAT, "%s: %.*s \"%.*s\": %s", s->path, (int)o->node->name_len,
                          o->node->name, (int)o->name_len, o->name, what);
    return sinew_fail(s->error, SINEW_ERROR_FORMAT, "%s: %s", s->path, what);
}

sinew_result fbx_oom(scene *s)
{
    return sinew_fail(s->error, SINEW_ERROR_OUT_OF_MEMORY, "%s: out of memory reading the FBX scene", s->path);
}

/* "Name\0\1Class" (binary) or "Class::Name" (ASCII): the name part. */
void fbx_object_name(const fbx_value *v, const char **name, size_t *len)
{
    *name = "";
    *len = 0;
    if (!v || v->type != FBX_STRING)
        return;
    const char *s = v->s;
    size_t n = v->count;
    for (size_t i = 0; i + 1 < n; i++)
        if (s[i] == '\0' && s[i + 1] == '\x01') {
            *name = s;
            *len = i;
            return;
        }
    for (size_t i = 0; i + 1 < n; i++)
        if (s[i] == ':' && s[i + 1] == ':') {
            *name = s + i + 2;
            *len = n - i - 2;
            return;
        }
    *name = s;
    *len = n;
}

bool fbx_value_is(const fbx_value *v, const char *text)
{
    size_t n = strlen(text);
    return v && v->type == FBX_STRING && v->count == n && memcmp(v->s, text, n) == 0;
}

static int object_kind(const fbx_node *n)
{
    const fbx_value *sub = n->value_count > 2 ? &n->values[2] : NULL;
    if (fbx_named(n, "Model"))
        return K_MODEL;
    if (fbx_named(n, "Geometry"))
        return fbx_value_is(sub, "Mesh") ? K_GEOMETRY : fbx_value_is(sub, "Shape") ? K_SHAPE : K_OTHER;
    if (fbx_named(n, "Deformer"))
        return fbx_value_is(sub, "Skin")                  ? K_SKIN
               : fbx_value_is(sub, "Cluster")             ? K_CLUSTER
               : fbx_value_is(sub, "BlendShape")          ? K_BLEND_SHAPE
               : fbx_value_is(sub, "BlendShapeChannel")   ? K_BLEND_CHANNEL
               : fbx_value_is(sub, "VertexCacheDeformer") ? K_CACHE_DEFORMER
                                                          : K_OTHER;
    static const struct {
        const char *name;
        int kind;
    } kinds[] = {{"AnimationStack", K_STACK}, {"AnimationLayer", K_LAYER}, {"AnimationCurveNode", K_CURVE_NODE},
                 {"AnimationCurve", K_CURVE}, {"Material", K_MATERIAL},    {"Texture", K_TEXTURE},
                 {"Video", K_VIDEO},          {"Cache", K_CACHE}};
    for (size_t i = 0; i < sizeof kinds / sizeof kinds[0]; i++)
        if (fbx_named(n, kinds[i].name))
            return kinds[i].kind;
    return K_OTHER;
}

static int compare_objects(const void *a, const void *b)
{
    const fbx_object *x = a, *y = b;
    return x->id < y->id ? -1 : x->id > y->id;
}

static int32_t find_object(const scene *s, int64_t id)
{
    uint32_t lo = 0, hi = s->object_count;
    while (lo < hi) {
        uint32_t mid = lo + (hi - lo) / 2;
        if (s->objects[mid].id < id)
            lo = mid + 1;
        else
            hi = mid;
    }
    return lo < s->object_count && s->objects[lo].id == id ? (int32_t)lo : -1;
}

static int compare_up(const void *a, const void *b)
{
    const fbx_link *x = a, *y = b;
    if (x->child != y->child)
        return x->child < y->child ? -1 : 1;
    return x->order < y->order ? -1 : x->order > y->order;
}

static int compare_down(const void *a, const void *b)
{
    const fbx_link *x = a, *y = b;
    if (x->parent != y->parent)
        return x->parent < y->parent ? -1 : 1;
    return x->order < y->order ? -1 : x->order > y->order;
}

/* The property template of an object type (Definitions/ObjectType/PropertyTemplate). */
static const fbx_node *template_for(const scene *s, const fbx_node *object)
{
    const fbx_node *defs = fbx_child(&s->doc.root, "Definitions");
    for (uint32_t i = 0; defs && i < defs->child_count; i++) {
        const fbx_node *t = &defs->children[i];
        if (!fbx_named(t, "ObjectType") || t->value_count < 1 || t->values[0].type != FBX_STRING ||
            t->values[0].count != object->name_len || memcmp(t->values[0].s, object->name, object->name_len) != 0)
            continue;
        const fbx_node *pt = fbx_child(t, "PropertyTemplate");
        return pt ? fbx_child(pt, "Properties70") : NULL;
    }
    return NULL;
}

static sinew_result index_objects(scene *s)
{
    const fbx_node *objects = fbx_child(&s->doc.root, "Objects");
    uint32_t n = objects ? objects->child_count : 0;
    s->objects = calloc(n ? n : 1, sizeof *s->objects);
    if (!s->objects)
        return fbx_oom(s);
    for (uint32_t i = 0; i < n; i++) {
        const fbx_node *node = &objects->children[i];
        if (node->value_count < 1 || node->values[0].type != FBX_INT)
            continue; /* not an object with an id */
        fbx_object *o = &s->objects[s->object_count++];
        o->id = node->values[0].i;
        o->node = node;
        fbx_object_name(node->value_count > 1 ? &node->values[1] : NULL, &o->name, &o->name_len);
        o->kind = object_kind(node);
        o->props = fbx_child(node, "Properties70");
        o->defaults = template_for(s, node);
        o->order = i;
        o->raw_node = -1;
        o->raw_material = -1;
        o->curve = -1;
    }
    qsort(s->objects, s->object_count, sizeof *s->objects, compare_objects);
    for (uint32_t i = 1; i < s->object_count; i++)
        if (s->objects[i].id == s->objects[i - 1].id)
            return fbx_fail_data(s, "two objects have this id", &s->objects[i]);

    const fbx_node *conns = fbx_child(&s->doc.root, "Connections");
    uint32_t m = conns ? conns->child_count : 0;
    s->up = calloc(m ? m : 1, sizeof *s->up);
    s->down = calloc(m ? m : 1, sizeof *s->down);
    if (!s->up || !s->down)
        return fbx_oom(s);
    for (uint32_t i = 0; i < m; i++) {
        const fbx_node *c = &conns->children[i];
        if (!fbx_named(c, "C") || c->value_count < 3)
            continue;
        int32_t child = find_object(s, fbx_int(c, 1)), parent = find_object(s, fbx_int(c, 2));
        if (child < 0 || parent < 0)
            continue; /* to the scene root (id 0) or to an object the file does not have */
        if (child == parent)
            return fbx_fail_data(s, "is connected to itself", &s->objects[child]);
        fbx_link *l = &s->up[s->link_count++];
        *l = (fbx_link){(uint32_t)child, (uint32_t)parent, i, NULL};
        if (fbx_str_is(c, 0, "OP") && c->value_count > 3 && c->values[3].type == FBX_STRING)
            l->prop = &c->values[3];
    }
    fbx_sort_links(s);
    return SINEW_OK;
}

void fbx_sort_links(scene *s)
{
    memcpy(s->down, s->up, s->link_count * sizeof *s->up);
    qsort(s->up, s->link_count, sizeof *s->up, compare_up);
    qsort(s->down, s->link_count, sizeof *s->down, compare_down);
    for (uint32_t i = 0; i < s->object_count; i++)
        s->objects[i].parent_count = s->objects[i].child_count = 0;
    for (uint32_t i = s->link_count; i-- > 0;) {
        fbx_object *c = &s->objects[s->up[i].child], *p = &s->objects[s->down[i].parent];
        c->first_parent = i;
        c->parent_count++;
        p->first_child = i;
        p->child_count++;
    }
}

/* The k-th parent / child link of an object. */
const fbx_link *fbx_parent_link(const scene *s, const fbx_object *o, uint32_t k)
{
    return &s->up[o->first_parent + k];
}

const fbx_link *fbx_child_link(const scene *s, const fbx_object *o, uint32_t k)
{
    return &s->down[o->first_child + k];
}

/* The first object of `kind` connected to `o` either way (child first), or NULL. */
fbx_object *fbx_linked(const scene *s, const fbx_object *o, int kind, bool children, bool parents)
{
    for (uint32_t k = 0; children && k < o->child_count; k++) {
        fbx_object *c = &s->objects[fbx_child_link(s, o, k)->child];
        if (c->kind == kind)
            return c;
    }
    for (uint32_t k = 0; parents && k < o->parent_count; k++) {
        fbx_object *p = &s->objects[fbx_parent_link(s, o, k)->parent];
        if (p->kind == kind)
            return p;
    }
    return NULL;
}

/* ---- properties ---------------------------------------------------------------------- */

/* A property of a Properties70 (`P: name, type, label, flags, values...`) or Properties60
 * (`Property: name, type, flags, values...`) block, or NULL. */
const fbx_node *fbx_find_p(const fbx_node *props, const char *name)
{
    /* the property's name (its first value) first: most children differ in length or first byte */
    size_t n = strlen(name);
    for (uint32_t i = 0; props && i < props->child_count; i++) {
        const fbx_node *p = &props->children[i];
        const fbx_value *v = p->value_count ? &p->values[0] : NULL;
        if (!v || v->type != FBX_STRING || v->count != n || (n && v->s[0] != name[0]) || memcmp(v->s, name, n) != 0)
            continue;
        if ((p->name_len == 1 && p->name[0] == 'P') || (p->name_len == 8 && memcmp(p->name, "Property", 8) == 0))
            return p;
    }
    return NULL;
}

/* Where a property's values start. */
static uint32_t p_first_value(const fbx_node *p)
{
    return fbx_named(p, "P") ? 4u : 3u;
}

static double p_num(const fbx_node *p, uint32_t k, double fallback)
{
    uint32_t at = p ? p_first_value(p) + k : 0;
    return p && p->value_count > at ? fbx_num(p, at) : fallback;
}

const fbx_node *fbx_prop(const fbx_object *o, const char *name)
{
    const fbx_node *p = fbx_find_p(o->props, name);
    return p ? p : fbx_find_p(o->defaults, name);
}

double fbx_prop_num(const fbx_object *o, const char *name, double fallback)
{
    return p_num(fbx_prop(o, name), 0, fallback);
}

const fbx_value *fbx_prop_string(const fbx_object *o, const char *name)
{
    const fbx_node *p = fbx_prop(o, name);
    uint32_t at = p ? p_first_value(p) : 0;
    return p && p->value_count > at && p->values[at].type == FBX_STRING ? &p->values[at] : NULL;
}

static void prop_vec3(const fbx_object *o, const char *name, double fallback, double out[3])
{
    const fbx_node *p = fbx_prop(o, name);
    for (uint32_t c = 0; c < 3; c++)
        out[c] = p_num(p, c, fallback);
}

static double global_num(const scene *s, const char *name, double fallback)
{
    return p_num(fbx_find_p(s->global_settings, name), 0, fallback);
}

/* Whole numbers read from a file's doubles. A cast of a double out of the target's range is
 * undefined, so this checks first: an int32, `fallback` when out of range or NaN. */
static int32_t file_int(double v, int32_t fallback)
{
    return v >= -2147483648.0 && v <= 2147483647.0 ? (int32_t)v : fallback;
}

static int32_t prop_int(const fbx_object *o, const char *name, int32_t fallback)
{
    return file_int(fbx_prop_num(o, name, fallback), fallback);
}

/* FBX 5.x models have no properties: their transform is the Default of each X, Y, Z channel
 * of their own Channel "Transform" (T, R, S). */
static void read_channel_defaults(const fbx_node *model, fbx_static *st)
{
    static const char *const trs[3] = {"T", "R", "S"}, *const axes[3] = {"X", "Y", "Z"};
    const fbx_node *transform = NULL;
    for (uint32_t k = 0; k < model->child_count && !transform; k++)
        if (fbx_named(&model->children[k], "Channel") && fbx_str_is(&model->children[k], 0, "Transform"))
            transform = &model->children[k];
    for (uint32_t k = 0; transform && k < transform->child_count; k++)
        for (int p = 0; p < 3; p++) {
            const fbx_node *ch = &transform->children[k];
            if (!fbx_named(ch, "Channel") || !fbx_str_is(ch, 0, trs[p]))
                continue;
            for (uint32_t j = 0; j < ch->child_count; j++)
                for (int a = 0; a < 3; a++) {
                    const fbx_node *def = fbx_child(&ch->children[j], "Default");
                    if (fbx_named(&ch->children[j], "Channel") && fbx_str_is(&ch->children[j], 0, axes[a]) && def &&
                        isfinite(fbx_num(def, 0)))
                        st->value[p][a] = fbx_num(def, 0);
                }
        }
}

/* A model's transform properties without animation, and its rotation order. */
static void read_statics(scene *s, uint32_t model)
{
    const fbx_object *o = &s->objects[model];
    fbx_static *st = &s->statics[model];
    for (int p = 0; p < P_COUNT; p++)
        prop_vec3(o, fbx_transform_props[p], p == P_SCALING ? 1.0 : 0.0, st->value[p]);
    st->order = prop_int(o, "RotationOrder", 0);
    if (s->legacy && !o->props)
        read_channel_defaults(o->node, st);
    euler_rotation(st->value[P_PRE_ROTATION], 0, st->pre);
    post_rotation_inverse(st->value[P_POST_ROTATION], st->post_inverse);
}

/* ---- animation ------------------------------------------------------------------------ */

int32_t fbx_add_curve(scene *s, const fbx_curve *c)
{
    if (s->curve_count == s->curve_capacity) {
        uint32_t cap = s->curve_capacity ? s->curve_capacity * 2 : 16;
        fbx_curve *grown = realloc(s->curves, cap * sizeof *grown);
        if (!grown)
            return -1;
        s->curves = grown;
        s->curve_capacity = cap;
    }
    s->curves[s->curve_count] = *c;
    return (int32_t)s->curve_count++;
}

bool fbx_add_binding(scene *s, const fbx_binding *b)
{
    if (s->binding_count == s->binding_capacity) {
        uint32_t cap = s->binding_capacity ? s->binding_capacity * 2 : 16;
        fbx_binding *grown = realloc(s->bindings, cap * sizeof *grown);
        if (!grown)
            return false;
        s->bindings = grown;
        s->binding_capacity = cap;
    }
    s->bindings[s->binding_count++] = *b;
    return true;
}

static int compare_bindings(const void *a, const void *b)
{
    const fbx_binding *x = a, *y = b;
    if (x->model != y->model)
        return x->model < y->model ? -1 : 1;
    if (x->stack != y->stack)
        return x->stack < y->stack ? -1 : 1;
    return x->index < y->index ? -1 : x->index > y->index;
}

void fbx_sort_bindings(scene *s)
{
    /* A model's bindings together, its layers in their stack's order (stable within a layer:
     * the index is unique a layer, and qsort keeps nothing else in order that matters). */
    if (s->binding_count)
        qsort(s->bindings, s->binding_count, sizeof *s->bindings, compare_bindings);
    for (uint32_t i = s->binding_count; i-- > 0;) {
        fbx_object *m = &s->objects[s->bindings[i].model];
        m->first_binding = i;
        m->binding_count++;
    }
}

/* The curve of each component of a curve node (-1 for none) and the node's values: d|Y and
 * d|Z are the second and third, any other (d|X, d|Weight, d|DeformPercent) the first. */
static void curve_node_curves(const scene *s, const fbx_object *cn, int32_t curves[3], double defaults[3])
{
    static const char *const comps[3] = {"d|X", "d|Y", "d|Z"};
    static const char *const short_comps[3] = {"X", "Y", "Z"};
    for (int c = 0; c < 3; c++) {
        curves[c] = -1;
        defaults[c] = fbx_prop_num(cn, comps[c], fbx_prop_num(cn, short_comps[c], NAN));
    }
    for (uint32_t k = 0; k < cn->child_count; k++) {
        const fbx_link *dl = fbx_child_link(s, cn, k);
        const fbx_object *co = &s->objects[dl->child];
        if (!dl->prop || co->kind != K_CURVE || co->curve < 0)
            continue;
        int c = fbx_value_is(dl->prop, "d|Y") || fbx_value_is(dl->prop, "Y")   ? 1
                : fbx_value_is(dl->prop, "d|Z") || fbx_value_is(dl->prop, "Z") ? 2
                                                                               : 0;
        if (c == 0 && isnan(defaults[0]) && dl->prop->type == FBX_STRING) {
            char name[256];
            snprintf(name, sizeof name, "%.*s", (int)dl->prop->count, dl->prop->s);
            defaults[0] = fbx_prop_num(cn, name, NAN);
        }
        if (s->curves[co->curve].count)
            curves[c] = co->curve;
    }
}

/* A layer's blend: BlendMode 0 additive, 1 override, 2 override-passthrough; its weight
 * (percent), and how rotations and scales accumulate (0: by layer, composed; 1: by channel,
 * added component by component). */
static fbx_layer layer_info(const fbx_object *o, uint32_t stack, uint32_t index)
{
    fbx_layer l = {.stack = stack, .index = index, .weight_curve = -1};
    switch (prop_int(o, "BlendMode", 0)) {
    case 0:
        l.additive = l.blended = true;
        break;
    case 2:
        l.blended = true;
        break;
    default:
        break;
    }
    l.weight = fmin(fmax(fbx_prop_num(o, "Weight", 100.0) / 100.0, 0.0), 1.0);
    if (l.weight > 0.99999)
        l.weight = 1.0;
    l.compose_rotation = prop_int(o, "RotationAccumulationMode", 0) == 0;
    l.compose_scale = prop_int(o, "ScaleAccumulationMode", 0) == 0;
    return l;
}

/* A stack's time span: LocalStart..LocalStop, else ReferenceStart..ReferenceStop. */
static void stack_info(const scene *s, const fbx_object *o, fbx_stack *st)
{
    const char *start = "LocalStart", *stop = "LocalStop";
    if (!fbx_prop(o, start) || !fbx_prop(o, stop))
        start = "ReferenceStart", stop = "ReferenceStop";
    st->name = o->name;
    st->name_len = o->name_len;
    st->start = fbx_prop_num(o, start, 0) / s->ticks_per_second;
    st->stop = fbx_prop_num(o, stop, 0) / s->ticks_per_second;
    st->order = o->order;
}

static int compare_stacks(const void *a, const void *b)
{
    const fbx_object *x = *(const fbx_object *const *)a, *y = *(const fbx_object *const *)b;
    return x->order < y->order ? -1 : x->order > y->order;
}

/* FBX 7.x: curves, stacks in the file's order with their layers in the order of their
 * connections, and each curve node that animates a transform property (or a layer's weight). */
static sinew_result index_animation(scene *s)
{
    sinew_result result;
    fbx_curve_source src = {s->doc.version, s->doc.binary, s->ticks_per_second, &s->doc.arena};
    uint32_t stack_count = 0;
    for (uint32_t i = 0; i < s->object_count; i++) {
        fbx_object *o = &s->objects[i];
        stack_count += o->kind == K_STACK;
        if (o->kind != K_CURVE)
            continue;
        fbx_curve c;
        const char *problem = fbx_curve_read(o->node, &src, &c);
        if (problem)
            return strcmp(problem, "out of memory") == 0 ? fbx_oom(s) : fbx_fail_data(s, problem, o);
        if ((o->curve = fbx_add_curve(s, &c)) < 0) {
            fbx_curve_free(&c);
            return fbx_oom(s);
        }
    }
    fbx_object **stacks = malloc((stack_count ? stack_count : 1) * sizeof *stacks);
    uint32_t *layer_of = malloc((s->object_count ? s->object_count : 1) * sizeof *layer_of);
    s->stacks = calloc(stack_count ? stack_count : 1, sizeof *s->stacks);
    s->layers = calloc(s->link_count ? s->link_count : 1, sizeof *s->layers);
    if (!stacks || !layer_of || !s->stacks || !s->layers) {
        free(stacks);
        free(layer_of);
        return fbx_oom(s);
    }
    uint32_t n = 0;
    for (uint32_t i = 0; i < s->object_count; i++) {
        layer_of[i] = UINT32_MAX;
        if (s->objects[i].kind == K_STACK)
            stacks[n++] = &s->objects[i];
    }
    if (n)
        qsort(stacks, n, sizeof *stacks, compare_stacks);
    for (uint32_t k = 0; k < n; k++) {
        fbx_stack *st = &s->stacks[s->stack_count++];
        stack_info(s, stacks[k], st);
        st->first_layer = s->layer_count;
        for (uint32_t c = 0; c < stacks[k]->child_count; c++) {
            uint32_t child = fbx_child_link(s, stacks[k], c)->child;
            if (s->objects[child].kind != K_LAYER || layer_of[child] != UINT32_MAX)
                continue;
            layer_of[child] = s->layer_count;
            s->layers[s->layer_count++] = layer_info(&s->objects[child], k, st->layer_count++);
        }
    }
    free(stacks);
    /* Curve node -> transform property of a model, or -> the weight of its own layer. */
    result = SINEW_OK;
    for (uint32_t i = 0; i < s->link_count && !result; i++) {
        const fbx_link *l = &s->up[i];
        const fbx_object *cn = &s->objects[l->child], *target = &s->objects[l->parent];
        if (!l->prop || cn->kind != K_CURVE_NODE)
            continue;
        const fbx_object *layer_object = fbx_linked(s, cn, K_LAYER, false, true);
        if (!layer_object || layer_of[layer_object - s->objects] == UINT32_MAX)
            continue;
        uint32_t layer = layer_of[layer_object - s->objects];
        fbx_binding b = {.model = l->parent,
                         .layer = layer,
                         .stack = s->layers[layer].stack,
                         .index = s->layers[layer].index,
                         .prop = -1};
        curve_node_curves(s, cn, b.curves, b.defaults);
        if (target->kind == K_LAYER && target == layer_object && fbx_value_is(l->prop, "Weight")) {
            s->layers[layer].weight_curve = b.curves[0];
            continue;
        }
        for (int p = 0; p < P_COUNT; p++)
            if (fbx_value_is(l->prop, fbx_transform_props[p]))
                b.prop = p;
        if (target->kind == K_BLEND_CHANNEL && fbx_value_is(l->prop, "DeformPercent"))
            b.prop = P_DEFORM_PERCENT;
        bool wanted = (b.prop >= 0 && b.prop < P_COUNT && target->kind == K_MODEL) || b.prop == P_DEFORM_PERCENT;
        if (wanted && !fbx_add_binding(s, &b))
            result = fbx_oom(s);
    }
    free(layer_of);
    return result;
}

/* The statics of every model. */
static sinew_result index_statics(scene *s)
{
    s->statics = calloc(s->object_count ? s->object_count : 1, sizeof *s->statics);
    if (!s->statics)
        return fbx_oom(s);
    for (uint32_t i = 0; i < s->object_count; i++)
        if (s->objects[i].kind == K_MODEL)
            read_statics(s, i);
    return SINEW_OK;
}

/* |v|^e keeping v's sign (scales composed by a layer's weight). */
static double pow_signed(double v, double e)
{
    if (e <= 0.0)
        return 1.0;
    if (e >= 1.0)
        return v;
    return v < 0 ? -pow(-v, e) : pow(v, e);
}

/* A layer's value `v` of property `prop` combined with what the layers below gave (`out`). */
static void combine_layer(const fbx_layer *l, double weight, int prop, int order, double out[3], const double v[3])
{
    bool rotation = prop == P_ROTATION && l->compose_rotation, scale = prop == P_SCALING && l->compose_scale;
    if (!l->blended) { /* override */
        memcpy(out, v, 3 * sizeof *out);
    } else if (l->additive) {
        if (scale) {
            for (int c = 0; c < 3; c++)
                out[c] *= pow_signed(v[c], weight);
        } else if (rotation) {
            double a[4], b[4], id[4] = {0, 0, 0, 1};
            euler_rotation(out, order, a);
            euler_rotation(v, order, b);
            quat_slerp(id, b, weight, b);
            quat_mul(a, b, a);
            quat_euler(a, order, out);
        } else {
            for (int c = 0; c < 3; c++)
                out[c] += v[c] * weight;
        }
    } else { /* override-passthrough: blend by the weight */
        if (scale) {
            for (int c = 0; c < 3; c++)
                out[c] = pow_signed(out[c], 1.0 - weight) * pow_signed(v[c], weight);
        } else if (rotation) {
            double a[4], b[4];
            euler_rotation(out, order, a);
            euler_rotation(v, order, b);
            quat_slerp(a, b, weight, a);
            quat_euler(a, order, out);
        } else {
            for (int c = 0; c < 3; c++)
                out[c] = out[c] * (1.0 - weight) + v[c] * weight;
        }
    }
}

/* A layer's weight at time t: its own curve (percent, blended layers only) or its value. */
static double layer_weight(const scene *s, const fbx_layer *l, double t, double clip_start)
{
    if (l->weight_curve < 0 || !l->blended)
        return l->weight;
    double w = fbx_curve_eval_at(&s->curves[l->weight_curve], t, clip_start, l->weight * 100.0) / 100.0;
    return w < 0 ? 0 : w > 0.99999 ? 1 : w;
}

/* A model's transform properties at time t (seconds) of `stack`, or without animation when
 * stack < 0: the first layer's curves replace the property, each later layer's combine with
 * them by its blend mode and weight. Keys are matched as the clip's float times starting at
 * `clip_start` see them (fbx_curve_eval_at). */
static void anim_values(const scene *s, uint32_t model, int32_t stack, double t, double clip_start,
                        double v[P_COUNT][3])
{
    const fbx_object *o = &s->objects[model];
    memcpy(v, s->statics[model].value, sizeof s->statics[model].value);
    if (stack < 0)
        return;
    for (uint32_t b = o->first_binding; b < o->first_binding + o->binding_count; b++) {
        const fbx_binding *bind = &s->bindings[b];
        if (bind->stack != (uint32_t)stack)
            continue;
        double *out = v[bind->prop], x[3];
        for (int c = 0; c < 3; c++) {
            double fallback = isnan(bind->defaults[c]) ? out[c] : bind->defaults[c];
            x[c] = bind->curves[c] >= 0 ? fbx_curve_eval_at(&s->curves[bind->curves[c]], t, clip_start, fallback)
                                        : fallback;
        }
        const fbx_layer *l = &s->layers[bind->layer];
        if (bind->index == 0)
            memcpy(out, x, sizeof x);
        else
            combine_layer(l, layer_weight(s, l, t, clip_start), bind->prop, s->statics[model].order, out, x);
    }
}

double fbx_animated_value(const scene *s, uint32_t o, int prop, int32_t stack, double t, double clip_start,
                          double value)
{
    const fbx_object *obj = &s->objects[o];
    double out[3] = {value, 0, 0};
    for (uint32_t b = obj->first_binding; stack >= 0 && b < obj->first_binding + obj->binding_count; b++) {
        const fbx_binding *bind = &s->bindings[b];
        if (bind->stack != (uint32_t)stack || bind->prop != prop)
            continue;
        double fallback = isnan(bind->defaults[0]) ? out[0] : bind->defaults[0];
        double x[3] = {bind->curves[0] >= 0 ? fbx_curve_eval_at(&s->curves[bind->curves[0]], t, clip_start, fallback)
                                            : fallback,
                       0, 0};
        const fbx_layer *l = &s->layers[bind->layer];
        if (bind->index == 0)
            out[0] = x[0];
        else
            combine_layer(l, layer_weight(s, l, t, clip_start), prop, 0, out, x);
    }
    return out[0];
}

/* ---- transforms ----------------------------------------------------------------------- */

typedef bake_trs local_trs; /* translation, rotation (x, y, z, w), scale, in doubles */

/* The quaternion of a pre-rotation (post: the inverse of a post-rotation) of `degrees`, the
 * node's static one made once where the value is it; false, and the identity, where it is 0. */
static bool pre_post_rotation(const fbx_static *st, const double degrees[3], bool post, double q[4])
{
    if (degrees[0] == 0 && degrees[1] == 0 && degrees[2] == 0) {
        q[0] = q[1] = q[2] = 0, q[3] = 1;
        return false;
    }
    int prop = post ? P_POST_ROTATION : P_PRE_ROTATION;
    if (memcmp(degrees, st->value[prop], sizeof st->value[0]) == 0)
        memcpy(q, post ? st->post_inverse : st->pre, 4 * sizeof *q);
    else if (post)
        post_rotation_inverse(degrees, q);
    else
        euler_rotation(degrees, 0, q);
    return true;
}

/* A node's local transform at time t (seconds) of `stack` (-1: the rest pose):
 * T * Roff * Rp * Rpre * R * Rpost^-1 * Rp^-1 * Soff * Sp * S * Sp^-1, which is exactly a
 * translation, the rotation Rpre * R * Rpost^-1 and the scale S. */
static void local_from_values(const scene *s, uint32_t model, const double v[P_COUNT][3], local_trs *out)
{
    const double *t = v[P_TRANSLATION], *r = v[P_ROTATION], *sc = v[P_SCALING], *roff = v[P_ROTATION_OFFSET];
    const double *rp = v[P_ROTATION_PIVOT], *soff = v[P_SCALING_OFFSET], *sp = v[P_SCALING_PIVOT];
    const double *pre = v[P_PRE_ROTATION], *post = v[P_POST_ROTATION];
    const fbx_static *st = &s->statics[model];
    /* the rotation as quaternions (Rpre R Rpost^-1): half the work of the matrices */
    double q[4];
    euler_rotation(r, st->order, q);
    double qpre[4], qpost[4];
    if (pre_post_rotation(st, pre, false, qpre))
        quat_mul(qpre, q, q);
    if (pre_post_rotation(st, post, true, qpost))
        quat_mul(q, qpost, q);
    quat_canonical(q);
    memcpy(out->q, q, sizeof q);
    double inner[3];
    for (int c = 0; c < 3; c++) {
        inner[c] = soff[c] + sp[c] - sc[c] * sp[c];
        out->t[c] = t[c] + roff[c] + rp[c];
        out->s[c] = sc[c];
    }
    /* pivots and offsets: the rotation applied to (inner - rp), where there are any */
    double d[3] = {inner[0] - rp[0], inner[1] - rp[1], inner[2] - rp[2]};
    if (d[0] != 0 || d[1] != 0 || d[2] != 0) {
        dmat rot = dmat_from_trs((double[3]){0, 0, 0}, q, (double[3]){1, 1, 1});
        for (int row = 0; row < 3; row++)
            out->t[row] += rot.m[row] * d[0] + rot.m[4 + row] * d[1] + rot.m[8 + row] * d[2];
    }
}

static void node_local(const scene *s, uint32_t model, int32_t stack, double t_seconds, double clip_start,
                       local_trs *out)
{
    double v[P_COUNT][3];
    anim_values(s, model, stack, t_seconds, clip_start, v);
    local_from_values(s, model, (const double(*)[3])v, out);
}

/* The geometric transform: applied to what a node carries, not to its children. */
static dmat geometric_matrix(const fbx_object *o)
{
    double t[3], r[3], sc[3];
    prop_vec3(o, "GeometricTranslation", 0, t);
    prop_vec3(o, "GeometricRotation", 0, r);
    prop_vec3(o, "GeometricScaling", 1, sc);
    dmat g = euler_matrix(r, 0);
    for (int c = 0; c < 3; c++)
        for (int row = 0; row < 3; row++)
            g.m[c * 4 + row] *= sc[c];
    for (int row = 0; row < 3; row++)
        g.m[12 + row] = t[row];
    return g;
}

static uint8_t inherit_type(const fbx_object *o)
{
    switch (prop_int(o, "InheritType", 1)) {
    case 0:
        return SINEW_INHERIT_COMPONENTWISE_SCALE; /* RrSs */
    case 2:
        return SINEW_INHERIT_IGNORE_PARENT_SCALE; /* Rrs */
    default:
        return SINEW_INHERIT_NORMAL; /* RSrs */
    }
}

/* ---- nodes ---------------------------------------------------------------------------- */

/* The model a model hangs under, or -1 for the scene root. */
static int32_t model_parent(const scene *s, const fbx_object *o)
{
    for (uint32_t k = 0; k < o->parent_count; k++) {
        const fbx_link *l = fbx_parent_link(s, o, k);
        if (!l->prop && s->objects[l->parent].kind == K_MODEL)
            return (int32_t)l->parent;
    }
    return -1;
}

static sinew_result add_node(scene *s, uint32_t object, int32_t parent)
{
    raw_model *m = s->model;
    fbx_object *o = &s->objects[object];
    uint32_t i = m->node_count++;
    o->raw_node = (int32_t)i;
    s->models[i] = object;
    m->node_names[i] = malloc(o->name_len + 1);
    if (!m->node_names[i])
        return fbx_oom(s);
    memcpy(m->node_names[i], o->name, o->name_len);
    m->node_names[i][o->name_len] = 0;
    m->node_parents[i] = parent;
    m->node_inherit[i] = parent > 0 ? inherit_type(o) : SINEW_INHERIT_NORMAL;
    local_trs l;
    node_local(s, object, -1, 0, 0, &l);
    sinew_transform *r = &m->node_rest[i];
    for (int c = 0; c < 3; c++) {
        r->translation[c] = (float)l.t[c];
        r->scale[c] = (float)l.s[c];
    }
    for (int c = 0; c < 4; c++)
        r->rotation[c] = (float)l.q[c];
    return SINEW_OK;
}

/* The file's axes (UpAxis, FrontAxis, CoordAxis with signs) and unit (UnitScaleFactor,
 * centimetres a unit) as one matrix to right-handed Y-up metres. */
static void conversion(scene *s)
{
    int up = file_int(global_num(s, "UpAxis", 1), -1), front = file_int(global_num(s, "FrontAxis", 2), -1);
    int coord = file_int(global_num(s, "CoordAxis", 0), -1);
    double up_sign = global_num(s, "UpAxisSign", 1) < 0 ? -1 : 1;
    double front_sign = global_num(s, "FrontAxisSign", 1) < 0 ? -1 : 1;
    double coord_sign = global_num(s, "CoordAxisSign", 1) < 0 ? -1 : 1;
    double unit = global_num(s, "UnitScaleFactor", 1.0) / 100.0;
    if (!(unit > 0) || !isfinite(unit))
        unit = 0.01;
    bool valid = up >= 0 && up < 3 && front >= 0 && front < 3 && coord >= 0 && coord < 3 && up != front &&
                 up != coord && front != coord;
    if (!valid) {
        raw_model_warn(s->model,
                       "%s: the file's axes (up %d, front %d, coord %d) are not three different axes; "
                       "taken as Y up",
                       s->path, up, front, coord);
        up = 1, front = 2, coord = 0, up_sign = front_sign = coord_sign = 1;
    }
    memset(&s->convert, 0, sizeof s->convert);
    /* Row r of the rotation is the file's axis that becomes X, Y, Z. */
    s->convert.m[coord * 4 + 0] = (float)(coord_sign * unit);
    s->convert.m[up * 4 + 1] = (float)(up_sign * unit);
    s->convert.m[front * 4 + 2] = (float)(front_sign * unit);
    s->convert.m[15] = 1;
}

static int compare_order(const void *a, const void *b, void *context)
{
    const scene *s = context;
    uint32_t x = s->objects[*(const uint32_t *)a].order, y = s->objects[*(const uint32_t *)b].order;
    return x < y ? -1 : x > y;
}

static sinew_result build_nodes(scene *s)
{
    raw_model *m = s->model;
    for (uint32_t i = 0; i < s->object_count; i++)
        s->model_count += s->objects[i].kind == K_MODEL;
    if (s->model_count + 1 > FBX_MAX_NODES)
        return fbx_fail_data(s, "more than a million nodes", NULL);
    uint32_t n = s->model_count + 1;
    m->node_names = calloc(n, sizeof *m->node_names);
    m->node_parents = calloc(n, sizeof *m->node_parents);
    m->node_rest = calloc(n, sizeof *m->node_rest);
    m->node_inherit = calloc(n, 1);
    s->models = malloc(n * sizeof *s->models);
    uint32_t *stack = malloc(n * sizeof *stack);
    if (!m->node_names || !m->node_parents || !m->node_rest || !m->node_inherit || !s->models || !stack) {
        free(stack);
        return fbx_oom(s);
    }
    /* Root: the conversion to Y-up metres. */
    m->node_count = 1;
    s->models[0] = UINT32_MAX;
    m->node_names[0] = raw_strdup("RootNode");
    m->node_parents[0] = -1;
    if (!m->node_names[0]) {
        free(stack);
        return fbx_oom(s);
    }
    sinew_mat4_decompose(&s->convert, &m->node_rest[0]);
    /* Depth first from the top-level models in the file's order, children in the order of
     * their connections (objects are sorted by id, which differs between a scene's ASCII and
     * binary files). */
    uint32_t *by_order = malloc((s->object_count ? s->object_count : 1) * sizeof *by_order);
    if (!by_order) {
        free(stack);
        return fbx_oom(s);
    }
    for (uint32_t i = 0; i < s->object_count; i++)
        by_order[i] = i;
    qsort_r(by_order, s->object_count, sizeof *by_order, compare_order, s);
    sinew_result result = SINEW_OK;
    for (uint32_t r = 0; r < s->object_count && !result; r++) {
        uint32_t i = by_order[r];
        fbx_object *o = &s->objects[i];
        if (o->kind != K_MODEL || model_parent(s, o) >= 0)
            continue;
        uint32_t top = 0;
        stack[top++] = i;
        while (top && !result) {
            uint32_t cur = stack[--top];
            if (s->objects[cur].raw_node >= 0 || m->node_count >= n)
                continue; /* connected to its parent twice */
            int32_t parent_model = model_parent(s, &s->objects[cur]);
            int32_t parent = parent_model >= 0 ? s->objects[parent_model].raw_node : 0;
            if ((result = add_node(s, cur, parent)))
                break;
            const fbx_object *co = &s->objects[cur];
            for (uint32_t k = co->child_count; k-- > 0;) {
                const fbx_link *l = fbx_child_link(s, co, k);
                fbx_object *child = &s->objects[l->child];
                if (!l->prop && child->kind == K_MODEL && child->raw_node < 0 &&
                    model_parent(s, child) == (int32_t)cur && top < n)
                    stack[top++] = l->child;
            }
        }
    }
    free(stack);
    free(by_order);
    if (result)
        return result;
    if (m->node_count != n) {
        for (uint32_t i = 0; i < s->object_count; i++)
            if (s->objects[i].kind == K_MODEL && s->objects[i].raw_node < 0)
                return fbx_fail_data(s, "is its own ancestor (the connections between models form a cycle)",
                                     &s->objects[i]);
    }
    return SINEW_OK;
}

/* The size of the rest pose: the diagonal of its node positions in the file's units (the
 * root's conversion left out), for the bake's tolerance; posed by the runtime itself, inherit
 * types and all. */
static sinew_result measure(scene *s)
{
    return raw_model_rest_diagonal(s->model, &s->diagonal) ? SINEW_OK : fbx_oom(s);
}

/* ---- meshes -------------------------------------------------------------------------- */

enum { MAP_NONE, MAP_CORNER, MAP_POINT, MAP_POLYGON, MAP_ALL };

typedef struct layer_map {
    int mapping;
    const double *data, *index;
    uint32_t data_count, index_count, width;
} layer_map;

static sinew_result layer_element(scene *s, const fbx_object *g, const char *element, const char *data_name,
                                  const char *index_name, uint32_t width, layer_map *out)
{
    memset(out, 0, sizeof *out);
    const fbx_node *e = fbx_child(g->node, element);
    if (!e)
        return SINEW_OK;
    const fbx_node *mapping = fbx_child(e, "MappingInformationType");
    const fbx_node *reference = fbx_child(e, "ReferenceInformationType");
    static const struct {
        const char *name;
        int mapping;
    } maps[] = {{"ByPolygonVertex", MAP_CORNER}, {"ByVertice", MAP_POINT},   {"ByVertex", MAP_POINT},
                {"ByControlPoint", MAP_POINT},   {"ByPolygon", MAP_POLYGON}, {"AllSame", MAP_ALL}};
    for (size_t i = 0; i < sizeof maps / sizeof maps[0]; i++)
        if (fbx_str_is(mapping, 0, maps[i].name))
            out->mapping = maps[i].mapping;
    if (out->mapping == MAP_NONE) {
        raw_model_warn(s->model, "%s: mesh \"%.*s\": %s has a mapping sinew does not read; ignored", s->path,
                       (int)g->name_len, g->name, element);
        return SINEW_OK;
    }
    out->data = fbx_array(e, data_name, &out->data_count);
    out->width = width;
    if (!fbx_str_is(reference, 0, "Direct") && index_name) {
        out->index = fbx_array(e, index_name, &out->index_count);
        if (!out->index && fbx_child(e, index_name) == NULL && strcmp(index_name, "NormalsIndex") == 0)
            out->index = fbx_array(e, "NormalIndex", &out->index_count);
    }
    if (!out->data && out->mapping != MAP_NONE) {
        raw_model_warn(s->model, "%s: mesh \"%.*s\": its %s has no %s; left out", s->path, (int)g->name_len, g->name,
                       element, data_name);
        memset(out, 0, sizeof *out);
    }
    return SINEW_OK;
}

/* The element of a layer at one polygon corner, or -1 when the layer gives none. */
static int64_t layer_at(const layer_map *l, uint32_t corner, uint32_t point, uint32_t polygon, bool *bad)
{
    if (l->mapping == MAP_NONE)
        return -1;
    uint32_t i = l->mapping == MAP_CORNER    ? corner
                 : l->mapping == MAP_POINT   ? point
                 : l->mapping == MAP_POLYGON ? polygon
                                             : 0;
    int64_t e = i;
    if (l->index) {
        if (i >= l->index_count) {
            *bad = true;
            return -1;
        }
        double v = l->index[i];
        if (v < 0)
            return -1;
        if (!(v <= UINT32_MAX)) {
            *bad = true;
            return -1;
        }
        e = (int64_t)v;
    }
    if (l->width && ((uint64_t)e + 1) * l->width > l->data_count) {
        *bad = true;
        return -1;
    }
    return e;
}

typedef struct corner {
    uint32_t point;
    uint32_t polygon;
    int32_t material;
    float normal[3], uv[2], tangent[4], color[4]; /* contiguous: hashed and compared together (13 words) */
} corner;
_Static_assert(offsetof(corner, color) + sizeof(float[4]) - offsetof(corner, normal) == 52,
               "corner_hash reads the attributes as 13 words");

typedef struct vertex_table {
    uint32_t *slots; /* vertex index + 1, 0 empty */
    uint32_t capacity;
} vertex_table;

/* FNV-1a over the attributes' 32-bit words in 64 bits, then MurmurHash3's finaliser so that
 * the low bits the table uses depend on every word (a byte at a time cost a tenth of arnaud.fbx's
 * import). */
static uint32_t corner_hash(const corner *c)
{
    uint64_t h = 14695981039346656037u;
    uint32_t w[13];
    memcpy(w, c->normal, sizeof w);
    int words = (w[9] | w[10] | w[11] | w[12]) ? 13 : 9; /* a mesh without colours: 9 words, as before */
    for (int i = 0; i < words; i++)
        h = (h ^ w[i]) * 1099511628211u;
    h = (h ^ c->point) * 1099511628211u;
    h ^= h >> 33;
    h *= 0xff51afd7ed558ccdu;
    h ^= h >> 33;
    return (uint32_t)h;
}

static bool corner_same(const corner *a, const corner *b)
{
    return a->point == b->point && memcmp(a->normal, b->normal, sizeof a->normal) == 0 &&
           memcmp(a->uv, b->uv, sizeof a->uv) == 0 && memcmp(a->tangent, b->tangent, sizeof a->tangent) == 0 &&
           memcmp(a->color, b->color, sizeof a->color) == 0;
}

/* A corner's tangent from the tangent layer, its handedness from the binormal layer: +1 when
 * normal x tangent points along the binormal (FBX's binormal follows +v, as sinew's
 * bitangent does), -1 when against it, +1 without binormals. */
static void corner_tangent(corner *c, const layer_map *tangents, const layer_map *binormals, uint32_t i,
                           uint32_t polygon, bool *bad)
{
    int64_t e = layer_at(tangents, i, c->point, polygon, bad);
    for (int k = 0; e >= 0 && k < 3; k++)
        c->tangent[k] = (float)tangents->data[e * 3 + k];
    c->tangent[3] = 1.0f;
    e = binormals->mapping == MAP_NONE ? -1 : layer_at(binormals, i, c->point, polygon, bad);
    if (e < 0)
        return;
    const float *n = c->normal, *t = c->tangent;
    const double *b = &binormals->data[e * 3];
    double nxt[3] = {n[1] * t[2] - n[2] * t[1], n[2] * t[0] - n[0] * t[2], n[0] * t[1] - n[1] * t[0]};
    if (nxt[0] * b[0] + nxt[1] * b[1] + nxt[2] * b[2] < 0.0)
        c->tangent[3] = -1.0f;
}

/* The polygon corners of a mesh with their attributes (triangle fans come later). */
typedef struct mesh_source {
    const fbx_object *geometry;
    const double *points;
    uint32_t point_count;
    uint32_t corner_count, polygon_count;
    corner *corners;
    uint32_t *polygon_start; /* polygon_count + 1 */
    bool normals, uvs, tangents, colors;
} mesh_source;

static sinew_result read_polygons(scene *s, const fbx_object *g, mesh_source *src)
{
    memset(src, 0, sizeof *src);
    src->geometry = g;
    uint32_t n = 0, idx_count = 0;
    src->points = fbx_array(g->node, "Vertices", &n);
    if (n % 3)
        return fbx_fail_data(s, "mesh's vertex array is not a whole number of points", g);
    src->point_count = n / 3;
    for (uint32_t i = 0; i < n; i++)
        if (!isfinite(src->points[i]))
            return fbx_fail_data(s, "mesh has a vertex that is not finite", g);
    const double *idx = fbx_array(g->node, "PolygonVertexIndex", &idx_count);
    layer_map normals, uvs, materials, tangents, binormals, colors;
    sinew_result result;
    if ((result = layer_element(s, g, "LayerElementNormal", "Normals", "NormalsIndex", 3, &normals)) ||
        (result = layer_element(s, g, "LayerElementColor", "Colors", "ColorIndex", 4, &colors)) ||
        (result = layer_element(s, g, "LayerElementUV", "UV", "UVIndex", 2, &uvs)) ||
        (result = layer_element(s, g, "LayerElementTangent", "Tangents", "TangentsIndex", 3, &tangents)) ||
        (result = layer_element(s, g, "LayerElementBinormal", "Binormals", "BinormalsIndex", 3, &binormals)) ||
        (result = layer_element(s, g, "LayerElementMaterial", "Materials", NULL, 1, &materials)))
        return result;
    src->normals = normals.mapping != MAP_NONE;
    src->uvs = uvs.mapping != MAP_NONE;
    src->tangents = tangents.mapping != MAP_NONE && src->normals;
    src->colors = colors.mapping != MAP_NONE;
    src->corners = import_large_alloc((idx_count ? idx_count : 1) * sizeof *src->corners, IMPORT_PAGES_MIN);
    src->polygon_start = malloc((idx_count + 1) * sizeof *src->polygon_start);
    if (!src->corners || !src->polygon_start)
        return fbx_oom(s);
    uint32_t polygon = 0, start = 0;
    bool bad = false;
    for (uint32_t i = 0; i < idx_count; i++) {
        double v = idx[i];
        bool last = v < 0;
        int64_t point = !(fabs(v) <= UINT32_MAX) ? -1 : last ? -(int64_t)v - 1 : (int64_t)v;
        if (point < 0 || point >= src->point_count)
            return fbx_fail_data(s, "mesh has a polygon corner outside its vertex array", g);
        corner *c = &src->corners[i];
        memset(c, 0, sizeof *c);
        c->point = (uint32_t)point;
        c->polygon = polygon;
        int64_t e = layer_at(&normals, i, c->point, polygon, &bad);
        for (int k = 0; e >= 0 && k < 3; k++)
            c->normal[k] = (float)normals.data[e * 3 + k];
        e = layer_at(&uvs, i, c->point, polygon, &bad);
        for (int k = 0; e >= 0 && k < 2; k++)
            c->uv[k] = (float)uvs.data[e * 2 + k];
        e = src->colors ? layer_at(&colors, i, c->point, polygon, &bad) : -1;
        for (int k = 0; e >= 0 && k < 4; k++)
            c->color[k] = (float)colors.data[e * 4 + k];
        if (src->tangents)
            corner_tangent(c, &tangents, &binormals, i, polygon, &bad);
        e = materials.mapping == MAP_NONE ? -1 : layer_at(&materials, i, c->point, polygon, &bad);
        c->material = e >= 0 ? file_int(materials.data[e], -1) : 0;
        if (bad)
            return fbx_fail_data(s, "mesh has a normal, UV, tangent, colour or material index outside its array", g);
        if (last) {
            src->polygon_start[polygon++] = start;
            start = i + 1;
        }
    }
    if (start != idx_count)
        return fbx_fail_data(s, "mesh's last polygon is not closed (its last index is not negative)", g);
    src->polygon_start[polygon] = start;
    src->polygon_count = polygon;
    src->corner_count = idx_count;
    return SINEW_OK;
}

static void mesh_source_free(mesh_source *src)
{
    free(src->corners);
    free(src->polygon_start);
}

/* The vertex of a corner in a growing mesh (appended when new). */
static int64_t vertex_of(vertex_table *t, const corner *c, corner *verts, uint32_t *count)
{
    uint32_t h = corner_hash(c) & (t->capacity - 1);
    for (;;) {
        uint32_t v = t->slots[h];
        if (v == 0) {
            verts[*count] = *c;
            t->slots[h] = ++*count;
            return *count - 1;
        }
        if (corner_same(&verts[v - 1], c))
            return v - 1;
        h = (h + 1) & (t->capacity - 1);
    }
}

typedef struct skin_source {
    uint32_t joint_count;
    uint32_t *joints;       /* raw nodes */
    dmat *geometry_to_bone; /* the cluster's Transform, per joint */
    uint32_t *first;        /* per point: first influence, point_count + 1 */
    uint32_t *slot;         /* influence -> joint slot */
    float *weight;
    uint32_t max_influences;
} skin_source;

static void skin_source_free(skin_source *k)
{
    free(k->joints);
    free(k->geometry_to_bone);
    free(k->first);
    free(k->slot);
    free(k->weight);
    memset(k, 0, sizeof *k);
}

static bool read_matrix(const fbx_object *o, const char *name, dmat *out)
{
    uint32_t n = 0;
    const double *a = fbx_array(o->node, name, &n);
    if (!a || n != 16)
        return false;
    for (int i = 0; i < 16; i++)
        if (!isfinite(a[i]))
            return false;
    memcpy(out->m, a, sizeof out->m);
    return true;
}

/* The world matrix (file units and axes, the root's conversion left out) of every raw node
 * in the rest pose, made on first use; NULL when out of memory. */
static const sinew_mat4 *rest_worlds(scene *s)
{
    if (s->rest_worlds)
        return s->rest_worlds;
    raw_model *m = s->model;
    sinew_transform *locals = malloc((m->node_count + 1) * sizeof *locals);
    s->rest_worlds = malloc((m->node_count + 1) * sizeof *s->rest_worlds);
    if (!locals || !s->rest_worlds) {
        free(locals);
        free(s->rest_worlds);
        return s->rest_worlds = NULL;
    }
    memcpy(locals, m->node_rest, m->node_count * sizeof *locals);
    locals[0] = (sinew_transform){{0, 0, 0}, {0, 0, 0, 1}, {1, 1, 1}};
    const sinew_model view = {.node_count = m->node_count,
                              .node_parents = m->node_parents,
                              .node_rest = m->node_rest,
                              .node_inherit = m->node_inherit};
    sinew_local_to_world(&view, locals, m->node_count, NULL, s->rest_worlds, m->node_count, NULL);
    free(locals);
    return s->rest_worlds;
}

/* A model's matrix in the scene's bind pose (Pose "BindPose", its PoseNode naming the model
 * by id, or by "Model::name" before FBX 7.0); false when no bind pose has it. */
static bool bind_pose_matrix(const scene *s, const fbx_object *model, dmat *out)
{
    const fbx_node *objects = fbx_child(&s->doc.root, "Objects");
    for (uint32_t i = 0; objects && i < objects->child_count; i++) {
        const fbx_node *pose = &objects->children[i];
        if (!fbx_named(pose, "Pose") || !fbx_str_is(fbx_child(pose, "Type"), 0, "BindPose"))
            continue;
        for (uint32_t j = 0; j < pose->child_count; j++) {
            const fbx_node *pn = &pose->children[j], *node = fbx_child(pn, "Node");
            if (!fbx_named(pn, "PoseNode") || !node || node->value_count == 0)
                continue;
            bool same = false;
            if (node->values[0].type == FBX_STRING) {
                const char *name;
                size_t len;
                fbx_object_name(&node->values[0], &name, &len);
                same = s->legacy && len == model->name_len && memcmp(name, model->name, len) == 0;
            } else {
                same = !s->legacy && fbx_int(node, 0) == model->id;
            }
            uint32_t n = 0;
            const double *m = fbx_array(pn, "Matrix", &n);
            if (!same || !m || n != 16)
                continue;
            for (int k = 0; k < 16; k++)
                out->m[k] = m[k];
            return true;
        }
    }
    return false;
}

/* A cluster's geometry-to-bone matrix: its Transform (the mesh's bind matrix in the bone's
 * space), else made from the bone's bind matrix (TransformLink, else the bind pose, else the
 * bone at rest) and the mesh node's world matrix at rest. False when out of memory. */
static bool cluster_bind(scene *s, const fbx_object *cl, const fbx_object *bone, const fbx_object *mesh_model,
                         dmat *out)
{
    if (read_matrix(cl, "Transform", out))
        return true;
    const sinew_mat4 *w = rest_worlds(s);
    if (!w)
        return false;
    dmat bone_world, mesh_world = dmat_identity();
    if (!read_matrix(cl, "TransformLink", &bone_world) && !bind_pose_matrix(s, bone, &bone_world))
        for (int k = 0; k < 16; k++)
            bone_world.m[k] = w[bone->raw_node].m[k];
    for (int k = 0; k < 16 && mesh_model->raw_node >= 0; k++)
        mesh_world.m[k] = w[mesh_model->raw_node].m[k];
    dmat inv = dmat_inverse_affine(&bone_world);
    *out = dmat_mul(&inv, &mesh_world);
    return true;
}

/* Influences of a skin deformer on a geometry of `model`: every cluster's bone and weights.
 * Points that no cluster weighs (or only with zero) follow the model itself, as the
 * authoring tools leave them: an extra joint, the model's node. */
static sinew_result read_skin(scene *s, const fbx_object *skin, const fbx_object *model, uint32_t point_count,
                              skin_source *k)
{
    memset(k, 0, sizeof *k);
    uint32_t clusters = 0;
    for (uint32_t c = 0; c < skin->child_count; c++)
        clusters += s->objects[fbx_child_link(s, skin, c)->child].kind == K_CLUSTER;
    k->joints = calloc(clusters + 1u, sizeof *k->joints);
    k->geometry_to_bone = calloc(clusters + 1u, sizeof *k->geometry_to_bone);
    k->first = calloc(point_count + 1u, sizeof *k->first);
    double *sum = calloc(point_count + 1u, sizeof *sum);
    if (!k->joints || !k->geometry_to_bone || !k->first || !sum) {
        free(sum);
        return fbx_oom(s);
    }
    uint64_t total = 0;
    uint32_t unweighted = 0, extra = UINT32_MAX;
    sinew_result result = SINEW_OK;
    /* Two passes over the clusters: count a point's influences, then place them. */
    for (int pass = 0; pass < 2 && !result; pass++) {
        uint32_t slot = 0;
        for (uint32_t c = 0; c < skin->child_count && !result; c++) {
            const fbx_object *cl = &s->objects[fbx_child_link(s, skin, c)->child];
            if (cl->kind != K_CLUSTER)
                continue;
            const fbx_object *bone = fbx_linked(s, cl, K_MODEL, true, true);
            uint32_t ni = 0, nw = 0;
            const double *idx = fbx_array(cl->node, "Indexes", &ni);
            const double *w = fbx_array(cl->node, "Weights", &nw);
            if (!bone || bone->raw_node < 0)
                continue;
            if (ni != nw) {
                result = fbx_fail_data(s, "cluster has another number of weights than of indices", cl);
                break;
            }
            if (pass == 0) {
                if (!cluster_bind(s, cl, bone, model, &k->geometry_to_bone[slot])) {
                    result = fbx_oom(s);
                    break;
                }
                k->joints[slot] = (uint32_t)bone->raw_node;
            }
            for (uint32_t i = 0; i < ni; i++) {
                double p = idx[i];
                if (!(p >= 0 && p < point_count) || !isfinite(w[i])) {
                    result = fbx_fail_data(
                        s, "cluster has a vertex index outside its mesh or a weight that is not finite", cl);
                    break;
                }
                uint32_t pt = (uint32_t)p;
                if (pass == 0) {
                    k->first[pt + 1]++;
                    sum[pt] += w[i];
                    total++;
                } else {
                    uint32_t at = k->first[pt]++;
                    k->slot[at] = slot;
                    k->weight[at] = (float)w[i];
                }
            }
            slot++;
        }
        if (result)
            break;
        if (pass == 0) {
            for (uint32_t p = 0; p < point_count; p++)
                unweighted += !(sum[p] > 0);
            if (unweighted && model->raw_node >= 0) {
                extra = slot;
                k->joints[slot] = (uint32_t)model->raw_node;
                k->geometry_to_bone[slot++] = dmat_identity();
                total += unweighted;
                for (uint32_t p = 0; p < point_count; p++)
                    k->first[p + 1] += !(sum[p] > 0);
            }
            if (total > UINT32_MAX / 2) {
                result = fbx_fail_data(s, "skin has too many influences", skin);
                break;
            }
            for (uint32_t p = 0; p < point_count; p++) {
                if (k->first[p + 1] > k->max_influences)
                    k->max_influences = k->first[p + 1];
                k->first[p + 1] += k->first[p];
            }
            k->slot = malloc((total ? total : 1) * sizeof *k->slot);
            k->weight = malloc((total ? total : 1) * sizeof *k->weight);
            if (!k->slot || !k->weight)
                result = fbx_oom(s);
            k->joint_count = slot;
        } else if (extra != UINT32_MAX) {
            for (uint32_t p = 0; p < point_count; p++)
                if (!(sum[p] > 0)) {
                    uint32_t at = k->first[p]++;
                    k->slot[at] = extra;
                    k->weight[at] = 1.0f;
                }
        }
    }
    free(sum);
    if (result)
        return result;
    /* The second pass moved each start to the next point's start: shift back. */
    for (uint32_t p = point_count; p > 0; p--)
        k->first[p] = k->first[p - 1];
    k->first[0] = 0;
    return SINEW_OK;
}

/* Material of a model's material slot as a raw material index (made on first use). */
static int32_t material_of(scene *s, const fbx_object *model, int32_t slot)
{
    int32_t seen = 0;
    for (uint32_t k = 0; k < model->child_count; k++) {
        fbx_object *mat = &s->objects[fbx_child_link(s, model, k)->child];
        if (mat->kind != K_MATERIAL)
            continue;
        if (seen++ != slot)
            continue;
        return mat->raw_material;
    }
    return -1;
}

/* A texture's file: each of its file names as written, then each by its name beside the model
 * (FBX files often keep the path of the machine that wrote them). `warn`: say so when none is
 * found (not when the file embeds the image). */
static char *resolve_texture(scene *s, const fbx_object *tex, bool warn)
{
    static const char *const names[] = {"RelativeFilename", "FileName", "Filename"};
    char first[8192] = "", looked[8192];
    for (int by_name = 0; by_name < 2; by_name++)
        for (size_t i = 0; i < sizeof names / sizeof names[0]; i++) {
            const fbx_node *n = fbx_child(tex->node, names[i]);
            if (!n || n->value_count < 1 || n->values[0].type != FBX_STRING || n->values[0].count == 0)
                continue;
            char name[2048];
            snprintf(name, sizeof name, "%.*s", (int)n->values[0].count, n->values[0].s);
            char *path = import_find_texture(s->path, name, by_name, looked, sizeof looked);
            if (path)
                return path;
            if (!first[0])
                snprintf(first, sizeof first, "%s", name);
        }
    if (first[0] && warn)
        raw_model_warn(s->model, "%s: texture \"%s\" not found (looked beside the file too)", s->path, first);
    return NULL;
}

/* A texture's image embedded in the file (its Video's `Content`: the bytes in binary files,
 * base64 in ASCII ones, in one or more pieces) into `out`; false when out of memory. Content
 * that is not base64 is left out with a warning. */
static bool embedded_image(scene *s, const fbx_node *content, const char *material, raw_texture *out)
{
    size_t total = 0;
    for (uint32_t v = 0; v < content->value_count; v++)
        total += content->values[v].type == FBX_STRING ? content->values[v].count : 0;
    unsigned char *bytes = malloc(total / 4 * 3 + total + 3), *text = bytes + total / 4 * 3 + 3;
    if (!bytes)
        return false;
    size_t n = 0;
    for (uint32_t v = 0; v < content->value_count; v++)
        if (content->values[v].type == FBX_STRING) {
            memcpy((s->doc.binary ? bytes : text) + n, content->values[v].s, content->values[v].count);
            n += content->values[v].count;
        }
    if (!s->doc.binary && (n = import_base64_decode((const char *)text, n, bytes)) == SIZE_MAX) {
        free(bytes);
        return raw_model_warn(s->model, "%s: material \"%s\": its embedded texture is not base64; left out", s->path,
                              material);
    }
    if (n == 0 || n > UINT32_MAX) {
        free(bytes);
        return true;
    }
    out->image = bytes;
    out->image_size = (uint32_t)n;
    return true;
}

static sinew_result build_materials(scene *s)
{
    raw_model *m = s->model;
    uint32_t count = 0;
    for (uint32_t i = 0; i < s->object_count; i++)
        count += s->objects[i].kind == K_MATERIAL;
    m->materials = calloc(count ? count : 1, sizeof *m->materials);
    if (!m->materials)
        return fbx_oom(s);
    for (uint32_t i = 0; i < s->object_count; i++) {
        fbx_object *o = &s->objects[i];
        if (o->kind != K_MATERIAL)
            continue;
        raw_material *r = &m->materials[m->material_count];
        o->raw_material = (int32_t)m->material_count++;
        r->name = malloc(o->name_len + 1);
        if (!r->name)
            return fbx_oom(s);
        memcpy(r->name, o->name, o->name_len);
        r->name[o->name_len] = 0;
        double color[3];
        prop_vec3(o, fbx_prop(o, "DiffuseColor") ? "DiffuseColor" : "Diffuse", 0.8, color);
        double factor = fbx_prop_num(o, "DiffuseFactor", 1.0), opacity = fbx_prop_num(o, "Opacity", 1.0);
        for (int c = 0; c < 3; c++)
            r->base_color[c] = (float)fmin(fmax(color[c] * factor, 0.0), 1.0);
        r->base_color[3] = (float)fmin(fmax(opacity, 0.0), 1.0);
        double emissive[3];
        prop_vec3(o, fbx_prop(o, "EmissiveColor") ? "EmissiveColor" : "Emissive", 0.0, emissive);
        double emissive_factor = fbx_prop_num(o, "EmissiveFactor", 1.0);
        for (int c = 0; c < 3; c++)
            r->emissive[c] = (float)fmax(emissive[c] * emissive_factor, 0.0);
        /* a Lambert material stores no exponent: no highlight, fully rough */
        bool shiny = fbx_prop(o, "ShininessExponent") || fbx_prop(o, "Shininess");
        r->roughness = shiny ? import_roughness_of_shininess(
                                   fbx_prop_num(o, "ShininessExponent", fbx_prop_num(o, "Shininess", 20.0)))
                             : 1.0f;
        /* textures by the property they drive (a "Bump" is a height map, which sinew does not read) */
        static const char *const slots[SINEW_MAP_COUNT] = {[SINEW_MAP_BASE_COLOR] = "DiffuseColor",
                                                           [SINEW_MAP_NORMAL] = "NormalMap",
                                                           [SINEW_MAP_EMISSIVE] = "EmissiveColor"};
        for (uint32_t k = 0; k < o->child_count; k++) {
            const fbx_link *l = fbx_child_link(s, o, k);
            const fbx_object *tex = &s->objects[l->child];
            int slot = -1;
            for (int q = 0; q < SINEW_MAP_COUNT && slot < 0 && tex->kind == K_TEXTURE; q++)
                if (slots[q] && fbx_value_is(l->prop, slots[q]))
                    slot = q;
            if (slot < 0 || r->maps[slot].path)
                continue;
            const fbx_object *video = fbx_linked(s, tex, K_VIDEO, true, true);
            uint32_t content = 0;
            const fbx_node *c = video ? fbx_child(video->node, "Content") : NULL;
            for (uint32_t v = 0; c && v < c->value_count; v++)
                content += c->values[v].type == FBX_STRING ? c->values[v].count : 0;
            r->maps[slot].path = resolve_texture(s, tex, content == 0);
            if (!r->maps[slot].path && content && !embedded_image(s, c, r->name, &r->maps[slot]))
                return fbx_oom(s);
        }
    }
    return SINEW_OK;
}

static sinew_result grow(scene *s, void **array, uint32_t count, size_t elem)
{
    if ((count & (count - 1)) == 0) { /* powers of two: double */
        void *p = realloc(*array, (count ? count * 2 : 1) * elem);
        if (!p)
            return fbx_oom(s);
        *array = p;
    }
    return SINEW_OK;
}

/* One raw mesh of the polygons of `src` that use material slot `slot`. */
static sinew_result emit_mesh(scene *s, const mesh_source *src, const fbx_object *model, int32_t slot,
                              const dmat *geometry, const skin_source *skin, int32_t skin_index,
                              const fbx_deform *deform)
{
    raw_model *m = s->model;
    sinew_result result;
    if ((result = grow(s, (void **)&m->meshes, m->mesh_count, sizeof *m->meshes)))
        return result;
    raw_mesh *mesh = &m->meshes[m->mesh_count++];
    memset(mesh, 0, sizeof *mesh);
    mesh->skin = skin_index;
    mesh->material = material_of(s, model, slot);
    mesh->name = malloc(src->geometry->name_len + model->name_len + 24);
    if (!mesh->name)
        return fbx_oom(s);
    const fbx_object *g = src->geometry;
    if (g->name_len)
        sprintf(mesh->name, "%.*s", (int)g->name_len, g->name);
    else
        sprintf(mesh->name, "%.*s", (int)model->name_len, model->name);
    if (slot > 0)
        sprintf(mesh->name + strlen(mesh->name), " (material %d)", slot);
    uint32_t triangles = 0;
    for (uint32_t p = 0; p < src->polygon_count; p++) {
        uint32_t n = src->polygon_start[p + 1] - src->polygon_start[p];
        if (n >= 3 && src->corners[src->polygon_start[p]].material == slot)
            triangles += n - 2;
    }
    if ((uint64_t)triangles * 3 > UINT32_MAX / 2)
        return fbx_fail_data(s, "mesh has too many triangles", g);
    corner *verts = import_large_alloc((triangles ? triangles * 3 : 1) * sizeof *verts, IMPORT_PAGES_MIN);
    vertex_table table = {0};
    table.capacity = 16;
    while (table.capacity < triangles * 6)
        table.capacity *= 2;
    table.slots = calloc(table.capacity, sizeof *table.slots);
    mesh->indices = malloc((triangles ? triangles * 3 : 1) * sizeof *mesh->indices);
    if (!verts || !table.slots || !mesh->indices) {
        free(verts);
        free(table.slots);
        return fbx_oom(s);
    }
    uint32_t vcount = 0;
    for (uint32_t p = 0; p < src->polygon_count; p++) {
        uint32_t a = src->polygon_start[p], n = src->polygon_start[p + 1] - a;
        if (n < 3 || src->corners[a].material != slot)
            continue;
        for (uint32_t k = 1; k + 1 < n; k++) {
            uint32_t tri[3] = {a, a + k, a + k + 1};
            for (int c = 0; c < 3; c++)
                mesh->indices[mesh->index_count++] = (uint32_t)vertex_of(&table, &src->corners[tri[c]], verts, &vcount);
        }
    }
    free(table.slots);
    mesh->vertex_count = vcount;
    mesh->positions = malloc((vcount ? vcount : 1) * 3 * sizeof(float));
    mesh->normals = src->normals ? malloc((vcount ? vcount : 1) * 3 * sizeof(float)) : NULL;
    mesh->uvs = src->uvs ? malloc((vcount ? vcount : 1) * 2 * sizeof(float)) : NULL;
    mesh->tangents = src->tangents ? malloc((vcount ? vcount : 1) * 4 * sizeof(float)) : NULL;
    mesh->colors = src->colors ? malloc((vcount ? vcount : 1) * 4 * sizeof(float)) : NULL;
    if (!mesh->positions || (src->normals && !mesh->normals) || (src->uvs && !mesh->uvs) ||
        (src->tangents && !mesh->tangents) || (src->colors && !mesh->colors)) {
        free(verts);
        return fbx_oom(s);
    }
    /* Rigid meshes carry the geometric transform in their vertices; skinned ones in their
     * inverse binds. Normals go through the inverse transpose (the direction of the runtime's
     * sign(det) * cofactor: right under non-uniform scale and mirrors). */
    dmat place = skin ? dmat_identity() : *geometry;
    dmat inverse = dmat_inverse_affine(&place);
    bool mirrored = dmat_det3(&place) < 0.0; /* turns the tangents' handedness */
    for (uint32_t v = 0; v < vcount; v++) {
        const corner *c = &verts[v];
        double p[3], q[3];
        memcpy(p, &src->points[c->point * 3], sizeof p);
        dmat_point(&place, p, q);
        for (int k = 0; k < 3; k++)
            mesh->positions[v * 3 + k] = (float)q[k];
        if (mesh->normals) {
            double n[3], len = 0;
            for (int r = 0; r < 3; r++) {
                n[r] = inverse.m[r * 4] * c->normal[0] + inverse.m[r * 4 + 1] * c->normal[1] +
                       inverse.m[r * 4 + 2] * c->normal[2];
                len += n[r] * n[r];
            }
            len = len > 0 ? sqrt(len) : 1;
            for (int r = 0; r < 3; r++)
                mesh->normals[v * 3 + r] = (float)(n[r] / len);
        }
        if (mesh->uvs) {
            mesh->uvs[v * 2] = c->uv[0];
            mesh->uvs[v * 2 + 1] = c->uv[1];
        }
        if (mesh->colors)
            memcpy(&mesh->colors[v * 4], c->color, sizeof c->color); /* sRGB: made linear below */
        if (mesh->tangents) { /* a direction on the surface: through the placement itself */
            double t[3], len = 0;
            for (int r = 0; r < 3; r++) {
                t[r] = place.m[r] * c->tangent[0] + place.m[4 + r] * c->tangent[1] + place.m[8 + r] * c->tangent[2];
                len += t[r] * t[r];
            }
            len = len > 0 ? sqrt(len) : 1;
            for (int r = 0; r < 3; r++)
                mesh->tangents[v * 4 + r] = (float)(t[r] / len);
            mesh->tangents[v * 4 + 3] = mirrored ? -c->tangent[3] : c->tangent[3];
        }
    }
    if (mesh->colors)
        raw_colors_from_srgb(mesh->colors, 4, vcount, mesh->colors);
    if (skin) {
        uint32_t k = skin->max_influences ? skin->max_influences : 1;
        mesh->influence_count = k;
        mesh->joints = calloc((size_t)vcount * k + 1, sizeof *mesh->joints);
        mesh->weights = calloc((size_t)vcount * k + 1, sizeof *mesh->weights);
        if (!mesh->joints || !mesh->weights) {
            free(verts);
            return fbx_oom(s);
        }
        for (uint32_t v = 0; v < vcount; v++) {
            uint32_t pt = verts[v].point, at = skin->first[pt], n = skin->first[pt + 1] - at;
            for (uint32_t i = 0; i < n; i++) {
                mesh->joints[v * k + i] = skin->slot[at + i];
                mesh->weights[v * k + i] = skin->weight[at + i];
            }
        }
    }
    /* blend shapes, DQ weights and the vertex cache, by each vertex's control point */
    uint32_t *points = malloc((vcount ? vcount : 1) * sizeof *points);
    if (!points) {
        free(verts);
        return fbx_oom(s);
    }
    for (uint32_t v = 0; v < vcount; v++)
        points[v] = verts[v].point;
    free(verts);
    result = fbx_deform_emit(s, deform, points, &place, mesh);
    free(points);
    if (result)
        return result;
    if ((result = grow(s, (void **)&m->instances, m->instance_count, sizeof *m->instances)))
        return result;
    uint32_t first = deform->first_channel >= 0 ? (uint32_t)deform->first_channel : 0;
    m->instances[m->instance_count++] = (sinew_instance){m->mesh_count - 1, (uint32_t)model->raw_node, first};
    return SINEW_OK;
}

static sinew_result add_skin(scene *s, const skin_source *k, const dmat *geometry, uint32_t blend, int32_t *out)
{
    raw_model *m = s->model;
    sinew_result result;
    if ((result = grow(s, (void **)&m->skins, m->skin_count, sizeof *m->skins)))
        return result;
    raw_skin *rs = &m->skins[m->skin_count++];
    memset(rs, 0, sizeof *rs);
    rs->joint_count = k->joint_count;
    rs->blend = blend;
    rs->joints = malloc((k->joint_count ? k->joint_count : 1) * sizeof *rs->joints);
    rs->inverse_bind = malloc((k->joint_count ? k->joint_count : 1) * sizeof *rs->inverse_bind);
    if (!rs->joints || !rs->inverse_bind)
        return fbx_oom(s);
    for (uint32_t j = 0; j < k->joint_count; j++) {
        rs->joints[j] = k->joints[j];
        dmat ib = dmat_mul(&k->geometry_to_bone[j], geometry);
        dmat_to_float(&ib, &rs->inverse_bind[j]);
    }
    *out = (int32_t)m->skin_count - 1;
    return SINEW_OK;
}

static int compare_int32(const void *a, const void *b)
{
    int32_t x = *(const int32_t *)a, y = *(const int32_t *)b;
    return x < y ? -1 : x > y;
}

/* The distinct material slots (>= 0) of the polygons of three corners or more, ascending;
 * NULL when out of memory. */
static int32_t *used_slots(const mesh_source *src, uint32_t *count)
{
    int32_t *slots = malloc((src->polygon_count ? src->polygon_count : 1) * sizeof *slots);
    uint32_t n = 0;
    for (uint32_t p = 0; slots && p < src->polygon_count; p++) {
        int32_t slot = src->corners[src->polygon_start[p]].material;
        /* runs of one slot once: polygons come grouped by material (sorting every polygon's
         * slot was 7% of arnaud.fbx's import) */
        if (slot >= 0 && src->polygon_start[p + 1] - src->polygon_start[p] >= 3 && (n == 0 || slots[n - 1] != slot))
            slots[n++] = slot;
    }
    if (slots)
        qsort(slots, n, sizeof *slots, compare_int32);
    uint32_t unique = 0;
    for (uint32_t i = 0; i < n; i++)
        if (unique == 0 || slots[i] != slots[unique - 1])
            slots[unique++] = slots[i];
    *count = unique;
    return slots;
}

/* Every geometry a model carries: one mesh a material, skinned when a skin deforms it. */
static sinew_result build_model_meshes(scene *s, const fbx_object *model)
{
    dmat geometry = geometric_matrix(model);
    for (uint32_t k = 0; k < model->child_count; k++) {
        const fbx_object *g = &s->objects[fbx_child_link(s, model, k)->child];
        if (g->kind != K_GEOMETRY)
            continue;
        mesh_source src;
        skin_source skin = {0};
        fbx_deform deform = {.first_channel = -1};
        sinew_result result = read_polygons(s, g, &src);
        const fbx_object *deformer = result ? NULL : fbx_linked(s, g, K_SKIN, true, false);
        if (!result && deformer)
            result = read_skin(s, deformer, model, src.point_count, &skin);
        if (!result)
            result = fbx_deform_read(s, g, deformer, src.point_count, &deform);
        int32_t skin_index = -1;
        if (!result && deformer && skin.joint_count)
            result = add_skin(s, &skin, &geometry, deform.blend, &skin_index);
        /* The material slots that polygons use, ascending (not 0 to the largest, which a file
         * may give as two billion). */
        uint32_t slot_count = 0;
        int32_t *slots = result ? NULL : used_slots(&src, &slot_count);
        if (!result && !slots)
            result = fbx_oom(s);
        for (uint32_t i = 0; !result && i < slot_count; i++)
            result =
                emit_mesh(s, &src, model, slots[i], &geometry, skin_index >= 0 ? &skin : NULL, skin_index, &deform);
        free(slots);
        mesh_source_free(&src);
        skin_source_free(&skin);
        fbx_deform_free(&deform);
        if (result)
            return result;
    }
    return SINEW_OK;
}

static sinew_result build_meshes(scene *s)
{
    for (uint32_t i = 1; i < s->model->node_count; i++) {
        sinew_result result = build_model_meshes(s, &s->objects[s->models[i]]);
        if (result)
            return result;
    }
    return SINEW_OK;
}

/* ---- clips ---------------------------------------------------------------------------- */

/* The baker's view of a node: its exact local transform at clip time t (seconds). */
typedef struct bake_node {
    const scene *s;
    uint32_t model;
    int32_t stack;
    double start;
} bake_node;

static void bake_node_eval(const void *context, double t, bake_trs *out)
{
    const bake_node *n = context;
    node_local(n->s, n->model, n->stack, n->start + t, n->start, out);
}

/* The clip time of the node's key that the float clip time t stands for (fbx_curve_eval_at
 * takes a float-equal time as the key's), or t. */
static double bake_node_key_time(const void *context, double t)
{
    const bake_node *n = context;
    const fbx_object *o = &n->s->objects[n->model];
    for (uint32_t b = o->first_binding; b < o->first_binding + o->binding_count; b++) {
        const fbx_binding *bind = &n->s->bindings[b];
        for (int c = 0; bind->stack == (uint32_t)n->stack && c < 3; c++) {
            double k;
            if (bind->curves[c] >= 0 && fbx_curve_key_near(&n->s->curves[bind->curves[c]], n->start + t, n->start, &k))
                return k - n->start;
        }
    }
    return t;
}

/* The local transform of property values v + e * w, as ten numbers, its rotation on the side
 * of `near`'s. */
static void local_along(const bake_node *n, const double v[P_COUNT][3], const double w[P_COUNT][3], double e,
                        const double *near, double out[10])
{
    double x[P_COUNT][3];
    for (int p = 0; p < P_COUNT; p++)
        for (int c = 0; c < 3; c++)
            x[p][c] = v[p][c] + e * w[p][c];
    local_trs l;
    local_from_values(n->s, n->model, (const double(*)[3])x, &l);
    bake_trs_ten(&l, near, out);
}

/* The derivative of the local transform along property slopes w (per second): the transform
 * is a smooth function of the property values, so a central difference over a small step of
 * the values is exact to rounding (differences in time would carry the curves' kinks). */
static void local_derivative(const bake_node *n, const double v[P_COUNT][3], const double w[P_COUNT][3],
                             const double *near, double out[10])
{
    double size = 0;
    for (int p = 0; p < P_COUNT; p++)
        for (int c = 0; c < 3; c++)
            size = fmax(size, fabs(w[p][c]));
    if (!(size > 0)) {
        memset(out, 0, 10 * sizeof *out);
        return;
    }
    double e = 1e-4 / size, plus[10], minus[10]; /* a step of 1e-4 in the fastest value */
    local_along(n, v, w, e, near, plus);
    local_along(n, v, w, -e, near, minus);
    for (int c = 0; c < 10; c++)
        out[c] = (plus[c] - minus[c]) / (2 * e);
}

/* The derivatives of the local transform along the property slopes w[0] and w[1] (per second),
 * worked out where only translation, rotation and scaling move and the translation does not
 * turn with the rotation or grow with the scale (no pivots or offsets that differ: nearly every
 * animated node); false elsewhere. The rotation's derivative is the sum of each Euler axis's,
 * an axis's half-angle quaternion (sin h, cos h) having (cos h, -sin h) * pi/360 a degree;
 * `value` gives the sign the rotation was put on. One pass serves both sides, where
 * local_derivative's differences evaluate the transform twice a side. */
static bool local_derivative_exact(const bake_node *n, const double v[P_COUNT][3], const double w[2][P_COUNT][3],
                                   bool make, const double *near, double value[10], double out[2][10])
{
    for (int side = 0; side < 2; side++)
        for (int p = P_ROTATION_OFFSET; p < P_COUNT; p++)
            if (w[side][p][0] != 0 || w[side][p][1] != 0 || w[side][p][2] != 0)
                return false;
    const double *sp = v[P_SCALING_PIVOT], *soff = v[P_SCALING_OFFSET], *rp = v[P_ROTATION_PIVOT];
    for (int c = 0; c < 3; c++)
        if (sp[c] != 0 || soff[c] != rp[c])
            return false;
    const fbx_static *st = &n->s->statics[n->model];
    const int *axes = euler_axes(st->order);
    /* each axis's quaternion e[k] and its derivative de[k] (a degree), in the order applied */
    double e[3][4], de[3][4];
    for (int k = 0; k < 3; k++) {
        int i = axes[k];
        double half = v[P_ROTATION][i] * (M_PI / 360.0), c = cos(half), sn = sin(half);
        memset(e[k], 0, sizeof e[k]);
        memset(de[k], 0, sizeof de[k]);
        e[k][i] = sn, e[k][3] = c;
        de[k][i] = c * (M_PI / 360.0), de[k][3] = -sn * (M_PI / 360.0);
    }
    /* q = pre * e2 e1 e0 * post^-1 and its partial derivatives by the three angles */
    double pre[4], post[4], q[4], partial[3][4];
    pre_post_rotation(st, v[P_PRE_ROTATION], false, pre);
    pre_post_rotation(st, v[P_POST_ROTATION], true, post);
    for (int k = -1; k < 3; k++) {
        double *r = k < 0 ? q : partial[k];
        memcpy(r, pre, sizeof pre);
        for (int f = 2; f >= 0; f--)
            quat_mul(r, f == k ? de[f] : e[f], r);
        quat_mul(r, post, r);
    }
    if (make) { /* the transform itself, as local_from_values makes it where nothing turns the translation */
        local_trs l;
        memcpy(l.q, q, sizeof q);
        quat_canonical(l.q);
        for (int c = 0; c < 3; c++) {
            l.t[c] = v[P_TRANSLATION][c] + v[P_ROTATION_OFFSET][c] + rp[c];
            l.s[c] = v[P_SCALING][c];
        }
        bake_trs_ten(&l, near, value);
    }
    double sign = q[0] * value[3] + q[1] * value[4] + q[2] * value[5] + q[3] * value[6] < 0 ? -1.0 : 1.0;
    for (int side = 0; side < 2; side++) {
        for (int c = 0; c < 3; c++) {
            out[side][c] = w[side][P_TRANSLATION][c];
            out[side][7 + c] = w[side][P_SCALING][c];
        }
        for (int c = 0; c < 4; c++) {
            double d = 0;
            for (int k = 0; k < 3; k++)
                d += w[side][P_ROTATION][axes[k]] * partial[k][c];
            out[side][3 + c] = sign * d;
        }
    }
    return true;
}

/* A node's transform properties at clip time t and their slopes on each side (w[0] before t,
 * w[1] after, per second) from its curves' own (fbx_curve_slopes_at), where the node's
 * transform comes from one layer's curves (later layers blend nonlinearly: the baker takes
 * differences for them); *smooth when the two sides agree to rounding. */
static bool key_slopes(const bake_node *n, double t, double v[P_COUNT][3], double w[2][P_COUNT][3], bool *smooth)
{
    const scene *s = n->s;
    const fbx_object *o = &s->objects[n->model];
    memcpy(v, s->statics[n->model].value, sizeof(double[P_COUNT][3]));
    memset(w, 0, sizeof(double[2][P_COUNT][3]));
    *smooth = true;
    for (uint32_t b = o->first_binding; b < o->first_binding + o->binding_count; b++) {
        const fbx_binding *bind = &s->bindings[b];
        if (bind->stack != (uint32_t)n->stack || bind->prop >= P_COUNT)
            continue;
        if (bind->index != 0)
            return false;
        for (int c = 0; c < 3; c++) {
            double *x = &v[bind->prop][c], *l = &w[0][bind->prop][c], *r = &w[1][bind->prop][c];
            if (!isnan(bind->defaults[c]))
                *x = bind->defaults[c];
            if (bind->curves[c] >= 0 &&
                !fbx_curve_slopes_at(&s->curves[bind->curves[c]], n->start + t, n->start, x, l, r))
                return false;
            *smooth &= fabs(*l - *r) <= 1e-9 * fmax(1.0, fabs(*l));
        }
    }
    return true;
}

/* A key's one-sided derivatives from its curves' own slopes (key_slopes). */
static bool bake_node_derivatives(const void *context, double t, const double value[10], double in[10], double out[10])
{
    const bake_node *n = context;
    double v[P_COUNT][3], w[2][P_COUNT][3], both[2][10], mine[10];
    bool smooth;
    if (!key_slopes(n, t, v, w, &smooth))
        return false;
    memcpy(mine, value, sizeof mine);
    if (local_derivative_exact(n, (const double(*)[3])v, (const double(*)[P_COUNT][3])w, false, NULL, mine, both)) {
        memcpy(in, both[0], sizeof both[0]);
        memcpy(out, both[1], sizeof both[1]);
        return true;
    }
    local_derivative(n, (const double(*)[3])v, (const double(*)[3])w[0], value, in);
    if (smooth)
        memcpy(out, in, 10 * sizeof *out);
    else
        local_derivative(n, (const double(*)[3])v, (const double(*)[3])w[1], value, out);
    return true;
}

/* A key's transform and derivatives in one pass, from the values key_slopes reads with its
 * slopes: the curves are read once a key instead of twice (a third of walk.fbx's
 * evaluations were its keys'). */
static bool bake_node_key(const void *context, double t, const double *near, double value[10], double in[10],
                          double out[10])
{
    const bake_node *n = context;
    double v[P_COUNT][3], w[2][P_COUNT][3], both[2][10];
    bool smooth;
    if (!key_slopes(n, t, v, w, &smooth) ||
        !local_derivative_exact(n, (const double(*)[3])v, (const double(*)[P_COUNT][3])w, true, near, value, both))
        return false;
    memcpy(in, both[0], sizeof both[0]);
    memcpy(out, both[1], sizeof both[1]);
    return true;
}

/* Sorts n clip times (finite, >= 0: their bits sort as integers) by their bytes, least
 * significant first; false when out of memory. A node's curves give some hundreds of times,
 * mostly the same ones again: qsort's comparisons were 6% of walk.fbx's import. */
static bool sort_times(float *t, uint32_t n)
{
    uint32_t *a = malloc((size_t)(n ? n : 1) * 2 * sizeof *a), *b = a + n;
    if (!a)
        return false;
    for (uint32_t i = 0; i < n; i++) {
        float f = t[i] + 0.0f; /* -0 as +0 */
        memcpy(&a[i], &f, sizeof f);
    }
    for (int shift = 0; shift < 32; shift += 8) {
        uint32_t count[257] = {0};
        for (uint32_t i = 0; i < n; i++)
            count[(a[i] >> shift & 0xFF) + 1]++;
        if (n == 0 || count[(a[0] >> shift & 0xFF) + 1] == n) /* one value of this byte: in order */
            continue;
        for (int k = 0; k < 256; k++)
            count[k + 1] += count[k];
        for (uint32_t i = 0; i < n; i++)
            b[count[a[i] >> shift & 0xFF]++] = a[i];
        uint32_t *swap = a;
        a = b;
        b = swap;
    }
    for (uint32_t i = 0; i < n; i++)
        memcpy(&t[i], &a[i], sizeof t[i]);
    free(a < b ? a : b);
    return true;
}

/* A growing list of clip times (seconds, as the runtime's floats). */
typedef struct time_list {
    float *t;
    uint32_t count, capacity;
    bool failed;
    double start;
    float duration;
} time_list;

static void time_push(time_list *l, float t)
{
    if (l->failed || !(t >= 0.0f && t <= l->duration))
        return;
    if (l->count == l->capacity) {
        uint32_t cap = l->capacity ? l->capacity * 2 : 16;
        float *grown = realloc(l->t, cap * sizeof *grown);
        if (!grown) {
            l->failed = true;
            return;
        }
        l->t = grown;
        l->capacity = cap;
    }
    l->t[l->count++] = t;
}

/* A key time of a curve (or of its extrapolated cycles): the time, and at a step the instant
 * on the step's far side, so that the bake keeps the step. */
static void push_key_time(void *context, double time, const fbx_curve *c, uint32_t key)
{
    time_list *l = context;
    float t = (float)(time - l->start);
    time_push(l, t);
    bool after = false;
    if (fbx_curve_step(c, key, &after) || (key > 0 && fbx_curve_step(c, key - 1, &after))) {
        time_push(l, nextafterf(t, -INFINITY));
        time_push(l, nextafterf(t, INFINITY));
    }
}

/* Clip times of every key of every curve that animates an object in a stack (their cycles
 * through extrapolation included), the clip's ends, and the instants beside each step. */
sinew_result fbx_object_key_times(const scene *s, uint32_t model, int32_t stack, double start, float duration,
                                  float **out, uint32_t *count)
{
    time_list l = {.start = start, .duration = duration};
    time_push(&l, 0.0f);
    /* A node's curves mostly have the same keys: a curve's times that repeat the first curve's
     * are dropped as they come, and the list is sorted only when they do not come in order
     * (sorting some hundreds of times a node was 4% of walk.fbx's import). */
    uint32_t first = 0, first_count = 0;
    const fbx_object *mo = &s->objects[model];
    for (uint32_t b = mo->first_binding; b < mo->first_binding + mo->binding_count; b++) {
        const fbx_binding *bind = &s->bindings[b];
        if (bind->stack != (uint32_t)stack)
            continue;
        int32_t curves[4] = {bind->curves[0], bind->curves[1], bind->curves[2], s->layers[bind->layer].weight_curve};
        for (int k = 0; k < 4; k++) {
            if (curves[k] < 0)
                continue;
            uint32_t at = l.count;
            fbx_curve_key_times(&s->curves[curves[k]], start, start + duration, FBX_MAX_CYCLE_KEYS, push_key_time, &l);
            if (l.failed || l.count == at)
                continue;
            if (first_count == 0) {
                first = at;
                first_count = l.count - at;
            } else if (l.count - at == first_count && memcmp(l.t + at, l.t + first, first_count * sizeof *l.t) == 0) {
                l.count = at;
            }
        }
    }
    time_push(&l, duration);
    bool sorted = true;
    for (uint32_t i = 1; i < l.count && sorted; i++)
        sorted = l.t[i - 1] <= l.t[i];
    if (l.failed || (!sorted && !sort_times(l.t, l.count))) {
        free(l.t);
        return SINEW_ERROR_OUT_OF_MEMORY;
    }
    uint32_t u = 0;
    for (uint32_t i = 0; i < l.count; i++)
        if (u == 0 || l.t[i] != l.t[u - 1])
            l.t[u++] = l.t[i];
    *out = l.t;
    *count = u;
    return SINEW_OK;
}

static bool model_animated(const scene *s, uint32_t model, int32_t stack)
{
    const fbx_object *o = &s->objects[model];
    for (uint32_t b = o->first_binding; b < o->first_binding + o->binding_count; b++)
        if (s->bindings[b].stack == (uint32_t)stack)
            return true;
    return false;
}

/* The stack's time span: its own, else the span of its keys. */
static void stack_span(const scene *s, uint32_t stack, double *start, double *stop)
{
    const fbx_stack *st = &s->stacks[stack];
    *start = st->start;
    *stop = st->stop;
    if (*stop > *start)
        return;
    double lo = INFINITY, hi = -INFINITY;
    for (uint32_t b = 0; b < s->binding_count; b++) {
        if (s->bindings[b].stack != stack)
            continue;
        for (int k = 0; k < 3; k++) {
            if (s->bindings[b].curves[k] < 0)
                continue;
            const fbx_curve *c = &s->curves[s->bindings[b].curves[k]];
            if (c->count) {
                lo = fmin(lo, c->keys[0].time);
                hi = fmax(hi, c->keys[c->count - 1].time);
            }
        }
    }
    *start = isfinite(lo) ? lo : 0;
    *stop = isfinite(hi) ? hi : 0;
}

static sinew_result build_clip(scene *s, uint32_t stack)
{
    raw_model *m = s->model;
    const fbx_stack *st = &s->stacks[stack];
    double start, stop;
    stack_span(s, stack, &start, &stop);
    float duration = (float)(stop - start);
    if (!isfinite(duration) || duration < 0)
        duration = 0;
    sinew_result result;
    if ((result = grow(s, (void **)&m->clips, m->clip_count, sizeof *m->clips)))
        return result;
    raw_clip *clip = &m->clips[m->clip_count++];
    memset(clip, 0, sizeof *clip);
    clip->duration = duration;
    clip->name = malloc(st->name_len + 1);
    clip->tracks = calloc(m->node_count, sizeof *clip->tracks);
    if (!clip->name || !clip->tracks)
        return fbx_oom(s);
    memcpy(clip->name, st->name, st->name_len);
    clip->name[st->name_len] = 0;
    clip->timeline = (float)start;
    clip->frame_rate = (float)s->frame_rate;
    /* Halving may add at most this many keys to the whole clip (beyond the curves' own). */
    uint64_t budget = 1u << 20;
    for (uint32_t i = 1; i < m->node_count; i++) {
        uint32_t model = s->models[i];
        if (!model_animated(s, model, (int32_t)stack))
            continue;
        float *times = NULL;
        uint32_t n = 0;
        if (fbx_object_key_times(s, model, (int32_t)stack, start, duration, &times, &n))
            return fbx_oom(s);
        /* Translation tolerance relative to the rest pose's size in the file's units: the
         * local translation is in the parent's space, which under a scaled parent is not the
         * world's (the check against ufbx bounds the result in world space). */
        bake_node node = {s, model, (int32_t)stack, start};
        bake_desc desc = {.eval = bake_node_eval,
                          .key_time = bake_node_key_time,
                          .derivatives = bake_node_derivatives,
                          .key = bake_node_key,
                          .context = &node,
                          .tol_t = FBX_BAKE_TOLERANCE * s->diagonal,
                          .tol_r = FBX_BAKE_TOLERANCE,
                          .tol_s = FBX_BAKE_TOLERANCE,
                          .budget = &budget};
        raw_track *track = &clip->tracks[clip->track_count++];
        track->node = i;
        bool ok = bake_track(&desc, times, n, &m->node_rest[i], track);
        free(times);
        if (!ok)
            return fbx_oom(s);
    }
    if (budget == 0)
        raw_model_warn(m,
                       "%s: clip \"%s\" has more curve detail than sinew bakes (a million extra keys); parts "
                       "of it are interpolated more coarsely",
                       s->path, clip->name);
    return fbx_weight_tracks(s, stack, start, clip);
}

/* The file's active take: Documents/Document's ActiveAnimStackName (7.x), Takes/Current
 * (before 7.0); NULL when it names none. */
static const fbx_value *active_take(const scene *s)
{
    const fbx_node *current = fbx_child(fbx_child(&s->doc.root, "Takes"), "Current");
    if (current && current->value_count && current->values[0].type == FBX_STRING)
        return &current->values[0];
    const fbx_node *docs = fbx_child(&s->doc.root, "Documents");
    for (uint32_t i = 0; docs && i < docs->child_count; i++) {
        const fbx_node *p = fbx_find_p(fbx_child(&docs->children[i], "Properties70"), "ActiveAnimStackName");
        if (p && p->value_count > 4 && p->values[4].type == FBX_STRING)
            return &p->values[4];
    }
    return NULL;
}

/* A clip each stack, in the file's order (clip 0 is the first, as ufbx and the tools list
 * them); a note when the file marks another one active. */
static sinew_result build_clips(scene *s)
{
    for (uint32_t i = 0; i < s->stack_count; i++) {
        sinew_result result = build_clip(s, i);
        if (result)
            return result;
    }
    const fbx_value *active = active_take(s);
    for (uint32_t i = 1; active && active->count && i < s->stack_count; i++) {
        const char *name;
        size_t len;
        fbx_object_name(active, &name, &len);
        if (len == s->stacks[i].name_len && memcmp(name, s->stacks[i].name, len) == 0 &&
            !raw_model_warn(s->model,
                            "%s: the file marks clip %u (\"%.*s\") as its active take; clip 0 (\"%.*s\") is the file's "
                            "first, which sinew plays unless told (--clip)",
                            s->path, i, (int)len, name, (int)s->stacks[0].name_len, s->stacks[0].name))
            return fbx_oom(s);
    }
    return SINEW_OK;
}

/* ---- entry ---------------------------------------------------------------------------- */

static void scene_free(scene *s)
{
    for (uint32_t i = 0; i < s->curve_count; i++)
        fbx_curve_free(&s->curves[i]);
    free(s->curves);
    free(s->stacks);
    free(s->layers);
    free(s->bindings);
    free(s->statics);
    free(s->objects);
    free(s->up);
    free(s->down);
    free(s->models);
    free(s->rest_worlds);
    free(s->geometry_channel);
    free(s->channel_object);
    fbx_doc_free(&s->doc);
}

/* Whether a document without a version in its header is laid out as FBX 7.x (objects with
 * numeric ids) or as 6.x (objects named "Class::Name"). */
static bool objects_have_ids(const fbx_doc *doc)
{
    const fbx_node *objects = fbx_child(&doc->root, "Objects");
    for (uint32_t i = 0; objects && i < objects->child_count; i++)
        if (objects->children[i].value_count > 0)
            return objects->children[i].values[0].type == FBX_INT;
    return true;
}

/* The exporter that wrote the file is Blender's (its Creator, at the top or in the header). */
static bool written_by_blender(const fbx_node *root)
{
    const fbx_node *c = fbx_child(root, "Creator");
    if (!c)
        c = fbx_child(fbx_child(root, "FBXHeaderExtension"), "Creator");
    return c && c->value_count && c->values[0].type == FBX_STRING && c->values[0].count >= 7 &&
           memcmp(c->values[0].s, "Blender", 7) == 0;
}

/* Frames a second of GlobalSettings' TimeMode (FbxTime::EMode), or its CustomFrameRate; files
 * before 7.0 without them give a FrameRate in Version5/Settings (6.x) or Settings (5.x). */
static double frame_rate(const scene *s)
{
    if (!fbx_find_p(s->global_settings, "TimeMode")) {
        const fbx_node *root = &s->doc.root, *settings = fbx_child(fbx_child(root, "Version5"), "Settings");
        if (!settings)
            settings = fbx_child(root, "Settings");
        const fbx_node *rate = fbx_child(settings, "FrameRate");
        double fps = 0;
        if (rate && rate->value_count && rate->values[0].type == FBX_STRING) {
            char text[32];
            snprintf(text, sizeof text, "%.*s", (int)rate->values[0].count, rate->values[0].s);
            fps = strtod(text, NULL);
        } else if (rate && rate->value_count) {
            fps = fbx_num(rate, 0);
        }
        if (fps > 0 && fps < 1e6)
            return fps;
    }
    static const double rates[] = {30,          120, 100, 60,   50,     48, 30, 30, 29.97002997,
                                   29.97002997, 25,  24,  1000, 23.976, 0,  96, 72, 59.94};
    int32_t mode = file_int(global_num(s, "TimeMode", 0), 0);
    double custom = global_num(s, "CustomFrameRate", 24);
    if (mode == 14)
        return custom > 0 ? custom : 24;
    return mode >= 0 && mode < (int32_t)(sizeof rates / sizeof rates[0]) && rates[mode] > 0 ? rates[mode] : 30;
}

/* The file's FBX version (refusing those sinew does not read, and 7.x documents without their
 * sections) and its time unit: ticks a second, 46186158000 unless the header says the file
 * keeps the old unit (OtherFlags/TCDefinition 0, from header version 1004). */
static sinew_result check_version(scene *s)
{
    const fbx_node *root = &s->doc.root, *header = fbx_child(root, "FBXHeaderExtension");
    uint32_t v = s->doc.version;
    if (v == 0)
        v = !fbx_child(root, "Objects") ? 5000 : objects_have_ids(&s->doc) ? 7000 : 6000;
    if (v >= 8000)
        return sinew_fail(s->error, SINEW_ERROR_FORMAT,
                          "%s: FBX version %u.%u is newer than sinew reads (FBX 5.x to 7.x); export the file "
                          "again as FBX 7.x",
                          s->path, v / 1000, v % 1000 / 100);
    s->doc.version = v;
    s->legacy = v < 7000 && !(fbx_child(root, "Objects") && objects_have_ids(&s->doc));
    s->ticks_per_second = FBX_TICKS_PER_SECOND;
    const fbx_node *tc = fbx_child(fbx_child(header, "OtherFlags"), "TCDefinition");
    if (tc && fbx_int(tc, 0) == 0 && fbx_int(fbx_child(header, "FBXHeaderVersion"), 0) >= 1004)
        s->ticks_per_second = FBX_OLD_TICKS_PER_SECOND;
    const fbx_node *settings = fbx_child(root, "GlobalSettings");
    if (!settings)
        settings = fbx_child(fbx_child(root, "Objects"), "GlobalSettings");
    s->global_settings = fbx_child(settings, "Properties70");
    if (!s->global_settings)
        s->global_settings = fbx_child(settings, "Properties60");
    s->blender = written_by_blender(root);
    s->frame_rate = frame_rate(s);
    if (!s->legacy && (!fbx_child(root, "Objects") || !fbx_child(root, "Connections")))
        return sinew_fail(s->error, SINEW_ERROR_FORMAT,
                          "%s: the FBX %u.%u document has no %s section (the file may be cut short)", s->path, v / 1000,
                          v % 1000 / 100, fbx_child(root, "Objects") ? "Connections" : "Objects");
    return SINEW_OK;
}

sinew_result raw_model_from_fbx(const char *path, const unsigned char *bytes, size_t size, raw_model *model,
                                sinew_error *error)
{
    memset(model, 0, sizeof *model);
    scene s = {.path = path, .error = error, .model = model};
    sinew_result result = fbx_parse(bytes, size, path, &s.doc, error);
    if (result)
        return result;
    model->source = raw_strdup(path);
    model->format = raw_strdup("fbx");
    if (!model->source || !model->format)
        result = fbx_oom(&s);
    if (!result)
        result = check_version(&s);
    if (!result && s.legacy)
        result = fbx_legacy_index(&s);
    if (!result && !s.legacy) {
        result = index_objects(&s);
        if (!result)
            result = index_animation(&s);
        if (!result)
            fbx_sort_bindings(&s);
    }
    if (!result)
        result = index_statics(&s);
    if (!result) {
        s.geometry_channel = malloc((s.object_count ? s.object_count : 1) * sizeof *s.geometry_channel);
        if (!s.geometry_channel)
            result = fbx_oom(&s);
        for (uint32_t i = 0; !result && i < s.object_count; i++)
            s.geometry_channel[i] = -1;
    }
    if (!result) {
        conversion(&s);
        result = build_nodes(&s);
    }
    if (!result)
        result = measure(&s);
    if (!result)
        result = build_materials(&s);
    if (!result)
        result = build_meshes(&s);
    if (!result)
        result = build_clips(&s);
    scene_free(&s);
    if (result)
        raw_model_free(model);
    return result;
}
