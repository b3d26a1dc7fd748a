/* Line clustering benchmark (not a pass/fail test): for each line count,
 * the resampling, the dendrogram build (with its pruning figures) and a cut
 * per representative, then a Fourier frame's GPU time per pass with every
 * line and with the cut, against DLS Table 1's stages. A cut that does not
 * return the asked count fails the run, so a fast wrong result is caught.
 *
 *   cluster_bench [--demo tornado] [--lines 1000,10000] [--clusters 1000] [--size 1024] [--no-gpu]
 *   cluster_bench --file PATH ...   a real line file, whole (--lines is ignored)
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "cluster.h"
#include "demo.h"
#include "gl_context.h"
#include "loaders.h"
#include "renderer.h"

static double now(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

static void frame(lc_renderer *r, const lc_gpu_scene *gs, int size, int clusters, uint8_t *rgba)
{
    lc_render_params p;
    lc_render_params_default(&p);
    p.width = p.height = size;
    p.clusters.count = clusters;
    lc_frame_info info;
    lc_error err = {0};
    /* The first frame builds the dendrogram (and compiles); the second is timed. */
    for (int i = 0; i < 2; i++)
        if (lc_render_frame(r, gs, &p, NULL, 0, rgba, &info, &err) != 0) {
            fprintf(stderr, "frame: %s\n", err.msg);
            exit(1);
        }
    printf("  frame %dx%d, clusters %d: GPU %.2f ms (", size, size, clusters, info.gpu_ms);
    for (int k = 0; k < LC_PASS_COUNT; k++)
        if (info.pass_ms[k] >= 0)
            printf("%s %.2f ", lc_pass_name(k), info.pass_ms[k]);
    printf("), wall %.1f ms\n", info.wall_ms);
}

int main(int argc, char **argv)
{
    const char *demo = "tornado", *lines = "1000,10000", *file = NULL;
    int clusters = 1000, size = 1024, gpu = 1;
    for (int i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--demo") && i + 1 < argc)
            demo = argv[++i];
        else if (!strcmp(argv[i], "--file") && i + 1 < argc)
            file = argv[++i], lines = "0";
        else if (!strcmp(argv[i], "--lines") && i + 1 < argc)
            lines = argv[++i];
        else if (!strcmp(argv[i], "--clusters") && i + 1 < argc)
            clusters = atoi(argv[++i]);
        else if (!strcmp(argv[i], "--size") && i + 1 < argc)
            size = atoi(argv[++i]);
        else if (!strcmp(argv[i], "--no-gpu"))
            gpu = 0;
        else {
            fprintf(stderr, "usage: cluster_bench [--demo NAME | --file PATH] [--lines N,N] [--clusters K] [--size PX] "
                            "[--no-gpu]\n");
            return 2;
        }
    }
    lc_gl *gl = NULL;
    lc_renderer *r = NULL;
    lc_error err = {0};
    if (gpu && (lc_gl_create(&(lc_gl_desc){.device = -1}, &gl, &err) != 0 || lc_gl_make_current(gl, &err) != 0 ||
                lc_renderer_create(NULL, &r, &err) != 0)) {
        fprintf(stderr, "GL: %s (use --no-gpu)\n", err.msg);
        return 1;
    }
    uint8_t *rgba = gpu ? malloc((size_t)size * size * 4) : NULL;
    for (const char *s = lines; *s;) {
        uint32_t n = (uint32_t)strtoul(s, NULL, 10);
        lc_scene *sc = NULL;
        if (file ? lc_scene_load_file(file, &sc, &err) != 0
                 : lc_demo_create(demo, &(lc_demo_desc){.count = n}, &sc, &err) != 0) {
            fprintf(stderr, "%s: %s\n", file ? file : demo, err.msg);
            return 1;
        }
        if (sc->type != LC_PRIM_LINES) {
            fprintf(stderr, "%s: not a line dataset\n", file ? file : demo);
            return 1;
        }
        printf("%s%s, %u lines, %u vertices\n", file ? "" : "demo:", file ? file : demo, sc->line_count,
               sc->vertex_count);
        double t0 = now();
        clock_t c0 = clock(); /* process CPU time, all threads: the wall time depends on the host's load */
        lc_line_samples *ls = NULL;
        if (lc_line_samples_create(sc->positions, sc->line_offsets, sc->line_count, 0, NULL, 0, &ls, &err) != 0)
            return 1;
        double t1 = now();
        lc_dendrogram *d = NULL;
        if (lc_dendrogram_build_samples(ls, NULL, &d, &err) != 0) {
            fprintf(stderr, "%s\n", err.msg);
            return 1;
        }
        double t2 = now(), cpu = (double)(clock() - c0) / CLOCKS_PER_SEC;
        lc_cluster_stats st;
        lc_dendrogram_stats(d, &st);
        printf("  resample %.1f ms; build %.2f s wall, resample + build %.2f s CPU (%u attempt(s), radius %.4g, %llu "
               "pairs measured, %u top clusters)\n",
               1e3 * (t1 - t0), t2 - t1, cpu, st.attempts, st.prune_radius, (unsigned long long)st.pairs_tested,
               st.top_clusters);
        if (st.sampled_lines)
            printf("  sampled: %u lines clustered, the other %u attached\n", st.sampled_lines,
                   sc->line_count - st.sampled_lines);
        uint8_t *keep = malloc(sc->line_count);
        for (int rep = 0; rep < 3; rep++) {
            double a = now();
            int k = lc_dendrogram_mask(d, (uint32_t)clusters, (lc_representative)rep, NULL, keep, &err);
            uint32_t want = (uint32_t)clusters < sc->line_count ? (uint32_t)clusters : sc->line_count;
            if (k != (int)want) {
                fprintf(stderr, "cut returned %d clusters, want %u\n", k, want);
                return 1;
            }
            printf("  cut into %d, %s: %.2f ms\n", k, lc_representative_name((lc_representative)rep),
                   1e3 * (now() - a));
        }
        free(keep);
        lc_dendrogram_destroy(d);
        lc_line_samples_destroy(ls);
        if (gpu) {
            lc_gpu_scene *gs = NULL;
            if (lc_gpu_scene_create(sc, &gs, &err) != 0) {
                fprintf(stderr, "upload: %s\n", err.msg);
                return 1;
            }
            frame(r, gs, size, 0, rgba);
            frame(r, gs, size, clusters, rgba);
            lc_gpu_scene_destroy(gs);
        }
        lc_scene_destroy(sc);
        s = strchr(s, ',');
        s = s ? s + 1 : "";
    }
    free(rgba);
    if (gpu) {
        lc_renderer_destroy(r);
        lc_gl_release_current(gl);
        lc_gl_destroy(gl);
    }
    return 0;
}
