/* Time windows (docs/ALGORITHM.md "Time windows") on straight lines whose
 * vertices carry a time t = k + offset of the line:
 * - opaque: the middle pixel of every segment is lit exactly where the CPU
 *   says that both of its vertices lie in the window (and dark elsewhere);
 * - exact and Fourier: the windowed frame equals the frame of a scene that
 *   holds only the kept segments (exact: byte for byte; Fourier: SSIM >= 0.999,
 *   byte for byte on llvmpipe) (lines overlap in depth in pairs, so a hidden
 *   segment that still counted would change the opacity of the one behind);
 * - errors: t0 > t1 names time.window, data without a time attribute and a
 *   named attribute the data lacks name time.attribute;
 * - time.markers: where each front line leaves the window, its position at
 *   t1 (interpolated on the segment that crosses t1, beyond the last drawn
 *   vertex) is lit with markers and dark without, in the line's colour, with
 *   the opaque and the Fourier method; antialiased and tiled stills draw them
 *   over every sample and tile (a tiled frame equals the untiled one). */
#include <math.h>

#include "colormap.h"
#include "image.h"
#include "render_util.h"

enum { SIZE = 128, LINES = 8, PER_LINE = 16 };
static const double T0 = 3.2, T1 = 9.7;

/* Line i lies along x at height y_i (pairs share a height at z = +-0.4);
 * vertex k is at x_k = -1 + 2k/(PER_LINE-1) with time k + 0.7 i. */
static double line_y(int i) { return -0.75 + 1.5 * (i / 2) / (LINES / 2 - 1); }
static double line_z(int i) { return i % 2 ? -0.4 : 0.4; }
static double vertex_x(int k) { return -1 + 2.0 * k / (PER_LINE - 1); }
static double vertex_t(int i, int k) { return k + 0.7 * i; }
static int inside(int i, int k) { return vertex_t(i, k) >= T0 && vertex_t(i, k) <= T1; }
static int segment_kept(int i, int k) { return inside(i, k) && inside(i, k + 1); }

/* The lines from first_line on, dz nearer the camera; reduced: only each
 * line's run of vertices inside the window (a line with no kept segment is
 * left out). time_name: the time attribute's name. */
static lc_scene *lines_scene_from(int reduced, const char *time_name, int first_line, double dz)
{
    lc_error err = {0};
    int first[LINES], count[LINES], n = 0, lines = 0;
    for (int i = 0; i < LINES; i++) {
        first[i] = 0, count[i] = i >= first_line ? PER_LINE : 0;
        if (reduced && i >= first_line) {
            first[i] = -1, count[i] = 0;
            for (int k = 0; k < PER_LINE; k++)
                if (inside(i, k)) {
                    first[i] = first[i] < 0 ? k : first[i];
                    count[i]++;
                }
            if (count[i] < 2)
                count[i] = 0;
        }
        n += count[i];
        lines += count[i] > 0;
    }
    lc_scene *s = lc_scene_create("timed", LC_PRIM_LINES);
    if (!s || lc_scene_alloc_vertices(s, (uint32_t)n, 0, &err) != 0)
        return NULL;
    s->line_count = (uint32_t)lines;
    s->line_offsets = malloc(sizeof(uint32_t) * ((size_t)lines + 1));
    float *t = malloc(sizeof(float) * (size_t)n), *g = malloc(sizeof(float) * (size_t)n);
    uint32_t v = 0;
    int l = 0;
    for (int i = 0; i < LINES; i++) {
        if (!count[i])
            continue;
        s->line_offsets[l++] = v;
        for (int k = first[i]; k < first[i] + count[i]; k++, v++) {
            s->positions[3 * v] = (float)vertex_x(k);
            s->positions[3 * v + 1] = (float)line_y(i);
            s->positions[3 * v + 2] = (float)(line_z(i) + dz);
            t[v] = (float)vertex_t(i, k);
            g[v] = (float)(0.2 + 0.1 * i); /* constant along a line */
        }
    }
    s->line_offsets[lines] = v;
    lc_scene_add_attribute(s, time_name, t, &err);
    lc_scene_add_attribute(s, "g", g, &err);
    lc_elements_desc desc = {.line_budget = (uint32_t)lines}; /* one element per line */
    if (lc_scene_finalize(s, &desc, &err) != 0) {
        fprintf(stderr, "finalize: %s\n", err.msg);
        lc_scene_destroy(s);
        return NULL;
    }
    return s;
}

