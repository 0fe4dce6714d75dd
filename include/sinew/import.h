/* sinew/import.h — reading animated characters from files.
 *
 * What: sinew_import() reads FBX 5.x, 6.x and 7.x (binary and ASCII), glTF 2.0 (.gltf, .glb), COLLADA
 * 1.4/1.5 (.dae), IQM and BVH with sinew's own readers and any other format Assimp reads (.x, MD5,
 * SMD, 3DS, OBJ, ...), and builds a runtime sinew_model: the skeleton from the node
 * hierarchy, every mesh and skin, materials, every clip in seconds, Y up, metres.
 * COLLADA: joints bound by SID under the instance's <skeleton>, transform stacks evaluated in
 * order, STEP/LINEAR keys kept, BEZIER/HERMITE curves and Euler-angle channels baked to cubic
 * keys within the FBX tolerances below, <animation_clip>s as clips. glTF: nodes by index,
 * samplers kept as written (STEP, LINEAR, CUBICSPLINE).
 * FBX is evaluated as Maya, 3ds Max and MotionBuilder evaluate it: pivots, offsets, pre- and
 * post-rotation, rotation order, geometric transforms, each node's inherit type (kept in
 * model->node_inherit), Bezier curves with weights and automatic tangents. Its clips are
 * baked to cubic keys that equal the curves at every key and stay within 1e-6 (radians,
 * relative scale, and of the scene's size for translation) in between. A file that looks
 * like FBX, glTF or COLLADA, or is named so, is never handed to Assimp unless desc->assimp
 * asks for it.
 * sinew's own readers run in the calling process, under the import's deadline and memory limit
 * (desc->timeout, desc->memory_limit): every allocation of the readers and the builder is
 * counted against the limit, and the readers look at the clock as they go, so that a file that
 * would make them loop or grow without end stops with SINEW_ERROR_LIMIT_TIME or
 * SINEW_ERROR_LIMIT_MEMORY and nothing is left behind. Assimp's formats (and desc->assimp) are
 * read in the import helper program, sinew-import (installed beside sinew, see
 * sinew_import_helper_path()), which hands them to sinew-import-assimp: libsinew never loads
 * Assimp. desc->isolate runs every format there
 * (an untrusted file: a crash in a reader then costs an error, not the caller). The helper is
 * started with posix_spawn and hands the model back through a pipe as one flat blob; it has the
 * same deadline and memory limit, dies with the thread that started it, and its reply can be no
 * larger than its memory limit.
 * What not: no rendering, no sampling; the model is immutable once built.
 * Memory: the model is one allocation through desc->allocator (malloc when NULL); free it
 * with sinew_model_free(). While reading, every allocation of sinew's readers and builder is
 * counted against the import's own byte limit (desc->memory_limit), and any that fails fails
 * the import with SINEW_ERROR_OUT_OF_MEMORY: never a partial model (the tests fail each
 * allocation in turn over the shared models, as ufbx's runner does). Large blocks in 2 MB pages
 * that an import or a model frees (the file's bytes, JSON, blobs) are kept by the process, up to
 * four and 32 MB, as MADV_FREE (the kernel takes them back when it needs memory), for the next
 * import: a program importing file after file does not have the same pages zeroed for each.
 * Errors: SINEW_ERROR_IO (missing, directory, unreadable), SINEW_ERROR_FORMAT (empty,
 * unknown format, truncated), SINEW_ERROR_IMPORTER (Assimp refused; the helper crashed or was
 * killed from outside: the signal is named, and its last stderr lines quoted),
 * SINEW_ERROR_DATA (NaN/Inf, bad indices, zero weights), SINEW_ERROR_LIMIT (over a documented
 * limit), SINEW_ERROR_LIMIT_TIME and SINEW_ERROR_LIMIT_MEMORY (the import passed its deadline or
 * memory limit), SINEW_ERROR_CANCELLED (desc->progress asked to stop). error->file names the file
 * (or the external part that failed); error->offset (binary FBX, glTF JSON) and error->line
 * (COLLADA, ASCII FBX) say where, when the reader knows.
 * Import warnings (dropped dummy meshes, missing textures, renormalised weights) are kept in
 * model->warnings.
 */
#ifndef SINEW_IMPORT_H
#define SINEW_IMPORT_H

#include "sinew/model.h"

