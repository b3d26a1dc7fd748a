/* Ground plane and ground shadows (docs/ALGORITHM.md §29; M3D §3.4.5, OOS §6):
 * the transparent layers' optical depth seen from a directional light is
 * projected into a Fourier opacity map (P4 from the light, with the frame's
 * element opacities), and every pixel of the opaque context (context layers
 * and the ground plane) is darkened by the transmittance reconstructed at its
 * own depth along the light, tinted by the occluders' colour when asked. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "frame_check.h"
#include "renderer_internal.h"

/* OOS §6: a 512² map, blurred by a 7×7 Gaussian (binomial weights here). */
#define SHADOW_MAP_SIZE 512

typedef struct shadow_state {
    lc_targets coef, color; /* the light's optical-depth sums and (sum f C, sum f) */
    lc_targets blur;        /* one target: the blur's intermediate direction */
    GLuint map_fbo;         /* both, for the light pass */
    int map_targets;
    GLuint shadowed, shadowed_fbo; /* the shadowed context colour at the output's size */
    int w, h;
    GLuint ground_prog, blur_prog, apply_prog[LC_MAX_BANDS + 1];
} shadow_state;

static shadow_state *state_of(lc_renderer *r, lc_error *err)
{
    if (!r->shadow && !(r->shadow = calloc(1, sizeof *r->shadow)))
        lc_err(err, LC_ERR_NOMEM, "out of memory (shadows)");
    return r->shadow;
}

int lc_shadow_ground(const lc_frame_setup *fs) { return lc_render_ground_drawn(fs->params, lc_frame_has_context(fs)); }

static void unit(const double in[3], double out[3])
{
    double n = sqrt(in[0] * in[0] + in[1] * in[1] + in[2] * in[2]);
    for (int i = 0; i < 3; i++)
        out[i] = n > 0 ? in[i] / n : (i == 1);
}

static void cross(const double a[3], const double b[3], double o[3])
{
    o[0] = a[1] * b[2] - a[2] * b[1], o[1] = a[2] * b[0] - a[0] * b[2], o[2] = a[0] * b[1] - a[1] * b[0];
}

/* Toward the light: style.shadowLight, or where it is zero (the default) the
 * up vector of the first dataset's suggested view, else +Y. */
static void light_direction(const lc_frame_setup *fs, double l[3])
{
    const double *d = fs->params->style.shadow_light;
    const lc_scene *s = fs->gs->scene;
    static const double y[3] = {0, 1, 0};
    unit(d[0] * d[0] + d[1] * d[1] + d[2] * d[2] > 0 ? d : s->has_view ? s->view_up : y, l);
}

/* The ground's four corners: a square of side 2·diagonal facing the light,
 * offset·diagonal beyond the bounds' farthest corner from it, centred under
 * the bounds' centre. */
static void ground_corners(const lc_frame_setup *fs, float out[4][3])
{
    const double *b = fs->bounds;
    const lc_style *st = &fs->params->style;
    double l[3], u[3], v[3], c[3], diag = 0;
    light_direction(fs, l);
    for (int i = 0; i < 3; i++) {
        c[i] = 0.5 * (b[i] + b[i + 3]);
        diag += (b[i + 3] - b[i]) * (b[i + 3] - b[i]);
    }
    diag = sqrt(diag);
    double low = INFINITY;
    for (int k = 0; k < 8; k++) {
        double p[3] = {b[(k & 1) ? 3 : 0], b[(k & 2) ? 4 : 1], b[(k & 4) ? 5 : 2]};
        double h = p[0] * l[0] + p[1] * l[1] + p[2] * l[2];
        low = h < low ? h : low;
    }
    double h = low - st->ground_offset * diag, ch = c[0] * l[0] + c[1] * l[1] + c[2] * l[2];
    double other[3] = {fabs(l[0]) < 0.9, fabs(l[0]) >= 0.9, 0};
    cross(l, other, u);
    unit(u, u);
    cross(l, u, v);
    double half = diag > 0 ? diag : 1;
    static const int su[4] = {-1, 1, -1, 1}, sv[4] = {-1, -1, 1, 1};
    for (int k = 0; k < 4; k++)
        for (int i = 0; i < 3; i++)
            out[k][i] = (float)(c[i] - (ch - h) * l[i] + half * (su[k] * u[i] + sv[k] * v[i]));
}

