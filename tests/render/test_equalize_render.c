/* View-dependent colour equalization end to end (color.equalize,
 * docs/ALGORITHM.md §19): the GPU's visibility-weighted histogram against the
 * image's own coverage, the equalized image, fixed ranges, the session's
 * decay, and the refusals. */
#include <math.h>

#include "demo.h"
#include "equalize.h"
#include "render_util.h"

#define SIZE 160
#define COARSE 16

static int render(test_gl *t, const lc_gpu_scene *gs, const lc_render_params *p, lc_frame_state *st, double dt,
                  uint8_t *rgba, lc_frame_info *info, lc_error *err)
{
    int rc = lc_render_frame(t->renderer, gs, p, st, dt, rgba, info, err);
    if (rc)
        fprintf(stderr, "render: %s\n", err->msg);
    return rc;
}

/* Tornado lines coloured by speed through the linear grayscale, unlit, so a
 * pixel's value is its visible colour coordinate's share. */
static void base_params(lc_render_params *p, double bg)
{
    lc_render_params_default(p);
    p->width = p->height = SIZE;
    snprintf(p->color.attribute, sizeof p->color.attribute, "velocity");
    snprintf(p->color.colormap, sizeof p->color.colormap, "grayscale");
    p->style.shading = LC_SHADING_NONE;
    p->style.background[0] = p->style.background[1] = p->style.background[2] = bg;
}

/* Deviation from uniform of the visibility-weighted histogram of F(u): the
 * weight H_b spread evenly over [F(b/256), F((b+1)/256)], summed into 16
 * coarse bins; max over them of |share - 1/16| / (1/16). */
static double coarse_deviation(const double *hist, const float *knots)
{
    double coarse[COARSE] = {0}, total = 0;
    for (int b = 0; b < LC_EQUALIZE_BINS; b++) {
        double lo = knots[b], hi = knots[b + 1], h = hist[b];
        total += h;
        if (h == 0)
            continue;
        if (!(hi > lo)) {
            int k = (int)(lo * COARSE);
            coarse[k < 0 ? 0 : k >= COARSE ? COARSE - 1 : k] += h;
            continue;
        }
        for (int k = 0; k < COARSE; k++) {
            double a = fmax(lo, (double)k / COARSE), z = fmin(hi, (double)(k + 1) / COARSE);
            if (z > a)
                coarse[k] += h * (z - a) / (hi - lo);
        }
    }
    double worst = 0;
    for (int k = 0; k < COARSE; k++)
        worst = fmax(worst, fabs(coarse[k] / total - 1.0 / COARSE) * COARSE);
    return worst;
}

/* Sum over pixels of 1 - T and of the grey value, from the same frame on a
 * black and a white background: I_white - I_black = 255 T. */
static void coverage(const uint8_t *black, const uint8_t *white, double *sum_cover, double *sum_grey)
{
    *sum_cover = *sum_grey = 0;
    for (size_t i = 0; i < (size_t)SIZE * SIZE; i++) {
        double t = 0, g = 0;
        for (int c = 0; c < 3; c++)
            t += (white[4 * i + c] - black[4 * i + c]) / 255.0, g += black[4 * i + c] / 255.0;
        *sum_cover += 1.0 - t / 3;
        *sum_grey += g / 3;
    }
}

/* The legend's ticks: tick i is the data value whose colormap coordinate u
 * has F(u) = i/4, found here by bisection on F; the middle one is the
 * visibility-weighted median of the visible colour values (F is their CDF). */
static void check_ticks(const lc_frame_info *info, const double *hist, const float *knots, double lo, double span,
                        const char *name)
{
    CHECK(info->has_color_ticks, "%s: the frame reports its colour ticks", name);
    double total = 0, run = 0, median = 0;
    for (int b = 0; b < LC_EQUALIZE_BINS; b++)
        total += hist[b];
    for (int b = 0; b < LC_EQUALIZE_BINS && run < total / 2; b++)
        if ((run += hist[b]) >= total / 2)
            median = lo + span * (b + 0.5) / LC_EQUALIZE_BINS;
    for (int i = 0; i < 5; i++) {
        double a = 0, z = 1;
        for (int k = 0; k < 40; k++) {
            double m = 0.5 * (a + z);
            if (lc_equalize_map(knots, LC_EQUALIZE_BINS, (float)m) < i / 4.0f)
                a = m;
            else
                z = m;
        }
        double want = lo + span * z;
        /* within half a bin: float knots and float interpolation reach F = 1 a little early or late */
        CHECK(fabs(info->color_ticks[i] - want) <= 0.5 * span / LC_EQUALIZE_BINS, "%s: tick %d = %g, F^-1 gives %g",
              name, i, info->color_ticks[i], want);
        CHECK(i == 0 || info->color_ticks[i] >= info->color_ticks[i - 1], "%s: ticks in order", name);
    }
    printf("%s: ticks %.3g %.3g %.3g %.3g %.3g (range %.3g..%.3g); visible median %.3g\n", name, info->color_ticks[0],
           info->color_ticks[1], info->color_ticks[2], info->color_ticks[3], info->color_ticks[4], lo, lo + span,
           median);
    CHECK(fabs(info->color_ticks[2] - median) <= span / LC_EQUALIZE_BINS, "%s: the middle tick is the visible median",
          name);
}