#ifdef __cplusplus
extern "C" {
#endif

/* The default memory limit of an import: 256 MiB and 64 times the file's size (a 600 kB file:
 * 294 MiB), at most half the machine's memory. */
#define SINEW_IMPORT_MEMORY_BASE ((uint64_t)256 << 20)
#define SINEW_IMPORT_MEMORY_FACTOR 64u

typedef struct sinew_import_desc {
    const char *path;
    bool isolate;                     /* read every format in the helper program (sinew's own too) */
    bool assimp;                      /* read with Assimp even a format sinew reads itself: to compare */
    const sinew_allocator *allocator; /* NULL: malloc/free */
    const char *helper;               /* the helper's path; NULL: found as sinew_import_helper_path() says */
    double timeout;                   /* seconds the import may take; 0: 120; negative: no deadline */
    uint64_t memory_limit;            /* bytes of address space it may use; 0: SINEW_IMPORT_MEMORY_BASE plus
                                         SINEW_IMPORT_MEMORY_FACTOR times the file's size, at most half the
                                         machine's memory (kept within 1..16 GiB; a session, whose files are
                                         not known in advance: that ceiling); UINT64_MAX: none. It also bounds
                                         the bytes sinew's readers and builder hold, in the helper and in
                                         process, counted allocation by allocation (glTF's JSON tokens
                                         too): past it SINEW_ERROR_LIMIT_MEMORY. (What libxml2 and Assimp
                                         allocate inside is not counted.) */
    int stderr_fd;                    /* 0: its stderr is kept, and its last lines quoted when it fails; else
                                         the descriptor it writes its stderr to (2: the caller's stderr) */
    /* Called on the calling thread before reading and about every 50 ms while the file is read
     * (in this process, or in the helper): `fraction` is -1 while the file is read, then, from
     * the helper, 0..1 as the model comes back. Returning false stops the import at once:
     * SINEW_ERROR_CANCELLED. NULL: none. */
    bool (*progress)(float fraction, void *user);
    void *progress_user;
    /* Where files come from, as cgltf's and ufbx's file callbacks: the model (sinew_import()) and its
     * external parts (a glTF's .bin buffers, an FBX's vertex caches, a COLLADA clip library), `path`
     * as the reader resolved it against the model's folder. Return true with *bytes (from malloc:
     * sinew frees it) and *size, or false: the file is missing. With a callback, sinew_import()
     * reads in this process with sinew's own readers (FBX, glTF, COLLADA, IQM, BVH, .sinew; Assimp's
     * formats need files: SINEW_ERROR_UNSUPPORTED). NULL: the file system. */
    bool (*read_file)(const char *path, void **bytes, size_t *size, void *user);
    void *read_user;
} sinew_import_desc;

sinew_result sinew_import(const sinew_import_desc *desc, sinew_model **out, sinew_error *error);

/* Imports a model from bytes in memory, in this process, with sinew's own readers: an engine's
 * asset loader, a file inside an archive, a fuzzer. `format` names it as its file extension would
 * ("fbx", "gltf", "glb", "dae", "iqm", "bvh", "sinew"), or NULL: desc->path's extension, else told from the bytes.
 * `desc` may be NULL; desc->path names the model in messages and is the folder its external parts are found in (through
 * desc->read_file when given; NULL path: "(memory).FORMAT", parts in the working folder); desc->allocator makes the
 * model; desc->progress is asked once. The bytes are only read, and may go when it returns. SINEW_ERROR_UNSUPPORTED for
 * bytes of another format (Assimp's need files), else the errors of sinew_import(). */
sinew_result sinew_import_memory(const void *bytes, size_t size, const char *format, const sinew_import_desc *desc,
                                 sinew_model **out, sinew_error *error);

/* Many files, one helper: with desc->isolate, a session keeps its helper running between
 * files, so that a library of small files does not pay for starting a process each (about 6 ms
 * of CPU, and on some machines process starts do not run in parallel). Each file keeps its own
 * deadline; past it, or on a crash, the helper is killed and the next file starts a fresh one;
 * one that used more than half the memory limit is replaced too. Files only Assimp reads,
 * .sinew files and, without desc->isolate, every file go as sinew_import() sends them (sinew's
 * own formats in this process, no helper started). A session is used by one thread at a time;
 * its helper dies with the thread that started it (the next file then starts another).
 * `desc` (its path unused) gives every setting, as for sinew_import(). */
typedef struct sinew_import_session sinew_import_session;
sinew_result sinew_import_session_create(const sinew_import_desc *desc, sinew_import_session **out, sinew_error *error);
sinew_result sinew_import_session_load(sinew_import_session *session, const char *path, sinew_model **out,
                                       sinew_error *error);
/* Ends the helper (it exits when its requests end) and frees the session. */
void sinew_import_session_free(sinew_import_session *session);
/* The process id of the session's helper, 0 when none runs (for monitoring and tests). */
int sinew_import_session_helper_pid(const sinew_import_session *session);

/* The helper program sinew_import() would start: desc->helper, else $SINEW_IMPORT_HELPER, else
 * sinew-import beside the running program, in its ../libexec/sinew/, in the libexec folder
 * beside the shared library, or in the installed libexec folder. SINEW_ERROR_IO lists where
 * it looked when none is there. `desc` may be NULL. */
sinew_result sinew_import_helper_path(const sinew_import_desc *desc, char *out, size_t size, sinew_error *error);

/* Imports the file into the flat blob that sinew_model_from_blob() reads; *bytes is
 * malloc'd, the caller frees it. This is what the import helper does (in this process for
 * sinew's own formats, through the helper for Assimp's). */
sinew_result sinew_import_blob(const char *path, void **bytes, size_t *size, sinew_error *error);
/* The same with the import desc's choice of reader (desc->assimp). */
sinew_result sinew_import_blob_desc(const sinew_import_desc *desc, void **bytes, size_t *size, sinew_error *error);

/* Serialises a model as the bytes of a .sinew file (tagged, versioned, checksummed; see
 * sinew_model_load()). `muscles`, when not NULL, are stored with it in place of the
 * model's own (model->muscles). *bytes is malloc'd. */
sinew_result sinew_model_write_blob(const sinew_model *model, const struct sinew_muscle_set *muscles, void **bytes,
                                    size_t *size, sinew_error *error);

/* The same written to `path`, through a temporary file renamed into place. */
sinew_result sinew_model_save(const sinew_model *model, const struct sinew_muscle_set *muscles, const char *path,
                              sinew_error *error);

/* A generated character for benchmarks and tests (no file involved): a chain of `joints`
 * joints standing 1.8 m tall along +Y, skinned by a tube of at least `vertices` vertices
 * (32 around) with `influences` smooth weights a vertex (1..8), and one looping clip
 * "sway" of `duration` seconds with `keys_per_second` rotation keys on every joint (the
 * chain sways and twists as a whole by up to about 60 degrees). Zero fields mean 64
 * joints, 10,000 vertices, 4 influences, 2 s, 30 keys/s. */
typedef struct sinew_synthetic_desc {
    uint32_t joints;
    uint32_t vertices;
    uint32_t influences;
    float duration;
    float keys_per_second;
    bool keyed_trs; /* key translation and scale on every joint too, as baked exports do */
    /* Morph targets ("bulge 0", ...): each swells a band of the tube outwards (bands spread
     * from the bottom to the top, overlapping), default weight 0; the clip animates the
     * weights of the first `morph_animated` of them (0 to 1 and back, each at its own rate),
     * as a face rig plays a few shapes at a time. 0: none. */
    uint32_t morph_targets;
    uint32_t morph_animated;
} sinew_synthetic_desc;

sinew_result sinew_synthetic_model(const sinew_synthetic_desc *desc, sinew_model **out, sinew_error *error);

/* The demo humanoid (`sinew demo`, the viewer's and `make run`'s first model): 24 joints
 * named as Unity's humanoid avatar names bones (Hips, Spine, Chest, ..., LeftUpperArm,
 * RightLowerArm, LeftUpperLeg, ...), a 15,000-vertex body skinned with smooth weights, a staff on its own node under
 * Hand.R, and the clips "walk" (1 s cycle in place) and "wave" (2 s), keyed 30 times a
 * second. Y up, metres, facing +z. Its muscles (sinew_demo_humanoid_muscles()) are its own
 * (model->muscles), as a .sinew file's. */
sinew_result sinew_demo_humanoid(sinew_model **out, sinew_error *error);

/* Its muscles as muscle JSON (sinew/muscle_file.h): LeftBiceps and RightBiceps. Static text. */
const char *sinew_demo_humanoid_muscles(void);

/* Clips of another file on this model (`--anim FILE`): every clip of `source`, retargeted onto
 * `target`'s skeleton and baked at frame_rate keys a second, in a new model that has them
 * first and then the target's own clips. Joints match by a name map (JSON {"source name":
 * "target name"}), else by name with prefixes ("mixamorig:", "Armature|"), case and
 * separators set aside, else through built-in humanoid namings (Mixamo, CMU's BVH, Unity's
 * humanoid and the demo's) mapped to one set. Rest poses are compensated: a matched joint
 * turns in world space as its source turns from the source's rest. The topmost matched joint
 * (the hips) also moves as its source does, scaled by the legs' length ratio. */
typedef struct sinew_retarget_desc {
    const sinew_model *target; /* the character */
    const sinew_model *source; /* whose clips are applied */
    const char *name_map;      /* a JSON file, or NULL */
    float frame_rate;          /* 0: 30 */
} sinew_retarget_desc;

sinew_result sinew_retarget(const sinew_retarget_desc *desc, sinew_model **out, sinew_error *error);
/* Which source node each target node takes its motion from (-1: none), by the rules above
 * without a name map; returns how many match. `match` holds target->node_count entries. */
uint32_t sinew_retarget_matches(const sinew_model *target, const sinew_model *source, int32_t *match);

/* Writes a model as a COLLADA 1.4.1 file that other COLLADA readers open: nodes with
 * matrices (id = sid = the name with characters other than letters, digits, '_' and '-'
 * made '_'; name = the name: Assimp names nodes by id), meshes (positions, normals, UVs), skins as controllers,
 * materials as Phong effects, and each clip as a time range of one timeline (<animation_clip>s; every animated node
 * gets one matrix channel keyed at its keys' times). Linear and step keys are written as they are; cubic and Bezier
 * ones sampled 60 times a second. */
sinew_result sinew_model_write_collada(const sinew_model *model, const char *path, sinew_error *error);

#ifdef __cplusplus
}
#endif
#endif
