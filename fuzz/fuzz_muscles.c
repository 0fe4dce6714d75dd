/* libFuzzer target for the muscle JSON reader: any bytes are read or refused with a format or
 * data error naming the input; a set that reads is bound (attachments without joints: in
 * model space), solved at its rest pose and turned into tube surfaces.
 *   build/fuzz_muscles_replay FILES   the same on given files (part of `make test`) */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "sinew/sinew.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    sinew_muscle_set *set = NULL;
    sinew_error error = {0};
    sinew_result result = sinew_muscle_set_parse((const char *)data, size, "fuzz", &set, &error);
    if (result != SINEW_OK) {
        if ((result != SINEW_ERROR_FORMAT && result != SINEW_ERROR_DATA) || !strstr(error.message, "fuzz"))
            abort(); /* every refusal names the input */
        return 0;
    }
    sinew_muscle_rig *rig = NULL;
    if (sinew_muscle_rig_create(NULL, set, &rig, &error) == SINEW_OK) {
        uint32_t n = sinew_muscle_rig_count(rig);
        sinew_muscle_pose *poses = calloc(n ? n : 1, sizeof *poses);
        if (!poses || sinew_muscle_rig_update(rig, NULL, 0, poses, n, &error) != SINEW_OK)
            abort(); /* a bound rig always has something to draw */
        for (uint32_t i = 0; i < n; i++) {
            uint32_t vertices, indices;
            sinew_muscle_surface_size(poses[i].node_count, poses[i].segments, &vertices, &indices);
            float *positions = malloc((size_t)vertices * 3 * sizeof(float));
            uint32_t *triangles = malloc((size_t)indices * sizeof(uint32_t));
            sinew_muscle_surface_desc desc = {.node_count = poses[i].node_count,
                                              .radii = poses[i].radii,
                                              .segments = poses[i].segments,
                                              .out_positions = positions,
                                              .vertex_capacity = vertices,
                                              .out_indices = triangles,
                                              .index_capacity = indices};
            memcpy(desc.origin, poses[i].origin, sizeof desc.origin);
            memcpy(desc.insertion, poses[i].insertion, sizeof desc.insertion);
            if (positions && triangles)
                sinew_muscle_surface(&desc, NULL);
            free(positions);
            free(triangles);
        }
        free(poses);
        sinew_muscle_rig_free(rig);
    }
    sinew_muscle_set_free(set);
    return 0;
}
