/* Perception aids (docs/ALGORITHM.md "Perception aids"): target opacity,
 * silhouette opacity transfer, depth-dependent halos; CPU reference and the
 * pixels of the Fourier and exact methods. */
#include "demo.h"
#include "elements.h"
#include "foo_math.h"
#include "render_util.h"

#define SIZE 128

static int render(test_gl *t, const lc_scene *s, const lc_render_params *p, lc_frame_state *st, uint8_t *rgba)
{
    lc_error err = {0};
    lc_gpu_scene *gs = NULL;
    if (lc_gpu_scene_create(s, &gs, &err) != 0) {
        fprintf(stderr, "gpu scene: %s\n", err.msg);
        return -1;
    }
    int rc = lc_render_frame(t->renderer, gs, p, st, 0.0, rgba, NULL, &err);
    if (rc)
        fprintf(stderr, "render: %s\n", err.msg);
    lc_gpu_scene_destroy(gs);
    return rc;
}

static const uint8_t *pixel(const uint8_t *rgba, int x, int y) { return rgba + 4 * ((size_t)y * SIZE + x); }

/* ---- params.targetOpacity: alpha = t / (1 + ...) */
static void test_target_cpu(void)
{
    lc_foo_params p;
    lc_foo_params_default(&p);
    CHECK(lc_foo_target_opacity(&p) == 1.0, "default t is 1");
    lc_fragment f[5];
    for (int pass = 0; pass < 2; pass++) {
        for (int i = 0; i < 5; i++)
            f[i] = (lc_fragment){.depth = 0.1 + 0.17 * i, .importance = 0.2 * i};
        p.q = p.r = 0;
        p.target_opacity = 0.7;
        if (pass)
            lc_foo_alpha_fourier(f, 5, &p);
        else
            lc_foo_alpha_exact(f, 5, &p);
        for (int i = 0; i < 5; i++)
            CHECK(f[i].alpha == 0.7, "q = r = 0: alpha %g, not t", f[i].alpha);
        /* With occlusion, t scales the paper's opacities. */
        lc_fragment g[5];
        memcpy(g, f, sizeof g);
        p.q = 60, p.r = 500, p.target_opacity = 1;
        if (pass)
            lc_foo_alpha_fourier(g, 5, &p);
        else
            lc_foo_alpha_exact(g, 5, &p);
        p.target_opacity = 0.5;
        if (pass)
            lc_foo_alpha_fourier(f, 5, &p);
        else
            lc_foo_alpha_exact(f, 5, &p);
        for (int i = 0; i < 5; i++)
            CHECK(f[i].alpha == 0.5 * g[i].alpha, "t = 0.5: %g vs %g", f[i].alpha, g[i].alpha);
    }
}

static void test_target_gpu(test_gl *t)
{
    test_quad q[3] = {{0.0, 0.9, {1, 0, 0}, 0.8}, {-0.5, 0.3, {0, 1, 0}, 0.9}, {-1.0, 0.6, {0, 0, 1}, 0.7}};
    lc_scene *s = test_quad_scene(q, 3);
    CHECK(s != NULL, "scene");
    if (!s)
        return;
    lc_render_params p;
    test_quad_params(&p, SIZE);
    p.foo.q = p.foo.r = 0;
    p.foo.target_opacity = 0.6;
    uint8_t *rgba = malloc(SIZE * SIZE * 4);
    for (int m = 0; m < 2; m++) {
        p.method = m ? LC_METHOD_EXACT : LC_METHOD_FOURIER;
        lc_frame_state *st = lc_frame_state_create(s->elements.count);
        CHECK(render(t, s, &p, st, rgba) == 0, "render");
        const float *a = lc_frame_state_alphas(st);
        uint32_t bad = 0;
        for (uint32_t e = 0; e < s->elements.count; e++)
            bad += a[e] != 0.6f;
        CHECK(bad == 0, "%s: %u of %u element opacities differ from t = 0.6 (e.g. %g)", lc_method_name(p.method), bad,
              s->elements.count, (double)a[0]);
        lc_frame_state_destroy(st);
    }
    free(rgba);
    lc_scene_destroy(s);
}

