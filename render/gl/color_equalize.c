/* View-dependent colour equalization (DLS §3.4, docs/ALGORITHM.md §19) on the
 * GPU side: the visibility-weighted histogram after P5, the equalized
 * colormap texture, and the order of passes for one-shot and session frames. */
#include <math.h>
#include <string.h>

#include "colormap.h"
#include "equalize.h"
#include "renderer_internal.h"

_Static_assert(LC_EQUALIZE_BINS == 256, "shader colour histogram bins");

#define EQUALIZE_SETTLED (0.25f / LC_EQUALIZE_BINS) /* F's largest step left when a session's colours have settled */

/* The request's fixed ranges in colormap coordinates (through color.range). */
static int fixed_ranges(const lc_frame_setup *fs, double (*out)[2])
{
    const lc_color_map *c = &fs->params->color;
    double lo = fs->color_range[0], span = fs->color_range[1] - fs->color_range[0];
    int n = 0;
    for (int i = 0; i < c->fixed_count && i < LC_MAX_COLOR_FIXED; i++) {
        double a = span != 0 ? (c->fixed[i][0] - lo) / span : 0.5;
        double b = span != 0 ? (c->fixed[i][1] - lo) / span : 0.5;
        if (a > b) {
            double t = a;
            a = b, b = t;
        }
        a = a < 0 ? 0 : a > 1 ? 1 : a;
        b = b < 0 ? 0 : b > 1 ? 1 : b;
        if (b > a || (a > 0 && a < 1))
            out[n][0] = a, out[n][1] = b, n++;
    }
    return n;
}

/* Writes T(F(.)) into the equalized texture and makes the frame's geometry
 * passes read it. */
