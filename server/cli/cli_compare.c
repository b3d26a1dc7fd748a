/* `lucent compare`: renders one request with its own method and with a
 * reference method (default: the exact linked-list method) on the same scene,
 * camera and parameters, and prints image metrics, per-pass times, GPU memory
 * and the depth complexity, one "NAME value" per line for scripts. */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "cli.h"
#include "image.h"

#define MIB (1024.0 * 1024.0)

/* The flags of `lucent compare` besides the shared ones (cli.c). */
typedef struct compare_args {
    const char *out_dir;
    int against, repeat;
    double pool_mib;
} compare_args;

static int set_method(void *target, const lc_option *o, const char *arg, char *why, size_t why_len)
{
    int m = lc_method_from_name(arg);
    if (m < 0) {
        snprintf(why, why_len,
                 "\"%s\": unknown method (fourier | exact | opaque | direct | wboit | weighted-average | binning | "
                 "kanzler)",
                 arg);
        return -1;
    }
    memcpy((char *)target + o->offset, &m, sizeof m);
    return 0;
}

#define COMPARE(member) LC_OPT_AT(compare_args, member)
static const lc_option compare_options[] = {{"--against", "METHOD", LC_OPT_CALL, COMPARE(against), .call = set_method,
                                             .help = "reference method (fourier | exact | opaque | direct | wboit |\n"
                                                     "weighted-average | binning | kanzler)"},
                                            {"--out-dir", "DIR", LC_OPT_TEXT, COMPARE(out_dir),
                                             .help = "write METHOD.png, AGAINST.png and difference.png (|a - b| x 4)"},
                                            {"--repeat", "N", LC_OPT_INT, COMPARE(repeat), 0, 1000,
                                             .help = "time N frames per method after one warm-up frame (default 3);\n"
                                                     "0 = a single frame per method, its (cold) times reported"},
                                            {"--pool-mib", "N", LC_OPT_REAL, COMPARE(pool_mib), 1, 65536,
                                             .help = "node pool of the exact method (default 256, clamped to the\n"
                                                     "driver's largest storage block)"},
                                            {NULL}};

static void compare_usage(FILE *f, const lc_opt_set *sets, int nsets)
{
    fprintf(f, "usage: lucent compare [--request REQ.json] [--input FILE|demo:NAME] [--against METHOD]\n"
               "                      [--out-dir DIR] [--repeat N] [--pool-mib N] [--device N] [flags]\n"
               "Renders the request with its method (default fourier) and with --against (default exact), same\n"
               "scene, camera and parameters, one-shot (no fading), and prints one \"NAME value\" per line:\n"
               "SSIM, RMSE (Rec. 709 luminance SSIM, 11x11 Gaussian, sigma 1.5; RMSE over RGB in [0,1]), per-pass\n"
               "and total GPU times, GPU memory of each method, the exact method's fragment count and layers.\n"
               "A request's layers[] (several datasets in one view) name each dataset as --input does.\n");
    lc_opt_usage(f, sets, nsets);
}

/* One method's frame: the image of the last repetition, mean times of the repetitions. */
typedef struct method_run {
    lc_method method;
    uint8_t *rgba;
    lc_frame_info info; /* last frame; pass_ms/gpu_ms/wall_ms replaced by means */
} method_run;

