/* NetCDF trajectories: the table tests/data/loaders/nc/cases.txt (files from
 * disk and through nc_open_mem), exact positions and the missing-value rule,
 * a round trip through this test's own libnetcdf writer (classic and NetCDF-4,
 * both layouts) and truncated/mutated inputs. */
#include <math.h>
#include <netcdf.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "io_util.h"
#include "lc_test.h"
#include "loader_test_util.h"
#include "loaders.h"
#include "scene.h"

#define DATA LUCENT_TEST_DATA "/loaders/"

static int load_path(const char *path, lc_scene **s, lc_error *err) { return lc_load_netcdf(path, s, err); }

static int load_memory(const char *path, const void *data, size_t size, lc_scene **s, lc_error *err)
{
    return lc_load_netcdf_memory(data, size, lc_io_basename(path), s, err);
}

static void test_values(void)
{
    lc_scene *s = NULL;
    lc_error err = {0};
    CHECK(lc_load_netcdf(DATA "nc/valid/trajectories.nc", &s, &err) == 0, "%s", err.msg);
    if (!s)
        return;
    static const uint32_t off[3] = {0, 4, 6};
    CHECK(s->line_count == 2 && memcmp(s->line_offsets, off, sizeof off) == 0, "cut at the missing pressure");
    CHECK(s->positions[0] == 0 && s->positions[1] == 50 &&
              fabsf(s->positions[2] - (float)(10 * log(1013.25 / 1000))) < 1e-6f,
          "x = lon, y = lat, z = 10 ln(1013.25 / p): %g %g %g", s->positions[0], s->positions[1], s->positions[2]);
    CHECK(s->attributes[0].values[5] == 245, "attribute follows its trajectory");
    lc_scene_destroy(s);
}

/* Writes the scene's lines (all of length T) as lon/lat/pressure over
 * (trajectory, time) or, with members > 1, (ensemble, trajectory, time). */
static int write_nc(const lc_scene *s, const char *path, int netcdf4, int members, size_t T)
{
    int nc, rc = nc_create(path, NC_CLOBBER | (netcdf4 ? NC_NETCDF4 : 0), &nc);
    if (rc != NC_NOERR)
        return rc;
    size_t rows = s->line_count, n = s->vertex_count;
    int dims[3], nd = members > 1 ? 3 : 2, var[3 + LC_MAX_ATTRIBUTES];
    if (members > 1)
        nc_def_dim(nc, "ensemble", (size_t)members, &dims[0]);
    nc_def_dim(nc, "trajectory", rows / (size_t)members, &dims[nd - 2]);
    nc_def_dim(nc, "time", T, &dims[nd - 1]);
    static const char *const pos[3] = {"lon", "lat", "pressure"};
    for (int k = 0; k < 3; k++)
        nc_def_var(nc, pos[k], NC_DOUBLE, nd, dims, &var[k]);
    for (int a = 0; a < s->attribute_count; a++)
        nc_def_var(nc, s->attributes[a].name, NC_FLOAT, nd, dims, &var[3 + a]);
    nc_enddef(nc);
    double *buf = malloc(n * sizeof *buf);
    for (int k = 0; k < 3; k++) {
        for (size_t i = 0; i < n; i++)
            buf[i] = k < 2 ? s->positions[3 * i + k] : 1013.25 * exp(-s->positions[3 * i + 2] / 10.0);
        nc_put_var_double(nc, var[k], buf);
    }
    for (int a = 0; a < s->attribute_count; a++)
        nc_put_var_float(nc, var[3 + a], s->attributes[a].values);
    free(buf);
    return nc_close(nc);
}

