/* `sinew pose FILE`: world transforms of every node at given times, and the skinned
 * geometry as OBJ. */
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "cjson.h"
#include "cli.h"

static const char pose_usage[] =
    "usage: sinew pose FILE [--clip NAME|INDEX] [--time T[,T...]] [--loop] [--json] [--mesh OUT.obj]\n"
    "                  [--muscles [FILE.json]] [--blend C:W,C:W] [--additive C:W] [--crossfade A,B,T]\n"
    "                  [--ik JOINT:X,Y,Z] [--root-motion] [--anim OTHER [--name-map M.json]]\n"
    "\n"
    "Poses FILE's skeleton and prints every node's world transform (metres, Y up) keyed by name.\n"
    "\n"
    "  --clip C        the clip, by name or index (default: the first clip; none: the rest pose)\n"
    "  --time T,...    times in seconds (default: ten evenly spaced times from 0 to the clip's duration,\n"
    "                  both included); times outside the clip clamp to its ends\n"
    "  --loop          wrap times outside the clip around its duration instead of clamping\n"
    "  --json          print {\"file\", \"clip\": {\"index\", \"name\", \"duration\"} | null, \"frames\": [{\"time\",\n"
    "                  \"nodes\": [{\"name\", \"parent\", \"translation\": [x,y,z], \"rotation\": [x,y,z,w],\n"
    "                  \"scale\": [x,y,z]}], \"weights\": [{\"channel\", \"weight\"}], \"morphs\": [{\"mesh\", "
    "\"node\",\n"
    "                  \"targets\": [{\"name\", \"channel\", \"weight\"}]}]}]} (weights and morphs for models with\n"
    "                  morph targets: each channel's weight, each instance's targets with in-betweens resolved)\n"
    "  --mesh OUT.obj  write every mesh at the (single) time as the file means it (morph targets at their\n"
    "                  weights, vertex caches, each skin's method), in world space\n"
    "  --muscles [M]   muscles attached to the joints (M, or FILE's stem + .muscles.json beside it):\n"
    "                  each frame gives every muscle's length, delta and volume; in JSON a frame's\n"
    "                  \"muscles\": [{\"name\", \"length\", \"delta\", \"volume\", \"rest_volume\", \"in_range\",\n"
    "                  \"origin\": [x,y,z], \"insertion\": [x,y,z], \"radii\": [...]}]\n"
    "\n"
    "combining clips (sinew/blend.h; with --root-motion a JSON frame gives \"root_motion\": {\"node\",\n"
    "\"translation\", \"yaw\"}, what was taken out):\n" APP_POSE_OPTIONS_HELP
    "  --anim OTHER          OTHER's clips retargeted onto FILE's skeleton, first in its clip list (joints by\n"
    "                        name, Mixamo/CMU/Unity humanoid names mapped; --name-map M.json: {\"from\": \"to\"};\n"
    "                        nameless joints of the same hierarchy, as IQM animation files have, by index)\n";

#define MAX_TIMES 4096

typedef struct pose_options {
    const char *path;
    const char *clip;
    const char *mesh_out;
    const char *muscles; /* NULL: none; "": beside the model */
    bool json, loop;
    app_pose_spec ops; /* --blend, --additive, --crossfade, --ik, --root-motion */
    const char *anim, *name_map;
    uint32_t time_count;
    double times[MAX_TIMES]; /* as given: printed back exactly */
} pose_options;

static bool parse_times(const char *text, pose_options *o)
{
    double t[MAX_TIMES];
    int n = app_parse_list(text, t, 1, MAX_TIMES, -APP_MAX_SECONDS, APP_MAX_SECONDS);
    if (n < 0) {
        cli_error("pose: bad --time \"%s\": expected 1 to %d times in seconds (within +-%g) separated by commas", text,
                  MAX_TIMES, APP_MAX_SECONDS);
        return false;
    }
    o->time_count = 0;
    for (int i = 0; i < n; i++)
        o->times[o->time_count++] = t[i];
    return true;
}