static lc_scene *lines_scene(int reduced, const char *time_name) { return lines_scene_from(reduced, time_name, 0, 0); }

static void params(lc_render_params *p, lc_method method, int window)
{
    lc_render_params_default(p);
    p->width = p->height = SIZE;
    p->method = method;
    p->has_camera = true;
    lc_camera *c = &p->camera;
    c->position[2] = 5;
    c->view_up[1] = 1;
    c->view_angle = 30;
    c->parallel_projection = true;
    c->parallel_scale = 1.1;
    p->detail.lod_pixels = 0;
    p->style.line_width = 0.06;
    p->style.background[0] = p->style.background[1] = p->style.background[2] = 0;
    snprintf(p->importance.attribute, sizeof p->importance.attribute, "g");
    snprintf(p->color.attribute, sizeof p->color.attribute, "g");
    p->color.has_range = p->importance.has_range = true;
    p->color.range[0] = p->importance.range[0] = 0;
    p->color.range[1] = p->importance.range[1] = 1;
    p->time.has_window = window;
    p->time.window[0] = T0, p->time.window[1] = T1;
}

static int render(test_gl *t, const lc_scene *s, const lc_render_params *p, uint8_t *rgba, lc_error *err)
{
    lc_gpu_scene *gs = NULL;
    lc_gpu_scene_desc desc = {.exact_positions = 1};
    if (lc_gpu_scene_create_ex(s, &desc, &gs, err) != 0)
        return -1;
    int rc = lc_render_frame(t->renderer, gs, p, NULL, 0, rgba, NULL, err);
    lc_gpu_scene_destroy(gs);
    return rc;
}

static int differing(const uint8_t *x, const uint8_t *y)
{
    int n = 0;
    for (int i = 0; i < SIZE * SIZE * 4; i++)
        n += x[i] != y[i];
    return n;
}

/* The pixel of world (x, y) (rows from the top). */
static const uint8_t *pixel(const uint8_t *rgba, double x, double y)
{
    int col = (int)floor((x / 1.1 + 1) * 0.5 * SIZE), row = (int)floor((1 - (y / 1.1 + 1) * 0.5) * SIZE);
    return rgba + 4 * ((size_t)row * SIZE + (size_t)col);
}

/* Opaque lines: each segment's middle pixel is lit iff the CPU keeps it. */
static void check_segments(test_gl *t, const lc_scene *s)
{
    static uint8_t img[SIZE * SIZE * 4];
    lc_error err = {0};
    lc_render_params p;
    params(&p, LC_METHOD_OPAQUE, 1);
    if (render(t, s, &p, img, &err) != 0) {
        CHECK(0, "opaque with a window: %s", err.msg);
        return;
    }
    int kept = 0, wrong = 0;
    for (int i = 0; i < LINES; i += 2) /* the front line of each pair */
        for (int k = 0; k + 1 < PER_LINE; k++) {
            const uint8_t *px = pixel(img, 0.5 * (vertex_x(k) + vertex_x(k + 1)), line_y(i));
            int lit = px[0] + px[1] + px[2] > 0, want = segment_kept(i, k) || segment_kept(i + 1, k);
            kept += segment_kept(i, k) + segment_kept(i + 1, k);
            if (lit != want) {
                wrong++;
                printf("line %d segment %d: lit %d, kept %d\n", i, k, lit, want);
            }
        }
    printf("opaque: %d of %d segments kept, %d middle pixels wrong\n", kept, LINES * (PER_LINE - 1), wrong);
    CHECK(kept > 10 && kept < LINES * (PER_LINE - 1) - 10, "the window keeps %d segments", kept);
    CHECK(wrong == 0, "%d segments drawn against the window", wrong);
}

