/* NetCDF trajectory reader (libnetcdf): lon/lat/pressure over (trajectory,
 * time) or (ensemble, trajectory, time), read in blocks of trajectories. */
#include <math.h>
#include <netcdf.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "io_util.h"
#include "nc_trajectories.h"
#include "netcdf_util.h"

#define BLOCK_VALUES (1u << 18) /* values per read and variable */
#define P0_HPA 1013.25
#define HEIGHT_SCALE 10.0

typedef struct nc_var {
    int id;
    lc_nc_fill fill;
    double scale; /* 0.01 for pressure in Pa */
    char name[LC_NAME_LEN];
} nc_var;

typedef struct nc_load {
    int ncid;
    const char *file;
    size_t file_bytes;
    lc_error *err;
    int ndims;      /* 2 or 3 */
    size_t rows, T; /* trajectories (times members), time steps */
    nc_var pos[3];  /* lon, lat, pressure */
    nc_var attr[LC_IO_MAX_FILE_ATTRIBUTES];
    int nattr;
    lc_trajectory_info trajectory; /* lon/lat in degrees, the time step */
    lc_io_progress progress;
    lc_io_part *part;      /* the trajectories this process keeps */
    size_t row_lo, row_hi; /* the rows the walk reads: all in the first pass, the share's in the second */
} nc_load;

static int fail(nc_load *L, int code, const char *var, const char *fmt, ...) __attribute__((format(printf, 4, 5)));
static int fail(nc_load *L, int code, const char *var, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    int rc = lc_nc_vfail(L->err, L->file, code, var, fmt, ap);
    va_end(ap);
    return rc;
}

/* A variable's units attribute, or "" without one. */
static void units_of(nc_load *L, int varid, char *out, size_t size)
{
    size_t len = 0;
    out[0] = '\0';
    if (nc_inq_attlen(L->ncid, varid, "units", &len) == NC_NOERR && len < size &&
        nc_get_att_text(L->ncid, varid, "units", out) == NC_NOERR)
        out[len] = '\0';
}

/* Trajectories get derived attributes (scene_derive.c) when lon and lat are
 * in degrees (their units say so, or they have none: CF's lon/lat are); the
 * time step comes from a 1-D "time" variable ("hours since ..." etc.; hours
 * without units), else stays unknown. */
static void inspect_trajectory(nc_load *L, int time_dim)
{
    char units[64];
    int degrees = 1;
    for (int k = 0; k < 2; k++) {
        units_of(L, L->pos[k].id, units, sizeof units);
        degrees &= !units[0] || strncmp(units, "degree", 6) == 0;
    }
    L->trajectory.geographic = degrees;
    int id, n, dim;
    double t[2];
    size_t start = 0, count = 2;
    if (nc_inq_varid(L->ncid, "time", &id) != NC_NOERR || nc_inq_varndims(L->ncid, id, &n) != NC_NOERR || n != 1 ||
        nc_inq_vardimid(L->ncid, id, &dim) != NC_NOERR || dim != time_dim || L->T < 2 ||
        nc_get_vara_double(L->ncid, id, &start, &count, t) != NC_NOERR || !(t[1] > t[0]) || !isfinite(t[1] - t[0]))
        return;
    units_of(L, id, units, sizeof units);
    static const struct {
        const char *prefix;
        double hours;
    } scale[] = {{"day", 24},          {"hour", 1},       {"h ", 1},
                 {"minute", 1 / 60.0}, {"min", 1 / 60.0}, {"second", 1 / 3600.0},
                 {"s ", 1 / 3600.0}};
    double hours = units[0] ? 0 : 1;
    for (size_t i = 0; i < sizeof scale / sizeof scale[0] && !hours; i++)
        if (strncmp(units, scale[i].prefix, strlen(scale[i].prefix)) == 0)
            hours = scale[i].hours;
    L->trajectory.step_hours = (t[1] - t[0]) * hours;
}

