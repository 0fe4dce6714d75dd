/* COLLADA 1.4.1 and 1.5 read by sinew (libxml2): what the file says, not what Assimp made of it.
 *
 * - Scene: the instanced <visual_scene> under a root node (named as the scene, else its id,
 *   else "Scene") that carries <asset>'s unit and up axis (to Y-up metres); <node>s, named
 *   by name, id or sid, with their transform stacks (matrix, translate, rotate, scale,
 *   lookat, skew, composed in order); <instance_node> copies a node's subtree.
 * - Instances: a geometry instanced again with the same materials draws the same raw meshes
 *   at the new node; a controller instanced again on the same skeleton adds nothing.
 * - A file with no skin (an exported skeleton animation) gets a skin with no mesh of the
 *   nodes typed JOINT, else of the nodes its clips move, so that they are its joints.
 * - Skins: a controller's joints are named by SID, looked up under the instance's <skeleton>
 *   roots (then anywhere, then by id or name, as other readers fall back); the bind-shape
 *   matrix is folded into the inverse binds once; every influence is kept.
 * - Morphs: a <morph> controller, alone or under a <skin>: each target <geometry> a morph
 *   target of every primitive (its primitive of the same place when it makes the same
 *   vertices, else its POSITION source by position index), one model channel a target for
 *   each instance, MORPH_WEIGHT as the defaults; NORMALIZED and RELATIVE targets are shapes
 *   (RELATIVE ones nearer zero than the base are offsets). Channels "controller/x(i)" (or of
 *   the whole weight array) animate them: STEP and LINEAR keys kept, BEZIER and HERMITE cut
 *   into linear pieces.
 * - Geometry: <triangles>, <polylist>, <polygons>, <trifans>, <tristrips> with shared
 *   multi-index inputs (POSITION through <vertices>, NORMAL, the first TEXCOORD set),
 *   triangulated; a raw mesh per primitive (its material through <bind_material>).
 * - Materials: <lambert>, <phong>, <blinn>, <constant>: diffuse (emission for constant)
 *   colour or image texture.
 * - Animations: every <channel> into a node's transform element (whole, ".X/.Y/.Z/.ANGLE",
 *   "(i)(j)", "(i)"), samplers with LINEAR, STEP, BEZIER (2-D tangents; 1-D ones, which
 *   COLLADA 1.4.1 does not define, play linearly with a warning) and HERMITE keys. A node whose channels all drive
 * whole matrices with LINEAR or STEP keys gets the decomposed key matrices with that interpolation (what the file means
 * and what three.js plays); any other node is baked from the exact stack evaluation (bake.c). <animation_clip>s become
 * clips over their windows; without them, one clip of every animation. Refusals name the file and the element ("<node
 * id="x">: ...").
 *
 * Index:
 *   errors, numbers, ids .... fail, parse_numbers, by_url
 *   sources ................. read_source
 *   transforms .............. element_matrix, stack_matrix
 *   nodes ................... add_node (instance_node), build_nodes
 *   materials ............... material_of
 *   geometry ................ read_primitive, vertex table
 *   skins ................... resolve_joint, read_skin
 *   morphs .................. read_morph, target_shape, add_targets
 *   animations .............. read_channel, curve_eval, build_clips, weight_keys, morph_tracks
 *   raw_model_from_collada
 */
#define _GNU_SOURCE /* newlocale, strtod_l, qsort_r */
#include <locale.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "xml.h" /* libxml2, loaded on first use */

#include "../core/internal.h"
#include "decimal.h"
#include "internal.h"
#include "sinew/anim.h"
#include "alloc.h" /* last: the readers' allocations are the import's (alloc.h) */

#define DAE_MAX_NODES (1u << 20) /* nodes after <instance_node> copies */
#define DAE_MAX_DEPTH 2048       /* node nesting (libxml2 parses 2048 levels with XML_PARSE_HUGE) */
#define DAE_BAKE_TOLERANCE 1e-6  /* as the FBX reader's: rad, relative scale, of the scene's size */

enum { KEY_STEP, KEY_LINEAR, KEY_BEZIER, KEY_HERMITE };

typedef struct curve {
    xmlNode *node;  /* the target <node> */
    xmlNode *xform; /* its transform element */
    xmlNode *morph; /* or a morph <controller>, whose weights first .. first + count - 1 it drives */
    int first, count;
    uint32_t keys;
    double *times;
    double *values;           /* keys * count */
    uint8_t *interp;          /* a key */
    double *in_tan, *out_tan; /* keys * count * tdim, or NULL */
    int tdim;                 /* 2: (time, value) control points; 1: values at 1/3 and 2/3 */
    xmlNode *channel;         /* its <channel> (clips select by enclosing <animation>) */
} curve;

typedef struct pending {
    uint32_t node;
    xmlNode *instance; /* <instance_geometry> or <instance_controller> */
} pending;

typedef struct source {
    double *v;
    char **names;
    uint32_t count, stride;
} source;

/* A morph <controller> an instance draws: its targets are model channels first .. first +
 * count - 1 (another instance of it has channels of its own). */
typedef struct morph_use {
    xmlNode *controller;
    uint32_t first, count;
} morph_use;

typedef struct collada {
    const char *path;
    raw_model *m;
    sinew_error *error;
    xmlDoc *doc;
    xmlNode *root;
    xmlHashTablePtr ids;
    locale_t c_locale;
    dmat convert;
    double scale;      /* metres a unit */
    xmlNode **node_el; /* a sinew node: its <node> (NULL for the root) */
    uint32_t node_cap;
    pending *pending;
    uint32_t pending_count, pending_cap;
    curve *curves;
    uint32_t curve_count, curve_cap;
    double diagonal;
    uint32_t bezier_1d; /* channels whose BEZIER keys give one number a tangent */
    morph_use *morphs;  /* a morph controller drawn: the model channels of its targets */
    uint32_t morph_count;
} collada;

/* ---- errors, numbers, ids ------------------------------------------------------------- */

static sinew_result vfail(collada *c, const xmlNode *at, sinew_result kind, const char *format, va_list ap)
{
    char what[512], where[256] = "";
    vsnprintf(what, sizeof what, format, ap);
    long line = 0;
    if (at && at->type == XML_ELEMENT_NODE) {
        xmlChar *id = xmlGetProp(at, (const xmlChar *)"id");
        line = xmlGetLineNo(at);
        snprintf(where, sizeof where, "line %ld, <%s%s%s%s>: ", line, (const char *)at->name, id ? " id=\"" : "",
                 id ? (const char *)id : "", id ? "\"" : "");
        xmlFree(id);
    }
    return sinew_fail_at(c->error, kind, c->path, -1, line > 0 ? (uint32_t)line : 0, "%s: %s%s", c->path, where, what);
}

/* A file that breaks COLLADA's rules: "FILE: line N, <element id>: what". */
static sinew_result fail(collada *c, const xmlNode *at, const char *format, ...) __attribute__((format(printf, 3, 4)));
static sinew_result fail(collada *c, const xmlNode *at, const char *format, ...)
{
    va_list ap;
    va_start(ap, format);
    sinew_result r = vfail(c, at, SINEW_ERROR_FORMAT, format, ap);
    va_end(ap);
    return r;
}

/* The same with another kind: SINEW_ERROR_DATA for well-formed numbers no model can hold
 * (NaN, infinity), SINEW_ERROR_LIMIT for what is past sinew's limits. */
static sinew_result fail_kind(collada *c, const xmlNode *at, sinew_result kind, const char *format, ...)
    __attribute__((format(printf, 4, 5)));
static sinew_result fail_kind(collada *c, const xmlNode *at, sinew_result kind, const char *format, ...)
{
    va_list ap;
    va_start(ap, format);
    sinew_result r = vfail(c, at, kind, format, ap);
    va_end(ap);
    return r;
}

static sinew_result oom(collada *c)
{
    return sinew_fail(c->error, SINEW_ERROR_OUT_OF_MEMORY, "%s: out of memory while reading COLLADA", c->path);
}

static bool named(const xmlNode *n, const char *name)
{
    return n && n->type == XML_ELEMENT_NODE && strcmp((const char *)n->name, name) == 0;
}

static xmlNode *child(const xmlNode *n, const char *name)
{
    for (xmlNode *k = n ? n->children : NULL; k; k = k->next)
        if (named(k, name))
            return k;
    return NULL;
}

static xmlNode *next_named(xmlNode *n, const char *name)
{
    for (n = n ? n->next : NULL; n; n = n->next)
        if (named(n, name))
            return n;
    return NULL;
}

/* An attribute copied into buf ("" when absent; false then). */
static bool attr(const xmlNode *n, const char *name, char *buf, size_t size)
{
    xmlChar *v = n ? xmlGetProp(n, (const xmlChar *)name) : NULL;
    size_t len = v ? strlen((const char *)v) : 0; /* as snprintf "%s" truncates, at a sixteenth of its cost */
    if (size) {
        len = len < size ? len : size - 1;
        memcpy(buf, v ? (const char *)v : "", len);
        buf[len] = '\0';
    }
    xmlFree(v);
    return v != NULL;
}

static long attr_long(const xmlNode *n, const char *name, long fallback)
{
    char buf[64];
    if (!attr(n, name, buf, sizeof buf))
        return fallback;
    char *end;
    long v = strtol(buf, &end, 10);
    return end != buf && *end == 0 ? v : LONG_MIN;
}

/* The element an URL ("#id") names, or NULL. */
static xmlNode *by_url(const collada *c, const char *url)
{
    if (!url || url[0] != '#')
        return NULL;
    return xmlHashLookup(c->ids, (const xmlChar *)url + 1);
}

static xmlNode *by_url_attr(const collada *c, const xmlNode *n, const char *name)
{
    char url[1024];
    return attr(n, name, url, sizeof url) ? by_url(c, url) : NULL;
}

static void index_ids(collada *c, xmlNode *n)
{
    for (; n; n = n->next) {
        if (n->type != XML_ELEMENT_NODE)
            continue;
        xmlChar *id = xmlGetProp(n, (const xmlChar *)"id");
        if (id) {
            xmlHashAddEntry(c->ids, id, n); /* the first of repeated ids wins */
            xmlFree(id);
        }
        index_ids(c, n->children);
    }
}

/* Numbers of an element's text (at most `max`; *count gets how many), in the C locale. */
/* The numbers of `text`, an element's text. */
static sinew_result parse_text(collada *c, const xmlNode *el, const char *text, double *out, uint32_t max,
                               uint32_t *count)
{
    const char *p = text ? text : "", *limit = p + strlen(p);
    uint32_t n = 0;
    sinew_result r = SINEW_OK;
    for (;;) {
        while (*p == ' ' || *p == '\t' || *p == '\n' || *p == '\r')
            p++;
        if (!*p)
            break;
        double v;
        const char *fast = p;
        char *end;
        /* a number ends at white space (xs:list); the rest of xs:double ("+1", ".5", "1e400", "INF"): strtod */
        if (decimal_scan_within(p, limit, &fast, &v) > 0 &&
            (!*fast || *fast == ' ' || *fast == '\t' || *fast == '\n' || *fast == '\r'))
            end = (char *)fast;
        else
            v = strtod_l(p, &end, c->c_locale);
        if (end == p || !isfinite(v)) {
            int length = (int)strcspn(p, " \t\r\n");
            r = end == p ? fail(c, el, "\"%.*s\" is not a number", length < 20 ? length : 20, p)
                         : fail_kind(c, el, SINEW_ERROR_DATA, "%.*s is not finite", length < 20 ? length : 20, p);
            break;
        }
        if (n == max) {
            r = fail(c, el, "more than %u numbers", max);
            break;
        }
        out[n++] = v;
        p = end;
    }
    *count = n;
    return r;
}

/* An element's text: its one text child's own, where it has one (a number array's is most of
 * a COLLADA file: not copied), else a copy (*copy set: xmlFree it). */
static const char *text_of(const xmlNode *el, xmlChar **copy)
{
    const xmlNode *t = el ? el->children : NULL;
    *copy = NULL;
    if (t && !t->next && (t->type == XML_TEXT_NODE || t->type == XML_CDATA_SECTION_NODE) && t->content)
        return (const char *)t->content;
    if (el && !el->children)
        return "";
    *copy = xmlNodeGetContent(el);
    return (const char *)*copy;
}

static sinew_result parse_numbers(collada *c, const xmlNode *el, double *out, uint32_t max, uint32_t *count)
{
    xmlChar *copy;
    const char *text = text_of(el, &copy);
    sinew_result r = parse_text(c, el, text, out, max, count);
    xmlFree(copy);
    return r;
}

/* All numbers of an element's text (malloc'd). */
static sinew_result numbers_of(collada *c, const xmlNode *el, double **out, uint32_t *count)
{
    xmlChar *copy;
    const char *text = text_of(el, &copy);
    size_t len = text ? strlen(text) : 0;
    uint32_t max = (uint32_t)(len / 2 + 1);
    *out = malloc(max * sizeof **out);
    if (!*out) {
        xmlFree(copy);
        return oom(c);
    }
    sinew_result r = parse_text(c, el, text, *out, max, count);
    xmlFree(copy);
    if (r) {
        free(*out);
        *out = NULL;
    }
    return r;
}

/* ---- sources -------------------------------------------------------------------------- */

static void source_free(source *s)
{
    free(s->v);
    for (uint32_t i = 0; s->names && i < s->count * s->stride; i++)
        free(s->names[i]);
    free(s->names);
    memset(s, 0, sizeof *s);
}

/* A <source>: its accessor's count x stride values (numbers, or names for Name_array /
 * IDREF_array / SIDREF_array), checked against the array. */
