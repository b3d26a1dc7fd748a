/* A WebSocket session's frame flow: which frame is due next (moving, a
 * staged still's stages, the still) at what size, detail and quality, and
 * the bookkeeping of the frames it rendered, sent, had acked or abandoned. */
#include "stream_session.h"

#include <math.h>
#include <string.h>

#include "detail_ladder.h"
#include "metrics.h"
#include "still_stages.h"

#define MOD "session"

/* A session's first frame on a dataset of this many primitives or more is
 * rendered at the coarse end of the ladder, as a moving frame would be, and
 * the full-quality still follows at once: an image within a fraction of the
 * still's time instead of a black canvas (issue 35, coarse to fine). */
#define FIRST_COARSE_PRIMITIVES 500000
/* While the camera keeps moving, P1-P3 run again so the reused opacities
 * follow the view: at most once a REOPTIMIZE_SECONDS, and no more often than
 * keeps their measured extra time within REOPTIMIZE_SHARE of the motion's
 * (reoptimize_seconds), but at least once a REOPTIMIZE_MAX_SECONDS. */
#define REOPTIMIZE_SECONDS 1.0
#define REOPTIMIZE_SHARE 0.02
#define REOPTIMIZE_MAX_SECONDS 3.0
/* Staged stills (protocol/websocket.md): when the session's last full still
 * took longer than this, a still comes in two stages, the moving frames'
 * opacities at full size first, then the full optimization. On data the
 * moving frames thinned, stage 1 is thinned too where its full detail would
 * miss LC_STILL_PREVIEW_TARGET_MS (a preview, still_stages.h). */
#define STAGED_STILL_MS 500.0

void lc_stream_frame_size(const lc_serve_config *cfg, int css_w, int css_h, double dpr, double scale, int *w, int *h)
{
    const lc_proto_limits *lim = &cfg->limits;
    double fw = css_w * dpr, fh = css_h * dpr;
    long long cap = cfg->max_stream_pixels;
    if (lim->max_pixels > 0 && (cap <= 0 || lim->max_pixels < cap))
        cap = lim->max_pixels;
    if (cap > 0 && fw * fh > (double)cap) {
        double k = sqrt((double)cap / (fw * fh));
        fw *= k;
        fh *= k;
    }
    fw *= scale;
    fh *= scale;
    int lo = lim->min_size, hi = lim->max_size;
    int iw = (int)lround(fw), ih = (int)lround(fh);
    *w = iw < lo ? lo : iw > hi ? hi : iw;
    *h = ih < lo ? lo : ih > hi ? hi : ih;
}

/* Whether the still frame is due: the last frame was interactive and input has
 * been quiet for still_delay. */
/* The quiet time before a still: --still-delay, or 1.5 times the session's
 * recent spacing of input where that is longer (at most STILL_DELAY_MAX).
 * Input that comes at a slow, steady pace, such as the page's time bar
 * playing at 5 steps a second, would otherwise start a still between every
 * two steps that the next step then has to wait out (a pass of a still of
 * the MD trajectories takes up to a second); camera drags at 30-60 updates a
 * second keep the configured delay. */
#define STILL_DELAY_MAX 1.0
static double effective_still_delay(const lc_stream *st, double delay)
{
    double paced = 1.5 * st->input_interval;
    paced = paced < STILL_DELAY_MAX ? paced : STILL_DELAY_MAX;
    return paced > delay ? paced : delay;
}

/* How long a drag's moving frames reuse opacities before P1-P3 run again.
 * A re-optimizing frame costs its P0-P3 more than the frames around it (the
 * tornado at 243x190 on llvmpipe: 30-110 ms over 60-180), and at once a
 * second those frames were a third of an orbit's slowest 5 %: spacing them by
 * their measured cost keeps that cost to a share of the motion's time (40 ms:
 * every 2 s), while cheap data re-optimizes once a second as before. */
static double reoptimize_seconds(const lc_stream *st)
{
    double s = st->reoptimize_ms / 1000.0 / REOPTIMIZE_SHARE;
    return s < REOPTIMIZE_SECONDS ? REOPTIMIZE_SECONDS : s > REOPTIMIZE_MAX_SECONDS ? REOPTIMIZE_MAX_SECONDS : s;
}

static bool still_due(const lc_session *s, double now, double delay)
{
    return s->stream.last_interactive && now - s->stream.last_input >= effective_still_delay(&s->stream, delay);
}