/* The dimension ids of lon decide the layout; other variables must match. */
static int same_dims(nc_load *L, int varid, const int *dims, int ndims)
{
    int n, d[NC_MAX_VAR_DIMS];
    if (nc_inq_varndims(L->ncid, varid, &n) != NC_NOERR || n != ndims || n > NC_MAX_VAR_DIMS)
        return 0;
    if (nc_inq_vardimid(L->ncid, varid, d) != NC_NOERR)
        return 0;
    return memcmp(d, dims, sizeof(int) * (size_t)ndims) == 0;
}

static int inspect(nc_load *L)
{
    static const char *const names[3] = {"lon", "lat", "pressure"};
    int dims[3], rc;
    for (int k = 0; k < 3; k++) {
        nc_var *v = &L->pos[k];
        if ((rc = nc_inq_varid(L->ncid, names[k], &v->id)) != NC_NOERR)
            return fail(L, LC_ERR_INVALID, NULL,
                        "no variable '%s' (expected lon, lat, pressure over (trajectory, time))", names[k]);
        snprintf(v->name, sizeof v->name, "%s", names[k]);
        v->scale = 1;
        lc_nc_read_fill(L->ncid, v->id, &v->fill);
        if (k == 0) {
            if (nc_inq_varndims(L->ncid, v->id, &L->ndims) != NC_NOERR || (L->ndims != 2 && L->ndims != 3))
                return fail(L, LC_ERR_INVALID, "lon",
                            "%d dimensions; expected (trajectory, time) or (ensemble, "
                            "trajectory, time)",
                            L->ndims);
            nc_inq_vardimid(L->ncid, v->id, dims);
            size_t len[3] = {1, 1, 1};
            char dname[NC_MAX_NAME + 1];
            for (int d = 0; d < L->ndims; d++) {
                if (nc_inq_dim(L->ncid, dims[d], dname, &len[d]) != NC_NOERR)
                    return fail(L, LC_ERR_INVALID, "lon", "unreadable dimension");
                static const char *const want2[2] = {"trajectory", "time"};
                static const char *const want3[3] = {"ensemble", "trajectory", "time"};
                const char *want = L->ndims == 2 ? want2[d] : want3[d];
                if (strcmp(dname, want) != 0)
                    return fail(L, LC_ERR_INVALID, "lon", "dimension %d is '%s', expected '%s'", d + 1, dname, want);
            }
            L->T = len[L->ndims - 1];
            uint64_t rows = L->ndims == 2 ? len[0] : (uint64_t)len[0] * len[1];
            if (rows * (uint64_t)L->T > LC_MAX_VERTICES)
                return fail(L, LC_ERR_LIMIT, "lon", "%llu points exceed the limit %u",
                            (unsigned long long)(rows * L->T), (unsigned)LC_MAX_VERTICES);
            L->rows = (size_t)rows;
        } else if (!same_dims(L, v->id, dims, L->ndims)) {
            return fail(L, LC_ERR_INVALID, names[k], "its dimensions differ from lon's");
        }
    }
    char units[64] = "";
    size_t ulen = 0;
    if (nc_inq_attlen(L->ncid, L->pos[2].id, "units", &ulen) == NC_NOERR && ulen < sizeof units &&
        nc_get_att_text(L->ncid, L->pos[2].id, "units", units) == NC_NOERR) {
        units[ulen] = '\0';
        if (strcmp(units, "Pa") == 0)
            L->pos[2].scale = 0.01;
    }
    inspect_trajectory(L, dims[L->ndims - 1]);
    int nvars;
    nc_inq_nvars(L->ncid, &nvars);
    for (int id = 0; id < nvars; id++) {
        if (id == L->pos[0].id || id == L->pos[1].id || id == L->pos[2].id || !same_dims(L, id, dims, L->ndims))
            continue;
        nc_type type;
        if (nc_inq_vartype(L->ncid, id, &type) != NC_NOERR || type == NC_CHAR || type == NC_STRING)
            continue;
        if (L->nattr == LC_IO_MAX_FILE_ATTRIBUTES) {
            LC_WARN(LC_IO_LOG, "%s: more than %d per-point variables, the rest skipped", L->file,
                    LC_IO_MAX_FILE_ATTRIBUTES);
            break;
        }
        nc_var *v = &L->attr[L->nattr++];
        char vname[NC_MAX_NAME + 1];
        nc_inq_varname(L->ncid, id, vname);
        snprintf(v->name, sizeof v->name, "%.63s", vname);
        for (char *c = v->name; *c; c++) /* names travel in URLs and PLY headers */
            if (*c == ' ' || (unsigned char)*c < 32)
                *c = '_';
        v->id = id;
        v->scale = 1;
        lc_nc_read_fill(L->ncid, v->id, &v->fill);
    }
    return 0;
}

