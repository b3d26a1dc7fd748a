/* Surface layers benchmark (not a pass/fail test; docs/EVALUATION.md
 * "Surfaces": the epsilon sweep and the time to a recognizable surface): on a
 * demo field with a fixed seed line and camera, (1) the layers per covered
 * pixel and the overflow against epsilon after N curves (PRT Fig. 6/7), and
 * (2) batches of B curves traced, added and composited until the composite
 * reaches SSIM >= 0.9 against the converged image (all N curves), with the
 * wall time per stage (PRT §2.4's 100 and 10,000 curves a frame).
 *
 *   surface_bench [--field abc-flow] [--seed "x,y,z;x,y,z"] [--curves N] [--size PX] [--k K]
 *                 [--eps F,F,...] [--eps-ref F] [--batches B,B] [--threads T] [--png converged.png]
 *
 * Epsilons are given as fractions of the field's domain diagonal (PRT tuned
 * its epsilon on unit-sized scenes); the module gets epsilon = F * diagonal
 * in view-depth world units, and both are printed. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "field.h"
#include "gl_context.h"
#include "image.h"
#include "surface_layers.h"
#include "trace.h"

#define MAX_LIST 16
#define ADD_CHUNK 1000 /* curves per lc_surface_layers_add in the sweep: bounds the fragment pool */
#define TARGET_SSIM 0.9

static const float RGB[3] = {0.9f, 0.6f, 0.2f};

static double now_ms(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return 1e3 * (double)t.tv_sec + 1e-6 * (double)t.tv_nsec;
}

static void die(const char *what, const lc_error *err)
{
    fprintf(stderr, "%s: %s\n", what, err->msg);
    exit(1);
}

static int parse_list(const char *s, double *out)
{
    int n = 0;
    for (char *end; *s && n < MAX_LIST; s = *end ? end + 1 : end) {
        out[n++] = strtod(s, &end);
        if (end == s || (*end && *end != ',')) {
            fprintf(stderr, "bad number list at \"%s\"\n", s);
            exit(2);
        }
    }
    return n;
}

/* Column-major look-at (camera at eye looking at c, up +z) and perspective (fovy, aspect 1). */
static void camera(const double eye[3], const double c[3], double near, double far, float view[16], float proj[16])
{
    double f[3], s[3], u[3], up[3] = {0, 0, 1}, l;
    for (int i = 0; i < 3; i++)
        f[i] = c[i] - eye[i];
    l = sqrt(f[0] * f[0] + f[1] * f[1] + f[2] * f[2]);
    for (int i = 0; i < 3; i++)
        f[i] /= l;
    s[0] = f[1] * up[2] - f[2] * up[1], s[1] = f[2] * up[0] - f[0] * up[2], s[2] = f[0] * up[1] - f[1] * up[0];
    l = sqrt(s[0] * s[0] + s[1] * s[1] + s[2] * s[2]);
    for (int i = 0; i < 3; i++)
        s[i] /= l;
    u[0] = s[1] * f[2] - s[2] * f[1], u[1] = s[2] * f[0] - s[0] * f[2], u[2] = s[0] * f[1] - s[1] * f[0];
    memset(view, 0, 16 * sizeof *view);
    memset(proj, 0, 16 * sizeof *proj);
    for (int i = 0; i < 3; i++) {
        view[4 * i + 0] = (float)s[i];
        view[4 * i + 1] = (float)u[i];
        view[4 * i + 2] = (float)-f[i];
    }
    view[12] = (float)-(s[0] * eye[0] + s[1] * eye[1] + s[2] * eye[2]);
    view[13] = (float)-(u[0] * eye[0] + u[1] * eye[1] + u[2] * eye[2]);
    view[14] = (float)(f[0] * eye[0] + f[1] * eye[1] + f[2] * eye[2]);
    view[15] = 1.0f;
    double t = 1.0 / tan(0.5 * 40.0 * M_PI / 180.0); /* 40 degrees field of view */
    proj[0] = proj[5] = (float)t;
    proj[10] = (float)((far + near) / (near - far));
    proj[11] = -1.0f;
    proj[14] = (float)(2 * far * near / (near - far));
}

