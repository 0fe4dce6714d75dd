/* Comparing sinew's poses with the references of ../shared/testdata/reference (its README
 * gives the format): node world positions by name and skinned vertices as point sets,
 * relative to the bounding diagonal of the reference's nodes. */
#include "reference.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include <libxml/parser.h>
#include <libxml/tree.h>
#include <zlib.h>

cJSON *read_gzip_json(const char *path)
{
    gzFile f = gzopen(path, "rb");
    assert_non_null(f);
    size_t cap = 1 << 20, n = 0;
    char *text = malloc(cap);
    int got;
    while ((got = gzread(f, text + n, (unsigned)(cap - n - 1))) > 0) {
        n += (size_t)got;
        if (n + 1 == cap)
            text = realloc(text, cap *= 2);
    }
    gzclose(f);
    text[n] = 0;
    cJSON *root = cJSON_Parse(text);
    free(text);
    assert_non_null(root);
    return root;
}

static double dist3(const float *a, const double *b)
{
    double dx = a[0] - b[0], dy = a[1] - b[1], dz = a[2] - b[2];
    return sqrt(dx * dx + dy * dy + dz * dz);
}

static int compare_x(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

/* Distance from p to the nearest of n points sorted by x (3 doubles each). */
static double nearest(const double *sorted, uint32_t n, const double p[3])
{
    uint32_t lo = 0, hi = n;
    while (lo < hi) {
        uint32_t mid = (lo + hi) / 2;
        if (sorted[mid * 3] < p[0])
            lo = mid + 1;
        else
            hi = mid;
    }
    double best = INFINITY;
    for (uint32_t i = lo; i < n && sorted[i * 3] - p[0] < best; i++) {
        double dx = sorted[i * 3] - p[0], dy = sorted[i * 3 + 1] - p[1], dz = sorted[i * 3 + 2] - p[2];
        best = fmin(best, sqrt(dx * dx + dy * dy + dz * dz));
    }
    for (uint32_t i = lo; i-- > 0 && p[0] - sorted[i * 3] < best;) {
        double dx = sorted[i * 3] - p[0], dy = sorted[i * 3 + 1] - p[1], dz = sorted[i * 3 + 2] - p[2];
        best = fmin(best, sqrt(dx * dx + dy * dy + dz * dz));
    }
    return best;
}

/* Largest distance from a point of one set to the nearest of the other, both ways. */
double point_set_distance(const float *ours, uint32_t n_ours, const double *ref, uint32_t n_ref)
{
    double *a = malloc(((size_t)n_ours + 1) * 3 * sizeof *a), *b = malloc(((size_t)n_ref + 1) * 3 * sizeof *b);
    for (size_t i = 0; i < (size_t)n_ours * 3; i++)
        a[i] = ours[i];
    memcpy(b, ref, (size_t)n_ref * 3 * sizeof *b);
    qsort(a, n_ours, 3 * sizeof *a, compare_x);
    qsort(b, n_ref, 3 * sizeof *b, compare_x);
    double worst = 0;
    for (uint32_t i = 0; i < n_ref; i++)
        worst = fmax(worst, nearest(a, n_ours, &b[i * 3]));
    for (uint32_t j = 0; j < n_ours; j++)
        worst = fmax(worst, nearest(b, n_ref, &a[j * 3]));
    free(a);
    free(b);
    return worst;
}

static double vec_at(const cJSON *a, int i)
{
    return cJSON_GetArrayItem(a, i)->valuedouble;
}

/* The diagonal of the points of every frame's `key` ("nodes" or "verts"), 0 for none. */
static double points_diagonal(const cJSON *frames, const char *key)
{
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    const cJSON *frame, *node;
    cJSON_ArrayForEach(frame, frames)
        cJSON_ArrayForEach(node, cJSON_GetObjectItem(frame, key)) for (int c = 0; c < 3; c++)
    {
        lo[c] = fmin(lo[c], vec_at(node, c));
        hi[c] = fmax(hi[c], vec_at(node, c));
    }
    double d =
        sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) + (hi[2] - lo[2]) * (hi[2] - lo[2]));
    return isfinite(d) ? d : 0.0;
}

/* The diagonal of every node position of every frame of the reference; of its vertices when
 * its nodes do not move apart (a scene of one node, or only made-up ones at the origin). */
double reference_diagonal(const cJSON *frames)
{
    double d = points_diagonal(frames, "nodes");
    if (!(d > 0))
        d = points_diagonal(frames, "verts");
    return d > 0 ? d : 1.0;
}

/* three.js's node name for a name (PropertyBinding.sanitizeNodeName): white space as '_',
 * and without '[', ']', '.', ':' and '/'. */
static void threejs_name(const char *name, char *out, size_t size)
{
    size_t n = 0;
    for (const char *c = name; *c && n + 1 < size; c++) {
        if (strchr("[].:/", *c))
            continue;
        out[n++] = (*c == ' ' || *c == '\t' || *c == '\n') ? '_' : *c;
    }
    out[n] = 0;
}

/* The distance from a reference node position to the node it names: its own name, else
 * three.js's sanitised form of a name. When names repeat, three.js tells them apart by a
 * suffix ("Head#2" in the COLLADA references, "FootL_1" for glTF's second "Foot.L") counted
 * in its own loading order, which is not the file's: the nearest of the nodes with that
 * name stands for it. INFINITY: no node of that name. */