/* Returns -1 to go on, or an exit code. */
static int parse_pose_args(int argc, char **argv, pose_options *o)
{
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i];
        bool has_value = i + 1 < argc;
        if (cli_is_help(a)) {
            fputs(pose_usage, stdout);
            return EXIT_OK;
        } else if (strcmp(a, "--json") == 0) {
            o->json = true;
        } else if (strcmp(a, "--loop") == 0) {
            o->loop = true;
        } else if (strcmp(a, "--clip") == 0 && has_value) {
            o->clip = argv[++i];
        } else if (strcmp(a, "--time") == 0 && has_value) {
            if (!parse_times(argv[++i], o))
                return EXIT_USAGE;
        } else if (strcmp(a, "--muscles") == 0) {
            o->muscles = cli_muscles_arg(argc, argv, &i);
        } else if (strcmp(a, "--mesh") == 0 && has_value) {
            o->mesh_out = argv[++i];
        } else if (strcmp(a, "--anim") == 0 && has_value) {
            o->anim = argv[++i];
        } else if (strcmp(a, "--name-map") == 0 && has_value) {
            o->name_map = argv[++i];
        } else if (app_pose_option_parse(&o->ops, argc, argv, i) > 0) {
            i += app_pose_option_parse(&o->ops, argc, argv, i) - 1;
        } else if (a[0] == '-' && a[1]) {
            cli_error("pose: unknown option or missing value \"%s\"\n%s", a, pose_usage);
            return EXIT_USAGE;
        } else if (!o->path) {
            o->path = a;
        } else {
            cli_error("pose: one FILE only (got \"%s\" and \"%s\")", o->path, a);
            return EXIT_USAGE;
        }
    }
    if (!o->path) {
        cli_error("pose: no FILE given\n%s", pose_usage);
        return EXIT_USAGE;
    }
    if (o->mesh_out && o->time_count > 1) {
        cli_error("pose: --mesh writes one time; give a single --time");
        return EXIT_USAGE;
    }
    return -1;
}

static void default_times(const sinew_clip *clip, pose_options *o)
{
    double duration = clip ? clip->duration : 0.0;
    if (!(duration > 0.0)) {
        o->times[0] = 0.0;
        o->time_count = 1;
        return;
    }
    o->time_count = 10;
    for (uint32_t i = 0; i < 10; i++)
        o->times[i] = duration * i / 9.0;
}

static cJSON *vector_json(const float *v, int n)
{
    cJSON *a = cJSON_CreateArray();
    for (int i = 0; i < n; i++)
        cJSON_AddItemToArray(a, cJSON_CreateNumber(cli_json_float(v[i])));
    return a;
}

static cJSON *frame_json(const sinew_model *m, const sinew_mat4 *worlds, double time)
{
    cJSON *frame = cJSON_CreateObject();
    cJSON_AddNumberToObject(frame, "time", time);
    cJSON *nodes = cJSON_AddArrayToObject(frame, "nodes");
    for (uint32_t n = 0; n < m->node_count; n++) {
        sinew_transform t;
        sinew_mat4_decompose(&worlds[n], &t);
        cJSON *o = cJSON_CreateObject();
        cJSON_AddStringToObject(o, "name", m->node_names[n]);
        if (m->node_parents[n] >= 0)
            cJSON_AddStringToObject(o, "parent", m->node_names[m->node_parents[n]]);
        else
            cJSON_AddNullToObject(o, "parent");
        cJSON_AddItemToObject(o, "translation", vector_json(t.translation, 3));
        cJSON_AddItemToObject(o, "rotation", vector_json(t.rotation, 4));
        cJSON_AddItemToObject(o, "scale", vector_json(t.scale, 3));
        cJSON_AddItemToArray(nodes, o);
    }
    return frame;
}

/* Each mesh instance's morph targets at the pose: {"mesh", "node", "targets": [{"name",
 * "channel", "weight"}]} for the instances of meshes with targets; and the channels' weights. */
static void weights_json(cJSON *frame, const app_scene *scene)
{
    const sinew_model *m = scene->model;
    if (m->morph_channel_count == 0)
        return;
    cJSON *channels = cJSON_AddArrayToObject(frame, "weights");
    for (uint32_t c = 0; c < m->morph_channel_count; c++) {
        cJSON *o = cJSON_CreateObject();
        cJSON_AddStringToObject(o, "channel", m->morph_channels[c].name);
        cJSON_AddNumberToObject(o, "weight", cli_json_float(scene->weights[c]));
        cJSON_AddItemToArray(channels, o);
    }
    cJSON *meshes = cJSON_AddArrayToObject(frame, "morphs");
    float tw[256];
    for (uint32_t i = 0; i < m->instance_count; i++) {
        const sinew_instance *in = &m->instances[i];
        const sinew_mesh *mesh = &m->meshes[in->mesh];
        if (mesh->target_count == 0 || mesh->target_count > 256 ||
            sinew_morph_target_weights(mesh, scene->weights + in->morph_first, mesh->morph_channel_count, tw, 256,
                                       NULL) != SINEW_OK)
            continue;
        cJSON *o = cJSON_CreateObject();
        cJSON_AddStringToObject(o, "mesh", mesh->name);
        cJSON_AddStringToObject(o, "node", m->node_names[in->node]);
        cJSON *targets = cJSON_AddArrayToObject(o, "targets");
        for (uint32_t t = 0; t < mesh->target_count; t++) {
            cJSON *to = cJSON_CreateObject();
            cJSON_AddStringToObject(to, "name", mesh->targets[t].name);
            cJSON_AddStringToObject(to, "channel", m->morph_channels[in->morph_first + mesh->targets[t].channel].name);
            cJSON_AddNumberToObject(to, "weight", cli_json_float(tw[t]));
            cJSON_AddItemToArray(targets, to);
        }
        cJSON_AddItemToArray(meshes, o);
    }
}

