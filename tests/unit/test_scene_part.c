/* lc_scene_read_file_part + lc_scene_finalize_part: 1..4 "processes" (threads
 * with a barrier-based lc_scene_collective) each read only their share of a
 * .binlines, .tck, .trx (directory), NetCDF (with and without an ensemble
 * dimension), polyline .vtk, .csv, LAMMPS .dump and point-cloud .ply file, or finalize
 * their share of a
 * point cloud cut by hand,
 * and every part must equal, array for array and bit for bit, the shard that
 * lc_scene_shard cuts from the whole scene finalized in one piece: positions,
 * line offsets, tangents, attribute values and statistics (min, max, 2nd/98th
 * percentiles, auto range: summed histograms must find the same values),
 * bounds, element blends and adjacency; and so after a collective element
 * rebuild (lc_scene_set_element_budget on parts). */
#include <math.h>
#include <netcdf.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "demo.h"
#include "lc_test.h"
#include "loaders.h"
#include "scene_part.h"
#include "scene_shard.h"

#define MAX_PARTS 4

/* ---- a collective over threads */

typedef struct group {
    int size;
    pthread_barrier_t barrier;
    const void *in[MAX_PARTS];
    size_t bytes[MAX_PARTS];
    int rc[MAX_PARTS];
    char msg[MAX_PARTS][LC_ERROR_MSG_LEN];
} group;

typedef struct member {
    group *g;
    int rank;
    lc_scene_collective c;
} member;

static int t_agree(void *ctx, int rc, lc_error *err)
{
    member *m = ctx;
    group *g = m->g;
    g->rc[m->rank] = rc;
    snprintf(g->msg[m->rank], LC_ERROR_MSG_LEN, "%s", rc && err ? err->msg : "");
    pthread_barrier_wait(&g->barrier);
    int out = 0;
    for (int r = 0; r < g->size && !out; r++)
        if (g->rc[r])
            out = lc_err(err, g->rc[r], "part %d: %s", r, g->msg[r]);
    pthread_barrier_wait(&g->barrier);
    return out;
}

/* Every member publishes its array; each combines all into a copy, then
 * (after everyone has read) writes the copy back. */
static int t_reduce(member *m, void *v, size_t n, int is_min)
{
    group *g = m->g;
    g->in[m->rank] = v;
    pthread_barrier_wait(&g->barrier);
    size_t each = is_min ? sizeof(double) : sizeof(uint64_t);
    unsigned char *out = malloc(n * each + 1);
    for (size_t i = 0; i < n; i++) {
        if (is_min) {
            double x = INFINITY;
            for (int r = 0; r < g->size; r++)
                x = fmin(x, ((const double *)g->in[r])[i]);
            ((double *)out)[i] = x;
        } else {
            uint64_t x = 0;
            for (int r = 0; r < g->size; r++)
                x += ((const uint64_t *)g->in[r])[i];
            ((uint64_t *)out)[i] = x;
        }
    }
    pthread_barrier_wait(&g->barrier);
    memcpy(v, out, n * each);
    free(out);
    return 0;
}

static int t_sum(void *ctx, uint64_t *v, size_t n, lc_error *err) { return (void)err, t_reduce(ctx, v, n, 0); }
static int t_min(void *ctx, double *v, size_t n, lc_error *err) { return (void)err, t_reduce(ctx, v, n, 1); }

static int t_gather(void *ctx, const void *mine, size_t bytes, void **all, uint64_t **bytes_out, lc_error *err)
{
    (void)err;
    member *m = ctx;
    group *g = m->g;
    uint64_t *bytes_of = *bytes_out = malloc((size_t)g->size * sizeof *bytes_of);
    g->in[m->rank] = mine;
    g->bytes[m->rank] = bytes;
    pthread_barrier_wait(&g->barrier);
    size_t total = 0;
    for (int r = 0; r < g->size; r++)
        total += g->bytes[r];
    unsigned char *out = malloc(total + 1);
    for (int r = 0, at = 0; r < g->size; r++) {
        memcpy(out + at, g->in[r], g->bytes[r]);
        at += (int)g->bytes[r];
        bytes_of[r] = g->bytes[r];
    }
    *all = out;
    pthread_barrier_wait(&g->barrier);
    return 0;
}

