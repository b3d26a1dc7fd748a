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
           (p->method == LC_METHOD_FOURIER || p->method == LC_METHOD_WBOIT || p->method == LC_METHOD_EXACT ||
            p->method == LC_METHOD_WEIGHTED_AVERAGE || p->method == LC_METHOD_BINNING);
}

static double miss_of(double target, double top, double bottom, double occluder)
{
    double t = top > 0.01 ? top : 0.01;
    double miss = fmax(target / t, occluder / (0.5 * t));
    miss = fmax(miss, (bottom - 0.05) / t);
    return miss > 1 ? miss - 1 : 0;
}

double lc_clarity_miss(double target, const lc_frame_info *info)
{
    if (!info->has_visibility || info->visible_elements < 10)
        return 0;
    return miss_of(target, info->top_decile_alpha, info->bottom_half_alpha, info->occluder_alpha);
}

/* Whether P3's smoothing is what keeps the frame from the goal: P2's own
 * opacities, before smoothing, come at least twice as near. Smoothing
 * averages an element's opacity with its neighbours' along the line; where
 * importance changes from one element to the next (a grain that falls, then
 * rests in the pile; an atom's speed), it gives the fast moments the opacity
 * of the slow ones and the slow ones the opacity of the fast ones. */
static int smoothing_costs(double target, const lc_frame_info *info, double miss)
{
    if (!info->has_visibility || info->visible_elements < 10 || miss <= 0)
        return 0;
    return miss_of(target, info->raw_top_decile_alpha, info->raw_bottom_half_alpha, info->raw_occluder_alpha) <
           0.5 * miss;
}

/* gain: how steeply the top decile answers the emphasis, measured by the last
 * two tries (1 when unknown): the step toward the top decile's aim is the aim's
 * ratio to the power 1/gain. */
static void next_strength(lc_clarity_strength *st, double target, const lc_frame_info *info, double max_step,
                          double gain, double fade)
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
    /* fade: how much the occluders' share o/t answered the penalty between the
     * last two tries (d ln(o/t) / d ln b, negated; 0 when unknown): where it is
     * weak (dense lines, 0.2), the step is the one that answer asks for. */
    double up = 1;
    if (need_occ > 1)
        up = fmin(fmax(pow(need_occ, 1.5), fade > 0.05 ? pow(need_occ, 1 / fade) : 1), max_step * max_step);
    /* No more than the cap leaves (λ must not make up for a penalty not applied). */
    up = fmax(fmin(up, LC_CLARITY_MAX_STRENGTH * LC_CLARITY_MAX_STRENGTH / st->penalty), 1);
    /* λ follows the penalty only as far as the top decile needs: above its
     * aim it has room to drop and keeps λ (more would lift the occluders with
     * it); below, λ makes up for the stronger penalty. */
    double lift = pow(up > 1 ? (need_top < 1 ? 1 : need_top * sqrt(up)) : fmax(need_top, 1), 1 / gain);
    double step = lift > 1 ? fmin(lift, max_step) : 1;
    /* Well past the goal: ease off, toward the paper's strength. */
    if (lift <= 1 && t > target + 0.2 && info->occluder_alpha < 0.4 * t) {
        step = fmax(pow(target / t, 0.7), 1.0 / max_step);
        up = fmax(step * step, 1.0 / (max_step * max_step));
    }
    st->lambda = fmin(fmax(st->lambda * step, 1), LC_CLARITY_MAX_STRENGTH);
    st->penalty = fmin(fmax(st->penalty * up, 1), LC_CLARITY_MAX_STRENGTH * LC_CLARITY_MAX_STRENGTH);
}

void lc_clarity_next(lc_clarity_strength *st, double target, const lc_frame_info *info, double max_step)
{
    next_strength(st, target, info, max_step, 1, 0);
}

/* The top decile's answer to the strength between two tries: d ln t / d ln(a / √b),
 * the drive the step assumes (a follows b by √(b's step)); 1 when the tries
 * say nothing, at most 4. On dense data the answer is steep (ka_liquid: t 0.25
 * at (3, 2.8), 0.85 at (7.3, 3.5)), and an undamped step overshoots into a
 * picture where everything is opaque. */
static double top_gain(lc_clarity_strength a0, double t0, lc_clarity_strength a1, double t1)
{
    double drive = log(a1.lambda / a0.lambda) - 0.5 * log(a1.penalty / a0.penalty);
    if (t0 < 0.01 || t1 < 0.01 || fabs(drive) < 0.05)
        return 1;
    double g = log(t1 / t0) / drive;
    return g > 1 ? fmin(g, 4) : 1;
}

