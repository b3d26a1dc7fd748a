/* Vector-field datasets: the VTK legacy STRUCTURED_POINTS / RECTILINEAR_GRID
 * reader (the first POINT_DATA VECTORS array; SCALARS, NORMALS, FIELD arrays,
 * CELL_DATA and METADATA are skipped) and the opener of field sources
 * ("demo:NAME" of render/field, a .vtk file or a NetCDF .nc grid). ASCII or
 * big-endian BINARY; every count is checked against the bytes left before anything is allocated.
 * Threading: reentrant; a loaded field belongs to the caller. */
#ifndef LC_IO_VTK_FIELD_H
#define LC_IO_VTK_FIELD_H

#include <stddef.h>

#include "field.h"
#include "lc_base.h"

#ifdef __cplusplus
extern "C" {
#endif

/* On error *out is NULL and err names the file, the line (ASCII) or byte
 * offset (binary) and the reason. `name` is used in messages and as the
 * field's name. */
int lc_load_vtk_field_memory(const void *data, size_t size, const char *name, lc_field **out, lc_error *err);
int lc_load_vtk_field(const char *path, lc_field **out, lc_error *err);
/* 1 when the .vtk file at path declares DATASET STRUCTURED_POINTS or
 * RECTILINEAR_GRID (looks at its first 4 KiB only). */
int lc_vtk_file_is_field(const char *path);

/* 1 when spec names a field: "demo:NAME" of a demo field, a .vtk file
 * whose dataset is a grid, or a .nc file holding gridded u, v (nc_field.h). */
int lc_field_is_source(const char *spec);
/* Opens a field source (lc_field_is_source); file fields are named after the
 * file stem. */
int lc_field_open(const char *spec, lc_field **out, lc_error *err);

#ifdef __cplusplus
}
#endif
#endif
