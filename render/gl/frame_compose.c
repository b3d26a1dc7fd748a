/* A frame's image from its opacities: the method's compositing passes
 * (P4-P6 or a baseline's) into the output target, and images composed of
 * several composites of the one optimization: antialiased stills average
 * jittered samples, tiled stills assemble tiles (each possibly
 * antialiased), so that P1-P3 run once and only the compositing repeats
 * (frame.c dispatches here by the pass plan). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "renderer_internal.h"

/* The RGBA8 image every method ends in; a depth buffer only for the opaque
 * baseline (the order-independent methods never depth-test). */
void lc_frame_ensure_output(lc_renderer *r, int w, int h, int with_depth)
{
    lc_targets_ensure(&r->output, w, h, 1, GL_RGBA8, &r->bytes_targets);
    if (!with_depth || (r->output_depth && r->depth_width == w && r->depth_height == h))
        return;
    if (r->output_depth) {
        glDeleteRenderbuffers(1, &r->output_depth);
        r->bytes_targets -= (uint64_t)r->depth_width * r->depth_height * 4;
    }
    glCreateRenderbuffers(1, &r->output_depth);
    glNamedRenderbufferStorage(r->output_depth, GL_DEPTH_COMPONENT24, w, h);
    glNamedFramebufferRenderbuffer(r->output.fbo, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, r->output_depth);
    r->depth_width = w, r->depth_height = h;
    r->bytes_targets += (uint64_t)w * h * 4;
}

/* P4-P6 (or the baselines' single pass) of a method with the frame's opacities. */
int lc_frame_composite(lc_renderer *r, lc_frame_setup *fs, lc_error *err)
{
    switch (fs->params->method) {
    case LC_METHOD_FOURIER: return lc_fourier_composite(r, fs, 0, err);
    case LC_METHOD_DIRECT: return lc_fourier_composite(r, fs, LC_ALPHA_DIRECT, err);
    case LC_METHOD_KANZLER: return lc_fourier_composite(r, fs, LC_ALPHA_KANZLER, err);
    case LC_METHOD_OPAQUE: return lc_render_opaque(r, fs, err);
    case LC_METHOD_WBOIT: return lc_render_wboit(r, fs, err);
    case LC_METHOD_WEIGHTED_AVERAGE: return lc_render_weighted_average(r, fs, err);
    case LC_METHOD_BINNING: return lc_binning_composite(r, fs, err);
    default: return lc_err(err, LC_ERR_INVALID, "unknown method");
    }
}

/* ---- Anti-aliasing of still frames (style.antialias, docs/ALGORITHM.md
 * "Perception aids"): the frame's opacities (P1-P3) serve K compositing runs
 * (P4-P6) under sub-pixel camera jitter, whose images are averaged. */

/* Radical inverse of i in base b (the Halton sequence). */
static double halton(int i, int b)
{
    double f = 1, x = 0;
    for (; i > 0; i /= b) {
        f /= b;
        x += f * (i % b);
    }
    return x;
}

/* Shifts the image of v by (dx, dy) pixels of a w x h target: NDC moves by
 * 2 d / size, i.e. clip x += (2 dx / w) clip w (column-major matrices). */
static void jitter_view(lc_view *v, double dx, double dy, int w, int h)
{
    float tx = (float)(2.0 * dx / w), ty = (float)(2.0 * dy / h);
    for (int col = 0; col < 4; col++) {
        v->view_proj[4 * col] += tx * v->view_proj[4 * col + 3];
        v->view_proj[4 * col + 1] += ty * v->view_proj[4 * col + 3];
    }
}

/* The antialias sample count a frame uses: style.antialias for the methods
 * that composite from element opacities (or g^k); 1 for the others. */
int lc_frame_antialias_samples(const lc_render_params *p)
{
    int k = p->style.antialias;
    int composites = p->method != LC_METHOD_EXACT && p->method != LC_METHOD_OPAQUE;
    return composites && k > 1 ? (k > LC_MAX_ANTIALIAS ? LC_MAX_ANTIALIAS : k) : 1;
}