static sinew_result read_source(collada *c, xmlNode *src, source *out)
{
    memset(out, 0, sizeof *out);
    if (!named(src, "source"))
        return fail(c, src, "not a <source>");
    xmlNode *acc = child(child(src, "technique_common"), "accessor");
    if (!acc)
        return fail(c, src, "no <technique_common><accessor>");
    long count = attr_long(acc, "count", -1), stride = attr_long(acc, "stride", 1),
         offset = attr_long(acc, "offset", 0);
    if (count < 0 || count > (long)UINT32_MAX / 64 || stride < 1 || stride > 64 || offset < 0)
        return fail(c, acc, "count %ld, stride %ld, offset %ld", count, stride, offset);
    out->count = (uint32_t)count;
    out->stride = (uint32_t)stride;
    xmlNode *array = by_url_attr(c, acc, "source");
    if (!array) {
        for (xmlNode *k = src->children; k && !array; k = k->next)
            if (k->type == XML_ELEMENT_NODE && strstr((const char *)k->name, "_array"))
                array = k;
    }
    if (!array)
        return fail(c, acc, "its source array is not in the file");
    size_t need = (size_t)offset + (size_t)count * (size_t)stride;
    if (named(array, "float_array") || named(array, "int_array")) {
        double *all;
        uint32_t n;
        sinew_result r = numbers_of(c, array, &all, &n);
        if (r)
            return r;
        if (n < need) {
            free(all);
            return fail(c, array, "%u numbers, but its accessor reads %zu", n, need);
        }
        out->v = malloc((need - (size_t)offset + 1) * sizeof *out->v);
        if (!out->v) {
            free(all);
            return oom(c);
        }
        memcpy(out->v, all + offset, (need - (size_t)offset) * sizeof *out->v);
        free(all);
        return SINEW_OK;
    }
    if (named(array, "Name_array") || named(array, "IDREF_array") || named(array, "SIDREF_array")) {
        out->names = calloc(need - (size_t)offset + 1, sizeof *out->names);
        if (!out->names)
            return oom(c);
        xmlChar *text = xmlNodeGetContent(array);
        char *save = NULL, *tok = strtok_r((char *)text, " \t\r\n", &save);
        size_t i = 0;
        for (; tok && i < need; tok = strtok_r(NULL, " \t\r\n", &save), i++)
            if (i >= (size_t)offset && !(out->names[i - (size_t)offset] = raw_strdup(tok))) {
                xmlFree(text);
                return oom(c);
            }
        xmlFree(text);
        if (i < need)
            return fail(c, array, "%zu names, but its accessor reads %zu", i, need);
        return SINEW_OK;
    }
    return fail(c, array, "an array sinew does not read here");
}

/* ---- transforms ----------------------------------------------------------------------- */

static void normalize3(double v[3])
{
    double n = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    for (int i = 0; i < 3 && n > 0; i++)
        v[i] /= n;
}

static dmat axis_angle(const double axis[3], double degrees)
{
    double a[3] = {axis[0], axis[1], axis[2]};
    normalize3(a);
    double r = degrees * M_PI / 180.0, cs = cos(r), sn = sin(r), t = 1 - cs;
    dmat m = dmat_identity();
    m.m[0] = t * a[0] * a[0] + cs;
    m.m[1] = t * a[0] * a[1] + sn * a[2];
    m.m[2] = t * a[0] * a[2] - sn * a[1];
    m.m[4] = t * a[0] * a[1] - sn * a[2];
    m.m[5] = t * a[1] * a[1] + cs;
    m.m[6] = t * a[1] * a[2] + sn * a[0];
    m.m[8] = t * a[0] * a[2] + sn * a[1];
    m.m[9] = t * a[1] * a[2] - sn * a[0];
    m.m[10] = t * a[2] * a[2] + cs;
    return m;
}

/* How many numbers a transform element holds; 0 for an element that is not one. */
static int element_size(const xmlNode *el)
{
    static const struct {
        const char *name;
        int size;
    } kinds[] = {{"matrix", 16}, {"translate", 3}, {"rotate", 4}, {"scale", 3}, {"lookat", 9}, {"skew", 7}};
    for (size_t i = 0; i < sizeof kinds / sizeof kinds[0]; i++)
        if (named(el, kinds[i].name))
            return kinds[i].size;
    return 0;
}

/* The matrix of one transform element from its numbers (matrix: row-major in the file). */
static dmat element_matrix(const xmlNode *el, const double *v)
{
    dmat m = dmat_identity();
    if (named(el, "matrix")) {
        m = dmat_from_rows(v);
    } else if (named(el, "translate")) {
        m.m[12] = v[0], m.m[13] = v[1], m.m[14] = v[2];
    } else if (named(el, "rotate")) {
        m = axis_angle(v, v[3]);
    } else if (named(el, "scale")) {
        m.m[0] = v[0], m.m[5] = v[1], m.m[10] = v[2];
    } else if (named(el, "lookat")) {
        /* eye, interest, up: the camera's placement (it looks down its -Z) */
        double z[3] = {v[0] - v[3], v[1] - v[4], v[2] - v[5]}, up[3] = {v[6], v[7], v[8]}, x[3], y[3];
        normalize3(z);
        x[0] = up[1] * z[2] - up[2] * z[1], x[1] = up[2] * z[0] - up[0] * z[2], x[2] = up[0] * z[1] - up[1] * z[0];
        normalize3(x);
        y[0] = z[1] * x[2] - z[2] * x[1], y[1] = z[2] * x[0] - z[0] * x[2], y[2] = z[0] * x[1] - z[1] * x[0];
        for (int i = 0; i < 3; i++)
            m.m[i] = x[i], m.m[4 + i] = y[i], m.m[8 + i] = z[i], m.m[12 + i] = v[i];
    } else if (named(el, "skew")) {
        /* angle, rotation axis, translation axis (RenderMan's skew) */
        double a[3] = {v[1], v[2], v[3]}, t[3] = {v[4], v[5], v[6]};
        normalize3(a);
        normalize3(t);
        double s = tan(v[0] * M_PI / 180.0);
        for (int col = 0; col < 3; col++)
            for (int row = 0; row < 3; row++)
                m.m[col * 4 + row] += s * t[row] * a[col];
    }
    return m;
}

/* The node's local matrix: its transform elements in order, each with its numbers from
 * `values` (the first `value_count` elements, in document order) or the file. */
static dmat stack_matrix(collada *c, const xmlNode *node, const double *const *values, int value_count)
{
    dmat m = dmat_identity();
    int k = 0;
    for (xmlNode *el = node->children; el; el = el->next) {
        int size = element_size(el);
        if (!size)
            continue;
        double v[16] = {0};
        uint32_t n = 0;
        if (k < value_count && values[k])
            memcpy(v, values[k], (size_t)size * sizeof *v);
        else
            parse_numbers(c, el, v, (uint32_t)size, &n);
        dmat e = element_matrix(el, v);
        m = dmat_mul(&m, &e);
        k++;
    }
    return m;
}

/* Checks a node's transform elements once (so that later evaluation cannot fail). */
static sinew_result check_stack(collada *c, const xmlNode *node)
{
    for (xmlNode *el = node->children; el; el = el->next) {
        int size = element_size(el);
        if (!size)
            continue;
        double v[16];
        uint32_t n;
        sinew_result r = parse_numbers(c, el, v, 16, &n);
        if (r)
            return r;
        if (n != (uint32_t)size)
            return fail(c, el, "%u numbers where <%s> has %d", n, (const char *)el->name, size);
    }
    return SINEW_OK;
}

/* ---- nodes ---------------------------------------------------------------------------- */

static sinew_result push_node(collada *c, const char *name, int32_t parent, xmlNode *el, const dmat *local)
{
    raw_model *m = c->m;
    if (m->node_count == DAE_MAX_NODES)
        return fail_kind(c, el, SINEW_ERROR_LIMIT, "more than %u nodes (with <instance_node> copies)", DAE_MAX_NODES);
    if (m->node_count == c->node_cap) {
        uint32_t cap = c->node_cap ? c->node_cap * 2 : 64;
        bool grown = raw_model_grow_nodes(m, cap);
        xmlNode **els = realloc(c->node_el, cap * sizeof *els);
        if (els)
            c->node_el = els;
        if (!grown || !els)
            return oom(c);
        c->node_cap = cap;
    }
    uint32_t i = m->node_count;
    if (!(m->node_names[i] = raw_strdup(name)))
        return oom(c);
    m->node_count++;
    m->node_parents[i] = parent;
    c->node_el[i] = el;
    sinew_mat4 f;
    dmat_to_float(local, &f);
    sinew_mat4_decompose(&f, &m->node_rest[i]);
    return SINEW_OK;
}

static sinew_result add_pending(collada *c, uint32_t node, xmlNode *instance)
{
    if (c->pending_count == c->pending_cap) {
        uint32_t cap = c->pending_cap ? c->pending_cap * 2 : 16;
        pending *p = realloc(c->pending, cap * sizeof *p);
        if (!p)
            return oom(c);
        c->pending = p;
        c->pending_cap = cap;
    }
    c->pending[c->pending_count++] = (pending){node, instance};
    return SINEW_OK;
}

/* A <node> and its subtree (with <instance_node> copies) under `parent`. */
static sinew_result add_node(collada *c, xmlNode *el, int32_t parent, int depth)
{
    if (depth > DAE_MAX_DEPTH)
        return fail(c, el, "nodes nest deeper than %d (or <instance_node> instances itself)", DAE_MAX_DEPTH);
    sinew_result r = check_stack(c, el);
    if (r)
        return r;
    char name[512];
    if (!attr(el, "name", name, sizeof name) || !*name)
        if (!attr(el, "id", name, sizeof name) || !*name)
            if (!attr(el, "sid", name, sizeof name) || !*name)
                snprintf(name, sizeof name, "node");
    dmat local = stack_matrix(c, el, NULL, 0);
    if ((r = push_node(c, name, parent, el, &local)))
        return r;
    int32_t self = (int32_t)c->m->node_count - 1;
    for (xmlNode *k = el->children; k; k = k->next) {
        if (named(k, "node")) {
            r = add_node(c, k, self, depth + 1);
        } else if (named(k, "instance_node")) {
            xmlNode *target = by_url_attr(c, k, "url");
            r = named(target, "node") ? add_node(c, target, self, depth + 1)
                                      : fail(c, k, "url does not name a <node> of this file");
        } else if (named(k, "instance_geometry") || named(k, "instance_controller")) {
            r = add_pending(c, (uint32_t)self, k);
        }
        if (r)
            return r;
    }
    return SINEW_OK;
}

/* <asset>'s unit and up axis as the root's transform (to Y-up metres). */
static void read_asset(collada *c)
{
    xmlNode *asset = child(c->root, "asset");
    c->scale = 1;
    char buf[64];
    if (attr(child(asset, "unit"), "meter", buf, sizeof buf)) {
        char *end;
        double v = strtod_l(buf, &end, c->c_locale);
        if (end != buf && isfinite(v) && v > 0)
            c->scale = v;
    }
    xmlChar *up = xmlNodeGetContent(child(asset, "up_axis"));
    dmat m = dmat_identity();
    if (up && strstr((const char *)up, "Z_UP")) {
        m.m[5] = 0, m.m[6] = -1, m.m[9] = 1, m.m[10] = 0; /* (x, y, z) -> (x, z, -y) */
    } else if (up && strstr((const char *)up, "X_UP")) {
        m.m[0] = 0, m.m[1] = 1, m.m[4] = -1, m.m[5] = 0; /* (x, y, z) -> (-y, x, z) */
    }
    xmlFree(up);
    for (int i = 0; i < 12; i++)
        m.m[i] *= c->scale;
    c->convert = m;
}

static sinew_result build_nodes(collada *c)
{
    xmlNode *scene = child(c->root, "scene");
    xmlNode *vs = by_url_attr(c, child(scene, "instance_visual_scene"), "url");
    if (!vs)
        vs = child(child(c->root, "library_visual_scenes"), "visual_scene");
    if (!named(vs, "visual_scene"))
        return fail(c, scene, "no <visual_scene> (nothing to show)");
    char name[512];
    if ((!attr(vs, "name", name, sizeof name) || !*name) && (!attr(vs, "id", name, sizeof name) || !*name))
        snprintf(name, sizeof name, "Scene");
    sinew_result r = push_node(c, name, -1, NULL, &c->convert);
    for (xmlNode *k = vs->children; k && !r; k = k->next)
        if (named(k, "node"))
            r = add_node(c, k, 0, 1);
    return r;
}

/* ---- materials ------------------------------------------------------------------------ */

typedef struct material_map {
    xmlNode **elements; /* by raw material */
} material_map;

/* The image file a <texture texture="sampler"> names: sampler -> surface -> image (1.4.1),
 * or sampler -> <instance_image> (1.5), or an image id directly. */
static xmlNode *texture_image(collada *c, xmlNode *profile, const char *sampler)
{
    xmlNode *image = NULL;
    for (xmlNode *p = profile ? profile->children : NULL; p && !image; p = p->next) {
        char sid[256];
        if (!named(p, "newparam") || !attr(p, "sid", sid, sizeof sid) || strcmp(sid, sampler) != 0)
            continue;
        xmlNode *s2d = child(p, "sampler2D");
        xmlNode *inst = child(s2d, "instance_image");
        if (inst)
            return by_url_attr(c, inst, "url");
        xmlChar *surface = xmlNodeGetContent(child(s2d, "source"));
        for (xmlNode *q = profile->children; q && surface && !image; q = q->next) {
            if (named(q, "newparam") && attr(q, "sid", sid, sizeof sid) && strcmp(sid, (const char *)surface) == 0) {
                xmlChar *img = xmlNodeGetContent(child(child(q, "surface"), "init_from"));
                char url[1024];
                snprintf(url, sizeof url, "#%s", img ? (const char *)img : "");
                xmlFree(img);
                image = by_url(c, url);
            }
        }
        xmlFree(surface);
    }
    if (!image) {
        char url[1024];
        snprintf(url, sizeof url, "#%s", sampler);
        image = by_url(c, url);
    }
    return named(image, "image") ? image : NULL;
}

static char *image_path(collada *c, xmlNode *image, const char *material)
{
    xmlNode *from = child(image, "init_from");
    xmlNode *ref = child(from, "ref"); /* 1.5 */
    xmlChar *text = xmlNodeGetContent(ref ? ref : from);
    char name[4096];
    snprintf(name, sizeof name, "%s", text ? (const char *)text : "");
    xmlFree(text);
    /* URIs: a file:// prefix and %20 escapes */
    char decoded[4096];
    import_uri_decode(strncmp(name, "file://", 7) == 0 ? name + 7 : name, decoded, sizeof decoded);
    char *found = NULL;
    import_material_texture(c->m, c->path, material, decoded, &found);
    return found;
}