static void test_one_shot(test_gl *t, const lc_gpu_scene *gs, const lc_scene *s)
{
    const lc_attribute *speed = &s->attributes[lc_scene_find_attribute(s, "velocity")];
    double lo = speed->min, span = speed->max - speed->min;
    lc_error err = {0};
    uint8_t *black = malloc(SIZE * SIZE * 4), *white = malloc(SIZE * SIZE * 4), *plain = malloc(SIZE * SIZE * 4);
    lc_render_params p;
    double hist[LC_EQUALIZE_BINS];
    float knots[LC_EQUALIZE_BINS + 1], identity[LC_EQUALIZE_BINS + 1];
    for (int b = 0; b <= LC_EQUALIZE_BINS; b++)
        identity[b] = (float)b / LC_EQUALIZE_BINS;
    for (int method = 0; method < 2; method++) {
        const char *name = method ? "direct" : "fourier";
        /* color.range twice the data's: plain colours use the lower half of the map only. */
        base_params(&p, 0);
        p.method = method ? LC_METHOD_DIRECT : LC_METHOD_FOURIER;
        p.color.has_range = true, p.color.range[0] = lo, p.color.range[1] = lo + 2 * span;
        lc_frame_info plain_info;
        CHECK(render(t, gs, &p, NULL, 0, plain, &plain_info, &err) == 0 && !plain_info.has_color_ticks, "%s plain",
              name);
        p.color.equalize = true;
        lc_frame_info info;
        CHECK(render(t, gs, &p, NULL, 0, black, &info, &err) == 0, "%s black", name);
        CHECK(lc_renderer_color_histogram(t->renderer, hist, knots) == 0, "%s histogram", name);
        check_ticks(&info, hist, knots, lo, 2 * span, name);
        base_params(&p, 1);
        p.method = method ? LC_METHOD_DIRECT : LC_METHOD_FOURIER;
        p.color.has_range = true, p.color.range[0] = lo, p.color.range[1] = lo + 2 * span;
        p.color.equalize = true;
        CHECK(render(t, gs, &p, NULL, 0, white, NULL, &err) == 0, "%s white", name);
        double sum_h = 0;
        for (int b = 0; b < LC_EQUALIZE_BINS; b++)
            sum_h += hist[b];
        double cover, grey, plain_cover, plain_grey;
        coverage(black, white, &cover, &grey);
        coverage(plain, white, &plain_cover, &plain_grey);
        double before = coarse_deviation(hist, identity), after = coarse_deviation(hist, knots);
        printf("%s: sum H %.2f, sum (1 - T) %.2f (%.3f%%); 16-bin deviation from uniform %.3f before, %.3f after; "
               "mean visible grey %.3f plain, %.3f equalized\n",
               name, sum_h, cover, 100 * fabs(sum_h - cover) / cover, before, after, plain_grey / cover, grey / cover);
        CHECK(cover > 0.05 * SIZE * SIZE, "%s: the lines cover the image (%.0f px)", name, cover);
        CHECK(fabs(sum_h - cover) <= 0.01 * cover, "%s: sum H %.3f vs sum (1 - T) %.3f", name, sum_h, cover);
        CHECK(before > 0.3, "%s: the plain histogram is far from uniform (%.3f)", name, before);
        CHECK(after <= 0.1, "%s: equalized within 10%% of uniform (%.3f)", name, after);
        /* The image itself: the visibility-weighted mean of F(u) of a uniform F is 1/2. */
        CHECK(fabs(grey / cover - 0.5) < 0.01, "%s: mean visible grey %.3f", name, grey / cover);
        CHECK(plain_grey / cover < 0.3, "%s: plain mean visible grey %.3f", name, plain_grey / cover);
    }

    /* A fixed range (data units, through color.range) maps as the identity. */
    base_params(&p, 0);
    p.color.has_range = true, p.color.range[0] = lo, p.color.range[1] = lo + span;
    p.color.equalize = true;
    p.color.fixed_count = 1, p.color.fixed[0][0] = lo + 0.25 * span, p.color.fixed[0][1] = lo + 0.5 * span;
    CHECK(render(t, gs, &p, NULL, 0, black, NULL, &err) == 0, "fixed");
    CHECK(lc_renderer_color_histogram(t->renderer, hist, knots) == 0, "fixed histogram");
    for (int b = 64; b <= 128; b++)
        CHECK(fabsf(knots[b] - b / 256.0f) < 1e-6f, "fixed knot %d = %g", b, knots[b]);
    double outside = 0;
    for (int b = 0; b <= LC_EQUALIZE_BINS; b++)
        if (b < 64 || b > 128)
            outside = fmax(outside, fabs(knots[b] - b / 256.0));
    CHECK(outside > 0.01, "equalized outside the fixed range (%.3f)", outside);

    /* Off: the request fields change nothing. */
    base_params(&p, 0);
    CHECK(render(t, gs, &p, NULL, 0, plain, NULL, &err) == 0, "default");
    p.color.fixed_count = 1, p.color.fade_half_life = 3;
    CHECK(render(t, gs, &p, NULL, 0, black, NULL, &err) == 0, "off");
    CHECK(memcmp(plain, black, SIZE * SIZE * 4) == 0, "equalize off: bit for bit");
    free(black), free(white), free(plain);
}

