/* P0 recording its fragments (render/gl/fragment_list.c): its depth moments
 * (p0_list.comp.glsl, which turns each pixel's chain around), P1
 * (p1_list.comp.glsl) and P2 over the list against every pass drawn
 * (LUCENT_FRAGMENT_LISTS=0): the same image byte for byte and the same
 * topDecileAlpha, on lines and on points; a frame whose fragments overflow
 * P0's list records again in a list of what it counted (P1 then over the
 * list), or where the list may not grow draws P0's moments again and P1:
 * the same bytes either way. P4 and P5
 * draw in both (LUCENT_P5_LIST=0), so that the comparison is the
 * optimization's alone. Where fragment lists are off (a GPU) both draw. */
#include <stdlib.h>
#include <string.h>

#include "demo.h"
#include "render_util.h"
#include "renderer_internal.h"

#define SIZE 256

/* lists: LUCENT_FRAGMENT_LISTS for the renderer made here; limit: P0's list
 * holds at most that many entries (0: as guessed), the first list made only
 * where once. */
static void render_with(const char *lists, const char *name, uint64_t limit, int once, uint8_t *rgba,
                        lc_frame_info *info)
{
    setenv("LUCENT_FRAGMENT_LISTS", lists, 1);
    test_gl t;
    test_gl_open(&t);
    lc_fragment_list_limit(t.renderer, limit, once);
    lc_render_params p;
    lc_render_params_default(&p);
    p.width = p.height = SIZE;
    p.foo.fade_half_life = 0;
    test_render_demo(&t, name, &p, rgba, info);
    test_gl_close(&t);
}

static void compare(const char *name, uint64_t limit, int once, int software)
{
    size_t n = (size_t)SIZE * SIZE * 4;
    uint8_t *drawn = malloc(n), *listed = malloc(n);
    lc_frame_info a = {0}, b = {0};
    render_with("0", name, 0, 0, drawn, &a);
    render_with(software ? "1" : "0", name, limit, once, listed, &b);
    int want = software && (!limit || once);
    CHECK(!a.importance_from_list && b.importance_from_list == want,
          "%s (list limit %llu%s): P1 over P0's fragments %d, wanted %d", name, (unsigned long long)limit,
          once ? " once" : "", b.importance_from_list, want);
    size_t differ = 0;
    for (size_t i = 0; i < n; i++)
        differ += drawn[i] != listed[i];
    printf("%-8s limit %-6llu%s P1 listed %d: %zu of %zu channels differ, topDecileAlpha %.9f / %.9f\n", name,
           (unsigned long long)limit, once ? " once" : "     ", b.importance_from_list, differ, n, a.top_decile_alpha,
           b.top_decile_alpha);
    CHECK(differ == 0 && a.top_decile_alpha == b.top_decile_alpha,
          "%s (list limit %llu): the drawn optimization's image, byte for byte (%zu channels differ)", name,
          (unsigned long long)limit, differ);
    free(drawn);
    free(listed);
}

/* One session's frames on a renderer of its own: a still of the fitted view,
 * then (with `drag`) a moving frame of camera x (the state's opacities, every
 * other line: P4 drawn and counted), then the still of x. x shows the thick
 * lines twice as large, four times the fragments the first still recorded
 * and more than the first guess: without the moving frame P0's first list
 * overflows and it records again. Returns the still's P0 vertices. */
static uint64_t drag_then_still(int drag, uint8_t *rgba)
{
    setenv("LUCENT_FRAGMENT_LISTS", "1", 1);
    test_gl t;
    test_gl_open(&t);
    lc_error err = {0};
    lc_demo_desc desc = {.count = 300};
    lc_scene *s = NULL;
    lc_gpu_scene *gs = NULL;
    CHECK(lc_demo_create("tornado", &desc, &s, &err) == 0 && lc_gpu_scene_create(s, &gs, &err) == 0, "tornado: %s",
          err.msg);
    lc_frame_state *st = lc_frame_state_create(s->elements.count);
    lc_render_params p;
    lc_render_params_default(&p);
    p.width = p.height = SIZE;
    p.style.line_width = 0.05;
    p.foo.fade_half_life = 0;
    lc_frame_info info;
    test_render_frame(&t, gs, &p, st, rgba, &info);
    p.has_camera = true;
    p.camera = info.camera;
    p.camera.view_angle /= 2;
    if (drag) {
        p.detail.reuse_opacities = true;
        p.detail.line_stride = 2;
        test_render_frame(&t, gs, &p, st, rgba, &info);
        CHECK(info.reused_opacities && info.line_stride == 2, "the moving frame: reused %d, stride %d",
              info.reused_opacities, info.line_stride);
        p.detail.reuse_opacities = false;
        p.detail.line_stride = 0;
    }
    p.detail.still = true;
    test_render_frame(&t, gs, &p, st, rgba, &info);
    CHECK(info.importance_from_list, "the still's P1 ran over P0's fragments");
    lc_frame_state_destroy(st);
    lc_gpu_scene_destroy(gs);
    lc_scene_destroy(s);
    test_gl_close(&t);
    return info.pass_vertices[LC_PASS_DEPTH_RANGE];
}

/* A still after a drag into a denser view: P0's list is sized by what the
 * drag's frame of that camera drew (lc_frame_state.fragment_hint), so P0
 * records once; the same image either way. */
static void drag_hint(void)
{
    size_t n = (size_t)SIZE * SIZE * 4;
    uint8_t *a = malloc(n), *b = malloc(n);
    uint64_t plain = drag_then_still(0, a), hinted = drag_then_still(1, b);
    printf("still after a drag: P0 issued %llu vertices, %llu without the drag's count\n", (unsigned long long)hinted,
           (unsigned long long)plain);
    CHECK(hinted > 0 && plain == 2 * hinted, "P0 recorded %llu and %llu vertices: once with the hint, twice without",
          (unsigned long long)hinted, (unsigned long long)plain);
    CHECK(memcmp(a, b, n) == 0, "the still is the same with and without the drag before it");
    free(a);
    free(b);
}

int main(void)
{
    setenv("LUCENT_P5_LIST", "0", 1);
    /* Whether this device lists at all: lists follow the driver unless forced. */
    unsetenv("LUCENT_FRAGMENT_LISTS");
    test_gl t;
    test_gl_open(&t);
    int software = lc_fragment_list_enabled();
    test_gl_close(&t);
    compare("tornado", 0, 0, software);
    compare("points", 0, 0, software);
    compare("tornado", 1000, 0, software); /* the list may not grow: drawn */
    compare("tornado", 1000, 1, software); /* the first list overflows: P0 records again */
    if (software)
        drag_hint();
    unsetenv("LUCENT_P5_LIST");
    unsetenv("LUCENT_FRAGMENT_LISTS");
    return lc_test_finish();
}