/* The raw material of a <material> element (made on first use). */
static sinew_result material_of(collada *c, material_map *map, xmlNode *mat, int32_t *out)
{
    raw_model *m = c->m;
    for (uint32_t i = 0; i < m->material_count; i++)
        if (map->elements[i] == mat) {
            *out = (int32_t)i;
            return SINEW_OK;
        }
    raw_material *mats = realloc(m->materials, (m->material_count + 1) * sizeof *mats);
    xmlNode **els = realloc(map->elements, (m->material_count + 1) * sizeof *els);
    if (mats)
        m->materials = mats;
    if (els)
        map->elements = els;
    if (!mats || !els)
        return oom(c);
    raw_material *rm = &m->materials[m->material_count];
    memset(rm, 0, sizeof *rm);
    map->elements[m->material_count] = mat;
    *out = (int32_t)m->material_count++;
    char name[512];
    if (!attr(mat, "name", name, sizeof name) || !*name)
        attr(mat, "id", name, sizeof name);
    if (!(rm->name = raw_strdup(name)))
        return oom(c);
    rm->base_color[0] = rm->base_color[1] = rm->base_color[2] = 0.8f;
    rm->base_color[3] = 1;
    xmlNode *effect = by_url_attr(c, child(mat, "instance_effect"), "url");
    xmlNode *profile = child(effect, "profile_COMMON");
    xmlNode *technique = child(profile, "technique");
    xmlNode *shading = NULL;
    static const char *const models[] = {"phong", "lambert", "blinn", "constant"};
    for (size_t i = 0; i < 4 && !shading; i++)
        shading = child(technique, models[i]);
    if (!shading)
        return SINEW_OK;
    if (!named(shading, "constant")) {
        xmlNode *emission = child(child(shading, "emission"), "color");
        double e[4] = {0, 0, 0, 1}, shininess[1] = {20};
        uint32_t n;
        sinew_result r;
        if (emission && (r = parse_numbers(c, emission, e, 4, &n)))
            return r;
        for (int k = 0; k < 3; k++)
            rm->emissive[k] = (float)fmax(e[k], 0.0);
        xmlNode *shine = child(child(shading, "shininess"), "float");
        if (shine && (r = parse_numbers(c, shine, shininess, 1, &n)))
            return r;
        rm->roughness = named(shading, "lambert") ? 1.0f : import_roughness_of_shininess(shininess[0]);
    }
    xmlNode *diffuse = child(shading, named(shading, "constant") ? "emission" : "diffuse");
    xmlNode *color = child(diffuse, "color"), *texture = child(diffuse, "texture");
    if (color) {
        double v[4] = {0.8, 0.8, 0.8, 1};
        uint32_t n;
        sinew_result r = parse_numbers(c, color, v, 4, &n);
        if (r)
            return r;
        for (int k = 0; k < 4; k++)
            rm->base_color[k] = (float)fmin(fmax(v[k], 0.0), 1.0);
    }
    if (texture) {
        char sampler[256];
        attr(texture, "texture", sampler, sizeof sampler);
        xmlNode *image = texture_image(c, profile, sampler);
        if (image) {
            rm->maps[SINEW_MAP_BASE_COLOR].path = image_path(c, image, rm->name);
            rm->base_color[0] = rm->base_color[1] = rm->base_color[2] = rm->base_color[3] = 1;
        } else if (!raw_model_warn(c->m, "%s: material \"%s\": texture \"%s\" names no image", c->path, rm->name,
                                   sampler)) {
            return oom(c);
        }
    }
    return SINEW_OK;
}

/* The material bound to a primitive's symbol in an instance's <bind_material>, or -1. */
static sinew_result bound_material(collada *c, material_map *map, xmlNode *instance, const char *symbol, int32_t *out)
{
    *out = -1;
    xmlNode *tc = child(child(instance, "bind_material"), "technique_common");
    for (xmlNode *im = tc ? tc->children : NULL; im; im = im->next) {
        char sym[512];
        if (!named(im, "instance_material") || !attr(im, "symbol", sym, sizeof sym) || strcmp(sym, symbol) != 0)
            continue;
        xmlNode *mat = by_url_attr(c, im, "target");
        return named(mat, "material") ? material_of(c, map, mat, out) : SINEW_OK;
    }
    return SINEW_OK;
}

/* ---- geometry ------------------------------------------------------------------------- */

typedef struct prim {
    raw_mesh mesh;
    uint32_t *position_of; /* a vertex: its index into the POSITION source (for skins) */
} prim;

typedef struct input {
    source src;
    int offset;
    bool present;
} input;

#define INPUTS 4 /* a corner's inputs: position, normal, uv, colour */

typedef struct vertex_table {
    uint32_t *slots; /* vertex + 1, 0 empty */
    uint32_t mask;
    uint32_t *keys; /* INPUTS a vertex: position, normal, uv, colour index */
    uint32_t count;
} vertex_table;

static int64_t vertex_for(vertex_table *t, const uint32_t key[INPUTS])
{
    uint32_t h =
        (key[0] * 2654435761u) ^ (key[1] * 40503u + 0x9e3779b9u) ^ (key[2] * 2246822519u) ^ (key[3] * 3266489917u);
    for (uint32_t i = h & t->mask;; i = (i + 1) & t->mask) {
        uint32_t s = t->slots[i];
        if (!s) {
            t->slots[i] = t->count + 1;
            memcpy(&t->keys[t->count * INPUTS], key, INPUTS * sizeof *key);
            return t->count++;
        }
        if (memcmp(&t->keys[(s - 1) * INPUTS], key, INPUTS * sizeof *key) == 0)
            return s - 1;
    }
}

static void inputs_free(input in[INPUTS])
{
    for (int i = 0; i < INPUTS; i++)
        source_free(&in[i].src);
}

/* One input by semantic into in[0] position, in[1] normal, in[2] uv, in[3] colour (the first
 * set of each). */
static sinew_result read_input(collada *c, xmlNode *el, int offset, input in[INPUTS])
{
    char semantic[64];
    attr(el, "semantic", semantic, sizeof semantic);
    int slot = strcmp(semantic, "POSITION") == 0   ? 0
               : strcmp(semantic, "NORMAL") == 0   ? 1
               : strcmp(semantic, "TEXCOORD") == 0 ? 2
               : strcmp(semantic, "COLOR") == 0    ? 3
                                                   : -1;
    if (slot < 0 || in[slot].present)
        return SINEW_OK;
    xmlNode *src = by_url_attr(c, el, "source");
    if (!src)
        return fail(c, el, "source names nothing in this file");
    sinew_result r = read_source(c, src, &in[slot].src);
    if (r)
        return r;
    if (!in[slot].src.v || in[slot].src.stride < (slot == 2 ? 2u : 3u))
        return fail(c, src, "%s needs %d numbers an element", semantic, slot == 2 ? 2 : 3);
    in[slot].offset = offset;
    in[slot].present = true;
    return SINEW_OK;
}

/* Triangles of one primitive element as a raw mesh; *skip when it draws lines or points. */
static sinew_result read_primitive(collada *c, xmlNode *el, const char *geometry, prim *out, bool *skip)
{
    memset(out, 0, sizeof *out);
    out->mesh.skin = -1;
    out->mesh.material = -1;
    *skip = !(named(el, "triangles") || named(el, "polylist") || named(el, "polygons") || named(el, "trifans") ||
              named(el, "tristrips"));
    if (*skip)
        return SINEW_OK;
    input in[INPUTS];
    memset(in, 0, sizeof in);
    int stride = 0;
    sinew_result r = SINEW_OK;
    for (xmlNode *k = el->children; k && !r; k = k->next) {
        if (!named(k, "input"))
            continue;
        long offset = attr_long(k, "offset", 0);
        if (offset < 0 || offset > 64) {
            r = fail(c, k, "offset %ld", offset);
            break;
        }
        stride = stride > (int)offset + 1 ? stride : (int)offset + 1;
        char semantic[64];
        attr(k, "semantic", semantic, sizeof semantic);
        if (strcmp(semantic, "VERTEX") == 0) {
            xmlNode *vertices = by_url_attr(c, k, "source");
            if (!named(vertices, "vertices")) {
                r = fail(c, k, "VERTEX source is not a <vertices>");
                break;
            }
            for (xmlNode *v = vertices->children; v && !r; v = v->next)
                if (named(v, "input"))
                    r = read_input(c, v, (int)offset, in);
        } else {
            r = read_input(c, k, (int)offset, in);
        }
    }
    if (!r && !in[0].present)
        r = fail(c, el, "no POSITION input");
    /* Polygon sizes: from <vcount>, 3 for triangles, one polygon per <p> otherwise. */
    double *vcount = NULL;
    uint32_t nv = 0;
    if (!r && named(el, "polylist"))
        r = numbers_of(c, child(el, "vcount"), &vcount, &nv);
    uint32_t cap = 0;
    vertex_table t = {0};
    uint32_t *corners = NULL, corner_count = 0;
    for (xmlNode *p = child(el, "p"); p && !r; p = next_named(p, "p")) {
        double *idx;
        uint32_t n;
        if ((r = numbers_of(c, p, &idx, &n)))
            break;
        if (n % (uint32_t)stride) {
            r = fail(c, p, "%u indices is not a whole number of %d-index corners", n, stride);
            free(idx);
            break;
        }
        uint32_t count = n / (uint32_t)stride;
        for (uint32_t i = 0; i < n && !r; i++)
            if (idx[i] < 0 || idx[i] != floor(idx[i]) || idx[i] >= UINT32_MAX)
                r = fail(c, p, "index %g is not a whole number >= 0", idx[i]);
        /* Corner lists of this <p>: (first, size) polygons, fanned or stripped */
        uint32_t polys = named(el, "polylist") ? nv : named(el, "triangles") ? count / 3 : 1;
        uint32_t at = 0;
        for (uint32_t q = 0; q < polys && !r; q++) {
            uint32_t size = named(el, "polylist")
                                ? (vcount[q] >= 0 && vcount[q] < 1e6 ? (uint32_t)vcount[q] : UINT32_MAX)
                            : named(el, "triangles") ? 3
                                                     : count;
            if (size == UINT32_MAX || size > count - at) {
                r = fail(c, p, "polygon %u has %u corners, more than the indices hold", q, size);
                break;
            }
            uint32_t tris = size >= 3 ? size - 2 : 0;
            if (corner_count + tris * 3 > cap) {
                cap = (corner_count + tris * 3) * 2 + 16;
                uint32_t *grown = realloc(corners, (size_t)cap * INPUTS * sizeof *grown);
                if (!grown) {
                    r = oom(c);
                    break;
                }
                corners = grown;
            }
            for (uint32_t k = 0; k < tris && !r; k++) {
                uint32_t a, b2, d;
                if (named(el, "tristrips"))
                    a = at + k, b2 = at + k + (k % 2 ? 2 : 1), d = at + k + (k % 2 ? 1 : 2);
                else
                    a = at, b2 = at + k + 1, d = at + k + 2;
                uint32_t tri[3] = {a, b2, d};
                for (int j = 0; j < 3 && !r; j++) {
                    uint32_t *key = &corners[(size_t)(corner_count + (uint32_t)j) * INPUTS];
                    for (int s = 0; s < INPUTS; s++) {
                        if (!in[s].present) {
                            key[s] = 0;
                            continue;
                        }
                        double v = idx[(size_t)tri[j] * (size_t)stride + (size_t)in[s].offset];
                        if (v >= in[s].src.count) {
                            r = fail(c, p, "index %.0f is past the %u elements of its source", v, in[s].src.count);
                            break;
                        }
                        key[s] = (uint32_t)v;
                    }
                }
                corner_count += 3;
            }
            at += size;
        }
        free(idx);
    }
    free(vcount);
    if (!r && corner_count) {
        uint32_t slots = 16;
        while (slots < corner_count * 2)
            slots *= 2;
        t.slots = calloc(slots, sizeof *t.slots);
        t.keys = malloc((size_t)corner_count * INPUTS * sizeof *t.keys);
        t.mask = slots - 1;
        out->mesh.indices = malloc((size_t)corner_count * sizeof *out->mesh.indices);
        if (!t.slots || !t.keys || !out->mesh.indices)
            r = oom(c);
        for (uint32_t i = 0; i < corner_count && !r; i++)
            out->mesh.indices[i] = (uint32_t)vertex_for(&t, &corners[(size_t)i * INPUTS]);
        out->mesh.index_count = r ? 0 : corner_count;
    }
    free(corners);
    uint32_t n = t.count;
    if (!r && n) {
        raw_mesh *mm = &out->mesh;
        mm->vertex_count = n;
        mm->positions = malloc((size_t)n * 3 * sizeof *mm->positions);
        mm->normals = in[1].present ? malloc((size_t)n * 3 * sizeof *mm->normals) : NULL;
        mm->uvs = in[2].present ? malloc((size_t)n * 2 * sizeof *mm->uvs) : NULL;
        mm->colors = in[3].present ? malloc((size_t)n * 4 * sizeof *mm->colors) : NULL;
        out->position_of = malloc((size_t)n * sizeof *out->position_of);
        if (!mm->positions || (in[1].present && !mm->normals) || (in[2].present && !mm->uvs) ||
            (in[3].present && !mm->colors) || !out->position_of)
            r = oom(c);
        uint32_t channels = in[3].src.stride >= 4 ? 4 : 3; /* RGB or RGBA */
        for (uint32_t v = 0; v < n && !r; v++) {
            const uint32_t *key = &t.keys[(size_t)v * INPUTS];
            out->position_of[v] = key[0];
            for (int k = 0; k < 3; k++)
                mm->positions[v * 3 + k] = (float)in[0].src.v[(size_t)key[0] * in[0].src.stride + (size_t)k];
            for (int k = 0; k < 3 && mm->normals; k++)
                mm->normals[v * 3 + k] = (float)in[1].src.v[(size_t)key[1] * in[1].src.stride + (size_t)k];
            for (int k = 0; k < 2 && mm->uvs; k++)
                mm->uvs[v * 2 + k] = (float)in[2].src.v[(size_t)key[2] * in[2].src.stride + (size_t)k];
            for (uint32_t k = 0; k < 4 && mm->colors; k++) /* sRGB: made linear below */
                mm->colors[(size_t)v * 4 + k] =
                    k < channels ? (float)in[3].src.v[(size_t)key[3] * in[3].src.stride + k] : 1.0f;
        }
        if (!r && mm->colors)
            raw_colors_from_srgb(mm->colors, 4, n, mm->colors);
    }
    free(t.slots);
    free(t.keys);
    inputs_free(in);
    if (!r && !(out->mesh.name = raw_strdup(geometry)))
        r = oom(c);
    *skip = !r && out->mesh.index_count == 0;
    return r;
}

static void prim_free(prim *p)
{
    raw_mesh_free(&p->mesh);
    free(p->position_of);
    memset(p, 0, sizeof *p);
}

/* ---- skins ---------------------------------------------------------------------------- */

static bool descends(const raw_model *m, uint32_t node, uint32_t root)
{
    for (int32_t n = (int32_t)node; n >= 0; n = m->node_parents[n])
        if ((uint32_t)n == root)
            return true;
    return false;
}

static bool node_attr_is(const xmlNode *el, const char *name, const char *value)
{
    char buf[512];
    return el && attr(el, name, buf, sizeof buf) && strcmp(buf, value) == 0;
}

/* The node a skin's joint names: by SID under the instance's <skeleton> roots (COLLADA's
 * rule), else by SID anywhere, else by id, else by name (what exporters that ignore SIDs
 * mean). `by_id`: an IDREF_array names ids. -1: none. */
