/* Exact-method benchmark (not a pass/fail test): the sort and compositing
 * variants of render/gl/exact.c side by side in one run, frame after frame in
 * turn so that the host's load weighs on each alike. For each dataset and
 * strength it prints the median time of the sort passes, the nodes the
 * compositing lists stored, the image difference against the method as it
 * was before the 4-ary heap, the queue and the reduction ("before"), and the
 * ratios. An image more than one grey level off "before" fails the run, so a
 * fast wrong result is caught (the variants' bound: docs/ALGORITHM.md §12),
 * unless "before" itself is off the insertion sort's image: the heap's
 * lists on Mesa 22 llvmpipe (docs/EVALUATION.md), which the run reports.
 *
 *   exact_bench [--data demo:tornado?count=2000,demo:points] [--size 512] [--rounds 5] [--strength 1,0.1,0.01]
 *
 * --strength scales q and r of the optimization: smaller is more opaque, where
 * the queue stops early (Met.3D thesis Table 2.10). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "demo.h"
#include "gl_context.h"
#include "loaders.h"
#include "renderer.h"

/* The variants: the measurement knobs of exact.c (LUCENT_EXACT_*). */
typedef struct variant {
    const char *name, *sort, *queue, *saturation, *reduce;
} variant;

static const variant VARIANTS[] = {
    {"before", "auto2", "0", "1e-6", "0"},      /* insertion <= 16, binary heap above, full sort, T < 1e-6 */
    {"insert", "insertion", "0", "1e-6", "0"},  /* insertion sort on every list: O(n^2), in order by construction */
    {"heap2", "heap2", "0", "1e-6", "0"},       /* binary heap sort on every list */
    {"heap4", "heap", "0", "1e-6", "0"},        /* 4-ary heap sort on every list */
    {"auto4", "auto", "0", "1e-6", "0"},        /* insertion <= 16, 4-ary heap above */
    {"queue", "auto", "1", "0.00196078", "0"},  /* + the front-to-back queue, stop at T < 0.5/255 */
    {"reduce", "auto2", "0", "1e-6", "1"},      /* before + fragment reduction */
    {"default", "auto", "1", "0.00196078", "1"} /* what the method does now */
};
#define NV ((int)(sizeof VARIANTS / sizeof VARIANTS[0]))
#define MAX_ROUNDS 64

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

