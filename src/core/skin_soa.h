/* The skinning kernels' math in structure-of-arrays registers, written once for every vector
 * width: included by skin_x86.c (AVX-512, 16 lanes) and skin_avx2.c (AVX2 + FMA, 8 lanes),
 * each time after defining
 *   SOA_VEC            the register type (__m512, __m256)
 *   SOA_FN             the attributes of a helper (target, static inline, always_inline)
 *   SOA_NAME(x)        x with the width appended (apply3 -> apply3_16)
 *   SOA_ADD, SOA_MUL, SOA_XOR, SOA_AND (a, b); SOA_FMADD, SOA_FMSUB, SOA_FNMADD (a, b, c);
 *   SOA_SET1(x), SOA_ZERO(), SOA_RSQRT(x) (an estimate of 1 / sqrt(x), refined here),
 *   SOA_KEEP_POSITIVE(x, r) (r where x > 0, else 0).
 * The macros are undefined at the end, so that the next width can define its own.
 *
 * SOA_NAME(skin_math) turns a block's blended joint records (element i of every lane's record
 * in e[i]) and its inputs into skinned positions, normals and tangents: linear blend through
 * the blended matrix (normals through its cofactor, exact), or a dual quaternion after the
 * blended scale/shear (sinew_skin_vertices_scalar() is the reference). */

/* 1 / |q| for a 4-vector (0 for zero): the estimate and one Newton step. */
SOA_FN SOA_VEC SOA_NAME(inverse_length4)(SOA_VEC x, SOA_VEC y, SOA_VEC z, SOA_VEC w)
{
    SOA_VEC len2 = SOA_FMADD(w, w, SOA_FMADD(x, x, SOA_FMADD(y, y, SOA_MUL(z, z))));
    SOA_VEC r = SOA_RSQRT(len2);
    SOA_VEC half_len2 = SOA_MUL(SOA_SET1(0.5f), len2);
    r = SOA_MUL(r, SOA_FNMADD(SOA_MUL(half_len2, r), r, SOA_SET1(1.5f)));
    return SOA_KEEP_POSITIVE(len2, r);
}

SOA_FN SOA_VEC SOA_NAME(sign_of)(SOA_VEC x)
{
    return SOA_AND(x, SOA_SET1(-0.0f));
}

/* A 3x3 matrix in SoA registers, m[column][row]. */
typedef struct SOA_NAME(soa3) {
    SOA_VEC m[3][3];
} SOA_NAME(soa3);

SOA_FN void SOA_NAME(apply3)(const SOA_NAME(soa3) * a, const SOA_VEC v[3], SOA_VEC out[3])
{
#pragma GCC unroll 16
    for (int r = 0; r < 3; r++)
        out[r] = SOA_FMADD(a->m[0][r], v[0], SOA_FMADD(a->m[1][r], v[1], SOA_MUL(a->m[2][r], v[2])));
}

/* Cofactor matrix of a (det * a^-T) and det. */
SOA_FN SOA_VEC SOA_NAME(cofactor3)(const SOA_NAME(soa3) * a, SOA_NAME(soa3) * out)
{
#pragma GCC unroll 16
    for (int c = 0; c < 3; c++)
#pragma GCC unroll 16
        for (int r = 0; r < 3; r++) {
            int c1 = (c + 1) % 3, c2 = (c + 2) % 3, r1 = (r + 1) % 3, r2 = (r + 2) % 3;
            out->m[c][r] = SOA_FMSUB(a->m[c1][r1], a->m[c2][r2], SOA_MUL(a->m[c1][r2], a->m[c2][r1]));
        }
    return SOA_FMADD(a->m[0][0], out->m[0][0], SOA_FMADD(a->m[0][1], out->m[0][1], SOA_MUL(a->m[0][2], out->m[0][2])));
}

/* Normalises v in place, times -1 where `sign` has its sign bit. */
SOA_FN void SOA_NAME(normalize_signed)(SOA_VEC v[3], SOA_VEC sign)
{
    SOA_VEC r = SOA_XOR(SOA_NAME(inverse_length4)(v[0], v[1], v[2], SOA_ZERO()), sign);
#pragma GCC unroll 16
    for (int c = 0; c < 3; c++)
        v[c] = SOA_MUL(v[c], r);
}

/* a x b for SoA vectors. */
SOA_FN void SOA_NAME(cross_soa)(const SOA_VEC a[3], const SOA_VEC b[3], SOA_VEC out[3])
{
    SOA_VEC x = SOA_FMSUB(a[1], b[2], SOA_MUL(a[2], b[1]));
    SOA_VEC y = SOA_FMSUB(a[2], b[0], SOA_MUL(a[0], b[2]));
    SOA_VEC z = SOA_FMSUB(a[0], b[1], SOA_MUL(a[1], b[0]));
    out[0] = x, out[1] = y, out[2] = z;
}

