/* NetCDF gridded vector fields (libnetcdf): u, v, w by CF standard_name or
 * name on a rectilinear grid from the coordinate variables (nc_field.h). */
#include <math.h>
#include <netcdf.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "io_util.h"
#include "nc_field.h"
#include "netcdf_util.h"

typedef struct comp {
    int id; /* -1: absent (w only: 0 velocity) */
    char name[NC_MAX_NAME + 1];
    lc_nc_fill fill;
    double scale, offset; /* scale_factor, add_offset of packed data */
} comp;

typedef struct ncf_load {
    int ncid;
    const char *file;
    size_t file_bytes;
    lc_error *err;
    comp c[3];
    int ndims;           /* of u: 2, 3 or 4 */
    int has_time;        /* the leading dimension is time: index 0 is read */
    size_t T;            /* time steps (1 without a time dimension) */
    int dimids[4];       /* of u */
    size_t n[3];         /* nodes per axis in the file: x, y, z (z = 1 for one level) */
    int flip[3];         /* the axis' coordinates decrease: read it backwards */
    unsigned long fills; /* values that became 0 */
} ncf_load;

static int fail(ncf_load *L, int code, const char *var, const char *fmt, ...) __attribute__((format(printf, 4, 5)));
static int fail(ncf_load *L, int code, const char *var, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    int rc = lc_nc_vfail(L->err, L->file, code, var, fmt, ap);
    va_end(ap);
    return rc;
}

/* CF standard names per component; a name ending in "x_velocity" etc. also counts. */
static const char *const std_names[3][3] = {{"eastward_wind", "eastward_sea_water_velocity", "x_velocity"},
                                            {"northward_wind", "northward_sea_water_velocity", "y_velocity"},
                                            {"upward_air_velocity", "upward_sea_water_velocity", "z_velocity"}};

static int is_std_name(const char *s, int axis)
{
    size_t n = strlen(s), k = strlen(std_names[axis][2]);
    return strcmp(s, std_names[axis][0]) == 0 || strcmp(s, std_names[axis][1]) == 0 ||
           (n >= k && strcmp(s + n - k, std_names[axis][2]) == 0);
}

/* The variable of a component: its standard_name first, then the names u/U, v/V, w/W. -1 when none. */
static int find_component(int ncid, int axis)
{
    int nvars;
    if (nc_inq_nvars(ncid, &nvars) != NC_NOERR)
        return -1;
    for (int id = 0; id < nvars; id++) {
        char sn[256];
        size_t len;
        if (nc_inq_attlen(ncid, id, "standard_name", &len) == NC_NOERR && len < sizeof sn &&
            nc_get_att_text(ncid, id, "standard_name", sn) == NC_NOERR) {
            sn[len] = '\0';
            if (is_std_name(sn, axis))
                return id;
        }
    }
    char lower[2] = {"uvw"[axis], 0}, upper[2] = {"UVW"[axis], 0};
    int id;
    if (nc_inq_varid(ncid, lower, &id) == NC_NOERR || nc_inq_varid(ncid, upper, &id) == NC_NOERR)
        return id;
    return -1;
}

static void read_packing(ncf_load *L, comp *c)
{
    double x;
    c->scale = 1, c->offset = 0;
    lc_nc_read_fill(L->ncid, c->id, &c->fill);
    if (lc_nc_scalar_att(L->ncid, c->id, "scale_factor", &x) && isfinite(x))
        c->scale = x;
    if (lc_nc_scalar_att(L->ncid, c->id, "add_offset", &x) && isfinite(x))
        c->offset = x;
}

/* A 3-D variable is (time, y, x) when its first dimension is the record
 * dimension or is named time..., else (z, y, x). */
static int leading_is_time(int ncid, int dimid)
{
    int unlim = -1;
    char name[NC_MAX_NAME + 1];
    nc_inq_unlimdim(ncid, &unlim);
    return dimid == unlim || (nc_inq_dimname(ncid, dimid, name) == NC_NOERR && strncasecmp(name, "time", 4) == 0);
}

static void shape_text(int ncid, int id, char *out, size_t size)
{
    int nd = 0, dims[NC_MAX_VAR_DIMS];
    size_t used = 0;
    out[0] = '\0';
    if (nc_inq_varndims(ncid, id, &nd) != NC_NOERR || nd > NC_MAX_VAR_DIMS || nc_inq_vardimid(ncid, id, dims))
        return;
    for (int d = 0; d < nd && used < size; d++) {
        size_t len = 0;
        nc_inq_dimlen(ncid, dims[d], &len);
        used += (size_t)snprintf(out + used, size - used, "%s%zu", d ? " x " : "", len);
    }
}

