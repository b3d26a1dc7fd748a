/* What the two NetCDF readers (netcdf_read.c: trajectories, nc_field_read.c:
 * gridded vector fields) share: opening a file from memory after the classic
 * header check, a variable's fill values, and errors naming the variable.
 * Internal to render/io/. */
#ifndef LC_IO_NETCDF_UTIL_H
#define LC_IO_NETCDF_UTIL_H

#include <stdarg.h>
#include <stddef.h>

#include "lc_base.h"

/* Opens data (a whole file, borrowed) with nc_open_mem in read-only mode after
 * lc_netcdf_check_classic; file names it in errors. Close with nc_close. */
int lc_nc_open_memory(const void *data, size_t size, const char *file, int *ncid, lc_error *err);

/* A numeric attribute holding exactly one value, as a double: 1 when read,
 * 0 when absent, of another type or of any other length (never writes more
 * than *out). */
int lc_nc_scalar_att(int ncid, int varid, const char *name, double *out);

/* The values of a variable that mean "no value": _FillValue, missing_value and
 * the type's default fill (CF); lc_nc_is_fill also takes every non-finite value. */
typedef struct lc_nc_fill {
    double v[3];
    int n;
} lc_nc_fill;
void lc_nc_read_fill(int ncid, int varid, lc_nc_fill *f);
int lc_nc_is_fill(const lc_nc_fill *f, double x);

/* err = "FILE: variable 'VAR': reason" (or "FILE: reason" when var is NULL);
 * returns code. */
int lc_nc_vfail(lc_error *err, const char *file, int code, const char *var, const char *fmt, va_list ap);

#endif
