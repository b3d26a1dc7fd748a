/* TrackVis coordinate space: the voxel-mm to RAS+ mm affine of a .trk header,
 * following nibabel (streamlines/trk.py get_affine_trackvis_to_rasmm and the
 * orientation helpers it calls). */
#include "trk_space.h"

#include <ctype.h>
#include <math.h>
#include <string.h>

#include "io_util.h"

#define OFF_DIM 6
#define OFF_VOXEL_SIZE 12
#define OFF_VOX_TO_RAS 440
#define OFF_VOXEL_ORDER 948
#define OFF_VERSION 992

/* Row-major 3x3 inverse; returns 0 when singular. */
static int invert3(const double m[9], double inv[9])
{
    double c0 = m[4] * m[8] - m[5] * m[7], c1 = m[5] * m[6] - m[3] * m[8], c2 = m[3] * m[7] - m[4] * m[6];
    double det = m[0] * c0 + m[1] * c1 + m[2] * c2;
    if (!isfinite(det) || fabs(det) < 1e-12)
        return 0;
    inv[0] = c0 / det, inv[3] = c1 / det, inv[6] = c2 / det;
    inv[1] = (m[2] * m[7] - m[1] * m[8]) / det;
    inv[4] = (m[0] * m[8] - m[2] * m[6]) / det;
    inv[7] = (m[1] * m[6] - m[0] * m[7]) / det;
    inv[2] = (m[1] * m[5] - m[2] * m[4]) / det;
    inv[5] = (m[2] * m[3] - m[0] * m[5]) / det;
    inv[8] = (m[0] * m[4] - m[1] * m[3]) / det;
    return 1;
}

/* nibabel io_orientation: for each voxel axis, the RAS axis it runs along
 * (out[i]) and its sign (flip[i]), from the rotation closest to the affine's
 * column-normalized 3x3 part (polar decomposition by Newton's iteration
 * X <- (X + X^-T) / 2, the same R as nibabel's SVD). Returns 0 if singular. */
static int affine_axes(const double a[16], int out[3], int flip[3])
{
    double x[9];
    for (int c = 0; c < 3; c++) {
        double norm = sqrt(a[c] * a[c] + a[4 + c] * a[4 + c] + a[8 + c] * a[8 + c]);
        for (int r = 0; r < 3; r++)
            x[3 * r + c] = a[4 * r + c] / (norm > 0 ? norm : 1);
    }
    for (int it = 0; it < 100; it++) {
        double inv[9], delta = 0;
        if (!invert3(x, inv))
            return 0;
        for (int r = 0; r < 3; r++)
            for (int c = 0; c < 3; c++) {
                double next = 0.5 * (x[3 * r + c] + inv[3 * c + r]);
                delta = fmax(delta, fabs(next - x[3 * r + c]));
                x[3 * r + c] = next;
            }
        if (delta < 1e-15)
            break;
    }
    for (int in = 0; in < 3; in++) { /* greedy, removing used RAS axes, as nibabel */
        int best = -1;
        for (int r = 0; r < 3; r++)
            if (fabs(x[3 * r + in]) > 1e-8 && (best < 0 || fabs(x[3 * r + in]) > fabs(x[3 * best + in])))
                best = r;
        if (best < 0)
            return 0;
        out[in] = best;
        flip[in] = x[3 * best + in] < 0 ? -1 : 1;
        for (int c = 0; c < 3; c++)
            x[3 * best + c] = 0;
    }
    return 1;
}

