/* `sinew info FILE [--json]`: what a model file holds. */
#include <stdlib.h>
#include <string.h>

#include "cjson.h"
#include "cli.h"

static const char info_usage[] =
    "usage: sinew info FILE [--json]\n"
    "\n"
    "Prints what FILE holds as sinew reads it: node, joint, mesh, vertex, triangle, skin, material and\n"
    "clip counts; each clip with its duration in seconds, its frame rate and key counts, the morph\n"
    "channels it animates (and, for clips cut from one animation that share its keys, where on its\n"
    "timeline the clip starts); the morph channels; each mesh with its skinning method, morph targets\n"
    "(by channel, with in-between shapes' full weights) and vertex cache; each material\n"
    "with its colour and texture (a file's path, or an image embedded in the file); the node tree with\n"
    "joints and meshes marked; and the import warnings (dropped dummy meshes, missing textures, repaired\n"
    "weights, ...).\n"
    "\n"
    "  --json   the same as one JSON object: {\"file\", \"format\", [\"converted_from\", \"converted_from_format\",]\n"
    "           \"counts\": {...}, \"meshes\": [...],\n"
    "           \"materials\": [{\"name\", \"base_color\", \"diffuse_texture\", \"diffuse_image\": null or\n"
    "           {\"type\": png/jpeg/other, \"bytes\"} (an image embedded in the file), \"alpha_mode\" (opaque, mask,\n"
    "           blend) and \"alpha_cutoff\", ...}],\n"
    "           \"clips\": [{\"index\", \"name\", \"duration\", \"start\", \"timeline\", \"frame_rate\",\n"
    "           \"clips_sharing_keys\", \"tracks\", \"keys\": {...}, \"weight_tracks\": [{\"channel\", \"keys\"}]}],\n"
    "           \"morph_channels\": [{\"name\", \"default_weight\"}], meshes also give \"skin_method\"\n"
    "           (linear, dual_quaternion or mixed), \"flat_normals\" (the file gave no normals and asks for\n"
    "           faceted ones, as glTF does: drawn flat), \"colors\" (vertex colours), \"morph_targets\": [{\"name\", "
    "\"channel\", \"full_weight\",\n"
    "           \"vertices\", \"normals\", \"tangents\"}] and \"cache\": {\"frames\", \"from\", \"to\"} or null,\n"
    "           \"nodes\":\n"
    "           [{\"name\", \"parent\", \"joint\", \"inherit\"}], \"warnings\": [...]}\n"
    "           (inherit: normal, ignore_parent_scale or componentwise_scale, FBX's inherit types)\n";

/* How many clips play the same keys as clip i (itself included): windows cut from one
 * animation share its times and values. */
static uint32_t clips_sharing_keys(const sinew_model *m, uint32_t i)
{
    uint32_t n = 0;
    for (uint32_t c = 0; c < m->clip_count; c++)
        n += m->clips[c].time_count && m->clips[c].times == m->clips[i].times;
    return n ? n : 1;
}

/* Each map's name in text and JSON output. */
static const char *const MAP_LABELS[SINEW_MAP_COUNT] = {"base colour", "metallic-roughness", "normal", "occlusion",
                                                        "emissive"};
static const char *const MAP_KEYS[SINEW_MAP_COUNT] = {"base_color", "metallic_roughness", "normal", "occlusion",
                                                      "emissive"};

/* What an embedded image is, by its first bytes. */
static const char *image_kind(const sinew_texture *map)
{
    const unsigned char *b = map->image;
    uint32_t n = map->image_size;
    if (n >= 8 && memcmp(b, "\x89PNG\r\n\x1a\n", 8) == 0)
        return "png";
    if (n >= 3 && b[0] == 0xff && b[1] == 0xd8 && b[2] == 0xff)
        return "jpeg";
    return "other";
}

typedef struct counts {
    uint32_t joints, vertices, triangles, bones, skinned;
} counts;