/* ---- comparing a part with a shard */

static int same_floats(const float *a, const float *b, size_t n)
{
    return n == 0 || (a && b && memcmp(a, b, n * sizeof(float)) == 0);
}

static void compare(const char *what, const lc_scene *part, const lc_scene *shard)
{
    uint32_t n = shard->vertex_count;
    CHECK(part->vertex_count == n && part->line_count == shard->line_count, "%s: %u vertices, %u lines (shard %u, %u)",
          what, part->vertex_count, part->line_count, n, shard->line_count);
    if (part->vertex_count != n || part->line_count != shard->line_count)
        return;
    CHECK(same_floats(part->positions, shard->positions, 3 * (size_t)n), "%s: positions", what);
    CHECK(shard->type != LC_PRIM_LINES ||
              memcmp(part->line_offsets, shard->line_offsets, (shard->line_count + 1) * sizeof(uint32_t)) == 0,
          "%s: line offsets", what);
    CHECK(!shard->tangents || same_floats(part->tangents, shard->tangents, 3 * (size_t)n), "%s: tangents", what);
    CHECK(memcmp(part->bounds, shard->bounds, sizeof part->bounds) == 0, "%s: bounds", what);
    CHECK(part->attribute_count == shard->attribute_count, "%s: %d attributes (shard %d)", what, part->attribute_count,
          shard->attribute_count);
    for (int i = 0; i < part->attribute_count && i < shard->attribute_count; i++) {
        const lc_attribute *a = &part->attributes[i], *b = &shard->attributes[i];
        CHECK(strcmp(a->name, b->name) == 0 && same_floats(a->values, b->values, n), "%s: attribute %s values", what,
              b->name);
        CHECK(a->min == b->min && a->max == b->max && a->p02 == b->p02 && a->p98 == b->p98 &&
                  a->auto_lo == b->auto_lo && a->auto_hi == b->auto_hi,
              "%s: attribute %s: min %g max %g p02 %g p98 %g auto %g..%g, whole %g %g %g %g %g..%g", what, b->name,
              a->min, a->max, a->p02, a->p98, a->auto_lo, a->auto_hi, b->min, b->max, b->p02, b->p98, b->auto_lo,
              b->auto_hi);
    }
    CHECK(strcmp(part->default_importance, shard->default_importance) == 0, "%s: default importance %s (shard %s)",
          what, part->default_importance, shard->default_importance);
    const lc_elements *e = &part->elements, *f = &shard->elements;
    CHECK(e->count == f->count && e->adjacency_count == f->adjacency_count, "%s: %u elements, %u adjacencies (%u, %u)",
          what, e->count, e->adjacency_count, f->count, f->adjacency_count);
    if (e->count != f->count || e->adjacency_count != f->adjacency_count)
        return;
    CHECK(memcmp(e->vertex_elements, f->vertex_elements, 4 * (size_t)n * sizeof(uint32_t)) == 0 &&
              same_floats(e->vertex_weights, f->vertex_weights, 4 * (size_t)n),
          "%s: vertex blends", what);
    CHECK(memcmp(e->adjacency_offsets, f->adjacency_offsets, ((size_t)f->count + 1) * sizeof(uint32_t)) == 0 &&
              (f->adjacency_count == 0 ||
               memcmp(e->adjacency, f->adjacency, (size_t)f->adjacency_count * sizeof(uint32_t)) == 0),
          "%s: adjacency", what);
    CHECK(part->part_of > 0 && part->whole_vertices > 0, "%s: marked as a part of %d", what, part->part_of);
    CHECK(part->lod_steps == shard->lod_steps, "%s: level-of-detail steps %#x (shard %#x)", what, part->lod_steps,
          shard->lod_steps);
    CHECK(part->vertex_base == shard->vertex_base, "%s: first vertex %llu of the whole (shard %llu)", what,
          (unsigned long long)part->vertex_base, (unsigned long long)shard->vertex_base);
}

