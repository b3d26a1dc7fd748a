/* Dataset file formats: PLY (ASCII, binary little/big endian), OBJ (v, f, l
 * with a per-vertex attribute in vt) and VTK legacy POLYDATA, reading and
 * writing; TrackVis .trk fiber tracts, reading. */
#ifndef LC_LOADERS_H
#define LC_LOADERS_H

#include <stddef.h>

#include "scene.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Loaders return an un-finalized scene (caller runs lc_scene_finalize and owns
 * the scene). On error *out is NULL and err names the file, the line or byte
 * offset and the reason, e.g. "a.ply: line 12: vertex count 4000000000 exceeds
 * the file size". `name` is used in messages and as the scene name. */
int lc_load_ply_memory(const void *data, size_t size, const char *name, lc_scene **out, lc_error *err);
int lc_load_obj_memory(const void *data, size_t size, const char *name, lc_scene **out, lc_error *err);
int lc_load_ply(const char *path, lc_scene **out, lc_error *err);
int lc_load_obj(const char *path, lc_scene **out, lc_error *err);
/* VTK legacy (.vtk) POLYDATA, ASCII or BINARY (big endian), classic or 5.1
 * OFFSETS/CONNECTIVITY cells. LINES give polylines, POLYGONS and
 * TRIANGLE_STRIPS triangles, otherwise the POINTS are a point cloud.
 * POINT_DATA SCALARS (one attribute per component), 1-component FIELD arrays
 * and VECTORS (as name_magnitude) become attributes, COLOR_SCALARS rgb;
 * NORMALS, CELL_DATA and METADATA are skipped. Other DATASET types fail with
 * LC_ERR_UNSUPPORTED. */
int lc_load_vtk_memory(const void *data, size_t size, const char *name, lc_scene **out, lc_error *err);
int lc_load_vtk(const char *path, lc_scene **out, lc_error *err);
/* TrackVis (.trk, either byte order): every track a polyline. Coordinates stay
 * as stored, in TrackVis voxel-mm space (voxel index times voxel size, not
 * RAS: vox_to_ras is not applied). Per-point scalars become attributes named
 * from scalar_name (else scalar_K); per-track properties become attributes
 * constant along each line. */
int lc_load_trk_memory(const void *data, size_t size, const char *name, lc_scene **out, lc_error *err);
int lc_load_trk(const char *path, lc_scene **out, lc_error *err);
/* Picks the loader by extension (.ply, .obj, .vtk, .trk); the scene is named
 * after the file stem. Finalizes the scene with default element options. */
int lc_scene_load_file(const char *path, lc_scene **out, lc_error *err);

/* Writers: binary little-endian PLY with every attribute as a float property
 * and rgb as uchar red/green/blue; OBJ with v, f or l, and the default
 * importance attribute in vt. */
int lc_save_ply(const lc_scene *s, const char *path, lc_error *err);
int lc_save_obj(const lc_scene *s, const char *path, lc_error *err);
/* Binary VTK legacy POLYDATA (version 3.0): float points, LINES, POLYGONS or
 * one VERTICES cell, every attribute as SCALARS float, rgb as COLOR_SCALARS. */
int lc_save_vtk(const lc_scene *s, const char *path, lc_error *err);

#ifdef __cplusplus
}
#endif
#endif