/* v + 2 q.xyz x (q.xyz x v + q.w v), in place. */
SOA_FN void SOA_NAME(rotate_soa)(const SOA_VEC q[4], SOA_VEC v[3])
{
    SOA_VEC t[3], u[3];
    SOA_NAME(cross_soa)(q, v, t);
#pragma GCC unroll 16
    for (int c = 0; c < 3; c++)
        t[c] = SOA_FMADD(q[3], v[c], t[c]);
    SOA_NAME(cross_soa)(q, t, u);
#pragma GCC unroll 16
    for (int c = 0; c < 3; c++)
        v[c] = SOA_FMADD(SOA_SET1(2.0f), u[c], v[c]);
}

/* The skinned vertices of a block: e the blended records (a column-major matrix, or for DQS
 * the normalised-later dual quaternion in e[0 .. 7] and S = xx yy zz xy xz yz in e[8 .. 13]),
 * p the positions; n_in / t_in (NULL: not wanted) the normals and the tangents' xyz with
 * their handedness t_w. Fills out_p, and out_n, out_t and *out_tw where their inputs are given. */
SOA_FN void SOA_NAME(skin_math)(const SOA_VEC e[16], bool dqs, const SOA_VEC p[3], const SOA_VEC *n_in,
                                const SOA_VEC *t_in, SOA_VEC t_w, SOA_VEC out_p[3], SOA_VEC *out_n, SOA_VEC *out_t,
                                SOA_VEC *out_tw)
{
    /* the linear part a and translation t; for DQS also the rotation q applied after a */
    SOA_NAME(soa3) a, cof;
    SOA_VEC t[3], q[4];
    if (!dqs) {
#pragma GCC unroll 16
        for (int col = 0; col < 3; col++)
#pragma GCC unroll 16
            for (int row = 0; row < 3; row++)
                a.m[col][row] = e[col * 4 + row];
#pragma GCC unroll 16
        for (int row = 0; row < 3; row++)
            t[row] = e[12 + row];
    } else {
        /* normalised by the real part's length */
        SOA_VEC inv = SOA_NAME(inverse_length4)(e[0], e[1], e[2], e[3]), d[4];
#pragma GCC unroll 16
        for (int i = 0; i < 4; i++)
            q[i] = SOA_MUL(e[i], inv), d[i] = SOA_MUL(e[4 + i], inv);
        SOA_VEC sxx = e[8], syy = e[9], szz = e[10], sxy = e[11], sxz = e[12], syz = e[13];
        a = (SOA_NAME(soa3)){{{sxx, sxy, sxz}, {sxy, syy, syz}, {sxz, syz, szz}}};
        /* translation 2 (q.w d.xyz - d.w q.xyz + q.xyz x d.xyz) */
        SOA_NAME(cross_soa)(q, d, t);
#pragma GCC unroll 16
        for (int i = 0; i < 3; i++)
            t[i] = SOA_MUL(SOA_SET1(2.0f), SOA_ADD(t[i], SOA_FMSUB(q[3], d[i], SOA_MUL(d[3], q[i]))));
    }
    SOA_NAME(apply3)(&a, p, out_p);
    if (dqs)
        SOA_NAME(rotate_soa)(q, out_p);
#pragma GCC unroll 16
    for (int i = 0; i < 3; i++)
        out_p[i] = SOA_ADD(out_p[i], t[i]);
    SOA_VEC det = SOA_ZERO();
    if (n_in || t_in)
        det = SOA_NAME(cofactor3)(&a, &cof);
    if (n_in) {
        SOA_NAME(apply3)(&cof, n_in, out_n);
        SOA_NAME(normalize_signed)(out_n, SOA_NAME(sign_of)(det));
        if (dqs)
            SOA_NAME(rotate_soa)(q, out_n);
    }
    if (t_in) {
        SOA_NAME(apply3)(&a, t_in, out_t);
        SOA_NAME(normalize_signed)(out_t, SOA_ZERO());
        if (dqs)
            SOA_NAME(rotate_soa)(q, out_t);
        *out_tw = SOA_XOR(t_w, SOA_NAME(sign_of)(det));
    }
}

#undef SOA_VEC
#undef SOA_FN
#undef SOA_NAME
#undef SOA_ADD
#undef SOA_MUL
#undef SOA_XOR
#undef SOA_AND
#undef SOA_FMADD
#undef SOA_FMSUB
#undef SOA_FNMADD
#undef SOA_SET1
#undef SOA_ZERO
#undef SOA_RSQRT
#undef SOA_KEEP_POSITIVE