typedef struct bench {
    const lc_field *field;
    lc_seed seed;
    lc_surface_layers_desc desc;
    int threads;
} bench;

static lc_surface_layers *make_layers(const bench *b, double eps, lc_error *err)
{
    lc_surface_layers_desc d = b->desc;
    d.epsilon = eps;
    lc_surface_layers *sl = NULL;
    if (lc_surface_layers_create(&d, &sl, err) != 0)
        die("create", err);
    return sl;
}

static void trace(const bench *b, uint64_t first, uint32_t count, lc_trace_curve *out)
{
    lc_error err = {0};
    if (lc_trace_curves(b->field, &b->seed, &(lc_trace_desc){0}, first, count, b->threads, out, &err) != 0)
        die("trace", &err);
}

/* PRT Fig. 6/7: all curves at each epsilon; the composite at eps_ref goes to ref. */
static void sweep(const bench *b, const lc_trace_curve *curves, uint32_t n, const double *eps, int neps, double eps_ref,
                  double diag, uint8_t *ref)
{
    lc_error err = {0};
    int done_ref = 0;
    for (int e = 0; e <= neps; e++) {
        /* The reference epsilon runs last if the list lacks it. */
        double f = e < neps ? eps[e] : eps_ref;
        if (e == neps && done_ref)
            break;
        lc_surface_layers *sl = make_layers(b, f * diag, &err);
        double t0 = now_ms();
        for (uint32_t i = 0; i < n; i += ADD_CHUNK) {
            uint32_t c = n - i < ADD_CHUNK ? n - i : ADD_CHUNK;
            if (lc_surface_layers_add(sl, curves + i, c, RGB, &err) != 0)
                die("add", &err);
        }
        lc_surface_layers_stats s;
        if (lc_surface_layers_read(sl, NULL, &s, &err) != 0)
            die("read", &err);
        double add_ms = now_ms() - t0;
        printf("sweep eps %.0e (view depth %.3g): curves %llu covered %u mean_layers %.3f max_layers %u fragments "
               "%llu merged %llu overflow %llu pool_dropped %llu add_ms %.0f\n",
               f, f * diag, (unsigned long long)s.curves, s.covered_pixels, s.mean_layers, s.max_layers,
               (unsigned long long)s.fragments, (unsigned long long)s.merged, (unsigned long long)s.overflow,
               (unsigned long long)s.pool_dropped, add_ms);
        if (f == eps_ref && !done_ref) {
            if (lc_surface_layers_composite(sl, ref, &err) != 0)
                die("composite", &err);
            done_ref = 1;
        }
        lc_surface_layers_destroy(sl);
    }
}

/* The box of ref's pixels that are not background (white), for an SSIM that
 * background cannot dominate; the whole image if that box is under 16 px. */
typedef struct box {
    int x0, y0, w, h;
} box;

static box surface_box(const uint8_t *ref, int w, int h)
{
    int x0 = w, y0 = h, x1 = -1, y1 = -1;
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) {
            const uint8_t *p = ref + 4 * ((size_t)y * w + x);
            if (p[0] < 255 || p[1] < 255 || p[2] < 255) {
                x0 = x < x0 ? x : x0, x1 = x > x1 ? x : x1;
                y0 = y < y0 ? y : y0, y1 = y > y1 ? y : y1;
            }
        }
    if (x1 - x0 < 15 || y1 - y0 < 15)
        return (box){0, 0, w, h};
    return (box){x0, y0, x1 - x0 + 1, y1 - y0 + 1};
}

static double box_ssim(const uint8_t *a, const uint8_t *b, int w, box r, uint8_t *ca, uint8_t *cb)
{
    for (int y = 0; y < r.h; y++) {
        memcpy(ca + 4 * (size_t)y * r.w, a + 4 * ((size_t)(r.y0 + y) * w + r.x0), 4 * (size_t)r.w);
        memcpy(cb + 4 * (size_t)y * r.w, b + 4 * ((size_t)(r.y0 + y) * w + r.x0), 4 * (size_t)r.w);
    }
    return lc_image_ssim(ca, cb, r.w, r.h);
}

