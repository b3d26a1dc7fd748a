/* Fourier opacity optimization passes (docs/ALGORITHM.md): P0 per-pixel depth
 * range, P1 importance projection, P2 optimal opacity, P3 smoothing and
 * fading, P4 optical depth, P5 accumulation and P6 resolve. */
#include <string.h>

#include "foo_math.h"
#include "renderer_internal.h"

/* Elements from which P3's fade takes 16 an invocation (p3_smooth.comp.glsl). */
#define FADE_BATCH_MIN 65536u

/* P3's stages over one dataset's elements, from element `offset` on. */
static void smooth_layer(GLuint prog, const lc_gpu_scene *gs, uint32_t offset, int smoothing, lc_renderer *r)
{
    uint32_t count = gs->scene->elements.count;
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_ADJ_OFFSETS, gs->adj_offsets);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_ADJ, gs->adj);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_ADJ_WEIGHTS, gs->adj_weights);
    lc_uniform_u(prog, "u_count", count);
    lc_uniform_u(prog, "u_element_offset", offset);
    GLuint groups = (count + 255) / 256;
    GLuint src = r->smooth_a, dst = r->smooth_b;
    int iterations = smoothing > 0 && gs->scene->elements.adjacency_count > 0 ? smoothing : 0;
    if (iterations) {
        /* Stage 0 writes the targets into dst; then ping-pong. */
        lc_uniform_i(prog, "u_stage", 0);
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_SMOOTH_SRC, dst);
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_SMOOTH_DST, src);
        if (groups)
            lc_dispatch_linear(groups);
        glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
    }
    lc_uniform_i(prog, "u_stage", 1);
    for (int i = 0; i < iterations; i++) {
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_SMOOTH_SRC, src);
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_SMOOTH_DST, dst);
        if (groups)
            lc_dispatch_linear(groups);
        glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
        GLuint t = src;
        src = dst, dst = t;
    }
    /* Fading toward the smoothed targets, or toward the targets themselves
     * without smoothing (points, params.smoothing 0): one pass fewer. */
    lc_uniform_i(prog, "u_stage", iterations ? 2 : 3);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_SMOOTH_SRC, src);
    /* 16 elements an invocation where there are many (a million points: P3
     * 48 against 80 ms); on the MD file's 36,000 the batches' 9 work groups
     * took 14-26 ms against 9-11 with one element an invocation. */
    GLuint batch = count >= FADE_BATCH_MIN ? 16 : 1;
    lc_uniform_u(prog, "u_fade_batch", batch);
    if (groups)
        lc_dispatch_linear((groups + batch - 1) / batch);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
}

int lc_renderer_smooth_and_fade(lc_renderer *r, const lc_frame_setup *fs, lc_frame_state *state, double dt,
                                lc_frame_info *info, lc_error *err)
{
    GLuint prog = lc_renderer_fixed_program(r, PROG_P3, err);
    if (!prog)
        return LC_ERR_GL;
    int one_shot = !state || state->fresh;
    double fade = one_shot ? 1.0 : lc_foo_fade_factor(dt, fs->params->foo.fade_half_life);
    if (state && !state->fresh)
        lc_frame_state_upload(state, r->element_alpha);
    else {
        /* Unseen elements start at the target opacity (1 unless params.targetOpacity). */
        const float one = (float)lc_foo_target_opacity(&fs->params->foo);
        glClearNamedBufferData(r->element_alpha, GL_R32F, GL_RED, GL_FLOAT, &one);
    }
    const uint32_t zero = 0;
    glClearNamedBufferData(r->stats, GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, &zero);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);

    glUseProgram(prog);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_ELEMENT_ALPHA_MIN, r->element_alpha_min);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_ELEMENT_ALPHA, r->element_alpha);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_STATS, r->stats);
    lc_uniform_i(prog, "u_weighted", fs->params->foo.smoothing_weights == LC_SMOOTHING_DISTANCE);
    lc_uniform_f(prog, "u_omega", fs->params->foo.smoothing_weight);
    lc_uniform_f(prog, "u_fade", fade);
    /* Layers smooth one by one over their own adjacency: smoothing never
     * crosses layers. Hidden layers too, so that their elements fade. */
    int layers = fs->layer_count > 0 ? fs->layer_count : 1;
    for (int l = 0; l < layers; l++) {
        const lc_gpu_scene *gs = fs->layer_count > 0 ? fs->layers[l].gs : fs->gs;
        smooth_layer(prog, gs, fs->layer_count > 0 ? fs->layers[l].element_offset : 0, fs->params->foo.smoothing, r);
    }
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);

    if (state) {
        lc_frame_state_download(state, r->element_alpha);
        state->fresh = 0;
    }
    uint32_t bits[2] = {0, 0};
    glGetNamedBufferSubData(r->stats, 0, sizeof bits, bits);
    float change, gap;
    memcpy(&change, &bits[0], 4);
    memcpy(&gap, &bits[1], 4);
    if (info) {
        /* Converged when this frame's step was small, or when what is left
         * is: after a long pause (a still after release, dt of seconds) the
         * fade reaches the targets in one frame, and another frame at the
         * same view would only confirm it at the cost of a whole still. */
        info->max_alpha_change = one_shot ? 0.0 : change;
        info->converged = info->max_alpha_change < LC_CONVERGED_EPSILON || (!one_shot && gap < LC_CONVERGED_EPSILON);
    }
    return 0;
}

