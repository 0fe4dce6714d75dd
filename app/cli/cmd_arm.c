/* `sinew arm`: the seed 003 arm — elbow angle and muscle length through the law of cosines,
 * the biceps re-solved at that length, and the arm drawn anywhere in space. */
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "cjson.h"
#include "cli.h"

static const char arm_usage[] =
    "usage: sinew arm [--angle DEG | --length L | --contract F] [--rotate Y,P,R] [--move X,Y,Z] [--scale S]\n"
    "                 [--json] [-o OUT.png [--size WxH] [--camera SPEC]]\n"
    "\n"
    "The seed's arm: two rods joined at the elbow (distances in data/arm.muscles.json) moved by a biceps.\n"
    "The elbow angle sets the muscle's length by the law of cosines, or the length sets the angle; the\n"
    "biceps is then re-solved at that length with its volume kept.\n"
    "\n"
    "  --angle DEG     elbow angle, 0 (folded) .. 180 (straight); default: the biceps' rest length\n"
    "  --length L     the muscle's length instead (between |a - b| and a + b of the two rods)\n"
    "  --contract F   shorten (F > 0) or lengthen (F < 0) the muscle by F of its rest length\n"
    "  --rotate Y,P,R --move X,Y,Z --scale S   place the whole arm (degrees, metres)\n"
    "  --json         {\"elbow_angle\": degrees, \"muscle\": {\"name\", \"length\", \"rest_length\", \"delta\",\n"
    "                 \"volume\", \"rest_volume\", \"in_range\", \"origin\", \"insertion\", \"radii\"}}\n"
    "  -o OUT.png     also draw it (muscle Gouraud-shaded); --size, --camera as for `sinew render`\n";

static bool parse_list(const char *option, const char *text, double *out, int count)
{
    if (app_parse_list(text, out, count, count, -1e9, 1e9) != count) {
        cli_error("arm: bad %s \"%s\": expected %d number%s separated by commas", option, text, count,
                  count == 1 ? "" : "s");
        return false;
    }
    return true;
}

typedef struct arm_args {
    double angle_deg, length, contract, rotate[3], move[3], scale;
    bool angle_set, length_set, contract_set, json;
    const char *out, *camera;
    int width, height;
} arm_args;

static int parse_arm_args(int argc, char **argv, arm_args *a)
{
    for (int i = 1; i < argc; i++) {
        const char *o = argv[i];
        bool v = i + 1 < argc, ok = true;
        if (cli_is_help(o)) {
            fputs(arm_usage, stdout);
            return EXIT_OK;
        } else if (strcmp(o, "--json") == 0) {
            a->json = true;
        } else if (strcmp(o, "--angle") == 0 && v) {
            ok = parse_list(o, argv[++i], &a->angle_deg, 1), a->angle_set = true;
        } else if (strcmp(o, "--length") == 0 && v) {
            ok = parse_list(o, argv[++i], &a->length, 1), a->length_set = true;
        } else if (strcmp(o, "--contract") == 0 && v) {
            ok = parse_list(o, argv[++i], &a->contract, 1), a->contract_set = true;
        } else if (strcmp(o, "--rotate") == 0 && v) {
            ok = parse_list(o, argv[++i], a->rotate, 3);
        } else if (strcmp(o, "--move") == 0 && v) {
            ok = parse_list(o, argv[++i], a->move, 3);
        } else if (strcmp(o, "--scale") == 0 && v) {
            ok = parse_list(o, argv[++i], &a->scale, 1);
            if (ok && !(a->scale > 0.0)) {
                cli_error("arm: --scale must be greater than 0");
                ok = false;
            }
        } else if ((strcmp(o, "-o") == 0 || strcmp(o, "--output") == 0) && v) {
            a->out = argv[++i];
        } else if (strcmp(o, "--size") == 0 && v) {
            ok = cli_parse_size("arm", argv[++i], &a->width, &a->height);
        } else if (strcmp(o, "--camera") == 0 && v) {
            a->camera = argv[++i];
        } else {
            cli_error("arm: unknown option or missing value \"%s\" (see `sinew arm --help`)", o);
            return EXIT_USAGE;
        }
        if (!ok)
            return EXIT_USAGE;
    }
    if (a->angle_set + a->length_set + a->contract_set > 1) {
        cli_error("arm: give one of --angle, --length and --contract");
        return EXIT_USAGE;
    }
    return -1;
}

/* Yaw (about Y), pitch (about X), roll (about Z), degrees, as a quaternion x,y,z,w. */
static void euler_quaternion(const double ypr[3], float q[4])
{
    double h[3];
    for (int i = 0; i < 3; i++)
        h[i] = ypr[i] * M_PI / 360.0;
    double cy = cos(h[0]), sy = sin(h[0]), cp = cos(h[1]), sp = sin(h[1]), cr = cos(h[2]), sr = sin(h[2]);
    /* q = qy * qx * qz */
    q[0] = (float)(cy * sp * cr + sy * cp * sr);
    q[1] = (float)(sy * cp * cr - cy * sp * sr);
    q[2] = (float)(cy * cp * sr - sy * sp * cr);
    q[3] = (float)(cy * cp * cr + sy * sp * sr);
}