static double median(double *v, int n)
{
    qsort(v, (size_t)n, sizeof *v, cmp_double);
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

static void set_variant(const variant *v)
{
    setenv("LUCENT_EXACT_SORT", v->sort, 1);
    setenv("LUCENT_EXACT_QUEUE", v->queue, 1);
    setenv("LUCENT_EXACT_SATURATION", v->saturation, 1);
    setenv("LUCENT_EXACT_REDUCE", v->reduce, 1);
}

static int load(const char *spec, lc_scene **out, lc_error *err)
{
    if (strncmp(spec, "demo:", 5) == 0)
        return lc_demo_create_spec(spec + 5, &(lc_demo_desc){0}, out, err);
    return lc_scene_load_file(spec, out, err);
}

static int bench(const char *spec, double strength, int size, int rounds)
{
    lc_error err = {0};
    lc_scene *sc = NULL;
    lc_gpu_scene *gs = NULL;
    if (load(spec, &sc, &err) != 0 || lc_gpu_scene_create(sc, &gs, &err) != 0) {
        fprintf(stderr, "%s: %s\n", spec, err.msg);
        return 1;
    }
    lc_render_params p;
    lc_render_params_default(&p);
    p.method = LC_METHOD_EXACT;
    p.width = p.height = size;
    p.foo.q *= strength;
    p.foo.r *= strength;
    /* One renderer per variant: exact.c reads its knobs when a renderer's first exact frame sets it up. */
    lc_renderer *r[NV];
    size_t px = (size_t)size * size * 4;
    uint8_t *img[NV];
    static double sort_ms[NV][MAX_ROUNDS], blend_ms[NV][MAX_ROUNDS], build_ms[NV][MAX_ROUNDS], gpu_ms[NV][MAX_ROUNDS];
    lc_frame_info info[NV];
    int rc = 0;
    for (int v = 0; v < NV; v++) {
        img[v] = malloc(px);
        if (lc_renderer_create(NULL, &r[v], &err) != 0) {
            fprintf(stderr, "renderer: %s\n", err.msg);
            return 1;
        }
    }
    /* Round 0 compiles and allocates (not timed); then the variants in turn. */
    for (int k = 0; k <= rounds; k++)
        for (int v = 0; v < NV; v++) {
            set_variant(&VARIANTS[v]);
            if (lc_render_frame(r[v], gs, &p, NULL, 0, img[v], &info[v], &err) != 0) {
                fprintf(stderr, "%s, %s: %s\n", spec, VARIANTS[v].name, err.msg);
                return 1;
            }
            if (k == 0)
                continue;
            sort_ms[v][k - 1] = info[v].pass_ms[LC_PASS_OPACITY];
            blend_ms[v][k - 1] = info[v].pass_ms[LC_PASS_ACCUMULATE];
            build_ms[v][k - 1] = info[v].pass_ms[LC_PASS_OPTICAL_DEPTH];
            gpu_ms[v][k - 1] = info[v].gpu_ms;
        }
    printf("%s, %dx%d, q=%g r=%g: %llu fragments at full resolution, max %u layers, mean %.1f\n", spec, size, size,
           p.foo.q, p.foo.r, (unsigned long long)info[0].fragments, info[0].max_layers, info[0].mean_layers);
    printf("  %-8s %10s %10s %10s %10s %8s %8s %12s %9s %8s %8s %8s\n", "variant", "opacity", "blend", "lists", "gpu",
           "blend", "gpu", "nodes", "nodes", "max diff", "to ins.", "cut");
    printf("  %-8s %10s %10s %10s %10s %8s %8s %12s %9s %8s %8s\n", "", "ms", "ms", "ms", "ms", "x before", "x before",
           "stored", "x before", "grey lvl", "grey lvl");
    double base_sort = median(sort_ms[0], rounds), base_blend = median(blend_ms[0], rounds);
    double base_gpu = median(gpu_ms[0], rounds);
    uint64_t base_nodes = info[0].fragments - info[0].reduced_fragments;
    int before_exact = 1; /* "before" has the insertion sort's image */
    for (int v = 0; v < NV; v++) {
        double so = median(sort_ms[v], rounds), bl = median(blend_ms[v], rounds), bu = median(build_ms[v], rounds);
        double g = median(gpu_ms[v], rounds);
        uint64_t nodes = info[v].fragments - info[v].reduced_fragments;
        int worst = 0, to_insertion = 0;
        for (size_t i = 0; i < px; i++) {
            int d = abs((int)img[v][i] - (int)img[0][i]), e = abs((int)img[v][i] - (int)img[1][i]);
            worst = d > worst ? d : worst;
            to_insertion = e > to_insertion ? e : to_insertion;
        }
        if (v == 0)
            before_exact = to_insertion == 0;
        printf("  %-8s %10.2f %10.2f %10.2f %10.2f %8.2f %8.2f %12llu %9.3f %8d %8d %8llu\n", VARIANTS[v].name, so, bl,
               bu, g, base_blend / bl, base_gpu / g, (unsigned long long)nodes,
               base_nodes ? (double)nodes / base_nodes : 0, worst, to_insertion, (unsigned long long)info[v].cut_lists);
        if (worst > 1 && before_exact) {
            fprintf(stderr, "%s: %d grey levels off \"before\", more than the bound of one\n", VARIANTS[v].name, worst);
            rc = 1;
        }
    }
    printf("  opacity-pass sort: 4-ary against binary heap on every list x%.2f, auto4 against before x%.2f; blend: "
           "queue against auto4 x%.2f, default against before x%.2f\n",
           median(sort_ms[2], rounds) / median(sort_ms[3], rounds), base_sort / median(sort_ms[4], rounds),
           median(blend_ms[4], rounds) / median(blend_ms[5], rounds), base_blend / median(blend_ms[NV - 1], rounds));
    if (!before_exact)
        printf("  \"before\" differs from the insertion sort's image: lists cut at the loop budget (the cut "
               "column) end where each sort's budget ran out\n");
    for (int v = 0; v < NV; v++) {
        lc_renderer_destroy(r[v]);
        free(img[v]);
    }
    lc_gpu_scene_destroy(gs);
    lc_scene_destroy(sc);
    return rc;
}

int main(int argc, char **argv)
{
    const char *data = "demo:tornado?count=2000,demo:points", *strengths = "1,0.1,0.01";
    int size = 512, rounds = 5;
    for (int i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--data") && i + 1 < argc)
            data = argv[++i];
        else if (!strcmp(argv[i], "--size") && i + 1 < argc)
            size = atoi(argv[++i]);
        else if (!strcmp(argv[i], "--rounds") && i + 1 < argc)
            rounds = atoi(argv[++i]);
        else if (!strcmp(argv[i], "--strength") && i + 1 < argc)
            strengths = argv[++i];
        else {
            fprintf(stderr, "usage: exact_bench [--data SPEC,SPEC] [--size PX] [--rounds N] [--strength S,S]\n");
            return 2;
        }
    }
    if (rounds < 1 || rounds > MAX_ROUNDS || size < 8) {
        fprintf(stderr, "exact_bench: --rounds 1..%d, --size >= 8\n", MAX_ROUNDS);
        return 2;
    }
    lc_log_set_level(LC_LOG_WARN); /* figures on stdout, no progress lines among them */
    lc_gl *gl = NULL;
    lc_error err = {0};
    if (lc_gl_create(&(lc_gl_desc){.device = -1}, &gl, &err) != 0 || lc_gl_make_current(gl, &err) != 0) {
        fprintf(stderr, "GL: %s\n", err.msg);
        return 1;
    }
    printf("renderer: %s\n", lc_gl_renderer(gl));
    int rc = 0;
    char *list = strdup(data);
    for (char *spec = strtok(list, ","); spec; spec = strtok(NULL, ","))
        for (const char *s = strengths; *s;) {
            rc |= bench(spec, atof(s), size, rounds);
            s = strchr(s, ',');
            if (!s)
                break;
            s++;
        }
    free(list);
    lc_gl_destroy(gl);
    return rc;
}