/* One optimization at strength st (p: the frame's parameters it scales). */
static int try_strength(lc_renderer *r, lc_frame_setup *fs, lc_render_params *p, const lc_render_params *given,
                        lc_clarity_strength st, lc_frame_state *state, double dt, lc_frame_info *info, int moments,
                        lc_clarity_step optimize, lc_error *err)
{
    p->foo.lambda = given->foo.lambda * st.lambda;
    p->foo.q = given->foo.q * st.penalty;
    p->foo.r = given->foo.r * st.penalty;
    p->foo.smoothing = (int)(given->foo.smoothing * st.smoothing);
    /* Beyond the paper's strength, a line's fragments take its element's mean
     * importance in the emphasis (docs/ALGORITHM.md §25): noise-like importance
     * (speed in a liquid) varies along each element, and its opacity, its
     * least emphasized fragment's, followed the element's slowest moment. */
    p->foo.element_emphasis = st.lambda > 1 || st.penalty > 1;
    int rc = optimize(r, fs, state, dt, info, moments, err);
    info->clarity_tries++;
    info->clarity_lambda = st.lambda;
    info->clarity_penalty = st.penalty;
    info->clarity_smoothing = p->foo.smoothing;
    info->clarity_smoothing_cut = p->foo.smoothing < given->foo.smoothing;
    return rc;
}

int lc_clarity_optimize(lc_renderer *r, lc_frame_setup *fs, lc_frame_state *state, double dt, lc_frame_info *info,
                        int moments, lc_clarity_step optimize, lc_error *err)
{
    const lc_render_params *given = fs->params;
    /* params.progressive (progressive.c): a batch before the last adds its
     * elements' minima to the kept ones, which a second try would mix with
     * the first's; those frames run the paper's strength once, and the last
     * batch, whose P2 covers every primitive, runs the loop as a one-shot
     * frame does. */
    int batch = given->foo.progressive > 1 && given->foo.batch > 0 && given->foo.batch < given->foo.progressive &&
                !given->foo.batch_prefix;
    if (!lc_clarity_active(given) || batch)
        return optimize(r, fs, state, dt, info, moments, err);
    lc_render_params p = *given;
    double target = p.foo.clarity;
    lc_clarity_strength st = {1, 1, 0, -1, 1};
    /* A session's still settles as the one-shot render of its request does:
     * the strength the moving frames stepped to came from other pictures (a
     * coarse first frame, thinned lines), and one gentle step a frame would
     * stop wherever the opacities converge. */
    if (given->detail.still && state && !state->fresh) {
        int eq_valid[LC_MAX_LAYERS]; /* the colour maps keep their own half-life */
        for (int i = 0; i < LC_MAX_LAYERS; i++)
            eq_valid[i] = state->eq[i].valid;
        lc_frame_state_reset(state);
        for (int i = 0; i < LC_MAX_LAYERS; i++)
            state->eq[i].valid = eq_valid[i];
    }
    if (state && !state->fresh && state->clarity.lambda >= 1 && state->clarity.penalty >= 1 &&
        state->clarity.smoothing > 0)
        st = state->clarity;
    int iterate = !state || state->fresh;
    fs->params = &p;
    lc_clarity_strength best = st;
    double best_miss = -1;
    lc_clarity_strength prev = st;
    double prev_top = 0, prev_share = 0;
    int rc = 0;
    int smoothing_steps = 0; /* tries that only halved the smoothing: not counted in LC_CLARITY_ITERATIONS */
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
        double gain = i > 0 ? top_gain(prev, prev_top, st, info->top_decile_alpha) : 1;
        double share = info->occluder_alpha / fmax(info->top_decile_alpha, 0.01), fade = 0;
        if (i > 0 && prev_share > 0 && share > 0 && fabs(log(st.penalty / prev.penalty)) > 0.05)
            fade = fmin(fmax(-log(share / prev_share) / log(st.penalty / prev.penalty), 0), 1);
        prev = st, prev_top = info->top_decile_alpha, prev_share = share;
        /* Smoothing first: while it is what keeps the frame from the goal,
         * the next try halves its iterations at the same strength (a
         * stronger λ would only be smoothed away again). */
        int smoothed = smoothing_costs(target, info, miss) && p.foo.smoothing > 0;
        if (smoothed) /* at most LC_CLARITY_SMOOTHING_STEPS, the last to none (15, 7, 3, 1, 0) */
            next.smoothing =
                given->foo.smoothing * st.smoothing >= 2 && smoothing_steps + 1 < LC_CLARITY_SMOOTHING_STEPS
                    ? 0.5 * st.smoothing
                    : 0;
        else
            next_strength(&next, target, info, 3.0, gain, fade);
        int same = next.lambda == st.lambda && next.penalty == st.penalty && next.smoothing == st.smoothing;
        if (miss == 0 || same || stalled || i + 1 - smoothing_steps == LC_CLARITY_ITERATIONS) {
            if (best.lambda != st.lambda || best.penalty != st.penalty || best.smoothing != st.smoothing) {
                /* the last try was not the best: redo it */
                if (state)
                    lc_frame_state_reset(state);
                st = best;
                rc = try_strength(r, fs, &p, given, st, state, dt, info, moments, optimize, err);
            }
            st.stalled = stalled;
            st.miss = best_miss;
            break;
        }
        smoothing_steps += smoothed;
        st = next;
    }
    fs->params = given;
    info->clarity_reached = rc == 0 && lc_clarity_miss(target, info) == 0;
    LC_DEBUG("clarity", "clarity: %d tries (%s, %dx%d), lambda x%.3g, penalty x%.3g, miss %.3g", info->clarity_tries,
             iterate ? "loop" : "one step", fs->width, fs->height, st.lambda, st.penalty, best_miss);
    if (state)
        state->clarity = st;
    return rc;
}