static int32_t resolve_joint(const collada *c, const char *name, const uint32_t *roots, uint32_t root_count, bool by_id)
{
    const raw_model *m = c->m;
    static const char *const keys[] = {"sid", "sid", "id", "name"};
    for (int pass = by_id ? 2 : 0; pass < 4; pass++) {
        for (uint32_t i = 1; i < m->node_count; i++) {
            if (!node_attr_is(c->node_el[i], keys[pass], name))
                continue;
            bool under = pass > 0 || root_count == 0;
            for (uint32_t r = 0; r < root_count && !under; r++)
                under = descends(m, i, roots[r]);
            if (under)
                return (int32_t)i;
        }
    }
    return -1;
}

static uint32_t first_node_of(const collada *c, const xmlNode *el)
{
    for (uint32_t i = 1; i < c->m->node_count; i++)
        if (c->node_el[i] == el)
            return i;
    return UINT32_MAX;
}

typedef struct skin_data {
    int32_t skin; /* raw skin */
    uint32_t position_count;
    uint32_t *first, *count; /* a position: its influences in joints/weights */
    uint32_t *joints;
    float *weights;
    uint32_t max_influences;
} skin_data;

static void skin_data_free(skin_data *s)
{
    free(s->first);
    free(s->count);
    free(s->joints);
    free(s->weights);
}

/* A row-major 4x4 matrix in an element's text (<bind_shape_matrix>). */
static sinew_result read_matrix16(collada *c, xmlNode *el, dmat *out)
{
    double v[16];
    uint32_t n;
    sinew_result r = parse_numbers(c, el, v, 16, &n);
    if (r)
        return r;
    if (n != 16)
        return fail(c, el, "%u numbers, not a 4x4 matrix", n);
    *out = dmat_from_rows(v);
    return SINEW_OK;
}

#define DAE_MAX_SKELETONS 64

/* The nodes an instance's <skeleton> elements name (those that name a node of the scene). */
static uint32_t skeleton_roots(const collada *c, const xmlNode *instance, uint32_t roots[DAE_MAX_SKELETONS])
{
    uint32_t root_count = 0;
    for (xmlNode *k = instance->children; k; k = k->next) {
        if (!named(k, "skeleton") || root_count == DAE_MAX_SKELETONS)
            continue;
        xmlChar *url = xmlNodeGetContent(k);
        xmlNode *el = by_url(c, url ? (const char *)url : "");
        xmlFree(url);
        uint32_t at = el ? first_node_of(c, el) : UINT32_MAX;
        if (at != UINT32_MAX)
            roots[root_count++] = at;
    }
    return root_count;
}

static sinew_result read_skin(collada *c, const uint32_t *roots, uint32_t root_count, xmlNode *skin, skin_data *out)
{
    raw_model *m = c->m;
    memset(out, 0, sizeof *out);
    out->skin = -1;
    dmat bind_shape = dmat_identity();
    xmlNode *bsm = child(skin, "bind_shape_matrix");
    sinew_result r;
    if (bsm && (r = read_matrix16(c, bsm, &bind_shape)))
        return r;
    xmlNode *joints_el = child(skin, "joints");
    source names = {0}, ibm = {0};
    for (xmlNode *k = joints_el ? joints_el->children : NULL; k; k = k->next) {
        char semantic[64];
        if (!named(k, "input"))
            continue;
        attr(k, "semantic", semantic, sizeof semantic);
        source *s = strcmp(semantic, "JOINT") == 0 ? &names : strcmp(semantic, "INV_BIND_MATRIX") == 0 ? &ibm : NULL;
        xmlNode *src = by_url_attr(c, k, "source");
        if (s && !s->count && !s->names && !s->v && (r = read_source(c, src, s))) {
            source_free(&names);
            source_free(&ibm);
            return r;
        }
    }
    r = SINEW_OK;
    if (!names.names)
        r = fail(c, skin, "<joints> has no JOINT names");
    else if (!ibm.v || ibm.stride < 16 || ibm.count < names.count)
        r = fail(c, skin, "<joints> needs an INV_BIND_MATRIX for each of its %u joints", names.count);
    else if (names.count == 0)
        r = fail(c, skin, "<joints> names no joint");
    else if (names.count > SINEW_MAX_JOINTS)
        r = fail_kind(c, skin, SINEW_ERROR_LIMIT, "%u joints (sinew takes at most %d)", names.count, SINEW_MAX_JOINTS);
    raw_skin *skins = r ? NULL : realloc(m->skins, (m->skin_count + 1) * sizeof *skins);
    if (!r && !skins)
        r = oom(c);
    if (!r) {
        m->skins = skins;
        raw_skin *rs = &m->skins[m->skin_count++];
        memset(rs, 0, sizeof *rs);
        rs->joints = calloc(names.count, sizeof *rs->joints);
        rs->inverse_bind = calloc(names.count, sizeof *rs->inverse_bind);
        if (!rs->joints || !rs->inverse_bind)
            r = oom(c);
        rs->joint_count = r ? 0 : names.count;
        out->skin = (int32_t)m->skin_count - 1;
        char array_kind[32] = "";
        xmlNode *src = NULL;
        for (xmlNode *k = joints_el->children; k && !src; k = k->next)
            if (named(k, "input") && node_attr_is(k, "semantic", "JOINT"))
                src = by_url_attr(c, k, "source");
        for (xmlNode *k = src ? src->children : NULL; k; k = k->next)
            if (k->type == XML_ELEMENT_NODE && strstr((const char *)k->name, "_array"))
                snprintf(array_kind, sizeof array_kind, "%s", (const char *)k->name);
        for (uint32_t j = 0; j < rs->joint_count && !r; j++) {
            int32_t node = resolve_joint(c, names.names[j], roots, root_count, strcmp(array_kind, "IDREF_array") == 0);
            if (node < 0) {
                r = fail(c, skin, "joint \"%s\" is not a node of the scene", names.names[j]);
                break;
            }
            rs->joints[j] = (uint32_t)node;
            dmat inv = dmat_from_rows(&ibm.v[(size_t)j * ibm.stride]);
            dmat both = dmat_mul(&inv, &bind_shape);
            dmat_to_float(&both, &rs->inverse_bind[j]);
        }
    }
    uint32_t joint_count = names.count;
    source_free(&names);
    source_free(&ibm);
    if (r)
        return r;
    /* Influences by position */
    xmlNode *vw = child(skin, "vertex_weights");
    long count = attr_long(vw, "count", -1);
    if (!vw || count < 0 || count > (long)(1u << 28))
        return fail(c, vw ? vw : skin, "no <vertex_weights count>");
    int joint_offset = -1, weight_offset = -1, stride = 0;
    source weights = {0};
    for (xmlNode *k = vw->children; k && !r; k = k->next) {
        if (!named(k, "input"))
            continue;
        long off = attr_long(k, "offset", 0);
        if (off < 0 || off > 64)
            return fail(c, k, "offset %ld", off);
        stride = stride > (int)off + 1 ? stride : (int)off + 1;
        if (node_attr_is(k, "semantic", "JOINT"))
            joint_offset = (int)off;
        else if (node_attr_is(k, "semantic", "WEIGHT") && !weights.v)
            r = read_source(c, by_url_attr(c, k, "source"), &weights);
    }
    for (xmlNode *k = vw->children; k && !r && weight_offset < 0; k = k->next)
        if (named(k, "input") && node_attr_is(k, "semantic", "WEIGHT"))
            weight_offset = (int)attr_long(k, "offset", 0);
    if (!r && (joint_offset < 0 || weight_offset < 0 || !weights.v))
        r = fail(c, vw, "needs JOINT and WEIGHT inputs");
    double *vcount = NULL, *v = NULL;
    uint32_t nvc = 0, nv = 0;
    if (!r)
        r = numbers_of(c, child(vw, "vcount"), &vcount, &nvc);
    if (!r)
        r = numbers_of(c, child(vw, "v"), &v, &nv);
    if (!r && nvc != (uint32_t)count)
        r = fail(c, vw, "<vcount> has %u numbers for %ld vertices", nvc, count);
    out->position_count = (uint32_t)count;
    if (!r) {
        out->first = calloc((size_t)count + 1, sizeof *out->first);
        out->count = calloc((size_t)count + 1, sizeof *out->count);
        out->joints = malloc(((size_t)nv / (size_t)(stride ? stride : 1) + 1) * sizeof *out->joints);
        out->weights = malloc(((size_t)nv / (size_t)(stride ? stride : 1) + 1) * sizeof *out->weights);
        if (!out->first || !out->count || !out->joints || !out->weights)
            r = oom(c);
    }
    size_t at = 0, total = 0;
    uint32_t bind_shape_weights = 0;
    for (long i = 0; i < count && !r; i++) {
        double n = vcount[i];
        if (!(n >= 0 && n == floor(n) && n <= nv) || at + (size_t)n * (size_t)stride > nv) {
            r = fail(c, vw, "vertex %ld: %g influences, more than <v> holds", i, n);
            break;
        }
        out->first[i] = (uint32_t)total;
        for (uint32_t k = 0; k < (uint32_t)n; k++, at += (size_t)stride) {
            double j = v[at + (size_t)joint_offset], w = v[at + (size_t)weight_offset];
            if (!(w >= 0 && w < weights.count) || w != floor(w)) {
                r = fail(c, vw, "vertex %ld: weight index %g is past the %u weights", i, w, weights.count);
                break;
            }
            if (j == -1) { /* the bind shape itself: no joint moves it */
                bind_shape_weights++;
                continue;
            }
            if (weights.v[(size_t)w * weights.stride] == 0) /* an influence that does not influence */
                continue;
            if (!(j >= 0 && j < joint_count) || j != floor(j)) {
                r = fail(c, vw, "vertex %ld: joint index %g is past the %u joints", i, j, joint_count);
                break;
            }
            out->joints[total] = (uint32_t)j;
            out->weights[total] = (float)weights.v[(size_t)w * weights.stride];
            total++;
            out->count[i]++;
        }
        if (out->count[i] > out->max_influences)
            out->max_influences = out->count[i];
    }
    free(vcount);
    free(v);
    source_free(&weights);
    if (!r && bind_shape_weights &&
        !raw_model_warn(m, "%s: %u influences name the bind shape (joint -1); they are left out", c->path,
                        bind_shape_weights))
        r = oom(c);
    return r;
}

/* A primitive's influences from its skin, by the position each vertex came from. */
static sinew_result apply_skin(collada *c, const skin_data *s, prim *p, xmlNode *where)
{
    raw_mesh *mm = &p->mesh;
    uint32_t slots = s->max_influences ? s->max_influences : 1;
    mm->joints = calloc((size_t)mm->vertex_count * slots, sizeof *mm->joints);
    mm->weights = calloc((size_t)mm->vertex_count * slots, sizeof *mm->weights);
    if (!mm->joints || !mm->weights)
        return oom(c);
    mm->influence_count = slots;
    mm->skin = s->skin;
    for (size_t i = 0; i < (size_t)mm->vertex_count * slots; i++)
        mm->joints[i] = UINT32_MAX; /* unused: a vertex with none follows the mesh's node */
    for (uint32_t v = 0; v < mm->vertex_count; v++) {
        uint32_t pos = p->position_of[v];
        if (pos >= s->position_count)
            return fail(c, where, "position %u has no entry in <vertex_weights> (%u)", pos, s->position_count);
        for (uint32_t k = 0; k < s->count[pos]; k++) {
            mm->joints[(size_t)v * slots + k] = s->joints[s->first[pos] + k];
            mm->weights[(size_t)v * slots + k] = s->weights[s->first[pos] + k];
        }
    }
    return SINEW_OK;
}

/* ---- morphs --------------------------------------------------------------------------- */

static bool is_primitive(const xmlNode *k)
{
    return k->type == XML_ELEMENT_NODE && !named(k, "source") && !named(k, "vertices") && !named(k, "extra");
}

/* A <morph>: its target <geometry>s and their weights where no clip animates them. Both
 * methods read a target as a whole shape (the offset is target - base), as exporters write
 * them and as Blender, Maya and Assimp read them; a RELATIVE target that lies nearer zero
 * than the base shape is taken as the offsets the specification's formula adds. */
typedef struct morph_data {
    xmlNode *controller, *morph;
    bool relative;
    source ids, weights;
    xmlNode **geometry;    /* a target: its <geometry> */
    uint32_t count, first; /* targets; the model channel of target 0 */
} morph_data;

static void morph_data_free(morph_data *d)
{
    source_free(&d->ids);
    source_free(&d->weights);
    free(d->geometry);
}

/* Reads `controller`'s <morph> and gives each target a model channel (named as its geometry,
 * its default weight the MORPH_WEIGHT source's). */
static sinew_result read_morph(collada *c, xmlNode *controller, morph_data *d)
{
    memset(d, 0, sizeof *d);
    d->controller = controller;
    d->morph = child(controller, "morph");
    char method[64] = "NORMALIZED";
    attr(d->morph, "method", method, sizeof method);
    if (strcmp(method, "NORMALIZED") && strcmp(method, "RELATIVE"))
        return fail(c, d->morph, "method \"%s\" is not NORMALIZED or RELATIVE", method);
    d->relative = strcmp(method, "RELATIVE") == 0;
    xmlNode *targets = child(d->morph, "targets");
    sinew_result r = SINEW_OK;
    for (xmlNode *k = targets ? targets->children : NULL; k && !r; k = k->next) {
        char semantic[64] = "";
        if (!named(k, "input") || !attr(k, "semantic", semantic, sizeof semantic))
            continue;
        source *into = strcmp(semantic, "MORPH_TARGET") == 0   ? &d->ids
                       : strcmp(semantic, "MORPH_WEIGHT") == 0 ? &d->weights
                                                               : NULL;
        if (into && !into->count && !into->names && !into->v) {
            xmlNode *src = by_url_attr(c, k, "source");
            r = src ? read_source(c, src, into) : fail(c, k, "source names nothing in this file");
        }
    }
    if (r)
        return r;
    if (!d->ids.names)
        return fail(c, d->morph, "<targets> has no MORPH_TARGET input of geometry ids");
    if (d->weights.count && (!d->weights.v || d->weights.count != d->ids.count))
        return fail(c, d->morph, "%u MORPH_WEIGHT values for %u targets", d->weights.count, d->ids.count);
    d->count = d->ids.count;
    if (!(d->geometry = calloc(d->count + 1, sizeof *d->geometry)))
        return oom(c);
    for (uint32_t t = 0; t < d->count; t++) {
        char url[600];
        snprintf(url, sizeof url, "#%s", d->ids.names[t * d->ids.stride]);
        d->geometry[t] = by_url(c, url);
        if (!named(d->geometry[t], "geometry") || !child(d->geometry[t], "mesh"))
            return fail(c, d->morph, "target \"%s\" names no <geometry> <mesh> of this file", url + 1);
    }
    raw_model *m = c->m;
    raw_morph_channel *grown = realloc(m->morph_channels, (m->morph_channel_count + d->count + 1) * sizeof *grown);
    morph_use *uses = realloc(c->morphs, (c->morph_count + 1) * sizeof *uses);
    if (grown)
        m->morph_channels = grown;
    if (uses)
        c->morphs = uses;
    if (!grown || !uses)
        return oom(c);
    d->first = m->morph_channel_count;
    for (uint32_t t = 0; t < d->count; t++) {
        char name[512];
        if (!attr(d->geometry[t], "name", name, sizeof name) || !*name)
            attr(d->geometry[t], "id", name, sizeof name);
        raw_morph_channel *ch = &m->morph_channels[m->morph_channel_count];
        ch->default_weight = d->weights.v ? (float)d->weights.v[(size_t)t * d->weights.stride] : 0.0f;
        if (!(ch->name = raw_strdup(name)))
            return oom(c);
        m->morph_channel_count++;
    }
    c->morphs[c->morph_count++] = (morph_use){controller, d->first, d->count};
    return SINEW_OK;
}

