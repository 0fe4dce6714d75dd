/* Checksums of model blobs: CRC-32 (IEEE), the one zlib and PNG use. */
#include <string.h>
#include <threads.h>

#include "internal.h"

static uint32_t crc_table[256];
static once_flag crc_once = ONCE_FLAG_INIT;

static void crc_table_init(void)
{
    for (uint32_t i = 0; i < 256; i++) {
        uint32_t c = i;
        for (int k = 0; k < 8; k++)
            c = (c & 1u) ? 0xedb88320u ^ (c >> 1) : c >> 1;
        crc_table[i] = c;
    }
}

/* CRC-32 (IEEE 802.3), continued from `crc` (0 to start), as zlib's crc32() computes it. */
uint32_t sinew_crc32(uint32_t crc, const void *bytes, size_t size)
{
    call_once(&crc_once, crc_table_init);
    const uint32_t *table = crc_table;
    const unsigned char *p = bytes;
    crc ^= 0xffffffffu;
    for (size_t i = 0; i < size; i++)
        crc = table[(crc ^ p[i]) & 0xffu] ^ (crc >> 8);
    return crc ^ 0xffffffffu;
}

uint32_t sinew_blob_checksum(const void *bytes, size_t size)
{
    blob_header header;
    memcpy(&header, bytes, sizeof header);
    header.checksum = 0;
    uint32_t crc = sinew_crc32(0, &header, sizeof header);
    return sinew_crc32(crc, (const unsigned char *)bytes + sizeof header, size - sizeof header);
}
