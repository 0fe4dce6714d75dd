/* libFuzzer target for the player: the first 17 bytes are four times (any float, NaN and
 * infinities included) and a wrap mode, the rest a .sinew model; an input that is a .sinew
 * file itself (the seeds) is played at 0, 0.5 s, 1e9 s and NaN, looped. Every clip of a model that
 * loads is played (by two players of one layout, at those times in opposite orders): an update either succeeds or
 * refuses the time, never reads or writes out of bounds. build/fuzz_player_replay FILES   the same on given files (part
 * of `make test`) */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "core/internal.h"
#include "sinew/sinew.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

#define PREFIX 17

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    float times[4] = {0.0f, 0.5f, 1e9f, NAN};
    sinew_wrap wrap = SINEW_WRAP_LOOP;
    size_t skip = 0;
    if (!(size >= sizeof BLOB_MAGIC - 1 && memcmp(data, BLOB_MAGIC, sizeof BLOB_MAGIC - 1) == 0)) {
        if (size < PREFIX)
            return 0;
        memcpy(times, data, sizeof times);
        wrap = data[16] & 1 ? SINEW_WRAP_LOOP : SINEW_WRAP_CLAMP;
        skip = PREFIX;
    }
    sinew_model *m = NULL;
    if (sinew_model_from_blob(data + skip, size - skip, "fuzz", NULL, &m, NULL) != SINEW_OK)
        return 0;
    sinew_mat4 *worlds = malloc(((size_t)m->node_count + 1) * sizeof *worlds);
    for (uint32_t c = 0; worlds && c <= m->clip_count; c++) {
        const sinew_clip *clip = c < m->clip_count ? &m->clips[c] : NULL; /* and the rest pose */
        sinew_clip_layout *layout = NULL;
        sinew_player *player = NULL, *other = NULL;
        if (sinew_clip_layout_create(&(sinew_clip_layout_desc){.model = m, .clip = clip}, &layout, NULL) != SINEW_OK)
            abort(); /* a model that loaded can be played */
        size_t bytes = sinew_player_size(layout);
        unsigned char *memory = malloc(2 * bytes + 1);
        /* the second player starts on an odd address: it aligns itself */
        if (!memory || sinew_player_init(memory, bytes, layout, &player, NULL) != SINEW_OK ||
            sinew_player_init(memory + bytes + 1, bytes, layout, &other, NULL) != SINEW_OK)
            abort();
        for (int i = 0; i < 4; i++) {
            sinew_player_update(player, times[i], wrap, NULL, worlds, m->node_count, NULL);
            sinew_player_update(other, times[3 - i], wrap, NULL, worlds, m->node_count, NULL);
        }
        free(memory);
        sinew_clip_layout_free(layout);
    }
    free(worlds);
    sinew_model_free(m);
    return 0;
}
