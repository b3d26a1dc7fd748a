/* Render cost estimates (see cost.h for the model). */
#include "cost.h"

#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <string.h>

#include "foo_math.h"
#include "renderer.h"
#include "trace.h"
#include "yield.h"

#define PI 3.14159265358979323846
/* Set-up of one primitive in one pass, in fragment units: on llvmpipe 200,000
 * small splats cost about as much as 2e7 fragments per pass. */
#define PRIMITIVE_UNITS 100.0

/* The tiles a still of p composites in: the pool tiles frames above
 * LC_LARGE_FRAME_PIXELS at LC_YIELD_TILE (workers.c; with one worker it does
 * not, and the estimate is then on the safe side), the renderer larger ones
 * at its own size. */
static int frame_tiles(const lc_render_params *p, int *nx, int *ny)
{
    long long pixels = (long long)p->width * p->height;
    return lc_pass_plan_tiles(p, pixels > LC_LARGE_FRAME_PIXELS ? LC_YIELD_TILE : 0, nx, ny);
}

/* Output pixels per world unit at the data centre. */
static double pixels_per_unit(const lc_scene_measures *st, const lc_render_params *p)
{
    double h = p->height;
    if (!p->has_camera)
        return h / (2.0 * st->radius); /* the fit shows the bounding sphere */
    const lc_camera *c = &p->camera;
    if (c->parallel_projection)
        return c->parallel_scale > 0 ? h / (2.0 * c->parallel_scale) : h;
    double d2 = 0;
    for (int k = 0; k < 3; k++)
        d2 += (c->position[k] - st->center[k]) * (c->position[k] - st->center[k]);
    /* A camera inside the data sees its nearest parts larger; the floor keeps
     * the scale finite (each primitive is capped at the image anyway). */
    double dist = fmax(sqrt(d2), 0.05 * st->radius);
    double half = tan(0.5 * fmin(fmax(c->view_angle, 1.0), 179.0) * PI / 180.0);
    return h / (2.0 * dist * half);
}

/* The share of the primitives a frame draws: the coarsest level of detail
 * whose error stays under params.lod output pixels at the nearest depth of
 * the data's bounding sphere, as the renderer picks it (render/gl/mapping.c
 * takes the nearest corner of the bounds, never nearer: this share is never
 * the smaller). 1 without levels, with params.lod 0 or a camera inside. */
static double level_share(const lc_scene_measures *st, const lc_render_params *p, double ppu)
{
    if (st->levels <= 1 || !(p->detail.lod_pixels > 0) || !(ppu > 0))
        return 1.0;
    double pixel = 1.0 / ppu; /* world units per output pixel at the data centre */
    if (!p->has_camera || !p->camera.parallel_projection) {
        double dist = 0;
        if (p->has_camera) {
            for (int k = 0; k < 3; k++)
                dist += (p->camera.position[k] - st->center[k]) * (p->camera.position[k] - st->center[k]);
            dist = sqrt(dist);
        } else { /* the fit: the bounding sphere fills the view angle */
            double angle = p->camera.view_angle > 1 ? fmin(p->camera.view_angle, 179.0) : 30.0;
            dist = st->radius / sin(0.5 * angle * PI / 180.0);
        }
        double nearest = dist - st->radius;
        if (!(nearest > 0) || !(dist > 0))
            return 1.0;
        pixel *= nearest / dist;
    }
    double bound = p->detail.lod_pixels * pixel, share = 1.0;
    for (int i = 1; i < st->levels && i < LC_MEASURE_LEVELS; i++)
        if (st->level_error[i] <= bound)
            share = st->level_share[i];
    return share;
}

/* The work the perception aids add (docs/ALGORITHM.md "Perception aids"):
 * halos widen every line ribbon of the full-resolution compositing passes by
 * twice their width, and style.antialias K runs those passes (P4-P6 of the
 * fourier, direct and binning methods, the blended pass of wboit and
 * weighted-average) K times. */