/* The `ordinal`-th primitive element of a <mesh> (as bound_materials counts them), or NULL. */
static xmlNode *nth_primitive(xmlNode *mesh, uint32_t ordinal)
{
    for (xmlNode *k = mesh ? mesh->children : NULL; k; k = k->next)
        if (is_primitive(k) && ordinal-- == 0)
            return k;
    return NULL;
}

/* A target's positions (and normals) for the vertices of `p`: from the target's primitive of
 * the same ordinal when it makes the same vertices from the same positions, else its
 * POSITION source read by each vertex's position index (a target written as <vertices>
 * only, or with other normals). *normals is NULL when the target gives none that match. */
static sinew_result target_shape(collada *c, const morph_data *d, uint32_t t, uint32_t ordinal, const prim *p,
                                 float **positions, float **normals)
{
    *positions = *normals = NULL;
    xmlNode *mesh = child(d->geometry[t], "mesh"), *el = nth_primitive(mesh, ordinal);
    const char *id = d->ids.names[t * d->ids.stride];
    uint32_t n = p->mesh.vertex_count;
    if (el) {
        prim tp;
        bool skip = false;
        sinew_result r = read_primitive(c, el, id, &tp, &skip);
        if (r) {
            prim_free(&tp); /* what it read before it failed */
            return r;
        }
        if (!skip && tp.mesh.vertex_count == n &&
            memcmp(tp.position_of, p->position_of, n * sizeof *p->position_of) == 0) {
            *positions = tp.mesh.positions, tp.mesh.positions = NULL;
            if (p->mesh.normals)
                *normals = tp.mesh.normals, tp.mesh.normals = NULL;
        }
        prim_free(&tp);
        if (*positions)
            return SINEW_OK;
    }
    xmlNode *vertices = child(mesh, "vertices"), *src = NULL;
    for (xmlNode *k = vertices ? vertices->children : NULL; k && !src; k = k->next)
        if (named(k, "input") && node_attr_is(k, "semantic", "POSITION"))
            src = by_url_attr(c, k, "source");
    if (!src)
        return fail(c, d->geometry[t], "morph target \"%s\" has no POSITION source", id);
    source pos;
    sinew_result r = read_source(c, src, &pos);
    if (r)
        return r;
    uint32_t need = 0;
    for (uint32_t v = 0; v < n; v++)
        need = p->position_of[v] + 1 > need ? p->position_of[v] + 1 : need;
    if (!pos.v || pos.stride < 3 || pos.count < need) {
        r = fail(c, src, "morph target \"%s\" has %u positions where its base mesh has %u", id, pos.v ? pos.count : 0,
                 need);
    } else if (!(*positions = malloc(((size_t)n * 3 + 1) * sizeof **positions))) {
        r = oom(c);
    } else {
        for (uint32_t v = 0; v < n; v++)
            for (int k = 0; k < 3; k++)
                (*positions)[v * 3 + k] = (float)pos.v[(size_t)p->position_of[v] * pos.stride + (size_t)k];
    }
    source_free(&pos);
    return r;
}

/* The morph's targets as targets of the raw mesh of primitive `ordinal` (one a target; the
 * mesh's channel t is target t, at model channel d->first + t). */
static sinew_result add_targets(collada *c, const morph_data *d, uint32_t ordinal, prim *p)
{
    raw_mesh *mm = &p->mesh;
    uint32_t n = mm->vertex_count;
    if (!(mm->targets = calloc(d->count + 1, sizeof *mm->targets)))
        return oom(c);
    sinew_result r = SINEW_OK;
    for (uint32_t t = 0; t < d->count && !r; t++) {
        float *shape = NULL, *normals = NULL;
        if ((r = target_shape(c, d, t, ordinal, p, &shape, &normals)))
            break;
        raw_morph_target *tg = &mm->targets[mm->target_count++];
        tg->channel = t;
        tg->full_weight = 1.0f;
        tg->delta_count = n;
        tg->positions = shape;
        tg->normals = normals;
        tg->vertices = malloc(((size_t)n + 1) * sizeof *tg->vertices);
        char name[512];
        if (!attr(d->geometry[t], "name", name, sizeof name) || !*name)
            attr(d->geometry[t], "id", name, sizeof name);
        if (!tg->vertices || !(tg->name = raw_strdup(name))) {
            r = oom(c);
            break;
        }
        double to_base = 0, to_zero = 0;
        for (size_t i = 0; i < (size_t)n * 3; i++) {
            to_base += ((double)shape[i] - mm->positions[i]) * ((double)shape[i] - mm->positions[i]);
            to_zero += (double)shape[i] * shape[i];
        }
        bool offsets = d->relative && to_zero < to_base; /* the specification's RELATIVE: base + w * target */
        for (uint32_t v = 0; v < n; v++) {
            tg->vertices[v] = v;
            for (int k = 0; k < 3 && !offsets; k++)
                shape[v * 3 + k] -= mm->positions[v * 3 + k];
            for (int k = 0; k < 3 && normals; k++)
                normals[v * 3 + k] -= mm->normals[v * 3 + k];
        }
    }
    return r;
}

/* ---- instances ------------------------------------------------------------------------ */

static sinew_result add_mesh(collada *c, prim *p, uint32_t node, uint32_t morph_first)
{
    raw_model *m = c->m;
    raw_mesh *meshes = realloc(m->meshes, (m->mesh_count + 1) * sizeof *meshes);
    sinew_instance *inst = realloc(m->instances, (m->instance_count + 1) * sizeof *inst);
    if (meshes)
        m->meshes = meshes;
    if (inst)
        m->instances = inst;
    if (!meshes || !inst)
        return oom(c);
    m->meshes[m->mesh_count] = p->mesh;
    m->instances[m->instance_count++] = (sinew_instance){m->mesh_count++, node, morph_first};
    free(p->position_of);
    memset(p, 0, sizeof *p);
    return SINEW_OK;
}

/* An <instance_geometry> or <instance_controller> already turned into meshes. Another
 * instance of the same geometry with the same materials bound draws those meshes again at
 * its own node; of the same controller bound to the same skeleton, it would draw the same
 * skinned meshes in the same place (skinned meshes ignore their node), so it adds nothing. */
typedef struct geometry_use {
    xmlNode *geometry;  /* <geometry> or <controller> */
    int32_t *materials; /* a primitive element of the <mesh>: its bound material */
    uint32_t prim_count, first_mesh, mesh_count;
    uint32_t roots[DAE_MAX_SKELETONS], root_count; /* a controller's <skeleton> nodes */
} geometry_use;

typedef struct geometry_uses {
    geometry_use *uses;
    uint32_t count;
} geometry_uses;

/* The materials `inst` binds to its mesh's primitives, in order. */
static sinew_result bound_materials(collada *c, material_map *map, xmlNode *inst, xmlNode *mesh, geometry_use *use)
{
    for (xmlNode *k = mesh->children; k; k = k->next)
        use->prim_count += is_primitive(k);
    if (!(use->materials = malloc((use->prim_count ? use->prim_count : 1) * sizeof *use->materials)))
        return oom(c);
    uint32_t i = 0;
    for (xmlNode *k = mesh->children; k; k = k->next) {
        if (!is_primitive(k))
            continue;
        char symbol[256] = "";
        sinew_result r = attr(k, "material", symbol, sizeof symbol) && *symbol
                             ? bound_material(c, map, inst, symbol, &use->materials[i])
                             : (use->materials[i] = -1, SINEW_OK);
        if (r)
            return r;
        i++;
    }
    return SINEW_OK;
}

/* Draws an earlier use's meshes at `node` when `use` binds the same; true when it did. */
static sinew_result reuse_geometry(collada *c, const geometry_uses *uses, const geometry_use *use, uint32_t node,
                                   bool *reused)
{
    *reused = false;
    for (uint32_t i = 0; i < uses->count && !*reused; i++) {
        const geometry_use *u = &uses->uses[i];
        if (u->geometry != use->geometry || u->prim_count != use->prim_count ||
            memcmp(u->materials, use->materials, use->prim_count * sizeof *use->materials) != 0 ||
            u->root_count != use->root_count || memcmp(u->roots, use->roots, use->root_count * sizeof *use->roots))
            continue;
        *reused = true;
        if (named(use->geometry, "controller"))
            break;
        raw_model *m = c->m;
        sinew_instance *inst = realloc(m->instances, (m->instance_count + u->mesh_count) * sizeof *inst);
        if (!inst)
            return oom(c);
        m->instances = inst;
        for (uint32_t k = 0; k < u->mesh_count; k++)
            m->instances[m->instance_count++] = (sinew_instance){u->first_mesh + k, node, 0};
    }
    return SINEW_OK;
}

static sinew_result read_instance(collada *c, material_map *map, geometry_uses *uses, const pending *pi)
{
    xmlNode *inst = pi->instance, *target = by_url_attr(c, inst, "url");
    xmlNode *skin = NULL, *geometry = target, *morph = NULL;
    if (named(inst, "instance_controller")) {
        if (!named(target, "controller"))
            return fail(c, inst, "url does not name a <controller> of this file");
        skin = child(target, "skin");
        morph = child(target, "morph") ? target : NULL;
        xmlNode *base = by_url_attr(c, skin ? skin : child(target, "morph"), "source");
        if (skin && named(base, "controller") && child(base, "morph")) /* a skin over a morph */
            morph = base, base = by_url_attr(c, child(base, "morph"), "source");
        geometry = base;
    }
    if (!named(geometry, "geometry"))
        return fail(c, inst, "names no <geometry> of this file");
    xmlNode *mesh = child(geometry, "mesh");
    char name[512];
    if (!attr(geometry, "name", name, sizeof name) || !*name)
        attr(geometry, "id", name, sizeof name);
    if (!mesh)
        return raw_model_warn(c->m, "%s: geometry \"%s\" is not a <mesh> (splines and convex meshes are not drawn)",
                              c->path, name)
                   ? SINEW_OK
                   : oom(c);
    geometry_use use = {.geometry = skin || morph ? target : geometry, .first_mesh = c->m->mesh_count};
    if (skin)
        use.root_count = skeleton_roots(c, inst, use.roots);
    bool reused = false;
    sinew_result r = bound_materials(c, map, inst, mesh, &use);
    if (!r && !morph) /* a morph drawn again has weights of its own */
        r = reuse_geometry(c, uses, &use, pi->node, &reused);
    if (r || reused) {
        free(use.materials);
        return r;
    }
    skin_data sd = {.skin = -1};
    morph_data md = {0};
    r = skin ? read_skin(c, use.roots, use.root_count, skin, &sd) : SINEW_OK;
    if (!r && morph)
        r = read_morph(c, morph, &md);
    uint32_t lines = 0, index = 0;
    for (xmlNode *k = mesh->children; k && !r; k = k->next) {
        if (!is_primitive(k))
            continue;
        uint32_t ordinal = index;
        int32_t material = use.materials[index++];
        prim p;
        bool skip = false;
        r = read_primitive(c, k, name, &p, &skip);
        if (!r && skip) {
            lines += named(k, "lines") || named(k, "linestrips");
            prim_free(&p);
            continue;
        }
        p.mesh.material = material;
        if (!r && skin)
            r = apply_skin(c, &sd, &p, k);
        if (!r && morph)
            r = add_targets(c, &md, ordinal, &p);
        if (!r)
            r = add_mesh(c, &p, pi->node, morph ? md.first : 0);
        prim_free(&p);
    }
    skin_data_free(&sd);
    morph_data_free(&md);
    use.mesh_count = c->m->mesh_count - use.first_mesh;
    if (!r) {
        geometry_use *grown = realloc(uses->uses, (uses->count + 1) * sizeof *grown);
        if (grown) {
            uses->uses = grown;
            uses->uses[uses->count++] = use;
            use.materials = NULL;
        } else {
            r = oom(c);
        }
    }
    free(use.materials);
    if (!r && lines &&
        !raw_model_warn(c->m, "%s: geometry \"%s\" has %u line sets; sinew draws triangles only", c->path, name, lines))
        r = oom(c);
    return r;
}

static sinew_result build_meshes(collada *c)
{
    material_map map = {0};
    geometry_uses uses = {0};
    sinew_result r = SINEW_OK;
    for (uint32_t i = 0; i < c->pending_count && !r; i++)
        r = read_instance(c, &map, &uses, &c->pending[i]);
    for (uint32_t i = 0; i < uses.count; i++)
        free(uses.uses[i].materials);
    free(uses.uses);
    free(map.elements);
    return r;
}

/* ---- animations ----------------------------------------------------------------------- */

static void curve_free(curve *k)
{
    free(k->times);
    free(k->values);
    free(k->interp);
    free(k->in_tan);
    free(k->out_tan);
}

/* The transform element a channel target ("node/sid", ".X", "(i)(j)") names, and which of
 * its numbers. */