/* ---- the processes */

typedef struct job {
    member m;
    const char *path;         /* read this share of the file, or */
    lc_scene *points;         /* finalize this un-finalized share */
    uint32_t budget, rebuild; /* elements at finalize; then a collective rebuild (0: none) */
    lc_scene *out;
    int rc;
    lc_error err;
} job;

/* libnetcdf is not thread-safe: the "processes" here are threads, so they
 * read one at a time (the reads are not collective; real ranks are processes). */
static pthread_mutex_t read_lock = PTHREAD_MUTEX_INITIALIZER;

static void *run(void *arg)
{
    job *j = arg;
    lc_scene *s = j->points;
    pthread_mutex_lock(&read_lock);
    int rc = j->path ? lc_scene_read_file_part(j->path, j->m.rank, j->m.g->size, &s, &j->err) : 0;
    pthread_mutex_unlock(&read_lock);
    rc = t_agree(&j->m, rc, &j->err);
    lc_elements_desc desc = {.line_budget = j->budget};
    if (rc == 0)
        rc = lc_scene_finalize_part(s, &desc, &j->m.c, &j->err);
    if (rc == 0 && j->rebuild)
        rc = lc_scene_set_element_budget(s, j->rebuild, &j->err);
    j->out = s;
    j->rc = rc;
    return NULL;
}

/* Runs size processes over path (or the point shares) and compares each part
 * with the shard of whole (finalized with the same budgets). */
static void run_parts(const char *what, const char *path, lc_scene **points, int size, const lc_scene *whole,
                      uint32_t budget, uint32_t rebuild)
{
    group g = {.size = size};
    pthread_barrier_init(&g.barrier, NULL, (unsigned)size);
    job jobs[MAX_PARTS];
    pthread_t th[MAX_PARTS];
    for (int r = 0; r < size; r++) {
        jobs[r] = (job){.path = path, .points = points ? points[r] : NULL, .budget = budget, .rebuild = rebuild};
        jobs[r].m = (member){.g = &g, .rank = r};
        jobs[r].m.c = (lc_scene_collective){.ctx = &jobs[r].m,
                                            .rank = r,
                                            .size = size,
                                            .agree = t_agree,
                                            .sum_u64 = t_sum,
                                            .min_f64 = t_min,
                                            .gather = t_gather};
        pthread_create(&th[r], NULL, run, &jobs[r]);
    }
    for (int r = 0; r < size; r++)
        pthread_join(th[r], NULL);
    pthread_barrier_destroy(&g.barrier);
    for (int r = 0; r < size; r++) {
        char label[160];
        snprintf(label, sizeof label, "%s, part %d of %d", what, r, size);
        CHECK(jobs[r].rc == 0, "%s: %s", label, jobs[r].err.msg);
        lc_scene *shard = NULL;
        lc_error err = {0};
        CHECK(lc_scene_shard(whole, r, size, &shard, &err) == 0, "%s: shard (%s)", label, err.msg);
        if (jobs[r].rc == 0 && shard)
            compare(label, jobs[r].out, shard);
        lc_scene_destroy(shard);
        lc_scene_destroy(jobs[r].out);
    }
}

/* ---- data */

static void put_u32(FILE *f, uint32_t v) { fwrite(&v, 4, 1, f); }
static void put_f32(FILE *f, float v) { fwrite(&v, 4, 1, f); }

/* Helices of 2..60 points with a "speed" attribute (three far outliers, a
 * stretch of equal values), a one-point line and a NaN point. */
