/* TrackVis .trk (either byte order): every track a polyline. Coordinates are
 * mapped from TrackVis voxel-mm space (voxel corner at 0, times voxel size, in
 * voxel_order) to RAS+ mm as nibabel and MRtrix do: vox_to_ras applied to the
 * voxel-centre coordinates (trk_space.h), so a .trk and a .tck of one
 * tractogram coincide. Per-point scalars become attributes named
 * from scalar_name (else scalar_K); per-track properties become attributes
 * constant along each line. */
#ifndef LC_IO_TRK_H
#define LC_IO_TRK_H

#include <stddef.h>

#include "lc_base.h"
#include "scene.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Readers return an un-finalized scene (the caller runs lc_scene_finalize and
 * owns the scene). On error *out is NULL and err names the file, the line or
 * byte offset and the reason. `name` is used in messages and as the scene name. */
int lc_load_trk_memory(const void *data, size_t size, const char *name, lc_scene **out, lc_error *err);
int lc_load_trk(const char *path, lc_scene **out, lc_error *err);
/* Only the whole tracks of process rank's share of size (lc_scene_read_file_part). */
int lc_load_trk_part(const char *path, int rank, int size, lc_scene **out, lc_error *err);

#ifdef __cplusplus
}
#endif
#endif