static sinew_result parse_target(collada *c, xmlNode *channel, const char *target, curve *out)
{
    char buf[1024];
    snprintf(buf, sizeof buf, "%s", target);
    char *slash = strchr(buf, '/');
    if (!slash)
        return fail(c, channel, "target \"%s\" has no \"/\"", target);
    *slash = 0;
    char url[1100];
    snprintf(url, sizeof url, "#%s", buf);
    xmlNode *node = by_url(c, url);
    if (named(node, "controller") && child(node, "morph")) { /* "morph/weights(i)": weight i, or all of them */
        out->morph = node;
        const char *index = strrchr(slash + 1, '(');
        int i = -1;
        if (index && (sscanf(index, "(%d)", &i) != 1 || i < 0))
            return fail(c, channel, "target \"%s\": no weight %s of a <morph>", target, index);
        out->first = index ? i : 0;
        out->count = index ? 1 : 0; /* 0: as many as the sampler's OUTPUT gives a key */
        return SINEW_OK;
    }
    /* Ids should be unique; 3ds Max gives a camera and its node the same one. */
    for (uint32_t i = 1; !named(node, "node") && i < c->m->node_count; i++)
        if (node_attr_is(c->node_el[i], "id", buf))
            node = c->node_el[i];
    char *sid = strrchr(slash + 1, '/');
    sid = sid ? sid + 1 : slash + 1;
    char *member = sid + strcspn(sid, ".(");
    char mem[64];
    snprintf(mem, sizeof mem, "%s", member);
    *member = 0;
    out->node = named(node, "node") ? node : NULL;
    out->xform = NULL;
    for (xmlNode *k = out->node ? out->node->children : NULL; k && !out->xform; k = k->next)
        if (element_size(k) && node_attr_is(k, "sid", sid))
            out->xform = k;
    if (!out->xform)
        return SINEW_OK; /* a camera, a light, a material: not sinew's to play */
    int size = element_size(out->xform);
    out->first = 0;
    out->count = size;
    if (mem[0] == '.') {
        const char *m = mem + 1;
        int at = strcmp(m, "X") == 0 || strcmp(m, "S") == 0       ? 0
                 : strcmp(m, "Y") == 0 || strcmp(m, "T") == 0     ? 1
                 : strcmp(m, "Z") == 0 || strcmp(m, "P") == 0     ? 2
                 : strcmp(m, "ANGLE") == 0 || strcmp(m, "W") == 0 ? 3
                                                                  : -1;
        if (at < 0 || at >= size)
            return fail(c, channel, "target \"%s\": member %s of a <%s>", target, m, (const char *)out->xform->name);
        out->first = at, out->count = 1;
    } else if (mem[0] == '(') {
        int i = -1, j = -1;
        int got = sscanf(mem, "(%d)(%d)", &i, &j);
        int at = got == 2 && size == 16 ? i * 4 + j : got >= 1 ? i : -1;
        if (got == 2 && size == 16 && (i < 0 || i > 3 || j < 0 || j > 3))
            at = -1;
        if (at < 0 || at >= size)
            return fail(c, channel, "target \"%s\": no element %s of a <%s>", target, mem,
                        (const char *)out->xform->name);
        out->first = at, out->count = 1;
    }
    return SINEW_OK;
}

static sinew_result read_channel(collada *c, xmlNode *channel)
{
    char target[1024];
    attr(channel, "target", target, sizeof target);
    curve k = {0};
    k.channel = channel;
    sinew_result r = parse_target(c, channel, target, &k);
    if (r || (!k.xform && !k.morph))
        return r;
    xmlNode *sampler = by_url_attr(c, channel, "source");
    if (!named(sampler, "sampler"))
        return fail(c, channel, "source does not name a <sampler>");
    source in = {0}, out = {0}, how = {0}, tin = {0}, tout = {0};
    for (xmlNode *i = sampler->children; i && !r; i = i->next) {
        char semantic[64];
        if (!named(i, "input"))
            continue;
        attr(i, "semantic", semantic, sizeof semantic);
        source *s = strcmp(semantic, "INPUT") == 0           ? &in
                    : strcmp(semantic, "OUTPUT") == 0        ? &out
                    : strcmp(semantic, "INTERPOLATION") == 0 ? &how
                    : strcmp(semantic, "IN_TANGENT") == 0    ? &tin
                    : strcmp(semantic, "OUT_TANGENT") == 0   ? &tout
                                                             : NULL;
        if (s && !s->count)
            r = read_source(c, by_url_attr(c, i, "source"), s);
    }
    uint32_t n = in.count;
    if (!r && (!in.v || !out.v))
        r = fail(c, sampler, "needs INPUT and OUTPUT numbers");
    if (!r && k.morph && k.count == 0)
        k.count = (int)out.stride;
    if (!r && (out.count != n || out.stride != (uint32_t)k.count))
        r = fail(c, sampler, "%u outputs of %u numbers for %u keys of a target of %d numbers", out.count, out.stride, n,
                 k.count);
    if (!r && (how.count || how.names || how.v) && (how.count != n || !how.names))
        r = fail(c, sampler, "INTERPOLATION has %u names for %u keys", how.count, n);
    bool tangents = false;
    if (!r && n) {
        k.keys = n;
        k.times = malloc(n * sizeof *k.times);
        k.values = malloc((size_t)n * (size_t)k.count * sizeof *k.values);
        k.interp = malloc(n);
        if (!k.times || !k.values || !k.interp)
            r = oom(c);
    }
    for (uint32_t i = 0; i < n && !r; i++) {
        k.times[i] = in.v[(size_t)i * in.stride];
        if (i > 0 && k.times[i] < k.times[i - 1])
            r = fail(c, sampler, "key %u at %g s comes before the key before it", i, k.times[i]);
        memcpy(&k.values[(size_t)i * (size_t)k.count], &out.v[(size_t)i * out.stride],
               (size_t)k.count * sizeof *k.values);
        const char *name = how.names ? how.names[i] : "LINEAR";
        k.interp[i] = strcmp(name, "STEP") == 0      ? KEY_STEP
                      : strcmp(name, "BEZIER") == 0  ? KEY_BEZIER
                      : strcmp(name, "HERMITE") == 0 ? KEY_HERMITE
                                                     : KEY_LINEAR;
        if (strcmp(name, "LINEAR") && strcmp(name, "STEP") && strcmp(name, "BEZIER") && strcmp(name, "HERMITE") &&
            strcmp(name, "CARDINAL") && strcmp(name, "BSPLINE"))
            r = fail(c, sampler, "interpolation \"%s\"", name);
        tangents |= k.interp[i] >= KEY_BEZIER;
    }
    if (!r && tangents) {
        bool two = tin.stride == (uint32_t)k.count * 2 && tout.stride == (uint32_t)k.count * 2;
        bool one = tin.stride == (uint32_t)k.count && tout.stride == (uint32_t)k.count;
        if (!tin.v || !tout.v || tin.count != n || tout.count != n || !(one || two))
            r = fail(c, sampler, "BEZIER/HERMITE keys need IN_TANGENT and OUT_TANGENT for each key");
        k.tdim = two ? 2 : 1;
        size_t size = (size_t)n * (size_t)k.count * (size_t)k.tdim;
        k.in_tan = r ? NULL : malloc(size * sizeof *k.in_tan);
        k.out_tan = r ? NULL : malloc(size * sizeof *k.out_tan);
        if (!r && (!k.in_tan || !k.out_tan))
            r = oom(c);
        /* COLLADA 1.4.1 gives BEZIER control points as (time, value) pairs; one number a
         * tangent is older exporters' habit with no agreed meaning (FCollada reads offsets,
         * some exporters wrote slopes, ColladaMaya's clip test writes 6875.42 where a linear
         * ramp needs 120, its offset converted to degrees twice). Those keys play linearly,
         * as three.js and Assimp play them, with a warning. */
        bool flattened = false;
        for (uint32_t i = 0; i < n && !r && !two; i++)
            if (k.interp[i] == KEY_BEZIER) {
                k.interp[i] = KEY_LINEAR;
                flattened = true;
            }
        c->bezier_1d += flattened;
        for (uint32_t i = 0; i < n && !r; i++) {
            memcpy(&k.in_tan[(size_t)i * (size_t)k.count * (size_t)k.tdim], &tin.v[(size_t)i * tin.stride],
                   (size_t)k.count * (size_t)k.tdim * sizeof(double));
            memcpy(&k.out_tan[(size_t)i * (size_t)k.count * (size_t)k.tdim], &tout.v[(size_t)i * tout.stride],
                   (size_t)k.count * (size_t)k.tdim * sizeof(double));
        }
    }
    source_free(&in);
    source_free(&out);
    source_free(&how);
    source_free(&tin);
    source_free(&tout);
    if (!r && n && c->curve_count == c->curve_cap) {
        uint32_t cap = c->curve_cap ? c->curve_cap * 2 : 32;
        curve *grown = realloc(c->curves, cap * sizeof *grown);
        if (!grown)
            r = oom(c);
        else
            c->curves = grown, c->curve_cap = cap;
    }
    if (!r && n)
        c->curves[c->curve_count++] = k;
    else
        curve_free(&k);
    return r;
}

/* The channels of every <animation> under `parent` (depth 0: a <library_animations>), nested
 * or not. */
static sinew_result read_animations(collada *c, xmlNode *parent, int depth)
{
    if (depth > DAE_MAX_DEPTH)
        return fail(c, parent, "animations nest deeper than %d", DAE_MAX_DEPTH);
    sinew_result r = SINEW_OK;
    for (xmlNode *a = parent ? parent->children : NULL; a && !r; a = a->next) {
        if (named(a, "animation"))
            r = read_animations(c, a, depth + 1);
        else if (named(a, "channel") && depth > 0)
            r = read_channel(c, a);
    }
    return r;
}

/* One component of a curve at time t (seconds on the file's timeline). */
static double bezier_at(double t0, double v0, double c0t, double c0v, double c1t, double c1v, double t1, double v1,
                        double t)
{
    /* x(s) is monotonic for sane tangents: bisection on s, then y(s) */
    double lo = 0, hi = 1, s = (t - t0) / (t1 - t0);
    for (int i = 0; i < 60; i++) {
        double u = 1 - s, x = u * u * u * t0 + 3 * u * u * s * c0t + 3 * u * s * s * c1t + s * s * s * t1;
        if (x < t)
            lo = s;
        else
            hi = s;
        s = (lo + hi) / 2;
    }
    double u = 1 - s;
    return u * u * u * v0 + 3 * u * u * s * c0v + 3 * u * s * s * c1v + s * s * s * v1;
}

static double curve_at(const curve *k, int comp, double t)
{
    uint32_t n = k->keys;
    int count = k->count;
    if (t <= k->times[0])
        return k->values[comp];
    if (t >= k->times[n - 1])
        return k->values[(size_t)(n - 1) * (size_t)count + (size_t)comp];
    uint32_t lo = 0, hi = n - 1;
    while (hi - lo > 1) {
        uint32_t mid = (lo + hi) / 2;
        if (k->times[mid] <= t)
            lo = mid;
        else
            hi = mid;
    }
    double t0 = k->times[lo], t1 = k->times[hi], v0 = k->values[(size_t)lo * count + comp],
           v1 = k->values[(size_t)hi * count + comp], span = t1 - t0, u = span > 0 ? (t - t0) / span : 0;
    switch (k->interp[lo]) {
    case KEY_STEP:
        return v0;
    case KEY_BEZIER: {
        size_t a = ((size_t)lo * count + comp) * (size_t)k->tdim, b = ((size_t)hi * count + comp) * (size_t)k->tdim;
        if (k->tdim == 2)
            return bezier_at(t0, v0, k->out_tan[a], k->out_tan[a + 1], k->in_tan[b], k->in_tan[b + 1], t1, v1, t);
        return bezier_at(t0, v0, t0 + span / 3, k->out_tan[a], t1 - span / 3, k->in_tan[b], t1, v1, t);
    }
    case KEY_HERMITE: {
        size_t a = ((size_t)lo * count + comp) * (size_t)k->tdim, b = ((size_t)hi * count + comp) * (size_t)k->tdim;
        double m0 = k->out_tan[a + (size_t)k->tdim - 1], m1 = k->in_tan[b + (size_t)k->tdim - 1];
        double u2 = u * u, u3 = u2 * u;
        return (2 * u3 - 3 * u2 + 1) * v0 + (u3 - 2 * u2 + u) * m0 + (-2 * u3 + 3 * u2) * v1 + (u3 - u2) * m1;
    }
    default:
        return v0 + (v1 - v0) * u;
    }
}

/* ---- clips ---------------------------------------------------------------------------- */

#define DAE_MAX_ELEMENTS 64 /* transform elements of one node that can be animated */

typedef struct node_anim {
    collada *c;
    const xmlNode *el;
    const uint32_t *curves;
    uint32_t count;
    double start; /* the clip's start on the file's timeline */
    int elements; /* transform elements whose numbers are in `file` (at most DAE_MAX_ELEMENTS) */
    double file[DAE_MAX_ELEMENTS][16];
} node_anim;

/* Reads the numbers of the node's transform elements once, before it is evaluated. */
static void node_anim_init(node_anim *a)
{
    a->elements = 0;
    for (xmlNode *el = a->el->children; el && a->elements < DAE_MAX_ELEMENTS; el = el->next) {
        if (!element_size(el))
            continue;
        uint32_t n;
        memset(a->file[a->elements], 0, sizeof a->file[0]);
        parse_numbers(a->c, el, a->file[a->elements], 16, &n);
        a->elements++;
    }
}

static dmat animated_matrix(const node_anim *a, double t)
{
    double values[DAE_MAX_ELEMENTS][16];
    const double *use[DAE_MAX_ELEMENTS] = {0};
    int k = 0;
    for (xmlNode *el = a->el->children; el && k < a->elements; el = el->next) {
        if (!element_size(el))
            continue;
        memcpy(values[k], a->file[k], sizeof values[k]);
        for (uint32_t i = 0; i < a->count; i++) {
            const curve *cv = &a->c->curves[a->curves[i]];
            if (cv->xform == el)
                for (int j = 0; j < cv->count; j++)
                    values[k][cv->first + j] = curve_at(cv, j, t);
        }
        use[k] = values[k];
        k++;
    }
    return stack_matrix(a->c, a->el, use, k);
}

static void dmat_decompose(const dmat *m, bake_trs *out)
{
    double col[3][3], s[3];
    for (int i = 0; i < 3; i++) {
        for (int j = 0; j < 3; j++)
            col[i][j] = m->m[i * 4 + j];
        s[i] = sqrt(col[i][0] * col[i][0] + col[i][1] * col[i][1] + col[i][2] * col[i][2]);
        out->t[i] = m->m[12 + i];
    }
    double det = col[0][0] * (col[1][1] * col[2][2] - col[1][2] * col[2][1]) -
                 col[1][0] * (col[0][1] * col[2][2] - col[0][2] * col[2][1]) +
                 col[2][0] * (col[0][1] * col[1][2] - col[0][2] * col[1][1]);
    if (det < 0)
        s[0] = -s[0];
    dmat r = dmat_identity();
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            r.m[i * 4 + j] = s[i] != 0 ? col[i][j] / s[i] : (i == j);
    dmat_quat(&r, out->q);
    for (int i = 0; i < 3; i++)
        out->s[i] = s[i];
}

static void node_anim_eval(const void *context, double t, bake_trs *out)
{
    const node_anim *a = context;
    dmat m = animated_matrix(a, a->start + t);
    dmat_decompose(&m, out);
}

static bool in_clip(const curve *k, xmlNode *const *anims, uint32_t anim_count)
{
    if (anim_count == 0)
        return true;
    for (xmlNode *p = k->channel->parent; p; p = p->parent)
        for (uint32_t i = 0; i < anim_count; i++)
            if (anims[i] == p)
                return true;
    return false;
}