/* Exact and Fourier: windowed full scene against the scene of kept segments. */
static void check_methods(test_gl *t, const lc_scene *all, const lc_scene *part)
{
    static uint8_t want[SIZE * SIZE * 4], got[SIZE * SIZE * 4];
    lc_method methods[2] = {LC_METHOD_EXACT, LC_METHOD_FOURIER};
    for (int m = 0; m < 2; m++) {
        lc_error err = {0};
        lc_render_params p;
        params(&p, methods[m], 0);
        if (render(t, part, &p, want, &err) != 0) {
            CHECK(0, "reduced scene: %s", err.msg);
            return;
        }
        params(&p, methods[m], 1);
        if (render(t, all, &p, got, &err) != 0) {
            CHECK(0, "windowed scene: %s", err.msg);
            return;
        }
        int d = differing(want, got);
        double ssim = lc_image_ssim(want, got, SIZE, SIZE);
        printf("%s window: %d differing bytes, SSIM %.6f against the kept segments alone\n", lc_method_name(methods[m]),
               d, ssim);
        if (methods[m] == LC_METHOD_EXACT)
            CHECK(d == 0, "exact: the window differs from the kept segments alone in %d bytes", d);
        else
            CHECK(ssim >= 0.999, "fourier: SSIM %.5f of the window against the kept segments", ssim);
        params(&p, methods[m], 0);
        if (render(t, all, &p, got, &err) != 0)
            return;
        CHECK(differing(want, got) > 0, "%s: the frame without a window equals the windowed one",
              lc_method_name(methods[m]));
    }
}

static void expect_error(test_gl *t, const lc_scene *s, const lc_render_params *p, const char *field)
{
    static uint8_t img[SIZE * SIZE * 4];
    lc_error err = {0};
    int rc = render(t, s, p, img, &err);
    printf("error %s: %s\n", err.field, err.msg);
    CHECK(rc != 0 && strcmp(err.field, field) == 0, "expected an error naming %s, got rc %d field \"%s\"", field, rc,
          err.field);
}

/* The x where line i crosses T1: on the segment from its last kept vertex a
 * to the next, at (T1 - t_a) / (t_b - t_a). *s gets that fraction. */
static double marker_x(int i, double *s)
{
    int a = (int)floor(T1 - 0.7 * i);
    *s = (T1 - vertex_t(i, a)) / (vertex_t(i, a + 1) - vertex_t(i, a));
    return vertex_x(a) + *s * (vertex_x(a + 1) - vertex_x(a));
}

