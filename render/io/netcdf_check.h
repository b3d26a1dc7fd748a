/* Structural check of NetCDF classic headers before libnetcdf parses them
 * (internal to render/io/; used by netcdf_read.c). */
#ifndef LC_IO_NETCDF_CHECK_H
#define LC_IO_NETCDF_CHECK_H

#include <stddef.h>

#include "lc_base.h"

/* 0 when data is not a classic file (left to libnetcdf) or its header is well
 * formed: bounded counts, printable unique names, known types, dimension ids
 * in range, data offsets inside the file. Otherwise LC_ERR_INVALID with the
 * byte offset in err. */
int lc_netcdf_check_classic(const void *data, size_t size, const char *file, lc_error *err);

#endif