/* The keys a clip over [start, end] copies from a curve: those inside, and one at each end. */
static uint64_t keys_in_window(const curve *k, double start, double end)
{
    uint64_t n = 2;
    for (uint32_t i = 0; i < k->keys; i++)
        n += k->times[i] > start && k->times[i] < end;
    return n;
}

static int compare_float(const void *a, const void *b)
{
    float x = *(const float *)a, y = *(const float *)b;
    return x < y ? -1 : x > y;
}

/* The node's translation (kind TRANSLATION, its first transform element a <translate>) or
 * scale (SCALE, its last a <scale>) kept as the file's curves when the stack is translate,
 * rotates, scale, and the element's animated components share their key times with BEZIER
 * (2-D control points inside their segments) and LINEAR segments only: the channel becomes
 * the runtime's Bezier keys, the file's own curve, instead of the baked one. Otherwise the
 * baked channel stays. */
static sinew_result keep_bezier(collada *c, const node_anim *a, int kind, double start, raw_track *track)
{
    const char *want = kind == SINEW_CHANNEL_TRANSLATION ? "translate" : "scale";
    xmlNode *el = NULL;
    int index = -1, elements = 0, wanted = 0;
    for (xmlNode *e = a->el->children; e; e = e->next) {
        if (!element_size(e))
            continue;
        if (!named(e, "translate") && !named(e, "rotate") && !named(e, "scale"))
            return SINEW_OK; /* a matrix, lookat or skew: baked */
        if (named(e, want))
            el = e, index = elements, wanted++;
        elements++;
    }
    if (!el || wanted != 1 || index != (kind == SINEW_CHANNEL_TRANSLATION ? 0 : elements - 1) || index >= a->elements)
        return SINEW_OK;
    const curve *drives[3] = {0};
    int column[3] = {0};
    const curve *ref = NULL;
    for (uint32_t i = 0; i < a->count; i++) {
        const curve *cv = &c->curves[a->curves[i]];
        if (cv->xform != el)
            continue;
        for (int j = 0; j < cv->count; j++) {
            if (cv->first + j >= 3 || drives[cv->first + j])
                return SINEW_OK;
            drives[cv->first + j] = cv, column[cv->first + j] = j;
        }
        if (ref && (cv->keys != ref->keys || memcmp(cv->times, ref->times, cv->keys * sizeof *cv->times) != 0))
            return SINEW_OK; /* components keyed at different times: baked */
        ref = cv;
        for (uint32_t k = 0; k + 1 < cv->keys; k++)
            if (!(cv->interp[k] == KEY_LINEAR || (cv->interp[k] == KEY_BEZIER && cv->tdim == 2)))
                return SINEW_OK;
    }
    if (!ref || ref->keys < 2)
        return SINEW_OK;
    uint32_t n = ref->keys;
    float *times = malloc(n * sizeof *times), *values = malloc((size_t)n * 15 * sizeof *values);
    if (!times || !values) {
        free(times);
        free(values);
        return oom(c);
    }
    for (uint32_t k = 0; k < n; k++)
        times[k] = (float)(ref->times[k] - start);
    bool inside = true;
    for (uint32_t k = 0; k < n && inside; k++) {
        float *key = values + (size_t)k * 15;
        for (int i = 0; i < 3; i++) {
            const curve *cv = drives[i];
            int cnt = cv ? cv->count : 0;
            size_t at = cv ? (size_t)k * (size_t)cnt + (size_t)column[i] : 0;
            double v = cv ? cv->values[at] : a->file[index][i];
            double in_t = times[k], in_v = v, out_t = times[k], out_v = v;
            if (k > 0) { /* the segment before: its end's control point */
                double dt = (double)times[k] - times[k - 1], pv = cv ? cv->values[at - (size_t)cnt] : v;
                in_t = times[k] - dt / 3, in_v = v - (v - pv) / 3;
                if (cv && cv->interp[k - 1] == KEY_BEZIER)
                    in_t = cv->in_tan[at * 2] - start, in_v = cv->in_tan[at * 2 + 1];
            }
            if (k + 1 < n) { /* the segment after: its start's control point */
                double dt = (double)times[k + 1] - times[k], nv = cv ? cv->values[at + (size_t)cnt] : v;
                out_t = times[k] + dt / 3, out_v = v + (nv - v) / 3;
                if (cv && cv->interp[k] == KEY_BEZIER)
                    out_t = cv->out_tan[at * 2] - start, out_v = cv->out_tan[at * 2 + 1];
            }
            key[i] = (float)v;
            key[3 + i] = (float)in_t, key[6 + i] = (float)in_v;
            key[9 + i] = (float)out_t, key[12 + i] = (float)out_v;
            /* inside its segment (to float rounding, then exactly) or not kept */
            float lo_in = k > 0 ? times[k - 1] : times[k], hi_out = k + 1 < n ? times[k + 1] : times[k];
            float slack = 1e-6f * fmaxf(1.0f, fabsf(times[k]));
            inside = inside && key[3 + i] >= lo_in - slack && key[3 + i] <= times[k] + slack &&
                     key[9 + i] >= times[k] - slack && key[9 + i] <= hi_out + slack;
            key[3 + i] = fminf(fmaxf(key[3 + i], lo_in), times[k]);
            key[9 + i] = fminf(fmaxf(key[9 + i], times[k]), hi_out);
        }
    }
    for (uint32_t k = 1; k < n && inside; k++)
        inside = times[k] >= times[k - 1];
    if (!inside) {
        free(times);
        free(values);
        return SINEW_OK;
    }
    raw_channel *ch = &track->channels[kind];
    free(ch->times);
    free(ch->values);
    *ch = (raw_channel){.interp = SINEW_INTERP_BEZIER, .count = n, .times = times, .values = values};
    return SINEW_OK;
}

/* One node's track over [start, end]: the decomposed key matrices when every curve drives a
 * whole matrix with LINEAR (or every one with STEP) keys, else baked from the stack, with
 * translation and scale kept as the file's Bezier curves where they can be (keep_bezier). */
static sinew_result node_track(collada *c, raw_clip *clip, uint32_t node, const uint32_t *curves, uint32_t count,
                               double start, double end, uint64_t *budget)
{
    raw_model *m = c->m;
    uint32_t cap = 2;
    for (uint32_t i = 0; i < count; i++)
        cap += c->curves[curves[i]].keys * 2;
    float *times = malloc(cap * sizeof *times);
    if (!times)
        return oom(c);
    uint32_t n = 0;
    float duration = (float)(end - start);
    times[n++] = 0;
    times[n++] = duration;
    bool all_linear = true, all_step = true;
    for (uint32_t i = 0; i < count; i++) {
        const curve *k = &c->curves[curves[i]];
        bool whole = k->first == 0 && k->count == 16;
        for (uint32_t j = 0; j < k->keys; j++) {
            all_linear &= whole && (k->interp[j] == KEY_LINEAR || j + 1 == k->keys);
            all_step &= whole && (k->interp[j] == KEY_STEP || j + 1 == k->keys);
            float t = (float)(k->times[j] - start);
            if (!(t > 0 && t < duration))
                continue;
            times[n++] = t;
            if (j > 0 && k->interp[j - 1] == KEY_STEP)
                times[n++] = nextafterf(t, 0.0f);
        }
    }
    qsort(times, n, sizeof *times, compare_float);
    uint32_t u = 0;
    for (uint32_t i = 0; i < n; i++)
        if (u == 0 || times[i] != times[u - 1])
            times[u++] = times[i];
    n = u;
    node_anim a = {.c = c, .el = c->node_el[node], .curves = curves, .count = count, .start = start};
    node_anim_init(&a);
    raw_track *track = &clip->tracks[clip->track_count++];
    track->node = node;
    sinew_result r = SINEW_OK;
    if (all_linear || all_step) {
        uint32_t interp = all_step && !all_linear ? SINEW_INTERP_STEP : SINEW_INTERP_LINEAR;
        for (int kind = 0; kind < SINEW_CHANNEL_COUNT && !r; kind++) {
            int width = kind == SINEW_CHANNEL_ROTATION ? 4 : 3;
            raw_channel *ch = &track->channels[kind];
            ch->interp = interp;
            ch->times = malloc(n * sizeof *ch->times);
            ch->values = malloc((size_t)n * (size_t)width * sizeof *ch->values);
            if (!ch->times || !ch->values) {
                r = oom(c);
                break;
            }
            ch->count = n;
            memcpy(ch->times, times, n * sizeof *times);
        }
        for (uint32_t i = 0; i < n && !r; i++) {
            bake_trs l;
            node_anim_eval(&a, times[i], &l);
            for (int k = 0; k < 3; k++) {
                track->channels[SINEW_CHANNEL_TRANSLATION].values[i * 3 + k] = (float)l.t[k];
                track->channels[SINEW_CHANNEL_SCALE].values[i * 3 + k] = (float)l.s[k];
            }
            for (int k = 0; k < 4; k++)
                track->channels[SINEW_CHANNEL_ROTATION].values[i * 4 + k] = (float)l.q[k];
        }
    } else {
        bake_desc desc = {.eval = node_anim_eval,
                          .context = &a,
                          .tol_t = DAE_BAKE_TOLERANCE * c->diagonal,
                          .tol_r = DAE_BAKE_TOLERANCE,
                          .tol_s = DAE_BAKE_TOLERANCE,
                          .budget = budget};
        if (!bake_track(&desc, times, n, &m->node_rest[node], track))
            r = oom(c);
        for (int kind = SINEW_CHANNEL_TRANSLATION; kind <= SINEW_CHANNEL_SCALE && !r; kind += 2)
            r = keep_bezier(c, &a, kind, start, track);
    }
    free(times);
    return r;
}

/* Bakes the nodes moved by `anims` (every animation when anim_count is 0) over [start, end]
 * of the file's timeline into `pool` (a clip of its own, times from 0 = start), then moves
 * its keys into one of the model's pools: the clips cut from it play windows of it. */
static sinew_result bake_pool(collada *c, const char *name, double start, double end, xmlNode *const *anims,
                              uint32_t anim_count, raw_clip *pool)
{
    raw_model *m = c->m;
    memset(pool, 0, sizeof *pool);
    pool->duration = (float)(end - start);
    if (!(pool->name = raw_strdup(name)) || !(pool->tracks = calloc(m->node_count, sizeof *pool->tracks)))
        return oom(c);
    uint32_t *mine = malloc((c->curve_count + 1) * sizeof *mine);
    if (!mine)
        return oom(c);
    uint64_t budget = 1u << 20;
    sinew_result r = SINEW_OK;
    for (uint32_t i = 1; i < m->node_count && !r; i++) {
        uint32_t count = 0;
        for (uint32_t k = 0; k < c->curve_count; k++)
            if (c->curves[k].node == c->node_el[i] && in_clip(&c->curves[k], anims, anim_count))
                mine[count++] = k;
        if (count)
            r = node_track(c, pool, i, mine, count, start, end, &budget);
    }
    free(mine);
    if (!r && budget == 0 &&
        !raw_model_warn(m,
                        "%s: clip \"%s\" has more curve detail than sinew bakes (a million extra keys); parts of "
                        "it are interpolated more coarsely",
                        c->path, name))
        r = oom(c);
    if (!r)
        r = raw_model_pool_clip(m, pool, c->error);
    return r;
}

static double curves_end(const collada *c, xmlNode *const *anims, uint32_t anim_count)
{
    double end = 0;
    for (uint32_t k = 0; k < c->curve_count; k++)
        if (in_clip(&c->curves[k], anims, anim_count))
            end = fmax(end, c->curves[k].times[c->curves[k].keys - 1]);
    return end;
}

/* An <animation_clip>: its name, window and the <animation>s it instances (sorted, so that
 * clips of the same animations compare equal and share one pool of keys). */
typedef struct clip_window {
    xmlNode *el;
    char *name;
    double start, end;
    xmlNode **anims;
    uint32_t anim_count;
    uint32_t pool;
} clip_window;

/* One weight of a morph curve over [start, end] as keys from clip time 0: the curve's own keys
 * where they are all STEP or all LINEAR (as the file plays them), else linear keys with each
 * BEZIER or HERMITE segment cut in DAE_WEIGHT_STEPS and each STEP held to just before the
 * next key. */
#define DAE_WEIGHT_STEPS 32

static sinew_result weight_keys(collada *c, const curve *k, int comp, double start, double end, raw_channel *out)
{
    uint32_t lo = 0, hi = k->keys; /* the keys inside (start, end) */
    while (lo < k->keys && k->times[lo] <= start)
        lo++;
    while (hi > lo && k->times[hi - 1] >= end)
        hi--;
    uint32_t from = lo > 0 ? lo - 1 : 0, to = hi < k->keys ? hi : k->keys - 1; /* the segments they span */
    bool step = true, linear = true;
    for (uint32_t i = from; i <= to; i++) {
        step &= k->interp[i] == KEY_STEP || i == k->keys - 1;
        linear &= k->interp[i] == KEY_LINEAR || i == k->keys - 1;
    }
    uint64_t cap = 2 + (uint64_t)(hi - lo + 1) * (step || linear ? 1 : DAE_WEIGHT_STEPS);
    if (cap > (1u << 24))
        return fail(c, k->channel, "weight curve of %u keys is too long to cut", k->keys);
    out->interp = step && !linear ? SINEW_INTERP_STEP : SINEW_INTERP_LINEAR;
    out->times = malloc((size_t)cap * sizeof *out->times);
    out->values = malloc((size_t)cap * sizeof *out->values);
    if (!out->times || !out->values)
        return oom(c);
    uint32_t n = 0;
#define PUT(t_, v_)                                                                                                    \
    do {                                                                                                               \
        out->times[n] = (float)((t_)-start);                                                                           \
        out->values[n++] = (float)(v_);                                                                                \
    } while (0)
    double last = start;
    PUT(start, curve_at(k, comp, start));
    for (uint32_t i = lo; i <= hi && end > start; i++) { /* the segment from the last point to key i (or end) */
        double b = i < hi ? k->times[i] : end;
        if (!(b > last))
            continue; /* keys at one time */
        int how = last < k->times[0] || last >= k->times[k->keys - 1] ? KEY_LINEAR : k->interp[i - 1];
        if (!(step || linear) && how == KEY_STEP) {
            PUT(b - (b - last) * 1e-6, curve_at(k, comp, last));
        } else if (!(step || linear) && how >= KEY_BEZIER) {
            for (int j = 1; j < DAE_WEIGHT_STEPS; j++)
                PUT(last + (b - last) * j / DAE_WEIGHT_STEPS,
                    curve_at(k, comp, last + (b - last) * j / DAE_WEIGHT_STEPS));
        }
        PUT(b, curve_at(k, comp, b));
        last = b;
    }
#undef PUT
    out->count = n;
    return SINEW_OK;
}