/* u, v (required) and w (optional) with equal shapes of 2 to 4 dimensions. */
static int find_variables(ncf_load *L)
{
    static const char *const what[3] = {"x (u, U or standard_name eastward_wind / sea_water_x_velocity / *x_velocity)",
                                        "y (v, V or standard_name northward_wind / sea_water_y_velocity / *y_velocity)",
                                        "z"};
    for (int a = 0; a < 3; a++) {
        comp *c = &L->c[a];
        c->id = find_component(L->ncid, a);
        if (c->id < 0) {
            if (a < 2)
                return fail(L, LC_ERR_INVALID, NULL, "no variable for the %s velocity component", what[a]);
            continue;
        }
        nc_inq_varname(L->ncid, c->id, c->name);
        int nd;
        nc_type type;
        if (nc_inq_varndims(L->ncid, c->id, &nd) != NC_NOERR || nc_inq_vartype(L->ncid, c->id, &type) != NC_NOERR)
            return fail(L, LC_ERR_INVALID, c->name, "cannot be inquired");
        if (type == NC_CHAR || type == NC_STRING || type > NC_STRING)
            return fail(L, LC_ERR_INVALID, c->name, "is not numeric");
        if (a == 0) {
            if (nd < 2 || nd > 4)
                return fail(L, LC_ERR_INVALID, c->name,
                            "has %d dimensions; a field is (y, x), (z, y, x) or (time, z, y, x)", nd);
            L->ndims = nd;
            nc_inq_vardimid(L->ncid, c->id, L->dimids);
        } else {
            int dims[NC_MAX_VAR_DIMS];
            int same = nd == L->ndims && nc_inq_vardimid(L->ncid, c->id, dims) == NC_NOERR;
            for (int d = 0; same && d < nd; d++) {
                size_t l0 = 0, l1 = 0;
                nc_inq_dimlen(L->ncid, L->dimids[d], &l0);
                nc_inq_dimlen(L->ncid, dims[d], &l1);
                same = l0 == l1;
            }
            if (!same) {
                char s0[96], s1[96];
                shape_text(L->ncid, L->c[0].id, s0, sizeof s0);
                shape_text(L->ncid, c->id, s1, sizeof s1);
                return fail(L, LC_ERR_INVALID, c->name, "shape %s differs from '%s' (%s)", s1, L->c[0].name, s0);
            }
        }
        read_packing(L, c);
    }
    return 0;
}

/* The spatial dimensions of u: x and y last, z before them when there is one. */
static int read_shape(ncf_load *L)
{
    int nd = L->ndims;
    L->has_time = nd == 4 || (nd == 3 && leading_is_time(L->ncid, L->dimids[0]));
    L->T = 1;
    if (L->has_time)
        nc_inq_dimlen(L->ncid, L->dimids[0], &L->T);
    int spatial = nd - L->has_time;
    for (int a = 0; a < 3; a++) {
        L->n[a] = 1;
        if (a < spatial)
            nc_inq_dimlen(L->ncid, L->dimids[nd - 1 - a], &L->n[a]);
    }
    for (int a = 0; a < 2; a++)
        if (L->n[a] < 2)
            return fail(L, LC_ERR_INVALID, L->c[0].name, "has %zu node(s) along %c; a field needs at least 2", L->n[a],
                        "xy"[a]);
    size_t nz = L->n[2] < 2 ? 2 : L->n[2];
    if (L->n[0] > LC_FIELD_MAX_NODES || L->n[1] > LC_FIELD_MAX_NODES || nz > LC_FIELD_MAX_NODES ||
        (uint64_t)L->n[0] * L->n[1] > LC_FIELD_MAX_NODES || (uint64_t)L->n[0] * L->n[1] * nz > LC_FIELD_MAX_NODES)
        return fail(L, LC_ERR_LIMIT, L->c[0].name, "grid %zu x %zu x %zu exceeds the limit of %llu nodes", L->n[0],
                    L->n[1], nz, (unsigned long long)LC_FIELD_MAX_NODES);
    if (L->T == 0)
        return fail(L, LC_ERR_INVALID, L->c[0].name, "its time dimension is empty");
    return 0;
}

/* Axis a's node coordinates from the dimension's coordinate variable (a 1-D
 * variable of the dimension's name), else 0..n-1. Decreasing axes are
 * reversed (flip); anything else not strictly monotone is an error. */
