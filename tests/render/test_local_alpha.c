/* The local transparency baselines (OOS §2.1) as the direct method's opacity
 * (params.alphaSource) on an analytic sphere, slanted lines and a point splat, black on white
 * under an orthographic camera: a black fragment adds no colour, so a pixel is
 * the exact transmittance P6 composites, prod (1 - alpha_i), and its expected
 * value follows from the sphere's normal at the pixel. */
#include <math.h>

#include "render_util.h"

#define SIZE 96
#define RADIUS 0.8

/* A UV sphere of RADIUS at the origin, black, importance 1. */
static lc_scene *sphere_scene(int slices, int stacks)
{
    lc_error err = {0};
    int nv = (slices + 1) * (stacks + 1);
    lc_scene *s = lc_scene_create("sphere", LC_PRIM_TRIANGLES);
    if (!s || lc_scene_alloc_vertices(s, (uint32_t)nv, 1, &err) != 0)
        return NULL;
    float *g = malloc(sizeof(float) * (size_t)nv);
    for (int j = 0; j <= stacks; j++)
        for (int i = 0; i <= slices; i++) {
            int v = j * (slices + 1) + i;
            double th = M_PI * j / stacks, ph = 2 * M_PI * i / slices;
            s->positions[3 * v] = (float)(RADIUS * sin(th) * cos(ph));
            s->positions[3 * v + 1] = (float)(RADIUS * cos(th));
            s->positions[3 * v + 2] = (float)(RADIUS * sin(th) * sin(ph));
            s->rgb[3 * v] = s->rgb[3 * v + 1] = s->rgb[3 * v + 2] = 0;
            g[v] = 1;
        }
    s->triangle_count = (uint32_t)(2 * slices * stacks);
    s->triangles = malloc(sizeof(uint32_t) * 3 * s->triangle_count);
    uint32_t *t = s->triangles;
    for (int j = 0; j < stacks; j++)
        for (int i = 0; i < slices; i++) {
            uint32_t a = (uint32_t)(j * (slices + 1) + i), b = a + 1, c = a + (uint32_t)(slices + 1), d = c + 1;
            *t++ = a, *t++ = c, *t++ = b, *t++ = b, *t++ = c, *t++ = d;
        }
    return test_finish_scene(s, g, (lc_elements_desc){0});
}

/* One black straight line through the origin in the x-z plane at angle theta to the view axis (z). */
static lc_scene *line_scene(double theta)
{
    lc_error err = {0};
    enum { N = 9 };
    lc_scene *s = lc_scene_create("slanted", LC_PRIM_LINES);
    if (!s || lc_scene_alloc_vertices(s, N, 1, &err) != 0)
        return NULL;
    float *g = malloc(sizeof(float) * N);
    s->line_count = 1;
    s->line_offsets = malloc(2 * sizeof(uint32_t));
    s->line_offsets[0] = 0, s->line_offsets[1] = N;
    for (int v = 0; v < N; v++) {
        double u = -0.8 + 1.6 * v / (N - 1);
        s->positions[3 * v] = (float)(u * sin(theta));
        s->positions[3 * v + 1] = 0;
        s->positions[3 * v + 2] = (float)(u * cos(theta));
        s->rgb[3 * v] = s->rgb[3 * v + 1] = s->rgb[3 * v + 2] = 0;
        g[v] = 1;
    }
    return test_finish_scene(s, g, (lc_elements_desc){0});
}

/* One black point at the origin. */
static lc_scene *point_scene(void)
{
    lc_error err = {0};
    lc_scene *s = lc_scene_create("point", LC_PRIM_POINTS);
    if (!s || lc_scene_alloc_vertices(s, 1, 1, &err) != 0)
        return NULL;
    float *g = malloc(sizeof(float));
    g[0] = 1;
    s->positions[0] = s->positions[1] = s->positions[2] = 0;
    s->rgb[0] = s->rgb[1] = s->rgb[2] = 0;
    return test_finish_scene(s, g, (lc_elements_desc){0});
}

static void render(test_gl *t, const lc_scene *s, const lc_render_params *p, uint8_t *rgba)
{
    lc_error err = {0};
    lc_gpu_scene *gs = NULL;
    CHECK(lc_gpu_scene_create(s, &gs, &err) == 0, "gpu scene: %s", err.msg);
    lc_frame_info info;
    CHECK(lc_render_frame(t->renderer, gs, p, NULL, 0, rgba, &info, &err) == 0, "render: %s", err.msg);
    lc_gpu_scene_destroy(gs);
}