/* Reads rows [r0, r0 + n) of variable v into buf (n * T doubles). */
static int read_rows(nc_load *L, const nc_var *v, size_t r0, size_t n, double *buf)
{
    size_t start[3] = {0, 0, 0}, count[3] = {1, 1, 1};
    int rc;
    if (L->ndims == 2) {
        start[0] = r0, count[0] = n, count[1] = L->T;
        rc = nc_get_vara_double(L->ncid, v->id, start, count, buf);
    } else { /* rows run over (ensemble, trajectory); read member by member */
        size_t ntraj = 0;
        int dims[3];
        nc_inq_vardimid(L->ncid, v->id, dims);
        nc_inq_dimlen(L->ncid, dims[1], &ntraj);
        rc = NC_NOERR;
        for (size_t done = 0; done < n && rc == NC_NOERR;) {
            size_t r = r0 + done, e = r / ntraj, t = r % ntraj, take = ntraj - t < n - done ? ntraj - t : n - done;
            start[0] = e, start[1] = t, count[1] = take, count[2] = L->T;
            rc = nc_get_vara_double(L->ncid, v->id, start, count, buf + done * L->T);
            done += take;
        }
    }
    if (rc != NC_NOERR)
        return fail(L, LC_ERR_INVALID, v->name, "cannot read: %s", nc_strerror(rc));
    return 0;
}

/* Reads the last value of variable v. The walk reads the per-point variables
 * only in the rows a process keeps; this tells every process, whichever
 * share it reads, whether the whole variable lies in the file (its values
 * before the last lie below it), so that all refuse a truncated file alike. */
static int check_extent(nc_load *L, const nc_var *v)
{
    size_t last[3] = {0, 0, 0};
    int dims[3];
    nc_inq_vardimid(L->ncid, v->id, dims);
    for (int d = 0; d < L->ndims; d++) {
        size_t len = 0;
        nc_inq_dimlen(L->ncid, dims[d], &len);
        last[d] = len ? len - 1 : 0;
    }
    double x;
    int rc = nc_get_var1_double(L->ncid, v->id, last, &x);
    if (rc != NC_NOERR)
        return fail(L, LC_ERR_INVALID, v->name, "cannot read: %s", nc_strerror(rc));
    return 0;
}

/* Walks the trajectories block by block. Without a scene it stores each
 * row's valid length (up to the first missing position); with one it fills. */