static int read_axis(ncf_load *L, int a, double **out)
{
    size_t n = L->n[a], nn = n < 2 ? 2 : n;
    double *c = malloc(nn * sizeof *c);
    *out = c;
    if (!c)
        return fail(L, LC_ERR_NOMEM, NULL, "out of memory for the grid");
    for (size_t i = 0; i < n; i++)
        c[i] = (double)i;
    int spatial = L->ndims - L->has_time;
    if (a < spatial) {
        int dim = L->dimids[L->ndims - 1 - a], id, nd, vd;
        char name[NC_MAX_NAME + 1];
        if (nc_inq_dimname(L->ncid, dim, name) == NC_NOERR && nc_inq_varid(L->ncid, name, &id) == NC_NOERR &&
            nc_inq_varndims(L->ncid, id, &nd) == NC_NOERR && nd == 1 && nc_inq_vardimid(L->ncid, id, &vd) == NC_NOERR &&
            vd == dim) {
            if (nc_get_var_double(L->ncid, id, c) != NC_NOERR)
                return fail(L, LC_ERR_INVALID, name, "coordinate values cannot be read");
            int up = n < 2 || c[1] > c[0];
            for (size_t i = 0; i < n; i++)
                if (!isfinite(c[i]) || (i && !(up ? c[i] > c[i - 1] : c[i] < c[i - 1])))
                    return fail(L, LC_ERR_INVALID, name,
                                "coordinate value %zu (%g) is not finite or not strictly monotone", i, c[i]);
            if (!up) {
                L->flip[a] = 1;
                for (size_t i = 0; i < n / 2; i++) {
                    double t = c[i];
                    c[i] = c[n - 1 - i], c[n - 1 - i] = t;
                }
            }
        }
    }
    if (n < 2) /* one level: extruded to two, one unit apart */
        c[1] = c[0] + 1;
    if (!isfinite(c[nn - 1] - c[0]))
        return fail(L, LC_ERR_INVALID, NULL, "the grid's %c extent is not finite", "xyz"[a]);
    return 0;
}

static int is_uniform(const double *c, size_t n)
{
    double step = (c[n - 1] - c[0]) / (double)(n - 1);
    for (size_t i = 1; i < n; i++)
        if (fabs(c[i] - c[i - 1] - step) > 1e-9 * fabs(step))
            return 0;
    return 1;
}

/* Component a over the grid, one z level at a time, into vectors (x fastest). */
static int read_component(ncf_load *L, int a, double *slab, float *vectors)
{
    const comp *c = &L->c[a];
    size_t nx = L->n[0], ny = L->n[1], nz = L->n[2];
    for (size_t k = 0; k < nz; k++) {
        size_t start[4] = {0}, count[4] = {1, 1, 1, 1};
        int d = L->ndims;
        start[d - 1] = 0, count[d - 1] = nx;
        start[d - 2] = 0, count[d - 2] = ny;
        if (d - L->has_time == 3)
            start[d - 3] = k; /* the time index, when there is one, stays 0 */
        if (c->id >= 0) {
            int rc = nc_get_vara_double(L->ncid, c->id, start, count, slab);
            if (rc != NC_NOERR)
                return fail(L, LC_ERR_INVALID, c->name, "level %zu cannot be read: %s", k, nc_strerror(rc));
        }
        size_t kz = L->flip[2] ? nz - 1 - k : k;
        for (size_t j = 0; j < ny; j++) {
            size_t jy = L->flip[1] ? ny - 1 - j : j;
            for (size_t i = 0; i < nx; i++) {
                size_t ix = L->flip[0] ? nx - 1 - i : i;
                double x = 0;
                if (c->id >= 0) {
                    x = slab[j * nx + i];
                    if (lc_nc_is_fill(&c->fill, x))
                        x = 0, L->fills++;
                    else
                        x = x * c->scale + c->offset;
                    if (!isfinite(x) || fabs(x) > 3e38)
                        x = 0, L->fills++;
                }
                vectors[3 * (ix + nx * (jy + ny * kz)) + (size_t)a] = (float)x;
            }
        }
    }
    return 0;
}

