/* The cost model in process (cost.c) against the pass plan (render/gl
 * pass_plan.c): an opaque frame of splats computed by hand, the passes the
 * plan adds for each depth range and method, and the field a refusal names. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "cost.h"
#include "lc_test.h"
#include "renderer.h"

#define PI 3.14159265358979323846

static lc_scene_measures points(double n)
{
    lc_scene_measures st;
    memset(&st, 0, sizeof st);
    st.type = LC_PRIM_POINTS;
    st.primitives = st.vertices = st.elements = n;
    st.radius = 1.0;
    return st;
}

static lc_render_params params(lc_method m, lc_depth_range range)
{
    lc_render_params p;
    lc_render_params_default(&p);
    p.width = 200;
    p.height = 100;
    p.method = m;
    p.foo.depth_range = range;
    return p;
}

static void test_plan(void)
{
    lc_pass_plan plan;
    lc_render_params p = params(LC_METHOD_FOURIER, LC_DEPTH_RANGE_MOMENTS);
    lc_pass_plan_make(&p, 0, &plan);
    CHECK(plan.moments && !plan.pixel_range && plan.run[LC_PASS_DEPTH_RANGE] == LC_RUN_LOW,
          "fourier, moments: P0 at the optimization resolution");
    CHECK(plan.run[LC_PASS_IMPORTANCE] == LC_RUN_LOW && plan.run[LC_PASS_OPACITY] == LC_RUN_LOW &&
              plan.run[LC_PASS_SMOOTH] == LC_RUN_ONCE && plan.run[LC_PASS_OPTICAL_DEPTH] == LC_RUN_FULL &&
              plan.run[LC_PASS_ACCUMULATE] == LC_RUN_FULL && plan.run[LC_PASS_RESOLVE] == LC_RUN_FULL,
          "fourier: P1, P2 low, P3 once, P4-P6 full");
    p.detail.reuse_opacities = 1;
    lc_pass_plan_make(&p, 1, &plan);
    CHECK(plan.reuse && !plan.moments && plan.run[LC_PASS_IMPORTANCE] == LC_RUN_NONE &&
              plan.run[LC_PASS_SMOOTH] == LC_RUN_NONE && plan.run[LC_PASS_DEPTH_RANGE] == LC_RUN_NONE,
          "reusing opacities: no P1-P3 and no moments");
    lc_pass_plan_make(&p, 0, &plan);
    CHECK(!plan.reuse && plan.moments, "no state to reuse: a full frame");
    p = params(LC_METHOD_OPAQUE, LC_DEPTH_RANGE_PIXEL);
    lc_pass_plan_make(&p, 0, &plan);
    int runs = 0;
    for (int k = 0; k < LC_PASS_COUNT; k++)
        runs += plan.run[k] != LC_RUN_NONE;
    CHECK(runs == 2 && plan.run[LC_PASS_ACCUMULATE] == LC_RUN_FULL && plan.run[LC_PASS_READBACK] == LC_RUN_FULL,
          "opaque: one pass and the readback (%d)", runs);
    p = params(LC_METHOD_DIRECT, LC_DEPTH_RANGE_PIXEL);
    lc_pass_plan_make(&p, 0, &plan);
    CHECK(plan.pixel_range && plan.run[LC_PASS_DEPTH_RANGE] == LC_RUN_BOTH &&
              plan.run[LC_PASS_IMPORTANCE] == LC_RUN_NONE,
          "direct, pixel range: P0 at both resolutions, no P1-P3");
}

static void test_estimates(void)
{
    /* Opaque splats by hand: each covers pi r^2 pixels, one pass. */
    lc_scene_measures st = points(1000);
    lc_render_params p = params(LC_METHOD_OPAQUE, LC_DEPTH_RANGE_GLOBAL);
    double r = fmax(0.5 * p.style.point_size, 0.75), image = 200.0 * 100.0;
    double frags = 1000 * fmin(PI * r * r, image);
    double want = frags + image + (1000 + 100.0 * 1000) + 1000 * (p.foo.smoothing + 1.0);
    CHECK_NEAR(lc_cost_estimate(&st, &p), want, 1e-9 * want, "opaque splats");

    /* Fourier by hand: P1 (targets / subset) and P2 at s^2, P4 and P5 at full,
     * plus P0 by the depth range; the set-up once per traversal (P1 and P4
     * write their targets in one draw). */
    p = params(LC_METHOD_FOURIER, LC_DEPTH_RANGE_GLOBAL);
    p.foo.clarity = 0; /* one try */
    double s2 = p.foo.resolution_scale * p.foo.resolution_scale, t = ceil((2.0 * p.foo.bands + 1.0) / 4.0);
    double sub = p.foo.subset > 1 ? p.foo.subset : 1, setup = 1000 + 100.0 * 1000;
    double geometry = (s2 + 1.0) * (t / sub + 1.0), screens = t + 2.0;
    double base = frags * geometry + image * screens + setup * 4 + 1000 * (p.foo.smoothing + 1.0);
    CHECK_NEAR(lc_cost_estimate(&st, &p), base, 1e-9 * base, "fourier, global range: four traversals");
    p.foo.depth_range = LC_DEPTH_RANGE_MOMENTS;
    double g2 = geometry + s2 / sub;
    double m = frags * g2 + image * screens + setup * 5 + 1000 * (p.foo.smoothing + 1.0);
    CHECK_NEAR(lc_cost_estimate(&st, &p), m, 1e-9 * m, "fourier, moments: one more target at s^2, one more traversal");
    p.foo.depth_range = LC_DEPTH_RANGE_PIXEL;
    double g3 = geometry + s2 + 1.0;
    double px = frags * g3 + image * screens + setup * 6 + 1000 * (p.foo.smoothing + 1.0);
    CHECK_NEAR(lc_cost_estimate(&st, &p), px, 1e-9 * px, "fourier, pixel range: a pass at both resolutions");
    /* params.clarity: each try repeats P2 (and P3), never P1, whose sums do not depend on the strength. */
    lc_render_params cl = p;
    cl.foo.clarity = 0.5;
    double more = (LC_CLARITY_CHARGED_TRIES - 1.0) * (frags * s2 + setup + 1000 * (p.foo.smoothing + 1.0));
    CHECK_NEAR(lc_cost_estimate(&st, &cl) - px, more, 1e-9 * px, "clarity: P2 and P3 once more per try, not P1");

    /* color.equalize: the histogram pass (one geometry pass at full resolution)
     * and P4-P6 once more. */
    p.foo.depth_range = LC_DEPTH_RANGE_GLOBAL;
    p.color.equalize = true;
    double eg = 1.0 + t / sub + 1.0;
    double eq = base + LC_COST_EQUALIZE_FACTOR * (frags * eg + image * screens + (1000 + 100.0 * 1000) * 3.0);
    CHECK_NEAR(lc_cost_estimate(&st, &p), eq, 1e-9 * eq, "fourier, color.equalize");
    p.color.equalize = false;
    /* exact: list pass 1 (2 units a fragment) and the blend (2) once more, one more draw. */
    lc_render_params ex = params(LC_METHOD_EXACT, LC_DEPTH_RANGE_GLOBAL), exq = ex;
    exq.color.equalize = true;
    double de = lc_cost_estimate(&st, &exq) - lc_cost_estimate(&st, &ex),
           want_eq = LC_COST_EQUALIZE_FACTOR * (frags * 4 + image * 2 + 101000.0);
    CHECK_NEAR(de, want_eq, 1e-9 * want_eq, "exact, color.equalize: list pass 1 and the blend again");
    p.foo.depth_range = LC_DEPTH_RANGE_PIXEL;

    /* Direct: what the plan runs is charged, P0's pixel range included. */
    lc_render_params d = params(LC_METHOD_DIRECT, LC_DEPTH_RANGE_GLOBAL), dp = d;
    dp.foo.depth_range = LC_DEPTH_RANGE_PIXEL;
    CHECK(lc_cost_estimate(&st, &dp) > lc_cost_estimate(&st, &d), "direct with the pixel range costs more");
    /* Kanzler: direct's passes plus its maps, one geometry pass of the frame's fragments and three screens in P0. */
    lc_render_params k = params(LC_METHOD_KANZLER, LC_DEPTH_RANGE_GLOBAL);
    double dk = lc_cost_estimate(&st, &k) - lc_cost_estimate(&st, &d), want_k = frags + image * 3 + 101000.0;
    CHECK_NEAR(dk, want_k, 1e-9 * want_k, "kanzler: direct's cost and its maps");
    lc_pass_plan kp;
    lc_pass_plan_make(&k, 0, &kp);
    CHECK(kp.kanzler_maps && kp.run[LC_PASS_DEPTH_RANGE] == LC_RUN_FULL && kp.run[LC_PASS_IMPORTANCE] == LC_RUN_NONE,
          "kanzler's plan: the maps in P0 at full resolution, no optimization");

    /* Larger images cost more; a refusal names the field to lower. */
    lc_render_params big = p;
    big.width *= 2;
    CHECK(lc_cost_estimate(&st, &big) > lc_cost_estimate(&st, &p), "a wider image costs more");
    lc_render_params huge = params(LC_METHOD_FOURIER, LC_DEPTH_RANGE_AUTO);
    huge.style.point_size = 64;
    double cost = 0;
    const char *field = NULL;
    char why[320];
    lc_render_params normal = params(LC_METHOD_FOURIER, LC_DEPTH_RANGE_AUTO);
    double budget = lc_cost_estimate(&st, &normal) * 1.1;
    CHECK(lc_cost_check(&st, &huge, budget, &cost, &field, why, sizeof why) != 0 && field &&
              strcmp(field, "style.pointSize") == 0,
          "huge splats are refused naming style.pointSize (%s: %s)", field ? field : "-", why);
    CHECK(lc_cost_check(&st, &huge, 0, &cost, &field, why, sizeof why) == 0, "budget 0 = no limit");
}

