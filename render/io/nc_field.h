/* NetCDF gridded vector fields: u, v, w found by CF standard_name or by name,
 * over (z, y, x) or (time, z, y, x) (time index 0) or (y, x) (one level, w =
 * 0), on the grid their coordinate variables give (0..n-1 without them).
 * Threading: reentrant; a loaded field belongs to the caller. */
#ifndef LC_IO_NC_FIELD_H
#define LC_IO_NC_FIELD_H

#include <stddef.h>

#include "field.h"
#include "lc_base.h"

#ifdef __cplusplus
extern "C" {
#endif

/* On error *out is NULL and err names the file and the variable. `name` is
 * used in messages and (its stem) as the field's name. The field's
 * vectors_name says which variables were read, the time index taken and how
 * many fill values became 0. */
int lc_load_nc_field_memory(const void *data, size_t size, const char *name, lc_field **out, lc_error *err);
int lc_load_nc_field(const char *path, lc_field **out, lc_error *err);
/* 1 when the NetCDF file at path holds an x and a y velocity variable of 2 to
 * 4 dimensions (by standard_name or the names u/U, v/V). */
int lc_nc_file_is_field(const char *path);

#ifdef __cplusplus
}
#endif
#endif