/* Draws the (z, -z) GL_MIN pass of P0 into one range target. */
static int draw_depth_range(lc_renderer *r, lc_frame_setup *fs, lc_targets *t, int w, int h, lc_error *err)
{
    lc_targets_ensure(t, w, h, 1, GL_RG32F, &r->bytes_targets);
    const float empty[4] = {1e30f, 1e30f, 0, 0};
    lc_targets_clear(t, empty);
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, t->fbo);
    for (int i = 0; i < lc_frame_layer_count(fs); i++) {
        lc_frame_setup tmp;
        const lc_frame_setup *lf = lc_frame_layer(fs, i, &tmp);
        if (!lf)
            continue;
        GLuint prog = lc_renderer_geometry_program(r, lf, PROG_DEPTH_RANGE, lf->gs->scene->type, 1, 1, err);
        if (!prog)
            return LC_ERR_GL;
        lc_renderer_bind_geometry(r, prog, lf, w, h, 1);
        lc_renderer_draw_geometry(lf, 1);
    }
    return 0;
}

/* P0: per-pixel depth ranges, drawn at both resolutions so that each pass sees
 * exactly the fragments its own rasterization produces (a range reduced from
 * full resolution misses thin geometry that is wider at the optimization
 * resolution, and a fragment outside its range would wrap to the periodic
 * ends). Afterwards every geometry pass normalizes depth by its pixel's range. */
int lc_fourier_depth_range(lc_renderer *r, lc_frame_setup *fs, int full, int low, lc_error *err)
{
    lc_progressive_pass(fs, LC_PASS_DEPTH_RANGE);
    if (fs->keep_sums) { /* params.progressive: the first batch's ranges, drawn over every primitive */
        fs->pixel_depth_range = 1;
        lc_renderer_timestamp(r, LC_PASS_DEPTH_RANGE);
        return 0;
    }
    glDisable(GL_DEPTH_TEST);
    glDisable(GL_CULL_FACE);
    glEnable(GL_BLEND);
    glBlendEquation(GL_MIN);
    fs->pixel_depth_range = 0; /* this pass itself uses nothing per pixel */
    int rc = full ? draw_depth_range(r, fs, &r->range_full, fs->width, fs->height, err) : 0;
    if (!rc && low)
        rc = draw_depth_range(r, fs, &r->range_low, fs->low_width, fs->low_height, err);
    glBlendEquation(GL_FUNC_ADD);
    if (rc)
        return rc;
    glMemoryBarrier(GL_FRAMEBUFFER_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT);
    rc = full ? lc_reduce_targets(r, &r->range_full, LC_REDUCE_MIN, 0, fs->info, err) : 0;
    if (rc || (low && (rc = lc_reduce_targets(r, &r->range_low, LC_REDUCE_MIN, 0, fs->info, err)) != 0))
        return rc;
    fs->pixel_depth_range = 1;
    lc_renderer_timestamp(r, LC_PASS_DEPTH_RANGE);
    return 0;
}

/* Draws prog additively at t's size with every subset-th primitive weighted
 * subset, into t unless the recording P0 (PROG_DEPTH_MOMENTS_LIST) has bound
 * its recording framebuffer (no target but its chain heads'). */