/* Batches of `batch` freshly traced curves up to all n. The layers depend on
 * the order in which fragments arrive (a pixel's first fragments fix where
 * its layers sit), so each batch size is compared with its own converged
 * image, the composite after all n curves in that batching; the SSIM to the
 * sweep's image (chunks of ADD_CHUNK) is printed beside. Composites are kept
 * until the end for that. Wall time = tracing + add + composite (not the
 * SSIM); the first batch whose SSIM reaches TARGET_SSIM is reported, over
 * the whole image and over the surface's box. */
static void progressive(const bench *b, uint32_t n, uint32_t batch, double eps, const uint8_t *sweep_ref)
{
    lc_error err = {0};
    int w = b->desc.width, h = b->desc.height;
    size_t px = (size_t)w * h * 4;
    uint32_t nb = (n + batch - 1) / batch;
    if ((double)nb * (double)px > 2e9) {
        fprintf(stderr, "batch %u: %u composites of %zu bytes are too many to keep; use a larger batch\n", batch, nb,
                px);
        return;
    }
    uint8_t *imgs = malloc(px * nb), *ca = malloc(px), *cb = malloc(px);
    double(*ms)[3] = calloc(nb, sizeof *ms);
    uint64_t *dropped = calloc(nb, sizeof *dropped);
    lc_trace_curve *c = calloc(batch, sizeof *c);
    if (!imgs || !ca || !cb || !ms || !dropped || !c) {
        fprintf(stderr, "out of memory\n");
        exit(1);
    }
    lc_surface_layers *sl = make_layers(b, eps, &err);
    lc_surface_layers_stats s = {0};
    for (uint32_t i = 0, done = 0; i < nb; i++) {
        uint32_t k = n - done < batch ? n - done : batch;
        double t0 = now_ms();
        trace(b, done, k, c);
        double t1 = now_ms();
        if (lc_surface_layers_add(sl, c, k, RGB, &err) != 0)
            die("add", &err);
        if (lc_surface_layers_read(sl, NULL, &s, &err) != 0) /* waits for the GPU, so add_ms is the GPU's too */
            die("read", &err);
        double t2 = now_ms();
        if (lc_surface_layers_composite(sl, imgs + px * i, &err) != 0)
            die("composite", &err);
        double t3 = now_ms();
        lc_trace_curves_free(c, k);
        done += k;
        ms[i][0] = t1 - t0, ms[i][1] = t2 - t1, ms[i][2] = t3 - t2;
        dropped[i] = s.pool_dropped;
    }
    const uint8_t *ref = imgs + px * (nb - 1);
    box r = surface_box(ref, w, h);
    printf("progressive batch %u: %u batches, converged mean_layers %.3f max_layers %u overflow %llu; box %dx%d at "
           "%d,%d\n",
           batch, nb, s.mean_layers, s.max_layers, (unsigned long long)s.overflow, r.w, r.h, r.x0, r.y0);
    double wall = 0, reached[2] = {-1, -1};
    uint32_t reached_at[2] = {0, 0};
    for (uint32_t i = 0; i < nb; i++) {
        uint32_t done = i + 1 == nb ? n : (i + 1) * batch;
        wall += ms[i][0] + ms[i][1] + ms[i][2];
        const uint8_t *img = imgs + px * i;
        double ssim[2] = {lc_image_ssim(img, ref, w, h), box_ssim(img, ref, w, r, ca, cb)};
        for (int j = 0; j < 2; j++)
            if (reached[j] < 0 && ssim[j] >= TARGET_SSIM)
                reached[j] = wall, reached_at[j] = done;
        /* Every batch until both have been reached, then every tenth. */
        if ((reached[0] < 0 || reached[1] < 0 || i % 10 == 9 || i + 1 == nb) || nb <= 20)
            printf("batch %u: curves %u trace_ms %.1f add_ms %.1f composite_ms %.1f wall_ms %.1f ssim %.4f "
                   "ssim_box %.4f pool_dropped %llu\n",
                   batch, done, ms[i][0], ms[i][1], ms[i][2], wall, ssim[0], ssim[1], (unsigned long long)dropped[i]);
    }
    for (int j = 0; j < 2; j++)
        if (reached[j] >= 0)
            printf("recognizable (%s >= %.2f) at batch %u: %u curves, %.1f ms wall (%.2f s)\n", j ? "ssim_box" : "ssim",
                   TARGET_SSIM, batch, reached_at[j], reached[j], reached[j] / 1e3);
        else
            printf("recognizable (%s >= %.2f) at batch %u: not reached\n", j ? "ssim_box" : "ssim", TARGET_SSIM, batch);
    box rs = surface_box(sweep_ref, w, h);
    printf("converged at batch %u against the sweep's image (chunks of %d): ssim %.4f ssim_box %.4f\n", batch,
           ADD_CHUNK, lc_image_ssim(ref, sweep_ref, w, h), box_ssim(ref, sweep_ref, w, rs, ca, cb));
    lc_surface_layers_destroy(sl);
    free(c);
    free(imgs);
    free(ca);
    free(cb);
    free(ms);
    free(dropped);
}

