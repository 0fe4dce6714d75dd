/* COLLADA <animation_clip>s that Assimp 5.2.5 merges into one clip.
 *
 * A COLLADA file may cut its animations into named clips (<library_animation_clips>, each
 * <animation_clip start end> instancing some <animation>s). Assimp hands back one clip
 * with every key on one timeline. sinew reads the clip list with libxml2 and cuts Assimp's
 * clip into the file's clips: each keeps the tracks of the nodes its animations target
 * (all tracks when that cannot be told) and the keys inside [start, end], with keys
 * sampled at both ends, shifted to start at 0.
 *
 * Index:
 *   reading the file ..... collect (clips, animations' target nodes, node ids -> names)
 *   cutting .............. raw_model_pool_clip + raw_model_add_window (builder.c)
 *   collada_split_clips
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "xml.h" /* libxml2, loaded on first use */

#include "../core/internal.h"
#include "internal.h"
#include "sinew/anim.h"
#include "alloc.h" /* last: the readers' allocations are the import's (alloc.h) */

#define MAX_CLIP_ANIMATIONS 256

typedef struct file_clip {
    char name[256];
    double start, end;
    bool has_end;
    int animation_count;
    xmlChar *animations[MAX_CLIP_ANIMATIONS]; /* ids, without '#' */
} file_clip;

typedef struct collected {
    file_clip *clips;
    int clip_count;
    xmlNode *root;
} collected;

static bool named(const xmlNode *n, const char *name)
{
    return n->type == XML_ELEMENT_NODE && strcmp((const char *)n->name, name) == 0;
}

static double attr_double(xmlNode *n, const char *key, bool *present)
{
    xmlChar *v = xmlGetProp(n, (const xmlChar *)key);
    *present = v != NULL;
    double d = v ? strtod((const char *)v, NULL) : 0.0;
    xmlFree(v);
    return isfinite(d) ? d : 0.0;
}

static bool read_clip(xmlNode *n, int index, file_clip *out)
{
    memset(out, 0, sizeof *out);
    bool has_start;
    out->start = attr_double(n, "start", &has_start);
    out->end = attr_double(n, "end", &out->has_end);
    xmlChar *name = xmlGetProp(n, (const xmlChar *)"name");
    if (!name)
        name = xmlGetProp(n, (const xmlChar *)"id");
    if (name)
        snprintf(out->name, sizeof out->name, "%s", (const char *)name);
    else
        snprintf(out->name, sizeof out->name, "clip %d", index);
    xmlFree(name);
    for (xmlNode *c = n->children; c; c = c->next) {
        if (!named(c, "instance_animation") || out->animation_count == MAX_CLIP_ANIMATIONS)
            continue;
        xmlChar *url = xmlGetProp(c, (const xmlChar *)"url");
        if (url && url[0] == '#')
            out->animations[out->animation_count++] = xmlStrdup(url + 1);
        xmlFree(url);
    }
    return true;
}

static void collect_clips(xmlNode *n, collected *c)
{
    for (; n; n = n->next) {
        if (named(n, "animation_clip")) {
            file_clip *grown = realloc(c->clips, (size_t)(c->clip_count + 1) * sizeof *grown);
            if (!grown)
                return;
            c->clips = grown;
            read_clip(n, c->clip_count, &c->clips[c->clip_count]);
            c->clip_count++;
        }
        collect_clips(n->children, c);
    }
}

static xmlNode *find_by_id(xmlNode *n, const char *element, const xmlChar *id)
{
    for (; n; n = n->next) {
        if (named(n, element)) {
            xmlChar *v = xmlGetProp(n, (const xmlChar *)"id");
            bool match = v && xmlStrEqual(v, id);
            xmlFree(v);
            if (match)
                return n;
        }
        xmlNode *found = find_by_id(n->children, element, id);
        if (found)
            return found;
    }
    return NULL;
}