static int draw_layers(lc_renderer *r, lc_frame_setup *fs, lc_program_kind kind, int bands, int subset,
                       const lc_targets *t, lc_error *err)
{
    lc_additive_blending();
    if (kind != PROG_DEPTH_MOMENTS_LIST)
        glBindFramebuffer(GL_DRAW_FRAMEBUFFER, t->fbo);
    r->draw_yields = 1; /* P0 and P1: a yield point follows before anything keeps the sums */
    for (int i = 0; i < lc_frame_layer_count(fs); i++) {
        lc_frame_setup tmp;
        const lc_frame_setup *lf = lc_frame_layer(fs, i, &tmp);
        if (!lf)
            continue;
        GLuint prog = lc_renderer_geometry_program(r, lf, kind, lf->gs->scene->type, bands, subset, err);
        if (!prog)
            return LC_ERR_GL;
        lc_renderer_bind_geometry(r, prog, lf, t->width, t->height, subset);
        lc_uniform_f(prog, "u_weight", lc_renderer_weight(subset));
        if (kind == PROG_P1_LIST || kind == PROG_DEPTH_MOMENTS_LIST)
            lc_uniform_u(prog, "u_fragment_capacity", (unsigned)r->fragment_capacity);
        if (kind == PROG_DEPTH_MOMENTS_LIST) {
            lc_uniform_u(prog, "u_chain_pixels", r->chain_pixels);
            lc_uniform_u(prog, "u_chain_width", r->chain_width);
        }
        lc_renderer_draw_geometry(lf, subset);
    }
    r->draw_yields = 0;
    glMemoryBarrier(GL_FRAMEBUFFER_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT);
    return 0;
}

/* Draws prog into t (cleared) with draw_layers, then sums t over MPI ranks:
 * P0 "moments" and P1. A recording P0 writes no target: its moments come
 * from the list it recorded, or where that overflowed from P0 drawn again. */
static int draw_summed(lc_renderer *r, lc_frame_setup *fs, lc_program_kind kind, int bands, int subset, lc_targets *t,
                       lc_error *err)
{
    if (!fs->keep_sums) /* params.progressive adds a batch to the sums kept */
        lc_targets_clear(t, NULL);
    int rc = draw_layers(r, fs, kind, bands, subset, t, err);
    if (!rc && kind == PROG_DEPTH_MOMENTS_LIST) {
        lc_fragment_chains_end(r);
        /* Past the list's room (a view denser than the guess, after a drag):
         * P0 records again in a list of what it counted, which costs less
         * than drawing its moments and P1. */
        if (!r->fragments_chained && lc_fragment_chains_retry(r, fs, t->width, t->height) &&
            (rc = draw_layers(r, fs, kind, bands, subset, t, err)) == 0)
            lc_fragment_chains_end(r);
        if (!rc)
            rc = r->fragments_chained ? lc_fragment_chains_moments(r, t, err)
                                      : draw_layers(r, fs, PROG_DEPTH_MOMENTS, bands, subset, t, err);
        glBindFramebuffer(GL_DRAW_FRAMEBUFFER, t->fbo);
    }
    return rc ? rc : lc_reduce_targets(r, t, LC_REDUCE_SUM, 0, fs->info, err);
}

/* params.autoSubset (docs/ALGORITHM.md §10): P1 draws every n-th primitive,
 * weighted n, where P0 measured dense data. P0's first moment is what P1's
 * zeroth coefficient will be, a pixel's sum of g^2; its fourth channel holds
 * sum g^4, so N = (sum g^2)^2 / sum g^4 is the effective number of fragments
 * in the sum. Keeping each fragment with probability 1/n at weight n gives
 * the sum a relative standard deviation of sqrt((n - 1) / N), so
 * n <= 1 + N / 4 keeps it within 1/2 at the median covered pixel. The opacity
 * P2 derives from the sums is a ratio over the same pixel's sums and a
 * minimum over an element's many pixels, and on the MD trajectories a stride
 * of 4 measured SSIM against exact no lower than every primitive
 * (docs/EVALUATION.md, "The geometry path").
 * A stride below 4 is not taken: lines then draw segment by segment (six
 * vertices each, against two in a strip), which would cost more vertex work
 * than the stride saves. P4 keeps every primitive: its stride lowered SSIM.
 * Off by default (LC_AUTO_SUBSET_DEFAULT): on the MD trajectories it saves
 * 8-11 % of the frame on a quiet host (docs/EVALUATION.md, "The geometry path"), but a rank's
 * every n-th primitive is not the whole file's, so MPI frames would no
 * longer equal one process's; ranks skip it. */
static int choose_p1_subset(lc_renderer *r, lc_frame_setup *fs, lc_error *err)
{
    const lc_foo_params *foo = &fs->params->foo;
    fs->p1_subset = foo->subset;
    if (foo->subset > 1 || foo->auto_subset <= 1 || foo->normalize == LC_NORMALIZE_OFF) /* the paper's formula */
        return 0;
    if (r->desc.reducer) /* a rank's every n-th primitive is not the whole's: MPI must equal one process */
        return 0;
    double median = lc_moments_effective_median(r, r->moments.tex[0], fs->low_width, fs->low_height, err);
    if (median < 0)
        return LC_ERR_GL;
    int n = 1;
    while (2 * n <= foo->auto_subset && 2.0 * n <= 1.0 + median / 4.0)
        n *= 2;
    fs->p1_subset = n >= 4 ? n : 1;
    fs->info->p0_fragments_median = median;
    return 0;
}