static int load(ncf_load *L, const char *name, lc_field **out)
{
    int rc;
    if ((rc = find_variables(L)) || (rc = read_shape(L)))
        return rc;
    double *coords[3] = {NULL, NULL, NULL};
    float *vectors = NULL;
    double *slab = NULL;
    size_t nx = L->n[0], ny = L->n[1], nz = L->n[2], nz2 = nz < 2 ? 2 : nz;
    for (int a = 0; a < 3 && !rc; a++)
        rc = read_axis(L, a, &coords[a]);
    if (!rc) {
        /* What the header declares is checked before it is allocated: a file
         * of a few bytes may declare a grid of gigabytes (chunks never written
         * read as fill values), beyond the load budget or --max-memory. */
        double nodes = (double)nx * (double)ny * (double)nz2;
        double resident = 3.0 * nodes * sizeof *vectors, need = resident + (double)nx * ny * sizeof *slab;
        char what[96];
        snprintf(what, sizeof what, "%zu x %zu x %zu vectors", nx, ny, nz2);
        rc = lc_io_check_bytes(L->file, L->file_bytes, resident >= 1.8e19 ? UINT64_MAX : (uint64_t)resident,
                               need >= 1.8e19 ? UINT64_MAX : (uint64_t)need, what, L->err);
    }
    if (!rc) {
        vectors = malloc(3 * nx * ny * nz2 * sizeof *vectors);
        slab = malloc(nx * ny * sizeof *slab);
        if (!vectors || !slab)
            rc = fail(L, LC_ERR_NOMEM, NULL, "out of memory for %zu x %zu x %zu vectors", nx, ny, nz2);
    }
    for (int a = 0; a < 3 && !rc; a++)
        rc = read_component(L, a, slab, vectors);
    free(slab);
    if (rc) {
        for (int a = 0; a < 3; a++)
            free(coords[a]);
        free(vectors);
        return rc;
    }
    if (nz < 2) /* one level: the second is a copy */
        memcpy(vectors + 3 * nx * ny, vectors, 3 * nx * ny * sizeof *vectors);
    int uniform = is_uniform(coords[0], nx) && is_uniform(coords[1], ny) && is_uniform(coords[2], nz2);
    uint32_t dims[3] = {(uint32_t)nx, (uint32_t)ny, (uint32_t)nz2};
    char stem[128];
    lc_io_stem(name, stem, sizeof stem);
    rc = lc_field_create_grid(stem, uniform ? LC_FIELD_UNIFORM : LC_FIELD_RECTILINEAR, dims, coords, vectors, out,
                              L->err);
    if (rc)
        return rc;
    /* What was read, shown by `lucent info` and the datasets listing. */
    char *s = (*out)->vectors_name;
    size_t size = sizeof(*out)->vectors_name, used;
    used = (size_t)snprintf(s, size, "%.12s,%.12s,%.12s", L->c[0].name, L->c[1].name,
                            L->c[2].id >= 0 ? L->c[2].name : "w=0");
    if (L->has_time && used < size)
        used += (size_t)snprintf(s + used, size - used, "; time 0 of %zu", L->T);
    if (nz < 2 && used < size)
        used += (size_t)snprintf(s + used, size - used, "; 1 level");
    if (L->fills && used < size)
        snprintf(s + used, size - used, "; %lu fill->0", L->fills);
    return 0;
}

int lc_load_nc_field_memory(const void *data, size_t size, const char *name, lc_field **out, lc_error *err)
{
    *out = NULL;
    ncf_load L;
    memset(&L, 0, sizeof L);
    L.file = name ? name : "<memory>";
    L.file_bytes = size;
    L.err = err;
    int rc = lc_nc_open_memory(data, size, L.file, &L.ncid, err);
    if (rc)
        return rc;
    rc = load(&L, L.file, out);
    nc_close(L.ncid);
    return rc;
}

int lc_load_nc_field(const char *path, lc_field **out, lc_error *err)
{
    *out = NULL;
    lc_io_file f;
    int rc = lc_io_file_open(path, &f, err);
    if (rc)
        return rc;
    rc = lc_load_nc_field_memory(f.data, f.size, lc_io_basename(path), out, err);
    lc_io_file_close(&f);
    return rc;
}

/* A trajectory file (netcdf_read.c: lon, lat, pressure) may carry u and v
 * along its trajectories: those over lon's dimensions are not a grid. */
static int along_trajectories(int ncid, int uid)
{
    int lon, lat, p, nd_lon = 0, nd_u = 0, dl[NC_MAX_VAR_DIMS], du[NC_MAX_VAR_DIMS];
    if (nc_inq_varid(ncid, "lon", &lon) || nc_inq_varid(ncid, "lat", &lat) || nc_inq_varid(ncid, "pressure", &p) ||
        nc_inq_varndims(ncid, lon, &nd_lon) || nc_inq_varndims(ncid, uid, &nd_u) || nd_lon != nd_u ||
        nd_u > NC_MAX_VAR_DIMS || nc_inq_vardimid(ncid, lon, dl) || nc_inq_vardimid(ncid, uid, du))
        return 0;
    return memcmp(dl, du, (size_t)nd_u * sizeof *du) == 0;
}

static int holds_field(const char *data, size_t size, const char *name)
{
    lc_error err = {0};
    int ncid, found = 1, id = -1;
    if (lc_nc_open_memory(data, size, name, &ncid, &err))
        return 0;
    for (int a = 0; a < 2 && found; a++) {
        int nd = 0;
        id = find_component(ncid, a);
        found = id >= 0 && nc_inq_varndims(ncid, id, &nd) == NC_NOERR && nd >= 2 && nd <= 4;
    }
    found = found && !along_trajectories(ncid, find_component(ncid, 0));
    nc_close(ncid);
    return found;
}

int lc_nc_file_is_field(const char *path) { return lc_io_file_test(path, holds_field); }