static double perception_aids_cost(const lc_scene_measures *st, const lc_render_params *p, double frags, double ppu)
{
    const lc_foo_params *f = &p->foo;
    double targets = ceil((2.0 * f->bands + 1.0) / 4.0), subset = f->subset > 1 ? f->subset : 1;
    double geometry, screens; /* of one compositing run */
    switch (p->method) {
    case LC_METHOD_FOURIER:
    case LC_METHOD_DIRECT: geometry = targets / subset + 1.0, screens = targets + 2.0; break;
    case LC_METHOD_KANZLER: geometry = targets + 2.0, screens = targets + 5.0; break; /* + its maps */
    case LC_METHOD_WBOIT:
    case LC_METHOD_WEIGHTED_AVERAGE: geometry = 2.0, screens = 3.0; break;
    case LC_METHOD_BINNING: geometry = 3.0 / subset + 1.0, screens = 5.0; break;
    case LC_METHOD_EXACT: geometry = 2.0, screens = 2.0; break;
    default: geometry = screens = 0; break;
    }
    int k = p->method != LC_METHOD_EXACT && p->style.antialias > 1 ? p->style.antialias : 1;
    double halo = 0;
    if (st->type == LC_PRIM_LINES && p->style.halo_width > 0 && p->method != LC_METHOD_WBOIT)
        halo = fmin(st->line_length * ppu * 2.0 * p->style.halo_width, st->primitives * p->width * (double)p->height);
    double passes = ceil(geometry);
    return LC_COST_HALO_FACTOR * halo * geometry * k +
           LC_COST_ANTIALIAS_FACTOR * (k - 1) *
               ((frags * geometry + p->width * (double)p->height * screens) +
                (st->vertices + PRIMITIVE_UNITS * st->primitives) * passes);
}

/* Ground shadows and smart transparency (docs/ALGORITHM.md §29): the light's
 * pass draws the transparent geometry once more into the 512² map (its
 * coefficient targets and one colour target, at the view's coverage), the
 * map's separable 7x7 blur reads 14 texels of every target per map texel, and
 * the shadowed context one texel of every target per output pixel; smart
 * transparency reads five texels of P4's targets per pixel, then one screen
 * pass per diffusion step and one to apply. */
static double shadows_cost(const lc_scene_measures *st, const lc_render_params *p, double frags)
{
    const lc_style *sty = &p->style;
    double targets = ceil((2.0 * p->foo.bands + 1.0) / 4.0), image = p->width * (double)p->height, cost = 0;
    if (sty->shadow > 0)
        cost += (frags / image + 14.0) * 512.0 * 512.0 * (targets + 1.0) + image * (targets + 1.0) + st->vertices +
                PRIMITIVE_UNITS * st->primitives;
    if (sty->ground == LC_GROUND_ON || sty->shadow > 0)
        cost += image * 2.0; /* the ground's two draws, at each resolution */
    if (sty->smart > 0)
        cost += image * (5.0 * targets + 2.0 + sty->smart_iterations);
    return LC_COST_SHADOW_FACTOR * cost;
}

/* color.equalize (docs/ALGORITHM.md §19) on fourier/direct: one full-resolution
 * geometry pass for the colour histogram, and a one-shot frame composites
 * again (P4-P6) with the equalized colormap; a tiled still draws those three
 * geometry passes per tile. The exact method measures in its blend and runs
 * list pass 1 and the blend once more. */
