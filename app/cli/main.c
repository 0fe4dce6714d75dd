/* `sinew`: the command line. One file per subcommand; this one dispatches. */
#include <errno.h>
#include <malloc.h>
#include <string.h>

#include "cli.h"

static const char usage[] =
    "usage: sinew COMMAND [ARGS]\n"
    "\n"
    "Skeletal animation, skinning and muscles.\n"
    "\n"
    "commands:\n"
    "  info FILE [--json]            what a model file holds: counts, clips, morph targets, the joint tree, warnings\n"
    "  pose FILE [--clip C] [--time T[,T...]] [--loop] [--json] [--mesh OUT.obj] [--muscles [M.json]]\n"
    "       [--morph MESH:TARGET=W]  world transform of every node and morph weights at given times; every\n"
    "                                mesh as OBJ as the file means it; muscles' length, delta and volume\n"
    "  render FILE [--time T | --from A --to B --fps N] [--camera SPEC] [display options] -o OUT\n"
    "                                draw frames off-screen (OpenGL through EGL) to PNG, PNG sequences or MP4\n"
    "  demo DIR [--force]            write the demo content (humanoid and arm as COLLADA, muscle files)\n"
    "  convert IN OUT.sinew [--muscles [M.json] | --no-muscles]\n"
    "                                write a model (and its muscles) as sinew's runtime format\n"
    "  bench render [FILE]           frames per second of the renderer, GPU against CPU skinning\n"
    "  bench muscle                  time to solve a muscle and build its surface\n"
    "  bench eval [--json]           runtime speed: sampling, skinning, crowds, .sinew loading\n"
    "  muscle FILE.json [--name M] [--length L] [--json]\n"
    "                                a volume-preserving muscle at a length: delta, radii, volume, valid range\n"
    "  batch INPUT... -o OUTDIR [--fps N] [--clips all|NAME] [--retarget SKELETON] [--skin] [--preview]\n"
    "        [--workers N | --scheduler tcp://HOST:PORT]\n"
    "                                every model file under the inputs to numpy arrays (.npz per clip) and a\n"
    "                                manifest, on a Dask cluster (Python 3, numpy, Dask distributed)\n"
    "  arm [--angle DEG | --length L | --contract F] [--rotate/--move/--scale] [--json] [-o OUT.png]\n"
    "                                the seed's two-rod arm and its biceps (law of cosines), numbers and picture\n"
    "\n"
    "FILE is an FBX file (5.x to 7.x, binary or ASCII), a glTF 2.0 file (.gltf/.glb), a COLLADA file (.dae), an IQM\n"
    "or a BVH file, read by sinew's own readers, any format Assimp reads: .x, MD5, SMD, 3DS, OBJ, ..., a .sinew file\n"
    "(`sinew convert`; its stored muscles are used), builtin:arm (the seed's arm with a \"flex\" clip), builtin:demo "
    "(the demo humanoid)\n"
    "or builtin:morph (a generated tube with 50 morph targets, 5 animated); the arm and the demo carry their biceps,\n"
    "which --muscles attaches.\n"
    "Output is in metres, Y up, seconds. `sinew COMMAND --help` describes one command.\n"
    "SINEW_IMPORTER=assimp reads even FBX, glTF and COLLADA through Assimp (to compare); SINEW_IMPORT_ISOLATE=1 reads\n"
    "them in the import helper program too, not only Assimp's formats (a crash then costs an error, not sinew).\n"
    "Exit status: 0 ok, 1 usage error, 2 bad input (the message names the file and the problem),\n"
    "3 this machine lacks what the command needs (an OpenGL 3.3 context through EGL, ffmpeg, libcjson for\n"
    "--json), 4 an output cannot be written (no space, no permission, it is one of the inputs, it exists: demo).\n"
    "Outputs are written whole or not at all (a temporary file renamed into place).\n"
    "Import warnings (a texture not found, a part of the file sinew leaves out) are printed on stderr;\n"
    "--quiet (-q) hides them (`sinew info` lists them in its output).\n"
    "Files are read by a helper process (sinew-import) that is stopped when it takes too long or too much memory;\n"
    "every command that reads a model takes:\n" APP_IMPORT_OPTIONS_HELP;