/* A session's transfer moves half way to the view's every half-life (DLS Eq. 10). */
static void test_session(test_gl *t, const lc_gpu_scene *gs, const lc_scene *s)
{
    lc_error err = {0};
    uint8_t *rgba = malloc(SIZE * SIZE * 4);
    lc_render_params p;
    base_params(&p, 0);
    p.color.equalize = true;
    p.color.fade_half_life = 0.5;
    p.foo.fade_half_life = 0; /* opacities settle at once: frames 2-4 see one histogram */
    lc_frame_state *st = lc_frame_state_create(s->elements.count);
    lc_frame_info info;
    CHECK(render(t, gs, &p, st, 0, rgba, &info, &err) == 0, "session frame 1");
    float first[LC_EQUALIZE_BINS + 1], target[LC_EQUALIZE_BINS + 1], now[LC_EQUALIZE_BINS + 1];
    double hist[LC_EQUALIZE_BINS];
    const float *k = lc_frame_state_equalize_knots(st);
    CHECK(k != NULL, "the first frame sets the session's transfer");
    if (!k)
        goto out;
    memcpy(first, k, sizeof first);
    /* Jump: look along +X instead of the fitted view. */
    p.has_camera = true;
    p.camera = info.camera;
    double d = 0;
    for (int i = 0; i < 3; i++)
        d += (p.camera.position[i] - p.camera.focal_point[i]) * (p.camera.position[i] - p.camera.focal_point[i]);
    d = sqrt(d);
    p.camera.position[0] = p.camera.focal_point[0] - d;
    p.camera.position[1] = p.camera.focal_point[1];
    p.camera.position[2] = p.camera.focal_point[2];
    p.camera.view_up[0] = 0, p.camera.view_up[1] = 0, p.camera.view_up[2] = 1;
    CHECK(render(t, gs, &p, st, 0.5, rgba, NULL, &err) == 0, "session frame 2");
    CHECK(lc_renderer_color_histogram(t->renderer, hist, NULL) == 0, "histogram 2");
    CHECK(lc_equalize_target(hist, LC_EQUALIZE_BINS, NULL, 0, target) == 0, "target 2");
    memcpy(now, lc_frame_state_equalize_knots(st), sizeof now);
    double jump = 0, err_half = 0;
    for (int b = 0; b <= LC_EQUALIZE_BINS; b++) {
        jump = fmax(jump, fabs(target[b] - first[b]));
        err_half = fmax(err_half, fabs((now[b] - target[b]) - 0.5 * (first[b] - target[b])));
    }
    printf("session: the view's transfer moved by up to %.3f; after one half-life the distance is half within %.2g\n",
           jump, err_half);
    CHECK(jump > 0.02, "the new view has another transfer (%.3f)", jump);
    CHECK(err_half < 1e-5, "one half-life halves the distance (off by %.2g)", err_half);
    /* Two more quarter half-lives ... the distance is 2^-1.5 of the jump. */
    CHECK(render(t, gs, &p, st, 0.25, rgba, NULL, &err) == 0, "frame 3");
    CHECK(render(t, gs, &p, st, 0.25, rgba, NULL, &err) == 0, "frame 4");
    memcpy(now, lc_frame_state_equalize_knots(st), sizeof now);
    double err_q = 0;
    for (int b = 0; b <= LC_EQUALIZE_BINS; b++)
        err_q = fmax(err_q, fabs((now[b] - target[b]) - 0.25 * (first[b] - target[b])));
    CHECK(err_q < 2e-3, "two half-lives quarter the distance (off by %.2g)", err_q);
out:
    lc_frame_state_destroy(st);
    free(rgba);
}