/* P0 "moments": sum g^2 (1, u, u^2) per pixel at the optimization resolution
 * (docs/ALGORITHM.md "Depth normalization"), drawn with P1's subset and
 * weights, summed over MPI ranks like P1. Afterwards P1, P2, P4 and P5 warp
 * depth by it (series_depth in common.glsl). Where the frame allows, it
 * records its fragments for P1 (fragment_list.c), which the pass plan runs
 * in every frame that runs this one. */
int lc_fourier_depth_moments(lc_renderer *r, lc_frame_setup *fs, lc_error *err)
{
    lc_targets_ensure(&r->moments, fs->low_width, fs->low_height, 1, GL_RGBA32F, &r->bytes_targets);
    lc_progressive_pass(fs, LC_PASS_DEPTH_RANGE);
    if (fs->keep_sums) { /* params.progressive: the first batch's moments, drawn over every primitive */
        fs->p1_subset = 1, fs->p0_chained = 0, fs->depth_moments = 1;
        lc_renderer_timestamp(r, LC_PASS_DEPTH_RANGE);
        return 0;
    }
    fs->depth_moments = 0; /* this pass itself normalizes by the bounds */
    int record = lc_fragment_chains_wanted(r, fs);
    fs->p0_chained = 0;
    if (record)
        lc_fragment_chains_begin(r, fs, fs->low_width, fs->low_height);
    int rc = draw_summed(r, fs, record ? PROG_DEPTH_MOMENTS_LIST : PROG_DEPTH_MOMENTS, 1, fs->params->foo.subset,
                         &r->moments, err);
    if (!rc && record) {
        fs->p0_chained = r->fragments_chained;
        fs->p0_fragments = r->fragment_count; /* every fragment P0 offered, listed or not (P4's list's guess) */
    }
    if (rc || (rc = choose_p1_subset(r, fs, err)) != 0)
        return rc;
    fs->depth_moments = 1;
    lc_renderer_timestamp(r, LC_PASS_DEPTH_RANGE);
    return 0;
}

/* P2's uniforms (opacity_common.glsl), drawn or over P1's fragment list. */
static void set_opacity_uniforms(GLuint prog, const lc_render_params *p)
{
    lc_uniform_f(prog, "u_q", p->foo.q);
    lc_uniform_f(prog, "u_r", p->foo.r);
    lc_uniform_f(prog, "u_lambda", p->foo.lambda); /* the shader applies lc_foo_effective_lambda */
    lc_uniform_f(prog, "u_norm_mass", lc_foo_norm_mass(&p->foo));
    lc_uniform_i(prog, "u_estimator", p->foo.estimator == LC_ESTIMATOR_MIDPOINT ? 1 : 0);
    lc_uniform_f(prog, "u_target_opacity", lc_foo_target_opacity(&p->foo));
}

/* P3 smoothing and fading after P2, and the visibility report. */
static int smooth_and_report(lc_renderer *r, lc_frame_setup *fs, lc_frame_state *state, double dt, lc_frame_info *info,
                             lc_error *err)
{
    lc_mass_report(r, fs, info);
    int rc = lc_renderer_smooth_and_fade(r, fs, state, dt, info, err);
    if (!rc) /* layered frames: per layer and over the transparent layers together */
        rc = lc_visibility_measure(r, fs, state ? state->alpha : NULL, info, err);
    lc_renderer_timestamp(r, LC_PASS_SMOOTH);
    return rc;
}

/* After P2, drawn or over the fragment list: the opacities combined across
 * ranks, then P3 and the report. */
static int finish_opacities(lc_renderer *r, lc_frame_setup *fs, lc_frame_state *state, double dt, lc_frame_info *info,
                            lc_error *err)
{
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
    int rc = lc_reduce_element_minima(r, fs->element_total, fs->info, err);
    if (rc)
        return rc;
    lc_renderer_timestamp(r, LC_PASS_OPACITY);
    if ((rc = lc_renderer_yield_point(r, err)) != 0)
        return rc;
    return smooth_and_report(r, fs, state, dt, info, err);
}