/* A frame is priced at the level of detail it draws: the coarsest level whose
 * error stays under params.lod pixels at the data's nearest depth. */
static void test_levels(void)
{
    lc_scene_measures st;
    memset(&st, 0, sizeof st);
    st.type = LC_PRIM_LINES;
    st.primitives = st.vertices = 2e6;
    st.elements = 1e4;
    st.lines = 4000;
    st.line_length = 500;
    st.radius = 1.0;
    st.levels = 3;
    /* level 1: half the segments within 4e-4 world units, level 2: a tenth within 4e-3 */
    st.level_error[1] = 4e-4, st.level_error[2] = 4e-3;
    st.level_share[0] = 1, st.level_share[1] = 0.5, st.level_share[2] = 0.1;
    lc_scene_measures full = st;
    full.levels = 0;
    lc_render_params p = params(LC_METHOD_FOURIER, LC_DEPTH_RANGE_MOMENTS);
    /* fitted: 2/H units a pixel at the centre, x (1 - sin 15 deg) = 0.741 at the
     * nearest depth, x params.lod 0.2 (the default): 64 -> 4.63e-3 */
    p.width = p.height = 64;
    lc_scene_measures coarse = st;
    coarse.levels = 0, coarse.primitives = coarse.vertices = 2e5;
    double small = lc_cost_estimate(&st, &p);
    CHECK(fabs(small - lc_cost_estimate(&coarse, &p)) < 1e-6 * small,
          "64x64: priced as level 2's tenth of the segments (%g, %g)", small, lc_cost_estimate(&coarse, &p));
    p.width = p.height = 4096; /* 7.2e-5: under level 1's error, full detail */
    CHECK(lc_cost_estimate(&st, &p) == lc_cost_estimate(&full, &p), "4096x4096: full detail");
    p.width = p.height = 800; /* 3.7e-4: just under level 1's error */
    CHECK(lc_cost_estimate(&st, &p) == lc_cost_estimate(&full, &p), "800x800: full detail");
    p.width = p.height = 600; /* 4.9e-4: level 1 */
    lc_scene_measures half = coarse;
    half.primitives = half.vertices = 1e6;
    CHECK(fabs(lc_cost_estimate(&st, &p) - lc_cost_estimate(&half, &p)) < 1e-6 * lc_cost_estimate(&half, &p),
          "600x600: level 1");
    p.width = p.height = 64;
    p.detail.lod_pixels = 0;
    CHECK(lc_cost_estimate(&st, &p) == lc_cost_estimate(&full, &p), "params.lod 0: full detail");
    p.detail.lod_pixels = LC_DEFAULT_LOD_PIXELS;
    p.has_camera = true;
    p.camera.position[0] = 0.5; /* inside the bounding sphere */
    CHECK(lc_cost_estimate(&st, &p) == lc_cost_estimate(&full, &p), "a camera inside the data: full detail");
}