void lc_shadow_clip_ground(const lc_frame_setup *fs, lc_view *view)
{
    const lc_render_params *p = fs->params;
    if (!lc_shadow_ground(fs))
        return;
    float corners[4][3];
    ground_corners(fs, corners);
    double b[6];
    memcpy(b, fs->bounds, sizeof b);
    for (int k = 0; k < 4; k++)
        for (int i = 0; i < 3; i++) {
            b[i] = corners[k][i] < b[i] ? corners[k][i] : b[i];
            b[i + 3] = corners[k][i] > b[i + 3] ? corners[k][i] : b[i + 3];
        }
    lc_view wide;
    lc_camera_view(&p->camera, b, (double)p->width / p->height, p->height, &wide);
    memcpy(view->proj, wide.proj, sizeof view->proj);
    memcpy(view->view_proj, wide.view_proj, sizeof view->view_proj);
    view->znear = wide.znear, view->zfar = wide.zfar;
}

int lc_shadow_draw_ground(lc_renderer *r, const lc_frame_setup *fs, int w, int h, lc_error *err)
{
    shadow_state *st = state_of(r, err);
    if (!st)
        return LC_ERR_NOMEM;
    if (!st->ground_prog) {
        static const char *const vs[] = {"ground.vert.glsl", NULL};
        static const char *const fsrc[] = {"ground.frag.glsl", NULL};
        if (!(st->ground_prog = lc_renderer_build_program("", vs, fsrc, NULL, "ground plane", err)))
            return LC_ERR_GL;
    }
    float corners[4][3];
    ground_corners(fs, corners);
    GLuint prog = st->ground_prog;
    glUseProgram(prog);
    glBindVertexArray(r->vao);
    glProgramUniform3fv(prog, glGetUniformLocation(prog, "u_corners"), 4, &corners[0][0]);
    glProgramUniformMatrix4fv(prog, glGetUniformLocation(prog, "u_view_proj"), 1, GL_FALSE, fs->view.view_proj);
    const double *gc = fs->params->style.ground_color;
    glProgramUniform3f(prog, glGetUniformLocation(prog, "u_ground_color"), (float)gc[0], (float)gc[1], (float)gc[2]);
    glViewport(0, 0, w, h);
    glDrawArrays(GL_TRIANGLE_STRIP, 0, 4);
    return 0;
}

/* Inverse of a column-major 4x4 matrix by cofactors (doubles: the depth of a
 * far receiver survives the inversion). Returns 0 when singular. */
