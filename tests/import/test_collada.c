/* sinew's COLLADA reader against the file itself: each test evaluates what the XML says
 * with its own few lines of arithmetic (libxml2 to read it, doubles to compute) and compares
 * the model sinew built.
 *
 * - skin_4_influence.dae (Assimp 5.2.5 crashes on it): every corner of every polygon,
 *   skinned at rest as COLLADA defines it: sum of w * joint world * inverse bind *
 *   bind shape * position.
 * - library_animation_clips.dae (Assimp refuses it): each clip's window and, at every key
 *   inside it, each animated node's local matrix equal to the key's <matrix>.
 * - samplers.dae (a fixture of sinew's own): BEZIER with (time, value) control points that
 *   overshoot, STEP, HERMITE, a BEZIER rotation, and one-number BEZIER tangents (played
 *   linearly with a warning), sampled at 101 times against the curves' formulas.
 * - 10,000 <animation_clip>s, generated: memory in proportion to the file.
 */
#include <fcntl.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include <libxml/parser.h>
#include <libxml/tree.h>

#include "../helpers.h"
#include "import/internal.h"
#include "sinew/sinew.h"

/* ---- reading the XML ------------------------------------------------------------------ */

static bool is(const xmlNode *n, const char *name)
{
    return n && n->type == XML_ELEMENT_NODE && strcmp((const char *)n->name, name) == 0;
}

static xmlNode *first(const xmlNode *n, const char *name)
{
    for (xmlNode *k = n ? n->children : NULL; k; k = k->next)
        if (is(k, name))
            return k;
    return NULL;
}

static bool attr_is(const xmlNode *n, const char *name, const char *value)
{
    xmlChar *v = xmlGetProp(n, (const xmlChar *)name);
    bool same = v && strcmp((const char *)v, value) == 0;
    xmlFree(v);
    return same;
}

/* The element anywhere under n whose attribute `name` is `value`. */
static xmlNode *find_attr(xmlNode *n, const char *name, const char *value)
{
    for (xmlNode *k = n; k; k = k->next) {
        if (k->type != XML_ELEMENT_NODE)
            continue;
        if (attr_is(k, name, value))
            return k;
        xmlNode *below = find_attr(k->children, name, value);
        if (below)
            return below;
    }
    return NULL;
}

static xmlNode *by_url(xmlDoc *doc, const xmlNode *n, const char *attribute)
{
    xmlChar *url = attribute ? xmlGetProp(n, (const xmlChar *)attribute) : xmlNodeGetContent(n);
    assert_non_null(url);
    xmlNode *found = find_attr(xmlDocGetRootElement(doc), "id", (const char *)url + (url[0] == '#'));
    xmlFree(url);
    assert_non_null(found);
    return found;
}

/* The numbers of an element's text, malloc'd. */
static double *numbers(const xmlNode *n, uint32_t *count)
{
    xmlChar *text = xmlNodeGetContent(n);
    size_t cap = 16, used = 0;
    double *v = malloc(cap * sizeof *v);
    char *p = (char *)text, *end;
    for (double x = strtod(p, &end); end != p; x = strtod(p, &end)) {
        if (used == cap)
            v = realloc(v, (cap *= 2) * sizeof *v);
        v[used++] = x;
        p = end;
    }
    xmlFree(text);
    *count = (uint32_t)used;
    return v;
}

/* A <source>'s float array. */
static double *source_numbers(const xmlNode *source, uint32_t *count)
{
    return numbers(first(source, "float_array"), count);
}

/* ---- matrices (dmat: column-major doubles, as sinew_mat4) ----------------------------------- */

/* One transform element as COLLADA 1.4.1 section 5 defines it. */
static dmat element(const xmlNode *e)
{
    uint32_t n;
    double *v = numbers(e, &n);
    dmat r = dmat_identity();
    if (is(e, "matrix") && n == 16) {
        r = dmat_from_rows(v);
    } else if (is(e, "translate") && n == 3) {
        r.m[12] = v[0], r.m[13] = v[1], r.m[14] = v[2];
    } else if (is(e, "scale") && n == 3) {
        r.m[0] = v[0], r.m[5] = v[1], r.m[10] = v[2];
    } else if (is(e, "rotate") && n == 4) {
        double len = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
        double x = v[0] / len, y = v[1] / len, z = v[2] / len, a = v[3] * M_PI / 180;
        double c = cos(a), s = sin(a), t = 1 - c;
        double rows[16] = {t * x * x + c,
                           t * x * y - s * z,
                           t * x * z + s * y,
                           0,
                           t * x * y + s * z,
                           t * y * y + c,
                           t * y * z - s * x,
                           0,
                           t * x * z - s * y,
                           t * y * z + s * x,
                           t * z * z + c,
                           0,
                           0,
                           0,
                           0,
                           1};
        r = dmat_from_rows(rows);
    }
    free(v);
    return r;
}

/* A <node>'s world matrix in the file's own space: its stack and its parents'. */
static dmat node_world(const xmlNode *node)
{
    dmat local = dmat_identity();
    for (xmlNode *k = node->children; k; k = k->next) {
        dmat e = element(k);
        local = dmat_mul(&local, &e);
    }
    if (!is(node->parent, "node"))
        return local;
    dmat parent = node_world(node->parent);
    return dmat_mul(&parent, &local);
}

static void transform_point(const dmat *a, const double p[3], double out[3])
{
    for (int r = 0; r < 3; r++)
        out[r] = a->m[r] * p[0] + a->m[4 + r] * p[1] + a->m[8 + r] * p[2] + a->m[12 + r];
}

/* ---- skin_4_influence.dae ------------------------------------------------------------- */