int lc_session_stream_next(lc_session *s, double now, lc_stream_frame *out, double *wake_at)
{
    const lc_serve_config *cfg = &s->srv->cfg;
    lc_stream *st = &s->stream;
    *wake_at = 0;
    pthread_mutex_lock(&s->lock);
    if (s->closed || st->rendering || st->unacked >= st->window || st->send_blocked || st->css_width <= 0) {
        pthread_mutex_unlock(&s->lock);
        return 0; /* an ack, the frame in hand finishing or a resize wakes us again */
    }
    bool fading = !st->converged;
    bool still = still_due(s, now, cfg->still_delay);
    if (!st->dirty && !fading && !still) {
        if (st->last_interactive)
            *wake_at = st->last_input + effective_still_delay(st, cfg->still_delay);
        pthread_mutex_unlock(&s->lock);
        return 0;
    }
    uint64_t primitives = 0;
    for (int i = 0; i < lc_request_layer_count(&s->req); i++)
        primitives += lc_scene_primitive_count(s->layer_ds[i]->scene);
    if (!lc_request_layer_count(&s->req) && s->dataset && s->dataset->scene)
        primitives = lc_scene_primitive_count(s->dataset->scene);
    bool first_coarse = st->frames == 0 && !st->any_input && primitives >= FIRST_COARSE_PRIMITIVES;
    bool interactive = first_coarse || st->moving_next ||
                       (st->any_input && now - st->last_input < effective_still_delay(st, cfg->still_delay));
    st->moving_next = false;
    /* A staged still: stage 1 reuses the opacities the moving frames drew with (methods that have them). */
    lc_method method = s->req.render.method;
    bool reusable = (method == LC_METHOD_FOURIER || method == LC_METHOD_WBOIT || method == LC_METHOD_WEIGHTED_AVERAGE ||
                     method == LC_METHOD_BINNING) &&
                    s->frame_state && !lc_frame_state_is_fresh(s->frame_state);
    out->stages = 0, out->stage = 0;
    /* Until a still has finished, a session that began with a coarse first
     * frame (a large dataset) stages its stills though no time is known:
     * stage 1, at the coarsest rung's line stride (or the moving frames'),
     * is a full-size picture well before the full still, and neither stage
     * fades from the coarse frame (which cost a second full still). */
    bool unmeasured = st->coarse_first && st->still_ms <= 0;
    if (!interactive && still &&
        (st->still_stage > 0 || (reusable && (st->still_ms > STAGED_STILL_MS || unmeasured)))) {
        if (st->still_stage == 0) {
            double budget = LC_STILL_PREVIEW_TARGET_MS - 1000.0 * effective_still_delay(st, cfg->still_delay);
            /* What stage 1 costs at full detail: measured by the last stage 1, else at most the whole still. */
            double full_ms = st->reused_ms > 0 ? st->reused_ms : st->still_ms;
            int coarsest = lc_detail_rung_at(LC_DETAIL_RUNGS - 1)->line_stride;
            st->preview_stride = full_ms > 0             ? lc_still_preview_stride(full_ms, budget, st->moving_stride)
                                 : st->moving_stride > 1 ? st->moving_stride
                                                         : coarsest;
        }
        out->stages = 2, out->stage = st->still_stage + 1;
    }
    double scale = interactive ? st->interactive_scale : 1.0;
    lc_request_copy(&out->req, &s->req); /* the layers by reference: the worker releases them */
    memcpy(out->layers, s->layer_ds, (size_t)lc_request_layer_count(&s->req) * sizeof *out->layers);
    out->detail_step = first_coarse ? LC_DETAIL_RUNGS - 1 : st->detail_step; /* not the controller's step */
    if (first_coarse)
        st->coarse_first = true;
    if (interactive) {
        lc_detail *d = &out->req.render.detail;
        if (!st->last_interactive && !first_coarse) {
            st->last_optimized = now; /* the still frame's opacities start the interaction */
            /* The session's first drag: no moving frame measured yet, so it
             * starts where the still's time, read as the first moving frame's,
             * puts it (lc_detail_rung_next). Data that a still overruns the
             * budget on are geometry-bound, and a moving frame's smaller size
             * and reused opacities save less than its share of the pixels (the
             * tornado: a 413x323 frame took a quarter of the 972x761 still's
             * time, not the 0.18 its pixels predict, and 160-250 ms where the
             * ladder settles at 243x190 and 60-80 ms). Too coarse a start costs
             * a frame or two at the coarse end; too fine, the drag's slowest
             * frame (docs/ALGORITHM.md "Interactive frames"). */
            if (!st->step_measured && st->still_ms > 0) {
                int step = lc_detail_rung_next(LC_DETAIL_START, st->still_ms, cfg->frame_budget_ms);
                st->detail_step = out->detail_step = step > st->detail_step ? step : st->detail_step;
            }
        }
        const lc_detail_rung *rung = lc_detail_rung_at(out->detail_step);
        d->lod_pixels = d->lod_pixels > rung->lod_pixels ? d->lod_pixels : rung->lod_pixels;
        d->point_stride = rung->point_stride;
        d->line_stride = rung->line_stride;
        d->reuse_opacities = !first_coarse && now - st->last_optimized < reoptimize_seconds(st);
        out->req.render.style.antialias = 1; /* frames while moving stay single */
        bool points = !lc_request_layer_count(&s->req) && s->dataset && s->dataset->scene &&
                      s->dataset->scene->type == LC_PRIM_POINTS;
        scale *= points || st->lines_thinned ? rung->thinned_scale : rung->scale;
    }
    if (out->stage == 1) {
        out->req.render.detail.reuse_opacities = true;
        if (st->preview_stride > 1) /* a preview; the renderer applies the stride its data type has */
            out->req.render.detail.line_stride = out->req.render.detail.point_stride = st->preview_stride;
    }
    /* The stages are one still refined: each shows its own targets, not a fade from the frame before. */
    if (out->stage > 0)
        out->req.render.foo.fade_half_life = 0;
    /* The still (the last stage) is the one-shot render of the session's request. */
    out->req.render.detail.still = !interactive && out->stage != 1;
    out->quality = interactive ? st->interactive_quality : st->quality;
    if (interactive) { /* quality, then size, so that the link carries the frame within the budget (stream_fit.h) */
        int w, h;
        bool measured;
        double rate = lc_stream_flow_link_rate(&st->flow, &measured);
        lc_stream_frame_size(cfg, st->css_width, st->css_height, st->device_pixel_ratio, scale, &w, &h);
        lc_fit before = st->fit;
        lc_stream_fit(measured ? rate : 0, measured ? 0 : rate, cfg->frame_budget_ms / 1000.0, &st->fit_ref,
                      (double)w * h, st->interactive_quality, &st->fit);
        /* Until a moving frame has gone out, frames are fitted from the still,
         * whose bytes per pixel (antialiased, full detail) are less than half a
         * moving frame's: a smaller rung after the first would leap in quality
         * (the tornado over 2 Mbit/s: 388x304 at 30, then 243x190 at 85 and
         * 12 kB where 5 kB was predicted). So such fits never climb. */
        if (st->fit_ref.still && st->fit_from_still) {
            st->fit.quality = before.quality < st->fit.quality ? before.quality : st->fit.quality;
            st->fit.scale = before.scale < st->fit.scale ? before.scale : st->fit.scale;
        }
        st->fit_from_still = st->fit_ref.still;
        out->quality = st->fit.quality;
        scale *= st->fit.scale;
    }
    lc_stream_frame_size(cfg, st->css_width, st->css_height, st->device_pixel_ratio, scale, &out->req.render.width,
                         &out->req.render.height);
    out->req.render.detail.pixel_scale = scale;
    out->req.format = LC_FORMAT_JPEG;
    out->req.quality = out->quality;
    out->interactive = interactive;
    out->frame = st->next_frame++;
    out->camera_seq = st->camera_seq;
    out->dt = s->last_frame_time > 0 ? now - s->last_frame_time : 0.0;
    s->last_frame_time = now;
    st->outstanding[st->unacked++] = out->frame;
    st->rendering = true;
    st->render_began = now;
    st->dirty = false;
    LC_DEBUG(MOD, "flow %s begin %llu seq %llu moving %d at %.4f unacked %d window %d q %d", s->id,
             (unsigned long long)out->frame, (unsigned long long)out->camera_seq, interactive, now, st->unacked,
             st->window, out->quality);
    if (st->updates_since_frame > 1) {
        lc_metrics_coalesced(s->srv->metrics, st->updates_since_frame - 1);
        st->coalesced += st->updates_since_frame - 1;
    }
    st->updates_since_frame = 0;
    s->last_used = now;
    pthread_mutex_unlock(&s->lock);
    return 1;
}