static void write_binlines(const char *path, int lines)
{
    FILE *f = fopen(path, "wb");
    put_u32(f, 2), put_u32(f, (uint32_t)lines + 1), put_u32(f, 1);
    put_u32(f, 5), fwrite("speed", 1, 5, f);
    for (int k = 0; k <= lines; k++) {
        uint32_t n = k == 7 ? 1 : 2 + (uint32_t)(k * 37) % 59;
        put_u32(f, n);
        for (uint32_t i = 0; i < n; i++) {
            double t = n > 1 ? (double)i / (n - 1) : 0, a = 0.9 * k + 6 * t, r = 0.2 + 0.8 * fmod(0.618 * k, 1.0);
            put_f32(f, k == 11 && i == 1 ? NAN : (float)(r * cos(a)));
            put_f32(f, (float)(r * sin(a)));
            put_f32(f, (float)(fmod(0.377 * k, 1.0) + 0.6 * t));
        }
        for (uint32_t i = 0; i < n; i++)
            put_f32(f, k % 97 == 0 ? 1e4f : k % 13 == 0 ? 0.5f : (float)(k * 0.01 + i * 0.001));
    }
    fclose(f);
}

/* The same kind of helices as MRtrix .tck (positions only). */
static void write_tck(const char *path, int lines)
{
    FILE *f = fopen(path, "wb");
    char head[128];
    int off = 0, len;
    for (;;) { /* the offset's own digits move the offset */
        len =
            snprintf(head, sizeof head, "mrtrix tracks\ncount: %d\ndatatype: Float32LE\nfile: . %d\nEND\n", lines, off);
        if (len == off)
            break;
        off = len;
    }
    fwrite(head, 1, (size_t)len, f);
    for (int k = 0; k < lines; k++) {
        int n = 2 + (k * 29) % 45;
        for (int i = 0; i < n; i++) {
            double t = (double)i / (n - 1), a = 1.3 * k + 5 * t;
            put_f32(f, (float)cos(a)), put_f32(f, (float)sin(a)), put_f32(f, (float)(0.01 * k + t));
        }
        put_f32(f, NAN), put_f32(f, NAN), put_f32(f, NAN);
    }
    put_f32(f, INFINITY), put_f32(f, INFINITY), put_f32(f, INFINITY);
    fclose(f);
}

/* The same kind of helices as a TRX directory: float32 positions, uint64
 * offsets, a per-vertex and a per-streamline value, a NaN point, a
 * one-point streamline. */
static void write_trx(const char *dir, int lines)
{
    char path[256];
    mkdir(dir, 0755);
    snprintf(path, sizeof path, "%s/dpv", dir);
    mkdir(path, 0755);
    snprintf(path, sizeof path, "%s/dps", dir);
    mkdir(path, 0755);
    FILE *pos, *off, *dpv, *dps;
    snprintf(path, sizeof path, "%s/positions.3.float32", dir);
    pos = fopen(path, "wb");
    snprintf(path, sizeof path, "%s/offsets.uint64", dir);
    off = fopen(path, "wb");
    snprintf(path, sizeof path, "%s/dpv/speed.float32", dir);
    dpv = fopen(path, "wb");
    snprintf(path, sizeof path, "%s/dps/group.float32", dir);
    dps = fopen(path, "wb");
    uint64_t nv = 0;
    for (int k = 0; k < lines; k++) {
        fwrite(&nv, 8, 1, off);
        int n = k == 3 ? 1 : 2 + (k * 31) % 40;
        for (int i = 0; i < n; i++) {
            double t = n > 1 ? (double)i / (n - 1) : 0, a = 0.7 * k + 4 * t;
            put_f32(pos, k == 9 && i == 2 ? NAN : (float)cos(a)), put_f32(pos, (float)sin(a));
            put_f32(pos, (float)(0.02 * k + t));
            put_f32(dpv, k % 50 == 0 ? 1e5f : (float)(t + 0.01 * k));
        }
        put_f32(dps, (float)(k % 5));
        nv += (uint64_t)n;
    }
    fclose(pos), fclose(off), fclose(dpv), fclose(dps);
    snprintf(path, sizeof path, "%s/header.json", dir);
    FILE *h = fopen(path, "w");
    fprintf(h,
            "{\"NB_VERTICES\": %llu, \"NB_STREAMLINES\": %d, \"DIMENSIONS\": [1, 1, 1], "
            "\"VOXEL_TO_RASMM\": [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]}\n",
            (unsigned long long)nv, lines);
    fclose(h);
}