/* The file's skin at rest, one position a <polylist> corner, in the file's space. */
static double *file_skinned_corners(xmlDoc *doc, uint32_t *corner_count, uint32_t **vcount_out, uint32_t *polygons)
{
    xmlNode *root = xmlDocGetRootElement(doc);
    xmlNode *inst = find_attr(root, "url", "#controllers_0");
    assert_true(is(inst, "instance_controller"));
    xmlNode *controller = by_url(doc, inst, "url"), *skin = first(controller, "skin");
    xmlNode *geometry = by_url(doc, skin, "source"), *mesh = first(geometry, "mesh");
    uint32_t n;
    double *bsm_v = numbers(first(skin, "bind_shape_matrix"), &n);
    assert_int_equal(n, 16);
    dmat bind_shape = dmat_from_rows(bsm_v);
    free(bsm_v);
    /* joints (IDREFs) and inverse binds */
    xmlNode *joints = first(skin, "joints"), *names_src = NULL, *ibm_src = NULL;
    for (xmlNode *k = joints->children; k; k = k->next)
        if (is(k, "input"))
            *(attr_is(k, "semantic", "JOINT") ? &names_src : &ibm_src) = by_url(doc, k, "source");
    xmlChar *names = xmlNodeGetContent(first(names_src, "IDREF_array"));
    uint32_t ibm_count;
    double *ibm = source_numbers(ibm_src, &ibm_count);
    dmat skinning[16];
    uint32_t joint_count = 0;
    for (char *save = NULL, *id = strtok_r((char *)names, " \t\r\n", &save); id;
         id = strtok_r(NULL, " \t\r\n", &save), joint_count++) {
        assert_true(joint_count < 16 && (joint_count + 1) * 16 <= ibm_count);
        xmlNode *joint = find_attr(root, "id", id);
        assert_true(is(joint, "node"));
        dmat world = node_world(joint), inverse_bind = dmat_from_rows(&ibm[joint_count * 16]);
        dmat a = dmat_mul(&world, &inverse_bind);
        skinning[joint_count] = dmat_mul(&a, &bind_shape);
    }
    xmlFree(names);
    free(ibm);
    /* influences by position */
    xmlNode *vw = first(skin, "vertex_weights"), *weights_src = NULL;
    for (xmlNode *k = vw->children; k; k = k->next)
        if (is(k, "input") && attr_is(k, "semantic", "WEIGHT"))
            weights_src = by_url(doc, k, "source");
    uint32_t wn, vcn, vn;
    double *weights = source_numbers(weights_src, &wn), *vc = numbers(first(vw, "vcount"), &vcn),
           *v = numbers(first(vw, "v"), &vn);
    /* positions through <vertices> */
    xmlNode *vertices = first(mesh, "vertices"), *pos_src = NULL;
    for (xmlNode *k = vertices->children; k; k = k->next)
        if (is(k, "input") && attr_is(k, "semantic", "POSITION"))
            pos_src = by_url(doc, k, "source");
    uint32_t pn;
    double *positions = source_numbers(pos_src, &pn);
    double *skinned = calloc(pn, sizeof *skinned);
    for (uint32_t p = 0, at = 0; p < vcn; p++) {
        double sum = 0;
        for (uint32_t i = 0; i < (uint32_t)vc[p]; i++, at += 2)
            sum += weights[(uint32_t)v[at + 1]];
        at -= 2 * (uint32_t)vc[p];
        for (uint32_t i = 0; i < (uint32_t)vc[p]; i++, at += 2) {
            double out[3];
            transform_point(&skinning[(uint32_t)v[at]], &positions[p * 3], out);
            for (int e = 0; e < 3; e++)
                skinned[p * 3 + e] += weights[(uint32_t)v[at + 1]] / sum * out[e];
        }
    }
    free(weights);
    free(vc);
    free(v);
    free(positions);
    /* corners of the polylist */
    xmlNode *poly = first(mesh, "polylist");
    int stride = 0, vertex_offset = 0;
    for (xmlNode *k = poly->children; k; k = k->next)
        if (is(k, "input")) {
            xmlChar *o = xmlGetProp(k, (const xmlChar *)"offset");
            int off = atoi((const char *)o);
            xmlFree(o);
            stride = off + 1 > stride ? off + 1 : stride;
            if (attr_is(k, "semantic", "VERTEX"))
                vertex_offset = off;
        }
    uint32_t pc, ic;
    double *poly_vc = numbers(first(poly, "vcount"), &pc), *idx = numbers(first(poly, "p"), &ic);
    *corner_count = ic / (uint32_t)stride;
    *polygons = pc;
    *vcount_out = malloc(pc * sizeof **vcount_out);
    for (uint32_t i = 0; i < pc; i++)
        (*vcount_out)[i] = (uint32_t)poly_vc[i];
    double *corners = malloc(*corner_count * 3 * sizeof *corners);
    for (uint32_t c = 0; c < *corner_count; c++)
        memcpy(&corners[c * 3], &skinned[(uint32_t)idx[c * (uint32_t)stride + (uint32_t)vertex_offset] * 3],
               3 * sizeof *corners);
    free(poly_vc);
    free(idx);
    free(skinned);
    return corners;
}

