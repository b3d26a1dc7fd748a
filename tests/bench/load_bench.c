/* Large-file load benchmark (not a pass/fail test): writes polylines of
 * 1, 4 and 16 million vertices (100 per line, one attribute) in every binary
 * format and loads each file in a fresh child process, printing the reader's
 * time, the finalize time (tangents, derived attributes, elements), the
 * scene's array memory and the child's peak RSS. A weighted checksum of the
 * loaded positions must match the written one within 1e-5 (TrackVis and
 * NetCDF positions pass through arithmetic), so a fast wrong load is caught.
 *
 *   load_bench [--sizes 1,4,16] [--formats tck,trx,...] [--dir /tmp] [--no-finalize]
 */
#include <math.h>
#include <netcdf.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>
#include <zip.h>

#include "loaders.h"
#include "scene.h"

#define PER_LINE 100

static lc_scene *make_lines(uint32_t n)
{
    lc_error err = {0};
    lc_scene *s = lc_scene_create("bench", LC_PRIM_LINES);
    if (!s || lc_scene_alloc_vertices(s, n, 0, &err) != 0)
        return NULL;
    uint32_t lines = n / PER_LINE;
    for (uint32_t l = 0; l < lines; l++) { /* helices on a grid: smooth lines of varied curvature */
        float cx = (float)(l % 512), cy = (float)(l / 512);
        for (uint32_t i = 0; i < PER_LINE; i++) {
            float *p = s->positions + 3 * ((size_t)l * PER_LINE + i);
            float t = (float)i * 0.1f;
            p[0] = cx + 0.4f * cosf(t + (float)l);
            p[1] = cy + 0.4f * sinf(t + (float)l);
            p[2] = t;
        }
    }
    float *fa = malloc((size_t)n * sizeof *fa);
    for (uint32_t i = 0; i < n; i++)
        fa[i] = (float)(i % 1000) / 1000.0f;
    lc_scene_add_attribute(s, "fa", fa, &err);
    s->line_count = lines;
    s->line_offsets = malloc(((size_t)lines + 1) * sizeof(uint32_t));
    for (uint32_t l = 0; l <= lines; l++)
        s->line_offsets[l] = l * PER_LINE;
    return s;
}

static double checksum(const lc_scene *s)
{
    double sum = 0;
    for (size_t i = 0; i < 3 * (size_t)s->vertex_count; i++)
        sum += s->positions[i] * (double)(1 + i % 7);
    return sum;
}

static int write_tck(const lc_scene *s, const char *path)
{
    FILE *f = fopen(path, "wb");
    if (!f)
        return -1;
    char head[128];
    int n = snprintf(head, sizeof head, "mrtrix tracks\ncount: %010u\ndatatype: Float32LE\nfile: . ", s->line_count);
    fprintf(f, "%s%03d\nEND\n", head, n + 8); /* three offset digits, "\nEND\n" */
    static const float sep[3] = {NAN, NAN, NAN}, end[3] = {INFINITY, INFINITY, INFINITY};
    for (uint32_t l = 0; l < s->line_count; l++) {
        uint32_t a = s->line_offsets[l], b = s->line_offsets[l + 1];
        fwrite(s->positions + 3 * (size_t)a, sizeof(float), 3 * (size_t)(b - a), f);
        fwrite(sep, sizeof sep, 1, f);
    }
    fwrite(end, sizeof end, 1, f);
    return fclose(f);
}

static int write_binlines(const lc_scene *s, const char *path)
{
    FILE *f = fopen(path, "wb");
    if (!f)
        return -1;
    uint32_t head[3] = {2, s->line_count, 1}, len = 2;
    fwrite(head, sizeof head, 1, f);
    fwrite(&len, 4, 1, f);
    fwrite("fa", 1, 2, f);
    for (uint32_t l = 0; l < s->line_count; l++) {
        uint32_t a = s->line_offsets[l], n = s->line_offsets[l + 1] - a;
        fwrite(&n, 4, 1, f);
        fwrite(s->positions + 3 * (size_t)a, sizeof(float), 3 * (size_t)n, f);
        fwrite(s->attributes[0].values + a, sizeof(float), n, f);
    }
    return fclose(f);
}