static int invert4(const float m[16], double out[16])
{
    double a[16], inv[16];
    for (int i = 0; i < 16; i++)
        a[i] = m[i];
    inv[0] = a[5] * a[10] * a[15] - a[5] * a[11] * a[14] - a[9] * a[6] * a[15] + a[9] * a[7] * a[14] +
             a[13] * a[6] * a[11] - a[13] * a[7] * a[10];
    inv[4] = -a[4] * a[10] * a[15] + a[4] * a[11] * a[14] + a[8] * a[6] * a[15] - a[8] * a[7] * a[14] -
             a[12] * a[6] * a[11] + a[12] * a[7] * a[10];
    inv[8] = a[4] * a[9] * a[15] - a[4] * a[11] * a[13] - a[8] * a[5] * a[15] + a[8] * a[7] * a[13] +
             a[12] * a[5] * a[11] - a[12] * a[7] * a[9];
    inv[12] = -a[4] * a[9] * a[14] + a[4] * a[10] * a[13] + a[8] * a[5] * a[14] - a[8] * a[6] * a[13] -
              a[12] * a[5] * a[10] + a[12] * a[6] * a[9];
    inv[1] = -a[1] * a[10] * a[15] + a[1] * a[11] * a[14] + a[9] * a[2] * a[15] - a[9] * a[3] * a[14] -
             a[13] * a[2] * a[11] + a[13] * a[3] * a[10];
    inv[5] = a[0] * a[10] * a[15] - a[0] * a[11] * a[14] - a[8] * a[2] * a[15] + a[8] * a[3] * a[14] +
             a[12] * a[2] * a[11] - a[12] * a[3] * a[10];
    inv[9] = -a[0] * a[9] * a[15] + a[0] * a[11] * a[13] + a[8] * a[1] * a[15] - a[8] * a[3] * a[13] -
             a[12] * a[1] * a[11] + a[12] * a[3] * a[9];
    inv[13] = a[0] * a[9] * a[14] - a[0] * a[10] * a[13] - a[8] * a[1] * a[14] + a[8] * a[2] * a[13] +
              a[12] * a[1] * a[10] - a[12] * a[2] * a[9];
    inv[2] = a[1] * a[6] * a[15] - a[1] * a[7] * a[14] - a[5] * a[2] * a[15] + a[5] * a[3] * a[14] +
             a[13] * a[2] * a[7] - a[13] * a[3] * a[6];
    inv[6] = -a[0] * a[6] * a[15] + a[0] * a[7] * a[14] + a[4] * a[2] * a[15] - a[4] * a[3] * a[14] -
             a[12] * a[2] * a[7] + a[12] * a[3] * a[6];
    inv[10] = a[0] * a[5] * a[15] - a[0] * a[7] * a[13] - a[4] * a[1] * a[15] + a[4] * a[3] * a[13] +
              a[12] * a[1] * a[7] - a[12] * a[3] * a[5];
    inv[14] = -a[0] * a[5] * a[14] + a[0] * a[6] * a[13] + a[4] * a[1] * a[14] - a[4] * a[2] * a[13] -
              a[12] * a[1] * a[6] + a[12] * a[2] * a[5];
    inv[3] = -a[1] * a[6] * a[11] + a[1] * a[7] * a[10] + a[5] * a[2] * a[11] - a[5] * a[3] * a[10] -
             a[9] * a[2] * a[7] + a[9] * a[3] * a[6];
    inv[7] = a[0] * a[6] * a[11] - a[0] * a[7] * a[10] - a[4] * a[2] * a[11] + a[4] * a[3] * a[10] +
             a[8] * a[2] * a[7] - a[8] * a[3] * a[6];
    inv[11] = -a[0] * a[5] * a[11] + a[0] * a[7] * a[9] + a[4] * a[1] * a[11] - a[4] * a[3] * a[9] -
              a[8] * a[1] * a[7] + a[8] * a[3] * a[5];
    inv[15] = a[0] * a[5] * a[10] - a[0] * a[6] * a[9] - a[4] * a[1] * a[10] + a[4] * a[2] * a[9] + a[8] * a[1] * a[6] -
              a[8] * a[2] * a[5];
    double det = a[0] * inv[0] + a[1] * inv[4] + a[2] * inv[8] + a[3] * inv[12];
    if (det == 0)
        return 0;
    for (int i = 0; i < 16; i++)
        out[i] = inv[i] / det;
    return 1;
}

/* The bounds of what casts shadows: the visible transparent layers (a context
 * layer only receives), so that a context floor lies beyond their far end. */
static void caster_bounds(const lc_frame_setup *fs, double b[6])
{
    memcpy(b, fs->bounds, 6 * sizeof *b);
    int first = 1;
    for (int i = 0; i < fs->layer_count; i++) {
        lc_frame_setup tmp;
        const lc_frame_setup *lf = lc_frame_layer(fs, i, &tmp);
        if (!lf)
            continue;
        const double *sb = lf->gs->scene->bounds;
        for (int k = 0; k < 3; k++) {
            b[k] = first || sb[k] < b[k] ? sb[k] : b[k];
            b[k + 3] = first || sb[k + 3] > b[k + 3] ? sb[k + 3] : b[k + 3];
        }
        first = 0;
    }
}