static void direct_params(lc_render_params *p, lc_alpha_source source)
{
    test_quad_params(p, SIZE);
    p->method = LC_METHOD_DIRECT;
    p->foo.alpha_source = source;
}

/* Pixel (x, y)'s value (red channel in [0, 1]) and its distance from the image centre in world units
 * (the view spans [-1, 1]^2, rows top first). */
static double pixel_at(const uint8_t *rgba, int x, int y, double *s)
{
    double wx = (x + 0.5) / SIZE * 2 - 1, wy = 1 - (y + 0.5) / SIZE * 2;
    *s = sqrt(wx * wx + wy * wy);
    return rgba[4 * (y * SIZE + x)] / 255.0;
}

/* The sphere's two layers at normalized radius u = s / RADIUS both have |<n, v>| = sqrt(1 - u^2). */
static void test_sphere(test_gl *t)
{
    lc_scene *s = sphere_scene(96, 48);
    CHECK(s != NULL, "sphere scene");
    if (!s)
        return;
    uint8_t *rgba = malloc(SIZE * SIZE * 4);
    lc_render_params p;

    /* Angle-based: alpha = (2/pi) arccos sqrt(1 - u^2) = (2/pi) arcsin u: 0 at the centre, 1 at the rim. */
    direct_params(&p, LC_ALPHA_ANGLE);
    render(t, s, &p, rgba);
    /* The opacity a pixel shows is 1 - sqrt(pixel) (two equal layers). */
    double centre = 0, rim = 1, worst = 0, worst_u = 0;
    for (int y = 0; y < SIZE; y++)
        for (int x = 0; x < SIZE; x++) {
            double r, got = pixel_at(rgba, x, y, &r), u = r / RADIUS;
            if (u > 0.98)
                continue;
            double a = 2 / M_PI * asin(u), want = (1 - a) * (1 - a);
            if (u < 0.02) /* the four central pixels, u = 0.018: alpha 0.012 */
                centre = fmax(centre, 1 - sqrt(got));
            if (u > 0.95) /* alpha 0.80 .. 0.87 */
                rim = fmin(rim, 1 - sqrt(got));
            if (u <= 0.95 && fabs(got - want) > worst)
                worst = fabs(got - want), worst_u = u;
        }
    CHECK(centre <= 0.015, "angle: alpha at the centre %.4f, want 0 (0.012 at the central pixels)", centre);
    CHECK(rim >= 0.79, "angle: alpha toward the rim %.3f, want -> 1 (0.80 at u 0.95)", rim);
    CHECK(worst <= 0.03, "angle: pixels against (1 - (2/pi) arcsin u)^2: worst error %.4f at u = %.3f", worst, worst_u);
    printf("angle: alpha at the centre %.4f, at u 0.95..0.98 at least %.3f, worst pixel error %.4f at u %.3f\n", centre,
           rim, worst, worst_u);

    /* Constant: every covered pixel is (1 - c)^2. */
    direct_params(&p, LC_ALPHA_CONSTANT);
    p.foo.alpha_constant = 0.4;
    render(t, s, &p, rgba);
    worst = 0;
    for (int y = 0; y < SIZE; y++)
        for (int x = 0; x < SIZE; x++) {
            double r, got = pixel_at(rgba, x, y, &r);
            if (r / RADIUS < 0.95)
                worst = fmax(worst, fabs(got - 0.36));
        }
    CHECK(worst <= 2.0 / 255, "constant 0.4: pixels against 0.36: worst error %.4f", worst);

    /* Normal variation (gamma 1): |grad n_z| per pixel, n_z = sqrt(1 - u^2), so
     * alpha = u / sqrt(1 - u^2) / R_px with R_px the radius in pixels; 0 at the centre, rising to the rim. */
    direct_params(&p, LC_ALPHA_NORMAL_VARIATION);
    render(t, s, &p, rgba);
    double rpx = RADIUS * SIZE / 2, nv_worst = 0, nv_centre = 1, nv_outer = 1;
    for (int y = 0; y < SIZE; y++)
        for (int x = 0; x < SIZE; x++) {
            double r, got = pixel_at(rgba, x, y, &r), u = r / RADIUS;
            if (u < 0.1)
                nv_centre = fmin(nv_centre, got);
            if (u > 0.85 && u < 0.9)
                nv_outer = fmin(nv_outer, got);
            if (u < 0.8) {
                double a = u / sqrt(1 - u * u) / rpx;
                nv_worst = fmax(nv_worst, fabs(got - (1 - a) * (1 - a)));
            }
        }
    CHECK(nv_centre >= 0.99, "normal variation: clear at the centre: %.3f", nv_centre);
    CHECK(nv_outer < nv_centre - 0.05, "normal variation: more opaque toward the rim (%.3f vs %.3f)", nv_outer,
          nv_centre);
    CHECK(nv_worst <= 0.03, "normal variation: pixels against the analytic gradient: worst error %.4f", nv_worst);
    printf("normal variation: centre %.3f, u 0.85..0.9 %.3f, worst error (u < 0.8) %.4f\n", nv_centre, nv_outer,
           nv_worst);
    free(rgba);
    lc_scene_destroy(s);
}

