/* NetCDF gridded vector fields (render/io/nc_field_read.c): files written by
 * this test with libnetcdf, sampled against the linear formulas they were
 * written from (trilinear interpolation of a linear field is exact), a
 * decreasing rectilinear axis, 4-D with time, 2-D u/v, CF standard names,
 * fill values, packed data, the field-source opener and bad files by their
 * error text. */
#include <math.h>
#include <netcdf.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "field.h"
#include "io_util.h"
#include "lc_test.h"
#include "nc_field.h"
#include "vtk_field.h"

static char dir[] = "/tmp/lc_nc_field_XXXXXX";

/* The linear field the valid files hold: v = A p + b. */
static void linear(const double p[3], double v[3])
{
    v[0] = 1 + 2 * p[0] - p[1] + 0.5 * p[2];
    v[1] = -3 + 0.25 * p[0] + p[1] - 2 * p[2];
    v[2] = 0.5 - p[0] + 0.75 * p[1] + p[2];
}

enum {
    F_TIME = 1,       /* a leading time dimension (2 steps; step 1 holds garbage) */
    F_NO_W = 2,       /* no w variable */
    F_2D = 4,         /* (y, x) only */
    F_STD = 8,        /* variables named a/b/c with CF standard names */
    F_NO_COORDS = 16, /* no coordinate variables */
    F_NO_V = 32,
    F_BAD_AXIS = 64,    /* y coordinates not monotone */
    F_SHAPE = 128,      /* v has one x node fewer */
    F_FILL = 256,       /* node (1, 0, 0) of u is _FillValue */
    F_PACKED = 512,     /* u stored as short with scale_factor / add_offset */
    F_LONG_ATTS = 1024, /* u: missing_value, v: scale_factor and add_offset of 16 values each */
};

static const double XS[] = {0, 1, 2.5, 3}, YS[] = {4, 2, 1}, ZS[] = {-1, 0};
#define NX 4
#define NY 3
#define NZ 2