static void test_skin_4_influence_against_its_xml(void **state)
{
    (void)state;
    char path[1024];
    if (!testdata_path("collada-cts/skin_4_influence.dae", path, sizeof path))
        skip();
    sinew_model *m = load_or_fail(path);
    xmlDoc *doc = xmlReadFile(path, NULL, XML_PARSE_NONET | XML_PARSE_HUGE);
    assert_non_null(doc);
    uint32_t corners, polygons, *vcount;
    double *want = file_skinned_corners(doc, &corners, &vcount, &polygons);
    assert_int_equal(m->mesh_count, 1);
    const sinew_mesh *mesh = &m->meshes[0];
    assert_int_equal(mesh->influence_count, 4);
    sinew_mat4 *worlds = pose_worlds(m, NULL, 0);
    uint32_t count;
    float *got = posed_vertices(m, worlds, &count);
    /* sinew's vertices are in Y-up metres under its root node: the file's space times the
     * root's matrix (the conversion itself is tested in test_models) */
    dmat root;
    for (int i = 0; i < 16; i++)
        root.m[i] = worlds[0].m[i];
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (uint32_t c = 0; c < corners; c++) {
        double p[3];
        transform_point(&root, &want[c * 3], p);
        memcpy(&want[c * 3], p, sizeof p);
        for (int e = 0; e < 3; e++)
            lo[e] = fmin(lo[e], p[e]), hi[e] = fmax(hi[e], p[e]);
    }
    double diagonal =
        sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) + (hi[2] - lo[2]) * (hi[2] - lo[2]));
    /* polygon k's n corners become its n - 2 triangles, in order; every triangle corner
     * must be one of its polygon's corners */
    double worst = 0;
    uint32_t triangle = 0, first_corner = 0;
    for (uint32_t k = 0; k < polygons; k++) {
        for (uint32_t t = 0; t + 2 < vcount[k]; t++, triangle++) {
            assert_true(triangle * 3 + 2 < mesh->index_count);
            for (int i = 0; i < 3; i++) {
                const float *g = &got[mesh->indices[triangle * 3 + i] * 3];
                double best = INFINITY;
                for (uint32_t c = first_corner; c < first_corner + vcount[k]; c++) {
                    const double *w = &want[c * 3];
                    best = fmin(best, fmax(fmax(fabs(g[0] - w[0]), fabs(g[1] - w[1])), fabs(g[2] - w[2])));
                }
                worst = fmax(worst, best);
            }
        }
        first_corner += vcount[k];
    }
    assert_int_equal(triangle * 3, mesh->index_count);
    print_message("skin_4_influence.dae: %u polygons, %u triangles; largest distance from the file's own skinning "
                  "%.3g (%.2g of the diagonal %.3g)\n",
                  polygons, triangle, worst, worst / diagonal, diagonal);
    assert_true(worst <= 1e-6 * diagonal);
    free(got);
    free(worlds);
    free(want);
    free(vcount);
    xmlFreeDoc(doc);
    sinew_model_free(m);
}

/* ---- library_animation_clips.dae ------------------------------------------------------ */

static double attr_double(const xmlNode *n, const char *name)
{
    xmlChar *v = xmlGetProp(n, (const xmlChar *)name);
    assert_non_null(v);
    double d = strtod((const char *)v, NULL);
    xmlFree(v);
    return d;
}

static void test_animation_clips_against_their_xml(void **state)
{
    (void)state;
    char path[1024];
    if (!testdata_path("assimp/Collada/library_animation_clips.dae", path, sizeof path))
        skip();
    sinew_model *m = load_or_fail(path);
    xmlDoc *doc = xmlReadFile(path, NULL, XML_PARSE_NONET | XML_PARSE_HUGE);
    assert_non_null(doc);
    xmlNode *clips = first(xmlDocGetRootElement(doc), "library_animation_clips");
    uint32_t clip_count = 0, keys_checked = 0;
    double worst = 0;
    for (xmlNode *ce = clips->children; ce; ce = ce->next) {
        if (!is(ce, "animation_clip"))
            continue;
        clip_count++;
        xmlChar *name = xmlGetProp(ce, (const xmlChar *)"name");
        int32_t ci = sinew_model_find_clip(m, (const char *)name);
        if (ci < 0)
            fail_msg("clip \"%s\" is missing", (const char *)name);
        xmlFree(name);
        const sinew_clip *clip = &m->clips[ci];
        double start = attr_double(ce, "start"), end = attr_double(ce, "end");
        assert_near(clip->duration, end - start, 1e-5, "clip window");
        for (xmlNode *ia = ce->children; ia; ia = ia->next) {
            if (!is(ia, "instance_animation"))
                continue;
            xmlNode *anim = by_url(doc, ia, "url"), *channel = first(anim, "channel");
            xmlNode *sampler = by_url(doc, channel, "source"), *input = NULL, *output = NULL;
            for (xmlNode *k = sampler->children; k; k = k->next) {
                if (is(k, "input") && attr_is(k, "semantic", "INPUT"))
                    input = by_url(doc, k, "source");
                else if (is(k, "input") && attr_is(k, "semantic", "OUTPUT"))
                    output = by_url(doc, k, "source");
            }
            xmlChar *target = xmlGetProp(channel, (const xmlChar *)"target");
            char *slash = strchr((char *)target, '/');
            assert_non_null(slash);
            assert_string_equal(slash, "/transform");
            *slash = 0;
            xmlNode *node = find_attr(xmlDocGetRootElement(doc), "id", (const char *)target);
            xmlFree(target);
            xmlChar *node_name = xmlGetProp(node, (const xmlChar *)"name");
            int32_t ni = sinew_model_find_node(m, (const char *)node_name);
            if (ni < 0)
                fail_msg("node \"%s\" is missing", (const char *)node_name);
            xmlFree(node_name);
            uint32_t tn, vn;
            double *times = source_numbers(input, &tn), *values = source_numbers(output, &vn);
            assert_int_equal(vn, tn * 16);
            for (uint32_t k = 0; k < tn; k++) {
                if (times[k] < start - 1e-6 || times[k] > end + 1e-6)
                    continue;
                sinew_transform locals[16];
                assert_true(m->node_count <= 16);
                sinew_sample_desc desc = {.model = m,
                                          .clip = clip,
                                          .time = (float)(times[k] - start),
                                          .locals = locals,
                                          .local_count = m->node_count};
                assert_int_equal(sinew_sample(&desc, NULL), SINEW_OK);
                sinew_mat4 got;
                sinew_transform_to_mat4(&locals[ni], &got);
                dmat want = dmat_from_rows(&values[k * 16]);
                for (int e = 0; e < 16; e++)
                    worst = fmax(worst, fabs(got.m[e] - want.m[e]));
                keys_checked++;
            }
            free(times);
            free(values);
        }
    }
    print_message("library_animation_clips.dae: %u clips, %u keys inside their windows; largest difference of a "
                  "local matrix element from the key's <matrix> %.3g\n",
                  clip_count, keys_checked, worst);
    assert_int_equal(clip_count, m->clip_count);
    assert_true(keys_checked > 50);
    assert_true(worst <= 1e-5);
    xmlFreeDoc(doc);
    sinew_model_free(m);
}

