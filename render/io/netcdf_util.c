/* Pieces the NetCDF readers share (netcdf_util.h). */
#include "netcdf_util.h"

#include <math.h>
#include <netcdf.h>
#include <netcdf_mem.h>
#include <stdio.h>

#include "netcdf_check.h"

int lc_nc_open_memory(const void *data, size_t size, const char *file, int *ncid, lc_error *err)
{
    if (!data || size == 0)
        return lc_err(err, LC_ERR_INVALID, "%.80s: empty file", file);
    int rc = lc_netcdf_check_classic(data, size, file, err);
    if (rc)
        return rc;
    /* nc_open_mem does not write to the buffer in NC_NOWRITE mode. */
    rc = nc_open_mem(file, NC_NOWRITE, size, (void *)data, ncid);
    if (rc != NC_NOERR)
        return lc_err(err, LC_ERR_INVALID, "%.80s: not a readable NetCDF file: %s", file, nc_strerror(rc));
    return 0;
}

int lc_nc_scalar_att(int ncid, int varid, const char *name, double *out)
{
    nc_type type = NC_NAT;
    size_t len = 0;
    /* nc_get_att_double writes every value the file declares: read only a
     * numeric attribute of exactly one value into the one double. */
    if (nc_inq_att(ncid, varid, name, &type, &len) != NC_NOERR || len != 1)
        return 0;
    switch (type) {
    case NC_BYTE:
    case NC_UBYTE:
    case NC_SHORT:
    case NC_USHORT:
    case NC_INT:
    case NC_UINT:
    case NC_INT64:
    case NC_UINT64:
    case NC_FLOAT:
    case NC_DOUBLE: break;
    default: return 0;
    }
    return nc_get_att_double(ncid, varid, name, out) == NC_NOERR;
}

void lc_nc_read_fill(int ncid, int varid, lc_nc_fill *f)
{
    nc_type type = NC_NAT;
    double x;
    f->n = 0;
    if (lc_nc_scalar_att(ncid, varid, "_FillValue", &x))
        f->v[f->n++] = x;
    if (lc_nc_scalar_att(ncid, varid, "missing_value", &x))
        f->v[f->n++] = x;
    nc_inq_vartype(ncid, varid, &type);
    switch (type) {
    case NC_FLOAT: f->v[f->n++] = (double)NC_FILL_FLOAT; break;
    case NC_DOUBLE: f->v[f->n++] = NC_FILL_DOUBLE; break;
    case NC_SHORT: f->v[f->n++] = NC_FILL_SHORT; break;
    case NC_INT: f->v[f->n++] = NC_FILL_INT; break;
    default: break;
    }
}

int lc_nc_is_fill(const lc_nc_fill *f, double x)
{
    if (!isfinite(x))
        return 1;
    for (int i = 0; i < f->n; i++)
        if (x == f->v[i] || (f->v[i] != 0 && fabs(x - f->v[i]) <= 1e-6 * fabs(f->v[i])))
            return 1;
    return 0;
}

int lc_nc_vfail(lc_error *err, const char *file, int code, const char *var, const char *fmt, va_list ap)
{
    char reason[LC_ERROR_MSG_LEN];
    vsnprintf(reason, sizeof reason, fmt, ap);
    if (var)
        return lc_err(err, code, "%.80s: variable '%.40s': %s", file, var, reason);
    return lc_err(err, code, "%.80s: %s", file, reason);
}
