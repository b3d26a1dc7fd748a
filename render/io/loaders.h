/* Dataset files: the reader chosen by extension, and every format's own API
 * (ply.h, obj.h, vtk.h, trk.h, tck.h, binlines.h,
 * csv.h, trx.h, nc_trajectories.h, dump.h) for callers that name a format.
 * Threading: reentrant; a loaded scene belongs to the caller. */
#ifndef LC_LOADERS_H
#define LC_LOADERS_H

#include "binlines.h"
#include "csv.h"
#include "dump.h"
#include "lc_base.h"
#include "nc_trajectories.h"
#include "obj.h"
#include "ply.h"
#include "scene.h"
#include "tck.h"
#include "trk.h"
#include "trx.h"
#include "vtk.h"

#ifdef __cplusplus
extern "C" {
#endif

/* The extensions lc_scene_load_file knows, for messages and help texts. */
#define LC_DATASET_EXTENSIONS                                                                                          \
    ".ply, .obj, .vtk, .trk, .tck, .trx, .binlines, .nc, .csv, .tsv, .xyz, .dump or .lammpstrj"

/* 1 when lc_scene_load_file has a reader for the path's extension. */
int lc_scene_is_dataset_file(const char *path);

/* The reader of the extension alone: an un-finalized scene named after the
 * file stem (for callers that finalize with their own options, or time the
 * reader). Errors as lc_scene_load_file. */
int lc_scene_read_file(const char *path, lc_scene **out, lc_error *err);

/* The extensions lc_scene_read_file_part reads in parts. */
#define LC_PART_EXTENSIONS                                                                                             \
    ".trk, .tck, .trx, .binlines, .nc, polyline .vtk, point-cloud .ply, .csv, .tsv, .xyz, .dump and .lammpstrj"

/* 1 when path can be read in parts (a .ply file only when it holds points alone). */
int lc_scene_can_read_part(const char *path);
/* Reads only process rank's share (of size processes) of a line file or a
 * point cloud: the whole lines or contiguous points that lc_scene_shard gives
 * rank from the whole scene, un-finalized
 * (finish with the collective lc_scene_finalize_part, scene_part.h), so no
 * process holds more than its share. LC_ERR_UNSUPPORTED for other formats. */
int lc_scene_read_file_part(const char *path, int rank, int size, lc_scene **out, lc_error *err);

/* The --max-memory left for the next load (0 = none): readers refuse a file
 * whose declared counts need more before allocating (io_util.h). Call from
 * the loading thread before lc_scene_load_file; process-wide. */
void lc_scene_set_load_limit(uint64_t bytes);

/* Picks the reader by extension (LC_DATASET_EXTENSIONS); the scene is named
 * after the file stem. Finalizes the scene with default element options. On
 * error *out is NULL and err names the file and the reason. */
int lc_scene_load_file(const char *path, lc_scene **out, lc_error *err);

#ifdef __cplusplus
}
#endif
#endif