/* Trajectories as NetCDF: lon, lat, pressure (and a PV attribute) over
 * (ensemble, trajectory, time) when members > 1, else (trajectory, time);
 * some end early at a missing pressure, some are too short to keep. */
static int write_nc(const char *path, int members, size_t rows, size_t T)
{
    int nc, rc = nc_create(path, NC_CLOBBER, &nc);
    if (rc != NC_NOERR)
        return rc;
    int dims[3], nd = members > 1 ? 3 : 2, var[4];
    if (members > 1)
        nc_def_dim(nc, "ensemble", (size_t)members, &dims[0]);
    nc_def_dim(nc, "trajectory", rows / (size_t)members, &dims[nd - 2]);
    nc_def_dim(nc, "time", T, &dims[nd - 1]);
    static const char *const names[4] = {"lon", "lat", "pressure", "PV"};
    for (int k = 0; k < 4; k++)
        nc_def_var(nc, names[k], NC_DOUBLE, nd, dims, &var[k]);
    double fill = -999.0;
    nc_put_att_double(nc, var[2], "_FillValue", NC_DOUBLE, 1, &fill);
    nc_enddef(nc);
    double *buf = malloc(rows * T * sizeof *buf);
    for (int k = 0; k < 4; k++) {
        for (size_t r = 0; r < rows; r++)
            for (size_t t = 0; t < T; t++) {
                size_t end = r % 7 == 3 ? 1 : r % 5 == 2 ? T / 2 : T; /* short, cut, whole */
                double a = 0.3 * r + 0.2 * t;
                buf[r * T + t] = k == 0   ? 10 + 5 * cos(a)
                                 : k == 1 ? 40 + 5 * sin(a)
                                 : k == 2 ? (t < end ? 900 - 20.0 * t - r : fill)
                                          : (r % 11 == 0 ? 1e4 : 0.1 * t + 0.01 * r);
            }
        nc_put_var_double(nc, var[k], buf);
    }
    free(buf);
    return nc_close(nc);
}

/* A point table: a header, 5000 rows, a few with a missing coordinate
 * (dropped); with_attribute 0: positions alone (the parts derive a density
 * together). */
static void write_csv(const char *path, int with_attribute)
{
    FILE *f = fopen(path, "w");
    fprintf(f, "# a comment\nx,y,z%s\n", with_attribute ? ",temperature" : "");
    for (int i = 0; i < 5000; i++) {
        double a = i * 0.37, r = 1 + (i % 13) * 0.1;
        if (i % 401 == 7)
            fprintf(f, "%g,,%g", r * cos(a), 0.001 * i);
        else
            fprintf(f, "%g,%g,%g", r * cos(a), r * sin(a), 0.001 * i);
        if (with_attribute)
            fprintf(f, ",%g", i % 997 == 0 ? 1e6 : 15 + (i % 29));
        fputc('\n', f);
    }
    fclose(f);
}

/* A LAMMPS dump of `atoms` atoms over `frames` frames in a periodic box,
 * wrapped without image flags, listed in another order every frame; some
 * atoms miss a frame (their lines end) or appear once (no line). */
static void write_dump(const char *path, int atoms, int frames)
{
    FILE *f = fopen(path, "w");
    for (int t = 0; t < frames; t++) {
        int count = 0;
        for (int a = 0; a < atoms; a++)
            count += (a + t) % 17 != 0 && !(a % 23 == 0 && t > 0);
        fprintf(f,
                "ITEM: TIMESTEP\n%d\nITEM: NUMBER OF ATOMS\n%d\nITEM: BOX BOUNDS pp pp pp\n0 8\n0 8\n0 8\n"
                "ITEM: ATOMS type x y z id\n",
                t, count);
        for (int k = 0; k < atoms; k++) {
            int a = (k * 7 + t) % atoms; /* atoms and 7 coprime: a permutation */
            if ((a + t) % 17 == 0 || (a % 23 == 0 && t > 0))
                continue;
            double x = fmod(0.37 * a + 0.3 * t, 8), y = fmod(0.11 * a * a, 8),
                   z = fmod(0.05 * a + 0.7 * t * (a % 3), 8);
            fprintf(f, "%d %.4f %.4f %.4f %d\n", 1 + a % 4, x, y, z, 1000 + a);
        }
    }
    fclose(f);
}

