/* A SIMD skinning kernel's entry point over its block loop, written once for skin_x86.c
 * (AVX-512) and skin_avx2.c (AVX2): SKIN_KERNEL(TARGET, name), placed after the file's
 * `skin_blocks(const skin_call *c, uint32_t k, bool dqs)`, instantiates that loop for 1, 2, 3,
 * 4 and 8 influences by each method (the count and method compile-time constants: no branch a
 * vertex on them) and defines `TARGET void name(const skin_call *c)`, which picks the instance
 * for the call; other counts run the loop with the count read at run time. */
#ifndef SINEW_SKIN_DISPATCH_H
#define SINEW_SKIN_DISPATCH_H

#define SKIN_BLOCKS_PAIR(TARGET, k)                                                                                    \
    TARGET static void skin_blocks_lbs_##k(const skin_call *c)                                                         \
    {                                                                                                                  \
        skin_blocks(c, k, false);                                                                                      \
    }                                                                                                                  \
    TARGET static void skin_blocks_dqs_##k(const skin_call *c)                                                         \
    {                                                                                                                  \
        skin_blocks(c, k, true);                                                                                       \
    }

#define SKIN_KERNEL(TARGET, name)                                                                                      \
    SKIN_BLOCKS_PAIR(TARGET, 1)                                                                                        \
    SKIN_BLOCKS_PAIR(TARGET, 2)                                                                                        \
    SKIN_BLOCKS_PAIR(TARGET, 3)                                                                                        \
    SKIN_BLOCKS_PAIR(TARGET, 4)                                                                                        \
    SKIN_BLOCKS_PAIR(TARGET, 8)                                                                                        \
    TARGET void name(const skin_call *c)                                                                               \
    {                                                                                                                  \
        static void (*const lbs[9])(const skin_call *) = {[1] = skin_blocks_lbs_1,                                     \
                                                          [2] = skin_blocks_lbs_2,                                     \
                                                          [3] = skin_blocks_lbs_3,                                     \
                                                          [4] = skin_blocks_lbs_4,                                     \
                                                          [8] = skin_blocks_lbs_8};                                    \
        static void (*const dqs[9])(const skin_call *) = {[1] = skin_blocks_dqs_1,                                     \
                                                          [2] = skin_blocks_dqs_2,                                     \
                                                          [3] = skin_blocks_dqs_3,                                     \
                                                          [4] = skin_blocks_dqs_4,                                     \
                                                          [8] = skin_blocks_dqs_8};                                    \
        uint32_t k = c->mesh->influence_count;                                                                         \
        void (*fn)(const skin_call *) = k < 9 ? (c->dqs ? dqs : lbs)[k] : NULL;                                        \
        if (fn)                                                                                                        \
            fn(c);                                                                                                     \
        else                                                                                                           \
            skin_blocks(c, k, c->dqs);                                                                                 \
    }

#endif