/* The CPU update alone: distance halves every half-life, whatever the steps. */
static void test_decay_cpu(void)
{
    lc_frame_state *st = lc_frame_state_create(1);
    float a[LC_EQUALIZE_BINS + 1], b[LC_EQUALIZE_BINS + 1];
    for (int i = 0; i <= LC_EQUALIZE_BINS; i++)
        a[i] = (float)i / LC_EQUALIZE_BINS, b[i] = sqrtf(a[i]);
    CHECK(lc_frame_state_equalize_knots(st) == NULL, "no transfer before the first frame");
    lc_frame_state_equalize(st, a, 0.0, 0.8);
    for (int s = 0; s < 8; s++)
        lc_frame_state_equalize(st, b, 0.1, 0.8);
    const float *k = lc_frame_state_equalize_knots(st);
    double worst = 0;
    for (int i = 0; i <= LC_EQUALIZE_BINS; i++)
        worst = fmax(worst, fabs((k[i] - b[i]) - 0.5 * (a[i] - b[i])));
    CHECK(worst < 1e-6, "eight steps of tau/8 halve the distance (off by %.2g)", worst);
    lc_frame_state_reset(st);
    CHECK(lc_frame_state_equalize_knots(st) == NULL, "a reset forgets the transfer");
    lc_frame_state_destroy(st);
}

/* The exact method measures the histogram in its blend pass (exact.c): the
 * shares of a pixel are differences of its rounded coverage, so sum H_b (plus
 * the halos' part) equals sum (1 - T) exactly, and both agree with the image. */