/* Samples 1..K-1 after the frame's own (unjittered) sample 0 in the output:
 * reads each back and writes the average into rgba. Sample i >= 1 is offset
 * by Halton (2, 3) point i + 1 minus 1/2, within the pixel. */
int lc_frame_antialias(lc_renderer *r, lc_frame_setup *fs, int samples, uint8_t *rgba, lc_error *err)
{
    size_t n = (size_t)fs->width * fs->height * 4;
    float *sum = malloc(n * sizeof *sum);
    if (!sum)
        return lc_err(err, LC_ERR_NOMEM, "out of memory (antialias sums)");
    int rc = lc_markers_draw(r, fs, err); /* over every sample: the markers are smoothed as the lines are */
    lc_renderer_readback(r, fs, rgba);
    for (size_t i = 0; i < n; i++)
        sum[i] = rgba[i];
    const lc_view base = fs->view;
    for (int i = 1; i < samples && !rc; i++) {
        fs->view = base;
        /* The shift is in pixels of the whole frame, which a tile's projection covers. */
        jitter_view(&fs->view, halton(i + 1, 2) - 0.5, halton(i + 1, 3) - 0.5, fs->tiled ? fs->frame_width : fs->width,
                    fs->tiled ? fs->frame_height : fs->height);
        rc = lc_context_draw(r, fs, LC_CONTEXT_FULL, err); /* the context of this sample's view */
        if (!rc)
            rc = lc_frame_composite(r, fs, err);
        if (!rc)
            rc = lc_markers_draw(r, fs, err);
        if (!rc) {
            lc_renderer_readback(r, fs, rgba);
            for (size_t j = 0; j < n; j++)
                sum[j] += rgba[j];
        }
    }
    fs->view = base;
    for (size_t i = 0; i < n && !rc; i++)
        rgba[i] = (uint8_t)lrintf(sum[i] / (float)samples);
    free(sum);
    return rc;
}

/* ---- Tiled stills (docs/ALGORITHM.md "Tiled stills"): a frame of more than
 * LC_TILE_PIXELS pixels (or larger than lc_renderer_desc.tile_size when that is
 * set; lc_pass_plan_tiles) is optimized once, P0-P3 over the whole view at the optimization
 * resolution, then composited tile by tile: each tile's full-resolution
 * passes project the whole frame through a viewport shifted by the tile's
 * origin, so a tile's pixels see the fragments, per-pixel textures and
 * opacities of the same pixels of one large frame, while the full-resolution
 * targets (the memory that grows with the image) stay tile-sized. */
/* Composites the frame in nx x ny about-equal tiles (lc_pass_plan_tiles) into
 * rgba (the frame's size, rows top-down). */
/* Sets fs to tile (i, j) of nx x ny (rows top-down) and its output; *x0, *y0: its origin in the image. */
static void select_tile(lc_renderer *r, lc_frame_setup *fs, int W, int H, int nx, int ny, int i, int j, int *x0,
                        int *y0)
{
    *y0 = (int)((long long)H * j / ny);
    *x0 = (int)((long long)W * i / nx);
    int th = (int)((long long)H * (j + 1) / ny) - *y0, tw = (int)((long long)W * (i + 1) / nx) - *x0;
    fs->width = tw, fs->height = th;
    fs->tile_origin[0] = *x0, fs->tile_origin[1] = H - *y0 - th;
    lc_frame_ensure_output(r, tw, th, fs->params->method == LC_METHOD_OPAQUE);
    glScissor(0, 0, tw, th);
}

/* color.equalize on a tiled still: one histogram over all tiles. Without a
 * session transfer (one-shot stills) a first round composites every tile
 * (P4, P5) only to measure it, and the image's round then draws with this
 * view's F; with one, the image's round measures as it draws (*measure).
 * Either way the histogram is that of the whole frame, as untiled. */
