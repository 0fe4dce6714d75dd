/* Checksums of model blobs: CRC-32C (Castagnoli, the iSCSI/ext4 polynomial), which x86
 * computes eight bytes an instruction (SSE4.2 crc32), three runs at once. The table-driven version is the
 * reference the tests hold the instruction path to, and the path on other processors. */
#include <string.h>
#include <threads.h>

#include "internal.h"

#if defined(__x86_64__) && defined(__GNUC__)
#include <nmmintrin.h>
#define SINEW_HAVE_SSE42_CRC 1
#endif

static uint32_t crc_table[256];
static once_flag crc_once = ONCE_FLAG_INIT;

static void crc_table_init(void)
{
    for (uint32_t i = 0; i < 256; i++) {
        uint32_t c = i;
        for (int k = 0; k < 8; k++)
            c = (c & 1u) ? 0x82f63b78u ^ (c >> 1) : c >> 1;
        crc_table[i] = c;
    }
}

uint32_t sinew_crc32c_scalar(uint32_t crc, const void *bytes, size_t size)
{
    call_once(&crc_once, crc_table_init);
    const uint32_t *table = crc_table;
    const unsigned char *p = bytes;
    crc ^= 0xffffffffu;
    for (size_t i = 0; i < size; i++)
        crc = table[(crc ^ p[i]) & 0xffu] ^ (crc >> 8);
    return crc ^ 0xffffffffu;
}

#ifdef SINEW_HAVE_SSE42_CRC
/* a * b modulo the polynomial, both bit-reflected as CRC-32C keeps them (bit 31 is x^0) */
static uint32_t crc_multiply(uint32_t a, uint32_t b)
{
    uint32_t product = 0;
    for (uint32_t m = 1u << 31; m; m >>= 1) {
        if (a & m)
            product ^= b;
        b = (b & 1u) ? 0x82f63b78u ^ (b >> 1) : b >> 1; /* b * x */
    }
    return product;
}

/* Three runs of CRC_RUN bytes at once: the crc32 instruction takes three cycles to give its
 * result but starts one a cycle, so one run waits on itself. Appending n bytes to a message
 * multiplies its CRC register by x^(8n) and adds the bytes' own (zero-started) CRC, which is how
 * the three are joined. */
#define CRC_RUN 8192
static uint32_t crc_run_shift; /* x^(8 * CRC_RUN) modulo the polynomial */
static once_flag crc_shift_once = ONCE_FLAG_INIT;

static void crc_shift_init(void)
{
    uint32_t power = 1u << 31, square = 1u << 23; /* x^0, x^8 */
    for (uint32_t n = CRC_RUN; n; n >>= 1) {      /* (x^8)^CRC_RUN by squaring */
        if (n & 1u)
            power = crc_multiply(power, square);
        square = crc_multiply(square, square);
    }
    crc_run_shift = power;
}

__attribute__((target("sse4.2"))) static uint32_t crc32c_sse42(uint32_t crc, const void *bytes, size_t size)
{
    const unsigned char *p = bytes;
    uint64_t c = crc ^ 0xffffffffu;
    if (size >= 3 * CRC_RUN) {
        call_once(&crc_shift_once, crc_shift_init);
        for (; size >= 3 * CRC_RUN; size -= 3 * CRC_RUN, p += 3 * CRC_RUN) {
            uint64_t a = c, b = 0, d = 0;
            for (size_t i = 0; i < CRC_RUN; i += 8) {
                uint64_t wa, wb, wd;
                memcpy(&wa, p + i, 8);
                memcpy(&wb, p + CRC_RUN + i, 8);
                memcpy(&wd, p + 2 * CRC_RUN + i, 8);
                a = _mm_crc32_u64(a, wa);
                b = _mm_crc32_u64(b, wb);
                d = _mm_crc32_u64(d, wd);
            }
            uint32_t ab = crc_multiply((uint32_t)a, crc_run_shift) ^ (uint32_t)b;
            c = crc_multiply(ab, crc_run_shift) ^ (uint32_t)d;
        }
    }
    for (; size >= 8; size -= 8, p += 8) {
        uint64_t word;
        memcpy(&word, p, 8);
        c = _mm_crc32_u64(c, word);
    }
    uint32_t c32 = (uint32_t)c;
    for (; size > 0; size--, p++)
        c32 = _mm_crc32_u8(c32, *p);
    return c32 ^ 0xffffffffu;
}
#endif

uint32_t sinew_crc32c(uint32_t crc, const void *bytes, size_t size)
{
#ifdef SINEW_HAVE_SSE42_CRC
    if (sinew_cpu_has(SINEW_CPU_SSE42))
        return crc32c_sse42(crc, bytes, size);
#endif
    return sinew_crc32c_scalar(crc, bytes, size);
}

uint32_t sinew_blob_checksum(const void *bytes, size_t size)
{
    blob_file_header header;
    memcpy(&header, bytes, sizeof header);
    header.checksum = 0;
    uint32_t crc = sinew_crc32c(0, &header, sizeof header);
    return sinew_crc32c(crc, (const unsigned char *)bytes + sizeof header, size - sizeof header);
}
