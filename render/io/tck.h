/* MRtrix .tck tractograms: every streamline a polyline, coordinates as stored
 * (scanner RAS+ millimetres). The text header ("mrtrix tracks", key: value
 * lines, END) names the data type (Float32/Float64, LE/BE) and the offset of
 * the data ("file: . OFFSET"); the data are xyz triplets, a NaN triplet ends a
 * streamline and an Inf triplet ends the data. Points with some non-finite
 * coordinate are dropped with a warning; streamlines of fewer than two points
 * too. No attributes (MRtrix keeps per-point scalars in separate .tsf files). */
#ifndef LC_IO_TCK_H
#define LC_IO_TCK_H

#include <stddef.h>

#include "lc_base.h"
#include "scene.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Readers return an un-finalized scene (the caller runs lc_scene_finalize and
 * owns the scene). On error *out is NULL and err names the file, the line or
 * byte offset and the reason. `name` is used in messages and as the scene name. */
int lc_load_tck_memory(const void *data, size_t size, const char *name, lc_scene **out, lc_error *err);
int lc_load_tck(const char *path, lc_scene **out, lc_error *err);
/* Only the whole streamlines of process rank's share of size (lc_scene_read_file_part). */
int lc_load_tck_part(const char *path, int rank, int size, lc_scene **out, lc_error *err);

#ifdef __cplusplus
}
#endif
#endif