static int equalize_tiles_first(lc_renderer *r, lc_frame_setup *fs, lc_frame_state *state, double dt, int nx, int ny,
                                int pixel_range, int *measure, lc_error *err)
{
    int direct = fs->params->method == LC_METHOD_DIRECT;
    float fresh = !(state && state->eq[0].valid);
    int rc = lc_reduce_sums(r, &fresh, 1, fs->info, err); /* all processes take the same branch */
    lc_color_equalize_reset(r);
    *measure = !rc && !(fresh > 0);
    int W = fs->frame_width, H = fs->frame_height, x0, y0, again = 0;
    for (int j = 0; j < ny && !rc && !*measure; j++)
        for (int i = 0; i < nx && !rc; i++) {
            select_tile(r, fs, W, H, nx, ny, i, j, &x0, &y0);
            int ignored = 1;
            rc = lc_context_draw(r, fs, LC_CONTEXT_FULL, err);
            if (!rc && pixel_range)
                rc = lc_fourier_depth_range(r, fs, 1, 0, err);
            if (!rc)
                rc = lc_fourier_composite(r, fs, direct, err);
            if (!rc)
                rc = lc_color_equalize_measure(r, fs, direct, &ignored, err);
        }
    if (!rc && !*measure)
        rc = lc_color_equalize_finish(r, fs, state, dt, 1, &again, err);
    return rc;
}

int lc_frame_render_tiles(lc_renderer *r, lc_frame_setup *fs, lc_frame_state *state, double dt, int nx, int ny,
                          int samples, int pixel_range, uint8_t *rgba, lc_error *err)
{
    GLint dims[2] = {0, 0};
    glGetIntegerv(GL_MAX_VIEWPORT_DIMS, dims);
    int W = fs->width, H = fs->height;
    if (W > dims[0] || H > dims[1])
        return lc_err(err, LC_ERR_INVALID, "a %dx%d frame exceeds this GL's viewport limit %dx%d", W, H, dims[0],
                      dims[1]);
    uint8_t *tile = malloc((size_t)((W + nx - 1) / nx) * ((H + ny - 1) / ny) * 4);
    if (!tile)
        return lc_err(err, LC_ERR_NOMEM, "out of memory (tile image)");
    fs->tiled = 1, fs->frame_width = W, fs->frame_height = H;
    fs->info->tiles = nx * ny;
    glEnable(GL_SCISSOR_TEST);
    int rc = 0, measure = 0, direct = fs->params->method == LC_METHOD_DIRECT;
    if (fs->params->color.equalize)
        rc = equalize_tiles_first(r, fs, state, dt, nx, ny, pixel_range, &measure, err);
    for (int j = 0; j < ny && !rc; j++) {
        for (int i = 0; i < nx && !rc; i++) {
            int x0, y0;
            select_tile(r, fs, W, H, nx, ny, i, j, &x0, &y0);
            int tw = fs->width, th = fs->height;
            rc = lc_context_draw(r, fs, LC_CONTEXT_FULL, err); /* the tile's part of the context */
            if (!rc && pixel_range)
                rc = lc_fourier_depth_range(r, fs, 1, 0, err);
            if (!rc)
                rc = lc_frame_composite(r, fs, err);
            if (!rc && measure) {
                int ignored = 0;
                rc = lc_color_equalize_measure(r, fs, direct, &ignored, err);
            }
            if (!rc && samples <= 1)
                rc = lc_markers_draw(r, fs, err); /* the tile's part of them (antialias draws its own) */
            if (!rc && samples > 1)
                rc = lc_frame_antialias(r, fs, samples, tile, err);
            else if (!rc)
                lc_renderer_readback(r, fs, tile);
            for (int y = 0; y < th && !rc; y++)
                memcpy(rgba + ((size_t)(y0 + y) * W + x0) * 4, tile + (size_t)y * tw * 4, (size_t)tw * 4);
            if (!rc && (i + 1 < nx || j + 1 < ny))
                rc = lc_renderer_yield_point(r, err);
        }
    }
    glDisable(GL_SCISSOR_TEST);
    if (!rc && measure) { /* the session's transfer moves toward the whole frame's */
        int again = 0;
        rc = lc_color_equalize_finish(r, fs, state, dt, 0, &again, err);
    }
    fs->tiled = 0, fs->width = W, fs->height = H;
    free(tile);
    return rc;
}
