/* `lucent bench`: renders each demo dataset and prints per-pass times, frames
 * per second and the GPU memory of the pipeline. Figures, not a test. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"
#include "demo.h"

/* The flags of `lucent bench` besides the shared ones (cli.c). */
typedef struct bench_args {
    int frames, warmup, memory, interactive, point_stride, uniform_points, line_stride, floor;
    const char *datasets;
} bench_args;

#define BENCH(member) LC_OPT_AT(bench_args, member)
static const lc_option bench_options[] = {
    {"--frames", "N", LC_OPT_INT, BENCH(frames), 1, 100000, .help = "timed frames per dataset (default 10)"},
    {"--warmup", "N", LC_OPT_INT, BENCH(warmup), 0, 100000, .help = "untimed frames before them (default 2)"},
    {"--datasets", "A,B,...", LC_OPT_TEXT, BENCH(datasets), .help = "the datasets (default: every demo)"},
    {"--memory", NULL, LC_OPT_BOOL, BENCH(memory),
     .help = "print each dataset's bytes per vertex by kind (CPU arrays, GPU\n"
             "buffers, state)"},
    {"--interactive", NULL, LC_OPT_BOOL, BENCH(interactive),
     .help = "time the frames a session renders while the camera moves: the\n"
             "opacities of the first warm-up frame are reused (P1-P3 skipped)"},
    {"--point-stride", "N", LC_OPT_INT, BENCH(point_stride), 1, 1024,
     .help = "with --interactive, points: the most important 1/(4N) in full,\n"
             "every N-th of the rest"},
    {"--uniform-points", NULL, LC_OPT_BOOL, BENCH(uniform_points),
     .help = "with --point-stride: every N-th of all points"},
    {"--floor", NULL, LC_OPT_BOOL, BENCH(floor),
     .help = "per geometry pass, one-shot stills timed three ways, alternated\n"
             "frame by frame: shaded, with an empty fragment shader and with\n"
             "GL_RASTERIZER_DISCARD (medians; docs/EVALUATION.md, the geometry path)"},
    {"--line-stride", "N", LC_OPT_INT, BENCH(line_stride), 1, 1024,
     .help = "with --interactive, lines: the most important 1/(4N) in full,\n"
             "every N-th of the rest (whole lines)"},
    {NULL}};

static void bench_usage(FILE *f, const lc_opt_set *sets, int nsets)
{
    fprintf(f,
            "usage: lucent bench [--size WxH] [--frames N] [--warmup N] [--datasets a,b,...] [--memory] [--device N]\n"
            "                    [--interactive [--point-stride N [--uniform-points]]] [--floor] [flags]\n"
            "Renders every demo dataset (default 1024x1024, 10 timed frames after 2 warm-up frames) with a\n"
            "fading frame state, as an interactive session would, and prints the mean per-pass GPU times.\n"
            "--dataset SPEC (or a --request file's dataset) benches that one; --datasets a,b,... a list.\n"
            "With --interactive, --lod PX (lines) and --point-stride N (points) set the coarser detail\n"
            "of those frames.\n");
    lc_opt_usage(f, sets, nsets);
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

static double median(double *v, int n)
{
    qsort(v, (size_t)n, sizeof *v, cmp_double);
    return n ? (n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2])) : 0.0;
}

/* --floor: where a geometry pass's time goes. One-shot stills (no frame
 * state: what a still costs), the three modes of lc_renderer_set_floor
 * alternated frame by frame so that a busy host spreads over all three;
 * medians of `frames` rounds after one warm-up frame per mode (which also
 * compiles the empty shaders). */
