/* VTK legacy POLYDATA.
 * Reader: ASCII or BINARY (big endian), classic or 5.1 OFFSETS/CONNECTIVITY
 * cells. LINES give polylines, POLYGONS and TRIANGLE_STRIPS triangles,
 * otherwise the POINTS are a point cloud. POINT_DATA SCALARS (one attribute per
 * component), 1-component FIELD arrays and VECTORS (as name_magnitude) become
 * attributes, COLOR_SCALARS rgb; NORMALS, CELL_DATA and METADATA are skipped.
 * Other DATASET types fail with LC_ERR_UNSUPPORTED.
 * Writer: binary version 3.0, float points, LINES, POLYGONS or one VERTICES
 * cell, every attribute as SCALARS float, rgb as COLOR_SCALARS. */
#ifndef LC_IO_VTK_H
#define LC_IO_VTK_H

#include <stddef.h>

#include "lc_base.h"
#include "scene.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Readers return an un-finalized scene (the caller runs lc_scene_finalize and
 * owns the scene). On error *out is NULL and err names the file, the line or
 * byte offset and the reason. `name` is used in messages and as the scene name. */
int lc_load_vtk_memory(const void *data, size_t size, const char *name, lc_scene **out, lc_error *err);
int lc_load_vtk(const char *path, lc_scene **out, lc_error *err);
/* Only the whole polylines of process rank's share of size
 * (lc_scene_read_file_part): the file is parsed whole (points, point data and
 * connectivity, the raw arrays), then only the share's lines are kept, before
 * any derived data. LC_ERR_UNSUPPORTED for a file without LINES. */
int lc_load_vtk_part(const char *path, int rank, int size, lc_scene **out, lc_error *err);
/* 1 when the file at path has a LINES section (a line starting "LINES "). */
int lc_vtk_file_has_lines(const char *path);
int lc_save_vtk(const lc_scene *s, const char *path, lc_error *err);

#ifdef __cplusplus
}
#endif
#endif