/* Fragment lists (software rasterizers, render/gl/fragment_list.c): P1 sums
 * P0's recorded fragments and P2 reads P1's list, so neither traverses the
 * geometry; a stride turns the lists off and, on lines, draws segment by
 * segment: a stride then costs more than none, and is neither advised nor
 * imposed. */
/* The estimate's traversals of the geometry: its slope in the vertex count. */
static double traversals(const lc_scene_measures *st, const lc_render_params *p)
{
    lc_scene_measures more = *st;
    more.vertices += 1e6;
    return (lc_cost_estimate(&more, p) - lc_cost_estimate(st, p)) / 1e6;
}

static void test_lists(void)
{
    lc_scene_measures st;
    memset(&st, 0, sizeof st);
    st.type = LC_PRIM_LINES;
    st.primitives = st.vertices = 2e6;
    st.elements = 6e4;
    st.lines = 16000;
    st.line_length = 400;
    st.radius = 20.0;
    lc_render_params p = params(LC_METHOD_FOURIER, LC_DEPTH_RANGE_MOMENTS);
    p.width = 972, p.height = 761;
    p.foo.clarity = 0.5;
    double setup = 2e6 + 100.0 * 2e6, tries = LC_CLARITY_CHARGED_TRIES;
    lc_fragment_list_configure("none");
    double drawn = lc_cost_estimate(&st, &p);
    lc_render_params s2 = p;
    s2.foo.subset = 2;
    double drawn2 = lc_cost_estimate(&st, &s2);
    lc_fragment_list_configure("llvmpipe (LLVM 15.0.6, 256 bits)");
    CHECK(lc_fragment_list_enabled(), "lists on for llvmpipe");
    double listed = lc_cost_estimate(&st, &p);
    CHECK(fabs(drawn - listed - setup * (2.0 + tries)) <= 1e-9 * drawn,
          "lists: P1, every try's P2 and P5 (over P4's fragments: millions of them) leave the set-up (%g -> %g)", drawn,
          listed);
    CHECK(lc_cost_estimate(&st, &s2) == drawn2, "a stride turns the lists off: P1 and P2 draw");
    CHECK(drawn2 > listed, "lines at params.subset 2 cost more than every primitive over the lists (%g > %g)", drawn2,
          listed);
    /* Traversals, counted through the vertices (which enter only the set-up,
     * once per traversal): P0, P1, P2 per try, P4, P5 where they draw; P0 and
     * P4 over the lists, and P5 too below a few million fragments. Lines with
     * a stride draw one segment in n, six vertices each against two in a
     * strip: P0's moments, P1 and P4 set up 3/n of a traversal (none saved at
     * 2). */
    CHECK_NEAR(traversals(&st, &p), 2.0, 1e-6, "lists: two traversals (P0, P4)");
    lc_render_params small = p;
    small.width = 128, small.height = 96;
    CHECK_NEAR(traversals(&st, &small), 3.0, 1e-6, "lists, a small frame: three traversals (P0, P4, P5)");
    lc_fragment_list_configure("none");
    CHECK_NEAR(traversals(&st, &p), 3.0 + 1.0 + tries, 1e-6, "drawn: P1 and each try's P2 as well");
    lc_render_params sn = p;
    sn.foo.subset = 2;
    CHECK_NEAR(traversals(&st, &sn), 3.0 + 1.0 + tries, 1e-6, "lines at subset 2: no set-up saved");
    sn.foo.subset = 4;
    CHECK_NEAR(traversals(&st, &sn), 3.0 * 0.75 + 1.0 + tries, 1e-6, "lines at subset 4: 3/4 of P0, P1 and P4");
    lc_scene_measures pts = st;
    pts.type = LC_PRIM_POINTS;
    CHECK_NEAR(traversals(&pts, &sn), 3.0 * 0.25 + 1.0 + tries, 1e-6, "points at subset 4: a quarter of them");
    lc_fragment_list_configure("llvmpipe (LLVM 15.0.6, 256 bits)");
    /* Over a budget the lists' frame misses by little, no stride is imposed or advised. */
    double budget = 0.9 * listed, cost = 0;
    const char *field = NULL;
    char why[320];
    CHECK(lc_cost_subset_for(&st, &p, budget) == 0, "no stride fits where every stride costs more (%d)",
          lc_cost_subset_for(&st, &p, budget));
    CHECK(lc_cost_check(&st, &p, budget, &cost, &field, why, sizeof why) != 0 && field &&
              strcmp(field, "params.subset") != 0 && !strstr(why, "params.subset"),
          "the advice is not a stride (%s: %s)", field ? field : "-", why);
    CHECK(lc_cost_check(&st, &p, listed * 1.01, &cost, &field, why, sizeof why) == 0,
          "a budget the lists' frame fits admits it at params.subset 1");
    lc_fragment_list_configure("none");
    CHECK(lc_cost_check(&st, &p, listed * 1.01, &cost, &field, why, sizeof why) != 0,
          "the same budget refuses the frame where P1 and P2 draw");
}