/* ---- style.silhouetteExponent: alpha' = 1 - (1 - alpha)^(1 + (eta - 1)(1 - |n.v|)) */
static void test_silhouette(test_gl *t)
{
    CHECK_NEAR(lc_foo_silhouette_alpha(0.1, 10, 1), 0.651, 5e-4, "alpha 0.1, eta 10 on a silhouette");
    CHECK_NEAR(lc_foo_silhouette_alpha(0.1, 10, 0), 0.1, 1e-12, "facing the viewer: unchanged");
    CHECK(lc_foo_silhouette_alpha(0.1, 1, 1) == 0.1, "eta 1: off");
    CHECK_NEAR(lc_foo_silhouette_alpha(0.1, 10, 0.5), 1 - pow(0.9, 5.5), 1e-12, "half a silhouette");

    /* One black quad over white at alpha = t = 0.1 (q = r = 0); its normals
     * either face the viewer or lie in the image plane (a silhouette). */
    test_quad q = {0.0, 1.0, {0, 0, 0}, 0.8};
    uint8_t *rgba = malloc(SIZE * SIZE * 4);
    for (int edge = 0; edge < 2; edge++) {
        lc_scene *s = test_quad_scene(&q, 1);
        if (!s)
            break;
        if (edge)
            for (uint32_t v = 0; v < s->vertex_count; v++)
                s->normals[3 * v] = 1, s->normals[3 * v + 1] = 0, s->normals[3 * v + 2] = 0;
        lc_render_params p;
        test_quad_params(&p, SIZE);
        p.foo.q = p.foo.r = 0;
        p.foo.target_opacity = 0.1;
        p.style.silhouette_exponent = 10;
        double alpha = edge ? 1 - pow(0.9, 10) : 0.1;
        for (int m = 0; m < 2; m++) {
            p.method = m ? LC_METHOD_EXACT : LC_METHOD_FOURIER;
            CHECK(render(t, s, &p, NULL, rgba) == 0, "render");
            const uint8_t *c = pixel(rgba, SIZE / 2, SIZE / 2);
            CHECK(fabs(c[0] - 255.0 * (1 - alpha)) <= 2.0, "%s, %s: pixel %d, expected %.1f", lc_method_name(p.method),
                  edge ? "silhouette" : "facing", c[0], 255.0 * (1 - alpha));
        }
        lc_scene_destroy(s);
    }
    free(rgba);
}

/* ---- style.halo*: two crossing lines, the front one (red, horizontal, z = 0)
 * over the back one (blue, vertical, z = -dz), and a short marker far behind
 * (z = -20) that stretches the depth range. */
static lc_scene *crossing_scene(double dz)
{
    lc_error err = {0};
    enum { PER = 9 };
    lc_scene *s = lc_scene_create("crossing", LC_PRIM_LINES);
    if (!s || lc_scene_alloc_vertices(s, 3 * PER, 1, &err) != 0)
        return NULL;
    float *g = malloc(sizeof(float) * 3 * PER);
    s->line_count = 3;
    s->line_offsets = malloc(4 * sizeof(uint32_t));
    for (int l = 0; l < 3; l++) {
        s->line_offsets[l] = (uint32_t)(l * PER);
        for (int i = 0; i < PER; i++) {
            int v = l * PER + i;
            double u = -0.9 + 1.8 * i / (PER - 1);
            float *P = s->positions + 3 * v, *c = s->rgb + 3 * v;
            if (l == 0)
                P[0] = (float)u, P[1] = 0, P[2] = 0, c[0] = 1, c[1] = 0, c[2] = 0;
            else if (l == 1)
                P[0] = 0, P[1] = (float)u, P[2] = (float)-dz, c[0] = 0, c[1] = 0, c[2] = 1;
            else
                P[0] = (float)(0.8 + 0.01 * i), P[1] = 0.8f, P[2] = -20, c[0] = c[1] = c[2] = 0;
            g[v] = 1;
        }
    }
    s->line_offsets[3] = 3 * PER;
    lc_scene_add_attribute(s, "importance", g, &err);
    snprintf(s->default_importance, sizeof s->default_importance, "importance");
    snprintf(s->default_color, sizeof s->default_color, "rgb");
    lc_elements_desc desc = {0};
    if (lc_scene_finalize(s, &desc, &err) != 0) {
        fprintf(stderr, "finalize: %s\n", err.msg);
        lc_scene_destroy(s);
        return NULL;
    }
    return s;
}