/* Writes demo `name` (count) to path with save; 0 on success, else a failed check. */
static int write_demo(const char *name, uint64_t count, const char *path,
                      int (*save)(const lc_scene *, const char *, lc_error *))
{
    lc_error err = {0};
    lc_scene *demo = NULL;
    lc_demo_desc desc = {.count = count};
    int rc = lc_demo_create(name, &desc, &demo, &err);
    if (rc == 0)
        rc = save(demo, path, &err);
    CHECK(rc == 0, "demo %s as %s (%s)", name, path, err.msg);
    lc_scene_destroy(demo);
    return rc;
}

static lc_scene *load_whole(const char *path, uint32_t budget, uint32_t rebuild)
{
    lc_scene *s = NULL;
    lc_error err = {0};
    int rc = lc_scene_read_file(path, &s, &err);
    lc_elements_desc desc = {.line_budget = budget};
    if (rc == 0)
        rc = lc_scene_finalize(s, &desc, &err);
    if (rc == 0 && rebuild)
        rc = lc_scene_set_element_budget(s, rebuild, &err);
    CHECK(rc == 0, "%s: whole (%s)", path, err.msg);
    return rc == 0 ? s : NULL;
}

static void check_file(const char *path, uint32_t budget, uint32_t rebuild)
{
    lc_scene *whole = load_whole(path, budget, rebuild);
    if (!whole)
        return;
    for (int size = 1; size <= MAX_PARTS; size++) {
        char what[200];
        snprintf(what, sizeof what, "%s (budget %u, rebuild %u)", strrchr(path, '/') + 1, budget, rebuild);
        run_parts(what, path, NULL, size, whole, budget, rebuild);
    }
    lc_scene_destroy(whole);
}

/* A point cloud cut into the shares lc_scene_shard makes, un-finalized. */
static void check_points(void)
{
    lc_error err = {0};
    lc_scene *whole = NULL;
    lc_demo_desc desc = {.count = 5000};
    CHECK(lc_demo_create("points", &desc, &whole, &err) == 0, "points demo (%s)", err.msg);
    if (!whole)
        return;
    for (int size = 1; size <= MAX_PARTS; size++) {
        lc_scene *parts[MAX_PARTS];
        for (int r = 0; r < size; r++) {
            uint32_t a = lc_scene_split_points(whole->vertex_count, r, size);
            uint32_t b = lc_scene_split_points(whole->vertex_count, r + 1, size);
            lc_scene *p = parts[r] = lc_scene_create("points", LC_PRIM_POINTS);
            lc_scene_alloc_vertices(p, b - a, whole->rgb != NULL, &err);
            memcpy(p->positions, whole->positions + 3 * (size_t)a, 3 * (size_t)(b - a) * sizeof(float));
            if (whole->rgb)
                memcpy(p->rgb, whole->rgb + 3 * (size_t)a, 3 * (size_t)(b - a) * sizeof(float));
            for (int i = 0; i < whole->attribute_count; i++) {
                float *v = malloc(((size_t)(b - a) + 1) * sizeof *v);
                memcpy(v, whole->attributes[i].values + a, (size_t)(b - a) * sizeof *v);
                lc_scene_add_attribute(p, whole->attributes[i].name, v, &err);
            }
            memcpy(p->default_importance, whole->default_importance, sizeof p->default_importance);
            memcpy(p->default_color, whole->default_color, sizeof p->default_color);
        }
        run_parts("points", NULL, parts, size, whole, 0, 0);
    }
    lc_scene_destroy(whole);
}