/* The clip just added for window `w`: the weight tracks of the morph curves of its
 * animations, for every instance of their controllers. */
static sinew_result morph_tracks(collada *c, const clip_window *w)
{
    raw_clip *clip = &c->m->clips[c->m->clip_count - 1];
    sinew_result r = SINEW_OK;
    for (uint32_t i = 0; i < c->curve_count && !r; i++) {
        const curve *k = &c->curves[i];
        if (!k->morph || !in_clip(k, w->anims, w->anim_count))
            continue;
        for (uint32_t u = 0; u < c->morph_count && !r; u++) {
            const morph_use *use = &c->morphs[u];
            if (use->controller != k->morph)
                continue;
            if ((uint32_t)k->first + (uint32_t)k->count > use->count) {
                r = raw_model_warn(c->m, "%s: <channel target=\"...(%d)\">: the morph has %u targets; not played",
                                   c->path, k->first + k->count - 1, use->count)
                        ? SINEW_OK
                        : oom(c);
                break;
            }
            raw_weight_track *grown =
                realloc(clip->weight_tracks, (clip->weight_track_count + (uint32_t)k->count) * sizeof *grown);
            if (!grown)
                return oom(c);
            clip->weight_tracks = grown;
            for (int comp = 0; comp < k->count && !r; comp++) {
                raw_weight_track *tr = &clip->weight_tracks[clip->weight_track_count++];
                memset(tr, 0, sizeof *tr);
                tr->channel = use->first + (uint32_t)k->first + (uint32_t)comp;
                r = weight_keys(c, k, comp, w->start, w->end, &tr->keys);
            }
        }
    }
    return r;
}

static int by_pointer(const void *a, const void *b)
{
    uintptr_t x = (uintptr_t) * (xmlNode *const *)a, y = (uintptr_t) * (xmlNode *const *)b;
    return x < y ? -1 : (x > y);
}

static sinew_result read_clip_window(collada *c, xmlNode *clip, uint32_t index, clip_window *w)
{
    memset(w, 0, sizeof *w);
    w->el = clip;
    uint32_t count = 0;
    for (xmlNode *k = clip->children; k; k = k->next)
        count += named(k, "instance_animation");
    if (count == 0)
        return SINEW_OK;
    if (!(w->anims = malloc(count * sizeof *w->anims)))
        return oom(c);
    for (xmlNode *k = clip->children; k; k = k->next) {
        xmlNode *a = named(k, "instance_animation") ? by_url_attr(c, k, "url") : NULL;
        if (named(a, "animation"))
            w->anims[w->anim_count++] = a;
    }
    if (w->anim_count == 0)
        return SINEW_OK;
    qsort(w->anims, w->anim_count, sizeof *w->anims, by_pointer);
    char name[512];
    if (!attr(clip, "name", name, sizeof name) || !*name)
        if (!attr(clip, "id", name, sizeof name) || !*name)
            snprintf(name, sizeof name, "clip %u", index);
    if (!(w->name = raw_strdup(name)))
        return oom(c);
    w->start = 0;
    w->end = curves_end(c, w->anims, w->anim_count);
    char buf[64], *e;
    if (attr(clip, "start", buf, sizeof buf)) {
        w->start = strtod_l(buf, &e, c->c_locale);
        if (e == buf || !isfinite(w->start))
            return fail(c, clip, "start \"%s\" is not a number", buf);
    }
    if (attr(clip, "end", buf, sizeof buf)) {
        w->end = strtod_l(buf, &e, c->c_locale);
        if (e == buf || !isfinite(w->end))
            return fail(c, clip, "end \"%s\" is not a number", buf);
    }
    if (!(w->end >= w->start))
        return fail(c, clip, "ends (%g s) before it starts (%g s)", w->end, w->start);
    return SINEW_OK;
}

static int by_animations_of(const clip_window *x, const clip_window *y)
{
    if (x->anim_count != y->anim_count)
        return x->anim_count < y->anim_count ? -1 : 1;
    for (uint32_t i = 0; i < x->anim_count; i++)
        if (x->anims[i] != y->anims[i])
            return by_pointer(&x->anims[i], &y->anims[i]);
    return 0;
}

static int by_animations(const void *a, const void *b, void *windows)
{
    const clip_window *w = windows;
    uint32_t i = *(const uint32_t *)a, j = *(const uint32_t *)b;
    int by = by_animations_of(&w[i], &w[j]);
    return by ? by : (i < j ? -1 : (i > j)); /* file order within a pool */
}

/* Windows of the same animations get the same pool number; returns how many pools. */
static uint32_t group_windows(clip_window *w, uint32_t count, uint32_t *order)
{
    for (uint32_t i = 0; i < count; i++)
        order[i] = i;
    qsort_r(order, count, sizeof *order, by_animations, w);
    uint32_t pools = 0;
    for (uint32_t i = 0; i < count; i++) {
        if (i == 0 || by_animations_of(&w[order[i - 1]], &w[order[i]]) != 0)
            pools++;
        w[order[i]].pool = pools - 1;
    }
    return pools;
}

/* The clips: one pool of keys for each set of <animation>s that <animation_clip>s instance
 * (baked over the union of their windows), every clip a window onto its pool, so that clips
 * cutting one long animation share its keys; a file without clips is one clip of every
 * animation. Past a bound proportional to the file's keys (windows over many different sets
 * of the same long animations) the file is refused before anything is baked. */
static sinew_result build_clips(collada *c)
{
    xmlNode *lib = child(c->root, "library_animations");
    sinew_result r = SINEW_OK;
    for (; lib && !r; lib = next_named(lib, "library_animations"))
        r = read_animations(c, lib, 0);
    if (r || c->curve_count == 0)
        return r;
    xmlNode *list = child(c->root, "library_animation_clips");
    uint32_t count = 0;
    for (xmlNode *clip = list ? list->children : NULL; clip; clip = clip->next)
        count += named(clip, "animation_clip");
    clip_window *w = calloc(count + 1, sizeof *w);
    uint32_t *order = calloc(count + 1, sizeof *order);
    double *pool_start = NULL, *pool_end = NULL;
    raw_clip *pools = NULL;
    uint32_t made = 0, pool_count = 0;
    if (!w || !order)
        r = oom(c);
    for (xmlNode *clip = list ? list->children : NULL; clip && !r; clip = clip->next) {
        if (!named(clip, "animation_clip"))
            continue;
        r = read_clip_window(c, clip, made, &w[made]);
        if (!r && w[made].anim_count) {
            made++;
        } else if (!r) { /* instances no <animation>: not a clip */
            free(w[made].anims);
            w[made].anims = NULL;
        }
    }
    if (!r && made == 0) {
        xmlNode *only = NULL;
        uint32_t tops = 0;
        for (lib = child(c->root, "library_animations"); lib; lib = next_named(lib, "library_animations"))
            for (xmlNode *a = lib->children; a; a = a->next)
                if (named(a, "animation"))
                    only = a, tops++;
        char name[512] = "";
        if (tops == 1 && !attr(only, "name", name, sizeof name))
            attr(only, "id", name, sizeof name);
        if (!*name)
            snprintf(name, sizeof name, "clip 0");
        w[0] = (clip_window){.el = c->root, .name = raw_strdup(name), .end = curves_end(c, NULL, 0)};
        made = 1;
        if (!w[0].name)
            r = oom(c);
    }
    if (!r) {
        pool_count = group_windows(w, made, order);
        pool_start = malloc(pool_count * sizeof *pool_start);
        pool_end = malloc(pool_count * sizeof *pool_end);
        pools = calloc(pool_count, sizeof *pools);
        if (!pool_start || !pool_end || !pools)
            r = oom(c);
    }
    for (uint32_t p = 0; p < pool_count && !r; p++)
        pool_start[p] = INFINITY, pool_end[p] = -INFINITY;
    for (uint32_t i = 0; i < made && !r; i++) {
        pool_start[w[i].pool] = fmin(pool_start[w[i].pool], w[i].start);
        pool_end[w[i].pool] = fmax(pool_end[w[i].pool], w[i].end);
    }
    if (!r) {
        uint64_t file_keys = 0, pooled = 0;
        for (uint32_t i = 0; i < c->curve_count; i++)
            file_keys += c->curves[i].keys;
        uint64_t budget = file_keys * 16 > (1u << 22) ? file_keys * 16 : (1u << 22);
        for (uint32_t i = 0; i < made && pooled <= budget; i++) {
            const clip_window *first = &w[order[i]];
            if (i > 0 && w[order[i - 1]].pool == first->pool)
                continue;
            for (uint32_t k = 0; k < c->curve_count && pooled <= budget; k++)
                if (in_clip(&c->curves[k], first->anims, first->anim_count))
                    pooled += keys_in_window(&c->curves[k], pool_start[first->pool], pool_end[first->pool]);
            if (pooled > budget)
                r = fail_kind(c, first->el, SINEW_ERROR_LIMIT,
                              "the <animation_clip>s instance so many different sets of the same <animation>s that "
                              "their keys would come to more than %llu (the file has %llu)",
                              (unsigned long long)budget, (unsigned long long)file_keys);
        }
    }
    for (uint32_t i = 0; i < made && !r; i++) {
        const clip_window *first = &w[order[i]];
        if (i == 0 || w[order[i - 1]].pool != first->pool)
            r = bake_pool(c, first->name, pool_start[first->pool], pool_end[first->pool], first->anims,
                          first->anim_count, &pools[first->pool]);
    }
    for (uint32_t i = 0; i < made && !r; i++)
        if (!raw_model_add_window(c->m, &pools[w[i].pool], w[i].name, (float)(w[i].start - pool_start[w[i].pool]),
                                  (float)(w[i].end - w[i].start), NULL))
            r = oom(c);
        else
            r = morph_tracks(c, &w[i]);
    for (uint32_t p = 0; pools && p < pool_count; p++)
        raw_clip_free(&pools[p]);
    for (uint32_t i = 0; w && i <= made && i <= count; i++) {
        free(w[i].name);
        free(w[i].anims);
    }
    free(pools);
    free(pool_start);
    free(pool_end);
    free(order);
    free(w);
    return r;
}

/* ---- skeleton-only files ----------------------------------------------------------------- */

/* A file with nodes and no skin (an animation exported without its mesh) still has a
 * skeleton: the nodes it types JOINT, else the nodes its clips move (with their end
 * sites), never a camera, light or geometry. They become a skin with no mesh, so they
 * are drawn and listed as joints. */
static sinew_result skeleton_only(collada *c)
{
    raw_model *m = c->m;
    if (m->skin_count || m->mesh_count || !m->node_count)
        return SINEW_OK;
    bool *excluded = calloc(m->node_count, sizeof *excluded), *joint = calloc(m->node_count, sizeof *joint);
    sinew_result r = excluded && joint ? SINEW_OK : oom(c);
    bool typed = false;
    for (uint32_t n = 0; n < m->node_count && !r; n++) {
        xmlNode *el = c->node_el[n];
        excluded[n] = !el || child(el, "instance_camera") || child(el, "instance_light") ||
                      child(el, "instance_geometry") || child(el, "instance_controller");
        joint[n] = el && node_attr_is(el, "type", "JOINT");
        typed |= joint[n];
    }
    if (!r && !typed && !raw_model_moved_nodes(m, excluded, joint))
        r = oom(c);
    uint32_t added = 0;
    if (!r && !raw_model_add_skeleton(m, joint, &added))
        r = oom(c);
    if (!r && added &&
        !raw_model_warn(m, "%s: no skin: the %u nodes %s are its skeleton", c->path, added,
                        typed ? "typed JOINT" : "its clips move"))
        r = oom(c);
    free(excluded);
    free(joint);
    return r;
}

/* ---- entry ---------------------------------------------------------------------------- */

bool collada_sniff(const unsigned char *head, size_t size)
{
    /* "<COLLADA" in the first bytes, in UTF-8 or (every other byte) UTF-16 */
    for (size_t i = 0; i + 8 <= size; i++)
        if (memcmp(head + i, "<COLLADA", 8) == 0)
            return true;
    for (size_t i = 0; i + 16 <= size; i++) {
        bool match = true;
        for (int k = 0; k < 8 && match; k++)
            match = head[i + 2 * (size_t)k] == (unsigned char)"<COLLADA"[k];
        if (match)
            return true;
    }
    return false;
}

sinew_result raw_model_from_collada(const char *path, const unsigned char *bytes, size_t size, raw_model *model,
                                    sinew_error *error)
{
    memset(model, 0, sizeof *model);
    collada c = {.path = path, .m = model, .error = error};
    model->source = raw_strdup(path);
    model->format = raw_strdup("dae");
    c.c_locale = newlocale(LC_NUMERIC_MASK, "C", (locale_t)0);
    sinew_result r = !model->source || !model->format || !c.c_locale ? oom(&c) : SINEW_OK;
    if (!r && size > INT32_MAX)
        r = fail(&c, NULL, "larger than 2 GB");
    if (!r) {
        import_xml_error first;
        c.doc = import_xml_parse(path, bytes, size, &first);
        if (!c.doc && first.unavailable)
            r = sinew_fail(error, SINEW_ERROR_UNSUPPORTED, "%s: reading COLLADA needs libxml2, and %s", path,
                           first.message);
        else if (!c.doc)
            r = sinew_fail_at(error, SINEW_ERROR_FORMAT, path, -1, (uint32_t)first.line,
                              "%s: not well-formed XML (line %d: %s)", path, first.line, first.message);
    }
    if (!r) {
        c.root = xmlDocGetRootElement(c.doc);
        if (!named(c.root, "COLLADA"))
            r = fail(&c, c.root, "the root element is not <COLLADA>");
    }
    if (!r && !(c.ids = xmlHashCreate(256)))
        r = oom(&c);
    if (!r) {
        index_ids(&c, c.root);
        read_asset(&c);
        r = build_nodes(&c);
    }
    if (!r)
        r = build_meshes(&c);
    if (!r && !raw_model_rest_diagonal(model, &c.diagonal))
        r = oom(&c);
    if (!r)
        r = build_clips(&c);
    if (!r)
        r = skeleton_only(&c);
    if (!r && c.bezier_1d &&
        !raw_model_warn(model,
                        "%s: %u channels give BEZIER tangents as one number (COLLADA 1.4.1 wants (time, value) "
                        "control points); they are played linearly",
                        path, c.bezier_1d))
        r = oom(&c);
    for (uint32_t i = 0; i < c.curve_count; i++)
        curve_free(&c.curves[i]);
    free(c.curves);
    free(c.morphs);
    free(c.pending);
    free(c.node_el);
    if (c.ids)
        xmlHashFree(c.ids, NULL);
    if (c.doc)
        xmlFreeDoc(c.doc);
    if (c.c_locale)
        freelocale(c.c_locale);
    if (r)
        raw_model_free(model);
    return r;
}