static double equalize_cost(const lc_scene_measures *st, const lc_render_params *p, double frags)
{
    if (!p->color.equalize)
        return 0;
    double vertex = st->vertices + PRIMITIVE_UNITS * st->primitives, image = p->width * (double)p->height;
    if (p->method == LC_METHOD_EXACT)
        return LC_COST_EQUALIZE_FACTOR * (frags * 4.0 + image * 2.0 + vertex);
    if (p->method != LC_METHOD_FOURIER && p->method != LC_METHOD_DIRECT)
        return 0;
    const lc_foo_params *f = &p->foo;
    double targets = ceil((2.0 * f->bands + 1.0) / 4.0), subset = f->subset > 1 ? f->subset : 1;
    double geometry = 1.0 + targets / subset + 1.0, screens = targets + 2.0;
    int nx, ny, tiles = frame_tiles(p, &nx, &ny);
    return LC_COST_EQUALIZE_FACTOR * (frags * geometry + image * screens + vertex * 3.0 * (tiles > 1 ? tiles : 1));
}

/* The largest fragment list (render/gl/fragment_list.c FRAGMENT_LIST_MAX):
 * a frame whose optimization draws more fragments draws P2 instead. */
#define LIST_MAX_FRAGMENTS 16777216.0

/* Whether P1 and P2 of a full frame of p run as compute passes over recorded
 * fragments rather than as traversals of the geometry (render/gl
 * fragment_list.c, on software rasterizers): P1 walks P0's chains where P0
 * "moments" records them (no stride, no layers, not a tile's optimization at
 * full resolution), and P2 reads P1's list wherever P1 draws every primitive.
 * A stride (params.subset, params.autoSubset) turns both off: it weights
 * fragments the list does not keep, so P1 and P2 draw again. low_frags: the
 * optimization's fragments (more than the list holds: P2 draws). */
static void lists_plan(const lc_render_params *p, const lc_pass_plan *plan, double low_frags, bool tile_low,
                       bool layered, bool *p1, bool *p2)
{
    *p1 = *p2 = false;
    if (!lc_fragment_list_enabled() || p->method == LC_METHOD_EXACT || plan->run[LC_PASS_IMPORTANCE] == LC_RUN_NONE)
        return;
    if (p->foo.subset > 1 || p->foo.auto_subset > 1 || p->detail.point_stride > 1 || p->detail.line_stride > 1 ||
        low_frags > LIST_MAX_FRAGMENTS)
        return;
    *p2 = true;
    *p1 = plan->moments && !tile_low && !layered;
}

/* Whether P5 of a Fourier frame runs over the fragments its P4 recorded (no
 * traversal: render/gl/fragment_list.c) where P0 recorded its own: no stride,
 * layer, tile or batches (points too: their P4 then draws to record rather
 * than computes, render/gl/compute_raster.c). */
static bool composite_listed(const lc_render_params *p, double frags, bool p1_listed, int tiles, bool layered)
{
    return p1_listed && p->method == LC_METHOD_FOURIER && tiles <= 1 && !layered && p->foo.progressive <= 1 &&
           lc_composite_list_expected(frags);
}

