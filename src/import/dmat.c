/* Double-precision 4x4 matrices for the readers that evaluate a file's transforms exactly
 * (fbx.c, collada.c, iqm.c) before they become the runtime's floats. */
#include <math.h>

#include "internal.h"
#include "alloc.h" /* last: the readers' allocations are the import's (alloc.h) */

dmat dmat_identity(void)
{
    dmat r = {{0}};
    r.m[0] = r.m[5] = r.m[10] = r.m[15] = 1.0;
    return r;
}

dmat dmat_mul(const dmat *a, const dmat *b)
{
    dmat r;
    for (int c = 0; c < 4; c++)
        for (int row = 0; row < 4; row++) {
            double s = 0;
            for (int k = 0; k < 4; k++)
                s += a->m[k * 4 + row] * b->m[c * 4 + k];
            r.m[c * 4 + row] = s;
        }
    return r;
}

dmat dmat_from_rows(const double v[16])
{
    dmat r;
    for (int row = 0; row < 4; row++)
        for (int col = 0; col < 4; col++)
            r.m[col * 4 + row] = v[row * 4 + col];
    return r;
}

void dmat_to_float(const dmat *a, sinew_mat4 *out)
{
    for (int i = 0; i < 16; i++)
        out->m[i] = (float)a->m[i];
}

void dmat_quat(const dmat *a, double q[4])
{
    const double *m = a->m;
    double m00 = m[0], m11 = m[5], m22 = m[10], trace = m00 + m11 + m22;
    if (trace > 0) {
        double s = sqrt(trace + 1.0) * 2;
        q[3] = 0.25 * s;
        q[0] = (m[6] - m[9]) / s;
        q[1] = (m[8] - m[2]) / s;
        q[2] = (m[1] - m[4]) / s;
    } else if (m00 > m11 && m00 > m22) {
        double s = sqrt(1.0 + m00 - m11 - m22) * 2;
        q[3] = (m[6] - m[9]) / s;
        q[0] = 0.25 * s;
        q[1] = (m[4] + m[1]) / s;
        q[2] = (m[8] + m[2]) / s;
    } else if (m11 > m22) {
        double s = sqrt(1.0 + m11 - m00 - m22) * 2;
        q[3] = (m[8] - m[2]) / s;
        q[0] = (m[4] + m[1]) / s;
        q[1] = 0.25 * s;
        q[2] = (m[9] + m[6]) / s;
    } else {
        double s = sqrt(1.0 + m22 - m00 - m11) * 2;
        q[3] = (m[1] - m[4]) / s;
        q[0] = (m[8] + m[2]) / s;
        q[1] = (m[9] + m[6]) / s;
        q[2] = 0.25 * s;
    }
    double n = sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
    for (int i = 0; i < 4; i++) /* a degenerate matrix (no rotation to speak of): identity */
        q[i] = n > 0 ? q[i] / n : (i == 3);
}

/* Inverse of an affine matrix (last row 0 0 0 1); identity when singular. */
dmat dmat_inverse_affine(const dmat *a)
{
    const double *m = a->m;
    double c00 = m[5] * m[10] - m[9] * m[6], c01 = m[9] * m[2] - m[1] * m[10], c02 = m[1] * m[6] - m[5] * m[2];
    double det = m[0] * c00 + m[4] * c01 + m[8] * c02;
    if (det == 0.0 || !isfinite(det))
        return dmat_identity();
    double inv = 1.0 / det;
    dmat r = dmat_identity();
    r.m[0] = c00 * inv;
    r.m[1] = c01 * inv;
    r.m[2] = c02 * inv;
    r.m[4] = (m[8] * m[6] - m[4] * m[10]) * inv;
    r.m[5] = (m[0] * m[10] - m[8] * m[2]) * inv;
    r.m[6] = (m[4] * m[2] - m[0] * m[6]) * inv;
    r.m[8] = (m[4] * m[9] - m[8] * m[5]) * inv;
    r.m[9] = (m[8] * m[1] - m[0] * m[9]) * inv;
    r.m[10] = (m[0] * m[5] - m[4] * m[1]) * inv;
    for (int row = 0; row < 3; row++)
        r.m[12 + row] = -(r.m[row] * m[12] + r.m[4 + row] * m[13] + r.m[8 + row] * m[14]);
    return r;
}

dmat dmat_from_trs(const double t[3], const double q_in[4], const double s[3])
{
    double n = sqrt(q_in[0] * q_in[0] + q_in[1] * q_in[1] + q_in[2] * q_in[2] + q_in[3] * q_in[3]);
    double q[4] = {0, 0, 0, 1};
    if (n > 0.0 && isfinite(n))
        for (int k = 0; k < 4; k++)
            q[k] = q_in[k] / n;
    double x = q[0], y = q[1], z = q[2], w = q[3];
    dmat r = dmat_identity();
    double cols[3][3] = {{1 - 2 * (y * y + z * z), 2 * (x * y + w * z), 2 * (x * z - w * y)},
                         {2 * (x * y - w * z), 1 - 2 * (x * x + z * z), 2 * (y * z + w * x)},
                         {2 * (x * z + w * y), 2 * (y * z - w * x), 1 - 2 * (x * x + y * y)}};
    for (int c = 0; c < 3; c++) {
        for (int row = 0; row < 3; row++)
            r.m[c * 4 + row] = cols[c][row] * s[c];
        r.m[12 + c] = t[c];
    }
    return r;
}
