/* Double-precision 4x4 matrices for the readers that evaluate a file's transforms exactly
 * (fbx.c, collada.c) before they become the runtime's floats. */
#include <math.h>

#include "internal.h"

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