static counts count_model(const sinew_model *m)
{
    counts c = {0};
    for (uint32_t n = 0; n < m->node_count; n++)
        c.joints += sinew_model_node_is_joint(m, n);
    for (uint32_t i = 0; i < m->mesh_count; i++) {
        c.vertices += m->meshes[i].vertex_count;
        c.triangles += m->meshes[i].index_count / 3;
        if (m->meshes[i].skin >= 0) {
            c.skinned++;
            c.bones += m->skins[m->meshes[i].skin].joint_count;
        }
    }
    return c;
}

static void clip_keys(const sinew_clip *clip, uint32_t keys[SINEW_CHANNEL_COUNT])
{
    memset(keys, 0, SINEW_CHANNEL_COUNT * sizeof keys[0]);
    for (uint32_t t = 0; t < clip->track_count; t++)
        for (int k = 0; k < SINEW_CHANNEL_COUNT; k++)
            keys[k] += clip->tracks[t].channels[k].key_count;
}

static const char *const SKIN_METHODS[] = {"linear", "dual_quaternion", "mixed"};

static const char *skin_method(const sinew_model *m, const sinew_mesh *mesh)
{
    uint32_t b = mesh->skin >= 0 ? m->skins[mesh->skin].blend : 0;
    return SKIN_METHODS[b <= 2 ? b : 0];
}

/* The model channel of a mesh's channel: through its first instance (glTF may give other
 * instances channels of their own). */
static const char *channel_name(const sinew_model *m, uint32_t mesh, uint32_t channel)
{
    for (uint32_t i = 0; i < m->instance_count; i++)
        if (m->instances[i].mesh == mesh && m->instances[i].morph_first + channel < m->morph_channel_count)
            return m->morph_channels[m->instances[i].morph_first + channel].name;
    return "?";
}

static void print_morphs(const sinew_model *m, uint32_t index)
{
    const sinew_mesh *mesh = &m->meshes[index];
    for (uint32_t t = 0; t < mesh->target_count; t++) {
        const sinew_morph_target *tg = &mesh->targets[t];
        printf("  target %u  \"%s\"  channel \"%s\"", t, tg->name, channel_name(m, index, tg->channel));
        if (tg->full_weight != 1.0f)
            printf(" (whole at %.4g)", (double)tg->full_weight);
        printf("  %u vertices moved%s%s\n", tg->delta_count, tg->normals ? ", normals" : "",
               tg->tangents ? ", tangents" : "");
    }
    if (mesh->cache && mesh->cache->frame_count)
        printf("  vertex cache: %u frames, %.4f to %.4f s of the file's timeline\n", mesh->cache->frame_count,
               (double)mesh->cache->times[0], (double)mesh->cache->times[mesh->cache->frame_count - 1]);
}

static void print_tree(const sinew_model *m, int32_t parent, int depth)
{
    for (uint32_t n = 0; n < m->node_count; n++) {
        if (m->node_parents[n] != parent)
            continue;
        bool has_mesh = false;
        for (uint32_t i = 0; i < m->instance_count; i++)
            has_mesh |= m->instances[i].node == n;
        static const char *const inherits[] = {"", "  [ignores parent scale: Rrs]", "  [componentwise scale: RrSs]"};
        uint8_t inherit = m->node_inherit ? m->node_inherit[n] : SINEW_INHERIT_NORMAL;
        printf("  %*s%s%s%s%s\n", depth * 2, "", m->node_names[n], sinew_model_node_is_joint(m, n) ? "  [joint]" : "",
               has_mesh ? "  [mesh]" : "", inherits[inherit <= 2 ? inherit : 0]);
        print_tree(m, (int32_t)n, depth + 1);
    }
}