static cJSON *muscles_json(const sinew_muscle_pose *poses, uint32_t count)
{
    cJSON *a = cJSON_CreateArray();
    for (uint32_t i = 0; i < count; i++)
        cJSON_AddItemToArray(a, cli_muscle_pose_json(&poses[i]));
    return a;
}

static void print_muscles_text(const sinew_muscle_pose *poses, uint32_t count)
{
    for (uint32_t i = 0; i < count; i++) {
        const sinew_muscle_pose *p = &poses[i];
        printf("  muscle %-25s length %.6g (rest %.6g)  delta %.6g  volume %.9g (rest %.9g)%s\n", p->name, p->distance,
               p->state.rest_length, p->state.delta, p->state.volume, p->state.rest_volume,
               p->in_range ? "" : "  OUT OF RANGE: solved at the nearest valid length");
    }
}

static void print_frame_text(const sinew_model *m, const sinew_mat4 *worlds, double time)
{
    printf("time %.9g s\n", time);
    for (uint32_t n = 0; n < m->node_count; n++) {
        sinew_transform t;
        sinew_mat4_decompose(&worlds[n], &t);
        printf("  %-32s  t (% .6f % .6f % .6f)  r (% .6f % .6f % .6f % .6f)  s (%.6g %.6g %.6g)\n", m->node_names[n],
               (double)t.translation[0], (double)t.translation[1], (double)t.translation[2], (double)t.rotation[0],
               (double)t.rotation[1], (double)t.rotation[2], (double)t.rotation[3], (double)t.scale[0],
               (double)t.scale[1], (double)t.scale[2]);
    }
}

/* Writes every mesh instance posed as the file means it (morph targets at the pose's weights,
 * a vertex cache at its time, skinned or placed at its node), in world space, whole or not at
 * all (cmd_pose has refused an output that is one of the inputs). Returns an exit code. */
static int write_obj(const app_scene *scene, void *scratch, size_t scratch_size, const char *out_path)
{
    const sinew_model *m = scene->model;
    app_output out;
    sinew_error output_error = {0};
    if (app_output_open(&out, out_path, &output_error) != SINEW_OK) {
        cli_error("pose: %s", output_error.message);
        return EXIT_OUTPUT;
    }
    FILE *f = out.file;
    fprintf(f, "# sinew pose of %s\n", m->source);
    uint32_t base = 1;
    bool ok = true;
    for (uint32_t i = 0; i < m->instance_count && ok; i++) {
        const sinew_mesh *mesh = &m->meshes[m->instances[i].mesh];
        float *pos = malloc(((size_t)mesh->vertex_count + 1) * 3 * sizeof(float));
        float *nrm = malloc(((size_t)mesh->vertex_count + 1) * 3 * sizeof(float));
        sinew_error error = {0};
        ok = pos && nrm;
        if (ok)
            ok = sinew_deform_instance(&(sinew_deform_desc){.model = m,
                                                            .instance = i,
                                                            .worlds = scene->worlds,
                                                            .world_count = m->node_count,
                                                            .weights = scene->weights,
                                                            .weight_count = m->morph_channel_count,
                                                            .cache_time = scene->cache_time,
                                                            .scratch = scratch,
                                                            .scratch_size = scratch_size,
                                                            .out_positions = pos,
                                                            .out_normals = mesh->normals ? nrm : NULL},
                                       &error) == SINEW_OK;
        if (ok && !mesh->normals)
            memset(nrm, 0, (size_t)mesh->vertex_count * 3 * sizeof(float));
        if (ok) {
            fprintf(f, "o %s\n", mesh->name);
            for (uint32_t v = 0; v < mesh->vertex_count; v++)
                fprintf(f, "v %.6f %.6f %.6f\n", (double)pos[v * 3], (double)pos[v * 3 + 1], (double)pos[v * 3 + 2]);
            for (uint32_t v = 0; v < mesh->vertex_count; v++)
                fprintf(f, "vn %.6f %.6f %.6f\n", (double)nrm[v * 3], (double)nrm[v * 3 + 1], (double)nrm[v * 3 + 2]);
            for (uint32_t t = 0; t < mesh->index_count; t += 3) {
                uint32_t a = base + mesh->indices[t], b = base + mesh->indices[t + 1], c = base + mesh->indices[t + 2];
                fprintf(f, "f %u//%u %u//%u %u//%u\n", a, a, b, b, c, c);
            }
            base += mesh->vertex_count;
        } else {
            cli_error("%s: %s", m->source, error.message[0] ? error.message : "out of memory");
        }
        free(pos);
        free(nrm);
    }
    if (!ok) {
        app_output_abort(&out);
        return EXIT_BAD_INPUT;
    }
    if (app_output_commit(&out, &output_error) != SINEW_OK) {
        cli_error("pose: %s", output_error.message);
        return EXIT_OUTPUT;
    }
    return EXIT_OK;
}

