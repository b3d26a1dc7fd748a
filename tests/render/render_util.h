/* Shared set-up for GL tests: one headless context + renderer, and scenes of
 * axis-aligned quads at known depths. */
#ifndef LC_RENDER_UTIL_H
#define LC_RENDER_UTIL_H

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "camera.h"
#include "demo.h"
#include "foo_math.h"
#include "gl_context.h"
#include "lc_test.h"
#include "renderer.h"
#include "scene.h"

typedef struct test_gl {
    lc_gl *gl;
    lc_renderer *renderer;
} test_gl;

/* Creates a context and renderer, or exits: 77 (skip) when no EGL/GL 4.5 is
 * available outside CI; in CI (CI=true) a missing GL fails the test. */
static inline void test_gl_open(test_gl *t)
{
    lc_error err = {0};
    lc_gl_desc desc = {.device = -1};
    if (lc_gl_create(&desc, &t->gl, &err) != 0) {
        const char *ci = getenv("CI");
        fprintf(stderr, "no OpenGL 4.5 context: %s\n", err.msg);
        exit(ci && strcmp(ci, "true") == 0 ? 1 : LC_TEST_SKIP);
    }
    if (lc_gl_make_current(t->gl, &err) != 0 || lc_renderer_create(NULL, &t->renderer, &err) != 0) {
        fprintf(stderr, "renderer: %s\n", err.msg);
        exit(1);
    }
}

/* One frame of gs at dt = 1/30 s with the state st (NULL: none); a failure fails the test. */
static inline void test_render_frame(test_gl *t, const lc_gpu_scene *gs, const lc_render_params *p, lc_frame_state *st,
                                     uint8_t *rgba, lc_frame_info *info)
{
    lc_error err = {0};
    int rc = lc_render_frame(t->renderer, gs, p, st, 1.0 / 30, rgba, info, &err);
    CHECK(rc == 0, "render: %s", err.msg);
}

/* Demo `name` (its defaults) and its GPU scene in *s and the result (NULL
 * after a failed check); the caller destroys both. */
static inline lc_gpu_scene *test_demo_upload(const char *name, lc_scene **s)
{
    lc_error err = {0};
    lc_gpu_scene *gs = NULL;
    lc_demo_desc desc = {0};
    *s = NULL;
    CHECK(lc_demo_create(name, &desc, s, &err) == 0 && lc_gpu_scene_create(*s, &gs, &err) == 0, "demo %s: %s", name,
          err.msg);
    return gs;
}

/* One frame of demo `name` (its defaults) under p without a frame state,
 * rendered on t: the scene is made and freed around it. */
static inline void test_render_demo(test_gl *t, const char *name, const lc_render_params *p, uint8_t *rgba,
                                    lc_frame_info *info)
{
    lc_scene *s;
    lc_gpu_scene *gs = test_demo_upload(name, &s);
    if (gs)
        test_render_frame(t, gs, p, NULL, rgba, info);
    lc_gpu_scene_destroy(gs);
    lc_scene_destroy(s);
}

static inline void test_gl_close(test_gl *t)
{
    lc_renderer_destroy(t->renderer);
    lc_gl_release_current(t->gl);
    lc_gl_destroy(t->gl);
}

/* Finishes a test scene whose importance is g (the scene takes it) and whose
 * colour is its per-vertex rgb: finalized with desc, or NULL (destroyed). */
static inline lc_scene *test_finish_scene(lc_scene *s, float *g, lc_elements_desc desc)
{
    lc_error err = {0};
    lc_scene_add_attribute(s, "importance", g, &err);
    snprintf(s->default_importance, sizeof s->default_importance, "importance");
    snprintf(s->default_color, sizeof s->default_color, "rgb");
    if (lc_scene_finalize(s, &desc, &err) != 0) {
        fprintf(stderr, "finalize: %s\n", err.msg);
        lc_scene_destroy(s);
        return NULL;
    }
    return s;
}

/* Finalizes s and uploads it: the GPU scene, or NULL after a failed check
 * (s is then destroyed). */
static inline lc_gpu_scene *test_upload_scene(lc_scene *s)
{
    lc_error err = {0};
    lc_gpu_scene *gs = NULL;
    int finalized = lc_scene_finalize(s, NULL, &err) == 0;
    CHECK(finalized, "finalize: %s", err.msg);
    if (finalized)
        CHECK(lc_gpu_scene_create(s, &gs, &err) == 0, "upload: %s", err.msg);
    if (!gs)
        lc_scene_destroy(s);
    return gs;
}

typedef struct test_quad {
    double z; /* world z of the quad (camera looks down -Z) */
    double g; /* importance */
    double rgb[3];
    double half; /* half extent in x and y */
} test_quad;