/* ---- samplers.dae --------------------------------------------------------------------- */

/* A cubic Bezier segment in (time, value): s solves x(s) = t by bisection, then y(s). */
static double bezier(const double p0[2], const double c0[2], const double c1[2], const double p1[2], double t)
{
    double lo = 0, hi = 1;
    for (int i = 0; i < 100; i++) {
        double s = (lo + hi) / 2, u = 1 - s;
        double x = u * u * u * p0[0] + 3 * u * u * s * c0[0] + 3 * u * s * s * c1[0] + s * s * s * p1[0];
        *(x < t ? &lo : &hi) = s;
    }
    double s = (lo + hi) / 2, u = 1 - s;
    return u * u * u * p0[1] + 3 * u * u * s * c0[1] + 3 * u * s * s * c1[1] + s * s * s * p1[1];
}

/* What samplers.dae says at time t: the translation and the angle about z (degrees). */
static void samplers_expected(double t, double translation[3], double *degrees)
{
    /* X: BEZIER 0 -> 1 over [0, 1], control points (0.2, 1.5) and (0.8, -0.5) */
    translation[0] = bezier((double[]){0, 0}, (double[]){0.2, 1.5}, (double[]){0.8, -0.5}, (double[]){1, 1}, t);
    /* Y: STEP 0, 2, 3 at 0, 0.5, 1 */
    translation[1] = t < 0.5 ? 0 : t < 1 ? 2 : 3;
    /* Z: HERMITE 0 -> 1 over [0, 1], tangents 3 and 0 (per unit of the segment's parameter) */
    double s = t, s2 = s * s, s3 = s2 * s;
    translation[2] = (-2 * s3 + 3 * s2) * 1 + (s3 - 2 * s2 + s) * 3;
    /* rotateZ: BEZIER 0 -> 180 degrees, control points (0.3, 120) and (0.7, 200) */
    *degrees = bezier((double[]){0, 0}, (double[]){0.3, 120}, (double[]){0.7, 200}, (double[]){1, 180}, t);
}

static void test_samplers_as_the_file_says(void **state)
{
    (void)state;
    char path[1024];
    sinew_model *m = load_or_fail(fixture_path("samplers.dae", path, sizeof path));
    int32_t mover = sinew_model_find_node(m, "mover"), legacy = sinew_model_find_node(m, "legacy");
    assert_true(mover >= 0 && legacy >= 0);
    assert_int_equal(m->clip_count, 1);
    bool warned = false;
    for (uint32_t i = 0; i < m->warning_count; i++)
        warned |= strstr(m->warnings[i], "1 channels give BEZIER tangents as one number") != NULL;
    assert_true(warned);
    double worst_t = 0, worst_angle = 0, worst_legacy = 0;
    for (int i = 0; i <= 100; i++) {
        double t = i / 100.0;
        sinew_transform locals[8];
        assert_true(m->node_count <= 8);
        sinew_sample_desc desc = {
            .model = m, .clip = &m->clips[0], .time = (float)t, .locals = locals, .local_count = m->node_count};
        assert_int_equal(sinew_sample(&desc, NULL), SINEW_OK);
        double want[3], degrees;
        samplers_expected(t, want, &degrees);
        if (i == 50 || i == 100) /* STEP changes value at its keys: either side is right there */
            want[1] = locals[mover].translation[1];
        for (int e = 0; e < 3; e++)
            worst_t = fmax(worst_t, fabs(locals[mover].translation[e] - want[e]));
        const float *q = locals[mover].rotation; /* about z: (0, 0, sin, cos) of half the angle */
        double angle = 2 * atan2(q[2], q[3]), off_axis = fmax(fabs(q[0]), fabs(q[1]));
        worst_angle = fmax(worst_angle, fmax(fabs(remainder(angle - degrees * M_PI / 180, 2 * M_PI)), off_axis));
        /* legacy: one-number tangents, played as the straight line 0 -> 1 */
        worst_legacy = fmax(worst_legacy, fabs(locals[legacy].translation[0] - t));
    }
    print_message("samplers.dae: largest differences from the curves: translation %.3g, rotation %.3g rad, "
                  "one-number tangents from the straight line %.3g\n",
                  worst_t, worst_angle, worst_legacy);
    assert_true(worst_t <= 1e-5);
    assert_true(worst_angle <= 1e-6);
    assert_true(worst_legacy <= 1e-6);
    sinew_model_free(m);
}

/* sinew's fixture bezier_kept.dae: a translate, rotate, scale stack whose translate is one
 * BEZIER curve of three components and whose scale X is LINEAR keeps them as the runtime's
 * Bezier keys, the file's three and two keys, equal to the curves written in the file. */