static void check_markers(test_gl *t, const lc_scene *s)
{
    static uint8_t with[SIZE * SIZE * 4], without[SIZE * SIZE * 4];
    lc_method methods[2] = {LC_METHOD_OPAQUE, LC_METHOD_FOURIER};
    for (int m = 0; m < 2; m++) {
        lc_error err = {0};
        lc_render_params p;
        params(&p, methods[m], 1);
        p.style.shading = LC_SHADING_NONE; /* the colormap's colour, unlit */
        if (render(t, s, &p, without, &err) != 0) {
            CHECK(0, "without markers: %s", err.msg);
            return;
        }
        p.time.markers = true;
        if (render(t, s, &p, with, &err) != 0) {
            CHECK(0, "markers: %s", err.msg);
            return;
        }
        int checked = 0;
        for (int i = 0; i < LINES; i += 2) { /* front lines: their pair's back line ends earlier (0.7 later in t) */
            double frac, x = marker_x(i, &frac);
            if (frac < 0.25) /* within a few pixels of the drawn end: not told apart from the line */
                continue;
            const uint8_t *on = pixel(with, x, line_y(i)), *off = pixel(without, x, line_y(i));
            float rgb[3];
            lc_colormap_sample(lc_colormap_find("viridis"), (float)(0.2 + 0.1 * i), rgb);
            int dc = 0;
            for (int c = 0; c < 3; c++)
                dc = fmax(dc, fabs(on[c] - 255.0 * rgb[c]));
            printf("%s line %d: t1 at x %.3f (%.2f of its segment): with markers %d %d %d, without %d %d %d, colormap "
                   "%.0f %.0f %.0f\n",
                   lc_method_name(methods[m]), i, x, frac, on[0], on[1], on[2], off[0], off[1], off[2], 255 * rgb[0],
                   255 * rgb[1], 255 * rgb[2]);
            CHECK(off[0] + off[1] + off[2] == 0, "%s line %d: the pixel at t1 is lit without markers",
                  lc_method_name(methods[m]), i);
            CHECK(dc <= 3, "%s line %d: the marker's colour is %d levels off the line's colour",
                  lc_method_name(methods[m]), i, dc);
            checked++;
        }
        CHECK(checked >= 3, "%d markers checked", checked);
        CHECK(differing(with, without) < SIZE * SIZE * 4 / 20, "markers change a few pixels only (%d bytes)",
              differing(with, without));
    }
    /* A moving frame drawn at half its view's size (detail.pixel_scale) draws
     * its markers at half the radius: they keep their size in the view. */
    lc_render_params p;
    lc_error err = {0};
    params(&p, LC_METHOD_OPAQUE, 1);
    p.style.shading = LC_SHADING_NONE;
    int rc = render(t, s, &p, without, &err);
    p.time.markers = true;
    rc |= render(t, s, &p, with, &err);
    int full = differing(with, without);
    p.detail.pixel_scale = 0.5;
    rc |= render(t, s, &p, with, &err);
    int half = differing(with, without);
    printf("marker pixels (bytes changed): %d at full size, %d at pixel_scale 0.5\n", full, half);
    CHECK(rc == 0 && half > 0 && half < 0.6 * full, "markers at pixel_scale 0.5 cover less: %d against %d bytes", half,
          full);
    /* Antialiased and tiled stills draw the markers over every sample and tile:
     * the antialiased markers light their pixels, the tiled frame equals the untiled one. */
    static uint8_t tiled[SIZE * SIZE * 4];
    params(&p, LC_METHOD_FOURIER, 1);
    p.time.markers = true;
    p.style.shading = LC_SHADING_NONE;
    rc = render(t, s, &p, with, &err);
    p.style.antialias = 4;
    rc |= render(t, s, &p, tiled, &err);
    double frac;
    const uint8_t *on = pixel(tiled, marker_x(2, &frac), line_y(2)),
                  *plain = pixel(with, marker_x(2, &frac), line_y(2));
    printf("antialias 4: marker of line 2 at %d %d %d (one sample: %d %d %d)\n", on[0], on[1], on[2], plain[0],
           plain[1], plain[2]);
    CHECK(rc == 0 && on[0] + on[1] + on[2] > 0, "markers with antialias 4 light the marker's pixel (%s)", err.msg);
    p.style.antialias = 1;
    lc_renderer *tiler = NULL;
    lc_renderer_desc desc = {.tile_size = 48};
    lc_gpu_scene *gs = NULL;
    lc_gpu_scene_desc gdesc = {.exact_positions = 1};
    lc_frame_info info = {0};
    rc = lc_renderer_create(&desc, &tiler, &err) || lc_gpu_scene_create_ex(s, &gdesc, &gs, &err) ||
         lc_render_frame(tiler, gs, &p, NULL, 0, tiled, &info, &err);
    double ssim = rc ? 0 : lc_image_ssim(with, tiled, SIZE, SIZE);
    printf("markers on %d tiles of 48: SSIM %.6f against the untiled frame\n", info.tiles, ssim);
    CHECK(rc == 0 && info.tiles > 1 && ssim >= 0.999, "tiled markers: %d tiles, SSIM %.6f (%s)", info.tiles, ssim,
          err.msg);
    lc_gpu_scene_destroy(gs);
    lc_renderer_destroy(tiler);
}

static void check_errors(test_gl *t, const lc_scene *timed)
{
    lc_render_params p;
    params(&p, LC_METHOD_FOURIER, 1);
    p.time.window[0] = 5, p.time.window[1] = 4;
    expect_error(t, timed, &p, "time.window");
    params(&p, LC_METHOD_FOURIER, 1);
    snprintf(p.time.attribute, sizeof p.time.attribute, "clock");
    expect_error(t, timed, &p, "time.attribute");
    lc_scene *untimed = lines_scene(0, "age"); /* no time, t, frame or timestep */
    CHECK(untimed != NULL, "untimed scene");
    if (!untimed)
        return;
    params(&p, LC_METHOD_FOURIER, 1);
    expect_error(t, untimed, &p, "time.attribute");
    snprintf(p.time.attribute, sizeof p.time.attribute, "age"); /* named: accepted */
    static uint8_t img[SIZE * SIZE * 4];
    lc_error err = {0};
    CHECK(render(t, untimed, &p, img, &err) == 0, "time.attribute \"age\": %s", err.msg);
    lc_scene_destroy(untimed);
}

/* A layer of the lines: g for importance and colour over [0, 1]. */
static void lines_layer(lc_layer_params *l, const lc_render_params *p)
{
    lc_layer_params_default(l);
    l->importance = p->importance;
    l->color = p->color;
    l->style = p->style;
}

