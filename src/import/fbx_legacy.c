/* FBX 5.x and 6.x documents indexed into the scene of fbx_scene.h, so that the rest of the
 * reader (fbx.c) builds them exactly as it builds FBX 7.x.
 *
 *   names ............. objects are named "Class::Name" (ASCII) or "Name\0\1Class" (binary)
 *                       instead of numbered: a sorted table of (class, name) finds them
 *   FBX 6.x ........... Objects (a Model carries its own geometry), Connections by name
 *                       ("Connect: OO, child, parent"), Properties60
 *   FBX 5.x ........... Models at the top level, children listed by name (Children), skin
 *                       clusters inside the mesh (Link), no Properties: a model's transform is
 *                       the Default of its own Transform channels
 *   takes ............. Takes/Take: a clip each, one layer, a model's Channel "Transform"
 *                       with T, R, S, each with X, Y, Z curves (fbx_curve_read_legacy)
 *
 * What FBX 7.x keeps in separate objects is given objects here: a mesh model's geometry is
 * an object of kind K_GEOMETRY on the same node, linked under the model, and a skin deformer
 * connected to a model is linked to that geometry instead, as 7.x files link it.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "fbx_scene.h"
#include "alloc.h" /* last: the readers' allocations are the import's (alloc.h) */

typedef struct name_entry {
    const char *cls, *name;
    size_t cls_len, name_len;
    uint32_t object;
} name_entry;

typedef struct legacy {
    scene *s;
    name_entry *names;
    uint32_t name_count;
    uint32_t object_capacity, link_capacity;
} legacy;

/* "Class::Name" or "Name\0\1Class"; a bare name has the class `fallback`. */
static void split_name(const fbx_value *v, const char *fallback, const char **cls, size_t *cls_len, const char **name,
                       size_t *name_len)
{
    *cls = fallback;
    *cls_len = strlen(fallback);
    *name = "";
    *name_len = 0;
    if (!v || v->type != FBX_STRING)
        return;
    const char *s = v->s;
    size_t n = v->count;
    for (size_t i = 0; i + 1 < n; i++)
        if (s[i] == '\0' && s[i + 1] == '\x01') {
            *name = s;
            *name_len = i;
            *cls = s + i + 2;
            *cls_len = n - i - 2;
            return;
        }
    for (size_t i = 0; i + 1 < n; i++)
        if (s[i] == ':' && s[i + 1] == ':') {
            *cls = s;
            *cls_len = i;
            *name = s + i + 2;
            *name_len = n - i - 2;
            return;
        }
    *name = s;
    *name_len = n;
}

static int compare_text(const char *a, size_t an, const char *b, size_t bn)
{
    int c = memcmp(a, b, an < bn ? an : bn);
    return c ? c : an < bn ? -1 : an > bn;
}

static int compare_names(const void *a, const void *b)
{
    const name_entry *x = a, *y = b;
    int c = compare_text(x->cls, x->cls_len, y->cls, y->cls_len);
    if (c)
        return c;
    c = compare_text(x->name, x->name_len, y->name, y->name_len);
    return c ? c : x->object < y->object ? -1 : x->object > y->object;
}

/* The object a name refers to (the first of its class and name in the file), or -1. */
static int32_t find_named(const legacy *l, const fbx_value *v, const char *fallback)
{
    name_entry key;
    split_name(v, fallback, &key.cls, &key.cls_len, &key.name, &key.name_len);
    uint32_t lo = 0, hi = l->name_count;
    while (lo < hi) {
        uint32_t mid = lo + (hi - lo) / 2;
        const name_entry *e = &l->names[mid];
        int c = compare_text(e->cls, e->cls_len, key.cls, key.cls_len);
        if (!c)
            c = compare_text(e->name, e->name_len, key.name, key.name_len);
        if (c < 0)
            lo = mid + 1;
        else
            hi = mid;
    }
    if (lo < l->name_count) {
        const name_entry *e = &l->names[lo];
        if (!compare_text(e->cls, e->cls_len, key.cls, key.cls_len) &&
            !compare_text(e->name, e->name_len, key.name, key.name_len))
            return (int32_t)e->object;
    }
    return -1;
}

