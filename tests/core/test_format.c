/* The .sinew runtime format: CRC-32C paths agree, save/load round trip with muscles, the
 * directory's tags (unknown skipped, duplicates and wrong sizes refused), every prefix and
 * changed byte of a file refused with a message naming it, and large blobs kept in 2 MB pages. */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/internal.h"
#include "helpers.h"

static void test_crc32c_paths_agree(void **state)
{
    (void)state;
    assert_int_equal(sinew_crc32c_scalar(0, "123456789", 9), 0xe3069283u); /* the standard check value */
    assert_int_equal(sinew_crc32c(0, "123456789", 9), 0xe3069283u);
    unsigned char buf[4099];
    uint32_t seed = 7;
    for (size_t i = 0; i < sizeof buf; i++) {
        seed = seed * 1103515245u + 12345u;
        buf[i] = (unsigned char)(seed >> 16);
    }
    for (size_t start = 0; start < 9; start++)
        for (size_t n = 0; n + start <= sizeof buf; n += n < 40 ? 1 : 397)
            assert_int_equal(sinew_crc32c(0, buf + start, n), sinew_crc32c_scalar(0, buf + start, n));
    /* Past three runs of 8 KiB the instruction path takes three at once and joins them. */
    static unsigned char big[3 * 8192 * 2 + 4099];
    for (size_t i = 0; i < sizeof big; i++)
        big[i] = (unsigned char)(i * 2654435761u >> 13);
    const size_t sizes[] = {3 * 8192 - 1, 3 * 8192, 3 * 8192 + 5, 6 * 8192, sizeof big - 3, sizeof big};
    for (size_t i = 0; i < sizeof sizes / sizeof sizes[0]; i++)
        assert_int_equal(sinew_crc32c(7, big + 3, sizes[i] - 3), sinew_crc32c_scalar(7, big + 3, sizes[i] - 3));
    /* Continuing a checksum equals taking it in one go. */
    assert_int_equal(sinew_crc32c(sinew_crc32c(0, buf, 1000), buf + 1000, 3099), sinew_crc32c_scalar(0, buf, 4099));
}

/* sinew_pages_alloc: 2 MB aligned and rounded, told apart from malloc'd pointers, 64 live at most. */
static void test_blocks_in_2mb_pages(void **state)
{
    (void)state;
    const size_t huge = (size_t)2 << 20;
    unsigned char *p = sinew_pages_alloc(3 * huge - 5, 1000);
    assert_non_null(p);
    assert_int_equal((uintptr_t)p % huge, 0);
    assert_int_equal(sinew_pages_length(p), 3 * huge);
    memset(p, 0x5a, 3 * huge - 5);
    assert_true(sinew_pages_free(p));
    void *m = malloc(64);
    assert_int_equal(sinew_pages_length(m), 0);
    assert_false(sinew_pages_free(m));
    sinew_block_free(m); /* a malloc'd pointer: freed as one */
    assert_false(sinew_pages_free(NULL));
    assert_int_equal(sinew_pages_length(NULL), 0);

    void *blocks[70];
    size_t got = 0;
    for (size_t i = 0; i < 70; i++)
        got += (blocks[i] = sinew_pages_alloc(huge, 0)) != NULL;
    assert_int_equal(got, 64); /* then the callers malloc */
    for (size_t i = 0; i < 70; i++)
        if (blocks[i])
            sinew_block_free(blocks[i]);
    p = sinew_pages_alloc(huge, huge); /* a slot free again */
    assert_non_null(p);
    sinew_block_free(p);
}

/* A freed block is kept for the next sinew_large_alloc() of its length; sinew_pages_alloc() (the
 * import's arena, which counts on zeroed pages) always maps fresh ones. */
static void test_freed_blocks_kept(void **state)
{
    (void)state;
    const size_t huge = (size_t)2 << 20;
    unsigned char *p = sinew_large_alloc(3 * huge - 5, huge);
    assert_non_null(p);
    assert_int_equal(sinew_pages_length(p), 3 * huge);
    memset(p, 0x5a, 3 * huge - 5);
    sinew_block_free(p);
    unsigned char *fresh = sinew_pages_alloc(3 * huge, 0);
    assert_non_null(fresh);
    assert_ptr_not_equal(fresh, p);
    for (size_t i = 0; i < 3 * huge; i += 4096)
        assert_int_equal(fresh[i] | fresh[i + 4095], 0);
    unsigned char *again = sinew_large_alloc(3 * huge - 100, huge); /* the same length: the kept block */
    assert_ptr_equal(again, p);
    assert_int_equal(sinew_pages_length(again), 3 * huge);
    memset(again, 1, 3 * huge - 100);                         /* writable */
    unsigned char *other = sinew_large_alloc(huge + 1, huge); /* another length: mapped anew */
    assert_non_null(other);
    assert_ptr_not_equal(other, p);
    sinew_block_free(other);
    sinew_block_free(again);
    sinew_block_free(fresh);
}