static int walk(nc_load *L, uint32_t *len, lc_scene *s, float **attr, double *buf)
{
    size_t block = BLOCK_VALUES / (L->T ? L->T : 1);
    if (block == 0)
        block = 1;
    uint64_t w = 0;
    uint32_t line = 0;
    for (size_t r0 = L->row_lo; r0 < L->row_hi; r0 += block) {
        size_t n = L->row_hi - r0 < block ? L->row_hi - r0 : block;
        lc_io_progress_report(&L->progress, r0 + (s ? L->rows : 0), 2 * L->rows); /* two passes */
        double *p[3] = {buf, buf + n * L->T, buf + 2 * n * L->T};
        for (int k = 0; k < 3; k++) {
            int rc = read_rows(L, &L->pos[k], r0, n, p[k]);
            if (rc)
                return rc;
        }
        if (!s) {
            for (size_t r = 0; r < n; r++) {
                size_t t = 0;
                while (t < L->T && !lc_nc_is_fill(&L->pos[0].fill, p[0][r * L->T + t]) &&
                       !lc_nc_is_fill(&L->pos[1].fill, p[1][r * L->T + t]) &&
                       !lc_nc_is_fill(&L->pos[2].fill, p[2][r * L->T + t]) && p[2][r * L->T + t] > 0)
                    t++;
                len[r0 + r] = (uint32_t)t;
            }
            continue;
        }
        uint64_t w0 = w;
        for (size_t r = 0; r < n; r++) {
            if (len[r0 + r] < 2)
                continue;
            for (size_t t = 0; t < len[r0 + r]; t++) {
                size_t i = r * L->T + t;
                float *d = s->positions + 3 * (w + t);
                d[0] = (float)p[0][i];
                d[1] = (float)p[1][i];
                d[2] = (float)(HEIGHT_SCALE * log(P0_HPA / (p[2][i] * L->pos[2].scale)));
            }
            w += len[r0 + r];
            s->line_offsets[++line] = (uint32_t)w;
        }
        double *abuf = buf + 3 * n * L->T;
        for (int a = 0; a < L->nattr; a++) {
            int rc = read_rows(L, &L->attr[a], r0, n, abuf);
            if (rc)
                return rc;
            uint64_t wa = w0;
            for (size_t r = 0; r < n; r++) {
                if (len[r0 + r] < 2)
                    continue;
                for (size_t t = 0; t < len[r0 + r]; t++) {
                    double x = abuf[r * L->T + t];
                    attr[a][wa + t] = lc_nc_is_fill(&L->attr[a].fill, x) ? NAN : (float)x;
                }
                wa += len[r0 + r];
            }
        }
    }
    return 0;
}

