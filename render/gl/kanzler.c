/* Method "kanzler" (M3D §3.2, §3.3.2; docs/ALGORITHM.md §28): the
 * view-dependent per-pixel maps (coverage C, maximum importance M and its
 * depth D, directional variance V) drawn before P4, and their binding for the
 * P4/P5 variants that multiply Kanzler's penalty into alpha = g^k. */
#include <stdlib.h>

#include "renderer_internal.h"

typedef struct kanzler_state {
    lc_targets sums; /* additive: (sum of unit tangents xyz, fragment count C) */
    lc_targets max;  /* R32UI: imageAtomicMax of packUnorm2x16(d, g), g in the high bits */
    lc_targets maps; /* RGBA32F: (C, M, D, V), M and D averaged over 5x5 pixels */
    int valid;       /* maps hold the last kanzler frame's (lc_kanzler_read_maps) */
} kanzler_state;

static kanzler_state *state_of(lc_renderer *r)
{
    if (!r->kanzler)
        r->kanzler = calloc(1, sizeof(kanzler_state));
    return r->kanzler;
}

int lc_kanzler_maps(lc_renderer *r, lc_frame_setup *fs, lc_error *err)
{
    kanzler_state *st = state_of(r);
    if (!st)
        return lc_err(err, LC_ERR_NOMEM, "out of memory (kanzler maps)");
    int w = fs->width, h = fs->height;
    lc_targets_ensure(&st->sums, w, h, 1, GL_RGBA32F, &r->bytes_targets);
    lc_targets_ensure(&st->max, w, h, 1, GL_R32UI, &r->bytes_targets);
    lc_targets_ensure(&st->maps, w, h, 1, GL_RGBA32F, &r->bytes_targets);
    lc_targets_clear(&st->sums, NULL);
    const GLuint zero = 0;
    glClearTexImage(st->max.tex[0], 0, GL_RED_INTEGER, GL_UNSIGNED_INT, &zero);
    st->valid = 0;

    lc_additive_blending();
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, st->sums.fbo);
    glMemoryBarrier(GL_TEXTURE_UPDATE_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
    glBindImageTexture(IMG_KANZLER_MAX, st->max.tex[0], 0, GL_FALSE, 0, GL_READ_WRITE, GL_R32UI);
    lc_prim_type prim = fs->gs->scene->type;
    for (int i = 0; i < lc_frame_layer_count(fs); i++) {
        lc_frame_setup tmp;
        const lc_frame_setup *lf = lc_frame_layer(fs, i, &tmp);
        if (!lf)
            continue;
        GLuint prog =
            lc_renderer_geometry_program(r, lf, PROG_KANZLER_MAPS, lf->gs->scene->type, fs->params->foo.bands, 1, err);
        if (!prog)
            return LC_ERR_GL;
        lc_renderer_bind_geometry(r, prog, lf, w, h, 1);
        lc_renderer_draw_geometry(lf, 1);
    }
    glMemoryBarrier(GL_FRAMEBUFFER_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);

    GLuint blur = lc_renderer_fixed_program(r, PROG_KANZLER_BLUR, err);
    if (!blur)
        return LC_ERR_GL;
    glUseProgram(blur);
    glBindTextureUnit(TEX_KANZLER_SUMS, st->sums.tex[0]);
    glBindImageTexture(IMG_KANZLER_MAX, st->max.tex[0], 0, GL_FALSE, 0, GL_READ_ONLY, GL_R32UI);
    glBindImageTexture(IMG_KANZLER_MAPS, st->maps.tex[0], 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32F);
    glProgramUniform2i(blur, glGetUniformLocation(blur, "u_size"), w, h);
    lc_uniform_i(blur, "u_has_tangents", prim == LC_PRIM_LINES);
    glDispatchCompute((GLuint)(w + 7) / 8, (GLuint)(h + 7) / 8, 1);
    glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_TEXTURE_UPDATE_BARRIER_BIT);
    st->valid = 1;
    lc_renderer_timestamp(r, LC_PASS_DEPTH_RANGE);
    return 0;
}

void lc_kanzler_report_begin(lc_renderer *r)
{
    const float sentinel = 2.0f; /* > 1: "no fragment this frame", as P2's */
    glClearNamedBufferData(r->element_alpha_min, GL_R32F, GL_RED, GL_FLOAT, &sentinel);
    lc_occluders_clear(r);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
}

int lc_kanzler_report(lc_renderer *r, const lc_frame_setup *fs, lc_frame_info *info, lc_error *err)
{
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
    /* The report reads an element's opacity from element_alpha (P3's buffer,
     * unused by this method): here its least fragment opacity. */
    glCopyNamedBufferSubData(r->element_alpha_min, r->element_alpha, 0, 0, (GLsizeiptr)fs->element_total * 4);
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    int rc = lc_visibility_measure(r, fs, NULL, info, err);
    /* Covered pixels from the coverage map (at the output resolution: the
     * method has no other); no importance mass is summed (no P1). */
    kanzler_state *st = r->kanzler;
    if (!rc && st && st->valid) {
        double covered = lc_covered_fraction(r, st->maps.tex[0], st->maps.width, st->maps.height, err);
        if (covered < 0)
            return LC_ERR_GL;
        info->covered_fraction = covered;
    }
    return rc;
}

void lc_kanzler_bind(lc_renderer *r, GLuint prog, const lc_foo_params *f)
{
    kanzler_state *st = r->kanzler;
    glBindTextureUnit(TEX_KANZLER_MAPS, st ? st->maps.tex[0] : 0);
    glProgramUniform4f(prog, glGetUniformLocation(prog, "u_kanzler_weights"), (float)f->kanzler_importance,
                       (float)f->kanzler_coverage, (float)f->kanzler_variance, (float)f->kanzler_depth);
    lc_uniform_f(prog, "u_kanzler_lambda", f->kanzler_lambda);
}

int lc_kanzler_read_maps(lc_renderer *r, float *out, int width, int height)
{
    kanzler_state *st = r->kanzler;
    if (!st || !st->valid || st->maps.width != width || st->maps.height != height)
        return -1;
    glGetTextureImage(st->maps.tex[0], 0, GL_RGBA, GL_FLOAT, (GLsizei)((size_t)width * height * 16), out);
    return 0;
}

void lc_kanzler_release(lc_renderer *r)
{
    kanzler_state *st = r->kanzler;
    if (!st)
        return;
    lc_targets_free(&st->sums, &r->bytes_targets);
    lc_targets_free(&st->max, &r->bytes_targets);
    lc_targets_free(&st->maps, &r->bytes_targets);
    st->valid = 0;
}

void lc_kanzler_destroy(lc_renderer *r)
{
    lc_kanzler_release(r);
    free(r->kanzler);
    r->kanzler = NULL;
}