static void drop_outstanding(lc_stream *st, uint64_t upto, bool only_exact)
{
    int k = 0;
    for (int i = 0; i < st->unacked; i++) {
        uint64_t id = st->outstanding[i];
        bool drop = only_exact ? id == upto : id <= upto;
        if (!drop)
            st->outstanding[k++] = id;
    }
    st->unacked = k;
}

/* The moving frames' mean time at the ladder's rung, and what running P1-P3
 * adds to it (reoptimize_seconds): means over recent frames, begun again at a
 * new rung; an extra measured before any reusing frame at that rung (a
 * session's coarse first frame) is not one. */
static void measure_reoptimize(lc_stream *st, int step, const lc_frame_info *info)
{
    if (step != st->moving_step)
        st->moving_ms = 0, st->moving_step = step;
    if (info->reused_opacities) {
        st->moving_ms = st->moving_ms > 0 ? 0.7 * st->moving_ms + 0.3 * info->wall_ms : info->wall_ms;
    } else if (st->moving_ms > 0) {
        double extra = info->wall_ms > st->moving_ms ? info->wall_ms - st->moving_ms : 0;
        st->reoptimize_ms = st->reoptimize_ms > 0 ? 0.5 * st->reoptimize_ms + 0.5 * extra : extra;
    }
}