static void print_text(const sinew_model *m)
{
    counts c = count_model(m);
    printf("file:       %s\n", m->source);
    if (m->converted_from)
        printf("format:     sinew, converted from %s (%s)\n", m->converted_from, m->format);
    else
        printf("format:     %s\n", m->format);
    printf("nodes:      %u (%u joints)\n", m->node_count, c.joints);
    printf("meshes:     %u (%u skinned), %u instances, %u vertices, %u triangles\n", m->mesh_count, c.skinned,
           m->instance_count, c.vertices, c.triangles);
    printf("skins:      %u (%u bones in all)\n", m->skin_count, c.bones);
    printf("materials:  %u\n", m->material_count);
    printf("clips:      %u\n", m->clip_count);
    if (m->muscles)
        printf("muscles:    %u stored with the model\n", m->muscles->muscle_count);
    for (uint32_t i = 0; i < m->clip_count; i++) {
        uint32_t keys[SINEW_CHANNEL_COUNT];
        clip_keys(&m->clips[i], keys);
        printf("  %u  \"%s\"  %.4f s  %u tracks  keys: %u translation, %u rotation, %u scale", i, m->clips[i].name,
               (double)m->clips[i].duration, m->clips[i].track_count, keys[0], keys[1], keys[2]);
        if (m->clips[i].weight_track_count)
            printf(", %u morph channels", m->clips[i].weight_track_count);
        if (m->clips[i].frame_rate > 0.0f)
            printf("  %.6g fps", (double)m->clips[i].frame_rate);
        if (m->clips[i].timeline != 0.0f)
            printf("  (from %.4f s of the file's timeline)", (double)m->clips[i].timeline);
        uint32_t sharing = clips_sharing_keys(m, i);
        if (sharing > 1)
            printf("  (from %.4f s of keys %u clips share)", (double)m->clips[i].start, sharing);
        printf("\n");
    }
    if (m->morph_channel_count)
        printf("morph channels: %u\n", m->morph_channel_count);
    for (uint32_t k = 0; k < m->morph_channel_count; k++)
        printf("  %u  \"%s\"  default weight %.4g\n", k, m->morph_channels[k].name,
               (double)m->morph_channels[k].default_weight);
    for (uint32_t i = 0; i < m->mesh_count; i++) {
        const sinew_mesh *mesh = &m->meshes[i];
        printf("mesh %u  \"%s\"  %u vertices, %u triangles", i, mesh->name, mesh->vertex_count, mesh->index_count / 3);
        if (mesh->skin >= 0)
            printf(", skinned: %u joints, up to %u influences, %s", m->skins[mesh->skin].joint_count,
                   mesh->influence_count, skin_method(m, mesh));
        else
            printf(", rigid");
        if (mesh->target_count)
            printf(", %u morph targets", mesh->target_count);
        if (mesh->uvs)
            printf(", UVs");
        if (mesh->tangents)
            printf(", tangents");
        if (mesh->colors)
            printf(", vertex colours");
        if (mesh->flat_normals)
            printf(", no normals: drawn flat");
        if (mesh->material >= 0)
            printf(", material \"%s\"", m->materials[mesh->material].name);
        printf("\n");
        print_morphs(m, i);
    }
    for (uint32_t i = 0; i < m->material_count; i++) {
        const sinew_material *mat = &m->materials[i];
        printf("material %u  \"%s\"  colour (%.3g %.3g %.3g %.3g)  %s %.3g  roughness %.3g", i, mat->name,
               (double)mat->base_color[0], (double)mat->base_color[1], (double)mat->base_color[2],
               (double)mat->base_color[3], mat->metallic_roughness ? "metallic" : "derived: metallic",
               (double)mat->metallic, (double)mat->roughness);
        if (mat->emissive[0] > 0.0f || mat->emissive[1] > 0.0f || mat->emissive[2] > 0.0f)
            printf("  emissive (%.3g %.3g %.3g)", (double)mat->emissive[0], (double)mat->emissive[1],
                   (double)mat->emissive[2]);
        if (mat->alpha_mode == SINEW_ALPHA_MASK)
            printf("  alpha mask %.3g", (double)mat->alpha_cutoff);
        else if (mat->alpha_mode == SINEW_ALPHA_BLEND)
            printf("  alpha blend");
        printf("\n");
        for (int k = 0; k < SINEW_MAP_COUNT; k++) {
            const sinew_texture *map = &mat->maps[k];
            if (map->image)
                printf("  %s map: embedded (%s, %u bytes)", MAP_LABELS[k], image_kind(map), map->image_size);
            else if (map->path)
                printf("  %s map: %s", MAP_LABELS[k], map->path);
            else
                continue;
            if (k == SINEW_MAP_NORMAL)
                printf("  scale %.3g", (double)mat->normal_scale);
            if (k == SINEW_MAP_OCCLUSION)
                printf("  strength %.3g", (double)mat->occlusion_strength);
            printf("\n");
        }
    }
    printf("node tree:\n");
    print_tree(m, -1, 0);
    printf("warnings:   %u\n", m->warning_count);
    for (uint32_t i = 0; i < m->warning_count; i++)
        printf("  %s\n", m->warnings[i]);
}