/* P1 + P2 (+ P3): element opacities for the frame. */
int lc_fourier_optimize(lc_renderer *r, lc_frame_setup *fs, lc_frame_state *state, double dt, lc_frame_info *info,
                        lc_error *err)
{
    const lc_render_params *p = fs->params;
    int bands = p->foo.bands, ntargets = (2 * bands + 1 + 3) / 4;
    int lw = fs->low_width, lh = fs->low_height;
    lc_targets_ensure(&r->coef_low, lw, lh, ntargets, GL_RGBA32F, &r->bytes_targets);

    /* P1 importance projection, once a frame: its sums do not depend on the
     * strength (lambda, q, r) that the clarity loop's tries change. */
    info->p1_subset = fs->p1_subset > 0 ? fs->p1_subset : p->foo.subset;
    int rc = 0;
    if (!fs->p1_done) {
        /* P1 over P0's fragments where P0 recorded them, else drawn, recording
         * its fragments for P2 where that is allowed (fragment_list.c). */
        lc_progressive_pass(fs, LC_PASS_IMPORTANCE);
        int chained = fs->p0_chained && r->fragments_chained && info->p1_subset <= 1 && !fs->batch_count;
        /* params.progressive: a batch's P1 appends to the list of the batches before (fragment_list.c). */
        int record =
            !chained && lc_fragment_list_wanted(r, info->p1_subset) && (!fs->keep_sums || r->progressive_listed);
        r->progressive_listed = record;
        info->importance_from_list = chained;
        fs->p0_chained = 0;
        r->fragments_ready = 0;
        if (chained) {
            lc_targets_clear(&r->coef_low, NULL);
            rc = lc_fragment_chains_p1(r, fs, &r->coef_low, bands, err);
            if (!rc)
                rc = lc_reduce_targets(r, &r->coef_low, LC_REDUCE_SUM, 0, fs->info, err);
        } else {
            r->fragments_chained = 0;
            if (record && fs->keep_sums)
                lc_fragment_list_resume(r);
            else if (record)
                lc_fragment_list_begin(r, fs);
            rc = draw_summed(r, fs, record ? PROG_P1_LIST : PROG_P1, bands, info->p1_subset, &r->coef_low, err);
        }
        if (!rc && record)
            lc_fragment_list_end(r);
        if (rc || (rc = lc_mass_histogram_fourier(r, fs, err)) != 0)
            return rc;
        fs->p1_done = 1;
        info->importance_passes++;
        /* Stamped only when P1 ran: the clarity loop's later tries would
         * otherwise restart P1's slot after the earlier tries' P2 and P3, and
         * report their time as P1's. "opacity" then spans every try's P2. */
        lc_renderer_timestamp(r, LC_PASS_IMPORTANCE);
    }
    if ((rc = lc_renderer_yield_point(r, err)) != 0)
        return rc;

    /* P2 optimal opacity into the element minimum buffer: over P1's
     * fragment list when P1 recorded one, else drawn. The element
     * importance of its emphasis on patches (a dispatch of its own, once per
     * mapping) comes first; layered frames go without (it ranks one
     * dataset's elements, as the visibility report does). */
    lc_progressive_pass(fs, LC_PASS_OPACITY);
    /* params.progressive: P1's list holds every fragment of the batches so far
     * (it appends), so P2 over it gives every element that has arrived its
     * opacity against the sums so far, the minima cleared; without a list
     * (one that overflowed, GPUs) batch k's elements are drawn into the kept
     * minima (progressive.c). */
    if (r->fragments_ready && p->foo.progressive > 1)
        fs->keep_sums = fs->batch_count = 0;
    GLuint listed = r->fragments_ready ? lc_fragment_list_program(r, bands, err) : 0;
    if (r->fragments_ready && !listed)
        return LC_ERR_GL;
    info->opacity_from_list = listed != 0;
    if (!fs->layer_count) {
        GLuint p2 = listed ? listed : lc_renderer_geometry_program(r, fs, PROG_P2, fs->gs->scene->type, bands, 1, err);
        if (!p2)
            return LC_ERR_GL;
        if ((rc = lc_element_emphasis_bind(r, fs, p2, err)) != 0)
            return rc;
    }
    const float sentinel = 2.0f; /* > 1: "no fragment this frame" */
    if (!fs->keep_sums)          /* params.progressive: the elements of earlier batches keep their minima */
        glClearNamedBufferData(r->element_alpha_min, GL_R32F, GL_RED, GL_FLOAT, &sentinel);
    lc_occluders_clear(r);
    glMemoryBarrier(GL_FRAMEBUFFER_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT |
                    GL_SHADER_STORAGE_BARRIER_BIT);
    if (listed) {
        if (fs->layer_count) {
            glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_ELEMENT_G, r->dummy_buffer);
            lc_uniform_i(listed, "u_element_emphasis", 0);
        }
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_ELEMENT_ALPHA_MIN, r->element_alpha_min);
        lc_bind_coefficients(&r->coef_low);
        set_opacity_uniforms(listed, p);
        lc_fragment_list_dispatch(r, listed);
        return finish_opacities(r, fs, state, dt, info, err);
    }
    glDisable(GL_BLEND);
    if (r->nofb_w != lw || r->nofb_h != lh) {
        glNamedFramebufferParameteri(r->nofb, GL_FRAMEBUFFER_DEFAULT_WIDTH, lw);
        glNamedFramebufferParameteri(r->nofb, GL_FRAMEBUFFER_DEFAULT_HEIGHT, lh);
        r->nofb_w = lw, r->nofb_h = lh;
    }
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, r->nofb);
    r->draw_yields = 1; /* the yield point after P2 comes before P3 keeps anything */
    for (int i = 0; i < lc_frame_layer_count(fs); i++) {
        lc_frame_setup tmp;
        const lc_frame_setup *lf = lc_frame_layer(fs, i, &tmp);
        if (!lf)
            continue;
        GLuint p2 = lc_renderer_geometry_program(r, lf, PROG_P2, lf->gs->scene->type, bands, 1, err);
        if (!p2)
            return LC_ERR_GL;
        lc_renderer_bind_geometry(r, p2, lf, lw, lh, 1);
        if (fs->layer_count) {
            glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_ELEMENT_G, r->dummy_buffer);
            lc_uniform_i(p2, "u_element_emphasis", 0);
        }
        lc_bind_coefficients(&r->coef_low);
        set_opacity_uniforms(p2, p);
        lc_renderer_draw_geometry(lf, 1);
    }
    r->draw_yields = 0;
    return finish_opacities(r, fs, state, dt, info, err);
}