void lc_session_stream_done(lc_session *s, const lc_stream_frame *f, bool ok, const lc_frame_info *info)
{
    pthread_mutex_lock(&s->lock);
    lc_stream *st = &s->stream;
    st->rendering = false;
    LC_DEBUG(MOD, "flow %s done %llu at %.4f", s->id, (unsigned long long)f->frame, lc_now());
    if (ok && f->interactive) { /* the moving frames' rate is the one the window covers the round trip at */
        lc_stream_flow_rendered(&st->flow, lc_now() - st->render_began);
        st->window = st->flow.window;
    }
    if (ok && f->stage > 0 && f->stage < f->stages) { /* the next stage is due: still_due holds on */
        st->still_stage = f->stage;
        st->frames++;
        int n = st->preview_stride;
        if (info) /* stage 1 at full detail, from this one's time and share */
            st->reused_ms = n > 1 ? info->wall_ms / LC_STILL_THINNED_SHARE(n) : info->wall_ms;
    } else if (ok) {
        st->still_stage = 0;
        if (!f->interactive && info)
            st->still_ms = info->wall_ms;
        st->converged = info ? info->converged != 0 : true;
        st->last_interactive = f->interactive;
        st->frames++;
        if (info && !info->reused_opacities)
            st->last_optimized = lc_now();
        if (info && f->interactive) /* a later still's stage 1 thins no further than this */
            st->moving_stride = info->line_stride > info->point_stride ? info->line_stride : info->point_stride;
        /* Dense lines (thinned 4-fold or more) take the lines' scales; lines
         * not thinned at all at such a step go back to the common ones. In
         * between nothing changes, so sizes do not flip frame to frame. */
        if (info && f->interactive && lc_detail_rung_at(f->detail_step)->line_stride >= 4)
            st->lines_thinned = info->line_stride >= 4 ? true : info->line_stride == 1 ? false : st->lines_thinned;
        /* Coarser when a frame overran the budget, finer when it took well
         * under half (the gap keeps the controller from oscillating). A step
         * roughly halves the work, so an overrun of k times the budget goes
         * ceil(log2 k) steps at once: the first moving frame of a drag on
         * dense data can take a second, and one step a frame would spend
         * several more such frames reaching the rung that fits. Finer goes
         * one step at a time. Only frames that reused opacities count: the
         * periodic re-optimized ones cost more by design. */
        double budget = s->srv->cfg.frame_budget_ms;
        if (info && f->interactive && f->detail_step == st->detail_step)
            measure_reoptimize(st, f->detail_step, info);
        if (info && f->interactive && info->reused_opacities && budget > 0 && f->detail_step == st->detail_step) {
            st->detail_step = lc_detail_rung_next(st->detail_step, info->wall_ms, budget);
            st->step_measured = true;
        }
    } else {
        /* Nothing goes out for this id, so it cannot be acked; and retrying
         * the same failing request would loop, so wait for new input. */
        drop_outstanding(st, f->frame, true);
        st->converged = true;
        st->last_interactive = false;
    }
    pthread_mutex_unlock(&s->lock);
}

bool lc_session_stream_preempted(lc_session *s)
{
    pthread_mutex_lock(&s->lock);
    bool stop = s->closed || s->stream.dirty;
    pthread_mutex_unlock(&s->lock);
    return stop;
}

void lc_session_stream_yielded(lc_session *s, const lc_stream_frame *f)
{
    pthread_mutex_lock(&s->lock);
    s->stream.rendering = false;
    drop_outstanding(&s->stream, f->frame, true);
    if (s->stream.next_frame == f->frame + 1) /* no id was taken since (rendering held): ids stay consecutive */
        s->stream.next_frame = f->frame;
    s->stream.yielded++;
    s->stream.moving_next = true;
    pthread_mutex_unlock(&s->lock);
    atomic_store(&s->progress.stage, LC_PROGRESS_NONE);
}