static void test_halo(test_gl *t)
{
    uint8_t *rgba = malloc(SIZE * SIZE * 4), *plain = malloc(SIZE * SIZE * 4);
    lc_render_params p;
    test_quad_params(&p, SIZE);
    p.foo.q = p.foo.r = 0;     /* opaque lines (alpha 0.9999) */
    p.style.line_width = 0.06; /* 3.84 px */
    const double diag = sqrt(1.8 * 1.8 + 1.8 * 1.8 + 20.0 * 20.0);
    const double offset = 4.0; /* world units at the ribbon's edge */
    /* Halo offset 4 world units: a gap of 1 is a bundle neighbour, 12 is far behind. */
    const double gaps[2] = {1.0, 12.0};
    for (int m = 0; m < 2; m++) {
        p.method = m ? LC_METHOD_EXACT : LC_METHOD_FOURIER;
        for (int k = 0; k < 2; k++) {
            lc_scene *s = crossing_scene(gaps[k]);
            if (!s)
                break;
            lc_render_params h = p;
            h.style.halo_width = 6, h.style.halo_depth = offset / diag, h.style.halo_strength = 1;
            lc_frame_state *a = lc_frame_state_create(s->elements.count), *b = lc_frame_state_create(s->elements.count);
            CHECK(render(t, s, &p, a, plain) == 0 && render(t, s, &h, b, rgba) == 0, "render");
            /* The optimization never sees halos. */
            CHECK(memcmp(lc_frame_state_alphas(a), lc_frame_state_alphas(b), s->elements.count * sizeof(float)) == 0,
                  "halos changed element opacities");
            /* 4.5 px below the front line's centre, on the back line: the halo band. */
            const uint8_t *c = pixel(rgba, SIZE / 2, SIZE / 2 + 4), *c0 = pixel(plain, SIZE / 2, SIZE / 2 + 4);
            const char *name = lc_method_name(p.method);
            CHECK(c0[0] < 40 && c0[2] > 200, "%s, no halo: the back line shows (%d %d %d)", name, c0[0], c0[1], c0[2]);
            if (gaps[k] > offset)
                CHECK(c[0] > 215 && c[1] > 215, "%s, gap %g > offset %g: back line cut (%d %d %d)", name, gaps[k],
                      offset, c[0], c[1], c[2]);
            else
                CHECK(c[0] < 40 && c[2] > 200, "%s, gap %g < offset %g: back line kept (%d %d %d)", name, gaps[k],
                      offset, c[0], c[1], c[2]);
            /* The lines themselves: the front one at the crossing, the back one away from it. */
            const uint8_t *f = pixel(rgba, SIZE / 2, SIZE / 2), *bk = pixel(rgba, SIZE / 2, 20);
            CHECK(f[0] > 200 && f[2] < 40, "%s: front line at the crossing (%d %d %d)", name, f[0], f[1], f[2]);
            CHECK(bk[0] < 40 && bk[2] > 200, "%s: back line away from it (%d %d %d)", name, bk[0], bk[1], bk[2]);
            /* Width 0 is today's image bit for bit, whatever the other halo fields. */
            h.style.halo_width = 0;
            CHECK(render(t, s, &h, NULL, rgba) == 0 && render(t, s, &p, NULL, plain) == 0, "render");
            CHECK(memcmp(rgba, plain, SIZE * SIZE * 4) == 0, "%s: halo width 0 changed the image", name);
            lc_frame_state_destroy(a);
            lc_frame_state_destroy(b);
            lc_scene_destroy(s);
        }
    }
    free(rgba);
    free(plain);
}

/* ---- params.smoothingWeights "distance": P3 against the CPU reference
 * (lc_foo_smooth_step_weighted over lc_elements_adjacency_weights), from the
 * targets P2 gives with no smoothing. A grid (several patches, importance
 * rising along x) behind a small occluder, so the targets vary. */