static int run_method(const lc_renderer_desc *desc, const lc_cli_scene *cs, lc_render_params p, lc_method method,
                      int repeat, method_run *out, lc_error *err)
{
    /* A renderer per method (on the current context) so that each one's pipeline memory is its own. */
    lc_renderer *r = NULL;
    int rc = lc_renderer_create(desc, &r, err);
    if (rc)
        return rc;
    p.method = method;
    out->method = method;
    double pass[LC_PASS_COUNT] = {0}, gpu = 0, wall = 0;
    for (int f = 0; f <= repeat && !rc; f++) {
        rc = lc_cli_scene_render(r, cs, &p, NULL, 0, out->rgba, &out->info, err);
        if (rc || (f == 0 && repeat > 0)) /* the first frame compiles shaders and allocates */
            continue;
        for (int i = 0; i < LC_PASS_COUNT; i++)
            pass[i] += out->info.pass_ms[i];
        gpu += out->info.gpu_ms;
        wall += out->info.wall_ms;
    }
    if (!rc) {
        int n = repeat > 0 ? repeat : 1;
        for (int i = 0; i < LC_PASS_COUNT; i++)
            if (out->info.pass_ms[i] >= 0)
                out->info.pass_ms[i] = pass[i] / n;
        out->info.gpu_ms = gpu / n;
        out->info.wall_ms = wall / n;
    }
    lc_renderer_destroy(r);
    return rc;
}

static void print_run(const method_run *m)
{
    const char *name = lc_method_name(m->method);
    for (int i = 0; i < LC_PASS_COUNT; i++)
        if (m->info.pass_ms[i] >= 0)
            printf("pass_ms.%s.%s %.3f\n", name, lc_pass_name(i), m->info.pass_ms[i]);
    printf("gpu_ms.%s %.3f\n", name, m->info.gpu_ms);
    printf("wall_ms.%s %.3f\n", name, m->info.wall_ms);
    printf("memory_mib.%s %.2f\n", name, m->info.pipeline_bytes / MIB);
    if (m->method == LC_METHOD_EXACT) {
        /* What this frame's lists occupy (nodes of 16 bytes + the head image), as opposed to the pool allocated
         * up front: the part of the exact method's memory that grows with the fragment count. */
        double lists = (16.0 * m->info.fragments + 4.0 * m->info.width * m->info.height) / MIB;
        printf("list_mib.exact %.2f\n", lists);
        printf("fragments %llu\n", (unsigned long long)m->info.fragments);
        printf("dropped_fragments %llu\n", (unsigned long long)m->info.dropped_fragments);
        printf("mean_layers %.2f\n", m->info.mean_layers);
        printf("max_layers %u\n", m->info.max_layers);
        printf("bands_exact %d\n", m->info.exact_bands);
    }
}

static int write_image(const char *dir, const char *name, const uint8_t *rgba, int w, int h)
{
    char path[4096];
    lc_error err = {0};
    snprintf(path, sizeof path, "%s/%s.png", dir, name);
    if (lc_image_write_file(path, rgba, w, h, 0, &err) != 0) {
        fprintf(stderr, "lucent compare: %s\n", err.msg);
        return -1;
    }
    printf("image %s\n", path);
    return 0;
}

