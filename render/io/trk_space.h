/* TrackVis voxel-mm to RAS+ millimetres, by nibabel's rules (internal to
 * render/io/; used by trk_read.c). */
#ifndef LC_IO_TRK_SPACE_H
#define LC_IO_TRK_SPACE_H

#include <stddef.h>

#include "lc_base.h"

/* The affine (3 rows of 4, row-major) that takes a point stored in a .trk
 * (voxel-mm: voxel corner at 0, scaled by voxel_size, axes in voxel_order) to
 * RAS+ mm at voxel centres, from the 1000-byte header `hdr` (big: big-endian
 * file): RAS = vox_to_ras · M · (p / voxel_size − ½), where M reorders and
 * flips voxel axes from voxel_order to the order vox_to_ras implies (nibabel's
 * get_affine_trackvis_to_rasmm). A version-1 header or vox_to_ras[3][3] = 0
 * means "not recorded": identity, with a warning, as in nibabel; an empty
 * voxel_order means LPS. Fails (LC_ERR_INVALID, message names the file and
 * header offset) on a non-positive or non-finite voxel size, a voxel_order
 * that is not a permutation of L/R, P/A, I/S, or a singular vox_to_ras. */
int lc_trk_voxmm_to_rasmm(const unsigned char *hdr, int big, const char *file, double affine[12], lc_error *err);

/* Applies affine to n xyz points in place (computed in double). */
void lc_trk_apply_affine(const double affine[12], float *xyz, size_t n);

#endif