static void test_roundtrip(const char *dir)
{
    lc_error err = {0};
    size_t T = 9, rows = 6;
    lc_scene *s = lc_scene_create("synthetic", LC_PRIM_LINES);
    CHECK(s && lc_scene_alloc_vertices(s, (uint32_t)(T * rows), 0, &err) == 0, "alloc: %s", err.msg);
    for (uint32_t i = 0; i < 3 * s->vertex_count; i++)
        s->positions[i] = (float)sin(i * 0.731) * 20.0f + 21.0f;
    const char *names[2] = {"PV", "specific_humidity"};
    for (int a = 0; a < 2; a++) {
        float *v = malloc(s->vertex_count * sizeof *v);
        for (uint32_t i = 0; i < s->vertex_count; i++)
            v[i] = (float)cos(i * (a + 1.3)) * 7.0f;
        lc_scene_add_attribute(s, names[a], v, &err);
    }
    s->line_count = (uint32_t)rows;
    s->line_offsets = malloc((rows + 1) * sizeof(uint32_t));
    for (size_t l = 0; l <= rows; l++)
        s->line_offsets[l] = (uint32_t)(l * T);
    for (int k = 0; k < 4; k++) {
        char path[512];
        snprintf(path, sizeof path, "%s/round%d.nc", dir, k);
        CHECK(write_nc(s, path, k % 2, k < 2 ? 1 : 3, T) == NC_NOERR, "write %s", path);
        lc_scene *r = NULL;
        CHECK(lc_scene_load_file(path, &r, &err) == 0, "reload %s: %s", path, err.msg);
        if (r && r->vertex_count == s->vertex_count && r->line_count == s->line_count) {
            double worst = 0;
            for (size_t i = 0; i < 3 * (size_t)s->vertex_count; i++)
                worst = fmax(worst, fabs(r->positions[i] - s->positions[i]));
            CHECK(worst < 1e-5, "%s: positions differ by %g (z passes through exp and log)", path, worst);
            CHECK(memcmp(r->line_offsets, s->line_offsets, (rows + 1) * sizeof(uint32_t)) == 0, "%s: lines", path);
            for (int a = 0; a < 2; a++) {
                int j = lc_scene_find_attribute(r, names[a]);
                CHECK(j >= 0 && memcmp(r->attributes[j].values, s->attributes[a].values,
                                       s->vertex_count * sizeof(float)) == 0,
                      "%s: attribute %s identical", path, names[a]);
            }
        } else {
            CHECK(0, "%s: counts differ", path);
        }
        lc_scene_destroy(r);
        unlink(path);
    }
    lc_scene_destroy(s);
}

static void test_mutations(void)
{
    static const char *const files[] = {"nc/valid/trajectories.nc", "nc/valid/met3d.nc"};
    check_prefixes_and_mutations(DATA, files, sizeof files / sizeof *files, "\1\377\200CDF0 ", 0x51afd7ed558ccd1dull,
                                 load_memory);
}

/* A deflated NetCDF-4 file of constant trajectories: a few hundred KB that
 * declare millions of points. The reader counts them and refuses before
 * allocating what the load budget (64 times the file, at least 64 MB) does
 * not allow. */
static void test_inflating(const char *dir)
{
    enum { ROWS = 4000, T = 1000 };
    char path[256];
    snprintf(path, sizeof path, "%s/inflating.nc", dir);
    int nc, dims[2], ids[3];
    CHECK(nc_create(path, NC_CLOBBER | NC_NETCDF4, &nc) == NC_NOERR, "inflating.nc: not created");
    nc_def_dim(nc, "trajectory", ROWS, &dims[0]);
    nc_def_dim(nc, "time", T, &dims[1]);
    static const char *const pos[3] = {"lon", "lat", "pressure"};
    for (int k = 0; k < 3; k++) {
        nc_def_var(nc, pos[k], NC_FLOAT, 2, dims, &ids[k]);
        nc_def_var_deflate(nc, ids[k], 1, 1, 9);
    }
    nc_enddef(nc);
    float *row = malloc(T * sizeof *row);
    for (int k = 0; row && k < 3; k++)
        for (size_t r = 0; r < ROWS; r++) {
            for (size_t t = 0; t < T; t++)
                row[t] = k == 2 ? 900.0f : (float)t * 0.01f;
            size_t start[2] = {r, 0}, count[2] = {1, T};
            nc_put_vara_float(nc, ids[k], start, count, row);
        }
    free(row);
    nc_close(nc);
    lc_scene *sc = NULL;
    lc_error err = {0};
    int rc = lc_load_netcdf(path, &sc, &err);
    CHECK(rc == LC_ERR_LIMIT && !sc && strstr(err.msg, "refused before loading") &&
              strstr(err.msg, "4000000 points in 4000 trajectories"),
          "a deflated file declaring 4M points is refused before loading: rc %d, %s", rc, err.msg);
    lc_scene_destroy(sc);
    unlink(path);
}

int main(void)
{
    lc_log_set_level(LC_LOG_ERROR); /* the cases trigger expected warnings */
    char dir[] = "/tmp/lc_loaders_netcdf_XXXXXX";
    if (!mkdtemp(dir)) {
        perror("mkdtemp");
        return 1;
    }
    int cases = run_case_table(DATA "nc/", load_path, load_memory);
    CHECK(cases >= 7, "only %d NetCDF cases", cases);
    test_values();
    test_roundtrip(dir);
    test_mutations();
    test_inflating(dir);
    rmdir(dir);
    return lc_test_finish();
}