static int write_file(const char *path, int flags)
{
    int nc, rc = nc_create(path, NC_CLOBBER, &nc);
    if (rc)
        return rc;
    int two = (flags & F_2D) != 0, t = (flags & F_TIME) != 0;
    int dt, dz, dy, dx, dx1, dims[4], nd = 0;
    if (t)
        nc_def_dim(nc, "time", NC_UNLIMITED, &dt), dims[nd++] = dt;
    if (!two)
        nc_def_dim(nc, "z", NZ, &dz), dims[nd++] = dz;
    nc_def_dim(nc, "y", NY, &dy), dims[nd++] = dy;
    nc_def_dim(nc, "x", NX, &dx), dims[nd++] = dx;
    nc_def_dim(nc, "x1", NX - 1, &dx1);
    int cx = -1, cy = -1, cz = -1, var[3] = {-1, -1, -1};
    if (!(flags & F_NO_COORDS)) {
        nc_def_var(nc, "x", NC_DOUBLE, 1, &dx, &cx);
        nc_def_var(nc, "y", NC_DOUBLE, 1, &dy, &cy);
        if (!two)
            nc_def_var(nc, "z", NC_FLOAT, 1, &dz, &cz);
    }
    static const char *names[3] = {"u", "v", "w"}, *std[3] = {"a", "b", "c"};
    static const char *stdn[3] = {"eastward_wind", "northward_wind", "upward_air_velocity"};
    for (int a = 0; a < 3; a++) {
        if ((a == 2 && (flags & (F_NO_W | F_2D))) || (a == 1 && (flags & F_NO_V)))
            continue;
        int vd[4];
        memcpy(vd, dims, sizeof vd);
        if (a == 1 && (flags & F_SHAPE))
            vd[nd - 1] = dx1;
        nc_type type = a == 0 && (flags & F_PACKED) ? NC_SHORT : NC_FLOAT;
        nc_def_var(nc, flags & F_STD ? std[a] : names[a], type, nd, vd, &var[a]);
        if (flags & F_STD)
            nc_put_att_text(nc, var[a], "standard_name", strlen(stdn[a]), stdn[a]);
        if (a == 0 && (flags & F_FILL)) {
            float fill = -999.f;
            nc_put_att_float(nc, var[a], "_FillValue", NC_FLOAT, 1, &fill);
        }
        if (flags & F_LONG_ATTS) {
            /* CF wants these scalar; a reader that trusts the file writes all
             * 16 values into one double. Not scalar: ignored. */
            double many[16];
            for (int i = 0; i < 16; i++)
                many[i] = i ? 7e300 : 1e6;
            nc_put_att_double(nc, var[a], a == 0 ? "missing_value" : "scale_factor", NC_DOUBLE, 16, many);
            nc_put_att_double(nc, var[a], "add_offset", NC_DOUBLE, 16, many);
        }
        if (type == NC_SHORT) {
            double sc = 0.001, off = 2;
            nc_put_att_double(nc, var[a], "scale_factor", NC_DOUBLE, 1, &sc);
            nc_put_att_double(nc, var[a], "add_offset", NC_DOUBLE, 1, &off);
        }
    }
    nc_enddef(nc);
    if (cx >= 0) {
        nc_put_var_double(nc, cx, XS);
        double ys[NY];
        memcpy(ys, YS, sizeof ys);
        if (flags & F_BAD_AXIS)
            ys[2] = 3;
        nc_put_var_double(nc, cy, ys);
        if (cz >= 0) {
            float zs[NZ] = {(float)ZS[0], (float)ZS[1]};
            nc_put_var_float(nc, cz, zs);
        }
    }
    int nt = t ? 2 : 1, nzl = two ? 1 : NZ;
    for (int a = 0; a < 3; a++) {
        if (var[a] < 0)
            continue;
        int nx = a == 1 && (flags & F_SHAPE) ? NX - 1 : NX;
        for (int ti = 0; ti < nt; ti++)
            for (int k = 0; k < nzl; k++)
                for (int j = 0; j < NY; j++)
                    for (int i = 0; i < nx; i++) {
                        double p[3] = {flags & F_NO_COORDS ? i : XS[i], flags & F_NO_COORDS ? j : YS[j],
                                       two ? 0 : (flags & F_NO_COORDS ? k : ZS[k])};
                        double v[3];
                        linear(p, v);
                        double x = ti ? 1e6 : v[a];
                        if (a == 0 && (flags & F_FILL) && i == 1 && j == 0 && k == 0)
                            x = -999;
                        size_t start[4], count[4] = {1, 1, 1, 1}, s = 0;
                        if (t)
                            start[s++] = (size_t)ti;
                        if (!two)
                            start[s++] = (size_t)k;
                        start[s++] = (size_t)j, start[s++] = (size_t)i;
                        if (var[a] >= 0 && a == 0 && (flags & F_PACKED)) {
                            short q = (short)lround((x - 2) / 0.001);
                            nc_put_vara_short(nc, var[a], start, count, &q);
                        } else {
                            float f = (float)x;
                            nc_put_vara_float(nc, var[a], start, count, &f);
                        }
                    }
    }
    return nc_close(nc);
}

static lc_field *open_case(const char *file, int flags, int expect_rc, const char *expect_msg)
{
    char path[256];
    snprintf(path, sizeof path, "%s/%s", dir, file);
    CHECK(write_file(path, flags) == NC_NOERR, "%s: not written", file);
    lc_field *f = NULL;
    lc_error err = {0};
    int rc = lc_field_open(path, &f, &err);
    if (expect_rc) {
        CHECK(rc == expect_rc && !f, "%s: rc %d (want %d)", file, rc, expect_rc);
        CHECK(strstr(err.msg, expect_msg) != NULL, "%s: message '%s' lacks '%s'", file, err.msg, expect_msg);
        return NULL;
    }
    CHECK(rc == 0 && f, "%s: %s", file, err.msg);
    CHECK(lc_field_is_source(path), "%s: not recognized as a field source", file);
    return f;
}

/* The field against the linear formula at nodes and between them. w0: the
 * file has no w (expect 0); z0: 2-D (expect the z = 0 values at every z). */