static void *plain_alloc(size_t size, void *user)
{
    ++*(int *)user;
    return malloc(size);
}

static void plain_free(void *p, void *user)
{
    --*(int *)user;
    free(p);
}

/* A .sinew file of a megabyte and more is read into 2 MB pages the model keeps (without an
 * allocator; with one it is copied into the allocator's memory), and reads back the same. */
static void test_large_file_in_pages(void **state)
{
    (void)state;
    sinew_error error = {0};
    sinew_model *model = NULL;
    if (sinew_synthetic_model(&(sinew_synthetic_desc){.vertices = 30000}, &model, &error) != SINEW_OK)
        fail_msg("%s", error.message);
    char out[4096];
    tmp_path("large.sinew", out, sizeof out);
    assert_int_equal(sinew_model_save(model, NULL, out, &error), SINEW_OK);
    const void *bytes;
    size_t size;
    sinew_model_blob(model, &bytes, &size);
    assert_true(size >= MODEL_PAGES_MIN);

    sinew_model *back = NULL;
    if (sinew_model_load(out, NULL, &back, &error) != SINEW_OK)
        fail_msg("%s", error.message);
    const void *kept;
    size_t kept_size;
    sinew_model_blob(back, &kept, &kept_size);
    assert_int_equal(kept_size, size);
    assert_true(sinew_pages_length(kept) >= kept_size);
    assert_memory_equal(back->meshes[0].positions, model->meshes[0].positions,
                        model->meshes[0].vertex_count * 3 * sizeof(float));
    sinew_model_free(back);

    int live = 0;
    sinew_allocator counting = {.alloc = plain_alloc, .free = plain_free, .user = &live};
    if (sinew_model_load(out, &counting, &back, &error) != SINEW_OK)
        fail_msg("%s", error.message);
    sinew_model_blob(back, &kept, &kept_size);
    assert_int_equal(sinew_pages_length(kept), 0);
    assert_memory_equal(back->meshes[0].positions, model->meshes[0].positions,
                        model->meshes[0].vertex_count * 3 * sizeof(float));
    sinew_model_free(back);
    assert_int_equal(live, 0);
    sinew_model_free(model);
    remove(out);
}

static sinew_model *fixture_with_muscles(sinew_muscle_set **set)
{
    char path[4096], mpath[4096];
    sinew_model *model = load_or_fail(fixture_path("two_bone.dae", path, sizeof path));
    sinew_error error = {0};
    if (sinew_muscle_set_read(fixture_path("two_bone.muscles.json", mpath, sizeof mpath), set, &error) != SINEW_OK)
        fail_msg("%s", error.message);
    return model;
}

static void test_save_load_round_trip(void **state)
{
    (void)state;
    sinew_muscle_set *set = NULL;
    sinew_model *model = fixture_with_muscles(&set);
    char out[4096];
    tmp_path("round_trip.sinew", out, sizeof out);
    sinew_error error = {0};
    assert_int_equal(sinew_model_save(model, set, out, &error), SINEW_OK);
    sinew_model *back = NULL;
    if (sinew_model_load(out, NULL, &back, &error) != SINEW_OK)
        fail_msg("%s", error.message);
    assert_string_equal(back->source, out);
    assert_string_equal(back->format, model->format);
    assert_string_equal(back->converted_from, model->source);
    assert_int_equal(back->node_count, model->node_count);
    assert_int_equal(back->clip_count, model->clip_count);
    assert_memory_equal(back->meshes[0].positions, model->meshes[0].positions,
                        model->meshes[0].vertex_count * 3 * sizeof(float));
    assert_memory_equal(back->clips[0].values, model->clips[0].values, model->clips[0].value_count * sizeof(float));

    /* The muscles came along, number for number. */
    assert_non_null(back->muscles);
    assert_int_equal(back->muscles->muscle_count, set->muscle_count);
    for (uint32_t i = 0; i < set->muscle_count; i++) {
        const sinew_muscle_def *a = &set->muscles[i], *b = &back->muscles->muscles[i];
        assert_string_equal(a->name, b->name);
        assert_true((a->origin.joint == NULL) == (b->origin.joint == NULL));
        if (a->origin.joint)
            assert_string_equal(a->origin.joint, b->origin.joint);
        assert_memory_equal(a->insertion.offset, b->insertion.offset, sizeof a->insertion.offset);
        assert_int_equal(a->node_count, b->node_count);
        assert_memory_equal(a->radii, b->radii, a->node_count * sizeof(double));
        assert_memory_equal(a->coefficients, b->coefficients, a->node_count * sizeof(double));
        assert_int_equal(a->segments, b->segments);
        assert_true(a->rest_length == b->rest_length);
    }
    sinew_muscle_rig *rig = NULL;
    assert_int_equal(sinew_muscle_rig_create(back, back->muscles, &rig, &error), SINEW_OK);
    sinew_muscle_rig_free(rig);

    /* Writing the loaded model again gives the same bytes (muscles kept by default). */
    void *again = NULL;
    size_t again_size = 0;
    assert_int_equal(sinew_model_write_blob(back, NULL, &again, &again_size, &error), SINEW_OK);
    const void *own;
    size_t own_size;
    sinew_model_blob(back, &own, &own_size);
    assert_int_equal(again_size, own_size);
    assert_memory_equal(again, own, own_size);
    free(again);

    /* Without muscles: the import blob's bytes exactly. */
    assert_int_equal(sinew_model_write_blob(model, NULL, &again, &again_size, &error), SINEW_OK);
    sinew_model_blob(model, &own, &own_size);
    assert_int_equal(again_size, own_size);
    assert_memory_equal(again, own, own_size);
    free(again);

    sinew_model_free(back);
    sinew_model_free(model);
    sinew_muscle_set_free(set);
}