/* The light's view: parallel, along -shadowLight, fitted to the casters' bounding sphere. */
static void light_view(const lc_frame_setup *fs, lc_render_params *lp, lc_view *out)
{
    double l[3], dir[3], up[3] = {0, 0, 1};
    light_direction(fs, l);
    for (int i = 0; i < 3; i++)
        dir[i] = -l[i];
    if (fabs(l[2]) > 0.9)
        up[1] = 1, up[2] = 0;
    double b[6];
    caster_bounds(fs, b);
    lc_camera_fit(&lp->camera, b, dir, up);
    lp->camera.parallel_projection = true;
    lc_camera_view(&lp->camera, b, 1.0, SHADOW_MAP_SIZE, out);
}

static int ensure_targets(lc_renderer *r, shadow_state *st, int ntargets, int w, int h)
{
    lc_targets_ensure(&st->coef, SHADOW_MAP_SIZE, SHADOW_MAP_SIZE, ntargets, GL_RGBA32F, &r->bytes_targets);
    lc_targets_ensure(&st->color, SHADOW_MAP_SIZE, SHADOW_MAP_SIZE, 1, GL_RGBA32F, &r->bytes_targets);
    lc_targets_ensure(&st->blur, SHADOW_MAP_SIZE, SHADOW_MAP_SIZE, 1, GL_RGBA32F, &r->bytes_targets);
    if (st->map_fbo && st->map_targets != ntargets) {
        glDeleteFramebuffers(1, &st->map_fbo);
        st->map_fbo = 0;
    }
    if (!st->map_fbo) { /* remade with the targets: their textures may be new */
        glCreateFramebuffers(1, &st->map_fbo);
        st->map_targets = ntargets;
    }
    GLenum draw[LC_MAX_COEF_TARGETS + 1];
    for (int i = 0; i <= ntargets; i++) {
        glNamedFramebufferTexture(st->map_fbo, GL_COLOR_ATTACHMENT0 + i,
                                  i < ntargets ? st->coef.tex[i] : st->color.tex[0], 0);
        draw[i] = GL_COLOR_ATTACHMENT0 + i;
    }
    glNamedFramebufferDrawBuffers(st->map_fbo, ntargets + 1, draw);
    if (st->shadowed && (st->w != w || st->h != h)) {
        glDeleteFramebuffers(1, &st->shadowed_fbo);
        glDeleteTextures(1, &st->shadowed);
        r->bytes_targets -= (uint64_t)st->w * st->h * 4;
        st->shadowed = st->shadowed_fbo = 0;
    }
    if (!st->shadowed) {
        glCreateTextures(GL_TEXTURE_2D, 1, &st->shadowed);
        glTextureStorage2D(st->shadowed, 1, GL_RGBA8, w, h);
        glCreateFramebuffers(1, &st->shadowed_fbo);
        glNamedFramebufferTexture(st->shadowed_fbo, GL_COLOR_ATTACHMENT0, st->shadowed, 0);
        glNamedFramebufferDrawBuffer(st->shadowed_fbo, GL_COLOR_ATTACHMENT0);
        st->w = w, st->h = h;
        r->bytes_targets += (uint64_t)w * h * 4;
    }
    return 0;
}

/* P4 from the light into the map: the transparent layers with the frame's
 * opacities, no context test (the context receives, it does not cast), no
 * halos, no depth warp, unlit colours. */