static lc_scene *grid_scene(void)
{
    lc_error err = {0};
    enum { N = 16 };
    lc_scene *s = lc_scene_create("grid", LC_PRIM_TRIANGLES);
    if (!s || lc_scene_alloc_vertices(s, N * N + 4, 1, &err) != 0)
        return NULL;
    float *g = malloc(sizeof(float) * (N * N + 4));
    s->triangle_count = 2 * (N - 1) * (N - 1) + 2;
    s->triangles = malloc(sizeof(uint32_t) * 3 * s->triangle_count);
    uint32_t *t = s->triangles;
    for (int y = 0; y < N; y++)
        for (int x = 0; x < N; x++) {
            int v = y * N + x;
            s->positions[3 * v] = (float)(-0.9 + 1.8 * x / (N - 1));
            s->positions[3 * v + 1] = (float)(-0.9 + 1.8 * y / (N - 1));
            s->positions[3 * v + 2] = 0;
            s->rgb[3 * v] = s->rgb[3 * v + 1] = s->rgb[3 * v + 2] = 0.5f;
            g[v] = (float)(0.1 + 0.8 * x / (N - 1));
            if (x + 1 < N && y + 1 < N) {
                uint32_t a = (uint32_t)v, b = a + 1, c = a + N + 1, d = a + N;
                *t++ = a, *t++ = b, *t++ = c, *t++ = a, *t++ = c, *t++ = d;
            }
        }
    static const double cx[4] = {-1, 1, 1, -1}, cy[4] = {-1, -1, 1, 1};
    for (int k = 0; k < 4; k++) {
        int v = N * N + k;
        s->positions[3 * v] = (float)(0.3 * cx[k] - 0.2), s->positions[3 * v + 1] = (float)(0.3 * cy[k] + 0.1);
        s->positions[3 * v + 2] = 0.5f;
        s->rgb[3 * v] = 1, s->rgb[3 * v + 1] = s->rgb[3 * v + 2] = 0;
        g[v] = 0.2f;
    }
    uint32_t b = N * N;
    *t++ = b, *t++ = b + 1, *t++ = b + 2, *t++ = b, *t++ = b + 2, *t++ = b + 3;
    lc_scene_add_attribute(s, "importance", g, &err);
    snprintf(s->default_importance, sizeof s->default_importance, "importance");
    snprintf(s->default_color, sizeof s->default_color, "rgb");
    lc_elements_desc desc = {.patch_count = 10};
    if (lc_scene_finalize(s, &desc, &err) != 0) {
        fprintf(stderr, "finalize: %s\n", err.msg);
        lc_scene_destroy(s);
        return NULL;
    }
    return s;
}

static void test_smoothing_weights(test_gl *t)
{
    lc_scene *s = grid_scene();
    CHECK(s != NULL, "grid scene");
    if (!s)
        return;
    const lc_elements *e = &s->elements;
    uint32_t n = e->count;
    float *w = malloc(sizeof(float) * (e->adjacency_count + 1));
    lc_elements_adjacency_weights(e, s->positions, s->vertex_count, w);
    /* Each row sums to 1 and is not uniform everywhere. */
    int rows_ok = 1, nonuniform = 0;
    for (uint32_t i = 0; i < n; i++) {
        double sum = 0;
        uint32_t deg = e->adjacency_offsets[i + 1] - e->adjacency_offsets[i];
        for (uint32_t k = e->adjacency_offsets[i]; k < e->adjacency_offsets[i + 1]; k++) {
            sum += w[k];
            nonuniform |= fabs(w[k] - 1.0 / deg) > 1e-3;
        }
        rows_ok &= deg == 0 || fabs(sum - 1) <= 0.5 * deg / 65535.0; /* 16-bit steps */
    }
    CHECK(rows_ok && nonuniform, "weights: rows sum to 1 (%d), not all uniform (%d)", rows_ok, nonuniform);

    lc_render_params p;
    test_quad_params(&p, SIZE);
    uint8_t *rgba = malloc(SIZE * SIZE * 4);
    float *targets = malloc(sizeof(float) * n), *a = malloc(sizeof(float) * n), *b = malloc(sizeof(float) * n);
    float *uni = malloc(sizeof(float) * n);
    enum { ITER = 10 };
    p.foo.smoothing = 0;
    lc_frame_state *st = lc_frame_state_create(n);
    CHECK(render(t, s, &p, st, rgba) == 0, "render");
    memcpy(targets, lc_frame_state_alphas(st), sizeof(float) * n);
    lc_frame_state_destroy(st);
    double spread = 0;
    for (uint32_t i = 0; i < n; i++)
        spread = fmax(spread, fabs(targets[i] - targets[0]));
    CHECK(spread > 0.05 && e->adjacency_count > 0, "targets vary (%g) over %u elements", spread, n);
    for (int mode = 0; mode < 2; mode++) {
        p.foo.smoothing = ITER;
        p.foo.smoothing_weights = mode ? LC_SMOOTHING_DISTANCE : LC_SMOOTHING_UNIFORM;
        st = lc_frame_state_create(n);
        CHECK(render(t, s, &p, st, rgba) == 0, "render");
        memcpy(a, targets, sizeof(float) * n);
        for (int it = 0; it < ITER; it++) {
            if (mode)
                lc_foo_smooth_step_weighted(a, b, n, e->adjacency_offsets, e->adjacency, w, p.foo.smoothing_weight);
            else
                lc_foo_smooth_step(a, b, n, e->adjacency_offsets, e->adjacency, p.foo.smoothing_weight);
            memcpy(a, b, sizeof(float) * n);
        }
        double worst = 0, from_uniform = 0;
        for (uint32_t i = 0; i < n; i++) {
            worst = fmax(worst, fabs(lc_frame_state_alphas(st)[i] - a[i]));
            if (mode)
                from_uniform = fmax(from_uniform, fabs(a[i] - uni[i]));
            else
                uni[i] = a[i];
        }
        CHECK(worst < 1e-5, "%s smoothing: GPU against the CPU reference, max |diff| %g", mode ? "distance" : "uniform",
              worst);
        if (mode)
            CHECK(from_uniform > 1e-4, "distance weights change the result (%g)", from_uniform);
        lc_frame_state_destroy(st);
    }
    free(w), free(targets), free(a), free(b), free(uni), free(rgba);
    lc_scene_destroy(s);
}