static void check_linear(const lc_field *f, const char *what, int no_w, int two_d, double tol)
{
    int n = 0;
    double worst = 0;
    for (int k = 0; k <= 10; k++)
        for (int j = 0; j <= 10; j++)
            for (int i = 0; i <= 10; i++) {
                double p[3], v[3], want[3];
                for (int a = 0; a < 3; a++)
                    p[a] = f->bounds[a] + (f->bounds[a + 3] - f->bounds[a]) * (a == 0 ? i : a == 1 ? j : k) / 10.0;
                double q[3] = {p[0], p[1], two_d ? 0 : p[2]};
                linear(q, want);
                if (no_w)
                    want[2] = 0;
                if (!lc_field_sample(f, p, 0, v))
                    continue;
                n++;
                for (int a = 0; a < 3; a++)
                    worst = fmax(worst, fabs(v[a] - want[a]));
            }
    CHECK(n == 11 * 11 * 11, "%s: %d of 1331 points inside", what, n);
    CHECK(worst <= tol, "%s: largest error %g (tolerance %g)", what, worst, tol);
}

/* A NetCDF-4 grid of nx x ny x nz whose chunks are never written: a file of
 * a few kilobytes that reads as gigabytes of fill values. */
static void write_unwritten(const char *path, size_t nx, size_t ny, size_t nz)
{
    int nc, d[3], v;
    CHECK(nc_create(path, NC_CLOBBER | NC_NETCDF4, &nc) == NC_NOERR, "%s: not created", path);
    nc_def_dim(nc, "z", nz, &d[0]);
    nc_def_dim(nc, "y", ny, &d[1]);
    nc_def_dim(nc, "x", nx, &d[2]);
    nc_def_var(nc, "u", NC_FLOAT, 3, d, &v);
    nc_def_var(nc, "v", NC_FLOAT, 3, d, &v);
    nc_def_var(nc, "w", NC_FLOAT, 3, d, &v);
    nc_close(nc);
}

/* The grid a file declares is checked before it is allocated: against the
 * load budget (64 times the file, at least 64 MB) and --max-memory. */
static void test_declared_size(void)
{
    char path[256];
    snprintf(path, sizeof path, "%s/unwritten.nc", dir);
    write_unwritten(path, 1000, 1000, 200); /* 2.4 GB of vectors */
    lc_field *f = NULL;
    lc_error err = {0};
    int rc = lc_field_open(path, &f, &err);
    CHECK(rc == LC_ERR_LIMIT && !f && strstr(err.msg, "refused before loading") && strstr(err.msg, "load budget"),
          "an unwritten 1000 x 1000 x 200 grid is refused before loading: rc %d, %s", rc, err.msg);
    snprintf(path, sizeof path, "%s/unwritten_small.nc", dir);
    write_unwritten(path, 200, 200, 100); /* 48 MB: within the load budget's floor */
    lc_io_set_memory_limit(16u << 20);
    rc = lc_field_open(path, &f, &err);
    CHECK(rc == LC_ERR_LIMIT && !f && strstr(err.msg, "--max-memory"),
          "a 48 MB grid over a 16 MB --max-memory is refused: rc %d, %s", rc, err.msg);
    lc_io_set_memory_limit(0);
    rc = lc_field_open(path, &f, &err);
    CHECK(rc == 0 && f, "without the limit it loads (fill values read as 0): %s", err.msg);
    lc_field_destroy(f);
}

