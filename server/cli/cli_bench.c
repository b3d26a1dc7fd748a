/* `lucent bench`: renders each demo dataset and prints per-pass times, frames
 * per second and the GPU memory of the pipeline. Figures, not a test. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"
#include "demo.h"

#define BENCH_MAX_LIST 8 /* sizes or methods of --sizes, --methods */

/* The flags of `lucent bench` besides the shared ones (cli.c). */
typedef struct bench_args {
    int frames, warmup, memory, interactive, point_stride, uniform_points, line_stride, floor;
    const char *datasets;
    int sizes[BENCH_MAX_LIST][2], nsizes, methods[BENCH_MAX_LIST], nmethods; /* --sizes, --methods */
} bench_args;

/* --sizes W1xH1,W2xH2,...: each side an integer in [1, 16384], as --size takes. */
static int set_sizes(void *target, const lc_option *o, const char *arg, char *why, size_t why_len)
{
    (void)o;
    bench_args *a = target;
    a->nsizes = 0;
    for (const char *p = arg;; p++) {
        size_t n = strcspn(p, ",");
        char item[48], *x = NULL;
        long long w, h;
        if (a->nsizes < BENCH_MAX_LIST && n > 0 && n < sizeof item) {
            memcpy(item, p, n);
            item[n] = '\0';
            x = strchr(item, 'x');
        }
        if (x)
            *x = '\0';
        if (!x || lc_opt_parse_int(item, 1, 16384, &w) != 0 || lc_opt_parse_int(x + 1, 1, 16384, &h) != 0) {
            snprintf(why, why_len, "\"%s\": expected 1 to %d sizes WxH,WxH,..., each side an integer in [1, 16384]",
                     arg, BENCH_MAX_LIST);
            return -1;
        }
        a->sizes[a->nsizes][0] = (int)w, a->sizes[a->nsizes][1] = (int)h;
        a->nsizes++;
        p += n;
        if (!*p)
            return 0;
    }
}

/* --methods a,b,...: names as --method takes them. */
static int set_methods(void *target, const lc_option *o, const char *arg, char *why, size_t why_len)
{
    (void)o;
    bench_args *a = target;
    a->nmethods = 0;
    for (const char *p = arg;; p++) {
        size_t n = strcspn(p, ",");
        char item[32];
        int m = -1;
        if (a->nmethods < BENCH_MAX_LIST && n > 0 && n < sizeof item) {
            memcpy(item, p, n);
            item[n] = '\0';
            m = lc_method_from_name(item);
        }
        if (m < 0) {
            snprintf(why, why_len,
                     "\"%s\": expected 1 to %d methods a,b,... (fourier, exact, opaque, direct, wboit, "
                     "weighted-average, binning, kanzler)",
                     arg, BENCH_MAX_LIST);
            return -1;
        }
        a->methods[a->nmethods++] = m;
        p += n;
        if (!*p)
            return 0;
    }
}

#define BENCH(member) LC_OPT_AT(bench_args, member)
static const lc_option bench_options[] = {
    {"--frames", "N", LC_OPT_INT, BENCH(frames), 1, 100000, .help = "timed frames per dataset (default 10)"},
    {"--warmup", "N", LC_OPT_INT, BENCH(warmup), 0, 100000, .help = "untimed frames before them (default 2)"},
    {"--datasets", "A,B,...", LC_OPT_TEXT, BENCH(datasets), .help = "the datasets (default: every demo)"},
    {"--sizes", "WxH,...", LC_OPT_CALL, .call = set_sizes, .numeric = 1,
     .help = "image sizes (instead of --size): a row per dataset, size and\n"
             "method, each dataset loaded once"},
    {"--methods", "A,B,...", LC_OPT_CALL, .call = set_methods,
     .help = "methods (instead of --method), e.g. fourier,exact,opaque"},
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
     .help = "per geometry pass, one-shot stills timed four ways, alternated\n"
             "frame by frame: shaded (P4, P5 drawn), with an empty fragment shader,\n"
             "with GL_RASTERIZER_DISCARD and with P4, P5 through the compute\n"
             "rasterizer (medians; docs/EVALUATION.md, the geometry path)"},
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
            "of those frames. --sizes and --methods time every size and method on each dataset loaded once.\n");
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
 * state: what a still costs), the four modes of lc_renderer_set_floor
 * alternated frame by frame so that a busy host spreads over all of them
 * ("shaded" draws P4 and P5 whatever the device's rule, "compute" computes
 * them wherever the compute rasterizer applies);
 * medians of `frames` rounds after one warm-up frame per mode (which also
 * compiles the empty shaders). */
