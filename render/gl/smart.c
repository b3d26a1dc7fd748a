/* Smart transparency in image space (docs/ALGORITHM.md §29; OOS §6 after
 * Carnecky et al.): after P6, silhouettes and halos are injected where P4's
 * optical depth steps between neighbouring pixels, scaled by the opacity of
 * the layer that ends there, diffused style.smartIterations steps and laid
 * over the image (black silhouettes, white halos). */
#include <stdio.h>
#include <stdlib.h>

#include "renderer_internal.h"

typedef struct smart_state {
    GLuint inject, v[2]; /* RGBA32F: injected (silhouette, halo, A0); the diffused pair, ping-pong */
    int w, h;
    GLuint programs[3][LC_MAX_BANDS + 1]; /* inject (per band count), diffuse, apply */
} smart_state;

static void release_textures(lc_renderer *r, smart_state *st)
{
    if (!st->inject)
        return;
    glDeleteTextures(1, &st->inject);
    glDeleteTextures(2, st->v);
    r->bytes_targets -= (uint64_t)st->w * st->h * 16 * 3;
    st->inject = st->v[0] = st->v[1] = 0;
}

static GLuint program(smart_state *st, int stage, int bands, lc_error *err)
{
    GLuint *slot = &st->programs[stage][stage == 0 ? bands : 0];
    if (*slot)
        return *slot;
    static const char *const cs_inject[] = {"common.glsl", "coefficients.glsl", "smart.comp.glsl", NULL};
    static const char *const cs_other[] = {"smart.comp.glsl", NULL};
    char defines[64];
    snprintf(defines, sizeof defines, "#define STAGE %d\n#define BANDS %d\n", stage, bands);
    static const char *const labels[3] = {"smart transparency (inject)", "smart transparency (diffuse)",
                                          "smart transparency (apply)"};
    *slot = lc_renderer_build_program(defines, NULL, NULL, stage == 0 ? cs_inject : cs_other, labels[stage], err);
    return *slot;
}

static void dispatch(GLuint prog, int w, int h)
{
    glUseProgram(prog);
    glProgramUniform2i(prog, glGetUniformLocation(prog, "u_size"), w, h);
    glDispatchCompute((GLuint)(w + 7) / 8, (GLuint)(h + 7) / 8, 1);
    glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
}

int lc_smart_apply(lc_renderer *r, const lc_frame_setup *fs, lc_error *err)
{
    const lc_render_params *p = fs->params;
    if (!(p->style.smart > 0))
        return 0;
    smart_state *st = r->smart;
    if (!st && !(st = r->smart = calloc(1, sizeof *st)))
        return lc_err(err, LC_ERR_NOMEM, "out of memory (smart transparency)");
    int w = fs->width, h = fs->height, bands = p->foo.bands;
    if (st->inject && (st->w != w || st->h != h))
        release_textures(r, st);
    if (!st->inject) {
        glCreateTextures(GL_TEXTURE_2D, 1, &st->inject);
        glCreateTextures(GL_TEXTURE_2D, 2, st->v);
        glTextureStorage2D(st->inject, 1, GL_RGBA32F, w, h);
        glTextureStorage2D(st->v[0], 1, GL_RGBA32F, w, h);
        glTextureStorage2D(st->v[1], 1, GL_RGBA32F, w, h);
        st->w = w, st->h = h;
        r->bytes_targets += (uint64_t)w * h * 16 * 3;
    }
    GLuint inject = program(st, 0, bands, err), diffuse = program(st, 1, bands, err),
           apply = program(st, 2, bands, err);
    if (!inject || !diffuse || !apply)
        return LC_ERR_GL;
    glMemoryBarrier(GL_FRAMEBUFFER_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
    lc_bind_coefficients(&r->coef_full);
    glBindImageTexture(IMG_SMART_INJECT, st->inject, 0, GL_FALSE, 0, GL_READ_WRITE, GL_RGBA32F);
    dispatch(inject, w, h);
    /* The injected values start the diffusion (a copy keeps inject's own). */
    glCopyImageSubData(st->inject, GL_TEXTURE_2D, 0, 0, 0, 0, st->v[0], GL_TEXTURE_2D, 0, 0, 0, 0, w, h, 1);
    int cur = 0;
    for (int i = 0; i < p->style.smart_iterations; i++, cur ^= 1) {
        glBindImageTexture(IMG_SMART_SRC, st->v[cur], 0, GL_FALSE, 0, GL_READ_ONLY, GL_RGBA32F);
        glBindImageTexture(IMG_SMART_DST, st->v[cur ^ 1], 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32F);
        dispatch(diffuse, w, h);
    }
    glBindImageTexture(IMG_SMART_SRC, st->v[cur], 0, GL_FALSE, 0, GL_READ_ONLY, GL_RGBA32F);
    glBindImageTexture(IMG_SMART_OUTPUT, r->output.tex[0], 0, GL_FALSE, 0, GL_READ_WRITE, GL_RGBA8);
    lc_uniform_f(apply, "u_strength", p->style.smart);
    dispatch(apply, w, h);
    glMemoryBarrier(GL_FRAMEBUFFER_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT | GL_PIXEL_BUFFER_BARRIER_BIT);
    return 0;
}

void lc_smart_destroy(lc_renderer *r)
{
    smart_state *st = r->smart;
    if (!st)
        return;
    release_textures(r, st);
    for (int k = 0; k < 3; k++)
        for (int b = 0; b <= LC_MAX_BANDS; b++)
            if (st->programs[k][b])
                glDeleteProgram(st->programs[k][b]);
    free(st);
    r->smart = NULL;
}