int main(int argc, char **argv)
{
    const char *name = "abc-flow", *seed_text = NULL, *png = NULL, *eps_text = "0,1e-4,3e-4,1e-3,3e-3,1e-2",
               *batch_text = "100,1000,10000";
    int size = 512, k = 16, threads = 2;
    long n = 20000;
    double eps_ref = 1e-3;
    for (int i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--field") && i + 1 < argc)
            name = argv[++i];
        else if (!strcmp(argv[i], "--seed") && i + 1 < argc)
            seed_text = argv[++i];
        else if (!strcmp(argv[i], "--curves") && i + 1 < argc)
            n = atol(argv[++i]);
        else if (!strcmp(argv[i], "--size") && i + 1 < argc)
            size = atoi(argv[++i]);
        else if (!strcmp(argv[i], "--k") && i + 1 < argc)
            k = atoi(argv[++i]);
        else if (!strcmp(argv[i], "--eps") && i + 1 < argc)
            eps_text = argv[++i];
        else if (!strcmp(argv[i], "--eps-ref") && i + 1 < argc)
            eps_ref = atof(argv[++i]);
        else if (!strcmp(argv[i], "--batches") && i + 1 < argc)
            batch_text = argv[++i];
        else if (!strcmp(argv[i], "--png") && i + 1 < argc)
            png = argv[++i];
        else if (!strcmp(argv[i], "--threads") && i + 1 < argc)
            threads = atoi(argv[++i]);
        else {
            fprintf(stderr, "usage: surface_bench [--field NAME] [--seed \"x,y,z;x,y,z\"] [--curves N] [--size PX] "
                            "[--k K] [--eps F,F] [--eps-ref F] [--batches B,B] [--threads T] [--png converged.png]\n");
            return 2;
        }
    }
    if (n < 1 || n > 1000000 || size < 16 || size > 4096) {
        fprintf(stderr, "--curves must be 1..1000000 and --size 16..4096\n");
        return 2;
    }
    setvbuf(stdout, NULL, _IOLBF, 0); /* figures appear as measured, also into a file */
    double eps[MAX_LIST], batches[MAX_LIST];
    int neps = parse_list(eps_text, eps), nb = parse_list(batch_text, batches);

    lc_error err = {0};
    lc_gl *gl = NULL;
    if (lc_gl_create(&(lc_gl_desc){.device = -1}, &gl, &err) != 0 || lc_gl_make_current(gl, &err) != 0)
        die("gl", &err);
    lc_field *field = NULL;
    if (lc_field_demo_create(name, &field, &err) != 0)
        die("field", &err);
    const double *bb = field->bounds;
    double ext[3], c[3], diag = 0;
    for (int i = 0; i < 3; i++) {
        ext[i] = bb[3 + i] - bb[i];
        c[i] = 0.5 * (bb[i] + bb[3 + i]);
        diag += ext[i] * ext[i];
    }
    diag = sqrt(diag);
    /* Default seed: a line across the domain's middle along y, a tenth in from the faces. */
    char def_seed[160];
    snprintf(def_seed, sizeof def_seed, "%g,%g,%g;%g,%g,%g", c[0], bb[1] + 0.1 * ext[1], c[2], c[0],
             bb[4] - 0.1 * ext[1], c[2]);
    bench b = {.field = field, .threads = threads};
    if (lc_seed_parse(seed_text ? seed_text : def_seed, &b.seed, field, &err) != 0)
        die("seed", &err);
    b.desc = (lc_surface_layers_desc){.width = size,
                                      .height = size,
                                      .max_layers = k,
                                      .opacity = 0.3,
                                      .background = {1, 1, 1},
                                      .pool_fragments = 16u << 20};
    printf("field %s diagonal %.4g seed \"%s\" size %d K %d opacity %.2f curves %ld threads %d\n", name, diag,
           seed_text ? seed_text : def_seed, size, k, b.desc.opacity, n, threads);

    lc_trace_curve *curves = calloc((size_t)n, sizeof *curves);
    uint8_t *ref = malloc((size_t)size * size * 4);
    if (!curves || !ref) {
        fprintf(stderr, "out of memory\n");
        return 1;
    }
    double t0 = now_ms();
    trace(&b, 0, (uint32_t)n, curves);
    uint64_t verts = 0;
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (long i = 0; i < n; i++) {
        verts += curves[i].n;
        for (uint32_t v = 0; v < curves[i].n; v++)
            for (int a = 0; a < 3; a++) {
                lo[a] = fmin(lo[a], curves[i].xyz[3 * v + a]);
                hi[a] = fmax(hi[a], curves[i].xyz[3 * v + a]);
            }
    }
    printf("traced %ld curves, %llu vertices in %.0f ms\n", n, (unsigned long long)verts, now_ms() - t0);
    /* Fixed camera fitted to the surface (all n curves' box), from direction
     * (1, -1.5, 0.8), so that the surface fills the image and the SSIM is not
     * dominated by background. */
    double sc[3], sr = 0, dir[3] = {1, -1.5, 0.8}, dl = sqrt(1 + 2.25 + 0.64), eye[3];
    for (int a = 0; a < 3; a++) {
        sc[a] = 0.5 * (lo[a] + hi[a]);
        sr += 0.25 * (hi[a] - lo[a]) * (hi[a] - lo[a]);
    }
    sr = sqrt(sr);
    for (int a = 0; a < 3; a++)
        eye[a] = sc[a] + 2.6 * sr * dir[a] / dl;
    camera(eye, sc, 0.5 * sr, 5.0 * sr, b.desc.view, b.desc.projection);
    printf("camera: centre %.3f,%.3f,%.3f eye %.3f,%.3f,%.3f (surface box radius %.3f), 40 degrees\n", sc[0], sc[1],
           sc[2], eye[0], eye[1], eye[2], sr);
    sweep(&b, curves, (uint32_t)n, eps, neps, eps_ref, diag, ref);
    lc_trace_curves_free(curves, (uint32_t)n);
    free(curves);
    if (png && lc_image_write_file(png, ref, size, size, 90, &err) != 0)
        die("png", &err);
    printf("converged image: eps %.0e (view depth %.3g), all %ld curves\n", eps_ref, eps_ref * diag, n);
    for (int i = 0; i < nb; i++)
        if (batches[i] >= 1)
            progressive(&b, (uint32_t)n, (uint32_t)batches[i], eps_ref * diag, ref);
    free(ref);
    lc_field_destroy(field);
    lc_gl_release_current(gl);
    lc_gl_destroy(gl);
    return 0;
}