int lc_trk_voxmm_to_rasmm(const unsigned char *hdr, int big, const char *file, double affine[12], lc_error *err)
{
    double vs[3], v2r[16];
    int dim[3];
    for (int i = 0; i < 3; i++) {
        vs[i] = lc_io_get_f32(hdr + OFF_VOXEL_SIZE + 4 * i, big);
        if (!isfinite(vs[i]) || vs[i] <= 0)
            return lc_err(err, LC_ERR_INVALID, "%.80s: byte offset %d: voxel size %g is not a positive number", file,
                          OFF_VOXEL_SIZE + 4 * i, vs[i]);
        const unsigned char *d = hdr + OFF_DIM + 2 * i;
        dim[i] = (int16_t)(big ? d[0] << 8 | d[1] : d[1] << 8 | d[0]);
    }
    for (int i = 0; i < 16; i++)
        v2r[i] = lc_io_get_f32(hdr + OFF_VOX_TO_RAS + 4 * i, big);
    int version = (int)lc_io_get_u32(hdr + OFF_VERSION, big);
    if (version == 1 || v2r[15] == 0) {
        LC_WARN(LC_IO_LOG, "%s: vox_to_ras is not recorded; assuming the identity (as nibabel)", file);
        memset(v2r, 0, sizeof v2r);
        v2r[0] = v2r[5] = v2r[10] = v2r[15] = 1;
    }
    for (int i = 0; i < 16; i++)
        if (!isfinite(v2r[i]))
            return lc_err(err, LC_ERR_INVALID, "%.80s: byte offset %d: vox_to_ras holds a non-finite value", file,
                          OFF_VOX_TO_RAS + 4 * i);
    int aff_out[3], aff_flip[3];
    if (!affine_axes(v2r, aff_out, aff_flip))
        return lc_err(err, LC_ERR_INVALID, "%.80s: byte offset %d: vox_to_ras is singular (no axis directions)", file,
                      OFF_VOX_TO_RAS);

    /* voxel_order, e.g. "LPS": the RAS axis and sign of each voxel axis. */
    char order[4] = {0};
    memcpy(order, hdr + OFF_VOXEL_ORDER, 3);
    if (!order[0]) {
        LC_WARN(LC_IO_LOG, "%s: voxel_order is empty; assuming LPS (TrackVis' default, as nibabel)", file);
        memcpy(order, "LPS", 3);
    }
    static const char *const labels = "LRPAIS";
    int hdr_out[3], hdr_flip[3], seen = 0;
    for (int i = 0; i < 3; i++) {
        const char *at = order[i] ? strchr(labels, toupper((unsigned char)order[i])) : NULL;
        if (!at || seen & (1 << ((at - labels) / 2)))
            return lc_err(err, LC_ERR_INVALID,
                          "%.80s: byte offset %d: voxel_order '%.3s' is not a permutation of L/R, P/A, I/S", file,
                          OFF_VOXEL_ORDER, order);
        hdr_out[i] = (int)(at - labels) / 2;
        hdr_flip[i] = (at - labels) % 2 ? 1 : -1;
        seen |= 1 << hdr_out[i];
    }
    /* nibabel ornt_transform(header, affine) then inv_ornt_aff(·, dim): voxel
     * axis i of the file becomes axis to[i] of vox_to_ras, mirrored when the
     * signs differ (x -> dim - 1 - x). */
    int to[3], sign[3];
    for (int e = 0; e < 3; e++)
        for (int i = 0; i < 3; i++)
            if (hdr_out[i] == aff_out[e]) {
                to[i] = e;
                sign[i] = hdr_flip[i] == aff_flip[e] ? 1 : -1;
            }
    /* u = p / vs - 1/2 (voxel corner to centre), then as inv_ornt_aff:
     * w_i = sign_i * u_{to[i]} + (sign_i < 0 ? dim_i - 1 : 0). */
    double m[12] = {0}; /* w = m · (p, 1) */
    for (int i = 0; i < 3; i++) {
        int j = to[i];
        m[4 * i + j] = sign[i] / vs[j];
        m[4 * i + 3] = sign[i] * -0.5 + (sign[i] < 0 ? dim[i] - 1 : 0);
    }
    for (int r = 0; r < 3; r++)
        for (int c = 0; c < 4; c++) {
            double sum = c == 3 ? v2r[4 * r + 3] : 0;
            for (int k = 0; k < 3; k++)
                sum += v2r[4 * r + k] * m[4 * k + c];
            affine[4 * r + c] = sum;
        }
    return 0;
}

void lc_trk_apply_affine(const double a[12], float *xyz, size_t n)
{
    for (size_t i = 0; i < n; i++, xyz += 3) {
        double x = xyz[0], y = xyz[1], z = xyz[2];
        for (int r = 0; r < 3; r++)
            xyz[r] = (float)(a[4 * r] * x + a[4 * r + 1] * y + a[4 * r + 2] * z + a[4 * r + 3]);
    }
}