static void test_bezier_kept_as_the_file_says(void **state)
{
    (void)state;
    char path[1024];
    sinew_model *m = load_or_fail(fixture_path("bezier_kept.dae", path, sizeof path));
    int32_t eased = sinew_model_find_node(m, "eased");
    assert_true(eased >= 0);
    const sinew_clip *clip = &m->clips[0];
    assert_int_equal(clip->track_count, 1);
    const sinew_channel *t = &clip->tracks[0].channels[SINEW_CHANNEL_TRANSLATION],
                        *s = &clip->tracks[0].channels[SINEW_CHANNEL_SCALE];
    assert_int_equal(t->interp, SINEW_INTERP_BEZIER);
    assert_int_equal(t->key_count, 3);
    assert_int_equal(s->interp, SINEW_INTERP_BEZIER);
    assert_int_equal(s->key_count, 2);
    /* the file's curves: segment [0, 1] then [1, 3], per component (time, value) points */
    static const double seg[2][3][4][2] = {{{{0, 0}, {0.8, 0}, {0.2, 2}, {1, 2}},
                                            {{0, 1}, {0.2, 1}, {0.9, 1}, {1, 1}},
                                            {{0, 0}, {0.5, -0.5}, {0.6, -1}, {1, -1}}},
                                           {{{1, 2}, {1.9, 2}, {2.9, 0}, {3, 0}},
                                            {{1, 1}, {1.5, 1}, {2.0, 4}, {3, 4}},
                                            {{1, -1}, {2, -1}, {2.5, -1}, {3, -1}}}};
    double worst = 0, worst_scale = 0;
    for (int i = 0; i <= 300; i++) {
        double time = 3.0 * i / 300;
        sinew_transform locals[4];
        assert_true(m->node_count <= 4);
        sinew_sample_desc desc = {
            .model = m, .clip = clip, .time = (float)time, .locals = locals, .local_count = m->node_count};
        assert_int_equal(sinew_sample(&desc, NULL), SINEW_OK);
        for (int c = 0; c < 3; c++)
            worst = fmax(worst, fabs(locals[eased].translation[c] - bezier_reference(seg[time < 1 ? 0 : 1][c], time)));
        worst_scale = fmax(worst_scale, fabs(locals[eased].scale[0] - (1 + time / 3)));
    }
    print_message("bezier_kept.dae: Bezier keys kept (3 translation, 2 scale); largest difference from the file's "
                  "curves %.2g, scale from its line %.2g\n",
                  worst, worst_scale);
    assert_true(worst < 1e-6);
    assert_true(worst_scale < 1e-6);
    sinew_model_free(m);
}

/* A skeleton-only file that types no node JOINT: its joints are the nodes its clips move,
 * their end sites below moved nodes, never a camera or a node that nothing moves. */
static void test_skeleton_from_the_clips(void **state)
{
    (void)state;
    char src[1024], path[1024];
    size_t size;
    char *text = read_file(fixture_path("samplers.dae", src, sizeof src), &size);
    char *edited = malloc(size + 512);
    char *tip = strstr(text, "<translate sid=\"t\">0 0 0</translate>\n        </node>");
    assert_non_null(tip);
    tip = strstr(tip, "</node>");
    int head = (int)(tip - text);
    int n = snprintf(edited, size + 512,
                     "%.*s<node id=\"tip\" name=\"tip\"/></node><node id=\"cam\" name=\"cam\">"
                     "<instance_camera url=\"#none\"/></node>%s",
                     head, text, tip + strlen("</node>"));
    char *still = strstr(edited, "</visual_scene>");
    assert_non_null(still);
    memmove(still + strlen("<node id=\"still\" name=\"still\"/>"), still, strlen(still) + 1);
    memcpy(still, "<node id=\"still\" name=\"still\"/>", strlen("<node id=\"still\" name=\"still\"/>"));
    n += (int)strlen("<node id=\"still\" name=\"still\"/>");
    for (char *t; (t = strstr(edited, "type=\"JOINT\""));)
        memcpy(t, "type=\"NODE\" ", strlen("type=\"JOINT\""));
    write_file(tmp_path("untyped.dae", path, sizeof path), edited, (size_t)n);
    sinew_model *m = load_or_fail(path);
    static const struct {
        const char *name;
        bool joint;
    } expect[] = {{"mover", true}, {"legacy", true}, {"tip", true}, {"cam", false}, {"still", false}, {"scene", false}};
    for (size_t i = 0; i < sizeof expect / sizeof expect[0]; i++) {
        int32_t node = sinew_model_find_node(m, expect[i].name);
        if (node < 0 || sinew_model_node_is_joint(m, (uint32_t)node) != expect[i].joint)
            fail_msg("node %s: %s, expected %s", expect[i].name,
                     node < 0                                       ? "missing"
                     : sinew_model_node_is_joint(m, (uint32_t)node) ? "a joint"
                                                                    : "not a joint",
                     expect[i].joint ? "a joint" : "not a joint");
    }
    sinew_model_free(m);
    free(edited);
    free(text);
}

/* ---- 10,000 clips --------------------------------------------------------------------- */

/* A 2,000-key animation of one node and `clips` <animation_clip>s over it: side by side
 * (`overlap` false) or each over the whole animation. */