/* The blob with directory entry `index` rewritten and the checksum fixed. */
static void *edit_section(const void *blob, size_t size, const char *tag, const char *new_tag, uint32_t elem_size)
{
    unsigned char *copy = malloc(size);
    memcpy(copy, blob, size);
    blob_file_header f;
    memcpy(&f, copy, sizeof f);
    bool found = false;
    for (uint32_t i = 0; i < f.section_count; i++) {
        blob_section sec;
        memcpy(&sec, copy + sizeof f + i * sizeof sec, sizeof sec);
        if (memcmp(sec.tag, tag, 4) != 0)
            continue;
        memcpy(sec.tag, new_tag, 4);
        sec.elem_size = elem_size;
        memcpy(copy + sizeof f + i * sizeof sec, &sec, sizeof sec);
        found = true;
    }
    assert_true(found);
    f.checksum = sinew_blob_checksum(copy, size);
    memcpy(copy, &f, sizeof f);
    return copy;
}

static void test_directory_tags(void **state)
{
    (void)state;
    sinew_muscle_set *set = NULL;
    sinew_model *model = fixture_with_muscles(&set);
    void *blob = NULL;
    size_t size = 0;
    sinew_error error = {0};
    assert_int_equal(sinew_model_write_blob(model, set, &blob, &size, &error), SINEW_OK);

    /* A section this build does not know is skipped: the model loads without it. */
    void *edited = edit_section(blob, size, "MUSC", "ZZZZ", 5);
    sinew_model *m = NULL;
    assert_int_equal(sinew_model_from_blob(edited, size, "unknown tag", NULL, &m, &error), SINEW_OK);
    assert_null(m->muscles);
    assert_int_equal(m->node_count, model->node_count);
    sinew_model_free(m);
    free(edited);

    /* A known tag twice, or with another element size, is refused. */
    edited = edit_section(blob, size, "WARN", "NNAM", 4);
    assert_int_equal(sinew_model_from_blob(edited, size, "twice", NULL, &m, &error), SINEW_ERROR_FORMAT);
    assert_non_null(strstr(error.message, "NNAM appears twice"));
    free(edited);
    edited = edit_section(blob, size, "MESH", "MESH", 44);
    assert_int_equal(sinew_model_from_blob(edited, size, "size", NULL, &m, &error), SINEW_ERROR_FORMAT);
    assert_non_null(strstr(error.message, "MESH has the wrong element size"));
    free(edited);

    /* Another version is refused with what to do. */
    edited = malloc(size);
    memcpy(edited, blob, size);
    ((blob_file_header *)edited)->version = 99;
    assert_int_equal(sinew_model_from_blob(edited, size, "v99", NULL, &m, &error), SINEW_ERROR_FORMAT);
    assert_non_null(strstr(error.message, "version 99"));
    free(edited);

    free(blob);
    sinew_model_free(model);
    sinew_muscle_set_free(set);
}

/* A copy of `blob` with the float at `at` set to `value` and the checksum fixed: loading it must
 * fail with SINEW_ERROR_FORMAT saying the track keys are wrong. */
static void expect_bad_key(const void *blob, size_t size, const float *at, float value)
{
    size_t offset = (size_t)((const unsigned char *)at - (const unsigned char *)blob);
    assert_true(offset + sizeof value <= size);
    unsigned char *copy = malloc(size);
    assert_non_null(copy);
    memcpy(copy, blob, size);
    memcpy(copy + offset, &value, sizeof value);
    blob_file_header f;
    memcpy(&f, copy, sizeof f);
    f.checksum = sinew_blob_checksum(copy, size);
    memcpy(copy, &f, sizeof f);
    sinew_model *m = NULL;
    sinew_error error = {0};
    assert_int_equal(sinew_model_from_blob(copy, size, "keys", NULL, &m, &error), SINEW_ERROR_FORMAT);
    assert_non_null(strstr(error.message, "track keys"));
    free(copy);
}