static void print_arm(const arm_args *a, double angle, const sinew_muscle_pose *p)
{
    if (a->json) {
        cJSON *o = cJSON_CreateObject();
        cJSON_AddNumberToObject(o, "elbow_angle", angle * 180.0 / M_PI);
        cJSON_AddItemToObject(o, "muscle", cli_muscle_pose_json(p));
        cli_json_print(o, true);
        return;
    }
    printf("elbow angle:  %.6g degrees\n", angle * 180.0 / M_PI);
    printf("muscle:       %s, length %.9g (rest %.9g)\n", p->name, p->distance, p->state.rest_length);
    printf("delta:        %.9g\n", p->state.delta);
    printf("volume:       %.9g (rest %.9g)%s\n", p->state.volume, p->state.rest_volume,
           p->in_range ? "" : "  OUT OF RANGE: solved at the nearest valid length");
    printf("radii:       ");
    for (uint32_t k = 0; k < p->node_count; k++)
        printf(" %.6g", p->radii[k]);
    printf("\n");
}

int cmd_arm(int argc, char **argv)
{
    arm_args a = {.scale = 1.0, .width = 1280, .height = 720};
    int code = parse_arm_args(argc, argv, &a);
    if (code >= 0)
        return code;
    char data[4096];
    app_data_path("arm.muscles.json", data, sizeof data);
    sinew_arm_desc desc = {0};
    sinew_muscle_set *set = NULL;
    sinew_error error = {0};
    if (sinew_arm_read(data, &desc, &error) != SINEW_OK || sinew_muscle_set_read(data, &set, &error) != SINEW_OK) {
        cli_error("%s", error.message);
        return EXIT_BAD_INPUT;
    }
    double rest = set->muscles[0].rest_length > 0.0 ? set->muscles[0].rest_length : 0.0;
    sinew_muscle_set_free(set);
    app_arm_spec spec = {.angle = a.angle_deg * M_PI / 180.0, .length = a.length_set ? a.length : 0.0};
    if (a.contract_set)
        spec.length = rest * (1.0 - a.contract);
    else if (!a.angle_set && !a.length_set)
        spec.length = rest;
    if ((a.angle_set && !(a.angle_deg >= 0.0 && a.angle_deg <= 180.0)) || (spec.length <= 0.0 && !a.angle_set)) {
        cli_error("arm: the elbow angle must be 0..180 degrees and the length positive");
        return EXIT_USAGE;
    }
    euler_quaternion(a.rotate, spec.place.rotation);
    for (int i = 0; i < 3; i++) {
        spec.place.translation[i] = (float)a.move[i];
        spec.place.scale[i] = (float)a.scale;
    }
    sinew_model *model = NULL;
    if (app_arm_model(&spec, &model, &error) != SINEW_OK) {
        cli_error("%s", error.message);
        return EXIT_BAD_INPUT;
    }
    double angle = 0.0;
    sinew_arm_angle(desc.origin_to_elbow, desc.elbow_to_insertion, spec.length, &angle, NULL);
    if (!(spec.length > 0.0))
        angle = spec.angle;
    cli_scene_desc sd = {.scene = {.model = model, .muscle_scale = a.scale},
                         .muscles = "",
                         .camera = a.camera,
                         .width = a.width,
                         .height = a.height,
                         .options = sinew_render_options_default()};
    if (!a.out) {
        /* Numbers need no GL: the arm's own biceps, solved at the rest pose. */
        app_scene arm;
        app_scene_desc ad = {.model = model, .muscles = APP_MUSCLES_REQUIRED, .muscle_scale = a.scale};
        if (cli_scene_load(&arm, &ad) != SINEW_OK) /* takes the model over */
            return EXIT_BAD_INPUT;
        bool ok = app_scene_pose(&arm, 0.0, SINEW_WRAP_CLAMP, &error) == SINEW_OK && arm.muscle_count > 0;
        if (ok)
            print_arm(&a, angle, &arm.muscle_poses[0]);
        else
            cli_error("%s", error.message[0] ? error.message : "arm: no biceps in the arm's muscle file");
        app_scene_close(&arm);
        return ok ? EXIT_OK : EXIT_BAD_INPUT;
    }
    cli_scene scene;
    code = cli_scene_open(&scene, &sd); /* takes the model over */
    if (code != EXIT_OK)
        return code;
    code = cli_scene_frame_all(&scene, 0.0, 0.0) && cli_scene_draw(&scene, 0.0) && cli_scene_read(&scene)
               ? EXIT_OK
               : EXIT_BAD_INPUT;
    if (code == EXIT_OK && scene.scene.muscle_count > 0)
        print_arm(&a, angle, &scene.scene.muscle_poses[0]);
    if (code == EXIT_OK && !cli_write_image(a.out, scene.pixels, scene.width, scene.height, false))
        code = EXIT_OUTPUT;
    cli_scene_close(&scene);
    return code;
}