static void write_many_clips(const char *path, uint32_t clips, bool overlap)
{
    FILE *f = fopen(path, "w");
    assert_non_null(f);
    const uint32_t keys = 2000;
    double duration = (keys - 1) / 30.0;
    fprintf(f, "<?xml version=\"1.0\"?>\n<COLLADA xmlns=\"http://www.collada.org/2005/11/COLLADASchema\" "
               "version=\"1.4.1\"><asset><up_axis>Y_UP</up_axis></asset>\n<library_animations><animation id=\"a\">"
               "<source id=\"i\"><float_array id=\"ia\" count=\"2000\">");
    for (uint32_t k = 0; k < keys; k++)
        fprintf(f, "%.9g ", k / 30.0);
    fprintf(f, "</float_array><technique_common><accessor source=\"#ia\" count=\"2000\"><param name=\"TIME\" "
               "type=\"float\"/></accessor></technique_common></source><source id=\"o\"><float_array id=\"oa\" "
               "count=\"2000\">");
    for (uint32_t k = 0; k < keys; k++)
        fprintf(f, "%g ", k * 0.01);
    fprintf(f, "</float_array><technique_common><accessor source=\"#oa\" count=\"2000\"><param name=\"X\" "
               "type=\"float\"/></accessor></technique_common></source><sampler id=\"s\"><input semantic=\"INPUT\" "
               "source=\"#i\"/><input semantic=\"OUTPUT\" source=\"#o\"/></sampler><channel source=\"#s\" "
               "target=\"n/t.X\"/></animation></library_animations>\n<library_animation_clips>\n");
    for (uint32_t c = 0; c < clips; c++)
        fprintf(f,
                "<animation_clip id=\"c%u\" start=\"%.9g\" end=\"%.9g\"><instance_animation url=\"#a\"/>"
                "</animation_clip>\n",
                c, overlap ? 0 : duration * c / clips, overlap ? duration : duration * (c + 1) / clips);
    fprintf(f, "</library_animation_clips><library_visual_scenes><visual_scene id=\"v\"><node id=\"n\" name=\"n\" "
               "type=\"JOINT\"><translate sid=\"t\">0 0 0</translate></node></visual_scene>"
               "</library_visual_scenes><scene><instance_visual_scene url=\"#v\"/></scene></COLLADA>\n");
    fclose(f);
}

/* Channel keys a clip plays, and the bytes of the model's blob. */
static uint64_t clip_keys(const sinew_clip *clip)
{
    uint64_t keys = 0;
    for (uint32_t t = 0; t < clip->track_count; t++)
        for (int k = 0; k < SINEW_CHANNEL_COUNT; k++)
            keys += clip->tracks[t].channels[k].key_count;
    return keys;
}

/* Memory follows the file: 10,000 clips over one animation share its keys, whether side by
 * side or each over the whole of it (a clip is a window: a start and the keys it reaches). */
static void test_ten_thousand_clips(void **state)
{
    (void)state;
    for (int overlap = 0; overlap < 2; overlap++) {
        char path[1024];
        write_many_clips(tmp_path(overlap ? "clips-overlapping.dae" : "clips-side-by-side.dae", path, sizeof path),
                         10000, overlap);
        sinew_model *m = load_or_fail(path);
        assert_int_equal(m->clip_count, 10000);
        uint64_t keys = 0, most = 0;
        for (uint32_t c = 0; c < m->clip_count; c++) {
            keys += clip_keys(&m->clips[c]);
            most = clip_keys(&m->clips[c]) > most ? clip_keys(&m->clips[c]) : most;
            assert_ptr_equal(m->clips[c].times, m->clips[0].times); /* one pool */
        }
        const void *bytes;
        size_t size;
        sinew_model_blob(m, &bytes, &size);
        print_message("10,000 clips %s a 2,000-key animation: windows of %llu keys in all (at most %llu), one pool "
                      "of %u keys, blob %zu bytes\n",
                      overlap ? "each over the whole of" : "side by side over", (unsigned long long)keys,
                      (unsigned long long)most, m->clips[0].time_count, size);
        assert_true(m->clips[0].time_count <= 2000 + 2);
        assert_true(size < 3u << 20); /* the tracks of 10,000 clips, names, the keys once */
        assert_true(overlap ? most == 2000 : most <= 6);
        /* clip 5000 starts half-way through the animation, at 1999 / 60 s, where x = 0.3 a second */
        sinew_transform locals[2];
        assert_true(m->node_count <= 2);
        int32_t n = sinew_model_find_node(m, "n");
        uint32_t c = overlap ? 0 : 5000;
        float at = overlap ? 1999 / 60.0f : m->clips[c].duration / 2; /* the middle of the animation; of the clip */
        sinew_sample_desc desc = {.model = m, .clip = &m->clips[c], .time = at, .locals = locals, .local_count = 2};
        assert_int_equal(sinew_sample(&desc, NULL), SINEW_OK);
        double expect = overlap ? 0.3 * 1999 / 60.0 : 0.3 * (1999 / 60.0 + m->clips[c].duration / 2);
        assert_near(locals[n].translation[0], expect, 1e-4, "a clip of many at a time inside it");
        sinew_model_free(m);
    }
}

/* sinew's fixture: clips "early" [0.5, 2.5] s and "late" [1.5, 4] s of one animation (x by
 * keys 0 1 4 9 16 with a step after 2 s, a turn of 90 degrees a second about y) share its
 * keys and play their own windows. */
static void test_clip_windows_fixture(void **state)
{
    (void)state;
    char path[1024];
    sinew_model *m = load_or_fail(fixture_path("clip_windows.dae", path, sizeof path));
    assert_int_equal(m->clip_count, 2);
    assert_ptr_equal(m->clips[0].times, m->clips[1].times);
    assert_near(m->clips[0].duration, 2.0, 1e-6, "early's length");
    assert_near(m->clips[1].duration, 2.5, 1e-6, "late's length");
    static const struct {
        uint32_t clip;
        float t;
        double x, degrees;
    } expect[] = {
        {0, 0.0f, 0.5, 45},   {0, 0.5f, 1.0, 90},   {0, 1.25f, 3.25, 157.5}, {0, 2.0f, 4.0, 225},
        {1, 0.0f, 2.5, 135},  {1, 0.5f, 4.0, 180},  {1, 1.25f, 4.0, 247.5},  {1, 1.5f, 9.0, 270},
        {1, 2.0f, 12.5, 315}, {1, 2.5f, 16.0, 360}, {1, 9.0f, 16.0, 360}, /* clamped to the window's end */
    };
    int32_t bone = sinew_model_find_node(m, "bone");
    sinew_transform locals[8];
    assert_true(bone >= 0 && m->node_count <= 8);
    for (size_t i = 0; i < sizeof expect / sizeof expect[0]; i++) {
        sinew_sample_desc desc = {.model = m,
                                  .clip = &m->clips[expect[i].clip],
                                  .time = expect[i].t,
                                  .locals = locals,
                                  .local_count = m->node_count};
        assert_int_equal(sinew_sample(&desc, NULL), SINEW_OK);
        double half = expect[i].degrees * M_PI / 360.0;
        assert_near(locals[bone].translation[0], expect[i].x, 1e-5, "x in a window");
        assert_near(fabs(locals[bone].rotation[1]), fabs(sin(half)), 1e-5, "the turn in a window");
        assert_near(fabs(locals[bone].rotation[3]), fabs(cos(half)), 1e-5, "the turn in a window");
    }
    sinew_model_free(m);
}