/* Triangles: one quad (4 vertices, 2 triangles) per entry, attribute
 * "importance" = g, per-vertex rgb. One patch per quad. */
static inline lc_scene *test_quad_scene(const test_quad *q, int n)
{
    lc_error err = {0};
    lc_scene *s = lc_scene_create("quads", LC_PRIM_TRIANGLES);
    if (!s || lc_scene_alloc_vertices(s, (uint32_t)(4 * n), 1, &err) != 0)
        return NULL;
    float *g = malloc(sizeof(float) * 4 * (size_t)n);
    s->triangles = malloc(sizeof(uint32_t) * 6 * (size_t)n);
    s->triangle_count = (uint32_t)(2 * n);
    static const double cx[4] = {-1, 1, 1, -1}, cy[4] = {-1, -1, 1, 1};
    for (int i = 0; i < n; i++) {
        for (int k = 0; k < 4; k++) {
            int v = 4 * i + k;
            s->positions[3 * v] = (float)(cx[k] * q[i].half);
            s->positions[3 * v + 1] = (float)(cy[k] * q[i].half);
            s->positions[3 * v + 2] = (float)q[i].z;
            for (int c = 0; c < 3; c++)
                s->rgb[3 * v + c] = (float)q[i].rgb[c];
            g[v] = (float)q[i].g;
        }
        uint32_t b = (uint32_t)(4 * i);
        uint32_t tri[6] = {b, b + 1, b + 2, b, b + 2, b + 3};
        memcpy(s->triangles + 6 * i, tri, sizeof tri);
    }
    return test_finish_scene(s, g, (lc_elements_desc){.patch_count = (uint32_t)n});
}

/* The fragments a pixel covered by every quad of q gets (n <= 16), as the
 * renderer sees them: depth normalized over the view's range (or, with
 * depthRange "pixel", the nearest to the farthest quad), warped by the
 * importance moments when `warp` (the moments' P0, which every quad covers at
 * the optimization resolution too), with the quads' importance and colour. */
static inline void test_quad_fragments(const test_quad *q, int n, const lc_render_params *p, const lc_scene *s,
                                       int warp, lc_fragment *frags)
{
    lc_view view;
    lc_camera_view(&p->camera, s->bounds, 1.0, p->height, &view);
    double zmin = view.depth_min, zmax = view.depth_max, margin = p->foo.depth_margin;
    if (p->foo.depth_range == LC_DEPTH_RANGE_PIXEL) {
        zmin = 1e30, zmax = -1e30, margin = LC_PIXEL_DEPTH_MARGIN;
        for (int i = 0; i < n; i++) {
            zmin = fmin(zmin, p->camera.position[2] - q[i].z);
            zmax = fmax(zmax, p->camera.position[2] - q[i].z);
        }
    }
    double moments[3] = {0, 0, 0};
    for (int i = 0; i < n; i++) {
        frags[i].depth = lc_foo_normalize_depth(p->camera.position[2] - q[i].z, zmin, zmax, margin);
        frags[i].importance = q[i].g;
        for (int c = 0; c < 3; c++)
            frags[i].color[c] = q[i].rgb[c];
        double w = q[i].g * q[i].g, u = frags[i].depth - 0.5;
        moments[0] += w, moments[1] += w * u, moments[2] += w * u * u;
    }
    for (int i = 0; warp && i < n; i++)
        frags[i].depth = lc_foo_moment_depth(frags[i].depth, moments, margin);
}

/* Orthographic view down -Z onto [-1,1]^2, unlit, rgb colours, importance range [0,1]. */
static inline void test_quad_params(lc_render_params *p, int size)
{
    lc_render_params_default(p);
    p->width = p->height = size;
    p->has_camera = true;
    lc_camera *c = &p->camera;
    c->position[0] = 0, c->position[1] = 0, c->position[2] = 5;
    c->focal_point[0] = c->focal_point[1] = c->focal_point[2] = 0;
    c->view_up[0] = 0, c->view_up[1] = 1, c->view_up[2] = 0;
    c->view_angle = 30;
    c->parallel_projection = true;
    c->parallel_scale = 1;
    p->style.shading = LC_SHADING_NONE;
    p->style.background[0] = p->style.background[1] = p->style.background[2] = 1;
    snprintf(p->color.attribute, sizeof p->color.attribute, "rgb");
    snprintf(p->importance.attribute, sizeof p->importance.attribute, "importance");
    p->importance.has_range = true;
    p->importance.range[0] = 0, p->importance.range[1] = 1;
    p->importance.exponent = 1;
}

#endif
