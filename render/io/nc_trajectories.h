/* NetCDF trajectories (.nc, read with libnetcdf): variables lon, lat and
 * pressure over the dimensions (trajectory, time) or, in Met.3D's layout,
 * (ensemble, trajectory, time); every (ensemble member, trajectory) is a
 * polyline over time. Positions: x = longitude and y = latitude in degrees as
 * stored, z = 10 · ln(1013.25 hPa / p), a log-pressure height (about 0 at sea
 * level, +10 per e-fold of pressure, i.e. per ~7 km of scale height; 250 hPa is
 * z ≈ 14). Pressure is taken in hPa, or in Pa when its units attribute says
 * "Pa". Every other variable over the same dimensions becomes an attribute of
 * its name. A missing position (_FillValue, missing_value, NetCDF's default
 * fill or NaN) ends its trajectory; a missing attribute value is NaN.
 * Trajectories shorter than two points are dropped with a warning. When lon
 * and lat are in degrees (units "degree..." or none) the scene is marked as
 * trajectories (lc_trajectory_info), with the time step of a 1-D "time"
 * variable, and finalize derives pressure, its change, speed, turning and
 * ascent angles (scene_derive.h). */
#ifndef LC_IO_NC_TRAJECTORIES_H
#define LC_IO_NC_TRAJECTORIES_H

#include <stddef.h>

#include "lc_base.h"
#include "scene.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Returns an un-finalized scene (the caller runs lc_scene_finalize and owns
 * it). On error *out is NULL and err names the file, the variable and the
 * reason. Both open the bytes with libnetcdf's nc_open_mem (the file form maps
 * the file first). */
int lc_load_netcdf(const char *path, lc_scene **out, lc_error *err);
int lc_load_netcdf_memory(const void *data, size_t size, const char *name, lc_scene **out, lc_error *err);
/* Only the trajectories of process rank's share of size (lc_scene_read_file_part):
 * the first pass reads every trajectory's valid length, the second only the
 * share's rows. */
int lc_load_netcdf_part(const char *path, int rank, int size, lc_scene **out, lc_error *err);

#ifdef __cplusplus
}
#endif
#endif