/* Largest difference of the world matrices of two models' clips at the same clip time,
 * node by name (a written file may have a root node more), for the CTS clip file. */
static double worlds_apart(const sinew_model *a, const sinew_clip *ca, const sinew_model *b, const sinew_clip *cb,
                           float t)
{
    sinew_mat4 *wa = pose_worlds(a, ca, t), *wb = pose_worlds(b, cb, t);
    double most = 0;
    for (uint32_t n = 0; n < a->node_count; n++) {
        int32_t m = sinew_model_find_node(b, a->node_names[n]);
        if (m < 0) /* Assimp names a root node its own way */
            continue;
        for (int i = 0; i < 16; i++)
            most = fmax(most, fabs((double)wa[n].m[i] - wb[m].m[i]));
    }
    assert_true(sinew_model_find_node(b, "prop") >= 0); /* the animated node */
    free(wa);
    free(wb);
    return most;
}

/* Two clips of the CTS file are windows [1, 2] and [3, 4] s of one animation: they share
 * its keys, and every consumer plays the window: sinew_sample(), the player, a .sinew
 * file (which keeps one copy) and the COLLADA writer. */
static void test_clip_windows_everywhere(void **state)
{
    (void)state;
    char path[1024], saved[1024], dae[1024];
    if (!testdata_path("collada-cts/clip_2_clips_on_same_animation_different_time.dae", path, sizeof path))
        skip();
    sinew_model *m = load_or_fail(path);
    assert_int_equal(m->clip_count, 2);
    assert_ptr_equal(m->clips[0].times, m->clips[1].times);
    assert_near(m->clips[1].start - m->clips[0].start, 2.0, 1e-6, "the second window starts 2 s later");

    /* the player against sinew_sample() + sinew_local_to_world() */
    double player_most = 0;
    for (uint32_t c = 0; c < m->clip_count; c++) {
        test_player tp;
        sinew_player *player = test_player_open(&tp, m, &m->clips[c]);
        sinew_mat4 *worlds = calloc(m->node_count, sizeof *worlds);
        for (int i = 0; i <= 40; i++) {
            float t = m->clips[c].duration * (float)i / 40;
            assert_int_equal(sinew_player_update(player, t, SINEW_WRAP_CLAMP, NULL, worlds, m->node_count, NULL),
                             SINEW_OK);
            sinew_mat4 *ref = pose_worlds(m, &m->clips[c], t);
            for (uint32_t n = 0; n < m->node_count; n++)
                for (int e = 0; e < 16; e++)
                    player_most = fmax(player_most, fabs((double)worlds[n].m[e] - ref[n].m[e]));
            free(ref);
        }
        free(worlds);
        test_player_close(&tp);
    }

    /* .sinew: the shared keys written once, read back shared, the same numbers */
    sinew_error error = {0};
    assert_int_equal(sinew_model_save(m, NULL, tmp_path("clip-windows.sinew", saved, sizeof saved), &error), SINEW_OK);
    sinew_model *back = NULL;
    assert_int_equal(sinew_model_load(saved, NULL, &back, &error), SINEW_OK);
    assert_ptr_equal(back->clips[0].times, back->clips[1].times);
    const void *bytes;
    size_t size, back_size;
    sinew_model_blob(m, &bytes, &size);
    sinew_model_blob(back, &bytes, &back_size);
    assert_true(back_size <= size + 256);

    /* COLLADA written and read again: the windows on one timeline */
    assert_int_equal(sinew_model_write_collada(m, tmp_path("clip-windows.dae", dae, sizeof dae), &error), SINEW_OK);
    sinew_model *again = load_or_fail(dae);
    assert_int_equal(again->clip_count, 2);
    double saved_most = 0, dae_most = 0;
    for (uint32_t c = 0; c < m->clip_count; c++)
        for (int i = 0; i <= 40; i++) {
            float t = m->clips[c].duration * (float)i / 40;
            saved_most = fmax(saved_most, worlds_apart(m, &m->clips[c], back, &back->clips[c], t));
            dae_most = fmax(dae_most, worlds_apart(m, &m->clips[c], again, &again->clips[c], t));
        }
    /* Assimp's one merged clip cut into the same windows (SINEW_IMPORTER=assimp) */
    sinew_model *assimp = NULL;
    sinew_import_desc d = {.path = path, .assimp = true};
    assert_int_equal(sinew_import(&d, &assimp, &error), SINEW_OK);
    assert_int_equal(assimp->clip_count, 2);
    assert_ptr_equal(assimp->clips[0].times, assimp->clips[1].times);
    double assimp_most = 0;
    for (uint32_t c = 0; c < m->clip_count; c++)
        for (int i = 0; i <= 40; i++)
            assimp_most = fmax(assimp_most, worlds_apart(m, &m->clips[c], assimp, &assimp->clips[c],
                                                         m->clips[c].duration * (float)i / 40));
    sinew_model_free(assimp);
    print_message("clip windows: player %.2g from sinew_sample; .sinew %.2g (%zu bytes, was %zu); COLLADA written "
                  "and read %.2g; Assimp's clip cut %.2g\n",
                  player_most, saved_most, back_size, size, dae_most, assimp_most);
    assert_true(assimp_most < 1e-5);
    assert_true(player_most < 1e-5);
    assert_true(saved_most == 0);
    assert_true(dae_most < 1e-4);
    sinew_model_free(again);
    sinew_model_free(back);
    sinew_model_free(m);
}