void lc_color_equalize_use_table(lc_renderer *r, lc_frame_setup *fs, const float *knots)
{
    float table[256 * 3];
    lc_equalize_table(lc_colormap_table(fs->colormap), LC_COLORMAP_SIZE, knots, LC_EQUALIZE_BINS, table, 256);
    uint8_t rgba[256 * 4];
    for (int k = 0; k < 256; k++) {
        for (int c = 0; c < 3; c++) {
            float v = table[3 * k + c];
            rgba[4 * k + c] = (uint8_t)lrintf(255.0f * (v < 0 ? 0 : v > 1 ? 1 : v));
        }
        rgba[4 * k + 3] = 255;
    }
    GLuint *tex = &r->equalized_tex[fs->eq_slot];
    if (!*tex) {
        glCreateTextures(GL_TEXTURE_2D, 1, tex);
        glTextureStorage2D(*tex, 1, GL_RGBA8, 256, 1);
        glTextureParameteri(*tex, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
        glTextureParameteri(*tex, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
        glTextureParameteri(*tex, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
        glTextureParameteri(*tex, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    }
    glTextureSubImage2D(*tex, 0, 0, 0, 256, 1, GL_RGBA, GL_UNSIGNED_BYTE, rgba);
    fs->colormap_texture = *tex;
}

/* Each equalized layer of a layered frame with its own transfer (layers.c
 * keeps the texture in the layer's setup). */
static void begin_layers(lc_renderer *r, lc_frame_setup *fs, const lc_frame_state *state)
{
    for (int i = 0; i < fs->layer_count; i++) {
        lc_layer_setup *l = lc_frame_layer_setup(fs, i);
        l->colormap_texture = 0;
        if (!l->params.color.equalize || !state || !state->eq[i].valid)
            continue;
        lc_frame_setup tmp;
        const lc_frame_setup *lf = lc_frame_layer(fs, i, &tmp);
        if (!lf)
            continue;
        lc_color_equalize_use_table(r, &tmp, state->eq[i].knots);
        l->colormap_texture = tmp.colormap_texture;
    }
}

int lc_color_equalize_begin(lc_renderer *r, lc_frame_setup *fs, const lc_frame_state *state)
{
    fs->colormap_texture = 0;
    if (fs->layer_count > 0) {
        begin_layers(r, fs, state);
        return 0;
    }
    if (fs->params->color.equalize && state && state->eq[0].valid)
        lc_color_equalize_use_table(r, fs, state->eq[0].knots);
    return 0;
}

void lc_color_equalize_reset(lc_renderer *r)
{
    memset(r->eq_hist, 0, sizeof r->eq_hist);
    r->eq_cover = r->eq_halo = -1;
}

/* The histogram of the composite that just ran (P4/P5 targets in place, a tile
 * or the whole frame) added to r->eq_hist, summed over the processes of a split
 * frame; *fresh: whether any process has no transfer yet (so that all of them
 * composite again, together). */
int lc_color_equalize_measure(lc_renderer *r, lc_frame_setup *fs, int direct, int *fresh, lc_error *err)
{
    const lc_render_params *p = fs->params;
    GLuint prog = lc_renderer_geometry_program(r, fs, direct ? PROG_COLOR_HISTOGRAM_DIRECT : PROG_COLOR_HISTOGRAM,
                                               fs->gs->scene->type, p->foo.bands, 1, err);
    if (!prog)
        return LC_ERR_GL;
    if (!r->color_histogram) {
        glCreateBuffers(1, &r->color_histogram);
        glNamedBufferStorage(r->color_histogram, LC_EQUALIZE_BINS * 4, NULL, GL_DYNAMIC_STORAGE_BIT);
    }
    const uint32_t zero = 0;
    glClearNamedBufferData(r->color_histogram, GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, &zero);
    /* Fixed point: the whole image's share (<= one unit per pixel) fits 31 bits. */
    double pixels = (double)fs->width * fs->height;
    double scale = floor(2147483647.0 / (pixels + 1));
    scale = scale > 65536 ? 65536 : scale < 1 ? 1 : scale;
    glMemoryBarrier(GL_FRAMEBUFFER_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT |
                    GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
    glDisable(GL_BLEND);
    if (r->nofb_w != fs->width || r->nofb_h != fs->height) {
        glNamedFramebufferParameteri(r->nofb, GL_FRAMEBUFFER_DEFAULT_WIDTH, fs->width);
        glNamedFramebufferParameteri(r->nofb, GL_FRAMEBUFFER_DEFAULT_HEIGHT, fs->height);
        r->nofb_w = fs->width, r->nofb_h = fs->height;
    }
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, r->nofb);
    lc_renderer_bind_geometry(r, prog, fs, fs->width, fs->height, 1);
    lc_bind_coefficients(&r->coef_full);
    glBindTextureUnit(TEX_EQUALIZE_ACCUM, r->accum.tex[0]);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_COLOR_HISTOGRAM, r->color_histogram);
    lc_uniform_i(prog, "u_estimator", p->foo.estimator == LC_ESTIMATOR_MIDPOINT ? 1 : 0);
    lc_renderer_bind_direct_alpha(prog, p);
    lc_uniform_f(prog, "u_eq_scale", scale);
    lc_renderer_bind_halo(prog, fs);
    lc_renderer_draw_geometry(fs, 1);
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT | GL_SHADER_STORAGE_BARRIER_BIT);
    uint32_t bins[LC_EQUALIZE_BINS];
    glGetNamedBufferSubData(r->color_histogram, 0, sizeof bins, bins);
    float sums[LC_EQUALIZE_BINS + 1];
    for (int b = 0; b < LC_EQUALIZE_BINS; b++)
        sums[b] = (float)(bins[b] / scale);
    sums[LC_EQUALIZE_BINS] = (float)*fresh;
    int rc = lc_reduce_sums(r, sums, LC_EQUALIZE_BINS + 1, fs->info, err);
    for (int b = 0; b < LC_EQUALIZE_BINS; b++)
        r->eq_hist[b] += sums[b];
    *fresh = sums[LC_EQUALIZE_BINS] > 0;
    return rc;
}

/* The legend's ticks (lc_frame_info.color_ticks): where the bar shows T(x),
 * the frame shows the data value whose colormap coordinate u has F(u) = x. */
static void color_ticks(lc_frame_setup *fs, const float *knots)
{
    lc_frame_info *info = fs->info;
    if (fs->layer_count > 0) /* the frame's ticks are one mapping's: a layered frame's legend keeps its ranges */
        return;
    info->has_color_ticks = fs->params->color.curve.count == 0; /* u would need the curve's inverse */
    for (int i = 0; i < 5 && info->has_color_ticks; i++) {
        double u = lc_equalize_inverse(knots, LC_EQUALIZE_BINS, (float)i / 4.0f);
        info->color_ticks[i] = fs->color_range[0] + u * (fs->color_range[1] - fs->color_range[0]);
    }
}

int lc_color_equalize_finish(lc_renderer *r, lc_frame_setup *fs, lc_frame_state *state, double dt, int fresh,
                             int *again, lc_error *err)
{
    const lc_color_map *c = &fs->params->color;
    *again = 0;
    double fixed[LC_MAX_COLOR_FIXED][2];
    int nfixed = fixed_ranges(fs, fixed);
    float target[LC_EQUALIZE_BINS + 1];
    if (lc_equalize_target(r->eq_hist, LC_EQUALIZE_BINS, (const double(*)[2])fixed, nfixed, target) != 0)
        return lc_err_field(err, LC_ERR_INVALID, "color.fixed", "a fixed range is invalid");
    int slot = fs->eq_slot;
    if (!fresh) {
        /* This frame drew with the session's F; the next one draws with F moved toward this view's. */
        memcpy(r->eq_knots, state->eq[slot].knots, sizeof r->eq_knots);
        r->eq_valid = 1;
        color_ticks(fs, r->eq_knots);
        lc_frame_state_equalize_slot(state, slot, target, dt, c->fade_half_life);
        /* The stream goes on until F has reached this view's (a session sends no
         * frame once a frame reports converged): within a quarter of one of the
         * colormap's 256 steps. */
        const float *next = lc_frame_state_equalize_knots_slot(state, slot);
        for (int i = 0; next && fs->info && i <= LC_EQUALIZE_BINS; i++)
            if (fabsf(next[i] - target[i]) > EQUALIZE_SETTLED) {
                fs->info->converged = 0;
                break;
            }
        return 0;
    }
    /* One-shot frames and a session's first: composite again with this view's F. */
    if (state) {
        state->eq[slot].valid = 0;
        lc_frame_state_equalize_slot(state, slot, target, dt, c->fade_half_life);
    }
    memcpy(r->eq_knots, target, sizeof r->eq_knots);
    r->eq_valid = 1;
    color_ticks(fs, target);
    lc_color_equalize_use_table(r, fs, target);
    *again = 1;
    return 0;
}

/* A layered frame: each equalized layer's histogram of its own fragments'
 * visibility in the whole frame, its own transfer; one composite again when
 * any of them had none yet. */
static int end_layers(lc_renderer *r, lc_frame_setup *fs, lc_frame_state *state, double dt, int direct, lc_error *err)
{
    int again = 0, rc = 0;
    for (int i = 0; i < fs->layer_count && !rc; i++) {
        lc_layer_setup *l = lc_frame_layer_setup(fs, i);
        lc_frame_setup tmp;
        const lc_frame_setup *lf = l->params.color.equalize ? lc_frame_layer(fs, i, &tmp) : NULL;
        if (!lf)
            continue;
        int fresh = !(state && state->eq[i].valid), more = 0;
        lc_color_equalize_reset(r);
        rc = lc_color_equalize_measure(r, &tmp, direct, &fresh, err);
        if (!rc)
            rc = lc_color_equalize_finish(r, &tmp, state, dt, fresh, &more, err);
        if (more)
            l->colormap_texture = tmp.colormap_texture;
        again |= more;
    }
    return rc || !again ? rc : lc_fourier_composite(r, fs, direct, err);
}

int lc_color_equalize_end(lc_renderer *r, lc_frame_setup *fs, lc_frame_state *state, double dt, int direct,
                          lc_error *err)
{
    if (fs->layer_count > 0)
        return end_layers(r, fs, state, dt, direct, err);
    if (!fs->params->color.equalize)
        return 0;
    int fresh = !(state && state->eq[0].valid), again = 0;
    lc_color_equalize_reset(r);
    int rc = lc_color_equalize_measure(r, fs, direct, &fresh, err);
    if (!rc)
        rc = lc_color_equalize_finish(r, fs, state, dt, fresh, &again, err);
    /* P1-P3 reused, only P4-P6 re-run. */
    return rc || !again ? rc : lc_fourier_composite(r, fs, direct, err);
}

int lc_renderer_color_histogram(const lc_renderer *r, double *hist, float *knots)
{
    if (!r->eq_valid)
        return -1;
    if (hist)
        memcpy(hist, r->eq_hist, sizeof r->eq_hist);
    if (knots)
        memcpy(knots, r->eq_knots, sizeof r->eq_knots);
    return 0;
}

int lc_renderer_color_coverage(const lc_renderer *r, double *cover, double *halo)
{
    if (!r->eq_valid || r->eq_cover < 0)
        return -1;
    if (cover)
        *cover = r->eq_cover;
    if (halo)
        *halo = r->eq_halo;
    return 0;
}