static fbx_object *add_object(legacy *l, const fbx_node *node, int kind, const fbx_value *name, const char *cls)
{
    scene *s = l->s;
    if (s->object_count == l->object_capacity) {
        uint32_t cap = l->object_capacity ? l->object_capacity * 2 : 64;
        fbx_object *grown = realloc(s->objects, cap * sizeof *grown);
        name_entry *names = realloc(l->names, cap * sizeof *names);
        if (grown)
            s->objects = grown;
        if (names)
            l->names = names;
        if (!grown || !names)
            return NULL;
        l->object_capacity = cap;
    }
    uint32_t index = s->object_count++;
    fbx_object *o = &s->objects[index];
    memset(o, 0, sizeof *o);
    o->id = (int64_t)index + 1;
    o->node = node;
    o->kind = kind;
    o->order = index;
    o->raw_node = o->raw_material = o->curve = -1;
    o->props = fbx_child(node, "Properties60");
    if (!o->props)
        o->props = fbx_child(node, "Properties70");
    name_entry *e = &l->names[l->name_count++];
    split_name(name, cls, &e->cls, &e->cls_len, &e->name, &e->name_len);
    e->object = index;
    o->name = e->name;
    o->name_len = e->name_len;
    return o;
}

static bool add_link(legacy *l, uint32_t child, uint32_t parent, const fbx_value *prop)
{
    scene *s = l->s;
    if (child == parent)
        return true;
    if (s->link_count == l->link_capacity) {
        uint32_t cap = l->link_capacity ? l->link_capacity * 2 : 64;
        fbx_link *grown = realloc(s->up, cap * sizeof *grown);
        if (!grown)
            return false;
        s->up = grown;
        l->link_capacity = cap;
    }
    s->up[s->link_count] = (fbx_link){child, parent, s->link_count, prop};
    s->link_count++;
    return true;
}

/* The kind of a 6.x object node from its node name and subclass. */
static int legacy_kind(const fbx_node *n)
{
    const fbx_value *sub = n->value_count > 1 ? &n->values[1] : NULL;
    if (fbx_named(n, "Model"))
        return K_MODEL;
    if (fbx_named(n, "Geometry"))
        return fbx_value_is(sub, "Mesh") ? K_GEOMETRY : K_OTHER;
    if (fbx_named(n, "Deformer"))
        return fbx_value_is(sub, "Skin")                  ? K_SKIN
               : fbx_value_is(sub, "Cluster")             ? K_CLUSTER
               : fbx_value_is(sub, "VertexCacheDeformer") ? K_CACHE_DEFORMER
                                                          : K_OTHER;
    if (fbx_named(n, "Cache"))
        return K_CACHE;
    if (fbx_named(n, "Material"))
        return K_MATERIAL;
    if (fbx_named(n, "Texture"))
        return K_TEXTURE;
    if (fbx_named(n, "Video"))
        return K_VIDEO;
    return K_OTHER;
}

/* A mesh model's geometry: an object on the model's own node, linked under it; and a blend
 * channel for each of its Shape nodes (linked under the geometry, with the model's
 * properties: a shape's weight is the model's property of the shape's name). */
static sinew_result add_geometry(legacy *l, uint32_t model)
{
    const fbx_node *node = l->s->objects[model].node;
    if (!fbx_child(node, "Vertices") || !fbx_child(node, "PolygonVertexIndex"))
        return SINEW_OK;
    fbx_object *g = add_object(l, node, K_GEOMETRY, NULL, "Geometry");
    if (!g || !add_link(l, (uint32_t)(g - l->s->objects), model, NULL))
        return fbx_oom(l->s);
    uint32_t gi = (uint32_t)(g - l->s->objects);
    g->name = l->s->objects[model].name; /* named after its model; not found by name */
    g->name_len = l->s->objects[model].name_len;
    for (uint32_t i = 0; i < node->child_count; i++) {
        const fbx_node *shape = &node->children[i];
        if (!fbx_named(shape, "Shape") || !shape->value_count || shape->values[0].type != FBX_STRING)
            continue;
        fbx_object *ch = add_object(l, shape, K_BLEND_CHANNEL, &shape->values[0], "SubDeformer");
        if (!ch || !add_link(l, l->s->object_count - 1, gi, NULL))
            return fbx_oom(l->s);
        ch->props = l->s->objects[model].props;
    }
    return SINEW_OK;
}

static int32_t geometry_of(const scene *s, uint32_t model);

/* The blend channel a model's take channel `name` animates (a Shape of its geometry named so,
 * or so with " (Shape)" after it, as FBX 5.x names them), or -1. */