/* layered: one layer's share of a frame of layers (lc_cost_check_layers). */
static double estimate(const lc_scene_measures *st, const lc_render_params *p, bool layered)
{
    double w = p->width, h = p->height, image = w * h;
    double ppu = pixels_per_unit(st, p);
    /* What the frame draws: its level of detail's primitives (every term below). */
    lc_scene_measures drawn;
    double share = level_share(st, p, ppu);
    if (share < 1) {
        drawn = *st;
        drawn.primitives *= share, drawn.vertices *= share;
        st = &drawn;
    }
    /* Fragments of one full-resolution geometry pass. */
    double frags;
    switch (st->type) {
    case LC_PRIM_POINTS: {
        double r = fmax(0.5 * p->style.point_size, 0.75);
        frags = st->primitives * fmin(PI * r * r, image);
        break;
    }
    case LC_PRIM_LINES: {
        double world = p->style.line_width > 0 ? p->style.line_width : 0.008 * st->radius; /* as render/gl/frame.c */
        double width = fmax(p->style.min_line_pixels, world * ppu);
        double ribbon = st->line_length * ppu * width + st->primitives * width; /* + the joins */
        frags = fmin(ribbon, st->primitives * image);
        /* lines.clusters draws one line per cluster (hidden ones still pass the vertex stage). */
        if (p->clusters.count > 0 && st->lines > p->clusters.count)
            frags *= p->clusters.count / st->lines;
        break;
    }
    default: frags = fmin(st->area * ppu * ppu, st->primitives * image); break;
    }
    const lc_foo_params *f = &p->foo;
    double guard = 1.0 + 2.0 * (f->guard_band > 0 ? f->guard_band : 0.0); /* params.guardBand widens P0-P2 */
    double s2 = f->resolution_scale * f->resolution_scale * guard * guard;
    double targets = ceil((2.0 * f->bands + 1.0) / 4.0);
    double subset = f->subset > 1 ? f->subset : 1;
    /* Which passes run, and where, is the renderer's plan (a full frame: no
     * opacities to reuse); what each costs is this model's: g = geometry
     * passes per fragment at the pass's resolution, sc = screen passes. */
    lc_pass_plan plan;
    lc_pass_plan_make(p, 0, &plan);
    double g[LC_PASS_COUNT] = {0}, sc[LC_PASS_COUNT] = {0};
    switch (p->method) {
    case LC_METHOD_FOURIER: /* P1 and P4 draw the coefficient targets (every subset-th element), P2 and P5 one */
        g[LC_PASS_IMPORTANCE] = g[LC_PASS_OPTICAL_DEPTH] = targets / subset;
        g[LC_PASS_OPACITY] = g[LC_PASS_ACCUMULATE] = 1.0;
        sc[LC_PASS_OPTICAL_DEPTH] = targets;
        sc[LC_PASS_ACCUMULATE] = sc[LC_PASS_RESOLVE] = 1.0;
        break;
    case LC_METHOD_EXACT: /* fragment lists at both resolutions; insertion, sort and blend per fragment */
        g[LC_PASS_IMPORTANCE] = g[LC_PASS_OPACITY] = g[LC_PASS_OPTICAL_DEPTH] = g[LC_PASS_ACCUMULATE] = 2.0;
        sc[LC_PASS_IMPORTANCE] = sc[LC_PASS_OPACITY] = sc[LC_PASS_OPTICAL_DEPTH] = sc[LC_PASS_ACCUMULATE] = 1.0;
        break;
    case LC_METHOD_OPAQUE: g[LC_PASS_ACCUMULATE] = sc[LC_PASS_ACCUMULATE] = 1.0; break;
    case LC_METHOD_BINNING: /* P1, P2 at s^2 as fourier; P4 into 3 targets (11 bins and the total), P5 one */
        g[LC_PASS_IMPORTANCE] = targets / subset;
        g[LC_PASS_OPACITY] = 1.0;
        g[LC_PASS_OPTICAL_DEPTH] = 3.0 / subset;
        g[LC_PASS_ACCUMULATE] = 1.0;
        sc[LC_PASS_OPTICAL_DEPTH] = 3.0;
        sc[LC_PASS_ACCUMULATE] = sc[LC_PASS_RESOLVE] = 1.0;
        break;
    case LC_METHOD_DIRECT:
    case LC_METHOD_KANZLER:
        g[LC_PASS_OPTICAL_DEPTH] = targets;
        g[LC_PASS_ACCUMULATE] = 1.0;
        sc[LC_PASS_OPTICAL_DEPTH] = targets;
        sc[LC_PASS_ACCUMULATE] = sc[LC_PASS_RESOLVE] = 1.0;
        break;
    default: /* wboit, weighted-average: P1, P2 at s^2, one blended pass into two targets */
        g[LC_PASS_IMPORTANCE] = targets;
        g[LC_PASS_OPACITY] = 1.0;
        g[LC_PASS_ACCUMULATE] = 2.0;
        sc[LC_PASS_ACCUMULATE] = targets + 2.0;
        sc[LC_PASS_RESOLVE] = 1.0;
        break;
    }
    /* params.clarity: a one-shot frame may optimize again at other strengths;
     * P1's sums do not depend on the strength and run once a frame
     * (fourier.c), each try repeats P2 and P3. */
    double tries = lc_clarity_active(p) ? LC_CLARITY_CHARGED_TRIES : 1.0;
    if (p->method == LC_METHOD_EXACT && p->foo.exclude_self) /* a walk over the pixel's list per fragment */
        sc[LC_PASS_OPACITY] *= 4.0;
    if (p->method == LC_METHOD_EXACT) /* its lists are built once; each try repeats the opacity pass over them */
        sc[LC_PASS_OPACITY] *= tries;
    else
        g[LC_PASS_OPACITY] *= tries;
    /* P0: the per-pixel range draws everything once at each resolution, the
     * moments one target of every subset-th element at s^2. */
    g[LC_PASS_DEPTH_RANGE] = plan.moments ? 1.0 / subset : 1.0;
    /* kanzler's maps: one full-resolution geometry pass (atomic max, two
     * sums) and three screens (clears and the 25-texel blur), within P0. */
    if (plan.kanzler_maps) {
        g[LC_PASS_DEPTH_RANGE] += plan.pixel_range ? 1.0 : 0.0;
        sc[LC_PASS_DEPTH_RANGE] = 3.0;
    }
    /* Traversals of the geometry, which pay the vertex and primitive set-up
     * however many targets a pass writes (P1 and P4 write theirs in one draw):
     * one per pass and resolution it runs at, P2 once per try, kanzler's maps
     * one more. P1 and P2 computed over recorded fragments (lists_plan), and
     * P5 over P4's (composite_listed), cost their fragments' work but no
     * traversal. A pass drawn with the stride
     * (P0's moments, P1, P4) sets up one primitive in n, but lines then draw
     * segment by segment, six vertices each against two in a strip
     * (render/gl/fourier.c): their set-up shrinks only as 3/n. */
    double tv[LC_PASS_COUNT] = {0};
    for (int k = 0; k < LC_PASS_COUNT; k++)
        tv[k] = g[k] > 0 ? 1.0 : 0.0;
    if (p->method != LC_METHOD_EXACT)
        tv[LC_PASS_OPACITY] *= tries;
    if (plan.kanzler_maps && plan.pixel_range)
        tv[LC_PASS_DEPTH_RANGE] += 0.5; /* the maps: one more at full resolution (BOTH counts two below) */
    double strided = subset <= 1 ? 1.0 : st->type == LC_PRIM_LINES ? fmin(1.0, 3.0 / subset) : 1.0 / subset;
    if (p->method == LC_METHOD_FOURIER || p->method == LC_METHOD_BINNING) {
        tv[LC_PASS_IMPORTANCE] *= strided;
        tv[LC_PASS_OPTICAL_DEPTH] *= strided;
    }
    if (plan.moments)
        tv[LC_PASS_DEPTH_RANGE] *= strided;
    bool listed[LC_PASS_COUNT] = {false};
    int nx, ny, tiles = frame_tiles(p, &nx, &ny);
    lists_plan(p, &plan, frags * s2, tiles > 1 && f->resolution_scale >= 1.0, layered, &listed[LC_PASS_IMPORTANCE],
               &listed[LC_PASS_OPACITY]);
    listed[LC_PASS_ACCUMULATE] = composite_listed(p, frags, listed[LC_PASS_IMPORTANCE], tiles, layered);
    double geometry = 0, passes = 0, full = 0, screens = 0;
    for (int k = 0; k < LC_PASS_COUNT; k++) {
        double at = plan.run[k] == LC_RUN_LOW    ? s2
                    : plan.run[k] == LC_RUN_FULL ? 1.0
                    : plan.run[k] == LC_RUN_BOTH ? s2 + 1.0
                                                 : 0.0;
        double runs = plan.run[k] == LC_RUN_LOW || plan.run[k] == LC_RUN_FULL ? 1.0
                      : plan.run[k] == LC_RUN_BOTH                            ? 2.0
                                                                              : 0.0;
        geometry += g[k] * at;
        passes += listed[k] ? 0.0 : tv[k] * runs;
        full += plan.run[k] == LC_RUN_FULL || plan.run[k] == LC_RUN_BOTH ? tv[k] : 0.0;
        screens += plan.run[k] == LC_RUN_NONE ? 0.0 : sc[k];
    }
    /* A tiled still draws every full-resolution pass's geometry once per tile
     * (its fragments are the same: each lands in one tile). */
    if (tiles > 1)
        passes += full * (tiles - 1);
    double clusters =
        p->clusters.count > 0 && st->type == LC_PRIM_LINES ? LC_COST_CLUSTER_BUILD_UNITS_PER_LINE * st->lines : 0;
    /* params.progressive n (render/gl/progressive.c): the batches draw the
     * frame's geometry once between them, then the last batch's P2, P4 and P5
     * draw all of it again, and every batch runs P3 and the screen passes. */
    double progressive = 0;
    if (f->progressive > 1 && p->method == LC_METHOD_FOURIER) {
        double n = f->progressive, again = g[LC_PASS_OPACITY] * s2 + g[LC_PASS_OPTICAL_DEPTH] + g[LC_PASS_ACCUMULATE];
        progressive = frags * again * (n - 1) / n + (n - 1) * (image * screens + st->elements * (f->smoothing + 1.0)) +
                      (st->vertices + PRIMITIVE_UNITS * st->primitives) * ceil(again);
    }
    /* The exact method past its node pool (render/gl/exact.c): a list pass
     * whose fragments the pool cannot hold builds the whole frame once, then
     * again band by band, a traversal each (at full resolution the whole
     * build is skipped where the optimization resolution's fragments foretell
     * the bands); at the optimization resolution every try of the clarity
     * loop builds its bands again. */
    double banded = 0;
    if (p->method == LC_METHOD_EXACT) {
        uint64_t nodes = lc_exact_pool_nodes();
        int full_bands = lc_exact_bands(frags, nodes), low_bands = lc_exact_bands(frags * s2, nodes);
        double traversal = st->vertices + PRIMITIVE_UNITS * st->primitives;
        if (full_bands > 1)
            banded +=
                (lc_exact_foretold(frags, nodes) ? 0.0 : frags * g[LC_PASS_OPTICAL_DEPTH]) + traversal * full_bands;
        if (low_bands > 1)
            banded += tries * (frags * s2 * g[LC_PASS_IMPORTANCE] + traversal * low_bands);
    }
    return frags * geometry + image * screens + (st->vertices + PRIMITIVE_UNITS * st->primitives) * passes + clusters +
           banded + st->elements * (f->smoothing + 1.0) * tries + perception_aids_cost(st, p, frags, ppu) +
           equalize_cost(st, p, frags) + shadows_cost(st, p, frags) + progressive;
}

