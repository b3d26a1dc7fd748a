/* params.clarity (docs/ALGORITHM.md §25): a closed loop on the strength of the
 * optimization. λ, and q and r together, are scaled by factors >= 1 until the
 * frame's visibility report says the important elements reach the target
 * opacity and the unimportant ones that hide them have faded; one-shot frames
 * (and a session's first) try a few strengths at the optimization resolution
 * (P1-P3 each), a session's later frames take one step each (fading smooths it). */
#include <math.h>

#include "renderer_internal.h"

int lc_clarity_active(const lc_render_params *p)
{
    const lc_foo_params *f = &p->foo;
    return f->clarity > 0 && f->normalize == LC_NORMALIZE_AUTO && !f->strength_given &&
           (p->method == LC_METHOD_FOURIER || p->method == LC_METHOD_WBOIT || p->method == LC_METHOD_EXACT);
}

double lc_clarity_miss(double target, const lc_frame_info *info)
{
    if (!info->has_visibility || info->visible_elements < 10)
        return 0;
    double t = info->top_decile_alpha > 0.01 ? info->top_decile_alpha : 0.01;
    double miss = fmax(target / t, info->occluder_alpha / (0.5 * t));
    miss = fmax(miss, (info->bottom_half_alpha - 0.05) / t);
    return miss > 1 ? miss - 1 : 0;
}

void lc_clarity_next(lc_clarity_strength *st, double target, const lc_frame_info *info, double max_step)
{
    if (!info->has_visibility || info->visible_elements < 10)
        return;
    double t = info->top_decile_alpha > 0.01 ? info->top_decile_alpha : 0.01;
    /* How far each goal is from being met, as a ratio > 1 when it is not. The
     * top decile below the target asks for more emphasis (λ); occluders above
     * half of it, or the least important half above the top decile (an
     * inversion), for a stronger penalty (q and r), which lowers the top
     * decile too, so λ follows. */
    /* Aimed a little past the goal (+0.05, 0.45), so that the last steps are
     * not vanishingly small. */
    double need_top = (target + 0.05) / t;
    double need_occ = info->occluder_alpha / (0.45 * t);
    if (info->bottom_half_alpha - 0.05 > t)
        need_occ = fmax(need_occ, info->bottom_half_alpha / t);
    double up = need_occ > 1 ? fmin(pow(need_occ, 1.5), max_step * max_step) : 1;
    /* λ follows the penalty only as far as the top decile needs: above its
     * aim it has room to drop, and more λ would lift the occluders with it. */
    double lift = (up > 1 ? need_top : fmax(need_top, 1)) * sqrt(up);
    double step = lift > 1 ? fmin(lift, max_step) : 1;
    /* Well past the goal: ease off, toward the paper's strength. */
    if (lift <= 1 && t > target + 0.2 && info->occluder_alpha < 0.4 * t) {
        step = fmax(pow(target / t, 0.7), 1.0 / max_step);
        up = fmax(step * step, 1.0 / (max_step * max_step));
    }
    st->lambda = fmin(fmax(st->lambda * step, 1), LC_CLARITY_MAX_STRENGTH);
    st->penalty = fmin(fmax(st->penalty * up, 1), LC_CLARITY_MAX_STRENGTH * LC_CLARITY_MAX_STRENGTH);
}

/* One optimization at strength st (p: the frame's parameters it scales). */
static int try_strength(lc_renderer *r, lc_frame_setup *fs, lc_render_params *p, const lc_render_params *given,
                        lc_clarity_strength st, lc_frame_state *state, double dt, lc_frame_info *info, int moments,
                        lc_clarity_step optimize, lc_error *err)
{
    p->foo.lambda = given->foo.lambda * st.lambda;
    p->foo.q = given->foo.q * st.penalty;
    p->foo.r = given->foo.r * st.penalty;
    int rc = optimize(r, fs, state, dt, info, moments, err);
    info->clarity_tries++;
    info->clarity_lambda = st.lambda;
    info->clarity_penalty = st.penalty;
    return rc;
}

int lc_clarity_optimize(lc_renderer *r, lc_frame_setup *fs, lc_frame_state *state, double dt, lc_frame_info *info,
                        int moments, lc_clarity_step optimize, lc_error *err)
{
    const lc_render_params *given = fs->params;
    if (!lc_clarity_active(given))
        return optimize(r, fs, state, dt, info, moments, err);
    lc_render_params p = *given;
    double target = p.foo.clarity;
    lc_clarity_strength st = {1, 1, 0, -1};
    /* A session's still settles as the one-shot render of its request does:
     * the strength the moving frames stepped to came from other pictures (a
     * coarse first frame, thinned lines), and one gentle step a frame would
     * stop wherever the opacities converge. */
    if (given->detail.still && state && !state->fresh) {
        int eq_valid = state->eq_valid; /* the colour map keeps its own half-life */
        lc_frame_state_reset(state);
        state->eq_valid = eq_valid;
    }
    if (state && !state->fresh && state->clarity.lambda >= 1 && state->clarity.penalty >= 1)
        st = state->clarity;
    int iterate = !state || state->fresh;
    fs->params = &p;
    lc_clarity_strength best = st;
    double best_miss = -1;
    int rc = 0;
    for (int i = 0;; i++) {
        if (i > 0 && state)
            lc_frame_state_reset(state); /* each try takes its targets whole, as a first frame does */
        if ((rc = try_strength(r, fs, &p, given, st, state, dt, info, moments, optimize, err)) != 0)
            break;
        double miss = lc_clarity_miss(target, info);
        /* A step that did not bring the goal nearer stops the loop: data
         * whose unimportant elements hide nothing (sparse points) or whose
         * importance points the wrong way cannot be helped by strength, and
         * the picture keeps the strength that came closest. */
        int stalled = best_miss >= 0 && miss > 0.95 * best_miss;
        if (best_miss < 0 || miss < best_miss)
            best = st, best_miss = miss;
        lc_clarity_strength next = st;
        if (!iterate) {
            /* A session's frame: one gentle step for the next frame, unless
             * the last one did not help (its fading smooths the steps). */
            if (!st.stalled && st.miss > 0 && miss > 0.95 * st.miss && (st.lambda > 1 || st.penalty > 1))
                next.stalled = 1;
            else if (!st.stalled)
                lc_clarity_next(&next, target, info, 1.25);
            next.miss = miss;
            st = next;
            break;
        }
        lc_clarity_next(&next, target, info, 3.0);
        int same = next.lambda == st.lambda && next.penalty == st.penalty;
        if (miss == 0 || same || stalled || i + 1 == LC_CLARITY_ITERATIONS) {
            if (best.lambda != st.lambda || best.penalty != st.penalty) { /* the last try was not the best: redo it */
                if (state)
                    lc_frame_state_reset(state);
                st = best;
                rc = try_strength(r, fs, &p, given, st, state, dt, info, moments, optimize, err);
            }
            st.stalled = stalled;
            st.miss = best_miss;
            break;
        }
        st = next;
    }
    fs->params = given;
    info->clarity_reached = rc == 0 && lc_clarity_miss(target, info) == 0;
    if (state)
        state->clarity = st;
    return rc;
}
