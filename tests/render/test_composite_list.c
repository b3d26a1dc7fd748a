/* P4's sums and P5 over the fragments P4 recorded (render/gl/fragment_list.c,
 * p4_list.comp.glsl, p5_list.comp.glsl) against the drawn passes, on lines
 * and on points, coloured through the colormap (lines' colours looked up in
 * P5's walk), per vertex (RGB) and unshaded: the same
 * picture (SSIM >= 0.999, no more than 2 % of the channels apart, one in 2000
 * by more than 2/255), topDecileReach within 1e-4 (the list keeps the opacity
 * in 11 significant bits and g in 16), and the frame reports which path P5
 * took; a frame that overflows the list is the drawn one. Both draw P4, the
 * pass that records (points without a list would compute it). LUCENT_P5_LIST picks the path for the renderer
 * created after it is set (the default takes the list only in frames of millions of fragments, which these small frames
 * are not). Where fragment lists are off (a GPU) both renderers draw and only the report is checked. The chain
 * heads kept through framebuffer fetch give the swapped heads' image byte for byte, and P4's sums made in P5's walk
 * the image of two walks. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "demo.h"
#include "gl_context.h"
#include "image.h"
#include "render_util.h"
#include "renderer_internal.h"

#define SIZE 256

/* limit: P4's list holds at most that many entries (0: as guessed), the
 * first list made only where once; halo:
 * style.haloWidth in pixels (the list marks a halo's fragments, whose series
 * depth the walks clamp short of the far end; their fragments overflow the
 * first guess, and the frame records again). */
typedef enum { COLORS_MAP, COLORS_RGB, COLORS_UNSHADED } colors;

/* The demo with per-vertex colours from its positions (color.attribute "rgb"). */
static void render_rgb(test_gl *t, const char *name, lc_render_params *p, uint8_t *rgba, lc_frame_info *info)
{
    lc_error err = {0};
    lc_scene *s = NULL;
    lc_gpu_scene *gs = NULL;
    lc_demo_desc desc = {0};
    CHECK(lc_demo_create(name, &desc, &s, &err) == 0, "demo %s: %s", name, err.msg);
    if (!s)
        return;
    s->rgb = malloc((size_t)s->vertex_count * 3 * sizeof *s->rgb);
    for (uint32_t v = 0; v < s->vertex_count && s->rgb; v++)
        for (int c = 0; c < 3; c++) {
            double lo = s->bounds[c], hi = s->bounds[3 + c];
            s->rgb[3 * v + c] = hi > lo ? (float)((s->positions[3 * v + c] - lo) / (hi - lo)) : 0.5f;
        }
    snprintf(p->color.attribute, sizeof p->color.attribute, "rgb");
    CHECK(s->rgb && lc_gpu_scene_create(s, &gs, &err) == 0, "demo %s with rgb: %s", name, err.msg);
    if (gs)
        test_render_frame(t, gs, p, NULL, rgba, info);
    lc_gpu_scene_destroy(gs);
    lc_scene_destroy(s);
}

static void render_colored(const char *mode, const char *name, uint64_t limit, int once, double halo, colors c,
                           uint8_t *rgba, lc_frame_info *info)
{
    setenv("LUCENT_P5_LIST", mode, 1);
    test_gl t;
    test_gl_open(&t);
    lc_composite_list_limit(t.renderer, limit, once);
    lc_render_params p;
    lc_render_params_default(&p);
    p.width = p.height = SIZE;
    p.foo.fade_half_life = 0;
    p.style.halo_width = halo;
    p.style.halo_depth = 0.5; /* pushes halos past their pixels' far ends, where the series depth is clamped */
    if (c == COLORS_UNSHADED)
        p.style.shading = LC_SHADING_NONE;
    if (c == COLORS_RGB)
        render_rgb(&t, name, &p, rgba, info);
    else
        test_render_demo(&t, name, &p, rgba, info);
    test_gl_close(&t);
}

static void render_with(const char *mode, const char *name, uint64_t limit, int once, double halo, uint8_t *rgba,
                        lc_frame_info *info)
{
    render_colored(mode, name, limit, once, halo, COLORS_MAP, rgba, info);
}

/* c: the colours through the colormap, lit (the list keeps the colormap's
 * coordinate and <n, l>, and P5's walk shades them), per-vertex RGB (the list
 * keeps the lit colour) or unshaded. */