/* P4's uniforms beyond the geometry's, drawn or computed (kanzler: its maps' binding and weights). */
static void set_p4_uniforms(GLuint prog, lc_renderer *r, const lc_frame_setup *lf, int subset, int kanzler)
{
    lc_uniform_f(prog, "u_weight", lc_renderer_weight(subset));
    lc_renderer_bind_direct_alpha(prog, lf->params);
    if (kanzler)
        lc_kanzler_bind(r, prog, &lf->params->foo);
    lc_renderer_bind_halo(prog, lf);
}

/* P5's, drawn or computed: it reads P4's sums at full resolution. */
static void set_p5_uniforms(GLuint prog, lc_renderer *r, const lc_frame_setup *lf, int kanzler)
{
    lc_bind_coefficients(&r->coef_full);
    lc_uniform_i(prog, "u_estimator", lf->params->foo.estimator == LC_ESTIMATOR_MIDPOINT ? 1 : 0);
    lc_uniform_f(prog, "u_reach_g", r->reach_g);
    lc_renderer_bind_direct_alpha(prog, lf->params);
    if (kanzler)
        lc_kanzler_bind(r, prog, &lf->params->foo);
    lc_renderer_bind_halo(prog, lf);
}

/* Which path P4 or P5 took this frame (lc_frame_info.computed_passes). */
static void info_paths(lc_frame_setup *fs, lc_raster_pass pass, int computed)
{
    if (fs->info && computed)
        fs->info->computed_passes |= 1 << pass;
}

/* P4 or P5 through the compute rasterizer (compute_raster.c): `planes` sums
 * per pixel of t, stored into t's targets once every primitive is in. */
static int compute_pass(lc_renderer *r, lc_frame_setup *fs, lc_program_kind kind, lc_targets *t, int planes, int subset,
                        lc_error *err)
{
    int rc = lc_compute_raster_begin(r, t->width, t->height, planes, err);
    GLuint prog = rc ? 0 : lc_compute_raster_program(r, kind, fs->gs->scene->type, fs->params->foo.bands, err);
    if (!prog)
        return rc ? rc : LC_ERR_GL;
    lc_compute_raster_bind(r, prog, fs, subset);
    if (kind == PROG_P4 || kind == PROG_P4_DIRECT)
        set_p4_uniforms(prog, r, fs, subset, 0);
    else
        set_p5_uniforms(prog, r, fs, 0);
    lc_compute_raster_dispatch(r, prog, fs, subset);
    return fs->keep_sums ? lc_compute_raster_end_add(r, t, err) : lc_compute_raster_end(r, t, err);
}