double lc_cost_estimate(const lc_scene_measures *st, const lc_render_params *p) { return estimate(st, p, false); }

/* The smallest params.subset (a power of two up to 64) whose frame fits the
 * budget, or 0: the optimization and compositing passes then draw every n-th
 * primitive of the methods that weight a stride, at full picture size. */
int lc_cost_subset_for(const lc_scene_measures *st, const lc_render_params *p, double budget)
{
    if (p->method != LC_METHOD_FOURIER && p->method != LC_METHOD_DIRECT && p->method != LC_METHOD_WBOIT &&
        p->method != LC_METHOD_WEIGHTED_AVERAGE && p->method != LC_METHOD_BINNING)
        return 0;
    lc_render_params q = *p;
    for (int n = 2 * (p->foo.subset > 1 ? p->foo.subset : 1); n <= 64; n *= 2) {
        q.foo.subset = n;
        if (lc_cost_estimate(st, &q) <= budget)
            return n;
    }
    return 0;
}

/* The largest frame of p's aspect that fits the budget (0 x 0: none down to 16 pixels a side). */
static void size_for(const lc_scene_measures *st, const lc_render_params *p, double budget, int *w, int *h)
{
    lc_render_params q = *p;
    double lo = 0, hi = 1;
    *w = *h = 0;
    for (int i = 0; i < 20; i++) {
        double k = 0.5 * (lo + hi);
        q.width = (int)(p->width * k), q.height = (int)(p->height * k);
        if (q.width < 16 || q.height < 16 || lc_cost_estimate(st, &q) > budget)
            hi = k;
        else
            lo = k, *w = q.width, *h = q.height;
    }
}