static void compare(const char *name, double halo, colors c)
{
    size_t n = (size_t)SIZE * SIZE * 4;
    uint8_t *drawn = malloc(n), *listed = malloc(n);
    lc_frame_info a = {0}, b = {0};
    render_colored("0", name, 0, 0, halo, c, drawn, &a);
    render_colored("1", name, 0, 0, halo, c, listed, &b);
    int lists = lc_fragment_list_enabled();
    CHECK(!a.composite_from_list, "%s: LUCENT_P5_LIST=0 draws P5", name);
    CHECK(b.composite_from_list == lists, "%s: LUCENT_P5_LIST=1 takes the list where lists are on (%d, lists %d)", name,
          b.composite_from_list, lists);
    size_t differ = 0, far = 0;
    int max = 0;
    for (size_t i = 0; i < n; i++) {
        int d = abs((int)drawn[i] - (int)listed[i]);
        differ += d > 0, far += d > 2;
        max = d > max ? d : max;
    }
    double ssim = lc_image_ssim(drawn, listed, SIZE, SIZE);
    static const char *const color_names[] = {"colormap", "rgb", "unshaded"};
    printf("%-8s halo %.0f %-8s listed %d: %zu of %zu channels differ (%zu by more than 2, max %d), SSIM %.6f, reach "
           "%.6f / %.6f\n",
           name, halo, color_names[c], b.composite_from_list, differ, n, far, max, ssim, a.top_decile_reach,
           b.top_decile_reach);
    CHECK(ssim >= 0.999, "%s: SSIM %.6f between the listed and the drawn P5", name, ssim);
    CHECK(differ <= n / 50 && far <= n / 2000, "%s: %zu channels differ, %zu by more than 2", name, differ, far);
    CHECK(a.has_reach && b.has_reach && fabs(a.top_decile_reach - b.top_decile_reach) <= 1e-4,
          "%s: topDecileReach %.6f drawn, %.6f listed", name, a.top_decile_reach, b.top_decile_reach);
    free(drawn);
    free(listed);
}

/* A frame whose fragments overflow a list that may not grow draws P4 again
 * and P5: the drawn image, byte for byte. One that overflows its first list
 * records again in a list of what it counted: the listed image, byte for byte. */
static void overflow(void)
{
    size_t n = (size_t)SIZE * SIZE * 4;
    uint8_t *drawn = malloc(n), *over = malloc(n), *listed = malloc(n), *again = malloc(n);
    lc_frame_info a = {0}, b = {0}, c = {0}, d = {0};
    render_with("0", "tornado", 0, 0, 0, drawn, &a);
    render_with("1", "tornado", 1000, 0, 0, over, &b);
    CHECK(!b.composite_from_list, "a list of 1000 entries overflows: P5 draws");
    CHECK(memcmp(drawn, over, n) == 0 && a.top_decile_reach == b.top_decile_reach,
          "the overflowing frame is the drawn one (reach %.6f / %.6f)", a.top_decile_reach, b.top_decile_reach);
    render_with("1", "tornado", 0, 0, 0, listed, &c);
    render_with("1", "tornado", 1000, 1, 0, again, &d);
    int lists = lc_fragment_list_enabled();
    CHECK(d.composite_from_list == lists, "a first list of 1000 entries overflows: P4 records again (listed %d)",
          d.composite_from_list);
    CHECK(memcmp(listed, again, n) == 0 && c.top_decile_reach == d.top_decile_reach,
          "the frame that recorded again is the listed one (reach %.6f / %.6f)", c.top_decile_reach,
          d.top_decile_reach);
    free(drawn);
    free(over);
    free(listed);
    free(again);
}

/* The demo rendered with lists by default and with the switch `var` at 0:
 * how many channels differ; a and b the two frames' reports. */
static size_t differ_with_switch_off(const char *name, const char *var, lc_frame_info *a, lc_frame_info *b)
{
    size_t n = (size_t)SIZE * SIZE * 4, differ = 0;
    uint8_t *on = malloc(n), *off = malloc(n);
    unsetenv(var);
    render_with("1", name, 0, 0, 0, on, a);
    setenv(var, "0", 1);
    render_with("1", name, 0, 0, 0, off, b);
    unsetenv(var);
    for (size_t i = 0; i < n; i++)
        differ += on[i] != off[i];
    free(on);
    free(off);
    return differ;
}

/* The recording passes' chain heads kept through framebuffer fetch (the
 * default where the driver has GL_EXT_shader_framebuffer_fetch) and swapped
 * atomically (LUCENT_HEADS_FETCH=0) give the same lists: P0's chains and P4's
 * in the same order, the same image byte for byte. */
static void heads_fetch(const char *name)
{
    lc_frame_info a = {0}, b = {0};
    unsetenv("LUCENT_HEADS_FETCH");
    test_gl t;
    test_gl_open(&t);
    bool fetch = t.renderer->heads_fetch;
    test_gl_close(&t);
    size_t differ = differ_with_switch_off(name, "LUCENT_HEADS_FETCH", &a, &b);
    printf("%-8s heads through framebuffer fetch %d: %zu of %d channels differ from the swapped heads'\n", name, fetch,
           differ, SIZE * SIZE * 4);
    CHECK(a.composite_from_list == b.composite_from_list && a.importance_from_list == b.importance_from_list,
          "%s: the same paths with the heads fetched and swapped", name);
    CHECK(differ == 0 && a.top_decile_reach == b.top_decile_reach,
          "%s: heads fetched or swapped, the same image byte for byte (%zu channels differ)", name, differ);
}

