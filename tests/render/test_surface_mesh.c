/* The meshed reference (docs/ALGORITHM.md §23, EVALUATION.md "Surfaces"): on the ABC
 * flow, the converged surface-layers image of a stream surface must match the
 * same surface integrated as a triangle mesh with front refinement
 * (stream_mesh.c) and rendered by the exact method with the same fixed
 * opacity per layer, SSIM >= 0.95; the weighted-average OIT of the same curves
 * must not (it saturates where many curves cross a pixel, PRT Fig. 5).
 * Also the mesh itself: every particle pair is split below the distance, and
 * the triangles join consecutive fronts. */
#include <math.h>

#include "camera.h"
#include "field.h"
#include "image.h"
#include "render_util.h"
#include "stream_mesh.h"
#include "surface_render.h"

#define SIZE 192
#define CURVES 4000
#define LENGTH 4.0 /* arc length of every curve (and mesh particle) */
#define OPACITY 0.3
/* Merge distance, a fraction of the diagonal (the request's default): at
 * 1e-3 a sheet seen obliquely splits into several layers per pixel (its depth
 * changes by more than epsilon across a pixel) and the SSIM falls to 0.91. */
#define EPSILON 1e-2
#define AMBIENT 0.3 /* surface_layers.c: shade = ambient + (1 - ambient) |n.z| */
#define SEED "3.14159,0.63,3.14159;3.14159,5.65,3.14159"

static const double COLOR[3] = {0.95, 0.6, 0.2};

/* The mesh as a triangle scene whose per-vertex rgb is the surface-layers
 * shading of its normal under the view (headlight along view z). */
static lc_scene *mesh_scene(const lc_stream_mesh *m, const lc_view *v)
{
    lc_error err = {0};
    lc_scene *s = lc_scene_create("stream-mesh", LC_PRIM_TRIANGLES);
    if (!s || lc_scene_alloc_vertices(s, m->vertex_count, 1, &err) != 0)
        return NULL;
    float *g = malloc(sizeof(float) * m->vertex_count);
    memcpy(s->positions, m->xyz, sizeof(float) * 3 * m->vertex_count);
    for (uint32_t i = 0; i < m->vertex_count; i++) {
        const float *n = m->normal + 3 * i;
        /* view z of the normal: the third row of the view matrix (column-major) */
        double nz = v->view[2] * n[0] + v->view[6] * n[1] + v->view[10] * n[2];
        double len = sqrt((double)n[0] * n[0] + (double)n[1] * n[1] + (double)n[2] * n[2]);
        double shade = AMBIENT + (1 - AMBIENT) * (len > 0 ? fabs(nz) / len : 1.0);
        for (int c = 0; c < 3; c++)
            s->rgb[3 * i + c] = (float)(COLOR[c] * shade);
        g[i] = 1.0f;
    }
    s->triangles = malloc(sizeof(uint32_t) * 3 * m->triangle_count);
    memcpy(s->triangles, m->triangles, sizeof(uint32_t) * 3 * m->triangle_count);
    s->triangle_count = m->triangle_count;
    lc_scene_add_attribute(s, "importance", g, &err);
    snprintf(s->default_importance, sizeof s->default_importance, "importance");
    snprintf(s->default_color, sizeof s->default_color, "rgb");
    lc_elements_desc ed = {.patch_count = 1}; /* one opacity for all: no element structure needed */
    if (lc_scene_finalize(s, &ed, &err) != 0) {
        fprintf(stderr, "finalize: %s\n", err.msg);
        lc_scene_destroy(s);
        return NULL;
    }
    return s;
}

/* The mesh's own guarantees: neighbours within split on every front, two
 * triangles per neighbour pair and step. */
static void check_mesh(const lc_stream_mesh *m, double split)
{
    CHECK(m->particles >= 33 && m->triangle_count > 0, "mesh: %u particles, %u triangles", m->particles,
          m->triangle_count);
    uint32_t far = 0;
    for (uint32_t t = 0; t < m->triangle_count; t++) {
        const uint32_t *v = m->triangles + 3 * t;
        CHECK(v[0] < m->vertex_count && v[1] < m->vertex_count && v[2] < m->vertex_count, "triangle %u indices", t);
        /* (a_k, b_k) of every quad's first triangle are neighbours on one front */
        if (t % 2 == 0) {
            const float *a = m->xyz + 3 * v[0], *b = m->xyz + 3 * v[1];
            double d =
                sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) + (a[2] - b[2]) * (a[2] - b[2]));
            far += d > split * (1 + 1e-6);
        }
    }
    CHECK(far == 0, "mesh: %u front edges longer than split %g", far, split);
}