static int32_t shape_channel(const scene *s, uint32_t model, const fbx_value *name)
{
    int32_t g = geometry_of(s, model);
    if (g < 0 || !name || name->type != FBX_STRING)
        return -1;
    const fbx_object *go = &s->objects[g];
    for (uint32_t k = 0; k < go->child_count; k++) {
        uint32_t c = fbx_child_link(s, go, k)->child;
        const fbx_object *ch = &s->objects[c];
        if (ch->kind != K_BLEND_CHANNEL)
            continue;
        size_t n = ch->name_len;
        if ((name->count == n && !memcmp(name->s, ch->name, n)) ||
            (name->count == n + 8 && !memcmp(name->s, ch->name, n) && !memcmp(name->s + n, " (Shape)", 8)))
            return (int32_t)c;
    }
    return -1;
}

/* The geometry object made for a model by add_geometry(), or -1. */
static int32_t geometry_of(const scene *s, uint32_t model)
{
    for (uint32_t i = 0; i < s->link_count; i++)
        if (s->up[i].parent == model && s->objects[s->up[i].child].kind == K_GEOMETRY &&
            s->objects[s->up[i].child].node == s->objects[model].node)
            return (int32_t)s->up[i].child;
    return -1;
}

static void sort_names(legacy *l)
{
    if (l->name_count)
        qsort(l->names, l->name_count, sizeof *l->names, compare_names);
}

/* ---- FBX 6.x ------------------------------------------------------------------------------ */

static sinew_result index_v6(legacy *l)
{
    scene *s = l->s;
    const fbx_node *objects = fbx_child(&s->doc.root, "Objects");
    for (uint32_t i = 0; objects && i < objects->child_count; i++) {
        const fbx_node *node = &objects->children[i];
        if (node->value_count < 1 || node->values[0].type != FBX_STRING)
            continue;
        fbx_object *o = add_object(l, node, legacy_kind(node), &node->values[0], "");
        if (!o)
            return fbx_oom(s);
        if (o->kind == K_MODEL) {
            sinew_result result = add_geometry(l, s->object_count - 1);
            if (result)
                return result;
        }
    }
    sort_names(l);
    const fbx_node *conns = fbx_child(&s->doc.root, "Connections");
    for (uint32_t i = 0; conns && i < conns->child_count; i++) {
        const fbx_node *c = &conns->children[i];
        if (!fbx_named(c, "Connect") || c->value_count < 3)
            continue;
        bool op = fbx_str_is(c, 0, "OP");
        if (!op && !fbx_str_is(c, 0, "OO"))
            continue;
        int32_t child = find_named(l, &c->values[1], ""), parent = find_named(l, &c->values[2], "");
        if (child < 0 || parent < 0)
            continue; /* to "Model::Scene", the root, or to an object the file does not have */
        /* a deformer connected to a mesh model deforms the model's geometry */
        int kind = s->objects[child].kind;
        if ((kind == K_SKIN || kind == K_CACHE_DEFORMER) && s->objects[parent].kind == K_MODEL) {
            int32_t g = geometry_of(s, (uint32_t)parent);
            if (g >= 0)
                parent = g;
        }
        const fbx_value *prop = op && c->value_count > 3 && c->values[3].type == FBX_STRING ? &c->values[3] : NULL;
        if (!add_link(l, (uint32_t)child, (uint32_t)parent, prop))
            return fbx_oom(s);
    }
    return SINEW_OK;
}

/* ---- FBX 5.x ------------------------------------------------------------------------------ */