int cmd_pose(int argc, char **argv)
{
    static pose_options o;
    memset(&o, 0, sizeof o);
    int code = parse_pose_args(argc, argv, &o);
    if (code >= 0)
        return code;
    sinew_error early = {0};
    const char *inputs[4] = {o.path, o.muscles && *o.muscles ? o.muscles : NULL, o.anim, o.name_map};
    if (o.mesh_out && app_output_check(o.mesh_out, inputs, 4, &early) != SINEW_OK) {
        cli_error("pose: %s", early.message);
        return EXIT_OUTPUT;
    }
    app_scene scene;
    app_scene_desc desc = {.path = o.path, .clip = o.clip, .anim = o.anim, .name_map = o.name_map};
    cli_scene_muscles(o.muscles, &desc);
    if (cli_scene_load(&scene, &desc) != SINEW_OK)
        return EXIT_BAD_INPUT;
    sinew_error ops_error = {0};
    if (app_scene_set_pose_ops(&scene, &o.ops, &ops_error) != SINEW_OK) {
        cli_error("pose: %s", ops_error.message);
        app_scene_close(&scene);
        return EXIT_USAGE;
    }
    const sinew_model *model = scene.model;
    const sinew_clip *clip = scene.clip;
    int32_t clip_index = scene.clip_index;
    sinew_muscle_rig *rig = scene.muscle_rig;
    size_t scratch_size = sinew_deform_scratch_size(model);
    void *scratch = o.mesh_out ? aligned_alloc(16, (scratch_size + 15) & ~(size_t)15) : NULL;
    if (o.mesh_out && !scratch) {
        cli_error("out of memory");
        app_scene_close(&scene);
        return EXIT_BAD_INPUT;
    }
    if (o.time_count == 0)
        default_times(clip, &o);
    cli_note_times(clip, o.times, o.time_count, o.loop);
    sinew_wrap wrap = o.loop ? SINEW_WRAP_LOOP : SINEW_WRAP_CLAMP;

    cJSON *root = NULL, *frames = NULL;
    if (o.json) {
        root = cJSON_CreateObject();
        cJSON_AddStringToObject(root, "file", model->source);
        if (clip) {
            cJSON *c = cJSON_AddObjectToObject(root, "clip");
            cJSON_AddNumberToObject(c, "index", clip_index);
            cJSON_AddStringToObject(c, "name", clip->name);
            cJSON_AddNumberToObject(c, "duration", cli_json_float(clip->duration));
        } else {
            cJSON_AddNullToObject(root, "clip");
        }
        frames = cJSON_AddArrayToObject(root, "frames");
    } else {
        printf("file %s\nclip %s\n", model->source, clip ? clip->name : "(none: rest pose)");
    }
    code = EXIT_OK;
    for (uint32_t i = 0; i < o.time_count && code == EXIT_OK; i++) {
        sinew_error error = {0};
        if (app_scene_pose(&scene, o.times[i], wrap, &error) != SINEW_OK) {
            cli_error("%s: %s", model->source, error.message);
            code = EXIT_BAD_INPUT;
            break;
        }
        if (o.json) {
            cJSON *frame = frame_json(model, scene.worlds, o.times[i]);
            float moved[3], yaw;
            const sinew_root_motion *took = app_scene_root_motion(&scene, moved, &yaw);
            if (took) { /* what --root-motion took out at this time */
                cJSON *motion = cJSON_AddObjectToObject(frame, "root_motion");
                cJSON_AddStringToObject(motion, "node", model->node_names[took->node]);
                cJSON_AddItemToObject(motion, "translation", vector_json(moved, 3));
                cJSON_AddNumberToObject(motion, "yaw", cli_json_float(yaw));
            }
            if (rig)
                cJSON_AddItemToObject(frame, "muscles", muscles_json(scene.muscle_poses, scene.muscle_count));
            weights_json(frame, &scene);
            cJSON_AddItemToArray(frames, frame);
        } else {
            print_frame_text(model, scene.worlds, o.times[i]);
            if (rig)
                print_muscles_text(scene.muscle_poses, scene.muscle_count);
        }
        if (o.mesh_out && code == EXIT_OK)
            code = write_obj(&scene, scratch, scratch_size, o.mesh_out);
    }
    if (root && code == EXIT_OK)
        cli_json_print(root, false);
    else if (root) /* not loaded where there is no JSON */
        cJSON_Delete(root);
    free(scratch);
    app_scene_close(&scene);
    return code;
}