int main(void)
{
    char dir[] = "/tmp/lucent-part-XXXXXX", bl[128], tck[128];
    if (!mkdtemp(dir))
        return 1;
    snprintf(bl, sizeof bl, "%s/helices.binlines", dir);
    snprintf(tck, sizeof tck, "%s/helices.tck", dir);
    write_binlines(bl, 400);
    write_tck(tck, 150);
    check_file(bl, 0, 0);
    check_file(bl, 900, 0);  /* a budget at load */
    check_file(bl, 0, 1500); /* a collective rebuild, as --elements and sidecars do */
    check_file(tck, 0, 0);
    char trx[128];
    snprintf(trx, sizeof trx, "%s/helices.trx", dir);
    write_trx(trx, 200);
    check_file(trx, 0, 0);
    char nc2[128], nc3[128];
    snprintf(nc2, sizeof nc2, "%s/trajectories.nc", dir);
    snprintf(nc3, sizeof nc3, "%s/members.nc", dir);
    CHECK(write_nc(nc2, 1, 90, 24) == NC_NOERR && write_nc(nc3, 3, 90, 24) == NC_NOERR, "NetCDF files written");
    check_file(nc2, 0, 0);
    check_file(nc3, 0, 0);
    char csv[128], xyz[128];
    snprintf(csv, sizeof csv, "%s/points.csv", dir);
    snprintf(xyz, sizeof xyz, "%s/bare.csv", dir);
    write_csv(csv, 1);
    write_csv(xyz, 0);
    check_file(csv, 0, 0);
    check_file(xyz, 0, 0);
    check_points();
    char dump[128];
    snprintf(dump, sizeof dump, "%s/atoms.dump", dir);
    write_dump(dump, 300, 12);
    check_file(dump, 0, 0);
    unlink(dump);

    /* A point cloud as PLY (every attribute a float property, colours as
     * uchar) and polylines as VTK (parsed whole, only the share's lines kept)
     * are read in parts; meshes are not (their patches need the whole). */
    char ply[128], vtk[128], mesh[128], vmesh[128];
    lc_error err = {0};
    snprintf(ply, sizeof ply, "%s/points.ply", dir);
    snprintf(vtk, sizeof vtk, "%s/tornado.vtk", dir);
    snprintf(mesh, sizeof mesh, "%s/surface.ply", dir);
    snprintf(vmesh, sizeof vmesh, "%s/surface.vtk", dir);
    if (write_demo("points", 7000, ply, lc_save_ply) == 0) {
        check_file(ply, 0, 0);
        CHECK(lc_scene_can_read_part(ply), "a point-cloud PLY is read in parts");
    }
    if (write_demo("tornado", 90, vtk, lc_save_vtk) == 0) {
        check_file(vtk, 0, 0);
        CHECK(lc_scene_can_read_part(vtk), "a VTK file with lines is read in parts");
    }
    if (write_demo("surface", 20, mesh, lc_save_ply) == 0 && write_demo("surface", 20, vmesh, lc_save_vtk) == 0) {
        CHECK(!lc_scene_can_read_part(mesh) && !lc_scene_can_read_part(vmesh), "PLY and VTK meshes are read whole");
        lc_scene *m = NULL;
        CHECK(lc_load_ply_part(mesh, 0, 2, &m, &err) == LC_ERR_UNSUPPORTED && !m, "PLY mesh in parts: %s", err.msg);
    }
    unlink(vmesh);

    /* Formats without a part reader say so; a part outside the processes is refused. */
    lc_scene *s = NULL;
    CHECK(lc_scene_read_file_part("x.vtk", 0, 2, &s, &err) == LC_ERR_UNSUPPORTED && !s, "vtk: %s", err.msg);
    CHECK(lc_scene_read_file_part(bl, 2, 2, &s, &err) == LC_ERR_INVALID && !s, "part 2 of 2: %s", err.msg);
    CHECK(lc_scene_can_read_part(tck) && lc_scene_can_read_part("a.TRK") && !lc_scene_can_read_part("a.vtk"),
          "part readers by extension");
    unlink(bl);
    unlink(tck);
    unlink(ply);
    unlink(mesh);
    unlink(vtk);
    unlink(nc2);
    unlink(nc3);
    unlink(csv);
    unlink(xyz);
    char cmd[300];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", trx);
    CHECK(system(cmd) == 0, "removing %s", trx);
    rmdir(dir);
    return lc_test_finish();
}