static void test_exact(test_gl *t, const lc_gpu_scene *gs, const lc_scene *s)
{
    const lc_attribute *speed = &s->attributes[lc_scene_find_attribute(s, "velocity")];
    double lo = speed->min, span = speed->max - speed->min;
    lc_error err = {0};
    uint8_t *black = malloc(SIZE * SIZE * 4), *white = malloc(SIZE * SIZE * 4), *plain = malloc(SIZE * SIZE * 4);
    lc_render_params p;
    double hist[LC_EQUALIZE_BINS], cover = -1, halo = -1;
    lc_frame_info info;
    float knots[LC_EQUALIZE_BINS + 1], identity[LC_EQUALIZE_BINS + 1];
    for (int b = 0; b <= LC_EQUALIZE_BINS; b++)
        identity[b] = (float)b / LC_EQUALIZE_BINS;
    for (int bg = 0; bg < 2; bg++) {
        base_params(&p, bg);
        p.method = LC_METHOD_EXACT;
        p.color.has_range = true, p.color.range[0] = lo, p.color.range[1] = lo + 2 * span;
        if (bg == 0)
            CHECK(render(t, gs, &p, NULL, 0, plain, NULL, &err) == 0, "exact plain");
        p.color.equalize = true;
        CHECK(render(t, gs, &p, NULL, 0, bg ? white : black, &info, &err) == 0, "exact equalized %d", bg);
    }
    CHECK(lc_renderer_color_histogram(t->renderer, hist, knots) == 0, "exact histogram");
    check_ticks(&info, hist, knots, lo, 2 * span, "exact");
    CHECK(lc_renderer_color_coverage(t->renderer, &cover, &halo) == 0, "exact coverage");
    double sum_h = 0;
    for (int b = 0; b < LC_EQUALIZE_BINS; b++)
        sum_h += hist[b];
    double img_cover, grey, plain_cover, plain_grey;
    coverage(black, white, &img_cover, &grey);
    coverage(plain, white, &plain_cover, &plain_grey);
    double before = coarse_deviation(hist, identity), after = coarse_deviation(hist, knots);
    printf("exact: sum H %.6f, sum (1 - T) %.6f (halos %.6f), from the images %.2f; deviation %.3f before, %.3f "
           "after; mean visible grey %.3f plain, %.3f equalized\n",
           sum_h, cover, halo, img_cover, before, after, plain_grey / img_cover, grey / img_cover);
    CHECK(cover > 0.05 * SIZE * SIZE, "exact: the lines cover the image (%.0f px)", cover);
    CHECK(sum_h == cover && halo == 0, "exact: sum H %.9g == sum (1 - T) %.9g exactly", sum_h, cover);
    CHECK(fabs(img_cover - cover) <= 0.01 * cover, "exact: the images' coverage %.3f vs %.3f", img_cover, cover);
    CHECK(before > 0.3 && after <= 0.1, "exact: deviation from uniform %.3f -> %.3f", before, after);
    CHECK(fabs(grey / img_cover - 0.5) < 0.02, "exact: mean visible grey %.3f", grey / img_cover);

    /* Halos: their fragments carry the background, not a colour value: counted apart. */
    base_params(&p, 0);
    p.method = LC_METHOD_EXACT;
    p.color.equalize = true;
    p.style.halo_width = 2, p.style.halo_strength = 1;
    CHECK(render(t, gs, &p, NULL, 0, black, NULL, &err) == 0, "exact halos");
    CHECK(lc_renderer_color_histogram(t->renderer, hist, NULL) == 0 &&
              lc_renderer_color_coverage(t->renderer, &cover, &halo) == 0,
          "exact halos histogram");
    sum_h = 0;
    for (int b = 0; b < LC_EQUALIZE_BINS; b++)
        sum_h += hist[b];
    printf("exact with halos: sum H %.6f + halos %.6f = %.6f, sum (1 - T) %.6f\n", sum_h, halo, sum_h + halo, cover);
    CHECK(halo > 0 && sum_h + halo == cover, "exact halos: sum H + halos == sum (1 - T) exactly");

    /* A session: the first frame composites twice, the next ones measure as they draw. */
    base_params(&p, 0);
    p.method = LC_METHOD_EXACT;
    p.color.equalize = true;
    lc_frame_state *st = lc_frame_state_create(s->elements.count);
    for (int f = 0; f < 3; f++) {
        CHECK(render(t, gs, &p, st, 0.1, black, NULL, &err) == 0, "exact session frame %d", f);
        CHECK(lc_renderer_color_histogram(t->renderer, hist, NULL) == 0 &&
                  lc_renderer_color_coverage(t->renderer, &cover, &halo) == 0,
              "exact session histogram %d", f);
        sum_h = 0;
        for (int b = 0; b < LC_EQUALIZE_BINS; b++)
            sum_h += hist[b];
        CHECK(sum_h == cover && cover > 0, "exact session frame %d: sum H == sum (1 - T)", f);
    }
    CHECK(lc_frame_state_equalize_knots(st) != NULL, "exact session transfer");
    lc_frame_state_destroy(st);
    /* Off: the exact image is the one without the fields. */
    base_params(&p, 0);
    p.method = LC_METHOD_EXACT;
    CHECK(render(t, gs, &p, NULL, 0, plain, NULL, &err) == 0, "exact default");
    p.color.fixed_count = 1, p.color.fade_half_life = 3;
    CHECK(render(t, gs, &p, NULL, 0, black, NULL, &err) == 0, "exact off");
    CHECK(memcmp(plain, black, SIZE * SIZE * 4) == 0, "exact, equalize off: bit for bit");
    free(black), free(white), free(plain);
}

static void test_refusals(test_gl *t, const lc_gpu_scene *gs)
{
    uint8_t *rgba = malloc(SIZE * SIZE * 4);
    lc_render_params p;
    base_params(&p, 0);
    p.color.equalize = true;
    p.method = LC_METHOD_WBOIT;
    lc_error err = {0};
    CHECK(lc_render_frame(t->renderer, gs, &p, NULL, 0, rgba, NULL, &err) != 0 &&
              strcmp(err.field, "color.equalize") == 0,
          "wboit refused naming color.equalize (%s)", err.msg);
    free(rgba);
}