int main(void)
{
    if (!mkdtemp(dir)) {
        perror("mkdtemp");
        return 1;
    }
    /* (z, y, x) on a rectilinear grid whose y decreases in the file. */
    lc_field *f = open_case("rect.nc", 0, 0, NULL);
    if (f) {
        CHECK(f->kind == LC_FIELD_RECTILINEAR, "rect.nc: kind %s", lc_field_kind_name(f->kind));
        CHECK(f->dims[0] == NX && f->dims[1] == NY && f->dims[2] == NZ, "rect.nc: dims %u %u %u", f->dims[0],
              f->dims[1], f->dims[2]);
        CHECK(f->bounds[0] == 0 && f->bounds[3] == 3 && f->bounds[1] == 1 && f->bounds[4] == 4 && f->bounds[2] == -1 &&
                  f->bounds[5] == 0,
              "rect.nc: bounds [%g %g] [%g %g] [%g %g]", f->bounds[0], f->bounds[3], f->bounds[1], f->bounds[4],
              f->bounds[2], f->bounds[5]);
        CHECK(strcmp(f->name, "rect") == 0 && strcmp(f->vectors_name, "u,v,w") == 0, "rect.nc: name %s vectors %s",
              f->name, f->vectors_name);
        check_linear(f, "rect.nc", 0, 0, 1e-5);
        lc_field_destroy(f);
    }
    /* 4-D with time: step 0 is read, step 1 (1e6 everywhere) is not. */
    if ((f = open_case("time.nc", F_TIME, 0, NULL))) {
        CHECK(strstr(f->vectors_name, "time 0 of 2") != NULL, "time.nc: vectors '%s'", f->vectors_name);
        check_linear(f, "time.nc", 0, 0, 1e-5);
        lc_field_destroy(f);
    }
    /* 2-D u, v: one level, extruded, w = 0. */
    if ((f = open_case("flat.nc", F_2D, 0, NULL))) {
        CHECK(f->dims[2] == 2 && f->bounds[2] == 0 && f->bounds[5] == 1, "flat.nc: z %u nodes [%g, %g]", f->dims[2],
              f->bounds[2], f->bounds[5]);
        CHECK(strstr(f->vectors_name, "w=0") && strstr(f->vectors_name, "1 level"), "flat.nc: vectors '%s'",
              f->vectors_name);
        check_linear(f, "flat.nc", 1, 1, 1e-5);
        lc_field_destroy(f);
    }
    /* 3-D (time, y, x): the record dimension is time, not z. */
    if ((f = open_case("surface_time.nc", F_TIME | F_2D, 0, NULL))) {
        CHECK(strstr(f->vectors_name, "time 0 of 2") != NULL, "surface_time.nc: vectors '%s'", f->vectors_name);
        check_linear(f, "surface_time.nc", 1, 1, 1e-5);
        lc_field_destroy(f);
    }
    /* CF standard names, no coordinate variables: a uniform 0..n-1 grid. */
    if ((f = open_case("std.nc", F_STD | F_NO_COORDS, 0, NULL))) {
        CHECK(f->kind == LC_FIELD_UNIFORM && f->bounds[3] == NX - 1 && f->bounds[4] == NY - 1,
              "std.nc: kind %s, max %g %g", lc_field_kind_name(f->kind), f->bounds[3], f->bounds[4]);
        CHECK(strcmp(f->vectors_name, "a,b,c") == 0, "std.nc: vectors '%s'", f->vectors_name);
        check_linear(f, "std.nc", 0, 0, 1e-5);
        lc_field_destroy(f);
    }
    /* No w: w = 0. */
    if ((f = open_case("no_w.nc", F_NO_W, 0, NULL))) {
        check_linear(f, "no_w.nc", 1, 0, 1e-5);
        lc_field_destroy(f);
    }
    test_declared_size();
    /* Attributes of 16 values where CF wants one: ignored, the field intact. */
    if ((f = open_case("long_atts.nc", F_LONG_ATTS, 0, NULL))) {
        check_linear(f, "long_atts.nc", 0, 0, 1e-5);
        lc_field_destroy(f);
    }
    /* Packed short u (scale 0.001, offset 2): within half a quantum. */
    if ((f = open_case("packed.nc", F_PACKED, 0, NULL))) {
        check_linear(f, "packed.nc", 0, 0, 6e-4);
        lc_field_destroy(f);
    }
    /* A fill value becomes 0 velocity and is counted. */
    if ((f = open_case("fill.nc", F_FILL, 0, NULL))) {
        double p[3] = {XS[1], YS[0], ZS[0]}, v[3];
        lc_field_sample(f, p, 0, v);
        CHECK(v[0] == 0 && strstr(f->vectors_name, "1 fill->0"), "fill.nc: u %g at the fill node, vectors '%s'", v[0],
              f->vectors_name);
        lc_field_destroy(f);
    }
    /* Bad files: the error names the variable. */
    open_case("no_v.nc", F_NO_V, LC_ERR_INVALID, "no variable for the y (v, V");
    open_case("bad_axis.nc", F_BAD_AXIS, LC_ERR_INVALID,
              "variable 'y': coordinate value 2 (3) is not finite or not "
              "strictly monotone");
    open_case("shape.nc", F_SHAPE, LC_ERR_INVALID, "variable 'v': shape 2 x 3 x 3 differs from 'u' (2 x 3 x 4)");
    char path[256];
    snprintf(path, sizeof path, "%s/no_v.nc", dir);
    CHECK(!lc_field_is_source(path), "a file without v counts as a field source");
    /* A trajectory file (lon, lat, pressure) with u, v along its trajectories stays a line dataset. */
    snprintf(path, sizeof path, "%s/traj.nc", dir);
    int nc, td[2], ids[5];
    if (nc_create(path, NC_CLOBBER, &nc) == NC_NOERR) {
        nc_def_dim(nc, "trajectory", 2, &td[0]);
        nc_def_dim(nc, "time", 3, &td[1]);
        static const char *const tv[5] = {"lon", "lat", "pressure", "u", "v"};
        for (int k = 0; k < 5; k++)
            nc_def_var(nc, tv[k], NC_FLOAT, 2, td, &ids[k]);
        nc_close(nc);
        CHECK(!lc_field_is_source(path), "a trajectory file with u, v counts as a field source");
        unlink(path);
    }
    /* Over the node cap (NetCDF-4 allocates no chunk that is never written: the file stays small), and an empty
     * time axis. */
    for (int big = 1; big >= 0; big--) {
        snprintf(path, sizeof path, "%s/big.nc", dir);
        int gd[4];
        if (nc_create(path, NC_CLOBBER | NC_NETCDF4, &nc) != NC_NOERR)
            continue;
        nc_def_dim(nc, "time", NC_UNLIMITED, &gd[0]);
        nc_def_dim(nc, "z", big ? 128 : 2, &gd[1]);
        nc_def_dim(nc, "y", big ? 2048 : 2, &gd[2]);
        nc_def_dim(nc, "x", big ? 2048 : 2, &gd[3]);
        nc_def_var(nc, "u", NC_FLOAT, 4, gd, &ids[0]);
        nc_def_var(nc, "v", NC_FLOAT, 4, gd, &ids[1]);
        nc_close(nc);
        lc_field *b = NULL;
        lc_error e = {0};
        int brc = lc_field_open(path, &b, &e);
        CHECK(brc == (big ? LC_ERR_LIMIT : LC_ERR_INVALID) && !b &&
                  strstr(e.msg, big ? "variable 'u': grid 2048 x 2048 x 128 exceeds the limit of 268435456 nodes"
                                    : "variable 'u': its time dimension is empty"),
              "big=%d: rc %d '%s'", big, brc, e.msg);
        unlink(path);
    }
    /* Garbage named .nc: not a field, and opening it says why. */
    snprintf(path, sizeof path, "%s/junk.nc", dir);
    FILE *j = fopen(path, "wb");
    if (j) {
        fputs("CDF\001 not really", j);
        fclose(j);
    }
    lc_field *g = NULL;
    lc_error err = {0};
    CHECK(!lc_field_is_source(path), "junk.nc counts as a field source");
    CHECK(lc_field_open(path, &g, &err) != 0 && !g && strstr(err.msg, "junk.nc"), "junk.nc: '%s'", err.msg);
    /* Memory form: empty input. */
    CHECK(lc_load_nc_field_memory("", 0, "empty.nc", &g, &err) == LC_ERR_INVALID && strstr(err.msg, "empty"),
          "empty: '%s'", err.msg);
    static const char *const files[] = {"rect.nc",      "time.nc",      "flat.nc",           "surface_time.nc",
                                        "std.nc",       "no_w.nc",      "packed.nc",         "fill.nc",
                                        "no_v.nc",      "bad_axis.nc",  "shape.nc",          "junk.nc",
                                        "long_atts.nc", "unwritten.nc", "unwritten_small.nc"};
    for (size_t i = 0; i < sizeof files / sizeof files[0]; i++) {
        snprintf(path, sizeof path, "%s/%s", dir, files[i]);
        unlink(path);
    }
    rmdir(dir);
    return lc_test_finish();
}