const char *lc_cost_field(const lc_scene_measures *st, const lc_render_params *p, double budget)
{
    lc_render_params q = *p;
    lc_style defaults;
    lc_style_default(&defaults);
    q.style.point_size = fmin(q.style.point_size, defaults.point_size);
    q.style.line_width = defaults.line_width; /* 0: derived from the bounds */
    q.style.min_line_pixels = fmin(q.style.min_line_pixels, defaults.min_line_pixels);
    if (lc_cost_estimate(st, &q) <= budget) {
        if (st->type == LC_PRIM_POINTS)
            return "style.pointSize";
        if (st->type == LC_PRIM_LINES)
            return p->style.min_line_pixels > defaults.min_line_pixels ? "style.minLinePixels" : "style.lineWidth";
    }
    lc_foo_params fd;
    lc_foo_params_default(&fd);
    q = *p;
    if (q.method != LC_METHOD_FOURIER && q.method != LC_METHOD_OPAQUE) {
        q.method = LC_METHOD_FOURIER;
        if (lc_cost_estimate(st, &q) <= budget)
            return "method";
    }
    if (lc_foo_depth_range(&p->foo) != LC_DEPTH_RANGE_GLOBAL) {
        q.foo.depth_range = LC_DEPTH_RANGE_GLOBAL;
        if (lc_cost_estimate(st, &q) <= budget)
            return "params.depthRange";
    }
    if (p->foo.bands > fd.bands) {
        q.foo.bands = fd.bands;
        if (lc_cost_estimate(st, &q) <= budget)
            return "params.bands";
    }
    if (p->foo.resolution_scale > fd.resolution_scale) {
        q.foo.resolution_scale = fd.resolution_scale;
        if (lc_cost_estimate(st, &q) <= budget)
            return "params.resolutionScale";
    }
    if (st->type == LC_PRIM_POINTS && p->style.point_size > defaults.point_size)
        return "style.pointSize";
    if (lc_cost_subset_for(st, p, budget) > 0)
        return "params.subset";
    return "width";
}