/* The layer's filter that keeps lines 3 on (g of the line >= 0.45). */
static void keep_lines_from_3(lc_layer_params *l)
{
    l->filter_count = 1;
    snprintf(l->filters[0].attribute, sizeof l->filters[0].attribute, "g");
    l->filters[0].over = LC_FILTER_MEAN;
    l->filters[0].lo = 0.45, l->filters[0].hi = INFINITY;
}

static int render_layers(test_gl *t, const lc_scene *const *scenes, const lc_layer_params *layers, int n,
                         const lc_render_params *p, uint8_t *rgba, lc_error *err)
{
    lc_gpu_scene *gs[4] = {0};
    lc_gpu_scene_desc desc = {.exact_positions = 1};
    int rc = 0;
    for (int i = 0; i < n && rc == 0; i++) /* the same scene twice: one upload */
        rc = i > 0 && scenes[i] == scenes[i - 1] ? (gs[i] = gs[i - 1], 0)
                                                 : lc_gpu_scene_create_ex(scenes[i], &desc, &gs[i], err);
    if (rc == 0)
        rc = lc_render_layers(t->renderer, (const lc_gpu_scene *const *)gs, layers, n, p, NULL, 0, rgba, NULL, err);
    for (int i = 0; i < n; i++)
        if (gs[i] && !(i > 0 && gs[i] == gs[i - 1]))
            lc_gpu_scene_destroy(gs[i]);
    return rc;
}

/* Layers with their own sections: the lines under a time window, the lines
 * again nearer the camera under a filter (g of the line >= 0.45: lines 3 on),
 * and an opaque floor behind both as context, against the same layers built
 * of the kept segments and lines alone (exact: byte for byte; Fourier: SSIM
 * >= 0.999); every section at once (window, clusters and equalized colours
 * on the lines, the filter on the copy, the context floor, antialias 2) in
 * one frame; then the same scene twice in one frame with two filters (two
 * masks of one dataset). */
