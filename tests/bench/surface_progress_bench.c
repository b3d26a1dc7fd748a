/* Progressive surface frames benchmark (not a pass/fail test;
 * docs/EVALUATION.md "Surfaces"): the frames of a surface
 * session with the camera still, B more curves each, drawn two ways side by
 * side in one run — adding the new curves to kept layers (lc_surface_keep,
 * today's session frame) and drawing every curve traced so far into fresh
 * layers (the session frame before) — with each frame's fragments rasterized
 * and wall time; tracing is done once beforehand and counted in neither.
 *
 *   surface_progress_bench [--field abc-flow] [--seed "x,y,z;x,y,z"] [--curves N] [--batch B] [--size PX]
 *                          [--every K] */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "field.h"
#include "gl_context.h"
#include "image.h"
#include "surface_render.h"
#include "trace.h"

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

int main(int argc, char **argv)
{
    const char *field_name = "abc-flow", *seed_text = "3.14159,0.63,3.14159;3.14159,5.65,3.14159";
    int curves = 4000, batch = 200, size = 512, every = 4;
    for (int i = 1; i + 1 < argc; i += 2) {
        if (!strcmp(argv[i], "--field"))
            field_name = argv[i + 1];
        else if (!strcmp(argv[i], "--seed"))
            seed_text = argv[i + 1];
        else if (!strcmp(argv[i], "--curves"))
            curves = atoi(argv[i + 1]);
        else if (!strcmp(argv[i], "--batch"))
            batch = atoi(argv[i + 1]);
        else if (!strcmp(argv[i], "--size"))
            size = atoi(argv[i + 1]);
        else if (!strcmp(argv[i], "--every"))
            every = atoi(argv[i + 1]);
        else {
            fprintf(stderr, "unknown option %s\n", argv[i]);
            return 2;
        }
    }
    if (curves < 1 || batch < 1 || size < 16 || every < 1) {
        fprintf(stderr, "--curves, --batch and --every must be >= 1, --size >= 16\n");
        return 2;
    }
    lc_error err = {0};
    lc_gl *gl = NULL;
    if (lc_gl_create(NULL, &gl, &err) != 0 || lc_gl_make_current(gl, &err) != 0)
        die("GL", &err);
    lc_field *f = NULL;
    if (lc_field_demo_create(field_name, &f, &err) != 0)
        die("field", &err);
    lc_seed seed;
    if (lc_seed_parse(seed_text, &seed, f, &err) != 0)
        die("seed", &err);
    lc_trace_curve *c = calloc((size_t)curves, sizeof *c);
    double t0 = now_ms();
    if (lc_trace_curves(f, &seed, &(lc_trace_desc){0}, 0, (uint32_t)curves, 2, c, &err) != 0)
        die("trace", &err);
    printf("%s, %d curves traced in %.0f ms; %dx%d, %d curves a frame\n", field_name, curves, now_ms() - t0, size, size,
           batch);

    lc_render_params p;
    lc_render_params_default(&p);
    p.width = p.height = size;
    lc_surface_params sp = {.particles = curves, .epsilon = 1e-2, .opacity = 0.3, .max_layers = 8};
    sp.color[0] = 0.95, sp.color[1] = 0.6, sp.color[2] = 0.2;
    uint8_t *kept_img = malloc((size_t)size * size * 4), *anew_img = malloc((size_t)size * size * 4);
    lc_surface_keep *keep = lc_surface_keep_create();
    printf("%8s | %12s %9s | %12s %9s\n", "curves", "kept: frags", "ms", "anew: frags", "ms");
    double kept_ms = 0, anew_ms = 0, first_kept = 0, first_anew = 0, last_kept = 0, last_anew = 0;
    uint64_t kept_frags = 0, anew_frags = 0;
    int frames = 0;
    for (int n = batch < curves ? batch : curves;; n = n + batch < curves ? n + batch : curves) {
        lc_surface_info a = {0}, b = {0};
        double ta = now_ms();
        if (lc_surface_draw(f, c, (uint32_t)n, 1, keep, &sp, &p, f->bounds, kept_img, &a, NULL, &err) != 0)
            die("kept frame", &err);
        double tb = now_ms();
        if (lc_surface_draw(f, c, (uint32_t)n, 0, NULL, &sp, &p, f->bounds, anew_img, &b, NULL, &err) != 0)
            die("frame anew", &err);
        double te = now_ms();
        kept_ms += tb - ta, anew_ms += te - tb;
        kept_frags += a.drawn_fragments, anew_frags += b.drawn_fragments;
        if (frames == 0)
            first_kept = tb - ta, first_anew = te - tb;
        last_kept = tb - ta, last_anew = te - tb;
        frames++;
        if (frames % every == 0 || n == curves || frames == 1)
            printf("%8d | %12llu %9.1f | %12llu %9.1f\n", n, (unsigned long long)a.drawn_fragments, tb - ta,
                   (unsigned long long)b.drawn_fragments, te - tb);
        if (n == curves)
            break;
    }
    int diff = 0;
    for (size_t i = 0; i < (size_t)size * size * 4; i++)
        if (i % 4 != 3 && abs((int)kept_img[i] - (int)anew_img[i]) > diff)
            diff = abs((int)kept_img[i] - (int)anew_img[i]);
    printf("%d frames: kept %llu fragments, %.0f ms in all (first %.1f, last %.1f ms); anew %llu fragments, %.0f ms "
           "(first %.1f, last %.1f ms)\n",
           frames, (unsigned long long)kept_frags, kept_ms, first_kept, last_kept, (unsigned long long)anew_frags,
           anew_ms, first_anew, last_anew);
    printf("last frames: largest channel difference %d, SSIM %.5f\n", diff,
           lc_image_ssim(kept_img, anew_img, size, size));
    lc_surface_keep_destroy(keep);
    lc_trace_curves_free(c, (uint32_t)curves);
    free(c);
    free(kept_img);
    free(anew_img);
    lc_field_destroy(f);
    lc_gl_destroy(gl);
    return 0;
}