int lc_cost_check(const lc_scene_measures *st, const lc_render_params *p, double budget, double *cost,
                  const char **field, char *msg, size_t n)
{
    *cost = lc_cost_estimate(st, p);
    if (budget <= 0 || *cost <= budget)
        return 0;
    *field = lc_cost_field(st, p, budget);
    /* Advice that works: the value that fits, not only the field to change. */
    char advice[160];
    int w = 0, h = 0, k = strcmp(*field, "params.subset") == 0 ? lc_cost_subset_for(st, p, budget) : 0;
    if (k > 0)
        snprintf(advice, sizeof advice,
                 "set params.subset to %d (the optimization draws one primitive in %d, "
                 "weighted %d; the picture keeps its size)",
                 k, k, k);
    else if (strcmp(*field, "width") == 0 && (size_for(st, p, budget, &w, &h), w > 0))
        snprintf(advice, sizeof advice, "a frame of at most %dx%d fits", w, h);
    else if (strcmp(*field, "width") == 0)
        snprintf(advice, sizeof advice,
                 "no frame size fits: filter the data (filter, time.window) or ask for a "
                 "server with a larger --max-cost");
    else
        snprintf(advice, sizeof advice, "lower %s", *field);
    snprintf(msg, n,
             "estimated cost %.3g exceeds this server's budget of %.3g per frame (--max-cost) for %dx%d, %s, "
             "%.0f primitives: %s",
             *cost, budget, p->width, p->height, lc_method_name(p->method), st->primitives, advice);
    return -1;
}