static int bench_floor(lc_cli_gl *g, const lc_gpu_scene *gs, const lc_scene *s, const lc_render_params *params,
                       int frames, uint8_t *rgba, lc_error *err)
{
    enum { MODES = LC_FLOOR_COUNT, COLS = LC_PASS_COUNT + 2 }; /* passes, gpu, wall */
    /* Lines: every mode with ribbons and with wide line strips, alternated too. */
    int forms = s->type == LC_PRIM_LINES ? 2 : 1;
    double *t = calloc((size_t)MODES * COLS * (size_t)frames * (size_t)forms, sizeof *t);
    if (!t)
        return lc_err(err, LC_ERR_NOMEM, "out of memory");
    lc_frame_info info = {0};
    int rc = 0, ran[LC_PASS_COUNT] = {0}, tries[LC_FLOOR_COUNT] = {0}, listed[LC_FLOOR_COUNT] = {0},
        summed[LC_FLOOR_COUNT] = {0}, composited[LC_FLOOR_COUNT] = {0}, walks = 0, computed = 0;
    for (int f = -1; f < frames && !rc; f++)
        for (int k = 0; k < forms * MODES && !rc; k++) {
            int form = k / MODES, m = k % MODES;
            lc_renderer_set_floor(g->renderer, (lc_floor_mode)m);
            lc_renderer_set_raster_path(g->renderer, 0);
            lc_renderer_set_line_path(g->renderer, forms > 1 ? form : -1);
            rc = lc_render_frame(g->renderer, gs, params, NULL, 0.0, rgba, &info, err);
            if (rc || f < 0)
                continue;
            tries[m] = info.clarity_tries;
            listed[m] = info.opacity_from_list;
            summed[m] = info.importance_from_list;
            composited[m] = info.composite_from_list;
            if (m == 0)
                walks = info.composite_walks;
            if (m == LC_FLOOR_COMPUTE)
                computed = info.computed_passes;
            double *row = t + ((size_t)(form * MODES + m) * COLS) * frames;
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
    lc_renderer_set_raster_path(g->renderer, -1);
    lc_renderer_set_line_path(g->renderer, -1);
    for (int form = 0; form < forms && !rc; form++) {
        printf("%s: %llu primitives, %dx%d, medians of %d rounds (ms)%s\n", s->name,
               (unsigned long long)lc_scene_primitive_count(s), params->width, params->height, frames,
               forms < 2   ? ""
               : form == 0 ? ", lines as ribbons (two triangles a segment)"
                           : ", lines as wide line strips (one primitive a segment, where they fit)");
        printf("  %-14s", "pass");
        for (int m = 0; m < MODES; m++)
            printf(" %13s", lc_floor_mode_name((lc_floor_mode)m));
        printf(" %9s\n", "shading");
        for (int c = 0; c < COLS; c++) {
            if (c < LC_PASS_COUNT && !ran[c])
                continue;
            double med[MODES];
            for (int m = 0; m < MODES; m++)
                med[m] = median(t + ((size_t)(form * MODES + m) * COLS + c) * frames, frames);
            printf("  %-14s", c < LC_PASS_COUNT ? lc_pass_name(c) : c == LC_PASS_COUNT ? "gpu total" : "wall");
            for (int m = 0; m < MODES; m++)
                printf(" %13.1f", med[m]);
            printf(" %8.0f%%\n", med[0] > 0 ? 100.0 * (med[0] - med[1]) / med[0] : 0.0);
        }
        printf("  (shading: the share of the shaded time above the empty shader's; opacity: one P2, the mean\n"
               "  over the clarity loop's tries, %d, %d and %d a frame)\n",
               tries[0], tries[1], tries[2]);
        printf("  P1: %s\n", summed[0] ? "a compute pass over P0's fragments (no traversal)" : "drawn (a traversal)");
        printf("  P2: %s\n",
               listed[0] ? "a compute pass over P1's fragment list (no traversal)" : "drawn (a traversal)");
        printf("  P4's sums, P5: %s\n", !composited[0] ? "drawn (a traversal each)"
                                        : walks == 1
                                            ? "one compute pass over the fragments P4 recorded (P5: no traversal)"
                                            : "compute passes over the fragments P4 recorded (P5: no traversal)");
        if (summed[0] || composited[0])
            printf("  recording P0, P4: each pixel's chain head %s\n",
                   lc_renderer_heads_fetch(g->renderer) ? "through framebuffer fetch" : "by an atomic exchange");
        printf("  P4, P5 in \"compute\": %s, %s (this device's rule: %s, %s)\n\n",
               computed & (1 << LC_RASTER_P4) ? "compute rasterizer" : "drawn (not applicable)",
               computed & (1 << LC_RASTER_P5) ? "compute rasterizer" : "drawn (not applicable)",
               lc_raster_path_name(lc_gl_renderer(g->gl), LC_RASTER_P4, s->type),
               lc_raster_path_name(lc_gl_renderer(g->gl), LC_RASTER_P5, s->type));
        if (forms > 1 && form == 1)
            printf("  lines: this device's rule: %s; widest line %.0f px (GL_ALIASED_LINE_WIDTH_RANGE)\n\n",
                   lc_line_path_name(), lc_renderer_line_width_max(g->renderer));
    }
    free(t);
    return rc;
}

/* lc_cli_bench with its request, which the caller releases (layers are a shared snapshot). */
static int bench_main(int argc, char **argv, lc_request *req)
{
    lc_cli_common common;
    bench_args args = {.frames = 10, .warmup = 2, .point_stride = 1, .line_stride = 1};
    int pr = lc_cli_parse("bench", bench_options, &args, argc, argv, req, &common, bench_usage);
    if (pr != 0)
        return pr == 1 ? 0 : 2;
    if (lc_request_layer_count(req) > 0) { /* a row a dataset: a layered frame is no dataset's */
        fprintf(stderr,
                "lucent bench: layers: bench times one dataset a row; `lucent render --request FILE --frames N` "
                "or `lucent compare --request FILE` time a layered request\n");
        return 2;
    }
    if (!common.request) { /* the benchmark's own default size, unless a flag gave one */
        req->render.width = common.width_set ? req->render.width : 1024;
        req->render.height = common.height_set ? req->render.height : 1024;
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
    int method_flag = 0;
    for (int i = 1; i < argc; i++)
        method_flag |= strcmp(argv[i], "--method") == 0 || strncmp(argv[i], "--method=", 9) == 0;
    const char *twice = args.nmethods && method_flag                             ? "method"
                        : args.nsizes && (common.width_set || common.height_set) ? "size"
                                                                                 : NULL;
    if (twice) {
        fprintf(stderr, "lucent bench: give --%s or --%ss, not both\n", twice, twice);
        return 2;
    }
    if (args.floor && (args.nsizes || args.nmethods)) {
        fprintf(stderr, "lucent bench: --floor times one size and method (--size, --method), not --%s\n",
                args.nsizes ? "sizes" : "methods");
        return 2;
    }
    /* A row per dataset, size and method: the lists, or the request's size and method. */
    int lists = args.nsizes || args.nmethods;
    if (!args.nsizes) {
        args.sizes[0][0] = req->render.width, args.sizes[0][1] = req->render.height;
        args.nsizes = 1;
    }
    if (!args.nmethods)
        args.methods[args.nmethods++] = (int)req->render.method;
    size_t max_pixels = 0;
    for (int i = 0; i < args.nsizes; i++)
        if ((size_t)args.sizes[i][0] * args.sizes[i][1] > max_pixels)
            max_pixels = (size_t)args.sizes[i][0] * args.sizes[i][1];
    lc_error err = {0};
    lc_cli_gl g;
    /* One dataset named by --input, --dataset or the request file, unless a list was given. */
    if (common.input)
        snprintf(datasets, sizeof datasets, "%s", common.input);
    else if (req->dataset[0] && !have_list)
        snprintf(datasets, sizeof datasets, "%s", req->dataset);
    if (lc_cli_gl_open(common.device, &g, &err) != 0) {
        fprintf(stderr, "lucent bench: %s\n", err.msg);
        return 1;
    }
    printf("renderer: %s | %s | %s\n", lc_gl_renderer(g.gl), lc_gl_version(g.gl), lc_gl_platform(g.gl));
    if (interactive && warmup < 1)
        warmup = 1; /* the frame whose opacities the timed ones reuse */
    if (lists) {
        printf("sizes");
        for (int i = 0; i < args.nsizes; i++)
            printf("%s%dx%d", i ? "," : " ", args.sizes[i][0], args.sizes[i][1]);
        printf(", methods");
        for (int i = 0; i < args.nmethods; i++)
            printf("%s%s", i ? "," : " ", lc_method_name((lc_method)args.methods[i]));
        printf(", ");
    } else {
        printf("%dx%d, method %s, ", req->render.width, req->render.height, lc_method_name(req->render.method));
    }
    printf("m=%d, %s estimator, s=%d, P1/P2 scale %.2f, lod %.2g px, %d frames (+%d warm-up)%s\n\n",
           req->render.foo.bands, lc_estimator_name(req->render.foo.estimator), req->render.foo.smoothing,
           req->render.foo.resolution_scale, req->render.detail.lod_pixels, frames, warmup,
           interactive ? ", interactive (opacities reused)" : "");
    if (!args.floor) {
        printf("%-16s", "dataset");
        if (lists)
            printf(" %-9s %-8s", "size", "method");
        printf(" %10s %9s", "primitives", "elements");
        for (int p = 0; p < LC_PASS_COUNT; p++)
            printf(" %12s", lc_pass_name(p));
        printf(" %9s %8s %7s %11s %11s %10s %8s %9s %10s\n", "gpu ms", "wall ms", "fps", "pipeline MB", "scene MB",
               "drawn", "load s", "rss MB", "rss B/vtx");
    }

    int status = 0;
    uint8_t *rgba = malloc(max_pixels * 4);
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
                if (bench_floor(&g, gs, s, &req->render, frames, rgba, &err) != 0) {
                    fprintf(stderr, "lucent bench: %s: %s\n", spec, err.msg);
                    status = 1;
                }
                lc_frame_state_destroy(st);
                lc_gpu_scene_destroy(gs);
                lc_scene_destroy(s);
                continue;
            }
            for (int c = 0; c < args.nsizes * args.nmethods; c++) {
                lc_render_params base = req->render;
                base.width = args.sizes[c / args.nmethods][0];
                base.height = args.sizes[c / args.nmethods][1];
                base.method = (lc_method)args.methods[c % args.nmethods];
                lc_frame_state_reset(st); /* each row fades from the start, as one run would */
                double pass_sum[LC_PASS_COUNT] = {0}, gpu = 0, wall = 0;
                lc_frame_info info;
                int ok = 1;
                for (int f = 0; f < warmup + frames && ok; f++) {
                    lc_render_params p = base;
                    if (interactive && f > 0) {
                        p.detail.reuse_opacities = true;
                        p.detail.point_stride = point_stride;
                        p.detail.uniform_points = uniform_points;
                        p.detail.line_stride = line_stride;
                    }
                    if (lc_render_frame(g.renderer, gs, &p, st, 1.0 / 30.0, rgba, &info, &err) != 0) {
                        if (lists)
                            fprintf(stderr, "lucent bench: %s, %dx%d, %s: %s\n", spec, p.width, p.height,
                                    lc_method_name(p.method), err.msg);
                        else
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
                    printf("%-16s", s->name);
                    if (lists) {
                        char size[24];
                        snprintf(size, sizeof size, "%dx%d", base.width, base.height);
                        printf(" %-9s %-8s", size, lc_method_name(base.method));
                    }
                    printf(" %10llu %9u", (unsigned long long)lc_scene_primitive_count(s), s->elements.count);
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
                    fflush(stdout); /* a row is whole when it appears, even if a later one never comes */
                }
            }
        }
        lc_frame_state_destroy(st);
        lc_gpu_scene_destroy(gs);
        lc_scene_destroy(s);
    }
    if (!args.floor)
        printf(
            "\npipeline MB: render targets and per-element buffers the method holds (FOO: O(W*H*m));\n"
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

int lc_cli_bench(int argc, char **argv) { return lc_cli_with_request(argc, argv, bench_main); }