/* ---- style.antialias: RMSE against a 4x4 supersampled reference (the same
 * optimization resolution, 64^2) falls with K = 1, 2, 4, 8 on the tornado. */
static double rmse(const uint8_t *a, const uint8_t *b, size_t pixels)
{
    double s = 0;
    for (size_t i = 0; i < pixels; i++)
        for (int c = 0; c < 3; c++) {
            double d = (double)a[4 * i + c] - b[4 * i + c];
            s += d * d;
        }
    return sqrt(s / (3.0 * pixels));
}

static void test_antialias(test_gl *t)
{
    lc_error err = {0};
    lc_scene *s = NULL;
    lc_demo_desc desc = {0};
    CHECK(lc_demo_create("tornado", &desc, &s, &err) == 0, "demo: %s", err.msg);
    if (!s)
        return;
    lc_render_params p;
    lc_render_params_default(&p);
    p.detail.lod_pixels = 0;        /* the same polylines at both sizes */
    p.style.min_line_pixels = 0.01; /* world widths only */
    enum { SS = 4, BIG = SIZE * SS };
    uint8_t *big = malloc((size_t)BIG * BIG * 4), *ref = malloc(SIZE * SIZE * 4), *img = malloc(SIZE * SIZE * 4);
    p.width = p.height = BIG;
    p.foo.resolution_scale = 0.5 / SS;
    CHECK(render(t, s, &p, NULL, big) == 0, "reference");
    for (int y = 0; y < SIZE; y++)
        for (int x = 0; x < SIZE; x++)
            for (int c = 0; c < 4; c++) {
                int sum = 0;
                for (int j = 0; j < SS; j++)
                    for (int i = 0; i < SS; i++)
                        sum += big[4 * ((size_t)(SS * y + j) * BIG + SS * x + i) + c];
                ref[4 * ((size_t)y * SIZE + x) + c] = (uint8_t)((sum + SS * SS / 2) / (SS * SS));
            }
    p.width = p.height = SIZE;
    p.foo.resolution_scale = 0.5;
    double prev = 1e300;
    for (int k = 1; k <= 8; k *= 2) {
        p.style.antialias = k;
        CHECK(render(t, s, &p, NULL, img) == 0, "render K = %d", k);
        double e = rmse(img, ref, SIZE * SIZE);
        printf("antialias K = %d: RMSE %.3f against the 4x4 supersampled reference\n", k, e);
        CHECK(e < prev, "K = %d: RMSE %.3f not below %.3f", k, e, prev);
        prev = e;
    }
    /* K = 1 is today's frame: the same bytes as without the field. */
    uint8_t *one = malloc(SIZE * SIZE * 4);
    p.style.antialias = 1;
    lc_render_params q = p;
    q.style.antialias = 0;
    CHECK(render(t, s, &p, NULL, img) == 0 && render(t, s, &q, NULL, one) == 0, "render");
    CHECK(memcmp(img, one, SIZE * SIZE * 4) == 0, "antialias 1 changed the image");
    free(one);
    free(big);
    free(ref);
    free(img);
    lc_scene_destroy(s);
}

/* ---- params.guardBand: a scripted orbit close to the tornado (elements
 * enter at the sides); the mean |opacity change| of elements in the frame
 * they first become visible (any vertex of theirs inside the view), with
 * fading at 30 frames per second. docs/EVALUATION.md quotes the figures. */
