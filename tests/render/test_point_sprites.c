/* Points drawn as GL point sprites (lc_frame_point_sprites, docs/ALGORITHM.md
 * "Point sprites") give the image of the 4-vertex quads they replace:
 * - with splats that cross every edge of the image (a camera close to the
 *   cloud), opaque, Fourier and exact frames equal the quads' within 3/255
 *   per channel, the edge columns and rows included: the guard band draws a
 *   splat whose centre lies just outside (GL drops such a point);
 * - a tiled frame with sprites equals the untiled quads' frame (no seams at
 *   the tiles' edges);
 * - LUCENT_POINT_SPRITES=0 draws quads, and a splat wider than the driver's
 *   largest point falls back to quads. */
#include <epoxy/gl.h>
#include <math.h>

#include "demo.h"
#include "image.h"
#include "render_util.h"

#define W 192
#define H 144
#define BAND 4 /* edge band of the image, pixels */

typedef struct diff {
    int max;         /* largest channel difference */
    double edge;     /* mean channel difference in the edge band */
    double coverage; /* share of edge-band pixels off the background in the quads' image */
} diff;

static diff compare(const uint8_t *quads, const uint8_t *sprites)
{
    diff d = {0, 0, 0};
    double sum = 0;
    int n = 0, covered = 0;
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            const uint8_t *a = quads + 4 * ((size_t)y * W + x), *b = sprites + 4 * ((size_t)y * W + x);
            int edge = x < BAND || y < BAND || x >= W - BAND || y >= H - BAND;
            for (int c = 0; c < 3; c++) {
                int e = abs((int)a[c] - (int)b[c]);
                d.max = e > d.max ? e : d.max;
                if (edge)
                    sum += e;
            }
            if (edge) {
                n++;
                covered += a[0] + a[1] + a[2] < 3 * 250;
            }
        }
    d.edge = sum / (3.0 * n);
    d.coverage = (double)covered / n;
    return d;
}

static void render(test_gl *t, const lc_gpu_scene *gs, const lc_render_params *p, int sprites, uint8_t *rgba,
                   lc_frame_info *info)
{
    setenv("LUCENT_POINT_SPRITES", sprites ? "1" : "0", 1);
    test_render_frame(t, gs, p, NULL, rgba, info);
    unsetenv("LUCENT_POINT_SPRITES");
}

int main(void)
{
    test_gl t, tiled;
    test_gl_open(&t);
    lc_error err = {0};
    lc_scene *s = NULL;
    lc_demo_desc desc = {.count = 3000};
    lc_gpu_scene *gs = NULL;
    CHECK(lc_demo_create("points", &desc, &s, &err) == 0 && lc_gpu_scene_create(s, &gs, &err) == 0, "points: %s",
          err.msg);
    if (!gs)
        return lc_test_finish();
    /* Look at one corner of the cloud from close by: splats cross all four edges. */
    double c[3], e = 0;
    for (int i = 0; i < 3; i++) {
        c[i] = 0.5 * (s->bounds[2 * i] + s->bounds[2 * i + 1]);
        e = fmax(e, s->bounds[2 * i + 1] - s->bounds[2 * i]);
    }
    lc_render_params p;
    lc_render_params_default(&p);
    p.width = W, p.height = H;
    p.has_camera = true;
    p.camera = (lc_camera){.position = {c[0] + 0.2 * e, c[1] + 0.1 * e, c[2] + 0.9 * e},
                           .focal_point = {c[0] + 0.2 * e, c[1] + 0.1 * e, c[2]},
                           .view_up = {0, 1, 0},
                           .view_angle = 30};
    p.style.point_size = 9;
    p.style.background[0] = p.style.background[1] = p.style.background[2] = 1;
    uint8_t *quads = malloc((size_t)W * H * 4), *sprites = malloc((size_t)W * H * 4);
    lc_frame_info qi, si;

    static const lc_method methods[] = {LC_METHOD_OPAQUE, LC_METHOD_FOURIER, LC_METHOD_EXACT};
    static const char *names[] = {"opaque", "fourier", "exact"};
    for (int m = 0; m < 3; m++) {
        p.method = methods[m];
        render(&t, gs, &p, 0, quads, &qi);
        render(&t, gs, &p, 1, sprites, &si);
        CHECK(!qi.point_sprites && si.point_sprites, "%s: quads with LUCENT_POINT_SPRITES=0 (%d), sprites else (%d)",
              names[m], qi.point_sprites, si.point_sprites);
        diff d = compare(quads, sprites);
        printf("%s: max channel difference %d/255, edge band mean %.4f, edge band covered %.2f\n", names[m], d.max,
               d.edge, d.coverage);
        CHECK(d.coverage > 0.3, "%s: the splats cross the edges (%.2f of the edge band covered)", names[m], d.coverage);
        CHECK(d.max <= 3 && d.edge < 0.05, "%s: sprites equal quads (max %d/255, edge band mean %.4f)", names[m], d.max,
              d.edge);
    }

    /* Tiles: a renderer that tiles every frame above 64x64. */
    p.method = LC_METHOD_FOURIER;
    render(&t, gs, &p, 0, quads, &qi);
    lc_gl_release_current(t.gl);
    tiled.gl = t.gl;
    lc_renderer_desc td = {.tile_size = 64};
    CHECK(lc_gl_make_current(tiled.gl, &err) == 0 && lc_renderer_create(&td, &tiled.renderer, &err) == 0,
          "tiled renderer: %s", err.msg);
    if (tiled.renderer) {
        render(&tiled, gs, &p, 1, sprites, &si);
        diff d = compare(quads, sprites);
        printf("tiled sprites (%d tiles) against untiled quads: max %d/255, edge band mean %.4f\n", si.tiles, d.max,
               d.edge);
        CHECK(si.tiles > 1 && si.point_sprites, "the frame was tiled (%d) and drew sprites (%d)", si.tiles,
              si.point_sprites);
        CHECK(d.max <= 3, "tiled sprites equal untiled quads (max %d/255): no seams", d.max);
        lc_renderer_destroy(tiled.renderer);
    }

    /* A splat wider than any driver's point (the request's limit is 256 px). */
    p.method = LC_METHOD_OPAQUE;
    p.style.point_size = 256;
    render(&t, gs, &p, 1, sprites, &si);
    GLfloat range[2] = {0, 0};
    glGetFloatv(GL_POINT_SIZE_RANGE, range);
    CHECK(si.point_sprites == (range[1] >= 256), "a 256 px splat: sprites %d where the largest point is %.0f px",
          si.point_sprites, range[1]);

    free(quads);
    free(sprites);
    lc_gpu_scene_destroy(gs);
    lc_scene_destroy(s);
    test_gl_close(&t);
    return lc_test_finish();
}