/* P4's sums made in P5's walk (one process, the default) and in a walk of
 * their own (LUCENT_SUMS_IN_WALK=0): the same sums from the same chains, the
 * same image byte for byte. */
static void sums_in_walk(const char *name)
{
    lc_frame_info a = {0}, b = {0};
    size_t differ = differ_with_switch_off(name, "LUCENT_SUMS_IN_WALK", &a, &b);
    printf("%-8s sums in P5's walk (%d walk, %d with the switch off): %zu of %d channels differ from two walks'\n",
           name, a.composite_walks, b.composite_walks, differ, SIZE * SIZE * 4);
    CHECK(a.composite_from_list == b.composite_from_list, "%s: the same paths with the sums in one walk or two", name);
    CHECK(!a.composite_from_list || (a.composite_walks == 1 && b.composite_walks == 2),
          "%s: %d walks over P4's fragments by default, %d with the switch off (want 1 and 2)", name, a.composite_walks,
          b.composite_walks);
    CHECK(differ == 0 && a.top_decile_reach == b.top_decile_reach,
          "%s: sums in one walk or two, the same image byte for byte (%zu channels differ)", name, differ);
}

/* Whether a frame takes the list is a function of the frame alone: a
 * renderer that learned another ratio of P4's entries to P0's for the scene
 * and size (here one that would put the frame past the list's bound) records
 * it as a fresh one does, the same bytes (the listed and the drawn images
 * differ in places, and a daemon's one-shot renders must not depend on what
 * their worker drew before). */
static void learned_ratio(void)
{
    size_t n = (size_t)SIZE * SIZE * 4;
    uint8_t *first = malloc(n), *second = malloc(n);
    lc_frame_info a = {0}, b = {0};
    setenv("LUCENT_P5_LIST", "1", 1);
    test_gl t;
    test_gl_open(&t);
    lc_render_params p;
    lc_render_params_default(&p);
    p.width = p.height = SIZE;
    p.foo.fade_half_life = 0;
    lc_scene *s;
    lc_gpu_scene *gs = test_demo_upload("tornado", &s);
    if (gs) {
        test_render_frame(&t, gs, &p, NULL, first, &a);
        t.renderer->composite_ratio *= 1e9; /* (its scene and size are this frame's) */
        test_render_frame(&t, gs, &p, NULL, second, &b);
    }
    int lists = lc_fragment_list_enabled();
    size_t differ = 0;
    for (size_t i = 0; i < n; i++)
        differ += first[i] != second[i];
    printf("learned ratio: listed %d then %d, %zu channels differ\n", a.composite_from_list, b.composite_from_list,
           differ);
    CHECK(a.composite_from_list == lists && b.composite_from_list == lists,
          "a learned ratio does not change the path (listed %d, then %d)", a.composite_from_list,
          b.composite_from_list);
    CHECK(differ == 0, "a learned ratio does not change the image (%zu channels differ)", differ);
    lc_gpu_scene_destroy(gs);
    lc_scene_destroy(s);
    test_gl_close(&t);
    free(first);
    free(second);
}

/* The device's rule (compute_raster.c): on a software rasterizer points compute
 * P4 and P5, except in a frame whose P4 records its fragments, which draws it. */
static void points_rule(void)
{
    unsetenv("LUCENT_COMPUTE_RASTER");
    size_t n = (size_t)SIZE * SIZE * 4;
    uint8_t *rgba = malloc(n);
    lc_frame_info a = {0}, b = {0};
    render_with("0", "points", 0, 0, 0, rgba, &a);
    render_with("1", "points", 0, 0, 0, rgba, &b);
    test_gl t;
    test_gl_open(&t);
    int software = lc_gl_renderer_is_software(lc_gl_renderer(t.gl));
    test_gl_close(&t);
    int lists = lc_fragment_list_enabled();
    CHECK(!!(a.computed_passes & (1 << LC_RASTER_P4)) == software && !a.composite_from_list,
          "points without the list: P4 %s by the rule (computed passes %#x)", software ? "computed" : "drawn",
          a.computed_passes);
    CHECK(b.composite_from_list == lists && !(b.computed_passes & (1 << LC_RASTER_P4)) == (lists || !software),
          "points with the list: P4 drawn, recording (listed %d, computed passes %#x)", b.composite_from_list,
          b.computed_passes);
    free(rgba);
}

int main(void)
{
    setenv("LUCENT_COMPUTE_RASTER", "0", 1); /* the drawn reference of points draws P4 and P5 too */
    compare("tornado", 0, COLORS_MAP);
    compare("tornado", 3, COLORS_MAP);
    compare("tornado", 0, COLORS_RGB);
    compare("tornado", 0, COLORS_UNSHADED);
    compare("points", 0, COLORS_MAP);
    compare("points", 0, COLORS_RGB);
    overflow();
    heads_fetch("tornado");
    heads_fetch("points");
    sums_in_walk("tornado");
    sums_in_walk("points");
    learned_ratio();
    points_rule();
    unsetenv("LUCENT_P5_LIST");
    return lc_test_finish();
}