/* P4 drawn with program kind over the frame's layers (PROG_P4_LIST records its fragments). */
static int draw_p4(lc_renderer *r, lc_frame_setup *fs, lc_program_kind kind, int kanzler, lc_error *err)
{
    const lc_render_params *p = fs->params;
    for (int i = 0; i < lc_frame_layer_count(fs); i++) {
        lc_frame_setup tmp;
        const lc_frame_setup *lf = lc_frame_layer(fs, i, &tmp);
        if (!lf)
            continue;
        GLuint p4 =
            lc_renderer_geometry_program(r, lf, kind, lf->gs->scene->type,
                                         kind == PROG_P4_BINS ? LC_TAU_BINS_BANDS : p->foo.bands, p->foo.subset, err);
        if (!p4)
            return LC_ERR_GL;
        lc_renderer_bind_geometry(r, p4, lf, fs->width, fs->height, p->foo.subset);
        set_p4_uniforms(p4, r, lf, p->foo.subset, kanzler);
        if (kind == PROG_P4_LIST) {
            lc_uniform_u(p4, "u_composite_capacity", (unsigned)r->composite_capacity);
            lc_uniform_u(p4, "u_chain_pixels", r->chain_pixels);
            lc_uniform_u(p4, "u_chain_width", r->chain_width);
        }
        lc_renderer_draw_geometry(lf, p->foo.subset);
    }
    return 0;
}

/* P4..P6 with the element opacities, the direct baseline's (params.alphaSource),
 * or, kanzler, g^k times Kanzler's penalty on this frame's maps (drawn first,
 * so that every antialias sample has maps of its own view); bins: the binning
 * baseline's depth bins in place of the series (their total in the first
 * channel, where P6 reads A0). */