static int bench_floor(lc_cli_gl *g, const lc_gpu_scene *gs, const lc_scene *s, const lc_render_params *params,
                       int frames, uint8_t *rgba, lc_error *err)
{
    enum { MODES = LC_FLOOR_COUNT, COLS = LC_PASS_COUNT + 2 }; /* passes, gpu, wall */
    double *t = calloc((size_t)MODES * COLS * (size_t)frames, sizeof *t);
    if (!t)
        return lc_err(err, LC_ERR_NOMEM, "out of memory");
    lc_frame_info info = {0};
    int rc = 0, ran[LC_PASS_COUNT] = {0}, tries[LC_FLOOR_COUNT] = {0}, listed[LC_FLOOR_COUNT] = {0},
        summed[LC_FLOOR_COUNT] = {0};
    for (int f = -1; f < frames && !rc; f++)
        for (int m = 0; m < MODES && !rc; m++) {
            lc_renderer_set_floor(g->renderer, (lc_floor_mode)m);
            rc = lc_render_frame(g->renderer, gs, params, NULL, 0.0, rgba, &info, err);
            if (rc || f < 0)
                continue;
            tries[m] = info.clarity_tries;
            listed[m] = info.opacity_from_list;
            summed[m] = info.importance_from_list;
            double *row = t + ((size_t)m * COLS) * frames;
            /* Per traversal: the clarity loop runs P2 (and P3) once a try. */
            int per = info.clarity_tries > 1 ? info.clarity_tries : 1;
            for (int p = 0; p < LC_PASS_COUNT; p++) {
                row[(size_t)p * frames + f] = info.pass_ms[p] / (p == LC_PASS_OPACITY ? per : 1);
                ran[p] |= info.pass_ms[p] >= 0;
            }
            row[(size_t)LC_PASS_COUNT * frames + f] = info.gpu_ms;
            row[(size_t)(LC_PASS_COUNT + 1) * frames + f] = info.wall_ms;
        }
    lc_renderer_set_floor(g->renderer, LC_FLOOR_FULL);
    if (!rc) {
        printf("%s: %llu primitives, %dx%d, medians of %d rounds (ms)\n", s->name,
               (unsigned long long)lc_scene_primitive_count(s), params->width, params->height, frames);
        printf("  %-14s", "pass");
        for (int m = 0; m < MODES; m++)
            printf(" %13s", lc_floor_mode_name((lc_floor_mode)m));
        printf(" %9s\n", "shading");
        for (int c = 0; c < COLS; c++) {
            if (c < LC_PASS_COUNT && !ran[c])
                continue;
            double med[MODES];
            for (int m = 0; m < MODES; m++)
                med[m] = median(t + ((size_t)m * COLS + c) * frames, frames);
            printf("  %-14s", c < LC_PASS_COUNT ? lc_pass_name(c) : c == LC_PASS_COUNT ? "gpu total" : "wall");
            for (int m = 0; m < MODES; m++)
                printf(" %13.1f", med[m]);
            printf(" %8.0f%%\n", med[0] > 0 ? 100.0 * (med[0] - med[1]) / med[0] : 0.0);
        }
        printf("  (shading: the share of the shaded time above the empty shader's; opacity: one P2, the mean\n"
               "  over the clarity loop's tries, %d, %d and %d a frame)\n",
               tries[0], tries[1], tries[2]);
        printf("  P1: %s\n", summed[0] ? "a compute pass over P0's fragments (no traversal)" : "drawn (a traversal)");
        printf("  P2: %s\n\n", listed[0] ? "a compute pass over P1's fragment list (no traversal)" : "drawn (a traversal)");
    }
    free(t);
    return rc;
}