/* Top-level models, their geometry, children by name and skin clusters (Link). */
static sinew_result index_v5(legacy *l)
{
    scene *s = l->s;
    const fbx_node *root = &s->doc.root;
    for (uint32_t i = 0; i < root->child_count; i++) {
        const fbx_node *node = &root->children[i];
        if (!fbx_named(node, "Model") || node->value_count < 1 || node->values[0].type != FBX_STRING)
            continue;
        if (!add_object(l, node, K_MODEL, &node->values[0], "Model"))
            return fbx_oom(s);
        sinew_result result = add_geometry(l, s->object_count - 1);
        if (result)
            return result;
    }
    sort_names(l);
    uint32_t models = s->object_count;
    for (uint32_t m = 0; m < models; m++) {
        const fbx_node *node = s->objects[m].node;
        if (s->objects[m].kind != K_MODEL)
            continue;
        const fbx_node *children = fbx_child(node, "Children");
        for (uint32_t k = 0; children && k < children->value_count; k++) {
            int32_t child = find_named(l, &children->values[k], "Model");
            if (child >= 0 && s->objects[child].kind == K_MODEL && !add_link(l, (uint32_t)child, m, NULL))
                return fbx_oom(s);
        }
        int32_t geometry = geometry_of(s, m);
        int32_t skin = -1;
        for (uint32_t k = 0; k < node->child_count && geometry >= 0; k++) {
            const fbx_node *link = &node->children[k];
            if (!fbx_named(link, "Link") || link->value_count < 1)
                continue;
            int32_t bone = find_named(l, &link->values[0], "Model");
            if (skin < 0) {
                fbx_object *o = add_object(l, node, K_SKIN, NULL, "Deformer");
                if (!o || !add_link(l, s->object_count - 1, (uint32_t)geometry, NULL))
                    return fbx_oom(s);
                skin = (int32_t)(s->object_count - 1);
            }
            fbx_object *cl = add_object(l, link, K_CLUSTER, &link->values[0], "SubDeformer");
            if (!cl || !add_link(l, s->object_count - 1, (uint32_t)skin, NULL) ||
                (bone >= 0 && !add_link(l, (uint32_t)bone, s->object_count - 1, NULL)))
                return fbx_oom(s);
        }
    }
    sort_names(l);
    return SINEW_OK;
}

/* ---- takes -------------------------------------------------------------------------------- */

static bool push_curve(scene *s, const fbx_node *channel, int32_t *out, const char **problem)
{
    fbx_curve_source src = {s->doc.version, s->doc.binary, s->ticks_per_second, &s->doc.arena};
    fbx_curve c;
    *out = -1;
    *problem = fbx_curve_read_legacy(channel, &src, &c);
    if (*problem)
        return false;
    if (c.count == 0)
        return true;
    if ((*out = fbx_add_curve(s, &c)) < 0) {
        fbx_curve_free(&c);
        *problem = "out of memory";
        return false;
    }
    return true;
}

/* One property channel of a model in a take: its X, Y, Z channels (or itself, when it has the
 * keys) as a binding of the take's layer. */
static sinew_result take_property(legacy *l, const fbx_node *channel, uint32_t model, int prop, uint32_t layer)
{
    scene *s = l->s;
    fbx_binding b = {.model = model, .layer = layer, .stack = s->layers[layer].stack, .index = 0, .prop = prop};
    static const char *const axes[3] = {"X", "Y", "Z"};
    bool any = false;
    for (int c = 0; c < 3; c++) {
        b.curves[c] = -1;
        b.defaults[c] = NAN;
    }
    uint32_t found = 0;
    for (uint32_t k = 0; k < channel->child_count && found < 3; k++) {
        const fbx_node *sub = &channel->children[k];
        if (!fbx_named(sub, "Channel") || (!fbx_child(sub, "Key") && !fbx_child(sub, "Default")))
            continue;
        int c = (int)found++;
        for (int a = 0; a < 3; a++)
            if (fbx_str_is(sub, 0, axes[a]))
                c = a;
        const fbx_node *def = fbx_child(sub, "Default");
        if (def)
            b.defaults[c] = fbx_num(def, 0);
        const char *problem;
        if (!push_curve(s, sub, &b.curves[c], &problem))
            return strcmp(problem, "out of memory") == 0 ? fbx_oom(s) : fbx_fail_data(s, problem, &s->objects[model]);
        any = true;
    }
    if (!any && (fbx_child(channel, "Key") || fbx_child(channel, "Default"))) {
        const fbx_node *def = fbx_child(channel, "Default");
        if (def)
            b.defaults[0] = fbx_num(def, 0);
        const char *problem;
        if (!push_curve(s, channel, &b.curves[0], &problem))
            return strcmp(problem, "out of memory") == 0 ? fbx_oom(s) : fbx_fail_data(s, problem, &s->objects[model]);
        any = true;
    }
    return any && !fbx_add_binding(s, &b) ? fbx_oom(s) : SINEW_OK;
}