/* A line at angle theta to the view: its normal in the plane of tangent and view has <n, v> = sin theta,
 * so alpha = (2/pi) arccos(sin theta) = 1 - 2 theta / pi, one layer: the line's pixels are 2 theta / pi. */
static void test_line(test_gl *t)
{
    const double thetas[3] = {M_PI / 2, M_PI / 3, M_PI / 6};
    for (int k = 0; k < 3; k++) {
        lc_scene *s = line_scene(thetas[k]);
        CHECK(s != NULL, "line scene");
        if (!s)
            return;
        uint8_t *rgba = malloc(SIZE * SIZE * 4);
        lc_render_params p;
        direct_params(&p, LC_ALPHA_ANGLE);
        p.style.line_width = 0.1; /* a ribbon several pixels wide */
        render(t, s, &p, rgba);
        /* The row through the line's middle: its darkest pixel near the image centre. */
        double darkest = 1, r;
        for (int x = SIZE / 2 - 4; x < SIZE / 2 + 4; x++)
            darkest = fmin(darkest, pixel_at(rgba, x, SIZE / 2, &r));
        double want = 2 * thetas[k] / M_PI;
        CHECK(fabs(darkest - want) <= 0.02, "line at %.0f degrees: pixel %.3f, want %.3f", thetas[k] * 180 / M_PI,
              darkest, want);
        printf("line at %2.0f degrees to the view: pixel %.3f (want %.3f)\n", thetas[k] * 180 / M_PI, darkest, want);
        free(rgba);
        lc_scene_destroy(s);
    }
}

/* A point splat is a sphere: at disc radius u, <n, v> = sqrt(1 - u^2) and alpha = (2/pi) arcsin u; one layer. */
static void test_point(test_gl *t)
{
    lc_scene *s = point_scene();
    CHECK(s != NULL, "point scene");
    if (!s)
        return;
    uint8_t *rgba = malloc(SIZE * SIZE * 4);
    lc_render_params p;
    direct_params(&p, LC_ALPHA_ANGLE);
    p.style.point_size = 60; /* diameter in pixels */
    render(t, s, &p, rgba);
    double worst = 0, worst_u = 0, r;
    for (int y = 0; y < SIZE; y++)
        for (int x = 0; x < SIZE; x++) {
            double px = x + 0.5 - SIZE / 2, py = y + 0.5 - SIZE / 2, u = sqrt(px * px + py * py) / 30;
            if (u > 0.95)
                continue;
            double got = pixel_at(rgba, x, y, &r), want = 1 - 2 / M_PI * asin(u);
            if (fabs(got - want) > worst)
                worst = fabs(got - want), worst_u = u;
        }
    CHECK(worst <= 0.02, "point splat: pixels against 1 - (2/pi) arcsin u: worst error %.4f at u = %.3f", worst,
          worst_u);
    printf("point splat: worst pixel error %.4f at u %.3f\n", worst, worst_u);
    free(rgba);
    lc_scene_destroy(s);
}

int main(void)
{
    test_gl t;
    test_gl_open(&t);
    printf("renderer: %s\n", lc_gl_renderer(t.gl));
    test_sphere(&t);
    test_line(&t);
    test_point(&t);
    test_gl_close(&t);
    return lc_test_finish();
}