int lc_cost_check_layers(const lc_scene_measures *const *st, const lc_layer_params *const *layers, int n,
                         const lc_render_params *p, double budget, double *cost, const char **field, char *msg,
                         size_t size)
{
    *cost = 0;
    for (int i = 0; i < n; i++) {
        if (!layers[i]->visible)
            continue;
        lc_render_params q = *p;
        q.style.line_width = layers[i]->style.line_width;
        q.style.min_line_pixels = layers[i]->style.min_line_pixels;
        q.style.point_size = layers[i]->style.point_size;
        *cost += estimate(st[i], &q, true);
    }
    if (budget <= 0 || *cost <= budget)
        return 0;
    *field = "layers";
    snprintf(msg, size,
             "estimated cost %.3g of the %d layers exceeds this server's budget of %.3g per frame (--max-cost); "
             "draw fewer or smaller layers, or lower width (%dx%d, %s)",
             *cost, n, budget, p->width, p->height, lc_method_name(p->method));
    return -1;
}

double lc_cost_surface_steps(double diagonal, double max_speed, double step, double length)
{
    double v = max_speed > 0 ? max_speed : 1.0;
    double h = step > 0 ? step : diagonal / (200.0 * v);
    double len = length > 0 ? length : 2.0 * diagonal;
    double steps = h > 0 ? len / (h * v) : 1e5;
    return steps < 1 ? 1 : steps > 1e5 ? 1e5 : steps;
}

double lc_cost_surface_step_units(const lc_render_params *p)
{
    double segment = fmax(1.0, p->height / 400.0);
    return LC_TRACE_STEP_UNITS + 20.0 * segment;
}

double lc_cost_surface(const lc_render_params *p, int particles, double steps, int k)
{
    return (double)particles * steps * lc_cost_surface_step_units(p) +
           LC_COST_SURFACE_SCREEN_UNITS * (double)p->width * p->height * (k + 3.0);
}

double lc_cost_grant(double cost) { return fmax(LC_COST_GRANT_FACTOR * cost, LC_COST_GRANT_FLOOR); }

void lc_cost_surface_budget(lc_work_budget *b, double cost, double max_cost)
{
    lc_work_init(b, max_cost > 0 ? lc_cost_grant(cost) : 0, "surface.particles");
}

void lc_cost_frame_budget(lc_work_budget *b, double cost, double rate, double max_cost, const char *field)
{
    bool on = max_cost > 0 && rate > 0;
    lc_work_init(b, on ? fmax(LC_COST_TIME_FACTOR * cost, LC_COST_TIME_FLOOR_S * rate) : 0, field);
    lc_work_time(b, on ? rate : 0);
}

int lc_cost_check_surface(const lc_render_params *p, int particles, double steps, int k, double budget, double *cost,
                          const char **field, char *msg, size_t n)
{
    *cost = lc_cost_surface(p, particles, steps, k);
    if (budget <= 0 || *cost <= budget)
        return 0;
    *field = "surface.particles";
    snprintf(msg, n,
             "estimated cost %.3g exceeds this server's budget of %.3g per frame (--max-cost); lower "
             "surface.particles (%d curves of about %.0f steps, %dx%d)",
             *cost, budget, particles, steps, p->width, p->height);
    return -1;
}

double lc_cost_trace(double vertices) { return 100.0 * (vertices > 0 ? vertices : 0); }