static void check_layered(test_gl *t, const lc_scene *all, const lc_scene *part)
{
    static uint8_t want[SIZE * SIZE * 4], got[SIZE * SIZE * 4], open[SIZE * SIZE * 4];
    const test_quad q = {.z = -1.5, .g = 0.5, .rgb = {0.35, 0.3, 0.25}, .half = 1.3};
    lc_scene *near = lines_scene_from(0, "time", 0, 0.2), *near_kept = lines_scene_from(0, "time", 3, 0.2);
    lc_scene *floor_scene = test_quad_scene(&q, 1);
    CHECK(near && near_kept && floor_scene, "layer scenes");
    lc_method methods[2] = {LC_METHOD_EXACT, LC_METHOD_FOURIER};
    for (int m = 0; near && near_kept && floor_scene && m < 2; m++) {
        lc_render_params p;
        lc_error err = {0};
        params(&p, methods[m], 0);
        lc_layer_params layers[3];
        lines_layer(&layers[0], &p);
        lines_layer(&layers[1], &p);
        lc_layer_params_default(&layers[2]);
        layers[2].role = LC_LAYER_CONTEXT;
        snprintf(layers[2].color.attribute, sizeof layers[2].color.attribute, "rgb");
        const lc_scene *kept[3] = {part, near_kept, floor_scene}, *whole[3] = {all, near, floor_scene};
        int rc = render_layers(t, kept, layers, 3, &p, want, &err);
        rc = rc ? rc : render_layers(t, whole, layers, 3, &p, open, &err);
        layers[0].time.has_window = true;
        layers[0].time.window[0] = T0, layers[0].time.window[1] = T1;
        keep_lines_from_3(&layers[1]);
        rc = rc ? rc : render_layers(t, whole, layers, 3, &p, got, &err);
        CHECK(rc == 0, "%s layered frames: %s", lc_method_name(methods[m]), err.msg);
        if (rc)
            continue;
        int d = differing(want, got);
        double ssim = lc_image_ssim(want, got, SIZE, SIZE);
        printf("%s layers with a window, a filter and a context floor: %d differing bytes, SSIM %.6f against the kept "
               "lines alone (%d bytes differ without the sections)\n",
               lc_method_name(methods[m]), d, ssim, differing(want, open));
        CHECK(differing(want, open) > 0, "%s: the sections change nothing", lc_method_name(methods[m]));
        if (methods[m] == LC_METHOD_EXACT)
            CHECK(d == 0, "exact: the layers' sections differ from the kept lines alone in %d bytes", d);
        else
            CHECK(ssim >= 0.999, "fourier: SSIM %.5f of the layers' sections against the kept lines", ssim);
    }
    /* All together over the context floor: the window, two clusters and equalized colours on the lines, the
     * filter on the nearer copy, antialias 2: one frame, unlike the frame without any of them. */
    if (near && floor_scene) {
        static uint8_t together[SIZE * SIZE * 4];
        lc_render_params p;
        lc_error err = {0};
        params(&p, LC_METHOD_FOURIER, 0);
        lc_layer_params layers[3];
        lines_layer(&layers[0], &p);
        lines_layer(&layers[1], &p);
        lc_layer_params_default(&layers[2]);
        layers[2].role = LC_LAYER_CONTEXT;
        snprintf(layers[2].color.attribute, sizeof layers[2].color.attribute, "rgb");
        const lc_scene *whole[3] = {all, near, floor_scene};
        int rc = render_layers(t, whole, layers, 3, &p, open, &err);
        layers[0].time = (lc_time_window){.has_window = true, .window = {T0, T1}};
        layers[0].clusters.count = 2;
        layers[0].color.equalize = true;
        layers[0].color.has_range = false;
        keep_lines_from_3(&layers[1]);
        p.style.antialias = 2;
        rc = rc ? rc : render_layers(t, whole, layers, 3, &p, together, &err);
        printf("window, clusters, equalize, filter, context and antialias in one layered frame: %d bytes differ from "
               "the plain layers\n",
               rc ? -1 : differing(open, together));
        CHECK(rc == 0 && differing(open, together) > 0, "every section together: %s", err.msg);
    }
    /* One dataset twice, two masks: the window on one layer, the filter on the other. */
    lc_render_params p;
    lc_error err = {0};
    params(&p, LC_METHOD_FOURIER, 0);
    lc_layer_params twice[2];
    lines_layer(&twice[0], &p);
    lines_layer(&twice[1], &p);
    lc_scene *kept_lines = lines_scene_from(0, "time", 3, 0);
    const lc_scene *kept2[2] = {part, kept_lines}, *same[2] = {all, all};
    int rc = kept_lines ? render_layers(t, kept2, twice, 2, &p, want, &err) : -1;
    twice[0].time = (lc_time_window){.has_window = true, .window = {T0, T1}};
    keep_lines_from_3(&twice[1]);
    rc = rc ? rc : render_layers(t, same, twice, 2, &p, got, &err);
    double ssim = rc ? 0 : lc_image_ssim(want, got, SIZE, SIZE);
    printf("one dataset as two layers with a window and a filter: SSIM %.6f against the kept lines\n", ssim);
    CHECK(rc == 0 && ssim >= 0.999, "the same dataset twice with two filter lists: SSIM %.5f (%s)", ssim, err.msg);
    /* Errors name the layer's field. */
    twice[1].filters[0].over = LC_FILTER_VERTEX;
    rc = render_layers(t, same, twice, 2, &p, got, &err);
    CHECK(rc != 0 && strcmp(err.field, "layers[1].filter[0].over") == 0, "a vertex filter on lines: %s", err.field);
    twice[1].filter_count = 0;
    twice[0].time.markers = true;
    rc = render_layers(t, same, twice, 2, &p, got, &err);
    CHECK(rc != 0 && strcmp(err.field, "layers[0].time.markers") == 0, "markers on a layer: %s", err.field);
    lc_scene_destroy(kept_lines);
    lc_scene_destroy(near);
    lc_scene_destroy(near_kept);
    lc_scene_destroy(floor_scene);
}

int main(void)
{
    test_gl t;
    test_gl_open(&t);
    lc_scene *all = lines_scene(0, "time"), *part = lines_scene(1, "time");
    CHECK(all && part, "scenes");
    if (all && part) {
        check_segments(&t, all);
        check_methods(&t, all, part);
        check_errors(&t, all);
        check_markers(&t, all);
        check_layered(&t, all, part);
    }
    lc_scene_destroy(all);
    lc_scene_destroy(part);
    test_gl_close(&t);
    return lc_test_finish();
}