/* A model's channels in a take: "Transform" with T, R, S, or properties by their own name. */
static sinew_result take_model(legacy *l, const fbx_node *node, uint32_t model, uint32_t layer)
{
    static const char *const trs[3] = {"T", "R", "S"};
    for (uint32_t k = 0; k < node->child_count; k++) {
        const fbx_node *ch = &node->children[k];
        if (!fbx_named(ch, "Channel"))
            continue;
        sinew_result result = SINEW_OK;
        if (fbx_str_is(ch, 0, "Transform")) {
            for (uint32_t j = 0; j < ch->child_count && !result; j++)
                for (int p = 0; p < 3 && !result; p++)
                    if (fbx_named(&ch->children[j], "Channel") && fbx_str_is(&ch->children[j], 0, trs[p]))
                        result = take_property(l, &ch->children[j], model, p, layer);
        } else {
            for (int p = 0; p < P_COUNT && !result; p++)
                if (fbx_str_is(ch, 0, fbx_transform_props[p]))
                    result = take_property(l, ch, model, p, layer);
            int32_t shape = ch->value_count ? shape_channel(l->s, model, &ch->values[0]) : -1;
            if (shape >= 0 && !result)
                result = take_property(l, ch, (uint32_t)shape, P_DEFORM_PERCENT, layer);
        }
        if (result)
            return result;
    }
    return SINEW_OK;
}

static sinew_result index_takes(legacy *l)
{
    scene *s = l->s;
    const fbx_node *takes = fbx_child(&s->doc.root, "Takes");
    uint32_t count = 0;
    for (uint32_t i = 0; takes && i < takes->child_count; i++)
        count += fbx_named(&takes->children[i], "Take");
    s->stacks = calloc(count ? count : 1, sizeof *s->stacks);
    s->layers = calloc(count ? count : 1, sizeof *s->layers);
    if (!s->stacks || !s->layers)
        return fbx_oom(s);
    for (uint32_t i = 0; takes && i < takes->child_count; i++) {
        const fbx_node *take = &takes->children[i];
        if (!fbx_named(take, "Take"))
            continue;
        uint32_t index = s->stack_count++;
        fbx_stack *st = &s->stacks[index];
        size_t cls_len;
        const char *cls;
        split_name(take->value_count ? &take->values[0] : NULL, "", &cls, &cls_len, &st->name, &st->name_len);
        const fbx_node *span = fbx_child(take, "LocalTime");
        if (!span)
            span = fbx_child(take, "ReferenceTime");
        st->start = fbx_num(span, 0) / s->ticks_per_second;
        st->stop = fbx_num(span, 1) / s->ticks_per_second;
        st->order = i;
        st->first_layer = s->layer_count;
        st->layer_count = 1;
        s->layers[s->layer_count++] = (fbx_layer){.stack = index,
                                                  .weight = 1,
                                                  .weight_curve = -1,
                                                  .additive = true,
                                                  .blended = true,
                                                  .compose_rotation = true,
                                                  .compose_scale = true};
        for (uint32_t k = 0; k < take->child_count; k++) {
            const fbx_node *node = &take->children[k];
            if (!fbx_named(node, "Model") || node->value_count < 1)
                continue;
            int32_t model = find_named(l, &node->values[0], "Model");
            if (model < 0 || s->objects[model].kind != K_MODEL)
                continue;
            sinew_result result = take_model(l, node, (uint32_t)model, st->first_layer);
            if (result)
                return result;
        }
    }
    return SINEW_OK;
}

sinew_result fbx_legacy_index(scene *s)
{
    legacy l = {.s = s};
    bool v6 = fbx_child(&s->doc.root, "Objects") != NULL;
    sinew_result result = v6 ? index_v6(&l) : index_v5(&l);
    if (!result && !s->objects && !(s->objects = calloc(1, sizeof *s->objects)))
        result = fbx_oom(s);
    if (!result) {
        s->down = malloc((s->link_count ? s->link_count : 1) * sizeof *s->down);
        if (!s->up)
            s->up = malloc(sizeof *s->up);
        if (!s->down || !s->up)
            result = fbx_oom(s);
    }
    if (!result) {
        fbx_sort_links(s);
        result = index_takes(&l);
    }
    if (!result)
        fbx_sort_bindings(s);
    if (!result && s->object_count == 0)
        result = sinew_fail(s->error, SINEW_ERROR_FORMAT,
                            "%s: the FBX %u.%u document has no models (the file may be cut short)", s->path,
                            s->doc.version / 1000, s->doc.version % 1000 / 100);
    free(l.names);
    return result;
}