static int light_pass(lc_renderer *r, shadow_state *st, const lc_frame_setup *fs, lc_frame_setup *light, lc_error *err)
{
    const lc_render_params *p = fs->params;
    int bands = p->foo.bands, direct = p->method == LC_METHOD_DIRECT;
    lc_targets_clear(&st->coef, NULL);
    lc_targets_clear(&st->color, NULL);
    lc_additive_blending();
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, st->map_fbo);
    /* The light's pass tests no context: its programs without the test (on
     * llvmpipe a compiled-in test costs a pass a third more even when off). */
    int context_layers = r->context_layers;
    r->context_layers = 0;
    for (int i = 0; i < lc_frame_layer_count(light); i++) {
        lc_frame_setup tmp;
        const lc_frame_setup *lf = lc_frame_layer(light, i, &tmp);
        if (!lf)
            continue;
        GLuint prog = lc_renderer_geometry_program(r, lf, direct ? PROG_SHADOW_DIRECT : PROG_SHADOW,
                                                   lf->gs->scene->type, bands, 1, err);
        if (!prog) {
            r->context_layers = context_layers;
            return LC_ERR_GL;
        }
        lc_renderer_bind_geometry(r, prog, lf, SHADOW_MAP_SIZE, SHADOW_MAP_SIZE, 1);
        lc_uniform_i(prog, "u_ortho", 1);
        lc_uniform_i(prog, "u_shading", 1);
        lc_uniform_i(prog, "u_context_depth", 0);
        lc_uniform_f(prog, "u_weight", 1);
        lc_uniform_f(prog, "u_direct_exponent", p->foo.direct_exponent);
        lc_renderer_draw_geometry(lf, 1);
    }
    r->context_layers = context_layers;
    glDisable(GL_BLEND);
    /* Over MPI every rank holds a shard of the casters; every rank's context needs the whole map. */
    int rc = lc_reduce_targets(r, &st->coef, LC_REDUCE_SUM, 0, fs->info, err);
    if (!rc)
        rc = lc_reduce_targets(r, &st->color, LC_REDUCE_SUM, 0, fs->info, err);
    glMemoryBarrier(GL_FRAMEBUFFER_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
    return rc;
}

/* The map's 7x7 binomial blur (OOS §6: a 7x7 Gaussian), separable: each
 * target across into st->blur and down back into itself. */
static int blur_map(shadow_state *st, lc_error *err)
{
    if (!st->blur_prog) {
        static const char *const cs[] = {"shadow_blur.comp.glsl", NULL};
        if (!(st->blur_prog = lc_renderer_build_program("", NULL, NULL, cs, "shadow map blur", err)))
            return LC_ERR_GL;
    }
    GLuint prog = st->blur_prog;
    glUseProgram(prog);
    glProgramUniform2i(prog, glGetUniformLocation(prog, "u_size"), SHADOW_MAP_SIZE, SHADOW_MAP_SIZE);
    GLuint groups = (SHADOW_MAP_SIZE + 7) / 8;
    for (int i = 0; i <= st->coef.count; i++) {
        GLuint tex = i < st->coef.count ? st->coef.tex[i] : st->color.tex[0];
        for (int pass = 0; pass < 2; pass++) {
            glProgramUniform2i(prog, glGetUniformLocation(prog, "u_step"), pass == 0, pass == 1);
            glBindImageTexture(IMG_SMART_SRC, pass == 0 ? tex : st->blur.tex[0], 0, GL_FALSE, 0, GL_READ_ONLY,
                               GL_RGBA32F);
            glBindImageTexture(IMG_SMART_DST, pass == 0 ? st->blur.tex[0] : tex, 0, GL_FALSE, 0, GL_WRITE_ONLY,
                               GL_RGBA32F);
            glDispatchCompute(groups, groups, 1);
            glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
        }
    }
    glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
    return 0;
}

