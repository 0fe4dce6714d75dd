/* AVX-512 intrinsics for processors without it: SIMDe's portable implementations (Debian's
 * libsimde-dev, header-only) under their Intel names, and the few this SIMDe lacks written out
 * here lane by lane. rsqrt14 is an exact 1/sqrt here: the emulated kernel is checked for its
 * data movement and arithmetic, not for the hardware estimate's last bits. Only
 * test_skin_avx512 includes it (through src/core/skin_x86.c). */
#ifndef SINEW_AVX512_EMULATED_H
#define SINEW_AVX512_EMULATED_H

#define SIMDE_ENABLE_NATIVE_ALIASES
#include <math.h>
#include <simde/x86/avx512.h>
#include <stddef.h>
#include <string.h>

/* the mask types, as immintrin.h names them (the same types: a repeated typedef is allowed) */
typedef simde__mmask16 __mmask16;
typedef simde__mmask8 __mmask8;

static inline simde__m512 emulated_maskz_loadu_ps(uint16_t mask, const void *p)
{
    float f[16];
    for (int i = 0; i < 16; i++)
        f[i] = ((mask >> i) & 1) ? ((const float *)p)[i] : 0.0f;
    return simde_mm512_loadu_ps(f);
}

static inline simde__m512 emulated_rsqrt14_ps(simde__m512 x)
{
    float f[16];
    simde_mm512_storeu_ps(f, x);
    for (int i = 0; i < 16; i++)
        f[i] = 1.0f / sqrtf(f[i]);
    return simde_mm512_loadu_ps(f);
}

static inline void emulated_mask_i32scatter_ps(void *base, uint16_t mask, simde__m512i index, simde__m512 v, int scale)
{
    int32_t at[16];
    float f[16];
    simde_mm512_storeu_si512(at, index);
    simde_mm512_storeu_ps(f, v);
    for (int i = 0; i < 16; i++)
        if ((mask >> i) & 1)
            memcpy((char *)base + (ptrdiff_t)at[i] * scale, &f[i], sizeof f[i]);
}

static inline simde__m512 emulated_mask_i32gather_ps(simde__m512 src, uint16_t mask, simde__m512i index,
                                                     const void *base, int scale)
{
    int32_t at[16];
    float f[16];
    simde_mm512_storeu_si512(at, index);
    simde_mm512_storeu_ps(f, src);
    for (int i = 0; i < 16; i++)
        if ((mask >> i) & 1)
            memcpy(&f[i], (const char *)base + (ptrdiff_t)at[i] * scale, sizeof f[i]);
    return simde_mm512_loadu_ps(f);
}

/* 128-bit lanes: the low two from a, the high two from b, each picked by 2 bits of imm */
static inline simde__m512 emulated_shuffle_f32x4(simde__m512 a, simde__m512 b, int imm)
{
    float fa[16], fb[16], r[16];
    simde_mm512_storeu_ps(fa, a);
    simde_mm512_storeu_ps(fb, b);
    for (int lane = 0; lane < 4; lane++)
        memcpy(r + 4 * lane, (lane < 2 ? fa : fb) + 4 * ((imm >> (2 * lane)) & 3), 4 * sizeof(float));
    return simde_mm512_loadu_ps(r);
}

#undef _mm512_maskz_loadu_ps
#undef _mm512_rsqrt14_ps
#undef _mm512_mask_i32scatter_ps
#undef _mm512_mask_i32gather_ps
#undef _mm512_shuffle_f32x4
#define _mm512_maskz_loadu_ps emulated_maskz_loadu_ps
#define _mm512_rsqrt14_ps emulated_rsqrt14_ps
#define _mm512_mask_i32scatter_ps emulated_mask_i32scatter_ps
#define _mm512_mask_i32gather_ps emulated_mask_i32gather_ps
#define _mm512_shuffle_f32x4 emulated_shuffle_f32x4

#endif