/* Layers take their own equalization: one equalized layer is the plain
 * equalized frame byte for byte (one-shot and a session's first two frames);
 * the tornado twice, one copy equalized and the other not, differs from both
 * plain and both equalized; exact and tiles refuse a layer's, naming it. */
static void test_layers(test_gl *t, const lc_gpu_scene *gs)
{
    size_t n = (size_t)SIZE * SIZE * 4;
    uint8_t *plain = malloc(n), *layered = malloc(n), *mixed = malloc(n), *both = malloc(n), *none = malloc(n);
    lc_render_params p;
    base_params(&p, 0);
    p.color.equalize = true;
    lc_error err = {0};
    lc_layer_params l[2];
    lc_layer_params_default(&l[0]);
    l[0].color = p.color;
    l[0].style.shading = LC_SHADING_NONE;
    lc_render_params q = p;
    q.color.equalize = false; /* the frame's own: a layered frame's is its layers' */
    const lc_gpu_scene *scenes[2] = {gs, gs};
    int rc = lc_render_frame(t->renderer, gs, &p, NULL, 0, plain, NULL, &err);
    rc = rc ? rc : lc_render_layers(t->renderer, scenes, l, 1, &q, NULL, 0, layered, NULL, &err);
    CHECK(rc == 0 && memcmp(plain, layered, n) == 0, "one equalized layer equals the plain equalized frame (%s)",
          err.msg);
    lc_frame_state *sa, *sb;
    uint32_t elements = 0;
    {
        lc_frame_info info = {0};
        rc = lc_render_frame(t->renderer, gs, &p, NULL, 0, plain, &info, &err);
        elements = info.element_count;
    }
    sa = lc_frame_state_create(elements), sb = lc_frame_state_create(elements);
    for (int k = 0; k < 2 && rc == 0; k++) { /* the second frame draws with the transfer the first left */
        rc = lc_render_frame(t->renderer, gs, &p, sa, 0.1, plain, NULL, &err);
        rc = rc ? rc : lc_render_layers(t->renderer, scenes, l, 1, &q, sb, 0.1, layered, NULL, &err);
        CHECK(rc == 0 && memcmp(plain, layered, n) == 0, "session frame %d: the equalized layer equals the plain frame",
              k);
    }
    lc_frame_state_destroy(sa);
    lc_frame_state_destroy(sb);
    l[1] = l[0];
    l[1].color.equalize = false;
    rc = lc_render_layers(t->renderer, scenes, l, 2, &q, NULL, 0, mixed, NULL, &err);
    l[1].color.equalize = true;
    rc = rc ? rc : lc_render_layers(t->renderer, scenes, l, 2, &q, NULL, 0, both, NULL, &err);
    l[0].color.equalize = l[1].color.equalize = false;
    rc = rc ? rc : lc_render_layers(t->renderer, scenes, l, 2, &q, NULL, 0, none, NULL, &err);
    CHECK(rc == 0 && memcmp(mixed, both, n) != 0 && memcmp(mixed, none, n) != 0 && memcmp(both, none, n) != 0,
          "one of two layers equalized differs from both and from neither (%s)", err.msg);
    l[0].color.equalize = true;
    q.method = LC_METHOD_EXACT;
    CHECK(lc_render_layers(t->renderer, scenes, l, 1, &q, NULL, 0, mixed, NULL, &err) != 0 &&
              strcmp(err.field, "layers[0].color.equalize") == 0,
          "exact refuses a layer's equalization naming layers[0].color.equalize (%s)", err.field);
    free(plain);
    free(layered);
    free(mixed);
    free(both);
    free(none);
}

int main(void)
{
    test_decay_cpu();
    test_gl t;
    test_gl_open(&t);
    lc_error err = {0};
    lc_scene *s = NULL;
    lc_demo_desc desc = {.count = 300};
    CHECK(lc_demo_create("tornado", &desc, &s, &err) == 0, "demo: %s", err.msg);
    lc_gpu_scene *gs = NULL;
    if (s && lc_gpu_scene_create(s, &gs, &err) == 0) {
        test_one_shot(&t, gs, s);
        test_session(&t, gs, s);
        test_exact(&t, gs, s);
        test_refusals(&t, gs);
        test_layers(&t, gs);
        lc_gpu_scene_destroy(gs);
    } else {
        CHECK(0, "gpu scene: %s", err.msg);
    }
    lc_scene_destroy(s);
    test_gl_close(&t);
    return lc_test_finish();
}