int lc_cli_bench(int argc, char **argv)
{
    lc_request req;
    lc_cli_common common;
    bench_args args = {.frames = 10, .warmup = 2, .point_stride = 1, .line_stride = 1};
    int pr = lc_cli_parse("bench", bench_options, &args, argc, argv, &req, &common, bench_usage);
    if (pr != 0)
        return pr == 1 ? 0 : 2;
    if (req.layer_count > 0) { /* a row a dataset: a layered frame is no dataset's */
        fprintf(stderr,
                "lucent bench: layers: bench times one dataset a row; `lucent render --request FILE --frames N` "
                "or `lucent compare --request FILE` time a layered request\n");
        return 2;
    }
    if (!common.request) { /* the benchmark's own default size, unless a flag gave one */
        req.render.width = common.width_set ? req.render.width : 1024;
        req.render.height = common.height_set ? req.render.height : 1024;
    }
    int frames = args.frames, warmup = args.warmup, show_memory = args.memory, interactive = args.interactive,
        point_stride = args.point_stride, uniform_points = args.uniform_points, line_stride = args.line_stride;
    int have_list = args.datasets != NULL, have_one = common.input || common.dataset_set;
    char datasets[512] = "";
    if (have_list && strlen(args.datasets) >= sizeof datasets) {
        fprintf(stderr, "lucent bench: --datasets: at most %zu bytes\n", sizeof datasets - 1);
        return 2;
    }
    if (have_list)
        snprintf(datasets, sizeof datasets, "%s", args.datasets);
    else
        for (const char *const *d = lc_demo_names(); *d; d++)
            snprintf(datasets + strlen(datasets), sizeof datasets - strlen(datasets), "%sdemo:%s",
                     datasets[0] ? "," : "", *d);
    /* Every flag is used or refused, never silently ignored. */
    if (have_one && have_list) {
        fprintf(stderr, "lucent bench: give --dataset or --datasets, not both\n");
        return 2;
    }
    if ((point_stride > 1 || line_stride > 1) && !interactive) {
        fprintf(stderr, "lucent bench: --%s-stride applies to --interactive frames only\n",
                point_stride > 1 ? "point" : "line");
        return 2;
    }
    if (args.floor && interactive) {
        fprintf(stderr, "lucent bench: --floor times one-shot stills, not --interactive frames\n");
        return 2;
    }
    if (uniform_points && point_stride <= 1) {
        fprintf(stderr, "lucent bench: --uniform-points applies to --point-stride N > 1 only\n");
        return 2;
    }
    lc_error err = {0};
    lc_cli_gl g;
    /* One dataset named by --input, --dataset or the request file, unless a list was given. */
    if (common.input)
        snprintf(datasets, sizeof datasets, "%s", common.input);
    else if (req.dataset[0] && !have_list)
        snprintf(datasets, sizeof datasets, "%s", req.dataset);
    if (lc_cli_gl_open(common.device, &g, &err) != 0) {
        fprintf(stderr, "lucent bench: %s\n", err.msg);
        return 1;
    }
    printf("renderer: %s | %s | %s\n", lc_gl_renderer(g.gl), lc_gl_version(g.gl), lc_gl_platform(g.gl));
    if (interactive && warmup < 1)
        warmup = 1; /* the frame whose opacities the timed ones reuse */
    printf("%dx%d, method %s, m=%d, %s estimator, s=%d, P1/P2 scale %.2f, lod %.2g px, %d frames (+%d warm-up)%s\n\n",
           req.render.width, req.render.height, lc_method_name(req.render.method), req.render.foo.bands,
           lc_estimator_name(req.render.foo.estimator), req.render.foo.smoothing, req.render.foo.resolution_scale,
           req.render.detail.lod_pixels, frames, warmup, interactive ? ", interactive (opacities reused)" : "");
    if (!args.floor) {
        printf("%-16s %10s %9s", "dataset", "primitives", "elements");
        for (int p = 0; p < LC_PASS_COUNT; p++)
            printf(" %12s", lc_pass_name(p));
        printf(" %9s %8s %7s %11s %11s %10s %8s %9s %10s\n", "gpu ms", "wall ms", "fps", "pipeline MB", "scene MB",
               "drawn", "load s", "rss MB", "rss B/vtx");
    }

    int status = 0;
    uint8_t *rgba = malloc((size_t)req.render.width * req.render.height * 4);
    char *list = strdup(datasets), *save = NULL;
    for (char *spec = strtok_r(list, ",", &save); spec && rgba; spec = strtok_r(NULL, ",", &save)) {
        lc_scene *s = NULL;
        lc_gpu_scene *gs = NULL;
        lc_frame_state *st = NULL;
        /* Resident memory before the dataset: the growth while it renders is its own. */
        uint64_t rss_before = lc_cli_resident_bytes();
        double t_load = lc_now();
        if (lc_cli_open_dataset(spec, &s, &err) != 0 ||
            (common.elements && lc_scene_set_element_budget(s, (uint32_t)common.elements, &err) != 0)) {
            fprintf(stderr, "lucent bench: %s: %s\n", spec, err.msg);
            status = 1;
        } else if (lc_cli_upload("bench", &common, s, &gs) != 0 ||
                   !(st = lc_cli_frame_state(&common, s->elements.count))) {
            if (gs)
                fprintf(stderr, "lucent bench: %s: out of memory\n", spec);
            status = 1;
        } else {
            t_load = lc_now() - t_load;
            if (args.floor) {
                if (bench_floor(&g, gs, s, &req.render, frames, rgba, &err) != 0) {
                    fprintf(stderr, "lucent bench: %s: %s\n", spec, err.msg);
                    status = 1;
                }
                lc_frame_state_destroy(st);
                lc_gpu_scene_destroy(gs);
                lc_scene_destroy(s);
                continue;
            }
            double pass_sum[LC_PASS_COUNT] = {0}, gpu = 0, wall = 0;
            lc_frame_info info;
            int ok = 1;
            for (int f = 0; f < warmup + frames && ok; f++) {
                lc_render_params p = req.render;
                if (interactive && f > 0) {
                    p.detail.reuse_opacities = true;
                    p.detail.point_stride = point_stride;
                    p.detail.uniform_points = uniform_points;
                    p.detail.line_stride = line_stride;
                }
                if (lc_render_frame(g.renderer, gs, &p, st, 1.0 / 30.0, rgba, &info, &err) != 0) {
                    fprintf(stderr, "lucent bench: %s: %s\n", spec, err.msg);
                    ok = 0, status = 1;
                    break;
                }
                if (f < warmup)
                    continue;
                for (int p = 0; p < LC_PASS_COUNT; p++)
                    pass_sum[p] += info.pass_ms[p];
                gpu += info.gpu_ms;
                wall += info.wall_ms;
            }
            if (ok) {
                printf("%-16s %10llu %9u", s->name, (unsigned long long)lc_scene_primitive_count(s), s->elements.count);
                for (int p = 0; p < LC_PASS_COUNT; p++)
                    if (info.pass_ms[p] >= 0)
                        printf(" %12.2f", pass_sum[p] / frames);
                    else
                        printf(" %12s", "-");
                uint64_t rss = lc_cli_resident_bytes();
                double grown = rss > rss_before ? (double)(rss - rss_before) : 0.0;
                printf(" %9.2f %8.2f %7.1f %11.1f %11.1f %10llu %8.2f %9.1f %10.1f\n", gpu / frames, wall / frames,
                       1000.0 * frames / wall, info.pipeline_bytes / 1048576.0, lc_gpu_scene_bytes(gs) / 1048576.0,
                       (unsigned long long)info.primitives_drawn, t_load, rss / 1048576.0,
                       s->vertex_count ? grown / s->vertex_count : 0.0);
                if (show_memory)
                    lc_cli_print_memory(s, gs, &common);
            }
        }
        lc_frame_state_destroy(st);
        lc_gpu_scene_destroy(gs);
        lc_scene_destroy(s);
    }
    if (!args.floor)
        printf("\npipeline MB: render targets and per-element buffers the method holds (FOO: O(W*H*m));\n"
           "scene MB: the dataset's GPU buffers (levels of detail included), shared by all workers.\n"
           "fps = 1000 / mean wall ms incl. readback. drawn: primitives a geometry pass drew (its level of detail).\n"
           "load s: generate or read, finalize and upload; rss MB: the process's resident memory after the frames;\n"
           "rss B/vtx: its growth since before the dataset was loaded, per vertex (on llvmpipe GPU buffers are\n"
           "resident memory too; the first dataset also pays for the render targets and programs).\n");
    free(list);
    free(rgba);
    lc_cli_gl_close(&g);
    return status;
}