static int load(nc_load *L, lc_scene **out)
{
    lc_io_progress_start(&L->progress, L->file);
    int rc = inspect(L);
    if (rc)
        return rc;
    if (L->rows == 0 || L->T < 2)
        return fail(L, LC_ERR_INVALID, "lon", "%zu trajectories of %zu time steps: nothing to draw", L->rows, L->T);
    for (int a = 0; a < L->nattr; a++) /* positions: the first walk reads every row */
        if ((rc = check_extent(L, &L->attr[a])) != 0)
            return rc;
    size_t block = BLOCK_VALUES / L->T ? BLOCK_VALUES / L->T : 1;
    uint32_t *len = malloc(L->rows * sizeof *len);
    double *buf = malloc(4 * (block < L->rows ? block : L->rows) * L->T * sizeof *buf);
    lc_scene *s = NULL;
    float *attr[LC_IO_MAX_FILE_ATTRIBUTES];
    if (!len || !buf) {
        rc = fail(L, LC_ERR_NOMEM, NULL, "out of memory for %zu trajectories", L->rows);
        goto done;
    }
    L->row_lo = 0, L->row_hi = L->rows;
    if ((rc = walk(L, len, NULL, NULL, buf)))
        goto done;
    uint64_t points = 0, lines = 0, short_lines = 0, cut = 0;
    for (size_t r = 0; r < L->rows; r++) {
        if (len[r] >= 2) {
            points += len[r], lines++;
            if ((rc = lc_io_part_count(L->part, len[r], L->file, L->err)) != 0)
                goto done;
        } else {
            short_lines++;
        }
        cut += len[r] < L->T;
    }
    if (points > LC_MAX_VERTICES || lines > LC_MAX_PRIMITIVES) {
        rc = fail(L, LC_ERR_LIMIT, "lon", "%llu points in %llu trajectories exceed the limits",
                  (unsigned long long)points, (unsigned long long)lines);
        goto done;
    }
    if (cut && lc_io_part_speaks(L->part))
        LC_WARN(LC_IO_LOG, "%s: %llu trajectories end early at a missing position", L->file, (unsigned long long)cut);
    if (short_lines && lc_io_part_speaks(L->part))
        LC_WARN(LC_IO_LOG, "%s: %llu trajectories with fewer than 2 points skipped", L->file,
                (unsigned long long)short_lines);
    if (lines == 0) {
        rc = fail(L, LC_ERR_INVALID, "lon", "no trajectory with two or more valid points");
        goto done;
    }
    /* The share's kept trajectories are contiguous: the rows from its first
     * to past its last, with only short rows between them. */
    if ((rc = lc_io_part_choose(L->part, (uint32_t)lines, points, L->file, L->err)) != 0)
        goto done;
    points = L->part->points, lines = L->part->last - L->part->first;
    L->row_lo = L->row_hi = L->rows;
    for (size_t r = 0, k = 0; r < L->rows; r++) {
        if (len[r] < 2)
            continue;
        if (k == L->part->first && L->row_lo == L->rows)
            L->row_lo = r;
        if (++k == L->part->last) {
            L->row_hi = r + 1;
            break;
        }
    }
    if (lines == 0)
        L->row_lo = L->row_hi = 0;
    /* The counts are known before anything of their size is allocated: a
     * deflated file may inflate far beyond the load budget. */
    char what[96];
    snprintf(what, sizeof what, "%llu points in %llu trajectories", (unsigned long long)points,
             (unsigned long long)lines);
    if ((rc = lc_io_check_load(L->file, L->file_bytes, points, points * sizeof(float) * (uint64_t)L->nattr, what,
                               L->err)) != 0)
        goto done;
    s = lc_scene_create(L->file, LC_PRIM_LINES);
    if (!s) {
        rc = fail(L, LC_ERR_NOMEM, NULL, "out of memory");
        goto done;
    }
    if ((rc = lc_scene_alloc_vertices(s, (uint32_t)points, 0, L->err)))
        goto done;
    s->line_offsets = calloc((size_t)lines + 1, sizeof *s->line_offsets);
    s->line_count = (uint32_t)lines;
    if (!s->line_offsets) {
        rc = fail(L, LC_ERR_NOMEM, NULL, "out of memory for %llu trajectories", (unsigned long long)lines);
        goto done;
    }
    for (int a = 0; a < L->nattr; a++) { /* the scene owns them on every path */
        float *v = malloc((size_t)points * sizeof *v);
        if (!v) {
            rc = fail(L, LC_ERR_NOMEM, NULL, "out of memory for attributes");
            goto done;
        }
        for (int k = 0; lc_scene_find_attribute(s, L->attr[a].name) >= 0; k++) /* never replace an earlier one */
            snprintf(L->attr[a].name, LC_NAME_LEN, "attribute_%d_%d", a, k);
        int idx = lc_scene_add_attribute(s, L->attr[a].name, v, L->err);
        if (idx < 0) {
            rc = idx;
            goto done;
        }
        attr[a] = s->attributes[idx].values;
    }
    if ((rc = walk(L, len, s, attr, buf)))
        goto done;
    lc_io_set_defaults(s);
    s->trajectory = L->trajectory;
done:
    free(len);
    free(buf);
    if (rc) {
        lc_scene_destroy(s);
        s = NULL;
    }
    *out = s;
    return rc;
}

static int load_netcdf(const void *data, size_t size, const char *name, lc_io_part *part, lc_scene **out, lc_error *err)
{
    *out = NULL;
    nc_load L = {.file = name ? name : "<memory>", .file_bytes = size, .err = err, .part = part};
    int rc = lc_nc_open_memory(data, size, L.file, &L.ncid, err);
    if (rc)
        return rc;
    rc = load(&L, out);
    nc_close(L.ncid);
    return rc;
}

int lc_load_netcdf_memory(const void *data, size_t size, const char *name, lc_scene **out, lc_error *err)
{
    lc_io_part whole = {0};
    return load_netcdf(data, size, name, &whole, out, err);
}

/* The file is mapped and opened from memory, so that both forms behave alike. */
int lc_load_netcdf(const char *path, lc_scene **out, lc_error *err)
{
    return lc_io_load_path(path, lc_load_netcdf_memory, out, err);
}

int lc_load_netcdf_part(const char *path, int rank, int size, lc_scene **out, lc_error *err)
{
    return lc_io_load_path_part(path, load_netcdf, rank, size, out, err);
}