static int composite_series(lc_renderer *r, lc_frame_setup *fs, int direct, int bins, lc_error *err)
{
    const lc_render_params *p = fs->params;
    int kanzler = direct == LC_ALPHA_KANZLER;
    if (kanzler) {
        int rc = lc_kanzler_maps(r, fs, err);
        if (rc)
            return rc;
    }
    int bands = bins ? LC_TAU_BINS_BANDS : p->foo.bands, ntargets = (2 * bands + 1 + 3) / 4;
    lc_program_kind kind4 = bins ? PROG_P4_BINS : kanzler ? PROG_P4_KANZLER : direct ? PROG_P4_DIRECT : PROG_P4;
    lc_program_kind kind5 = bins ? PROG_P5_BINS : kanzler ? PROG_P5_KANZLER : direct ? PROG_P5_DIRECT : PROG_P5;
    lc_targets_ensure(&r->coef_full, fs->width, fs->height, ntargets, GL_RGBA32F, &r->bytes_targets);
    /* Half floats suffice for the weighted sums: the image is their ratio. */
    lc_targets_ensure(&r->accum, fs->width, fs->height, 1, GL_RGBA16F, &r->bytes_targets);
    lc_progressive_pass(fs, LC_PASS_OPTICAL_DEPTH); /* P5 draws the same batches */
    if (!fs->keep_sums) {                           /* params.progressive adds a batch to the sums kept */
        lc_targets_clear(&r->coef_full, NULL);
        lc_targets_clear(&r->accum, NULL);
    }

    lc_additive_blending();
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, r->coef_full.fbo);
    r->draw_yields = 1; /* P4 and P5: yield points follow, and the image is all they make */
    /* The compute rasterizer has the series and the direct opacities but no depth bins, Kanzler maps or
     * screen-space derivatives (alphaSource normalVariation): those draw. */
    int computable = !bins && !kanzler && !(direct && p->foo.alpha_source == LC_ALPHA_NORMAL_VARIATION);
    /* params.progressive: a batch of points is a range of splats in both paths,
     * so it may compute (adding to the kept sums); a batch of lines is whole
     * strip runs when drawn and ribbon slots when computed, so it draws. */
    computable = computable && (!fs->batch_count || fs->gs->scene->type == LC_PRIM_POINTS);
    /* A drawn P4 records what its sums and P5 need of its fragments where the
     * frame allows (fragment_list.c); the rule then draws it, points too. */
    int listable = !bins && !fs->batch_count && lc_composite_list_wanted(fs, direct);
    int computed = computable && lc_compute_raster_wanted(r, fs, LC_RASTER_P4, listable);
    int record = !computed && listable;
    if (record)
        lc_composite_list_begin(r, fs);
    info_paths(fs, LC_RASTER_P4, computed);
    if (computed) {
        int rc =
            compute_pass(r, fs, direct ? PROG_P4_DIRECT : PROG_P4, &r->coef_full, 2 * bands + 1, p->foo.subset, err);
        if (rc)
            return rc;
    }
    /* The recording P4 draws into a framebuffer of no target (lc_composite_list_begin): its sums come from the list.
     * A drawn one counts its fragments for the next frame's P0 (lc_fragment_hint_begin). */
    int counting = !computed && !record && lc_fragment_hint_begin(r, fs);
    int rc = computed ? 0 : draw_p4(r, fs, record ? PROG_P4_LIST : kind4, kanzler, err);
    if (counting)
        lc_fragment_hint_end();
    if (record)
        glBindFramebuffer(GL_DRAW_FRAMEBUFFER, r->coef_full.fbo);
    int listed = !rc && record && lc_composite_list_end(r, fs);
    /* Past the list's room: P4 records again in a list of what it counted
     * (drawing P4 and P5 instead would cost about twice as much). */
    if (!rc && record && !listed && lc_composite_list_retry(r, fs)) {
        rc = draw_p4(r, fs, PROG_P4_LIST, kanzler, err);
        glBindFramebuffer(GL_DRAW_FRAMEBUFFER, r->coef_full.fbo);
        listed = !rc && lc_composite_list_end(r, fs);
    }
    if (fs->info)
        fs->info->composite_from_list = listed;
    if (!rc && listed) /* (nothing with one process: P5's walk makes the sums) */
        rc = lc_composite_list_p4(r, fs, &r->coef_full, err);
    else if (!rc && record) /* past the list's room: P4 draws its sums after all */
        rc = draw_p4(r, fs, kind4, kanzler, err);
    if (rc)
        return rc;
    if ((rc = lc_reduce_targets(r, &r->coef_full, LC_REDUCE_SUM, 0, fs->info, err)) != 0)
        return rc;
    lc_renderer_timestamp(r, LC_PASS_OPTICAL_DEPTH);
    if ((rc = lc_renderer_yield_point(r, err)) != 0)
        return rc;

    glMemoryBarrier(GL_FRAMEBUFFER_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, r->accum.fbo);
    /* topDecileReach: the optimized opacities' P5 (not the baselines' or the bins'). */
    int reach = !direct && !bins && !fs->batch_count; /* (not over one batch of params.progressive) */
    int p5_computed = computable && !listed && lc_compute_raster_wanted(r, fs, LC_RASTER_P5, 0);
    if (reach)
        lc_reach_begin(r, fs, !p5_computed); /* the list's P5 sums per pixel as the drawn one */
    else if (fs->batch_count)
        r->reach_g = 2.0f; /* > 1: P5 measures nothing */
    if (listed && (rc = lc_composite_list_p5(r, fs, &r->coef_full, &r->accum, err)) != 0)
        return rc;
    info_paths(fs, LC_RASTER_P5, p5_computed);
    if (p5_computed && (rc = compute_pass(r, fs, direct ? PROG_P5_DIRECT : PROG_P5, &r->accum, 4, 1, err)) != 0)
        return rc;
    for (int i = 0; i < lc_frame_layer_count(fs) && !listed && !p5_computed; i++) {
        lc_frame_setup tmp;
        const lc_frame_setup *lf = lc_frame_layer(fs, i, &tmp);
        if (!lf)
            continue;
        GLuint p5 = lc_renderer_geometry_program(r, lf, kind5, lf->gs->scene->type, bands, 1, err);
        if (!p5)
            return LC_ERR_GL;
        lc_renderer_bind_geometry(r, p5, lf, fs->width, fs->height, 1);
        set_p5_uniforms(p5, r, lf, kanzler);
        lc_renderer_draw_geometry(lf, 1);
    }
    r->draw_yields = 0;
    if (reach && (rc = lc_reach_end(r, fs, err)) != 0)
        return rc;
    /* color.equalize's histogram pass needs every pixel's sum w on every process. */
    int root_only = fs->params->color.equalize ? 0 : 1;
    if ((rc = lc_reduce_targets(r, &r->accum, LC_REDUCE_SUM, root_only, fs->info, err)) != 0)
        return rc;
    lc_renderer_timestamp(r, LC_PASS_ACCUMULATE);
    if ((rc = lc_renderer_yield_point(r, err)) != 0)
        return rc;

    glMemoryBarrier(GL_FRAMEBUFFER_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT);
    lc_renderer_resolve(r, fs, PROG_RESOLVE, &r->accum, r->coef_full.tex[0], err);
    /* style.smartTransparency over the resolved image, from P4's sums (smart.c). */
    if ((rc = lc_smart_apply(r, fs, err)) != 0)
        return rc;
    lc_renderer_timestamp(r, LC_PASS_RESOLVE);
    return 0;
}

int lc_fourier_composite(lc_renderer *r, lc_frame_setup *fs, int direct, lc_error *err)
{
    return composite_series(r, fs, direct, 0, err);
}

int lc_binning_composite(lc_renderer *r, lc_frame_setup *fs, lc_error *err)
{
    return composite_series(r, fs, 0, 1, err);
}