enum { ORBIT_FRAMES = 16 };
static double orbit_pop(test_gl *t, const lc_scene *s, double guard, int *events)
{
    lc_render_params p;
    lc_render_params_default(&p);
    p.width = p.height = SIZE;
    p.foo.guard_band = guard;
    p.has_camera = true;
    lc_camera_fit(&p.camera, s->bounds, NULL, NULL);
    double c[3], off[3];
    for (int k = 0; k < 3; k++) {
        c[k] = p.camera.focal_point[k];
        off[k] = 0.45 * (p.camera.position[k] - c[k]); /* close in: the view holds part of the data */
    }
    uint32_t n = s->elements.count;
    float *prev = malloc(sizeof(float) * n);
    uint8_t *vis = calloc(n, 1), *was = calloc(n, 1), *rgba = malloc(SIZE * SIZE * 4);
    lc_frame_state *st = lc_frame_state_create(n);
    double sum = 0;
    *events = 0;
    for (int f = 0; f < ORBIT_FRAMES; f++) {
        double a = 1.2 * f / ORBIT_FRAMES; /* radians about the view-up axis (+Y) */
        p.camera.position[0] = c[0] + cos(a) * off[0] + sin(a) * off[2];
        p.camera.position[1] = c[1] + off[1];
        p.camera.position[2] = c[2] - sin(a) * off[0] + cos(a) * off[2];
        lc_error err = {0};
        lc_gpu_scene *gs = NULL;
        if (lc_gpu_scene_create(s, &gs, &err) != 0 ||
            lc_render_frame(t->renderer, gs, &p, st, 1.0 / 30, rgba, NULL, &err) != 0) {
            CHECK(0, "orbit frame %d: %s", f, err.msg);
            lc_gpu_scene_destroy(gs);
            break;
        }
        lc_gpu_scene_destroy(gs);
        lc_view v;
        lc_camera_view(&p.camera, s->bounds, 1.0, SIZE, &v);
        memset(vis, 0, n);
        for (uint32_t i = 0; i < s->vertex_count; i++) {
            const float *P = s->positions + 3 * (size_t)i, *M = v.view_proj;
            double x = M[0] * P[0] + M[4] * P[1] + M[8] * P[2] + M[12];
            double y = M[1] * P[0] + M[5] * P[1] + M[9] * P[2] + M[13];
            double w = M[3] * P[0] + M[7] * P[1] + M[11] * P[2] + M[15];
            uint32_t e = s->elements.vertex_elements[4 * (size_t)i + 3];
            if (w > 0 && fabs(x) <= w && fabs(y) <= w && e < n)
                vis[e] = 1;
        }
        const float *alpha = lc_frame_state_alphas(st);
        for (uint32_t e = 0; f > 0 && e < n; e++)
            if (vis[e] && !was[e]) {
                sum += fabs(alpha[e] - prev[e]);
                ++*events;
            }
        memcpy(prev, alpha, sizeof(float) * n);
        memcpy(was, vis, n);
    }
    lc_frame_state_destroy(st);
    free(prev), free(vis), free(was), free(rgba);
    return *events ? sum / *events : 0;
}

static void test_guard_band(test_gl *t)
{
    lc_error err = {0};
    lc_scene *s = NULL;
    lc_demo_desc desc = {.count = 400};
    CHECK(lc_demo_create("tornado", &desc, &s, &err) == 0, "demo: %s", err.msg);
    if (!s)
        return;
    int n0 = 0, n1 = 0;
    double without = orbit_pop(t, s, 0, &n0), with = orbit_pop(t, s, 0.25, &n1);
    printf("guard band: mean |opacity change| of elements in their first visible frame %.4f without (%d "
           "entries), %.4f with guardBand 0.25 (%d)\n",
           without, n0, with, n1);
    CHECK(n0 > 20 && n0 == n1, "elements enter the view (%d, %d)", n0, n1);
    CHECK(with < 0.5 * without, "the guard band halves the pop-in: %.4f against %.4f", with, without);
    lc_scene_destroy(s);
}

int main(void)
{
    test_target_cpu();
    test_gl t;
    test_gl_open(&t);
    test_target_gpu(&t);
    test_silhouette(&t);
    test_halo(&t);
    test_smoothing_weights(&t);
    test_antialias(&t);
    test_guard_band(&t);
    test_gl_close(&t);
    return lc_test_finish();
}