int main(void)
{
    test_gl t;
    test_gl_open(&t);
    lc_error err = {0};
    lc_field *f = NULL;
    CHECK(lc_field_demo_create("abc-flow", &f, &err) == 0, "field: %s", err.msg);
    lc_seed seed;
    CHECK(lc_seed_parse(SEED, &seed, f, &err) == 0, "seed: %s", err.msg);

    /* The meshed reference with the same curves' length and step. */
    double split = 0.02;
    lc_stream_mesh m;
    lc_stream_mesh_desc md = {.trace = {.max_length = LENGTH}, .split = split};
    double t0 = lc_now();
    CHECK(lc_stream_mesh_build(f, &seed, &md, &m, &err) == 0, "mesh: %s", err.msg);
    printf("mesh: %u particles, %u vertices, %u triangles in %.0f ms\n", m.particles, m.vertex_count, m.triangle_count,
           (lc_now() - t0) * 1e3);
    check_mesh(&m, split);

    /* Surface layers, converged: all curves, the camera fitted to the surface
     * (the default frames the field's box, where the surface is small). */
    lc_render_params p;
    lc_render_params_default(&p);
    p.width = p.height = SIZE;
    double fit[6] = {INFINITY, INFINITY, INFINITY, -INFINITY, -INFINITY, -INFINITY};
    for (uint32_t i = 0; i < m.vertex_count; i++)
        for (int a = 0; a < 3; a++)
            fit[a] = fmin(fit[a], m.xyz[3 * i + a]), fit[3 + a] = fmax(fit[3 + a], m.xyz[3 * i + a]);
    const double dir[3] = {-1.0, 1.5, -0.8};
    lc_camera_fit(&p.camera, fit, dir, NULL);
    p.has_camera = true;
    p.style.background[0] = p.style.background[1] = p.style.background[2] = 1;
    lc_surface_params sp = {
        .particles = CURVES, .length = LENGTH, .epsilon = EPSILON, .opacity = OPACITY, .max_layers = 16};
    memcpy(sp.color, COLOR, sizeof sp.color);
    uint8_t *layers = malloc(SIZE * SIZE * 4), *wavg = malloc(SIZE * SIZE * 4), *ref = malloc(SIZE * SIZE * 4);
    lc_surface_info si;
    lc_camera cam;
    CHECK(lc_surface_render(f, &seed, &sp, &p, 2, layers, &si, &cam, &err) == 0, "surface layers: %s", err.msg);
    printf("surface layers: %llu curves, %.3f layers per covered pixel (max %u), overflow %llu, trace %.0f ms\n",
           (unsigned long long)si.stats.curves, si.stats.mean_layers, si.stats.max_layers,
           (unsigned long long)si.stats.overflow, si.trace_ms);
    sp.composite = LC_SURFACE_COMPOSITE_WEIGHTED_AVERAGE;
    CHECK(lc_surface_render(f, &seed, &sp, &p, 2, wavg, &si, NULL, &err) == 0, "weighted average: %s", err.msg);

    /* Exact method, one opacity for every fragment: q = r = 0 leave alpha = t. */
    p.method = LC_METHOD_EXACT;
    p.has_camera = true;
    p.camera = cam;
    p.style.shading = LC_SHADING_NONE;
    p.foo.q = p.foo.r = 0;
    p.foo.strength_given = true;
    p.foo.target_opacity = OPACITY;
    p.foo.normalize = LC_NORMALIZE_OFF;
    p.foo.clarity = 0;
    snprintf(p.color.attribute, sizeof p.color.attribute, "rgb");
    lc_view v;
    double box[6] = {f->bounds[0], f->bounds[1], f->bounds[2], f->bounds[3], f->bounds[4], f->bounds[5]};
    lc_camera_view(&cam, box, 1.0, SIZE, &v);
    lc_scene *s = mesh_scene(&m, &v);
    CHECK(s != NULL, "mesh scene");
    lc_gpu_scene *gs = NULL;
    CHECK(s && lc_gpu_scene_create(s, &gs, &err) == 0, "upload: %s", err.msg);
    lc_frame_info info;
    CHECK(gs && lc_render_frame(t.renderer, gs, &p, NULL, 0, ref, &info, &err) == 0, "exact: %s", err.msg);
    CHECK(info.dropped_fragments == 0, "exact: %llu fragments dropped", (unsigned long long)info.dropped_fragments);
    printf("exact mesh: %.3f fragments per covered pixel (max %u)\n", info.mean_layers, info.max_layers);

    double s_layers = lc_image_ssim(layers, ref, SIZE, SIZE), s_wavg = lc_image_ssim(wavg, ref, SIZE, SIZE);
    printf("SSIM to the exact-rendered mesh: surface layers %.4f, weighted average %.4f\n", s_layers, s_wavg);
    CHECK(s_layers >= 0.95, "surface layers match the meshed reference: SSIM %.4f", s_layers);
    CHECK(s_wavg < 0.95 && s_wavg < s_layers - 0.02, "weighted average does not: SSIM %.4f", s_wavg);
    if (getenv("LUCENT_SURFACE_MESH_PNG")) { /* the figure of EVALUATION.md "Surfaces" */
        const char *dir = getenv("LUCENT_SURFACE_MESH_PNG");
        char path[512];
        const uint8_t *imgs[3] = {layers, wavg, ref};
        const char *names[3] = {"layers", "weighted-average", "mesh-exact"};
        for (int i = 0; i < 3; i++) {
            snprintf(path, sizeof path, "%s/surface-%s.png", dir, names[i]);
            lc_image_write_file(path, imgs[i], SIZE, SIZE, 90, &err);
        }
    }
    lc_gpu_scene_destroy(gs);
    lc_scene_destroy(s);
    lc_stream_mesh_free(&m);
    free(layers);
    free(wavg);
    free(ref);
    lc_field_destroy(f);
    test_gl_close(&t);
    return lc_test_finish();
}