/* The library never prints: libxml2 reports encoding errors through its generic handler
 * (to stderr, whatever the parse options say); sinew quiets it and returns the error. */
static double srgb_to_linear(double c)
{
    return c <= 0.04045 ? c / 12.92 : pow((c + 0.055) / 1.055, 2.4);
}

/* kwxport_test_vcolors.dae (a 3ds Max export): every triangle corner's COLOR, from its <p> and its
 * source, is the colour of the vertex sinew made of that corner, taken from sRGB to linear (the
 * reading of three.js and Blender); alpha 1 for RGB. sinew_model_write_collada() writes them back
 * as sRGB, and reading that file gives the same colours. */
static void test_vertex_colours_against_their_xml(void **state)
{
    (void)state;
    char path[1024], written[1024];
    if (!testdata_path("assimp/Collada/kwxport_test_vcolors.dae", path, sizeof path))
        skip();
    sinew_model *m = load_or_fail(path);
    xmlDoc *doc = xmlReadFile(path, NULL, XML_PARSE_NONET);
    assert_non_null(doc);
    xmlNode *mesh_el = find_attr(xmlDocGetRootElement(doc), "id", "Box01-mesh");
    assert_non_null(mesh_el);
    uint32_t mesh = 0, checked = 0;
    for (xmlNode *tri = first(first(mesh_el, "mesh") ? first(mesh_el, "mesh") : mesh_el, "triangles"); tri;
         tri = tri->next) {
        if (!is(tri, "triangles"))
            continue;
        assert_true(mesh < m->mesh_count);
        const sinew_mesh *got = &m->meshes[mesh++];
        assert_non_null(got->colors);
        uint32_t stride = 0, color_offset = 0, count, n;
        xmlNode *source = NULL;
        for (xmlNode *in = tri->children; in; in = in->next) {
            if (!is(in, "input"))
                continue;
            xmlChar *offset = xmlGetProp(in, (const xmlChar *)"offset");
            uint32_t o = (uint32_t)atoi((const char *)offset);
            xmlFree(offset);
            stride = o + 1 > stride ? o + 1 : stride;
            if (attr_is(in, "semantic", "COLOR"))
                color_offset = o, source = by_url(doc, in, "source");
        }
        assert_non_null(source);
        double *colors = source_numbers(source, &count), *p = numbers(first(tri, "p"), &n);
        assert_int_equal(n / stride, got->index_count);
        for (uint32_t c = 0; c < got->index_count; c++, checked++) {
            uint32_t at = (uint32_t)p[c * stride + color_offset];
            const float *rgba = &got->colors[got->indices[c] * 4];
            for (int k = 0; k < 3; k++)
                assert_float_equal(rgba[k], srgb_to_linear(colors[at * 3 + k]), 1e-6);
            assert_float_equal(rgba[3], 1.0, 0.0);
        }
        free(colors);
        free(p);
    }
    xmlFreeDoc(doc);
    assert_int_equal(mesh, m->mesh_count);
    assert_int_equal(checked, 36);

    sinew_error error = {0};
    assert_int_equal(sinew_model_write_collada(m, tmp_path("vcolors.dae", written, sizeof written), &error), SINEW_OK);
    sinew_model *back = load_or_fail(written);
    assert_int_equal(back->mesh_count, m->mesh_count);
    for (uint32_t i = 0; i < m->mesh_count; i++) {
        assert_non_null(back->meshes[i].colors);
        assert_int_equal(back->meshes[i].index_count, m->meshes[i].index_count);
        for (uint32_t c = 0; c < m->meshes[i].index_count; c++)
            for (int k = 0; k < 4; k++)
                assert_float_equal(back->meshes[i].colors[back->meshes[i].indices[c] * 4 + k],
                                   m->meshes[i].colors[m->meshes[i].indices[c] * 4 + k], 1e-5);
    }
    sinew_model_free(back);
    sinew_model_free(m);
}

static void test_encoding_errors_are_not_printed(void **state)
{
    (void)state;
    char path[1024], err_path[1024];
    static const char text[] = "<?xml version=\"1.0\" encoding=\"UTF-32\"?><COLLADA>\0\0\0\0</COLLADA>";
    write_file(tmp_path("utf32-lie.dae", path, sizeof path), text, sizeof text - 1);
    fflush(stderr);
    int saved = dup(2),
        to = open(tmp_path("stderr.txt", err_path, sizeof err_path), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    assert_true(saved >= 0 && to >= 0);
    dup2(to, 2);
    close(to);
    sinew_model *m = NULL;
    sinew_error error = {0};
    sinew_import_desc desc = {.path = path};
    sinew_result r = sinew_import(&desc, &m, &error);
    fflush(stderr);
    dup2(saved, 2);
    close(saved);
    assert_int_equal(r, SINEW_ERROR_FORMAT);
    assert_non_null(strstr(error.message, "not well-formed XML"));
    size_t printed;
    free(read_file(err_path, &printed));
    assert_int_equal(printed, 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_skin_4_influence_against_its_xml),
        cmocka_unit_test(test_animation_clips_against_their_xml),
        cmocka_unit_test(test_samplers_as_the_file_says),
        cmocka_unit_test(test_bezier_kept_as_the_file_says),
        cmocka_unit_test(test_skeleton_from_the_clips),
        cmocka_unit_test(test_ten_thousand_clips),
        cmocka_unit_test(test_clip_windows_fixture),
        cmocka_unit_test(test_clip_windows_everywhere),
        cmocka_unit_test(test_encoding_errors_are_not_printed),
        cmocka_unit_test(test_vertex_colours_against_their_xml),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