/* Long channels are checked a block of 64 floats at a time: a key time that goes back, or a time
 * or value that is not finite, is found in any block and in the tail after the last. */
static void test_long_channel_keys_checked(void **state)
{
    (void)state;
    sinew_model *model = NULL;
    sinew_error error = {0};
    sinew_synthetic_desc desc = {.joints = 4, .vertices = 64, .duration = 10.0f, .keys_per_second = 30.0f};
    if (sinew_synthetic_model(&desc, &model, &error) != SINEW_OK)
        fail_msg("%s", error.message);
    const void *blob;
    size_t size;
    sinew_model_blob(model, &blob, &size);
    const sinew_clip *clip = &model->clips[0];
    const sinew_channel *ch = &clip->tracks[0].channels[SINEW_CHANNEL_ROTATION];
    assert_true(ch->key_count > 200);
    const float *times = clip->times + ch->first_key, *values = clip->values + ch->first_value;
    sinew_model *same = NULL;
    assert_int_equal(sinew_model_from_blob(blob, size, "as built", NULL, &same, &error), SINEW_OK);
    sinew_model_free(same);
    const uint32_t keys[] = {1, 63, 64, 65, 100, 128, 129, ch->key_count - 1};
    for (size_t i = 0; i < sizeof keys / sizeof *keys; i++) {
        uint32_t k = keys[i];
        expect_bad_key(blob, size, &times[k], times[k - 1] - 0.01f);
        expect_bad_key(blob, size, &times[k], INFINITY);
        expect_bad_key(blob, size, &values[4 * k + 2], NAN);
    }
    sinew_model_free(model);
}

/* Every prefix of a small .sinew file and every byte of it changed, read through the file
 * loader, is refused with a message naming the file; nothing crashes or leaks (ASan run). */
static void test_every_prefix_and_changed_byte_of_a_file(void **state)
{
    (void)state;
    sinew_muscle_set *set = NULL;
    sinew_model *model = fixture_with_muscles(&set);
    char whole[4096], cut[4096];
    tmp_path("whole.sinew", whole, sizeof whole);
    tmp_path("cut.sinew", cut, sizeof cut);
    sinew_error error = {0};
    assert_int_equal(sinew_model_save(model, set, whole, &error), SINEW_OK);
    size_t size = 0;
    unsigned char *bytes = read_file(whole, &size);
    assert_non_null(bytes);
    for (size_t n = 0; n < size; n++) {
        write_file(cut, bytes, n);
        sinew_model *m = (sinew_model *)1;
        memset(&error, 0, sizeof error);
        assert_int_equal(sinew_model_load(cut, NULL, &m, &error), SINEW_ERROR_FORMAT);
        assert_null(m);
        assert_non_null(strstr(error.message, cut));
    }
    for (size_t i = 0; i < size; i++) {
        unsigned char saved = bytes[i];
        bytes[i] ^= (unsigned char)(1u << (i % 8)); /* each byte, a different bit each time */
        write_file(cut, bytes, size);
        sinew_model *m = NULL;
        if (sinew_model_load(cut, NULL, &m, &error) == SINEW_OK)
            fail_msg("changing byte %zu of %zu was not noticed", i, size);
        bytes[i] = saved;
    }
    /* The untouched file still loads, and through sinew_import too (found by its magic). */
    write_file(cut, bytes, size);
    sinew_model *m = NULL;
    sinew_import_desc desc = {.path = cut};
    assert_int_equal(sinew_import(&desc, &m, &error), SINEW_OK);
    assert_non_null(m->converted_from);
    sinew_model_free(m);
    assert_int_equal(sinew_model_load("/nonexistent/x.sinew", NULL, &m, &error), SINEW_ERROR_IO);
    assert_non_null(strstr(error.message, "/nonexistent/x.sinew"));
    free(bytes);
    sinew_model_free(model);
    sinew_muscle_set_free(set);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_crc32c_paths_agree),
        cmocka_unit_test(test_blocks_in_2mb_pages),
        cmocka_unit_test(test_freed_blocks_kept),
        cmocka_unit_test(test_large_file_in_pages),
        cmocka_unit_test(test_save_load_round_trip),
        cmocka_unit_test(test_directory_tags),
        cmocka_unit_test(test_every_prefix_and_changed_byte_of_a_file),
        cmocka_unit_test(test_long_channel_keys_checked),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