static int write_trk(const lc_scene *s, const char *path)
{
    unsigned char h[1000] = {0};
    memcpy(h, "TRACK", 5);
    float vs[3] = {1, 1, 1};
    memcpy(h + 12, vs, sizeof vs);
    int16_t ns = 1;
    memcpy(h + 36, &ns, 2);
    memcpy(h + 38, "fa", 2);
    memcpy(h + 948, "RAS", 3);
    float v2r[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
    memcpy(h + 440, v2r, sizeof v2r);
    int32_t tail[3] = {(int32_t)s->line_count, 2, 1000};
    memcpy(h + 988, tail, sizeof tail);
    FILE *f = fopen(path, "wb");
    if (!f)
        return -1;
    fwrite(h, 1, sizeof h, f);
    float *rec = malloc(4 * sizeof(float) * PER_LINE);
    for (uint32_t l = 0; l < s->line_count; l++) {
        uint32_t a = s->line_offsets[l], n = s->line_offsets[l + 1] - a;
        for (uint32_t i = 0; i < n; i++) { /* voxel-mm = RAS + 0.5 with unit voxels and an identity vox_to_ras */
            for (int k = 0; k < 3; k++)
                rec[4 * i + k] = s->positions[3 * (size_t)(a + i) + k] + 0.5f;
            rec[4 * i + 3] = s->attributes[0].values[a + i];
        }
        fwrite(&n, 4, 1, f);
        fwrite(rec, sizeof(float), 4 * (size_t)n, f);
    }
    free(rec);
    return fclose(f);
}

static int write_trx(const lc_scene *s, const char *path)
{
    int ze;
    zip_t *z = zip_open(path, ZIP_CREATE | ZIP_TRUNCATE, &ze);
    if (!z)
        return -1;
    static char header[128];
    snprintf(header, sizeof header, "{\"NB_VERTICES\": %u, \"NB_STREAMLINES\": %u}", s->vertex_count, s->line_count);
    const char *names[4] = {"header.json", "positions.3.float32", "offsets.uint32", "dpv/fa.float32"};
    const void *data[4] = {header, s->positions, s->line_offsets, s->attributes[0].values};
    size_t sizes[4] = {strlen(header), 12 * (size_t)s->vertex_count, 4 * (size_t)s->line_count,
                       4 * (size_t)s->vertex_count};
    for (int i = 0; i < 4; i++) {
        zip_source_t *src = zip_source_buffer(z, data[i], sizes[i], 0);
        zip_int64_t idx = zip_file_add(z, names[i], src, ZIP_FL_OVERWRITE);
        zip_set_file_compression(z, (zip_uint64_t)idx, ZIP_CM_STORE, 0);
    }
    return zip_close(z);
}

static int write_nc(const lc_scene *s, const char *path)
{
    int nc, dims[2], var[4];
    if (nc_create(path, NC_CLOBBER | NC_64BIT_DATA, &nc) != NC_NOERR)
        return -1;
    nc_def_dim(nc, "trajectory", s->line_count, &dims[0]);
    nc_def_dim(nc, "time", PER_LINE, &dims[1]);
    static const char *const names[4] = {"lon", "lat", "pressure", "fa"};
    for (int k = 0; k < 4; k++)
        nc_def_var(nc, names[k], NC_FLOAT, 2, dims, &var[k]);
    nc_enddef(nc);
    float *buf = malloc((size_t)s->vertex_count * sizeof *buf);
    for (int k = 0; k < 3; k++) {
        for (size_t i = 0; i < s->vertex_count; i++)
            buf[i] = k < 2 ? s->positions[3 * i + k] : (float)(1013.25 * exp(-s->positions[3 * i + 2] / 10.0));
        nc_put_var_float(nc, var[k], buf);
    }
    nc_put_var_float(nc, var[3], s->attributes[0].values);
    free(buf);
    return nc_close(nc) == NC_NOERR ? 0 : -1;
}

typedef struct format {
    const char *name, *ext;
    int (*write)(const lc_scene *, const char *);
} format;

static int save_ply(const lc_scene *s, const char *path)
{
    lc_error err = {0};
    return lc_save_ply(s, path, &err);
}

static int save_vtk(const lc_scene *s, const char *path)
{
    lc_error err = {0};
    return lc_save_vtk(s, path, &err);
}

static const format formats[] = {{"ply", "ply", save_ply},  {"vtk", "vtk", save_vtk},
                                 {"trk", "trk", write_trk}, {"tck", "tck", write_tck},
                                 {"trx", "trx", write_trx}, {"binlines", "binlines", write_binlines},
                                 {"netcdf", "nc", write_nc}};

/* In a fresh process (load_bench --child PATH CHECKSUM FINALIZE, so that its
 * peak RSS is its own): load, print one line, exit. */
static int measure(const char *path, int finalize, double want_sum)
{
    lc_error err = {0};
    lc_scene *s = NULL;
    double t0 = lc_now();
    const char *dot = strrchr(path, '.');
    int rc = -1;
    for (size_t i = 0; i < sizeof formats / sizeof *formats; i++)
        if (strcmp(dot + 1, formats[i].ext) == 0) {
            rc = lc_scene_read_file(path, &s, &err); /* the reader alone, no finalize */
        }
    double t1 = lc_now();
    double fin = 0;
    if (rc == 0 && finalize) {
        lc_error ferr = {0};
        if (lc_scene_finalize(s, NULL, &ferr) != 0)
            rc = -2;
        fin = lc_now() - t1;
    }
    struct rusage ru;
    getrusage(RUSAGE_SELF, &ru);
    char line[512];
    if (rc == 0) {
        double sum = checksum(s);
        snprintf(line, sizeof line, "%9.0f %11.0f %12.1f %12.1f  %s\n", (t1 - t0) * 1e3, fin * 1e3,
                 lc_scene_bytes(s) / 1048576.0, ru.ru_maxrss / 1024.0,
                 fabs(sum - want_sum) <= 1e-5 * fabs(want_sum) ? "ok" : "CHECKSUM MISMATCH");
    } else {
        snprintf(line, sizeof line, "failed: %s\n", err.msg);
    }
    fputs(line, stdout);
    return rc == 0 ? 0 : 1;
}

int main(int argc, char **argv)
{
    if (argc == 5 && strcmp(argv[1], "--child") == 0) {
        lc_log_set_level(LC_LOG_ERROR);
        return measure(argv[2], atoi(argv[4]), strtod(argv[3], NULL));
    }
    const char *sizes = "1,4,16", *only = NULL, *dir = "/tmp";
    int finalize = 1;
    for (int i = 1; i < argc; i++) {
        if (strcmp(argv[i], "--sizes") == 0 && i + 1 < argc)
            sizes = argv[++i];
        else if (strcmp(argv[i], "--formats") == 0 && i + 1 < argc)
            only = argv[++i];
        else if (strcmp(argv[i], "--dir") == 0 && i + 1 < argc)
            dir = argv[++i];
        else if (strcmp(argv[i], "--no-finalize") == 0)
            finalize = 0;
        else {
            fprintf(stderr, "usage: load_bench [--sizes 1,4,16] [--formats ply,vtk,trk,tck,trx,binlines,netcdf] "
                            "[--dir /tmp] [--no-finalize]\n");
            return 2;
        }
    }
    lc_log_set_level(LC_LOG_ERROR);
    printf("%-9s %9s %9s %9s %11s %12s %12s  %s\n", "format", "vertices", "file MB", "read ms", "finalize ms",
           "arrays MiB", "peak RSS MiB", "check");
    for (const char *p = sizes; *p;) {
        uint32_t n = (uint32_t)(strtoul(p, NULL, 10) * 1000000ul / PER_LINE * PER_LINE);
        lc_scene *s = make_lines(n);
        if (!s) {
            fprintf(stderr, "out of memory for %u vertices\n", n);
            return 1;
        }
        double want = checksum(s);
        for (size_t f = 0; f < sizeof formats / sizeof *formats; f++) {
            if (only && !strstr(only, formats[f].name))
                continue;
            char path[512];
            snprintf(path, sizeof path, "%s/lucent_bench_%u.%s", dir, n, formats[f].ext);
            if (formats[f].write(s, path) != 0) {
                printf("%-9s %9u write failed\n", formats[f].name, n);
                continue;
            }
            struct stat st;
            stat(path, &st);
            int fds[2];
            if (pipe(fds) != 0)
                return 1;
            fflush(stdout);
            pid_t pid = fork();
            if (pid == 0) {
                char sum[64], fin[8];
                snprintf(sum, sizeof sum, "%.17g", want);
                snprintf(fin, sizeof fin, "%d", finalize);
                dup2(fds[1], 1);
                close(fds[0]);
                execl("/proc/self/exe", argv[0], "--child", path, sum, fin, (char *)NULL);
                _exit(127);
            }
            close(fds[1]);
            char line[512] = "";
            ssize_t got = read(fds[0], line, sizeof line - 1);
            close(fds[0]);
            waitpid(pid, NULL, 0);
            printf("%-9s %9u %9.1f %s", formats[f].name, n, st.st_size / 1e6, got > 0 ? line : "child died\n");
            unlink(path);
        }
        lc_scene_destroy(s);
        const char *comma = strchr(p, ',');
        if (!comma)
            break;
        p = comma + 1;
    }
    return 0;
}