/* Marks in `wanted` the sinew nodes that <channel target="NODE/..."> elements under
 * `animation` (nested ones too) drive. A node is named by its name attribute, or its id
 * when it has none, as Assimp names it. Returns how many channels were resolved. */
static int mark_targets(const collected *c, xmlNode *animation, const raw_model *m, bool *wanted)
{
    int resolved = 0;
    for (xmlNode *n = animation->children; n; n = n->next) {
        if (named(n, "animation")) {
            resolved += mark_targets(c, n, m, wanted);
            continue;
        }
        if (!named(n, "channel"))
            continue;
        xmlChar *target = xmlGetProp(n, (const xmlChar *)"target");
        if (!target)
            continue;
        size_t len = strcspn((const char *)target, "/(.");
        xmlChar *id = xmlStrndup(target, (int)len);
        xmlNode *node = find_by_id(c->root, "node", id);
        xmlChar *name = node ? xmlGetProp(node, (const xmlChar *)"name") : NULL;
        const char *want = (const char *)(name ? name : id);
        for (uint32_t i = 0; i < m->node_count; i++)
            if (strcmp(m->node_names[i], want) == 0) {
                wanted[i] = true;
                resolved++;
                break;
            }
        xmlFree(name);
        xmlFree(id);
        xmlFree(target);
    }
    return resolved;
}

/* ---- cutting ------------------------------------------------------------------------------ */

static void free_collected(collected *c)
{
    for (int i = 0; i < c->clip_count; i++)
        for (int a = 0; a < c->clips[i].animation_count; a++)
            xmlFree(c->clips[i].animations[a]);
    free(c->clips);
}

void collada_split_clips(const char *path, raw_model *m)
{
    if (m->clip_count != 1)
        return;
    unsigned char *bytes = NULL;
    size_t size = 0;
    if (!import_read_file(path, &bytes, &size))
        return;
    xmlDocPtr doc = size <= INT32_MAX ? import_xml_parse(path, bytes, size, NULL) : NULL;
    free(bytes);
    if (!doc)
        return;
    collected c = {.root = xmlDocGetRootElement(doc)};
    collect_clips(c.root, &c);
    bool *wanted = calloc(m->node_count ? m->node_count : 1, sizeof *wanted);
    raw_clip whole = m->clips[0];
    sinew_error ignored;
    /* the whole clip's keys go to a pool once; each <animation_clip> is a window onto it */
    bool ok = wanted && c.clip_count > 0 && raw_model_pool_clip(m, &whole, &ignored) == SINEW_OK;
    if (ok)
        m->clip_count = 0;
    for (int i = 0; ok && i < c.clip_count; i++) {
        memset(wanted, 0, (m->node_count ? m->node_count : 1) * sizeof *wanted);
        int resolved = 0;
        for (int a = 0; a < c.clips[i].animation_count; a++) {
            xmlNode *animation = find_by_id(c.root, "animation", c.clips[i].animations[a]);
            if (animation)
                resolved += mark_targets(&c, animation, m, wanted);
        }
        const file_clip *fc = &c.clips[i];
        float start = (float)fmax(0.0, fc->start);
        float end = fc->has_end ? (float)fc->end : whole.duration;
        ok = raw_model_add_window(m, &whole, fc->name, start, end > start ? end - start : 0.0f,
                                  resolved ? wanted : NULL);
    }
    if (ok) {
        raw_clip_free(&whole);
        raw_model_warn(m, "the file's %d <animation_clip>s were cut from the one clip Assimp makes of them",
                       c.clip_count);
    } else {
        /* no clips, bad keys or out of memory part way: back to the one clip (whose keys may
         * be pooled by now: a clip of its own still) */
        for (uint32_t i = 1; i < m->clip_count; i++)
            raw_clip_free(&m->clips[i]);
        if (m->clip_count != 1 || m->clips[0].tracks != whole.tracks)
            raw_clip_free(&m->clips[0]);
        m->clips[0] = whole;
        m->clip_count = 1;
    }
    free(wanted);
    free_collected(&c);
    xmlFreeDoc(doc);
}
