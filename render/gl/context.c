/* Opaque context layers (docs/ALGORITHM.md §24, FOO §4.2): the layers of role
 * "context" are drawn first, opaque and shaded with the depth test on, into a
 * depth texture at each resolution (and their colour at full resolution).
 * Every transparent pass then discards its fragments behind that depth (as a
 * depth test with writes off would, but before the fragment shader's atomic
 * side effects of P2 and the exact lists), and P6 composites over the
 * context's colour instead of the background. A tiled still draws the
 * optimization resolution once and the output resolution per tile, and an
 * antialiased one per jittered sample, so that each composite meets the
 * context of its own view. */
#include <stdlib.h>

#include "renderer_internal.h"

typedef struct context_state {
    GLuint fbo[2], color, depth[2]; /* [0] output resolution, [1] optimization resolution */
    int w[2], h[2];
} context_state;

static void release(lc_renderer *r, context_state *st, int k)
{
    if (!st->fbo[k])
        return;
    glDeleteFramebuffers(1, &st->fbo[k]);
    glDeleteTextures(1, &st->depth[k]);
    r->bytes_targets -= (uint64_t)st->w[k] * st->h[k] * 4;
    if (k == 0) {
        glDeleteTextures(1, &st->color);
        r->bytes_targets -= (uint64_t)st->w[k] * st->h[k] * 4;
        st->color = 0;
    }
    st->fbo[k] = st->depth[k] = 0;
    st->w[k] = st->h[k] = 0;
}

static void ensure(lc_renderer *r, context_state *st, int k, int w, int h)
{
    if (st->fbo[k] && st->w[k] == w && st->h[k] == h)
        return;
    release(r, st, k);
    glCreateFramebuffers(1, &st->fbo[k]);
    glCreateTextures(GL_TEXTURE_2D, 1, &st->depth[k]);
    glTextureStorage2D(st->depth[k], 1, GL_DEPTH_COMPONENT32F, w, h);
    glNamedFramebufferTexture(st->fbo[k], GL_DEPTH_ATTACHMENT, st->depth[k], 0);
    r->bytes_targets += (uint64_t)w * h * 4;
    if (k == 0) {
        glCreateTextures(GL_TEXTURE_2D, 1, &st->color);
        glTextureStorage2D(st->color, 1, GL_RGBA8, w, h);
        glNamedFramebufferTexture(st->fbo[k], GL_COLOR_ATTACHMENT0, st->color, 0);
        glNamedFramebufferDrawBuffer(st->fbo[k], GL_COLOR_ATTACHMENT0);
        r->bytes_targets += (uint64_t)w * h * 4;
    } else {
        glNamedFramebufferDrawBuffer(st->fbo[k], GL_NONE);
    }
    st->w[k] = w, st->h[k] = h;
}

int lc_context_draw(lc_renderer *r, lc_frame_setup *fs, int which, lc_error *err)
{
    if (which & LC_CONTEXT_FULL)
        fs->context_depth[0] = fs->context_color = 0;
    if (which & LC_CONTEXT_LOW)
        fs->context_depth[1] = 0;
    int ground = lc_shadow_ground(fs); /* shadow.c's ground plane is context too */
    if (!lc_frame_has_context(fs) && !ground)
        return 0;
    context_state *st = r->context;
    if (!st && !(st = r->context = calloc(1, sizeof *st)))
        return lc_err(err, LC_ERR_NOMEM, "out of memory");
    int size[2][2] = {{fs->width, fs->height}, {fs->low_width, fs->low_height}};
    glDisable(GL_BLEND);
    glDisable(GL_CULL_FACE);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glDepthMask(GL_TRUE);
    GLint scissor = glIsEnabled(GL_SCISSOR_TEST);
    glDisable(GL_SCISSOR_TEST); /* a tile's scissor is the output's; the targets here are cleared whole */
    for (int k = 0; k < 2; k++) {
        if (!(which & (k == 0 ? LC_CONTEXT_FULL : LC_CONTEXT_LOW)))
            continue;
        ensure(r, st, k, size[k][0], size[k][1]);
        static const float clear[4] = {0, 0, 0, 0}; /* alpha 0: no context at this pixel */
        if (k == 0)
            glClearNamedFramebufferfv(st->fbo[k], GL_COLOR, 0, clear);
        glClearNamedFramebufferfi(st->fbo[k], GL_DEPTH_STENCIL, 0, 1.0f, 0);
        glBindFramebuffer(GL_DRAW_FRAMEBUFFER, st->fbo[k]);
        for (int i = 0; i < fs->layer_count; i++) {
            lc_frame_setup tmp;
            const lc_frame_setup *lf = lc_frame_context_layer(fs, i, &tmp);
            if (!lf)
                continue;
            GLuint prog = lc_renderer_geometry_program(r, lf, PROG_OPAQUE, lf->gs->scene->type, 1, 1, err);
            if (!prog) {
                glDisable(GL_DEPTH_TEST);
                return LC_ERR_GL;
            }
            lc_renderer_bind_geometry(r, prog, lf, size[k][0], size[k][1], 1);
            lc_renderer_draw_geometry(lf, 1);
        }
        int rc = ground ? lc_shadow_draw_ground(r, fs, size[k][0], size[k][1], err) : 0;
        if (rc) {
            glDisable(GL_DEPTH_TEST);
            return rc;
        }
    }
    if (scissor)
        glEnable(GL_SCISSOR_TEST);
    glDisable(GL_DEPTH_TEST);
    glMemoryBarrier(GL_FRAMEBUFFER_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT);
    /* Over MPI each process drew its shard of the context: the ranks combine
     * the nearest depth (every rank's transparent passes test against the
     * whole context) and the colour once, on rank 0 (reduce.c); of the
     * resolutions drawn now only. */
    int w[2] = {which & LC_CONTEXT_FULL ? st->w[0] : 0, which & LC_CONTEXT_LOW ? st->w[1] : 0};
    int h[2] = {which & LC_CONTEXT_FULL ? st->h[0] : 0, which & LC_CONTEXT_LOW ? st->h[1] : 0};
    int rc = lc_reduce_context(r, st->depth, w, h, st->color, fs->info, err);
    if (rc)
        return rc;
    if (which & LC_CONTEXT_FULL)
        fs->context_depth[0] = st->depth[0], fs->context_color = st->color;
    if (which & LC_CONTEXT_LOW)
        fs->context_depth[1] = st->depth[1];
    r->context_layers = 1; /* the later passes' programs test the context's depth */
    return 0;
}

void lc_context_destroy(lc_renderer *r)
{
    context_state *st = r->context;
    if (!st)
        return;
    release(r, st, 0);
    release(r, st, 1);
    free(st);
    r->context = NULL;
}