void lc_session_progress_begin(lc_session *s, uint64_t frame)
{
    atomic_store(&s->progress.stage, LC_PROGRESS_PREPARE);
    atomic_store(&s->progress.done, 0);
    atomic_store(&s->progress.planned, 0);
    atomic_store(&s->progress.begun_us, (long long)(lc_now() * 1e6));
    atomic_store(&s->progress.frame, (unsigned long long)frame);
}

bool lc_session_stream_client_ack(lc_session *s, uint64_t frame, double now)
{
    pthread_mutex_lock(&s->lock);
    bool ok = frame <= s->stream.last_sent;
    if (ok) {
        drop_outstanding(&s->stream, frame, false);
        lc_stream_flow_acked(&s->stream.flow, frame, now);
        s->stream.window = s->stream.flow.window;
        LC_DEBUG(MOD, "flow %s ack %llu at %.4f window %d rtt %.4f link_s %.4f frame_s %.4f", s->id,
                 (unsigned long long)frame, now, s->stream.window, s->stream.flow.rtt, s->stream.flow.link_s,
                 s->stream.flow.frame_s);
        s->last_used = lc_now();
    }
    pthread_mutex_unlock(&s->lock);
    return ok;
}

bool lc_session_stream_ack(lc_session *s, uint64_t frame) { return lc_session_stream_client_ack(s, frame, -1); }

bool lc_session_stream_sent(lc_session *s, uint64_t frame, size_t bytes, int quality, long pixels)
{
    pthread_mutex_lock(&s->lock);
    if (frame <= s->stream.last_sent) {
        pthread_mutex_unlock(&s->lock);
        return false;
    }
    s->stream.last_sent = frame;
    bool moving = s->stream.last_interactive;
    if (bytes > 0 && pixels > 0 && (moving || s->stream.fit_ref.bytes <= 0 || s->stream.fit_ref.still)) {
        s->stream.fit_ref = (lc_fit_ref){(double)bytes, quality, (double)pixels, !moving};
        s->stream.fit_from_still = false;
    }
    lc_stream_flow_sent(&s->stream.flow, frame, moving, (double)bytes, lc_now());
    LC_DEBUG(MOD, "flow %s sent %llu at %.4f bytes %zu moving %d", s->id, (unsigned long long)frame, lc_now(), bytes,
             moving);
    pthread_mutex_unlock(&s->lock);
    return true;
}

bool lc_session_stream_blocked(lc_session *s, bool blocked)
{
    pthread_mutex_lock(&s->lock);
    bool drained = s->stream.send_blocked && !blocked;
    s->stream.send_blocked = blocked;
    pthread_mutex_unlock(&s->lock);
    return drained;
}

/* The longest gap within one burst of input while no spacing is known: a
 * step's params and camera from a busy client, not a drag's next move (a
 * drag this fast waits --still-delay whatever its pace). */
#define INPUT_SPLIT_MAX 0.050

void lc_session_stream_input(lc_session *s, double now)
{
    pthread_mutex_lock(&s->lock);
    s->stream.dirty = true;
    s->stream.still_stage = 0; /* a still begins again from stage 1 */
    /* The recent spacing of input (effective_still_delay): messages within
     * 10 ms are one burst (a time step's params and camera), and a gap of a
     * second or more starts a new gesture. A burst's two messages can also
     * arrive further apart (a busy client sends them 10-16 ms apart): one gap
     * under a quarter of the spacing (under INPUT_SPLIT_MAX while none is
     * known) after a full one is such a split, not a pace, which would shrink
     * the spacing and start a still between two steps (server.play); two such
     * gaps in a row are a faster pace. */
    double gap = now - s->stream.last_input, iv = s->stream.input_interval;
    if (!s->stream.any_input || gap < 0 || gap >= 1.0) {
        s->stream.input_interval = 0;
        s->stream.input_split = false;
    } else if (gap >= 0.010) {
        bool split = gap < (iv > 0 ? 0.25 * iv : INPUT_SPLIT_MAX) && !s->stream.input_split;
        s->stream.input_split = split;
        if (!split)
            s->stream.input_interval = iv > 0 ? 0.7 * iv + 0.3 * gap : gap;
    }
    s->stream.any_input = true;
    s->stream.last_input = now;
    s->stream.updates_since_frame++;
    s->last_used = now;
    pthread_mutex_unlock(&s->lock);
}