int lc_shadow_apply(lc_renderer *r, lc_frame_setup *fs, lc_error *err)
{
    const lc_render_params *p = fs->params;
    if (!(p->style.shadow > 0) || !fs->context_color ||
        (p->method != LC_METHOD_FOURIER && p->method != LC_METHOD_DIRECT))
        return 0;
    shadow_state *st = state_of(r, err);
    if (!st)
        return LC_ERR_NOMEM;
    int bands = p->foo.bands, ntargets = (2 * bands + 1 + 3) / 4;
    ensure_targets(r, st, ntargets, fs->width, fs->height);

    lc_render_params lp = *p;
    lc_frame_setup light = *fs;
    light.params = &lp;
    light_view(fs, &lp, &light.view);
    light.width = light.height = light.low_width = light.low_height = SHADOW_MAP_SIZE;
    light.tiled = 0, light.depth_moments = 0, light.pixel_depth_range = 0;
    light.context_depth[0] = light.context_depth[1] = light.context_color = 0;
    int rc = light_pass(r, st, fs, &light, err);
    if (!rc)
        rc = blur_map(st, err);
    if (rc)
        return rc;

    GLuint *prog = &st->apply_prog[bands];
    if (!*prog) {
        static const char *const vs[] = {"fullscreen.vert.glsl", NULL};
        static const char *const fsrc[] = {"common.glsl", "coefficients.glsl", "shadow_apply.frag.glsl", NULL};
        char defines[64];
        snprintf(defines, sizeof defines, "#define BANDS %d\n", bands);
        if (!(*prog = lc_renderer_build_program(defines, vs, fsrc, NULL, "shadow apply", err)))
            return LC_ERR_GL;
    }
    double inv[16];
    if (!invert4(fs->view.view_proj, inv))
        return lc_err(err, LC_ERR_INVALID, "the camera's projection cannot be inverted");
    float invf[16];
    for (int i = 0; i < 16; i++)
        invf[i] = (float)inv[i];
    glUseProgram(*prog);
    glBindVertexArray(r->vao);
    glDisable(GL_DEPTH_TEST);
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, st->shadowed_fbo);
    glViewport(0, 0, fs->width, fs->height);
    lc_bind_coefficients(&st->coef);
    glBindTextureUnit(TEX_CONTEXT_DEPTH, fs->context_depth[0]);
    glBindTextureUnit(TEX_CONTEXT_COLOR, fs->context_color);
    glBindTextureUnit(TEX_SHADOW_COLOR, st->color.tex[0]);
    glProgramUniformMatrix4fv(*prog, glGetUniformLocation(*prog, "u_inv_view_proj"), 1, GL_FALSE, invf);
    glProgramUniformMatrix4fv(*prog, glGetUniformLocation(*prog, "u_light_view"), 1, GL_FALSE, light.view.view);
    glProgramUniformMatrix4fv(*prog, glGetUniformLocation(*prog, "u_light_view_proj"), 1, GL_FALSE,
                              light.view.view_proj);
    lc_uniform_v2(*prog, "u_light_depth", light.view.depth_min, light.view.depth_max);
    lc_uniform_f(*prog, "u_margin", p->foo.depth_margin);
    lc_uniform_v2(*prog, "u_target_size", fs->width, fs->height);
    lc_uniform_i(*prog, "u_map_size", SHADOW_MAP_SIZE);
    lc_uniform_f(*prog, "u_shadow", p->style.shadow);
    lc_uniform_i(*prog, "u_colored", p->style.shadow_colored ? 1 : 0);
    glDrawArrays(GL_TRIANGLES, 0, 3);
    glMemoryBarrier(GL_FRAMEBUFFER_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT);
    fs->context_color = st->shadowed;
    return 0;
}

void lc_shadow_destroy(lc_renderer *r)
{
    shadow_state *st = r->shadow;
    if (!st)
        return;
    lc_targets_free(&st->coef, &r->bytes_targets);
    lc_targets_free(&st->color, &r->bytes_targets);
    lc_targets_free(&st->blur, &r->bytes_targets);
    if (st->map_fbo)
        glDeleteFramebuffers(1, &st->map_fbo);
    if (st->shadowed) {
        glDeleteFramebuffers(1, &st->shadowed_fbo);
        glDeleteTextures(1, &st->shadowed);
        r->bytes_targets -= (uint64_t)st->w * st->h * 4;
    }
    if (st->ground_prog)
        glDeleteProgram(st->ground_prog);
    if (st->blur_prog)
        glDeleteProgram(st->blur_prog);
    for (int i = 0; i <= LC_MAX_BANDS; i++)
        if (st->apply_prog[i])
            glDeleteProgram(st->apply_prog[i]);
    free(st);
    r->shadow = NULL;
}