static cJSON *info_json(const sinew_model *m)
{
    counts c = count_model(m);
    cJSON *root = cJSON_CreateObject();
    cJSON_AddStringToObject(root, "file", m->source);
    cJSON_AddStringToObject(root, "format", m->converted_from ? "sinew" : m->format);
    if (m->converted_from) {
        cJSON_AddStringToObject(root, "converted_from", m->converted_from);
        cJSON_AddStringToObject(root, "converted_from_format", m->format);
    }
    cJSON *cn = cJSON_AddObjectToObject(root, "counts");
    cJSON_AddNumberToObject(cn, "nodes", m->node_count);
    cJSON_AddNumberToObject(cn, "joints", c.joints);
    cJSON_AddNumberToObject(cn, "meshes", m->mesh_count);
    cJSON_AddNumberToObject(cn, "instances", m->instance_count);
    cJSON_AddNumberToObject(cn, "vertices", c.vertices);
    cJSON_AddNumberToObject(cn, "triangles", c.triangles);
    cJSON_AddNumberToObject(cn, "skins", m->skin_count);
    cJSON_AddNumberToObject(cn, "bones", c.bones);
    cJSON_AddNumberToObject(cn, "materials", m->material_count);
    cJSON_AddNumberToObject(cn, "clips", m->clip_count);
    cJSON_AddNumberToObject(cn, "muscles", m->muscles ? m->muscles->muscle_count : 0);
    cJSON_AddNumberToObject(cn, "morph_channels", m->morph_channel_count);

    cJSON *meshes = cJSON_AddArrayToObject(root, "meshes");
    for (uint32_t i = 0; i < m->mesh_count; i++) {
        const sinew_mesh *mesh = &m->meshes[i];
        cJSON *o = cJSON_CreateObject();
        cJSON_AddStringToObject(o, "name", mesh->name);
        cJSON_AddNumberToObject(o, "vertices", mesh->vertex_count);
        cJSON_AddNumberToObject(o, "triangles", mesh->index_count / 3);
        cJSON_AddBoolToObject(o, "skinned", mesh->skin >= 0);
        cJSON_AddNumberToObject(o, "joints", mesh->skin >= 0 ? m->skins[mesh->skin].joint_count : 0);
        cJSON_AddNumberToObject(o, "influences", mesh->influence_count);
        cJSON_AddBoolToObject(o, "uvs", mesh->uvs != NULL);
        cJSON_AddBoolToObject(o, "tangents", mesh->tangents != NULL);
        cJSON_AddBoolToObject(o, "flat_normals", mesh->flat_normals);
        cJSON_AddBoolToObject(o, "colors", mesh->colors != NULL);
        if (mesh->material >= 0)
            cJSON_AddStringToObject(o, "material", m->materials[mesh->material].name);
        else
            cJSON_AddNullToObject(o, "material");
        cJSON_AddStringToObject(o, "skin_method", skin_method(m, mesh));
        cJSON *targets = cJSON_AddArrayToObject(o, "morph_targets");
        for (uint32_t t = 0; t < mesh->target_count; t++) {
            const sinew_morph_target *tg = &mesh->targets[t];
            cJSON *to = cJSON_CreateObject();
            cJSON_AddStringToObject(to, "name", tg->name);
            cJSON_AddStringToObject(to, "channel", channel_name(m, i, tg->channel));
            cJSON_AddNumberToObject(to, "full_weight", cli_json_float(tg->full_weight));
            cJSON_AddNumberToObject(to, "vertices", tg->delta_count);
            cJSON_AddBoolToObject(to, "normals", tg->normals != NULL);
            cJSON_AddBoolToObject(to, "tangents", tg->tangents != NULL);
            cJSON_AddItemToArray(targets, to);
        }
        if (mesh->cache && mesh->cache->frame_count) {
            cJSON *cache = cJSON_AddObjectToObject(o, "cache");
            cJSON_AddNumberToObject(cache, "frames", mesh->cache->frame_count);
            cJSON_AddNumberToObject(cache, "from", cli_json_float(mesh->cache->times[0]));
            cJSON_AddNumberToObject(cache, "to", cli_json_float(mesh->cache->times[mesh->cache->frame_count - 1]));
        } else {
            cJSON_AddNullToObject(o, "cache");
        }
        cJSON_AddItemToArray(meshes, o);
    }
    cJSON *materials = cJSON_AddArrayToObject(root, "materials");
    for (uint32_t i = 0; i < m->material_count; i++) {
        const sinew_material *mat = &m->materials[i];
        cJSON *o = cJSON_CreateObject();
        cJSON_AddStringToObject(o, "name", mat->name);
        cJSON *colour = cJSON_AddArrayToObject(o, "base_color");
        for (int k = 0; k < 4; k++)
            cJSON_AddItemToArray(colour, cJSON_CreateNumber(cli_json_float(mat->base_color[k])));
        cJSON_AddBoolToObject(o, "metallic_roughness", mat->metallic_roughness);
        cJSON_AddNumberToObject(o, "metallic", cli_json_float(mat->metallic));
        cJSON_AddNumberToObject(o, "roughness", cli_json_float(mat->roughness));
        cJSON *emissive = cJSON_AddArrayToObject(o, "emissive");
        for (int k = 0; k < 3; k++)
            cJSON_AddItemToArray(emissive, cJSON_CreateNumber(cli_json_float(mat->emissive[k])));
        cJSON_AddNumberToObject(o, "normal_scale", cli_json_float(mat->normal_scale));
        cJSON_AddNumberToObject(o, "occlusion_strength", cli_json_float(mat->occlusion_strength));
        static const char *const ALPHA[] = {"opaque", "mask", "blend"};
        cJSON_AddStringToObject(o, "alpha_mode", ALPHA[mat->alpha_mode <= SINEW_ALPHA_BLEND ? mat->alpha_mode : 0]);
        cJSON_AddNumberToObject(o, "alpha_cutoff", cli_json_float(mat->alpha_cutoff));
        cJSON *maps = cJSON_AddObjectToObject(o, "maps");
        for (int k = 0; k < SINEW_MAP_COUNT; k++) {
            const sinew_texture *map = &mat->maps[k];
            if (!map->path && !map->image) {
                cJSON_AddNullToObject(maps, MAP_KEYS[k]);
                continue;
            }
            cJSON *entry = cJSON_AddObjectToObject(maps, MAP_KEYS[k]);
            if (map->path)
                cJSON_AddStringToObject(entry, "path", map->path);
            else
                cJSON_AddNullToObject(entry, "path");
            if (map->image) {
                cJSON_AddStringToObject(entry, "embedded", image_kind(map));
                cJSON_AddNumberToObject(entry, "bytes", map->image_size);
            }
        }
        cJSON_AddItemToArray(materials, o);
    }
    cJSON *clips = cJSON_AddArrayToObject(root, "clips");
    for (uint32_t i = 0; i < m->clip_count; i++) {
        uint32_t keys[SINEW_CHANNEL_COUNT];
        clip_keys(&m->clips[i], keys);
        cJSON *o = cJSON_CreateObject();
        cJSON_AddNumberToObject(o, "index", i);
        cJSON_AddStringToObject(o, "name", m->clips[i].name);
        cJSON_AddNumberToObject(o, "duration", cli_json_float(m->clips[i].duration));
        cJSON_AddNumberToObject(o, "start", cli_json_float(m->clips[i].start));
        cJSON_AddNumberToObject(o, "clips_sharing_keys", clips_sharing_keys(m, i));
        cJSON_AddNumberToObject(o, "tracks", m->clips[i].track_count);
        cJSON *k = cJSON_AddObjectToObject(o, "keys");
        cJSON_AddNumberToObject(k, "translation", keys[0]);
        cJSON_AddNumberToObject(k, "rotation", keys[1]);
        cJSON_AddNumberToObject(k, "scale", keys[2]);
        cJSON_AddNumberToObject(o, "timeline", cli_json_float(m->clips[i].timeline));
        if (m->clips[i].frame_rate > 0.0f)
            cJSON_AddNumberToObject(o, "frame_rate", cli_json_float(m->clips[i].frame_rate));
        else
            cJSON_AddNullToObject(o, "frame_rate");
        cJSON *wt = cJSON_AddArrayToObject(o, "weight_tracks");
        for (uint32_t t = 0; t < m->clips[i].weight_track_count; t++) {
            const sinew_weight_track *tr = &m->clips[i].weight_tracks[t];
            cJSON *to = cJSON_CreateObject();
            cJSON_AddStringToObject(to, "channel", m->morph_channels[tr->channel].name);
            cJSON_AddNumberToObject(to, "keys", tr->keys.key_count);
            cJSON_AddItemToArray(wt, to);
        }
        cJSON_AddItemToArray(clips, o);
    }
    cJSON *channels = cJSON_AddArrayToObject(root, "morph_channels");
    for (uint32_t k = 0; k < m->morph_channel_count; k++) {
        cJSON *o = cJSON_CreateObject();
        cJSON_AddStringToObject(o, "name", m->morph_channels[k].name);
        cJSON_AddNumberToObject(o, "default_weight", cli_json_float(m->morph_channels[k].default_weight));
        cJSON_AddItemToArray(channels, o);
    }
    cJSON *nodes = cJSON_AddArrayToObject(root, "nodes");
    for (uint32_t n = 0; n < m->node_count; n++) {
        cJSON *o = cJSON_CreateObject();
        cJSON_AddStringToObject(o, "name", m->node_names[n]);
        if (m->node_parents[n] >= 0)
            cJSON_AddStringToObject(o, "parent", m->node_names[m->node_parents[n]]);
        else
            cJSON_AddNullToObject(o, "parent");
        cJSON_AddBoolToObject(o, "joint", sinew_model_node_is_joint(m, n));
        static const char *const inherit_names[] = {"normal", "ignore_parent_scale", "componentwise_scale"};
        uint8_t inherit = m->node_inherit ? m->node_inherit[n] : SINEW_INHERIT_NORMAL;
        cJSON_AddStringToObject(o, "inherit", inherit_names[inherit <= 2 ? inherit : 0]);
        cJSON_AddItemToArray(nodes, o);
    }
    cJSON *warnings = cJSON_AddArrayToObject(root, "warnings");
    for (uint32_t i = 0; i < m->warning_count; i++)
        cJSON_AddItemToArray(warnings, cJSON_CreateString(m->warnings[i]));
    return root;
}

int cmd_info(int argc, char **argv)
{
    const char *path = NULL;
    bool json = false;
    for (int i = 1; i < argc; i++) {
        if (cli_is_help(argv[i])) {
            fputs(info_usage, stdout);
            return EXIT_OK;
        } else if (strcmp(argv[i], "--json") == 0) {
            json = true;
        } else if (argv[i][0] == '-' && argv[i][1]) {
            cli_error("info: unknown option \"%s\"\n%s", argv[i], info_usage);
            return EXIT_USAGE;
        } else if (!path) {
            path = argv[i];
        } else {
            cli_error("info: one FILE only (got \"%s\" and \"%s\")", path, argv[i]);
            return EXIT_USAGE;
        }
    }
    if (!path) {
        cli_error("info: no FILE given\n%s", info_usage);
        return EXIT_USAGE;
    }
    sinew_model *model = cli_load_model(path);
    if (!model)
        return EXIT_BAD_INPUT;
    if (json)
        cli_json_print(info_json(model), true);
    else
        print_text(model);
    sinew_model_free(model);
    return EXIT_OK;
}