app_import_options cli_import;

/* Takes the import options and --quiet out of argv (every command reads models the same way);
 * returns the arguments left, or -1 after printing the error. */
static int take_import_options(int argc, char **argv)
{
    int kept = 0;
    for (int i = 0; i < argc; i++) {
        if (i > 0 && (strcmp(argv[i], "--quiet") == 0 || strcmp(argv[i], "-q") == 0)) {
            cli_quiet = true;
            continue;
        }
        sinew_error error = {0};
        int used = app_import_option_parse(&cli_import, argc, argv, i, &error);
        if (used < 0) {
            cli_error("%s", error.message);
            return -1;
        }
        if (used > 0)
            i += used - 1;
        else
            argv[kept++] = argv[i];
    }
    argv[kept] = NULL;
    return kept;
}

/* What a command printed must have reached standard output (a full disk, /dev/full, a closed
 * pipe with SIGPIPE ignored): else a message and EXIT_OUTPUT, as for files. */
static int stdout_checked(int code)
{
    errno = 0;
    if (fflush(stdout) == 0 && !ferror(stdout))
        return code;
    cli_error("cannot write to standard output: %s", strerror(errno ? errno : EIO));
    return code == EXIT_OK ? EXIT_OUTPUT : code;
}

int main(int argc, char **argv)
{
    /* Large blocks from the heap, reused once freed, rather than a fresh mapping each whose pages
     * fault in one at a time: an import allocates and frees buffers of hundreds of KB (glTF's
     * accessors, JSON tokens), and a page fault costs microseconds on virtual machines (robot.glb's
     * `sinew info`: 0.81 of the time). A command runs once and exits: nothing to trim. */
    mallopt(M_MMAP_THRESHOLD, 32 << 20);
    mallopt(M_TRIM_THRESHOLD, 64 << 20);
    /* Small blocks coalesce as they are freed, not in one pass when a large one is next asked for:
     * libxml2 frees a COLLADA document's tree a node at a time, and gathering those nodes from the
     * fast bins was 3% of robot_walk.dae's `sinew info` (0.96 of the time without them; the
     * other formats the same). */
    mallopt(M_MXFAST, 0);
    cli_import.warm_heap = true; /* the heap keeps what is freed (above): app_warm_heap */
    if (argc < 2) {
        fputs(usage, stderr);
        return EXIT_USAGE;
    }
    const char *command = argv[1];
    if (cli_is_help(command)) {
        fputs(usage, stdout);
        return stdout_checked(EXIT_OK);
    }
    if (strcmp(command, "--version") == 0) {
        printf("sinew %s\n", sinew_version());
        return stdout_checked(EXIT_OK);
    }
    static const struct {
        const char *name;
        int (*run)(int argc, char **argv);
    } commands[] = {{"info", cmd_info},       {"pose", cmd_pose},     {"render", cmd_render},
                    {"bench", cmd_bench},     {"muscle", cmd_muscle}, {"demo", cmd_demo},
                    {"convert", cmd_convert}, {"arm", cmd_arm},       {"batch", cmd_batch}};
    const size_t count = sizeof commands / sizeof commands[0];
    if (strcmp(command, "batch") == 0) /* its options are its own (Python's argparse) */
        return cmd_batch(argc - 1, argv + 1);
    if ((argc = take_import_options(argc, argv)) < 0)
        return EXIT_USAGE;
    for (size_t i = 0; i < count; i++)
        if (strcmp(command, commands[i].name) == 0)
            return stdout_checked(commands[i].run(argc - 1, argv + 1));
    const char *nearest = NULL;
    int best = 3; /* two edits at most: "rendr", "poes" */
    for (size_t i = 0; i < count; i++) {
        int d = app_edit_distance(command, commands[i].name);
        if (d < best)
            best = d, nearest = commands[i].name;
    }
    if (nearest)
        cli_error("unknown command \"%s\"; did you mean `sinew %s`? (`sinew --help` lists them)", command, nearest);
    else
        cli_error("unknown command \"%s\" (try `sinew --help`)", command);
    return EXIT_USAGE;
}