static double reference_distance(const sinew_model *m, const sinew_mat4 *w, const char *ref_name, const double p[3])
{
    int32_t exact = sinew_model_find_node(m, ref_name);
    char base[256], san[256];
    snprintf(base, sizeof base, "%s", ref_name);
    char *mark = strrchr(base, '#');
    if (!mark)
        mark = strrchr(base, '_');
    if (mark && mark[1] && strspn(mark + 1, "0123456789") == strlen(mark + 1))
        *mark = 0;
    double best = INFINITY;
    uint32_t same_name = 0;
    for (uint32_t i = 0; i < m->node_count; i++)
        same_name += strcmp(m->node_names[i], ref_name) == 0;
    if (exact >= 0 && same_name == 1)
        return dist3(&w[exact].m[12], p);
    for (uint32_t i = 0; i < m->node_count; i++) {
        threejs_name(m->node_names[i], san, sizeof san);
        if (strcmp(san, base) == 0 || strcmp(san, ref_name) == 0 || strcmp(m->node_names[i], ref_name) == 0)
            best = fmin(best, dist3(&w[i].m[12], p));
    }
    return best;
}

/* three.js names a COLLADA joint by its SID ("Foot_L", "bone0"), sinew by its name ("Foot.L",
 * "joint1"): the file's own <node sid name> pairs, read here with libxml2. */
static void collect_sids(xmlNode *n, sid_names *out)
{
    for (; n; n = n->next) {
        if (n->type != XML_ELEMENT_NODE)
            continue;
        xmlChar *sid = xmlGetProp(n, (const xmlChar *)"sid"), *name = xmlGetProp(n, (const xmlChar *)"name");
        if (!name)
            name = xmlGetProp(n, (const xmlChar *)"id");
        if (strcmp((const char *)n->name, "node") == 0 && sid && name) {
            out->sid = realloc(out->sid, (out->count + 1) * sizeof *out->sid);
            out->name = realloc(out->name, (out->count + 1) * sizeof *out->name);
            snprintf(out->sid[out->count], 128, "%s", (const char *)sid);
            snprintf(out->name[out->count], 128, "%s", (const char *)name);
            out->count++;
        }
        xmlFree(sid);
        xmlFree(name);
        collect_sids(n->children, out);
    }
}

sid_names read_sids(const char *path)
{
    sid_names s = {0};
    size_t n = strlen(path);
    if (n < 4 || strcasecmp(path + n - 4, ".dae") != 0)
        return s;
    xmlDoc *doc = xmlReadFile(path, NULL, XML_PARSE_NONET | XML_PARSE_NOERROR | XML_PARSE_NOWARNING);
    if (doc)
        collect_sids(xmlDocGetRootElement(doc), &s);
    xmlFreeDoc(doc);
    return s;
}

const char *sid_to_name(const sid_names *s, const char *ref_name)
{
    if (!s)
        return ref_name;
    for (uint32_t i = 0; i < s->count; i++)
        if (strcmp(s->sid[i], ref_name) == 0)
            return s->name[i];
    return ref_name;
}

outcome compare_with_reference(const sinew_model *m, const cJSON *ref, const sid_names *sids)
{
    outcome o = {0};
    const cJSON *frames = cJSON_GetObjectItem(ref, "frames"), *frame;
    double diag = reference_diagonal(frames);
    const sinew_clip *clip = m->clip_count ? &m->clips[0] : NULL;
    cJSON_ArrayForEach(frame, frames)
    {
        float t = (float)cJSON_GetObjectItem(frame, "t")->valuedouble;
        sinew_mat4 *w = pose_worlds(m, clip, t);
        const cJSON *node;
        cJSON_ArrayForEach(node, cJSON_GetObjectItem(frame, "nodes"))
        {
            double p[3] = {vec_at(node, 0), vec_at(node, 1), vec_at(node, 2)};
            double d = reference_distance(m, w, sid_to_name(sids, node->string), p);
            if (!isfinite(d)) {
                o.missing++;
                continue;
            }
            o.nodes = fmax(o.nodes, d / diag);
            o.compared++;
        }
        const cJSON *verts = cJSON_GetObjectItem(frame, "verts");
        int nv = cJSON_GetArraySize(verts);
        if (nv > 0) {
            double *rv = malloc((size_t)nv * 3 * sizeof *rv);
            const cJSON *v;
            int i = 0;
            cJSON_ArrayForEach(v, verts)
            {
                for (int c = 0; c < 3; c++)
                    rv[i * 3 + c] = vec_at(v, c);
                i++;
            }
            uint32_t count;
            float *ours = posed_vertices_at(m, w, clip, t, &count);
            o.verts = fmax(o.verts, point_set_distance(ours, count, rv, (uint32_t)nv) / diag);
            free(ours);
            free(rv);
        }
        free(w);
    }
    return o;
}

/* reference/ufbx/NAME.json.gz of a model of the test data: its path with '/' as "__" and
 * without its extension (reference/README.md). */
void reference_name(const char *source, const char *model, char *out, size_t size)
{
    size_t n = (size_t)snprintf(out, size, "reference/%s/", source);
    const char *dot = strrchr(model, '.');
    for (const char *c = model; c < dot && n + 2 < size; c++) {
        if (*c == '/')
            out[n++] = '_', out[n++] = '_';
        else
            out[n++] = *c;
    }
    snprintf(out + n, size - n, ".json.gz");
}

void sid_names_free(sid_names *s)
{
    free(s->sid);
    free(s->name);
    memset(s, 0, sizeof *s);
}