/* The exact method past its node pool (render/gl/exact.c): a list pass the
 * pool cannot hold builds the whole frame once more (its fragments) and a
 * traversal a band, at full resolution without the whole frame where that is
 * foretold well past the pool; at the optimization resolution every try. */
static void test_exact_bands(void)
{
    lc_scene_measures st = points(2e6);
    lc_render_params p = params(LC_METHOD_EXACT, LC_DEPTH_RANGE_GLOBAL);
    p.width = p.height = 1000;
    double r = fmax(0.5 * p.style.point_size, 0.75), frags = 2e6 * PI * r * r;
    double s2 = p.foo.resolution_scale * p.foo.resolution_scale, traversal = 2e6 + 100.0 * 2e6;
    double tries = lc_clarity_active(&p) ? LC_CLARITY_CHARGED_TRIES : 1.0;
    lc_exact_pool_configure(0);
    double whole = lc_cost_estimate(&st, &p);
    /* The full resolution's fragments 1.2 pools: tried whole first, then 2 bands of 0.8 of it; the optimization
     * resolution's fit. */
    uint64_t nodes = (uint64_t)(frags / 1.2);
    lc_exact_pool_configure(nodes);
    CHECK(lc_exact_bands(frags, nodes) == 2 && !lc_exact_foretold(frags, nodes), "1.2 pools: %d bands",
          lc_exact_bands(frags, nodes));
    double want = frags * 2.0 + traversal * 2, got = lc_cost_estimate(&st, &p) - whole;
    CHECK_NEAR(got, want, 1e-6 * want, "exact in 2 bands at full resolution after the whole frame");
    /* 2.5 pools: foretold, 4 bands without the whole frame first. */
    nodes = (uint64_t)(frags / 2.5);
    lc_exact_pool_configure(nodes);
    CHECK(lc_exact_bands(frags, nodes) == 4 && lc_exact_bands(frags * s2, nodes) == 1 &&
              lc_exact_foretold(frags, nodes),
          "bands %d and %d", lc_exact_bands(frags, nodes), lc_exact_bands(frags * s2, nodes));
    want = traversal * 4, got = lc_cost_estimate(&st, &p) - whole;
    CHECK_NEAR(got, want, 1e-6 * want, "exact in 4 bands at full resolution, foretold");
    /* A pool below the optimization resolution's fragments too: its bands for every try. */
    nodes = (uint64_t)(frags * s2 / 1.5);
    lc_exact_pool_configure(nodes);
    int full = lc_exact_bands(frags, nodes), low = lc_exact_bands(frags * s2, nodes);
    want = traversal * full + tries * (frags * s2 * 2.0 + traversal * low);
    got = lc_cost_estimate(&st, &p) - whole;
    CHECK(low == 2 && full > 4, "bands %d and %d", full, low);
    CHECK_NEAR(got, want, 1e-6 * want, "exact in bands at both resolutions");
    lc_render_params f = params(LC_METHOD_FOURIER, LC_DEPTH_RANGE_GLOBAL);
    f.width = f.height = 1000;
    double fourier = lc_cost_estimate(&st, &f);
    lc_exact_pool_configure(0);
    CHECK(lc_cost_estimate(&st, &f) == fourier, "the pool leaves other methods' costs alone");
}

int main(void)
{
    unsetenv("LUCENT_FRAGMENT_LISTS"); /* the driver's choice, set below as the tests need it */
    test_lists();
    test_plan();
    test_estimates();
    test_levels();
    test_exact_bands();
    return lc_test_finish();
}
