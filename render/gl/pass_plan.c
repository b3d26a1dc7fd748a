/* The pass plan: which passes a frame of a request runs, and at which resolution. */
#include <string.h>

#include "foo_math.h"
#include "renderer.h"

void lc_pass_plan_make(const lc_render_params *p, int reuse, lc_pass_plan *out)
{
    memset(out, 0, sizeof *out);
    lc_method m = p->method;
    out->method = m;
    /* The baselines at equal memory (wboit, weighted-average, binning) composite the FOO opacities. */
    int blends = m == LC_METHOD_WBOIT || m == LC_METHOD_WEIGHTED_AVERAGE || m == LC_METHOD_BINNING;
    int opacities = m == LC_METHOD_FOURIER || blends || m == LC_METHOD_EXACT; /* P1-P3 */
    out->reuse = reuse && p->detail.reuse_opacities && (m == LC_METHOD_FOURIER || blends) && p->foo.progressive <= 1;
    /* The per-pixel depth range serves every method that normalizes depth; the
     * moments serve the Fourier method's optimization and compositing (and the
     * binning baseline's, whose bins then lie in the same warped depth). A frame
     * that reuses the opacities (P1-P3 skipped, the camera moving) composites by
     * the bounds: the pass would cost it 18-29% (tornado at 972x761, llvmpipe). */
    lc_depth_range range = lc_foo_depth_range(&p->foo);
    out->pixel_range = range == LC_DEPTH_RANGE_PIXEL &&
                       (m == LC_METHOD_FOURIER || m == LC_METHOD_DIRECT || blends || m == LC_METHOD_KANZLER);
    out->moments = range == LC_DEPTH_RANGE_MOMENTS && (m == LC_METHOD_FOURIER || m == LC_METHOD_BINNING) && !out->reuse;
    /* kanzler's per-pixel maps (kanzler.c) run and are timed as part of P0, at full resolution. */
    out->kanzler_maps = m == LC_METHOD_KANZLER;
    out->run[LC_PASS_DEPTH_RANGE] = out->pixel_range    ? LC_RUN_BOTH
                                    : out->moments      ? LC_RUN_LOW
                                    : out->kanzler_maps ? LC_RUN_FULL
                                                        : LC_RUN_NONE;
    if (opacities && !out->reuse) {
        out->run[LC_PASS_IMPORTANCE] = LC_RUN_LOW;
        out->run[LC_PASS_OPACITY] = LC_RUN_LOW;
        out->run[LC_PASS_SMOOTH] = LC_RUN_ONCE;
    }
    if (m == LC_METHOD_FOURIER || m == LC_METHOD_DIRECT || m == LC_METHOD_EXACT || m == LC_METHOD_BINNING ||
        m == LC_METHOD_KANZLER)
        out->run[LC_PASS_OPTICAL_DEPTH] = LC_RUN_FULL;
    out->run[LC_PASS_ACCUMULATE] = LC_RUN_FULL;
    out->run[LC_PASS_RESOLVE] = m != LC_METHOD_OPAQUE ? LC_RUN_FULL : LC_RUN_NONE;
    out->run[LC_PASS_READBACK] = LC_RUN_FULL;
}

int lc_pass_plan_tiles(const lc_render_params *p, int tile_size, int *nx, int *ny)
{
    *nx = *ny = 1;
    if (p->method == LC_METHOD_EXACT) /* its per-pixel fragment lists are not tiled */
        return 0;
    int ts = tile_size > 0 ? tile_size : LC_TILE_SIZE;
    if (tile_size > 0 ? p->width <= ts && p->height <= ts : (long long)p->width * p->height <= LC_TILE_PIXELS)
        return 0;
    *nx = (p->width + ts - 1) / ts, *ny = (p->height + ts - 1) / ts;
    return *nx * *ny;
}