/* lc_cli_compare with its request, which the caller releases (layers are a shared snapshot). */
static int compare_main(int argc, char **argv, lc_request *req)
{
    lc_cli_common common;
    compare_args args = {.against = LC_METHOD_EXACT, .repeat = 3, .pool_mib = 256};
    lc_error err = {0};
    int pr = lc_cli_parse("compare", compare_options, &args, argc, argv, req, &common, compare_usage);
    if (pr != 0)
        return pr == 1 ? 0 : 2;
    const char *out_dir = args.out_dir;
    int repeat = args.repeat, against = args.against;
    double pool_mib = args.pool_mib;
    if (out_dir && mkdir(out_dir, 0777) != 0 && errno != EEXIST) {
        fprintf(stderr, "lucent compare: %s: %s\n", out_dir, strerror(errno));
        return 1;
    }
    lc_cli_scene cs = {0}; /* one dataset, or the request's layers */
    lc_cli_gl g;
    if (lc_cli_scene_open("compare", req, &common, &cs, &g) != 0)
        return 1;
    int status = 1, w = req->render.width, h = req->render.height;
    size_t bytes = (size_t)w * h * 4;
    method_run runs[2] = {{.rgba = malloc(bytes)}, {.rgba = malloc(bytes)}};
    uint8_t *diff = NULL;
    lc_renderer_desc desc = {.exact_pool_bytes = (uint64_t)(pool_mib * MIB)};
    if (!runs[0].rgba || !runs[1].rgba) {
        fprintf(stderr, "lucent compare: out of memory\n");
        goto done;
    }
    const lc_method methods[2] = {req->render.method, (lc_method)against};
    for (int k = 0; k < 2; k++)
        if (run_method(&desc, &cs, req->render, methods[k], repeat, &runs[k], &err) != 0) {
            fprintf(stderr, "lucent compare: %s: %s\n", lc_method_name(methods[k]), err.msg);
            goto done;
        }

    char names[1200];
    printf("dataset %s\n", lc_cli_scene_name(&cs, names, sizeof names));
    if (cs.layer_count > 0)
        printf("layers %d\n", cs.layer_count);
    printf("primitives %llu\n", (unsigned long long)lc_cli_scene_primitives(&cs));
    printf("elements %llu\n", (unsigned long long)lc_cli_scene_elements(&cs));
    printf("renderer %s\n", lc_gl_renderer(g.gl));
    printf("size %dx%d\n", w, h);
    printf("method %s\n", lc_method_name(methods[0]));
    printf("against %s\n", lc_method_name(methods[1]));
    printf("bands %d\n", req->render.foo.bands);
    printf("estimator %s\n", lc_estimator_name(req->render.foo.estimator));
    printf("repeat %d\n", repeat);
    printf("SSIM %.4f\n", lc_image_ssim(runs[0].rgba, runs[1].rgba, w, h));
    printf("RMSE %.4f\n", lc_image_rmse(runs[0].rgba, runs[1].rgba, w, h));
    for (int k = 0; k < 2; k++)
        print_run(&runs[k]);
    for (int k = 0; k < 2; k++)
        if (runs[k].info.dropped_fragments)
            fprintf(stderr,
                    "lucent compare: WARNING: %s dropped %llu fragments (node pool or 256-layer cap); "
                    "raise --pool-mib\n",
                    lc_method_name(methods[k]), (unsigned long long)runs[k].info.dropped_fragments);
    if (out_dir) {
        const char *a = lc_method_name(methods[0]), *b = lc_method_name(methods[1]);
        if (write_image(out_dir, a, runs[0].rgba, w, h) ||
            (methods[1] != methods[0] && write_image(out_dir, b, runs[1].rgba, w, h)))
            goto done;
        diff = lc_image_difference(runs[0].rgba, runs[1].rgba, w, h, 4.0);
        if (!diff || write_image(out_dir, "difference", diff, w, h))
            goto done;
    }
    status = 0;
done:
    free(diff);
    free(runs[0].rgba);
    free(runs[1].rgba);
    lc_cli_scene_close(&cs, &g);
    return status;
}

int lc_cli_compare(int argc, char **argv) { return lc_cli_with_request(argc, argv, compare_main); }

int lc_cli_ssim(int argc, char **argv)
{
    if (argc != 3) {
        fprintf(stderr, "usage: lucent ssim A.png|.jpg B.png|.jpg\n"
                        "Prints the SSIM (Rec. 709 luminance, 11x11 Gaussian) and RMSE of two images of one size.\n");
        return 2;
    }
    lc_image a = {0}, b = {0};
    lc_error err = {0};
    int status = 1;
    if (lc_image_read_file(argv[1], &a, &err) != 0 || lc_image_read_file(argv[2], &b, &err) != 0)
        fprintf(stderr, "lucent ssim: %s\n", err.msg);
    else if (a.width != b.width || a.height != b.height)
        fprintf(stderr, "lucent ssim: %s is %dx%d, %s is %dx%d\n", argv[1], a.width, a.height, argv[2], b.width,
                b.height);
    else {
        printf("ssim %.6f\nrmse %.6f\n", lc_image_ssim(a.rgba, b.rgba, a.width, a.height),
               lc_image_rmse(a.rgba, b.rgba, a.width, a.height));
        status = 0;
    }
    lc_image_free(&a);
    lc_image_free(&b);
    return status;
}
