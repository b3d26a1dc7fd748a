/* Baseline methods for comparison: depth-tested opaque geometry, weighted
 * blended OIT (McGuire & Bavoil 2013) and weighted average OIT (Bavoil & Myers
 * 2008) with the optimized opacities. The "direct" baseline is the Fourier
 * compositing without optimization and "binning" its variant with tau(d) in
 * depth bins (fourier.c). */
#include "renderer_internal.h"

int lc_render_opaque(lc_renderer *r, lc_frame_setup *fs, lc_error *err)
{
    GLuint prog = lc_renderer_geometry_program(r, fs, PROG_OPAQUE, fs->gs->scene->type, 1, 1, err);
    if (!prog)
        return LC_ERR_GL;
    const double *bg = fs->params->style.background;
    const float clear[4] = {(float)bg[0], (float)bg[1], (float)bg[2], 1.0f};
    glClearNamedFramebufferfv(r->output.fbo, GL_COLOR, 0, clear);
    glClearNamedFramebufferfi(r->output.fbo, GL_DEPTH_STENCIL, 0, 1.0f, 0);
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, r->output.fbo);
    glDisable(GL_BLEND);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    lc_renderer_bind_geometry(r, prog, fs, fs->width, fs->height, 1);
    lc_renderer_draw_geometry(fs, 1);
    glDisable(GL_DEPTH_TEST);
    lc_renderer_timestamp(r, LC_PASS_ACCUMULATE);
    return 0;
}

int lc_render_wboit(lc_renderer *r, lc_frame_setup *fs, lc_error *err)
{
    GLuint prog = lc_renderer_geometry_program(r, fs, PROG_WBOIT, fs->gs->scene->type, 1, 1, err);
    if (!prog)
        return LC_ERR_GL;
    lc_targets_ensure(&r->accum, fs->width, fs->height, 2, GL_RGBA16F, &r->bytes_targets);
    static const float zero[4] = {0, 0, 0, 0}, one[4] = {1, 1, 1, 1};
    glClearNamedFramebufferfv(r->accum.fbo, GL_COLOR, 0, zero);
    glClearNamedFramebufferfv(r->accum.fbo, GL_COLOR, 1, one);
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, r->accum.fbo);
    glDisable(GL_DEPTH_TEST);
    glEnable(GL_BLEND);
    glBlendEquation(GL_FUNC_ADD);
    glBlendFunci(0, GL_ONE, GL_ONE);
    glBlendFunci(1, GL_ZERO, GL_ONE_MINUS_SRC_COLOR);
    lc_renderer_bind_geometry(r, prog, fs, fs->width, fs->height, 1);
    lc_renderer_draw_geometry(fs, 1);
    glBlendFunc(GL_ONE, GL_ONE);
    lc_renderer_timestamp(r, LC_PASS_ACCUMULATE);
    glMemoryBarrier(GL_FRAMEBUFFER_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT);
    lc_renderer_resolve(r, fs, PROG_WBOIT_RESOLVE, &r->accum, r->accum.tex[1], err);
    lc_renderer_timestamp(r, LC_PASS_RESOLVE);
    return 0;
}

int lc_render_weighted_average(lc_renderer *r, lc_frame_setup *fs, lc_error *err)
{
    /* Bavoil & Myers keep (sum a c, sum a) in RGBA32F and the count beside it:
     * half floats would stop counting at 2048 fragments. */
    lc_targets_ensure(&r->accum, fs->width, fs->height, 2, GL_RGBA32F, &r->bytes_targets);
    lc_targets_clear(&r->accum, NULL);
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, r->accum.fbo);
    glDisable(GL_DEPTH_TEST);
    lc_additive_blending();
    for (int i = 0; i < lc_frame_layer_count(fs); i++) {
        lc_frame_setup tmp;
        const lc_frame_setup *lf = lc_frame_layer(fs, i, &tmp);
        if (!lf)
            continue;
        GLuint prog = lc_renderer_geometry_program(r, lf, PROG_WEIGHTED_AVERAGE, lf->gs->scene->type, 1, 1, err);
        if (!prog)
            return LC_ERR_GL;
        lc_renderer_bind_geometry(r, prog, lf, fs->width, fs->height, 1);
        lc_renderer_bind_halo(prog, lf);
        lc_renderer_draw_geometry(lf, 1);
    }
    lc_renderer_timestamp(r, LC_PASS_ACCUMULATE);
    glMemoryBarrier(GL_FRAMEBUFFER_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT);
    lc_renderer_resolve(r, fs, PROG_WEIGHTED_AVERAGE_RESOLVE, &r->accum, r->accum.tex[1], err);
    lc_renderer_timestamp(r, LC_PASS_RESOLVE);
    return 0;
}
