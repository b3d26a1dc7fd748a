/* The stream's flow control in process (session.c, stream.c): hello through
 * the stream protocol, the window of unacknowledged frames, latest-wins
 * coalescing of updates, convergence and the still frame, staged stills and
 * their preview stage, blind acks, one update path with its budget check
 * for HTTP sessions and streams, the window that follows the round trip
 * (stream_flow.h), and the link's throughput from acks with the moving
 * frames' quality and size that follow it (stream_fit.h). */
#include <math.h>
#include <stdlib.h>

#include "daemon_test_util.h"
#include "detail_ladder.h"
#include "lc_test.h"
#include "still_stages.h"
#include "stream.h"
#include "stream_fit.h"
#include "stream_flow.h"
#include "stream_session.h"

static lc_server srv;

/* One text message through the protocol; returns the outcome (reply freed). */
static lc_stream_outcome send_text(lc_stream_conn *conn, const char *text, char *reply, size_t n)
{
    lc_stream_outcome o;
    lc_stream_on_text(&srv, &srv.cfg.limits, conn, text, strlen(text), lc_now(), &o);
    if (reply)
        snprintf(reply, n, "%s", o.reply ? o.reply : "");
    free(o.reply);
    return o;
}

/* What a render worker would do with a frame: finished, converged or not, and sent. */
static void finish(lc_session *s, const lc_stream_frame *f, bool converged)
{
    lc_frame_info info;
    memset(&info, 0, sizeof info);
    info.converged = converged;
    info.wall_ms = 10;
    lc_session_stream_done(s, f, true, &info);
    lc_session_stream_sent(s, f->frame, 1000, f->quality, (long)f->req.render.width * f->req.render.height);
}

static void test_window(lc_session *s)
{
    lc_stream_frame f1, f2, f3;
    double wake = 0, now = lc_now();
    CHECK(lc_session_stream_next(s, now, &f1, &wake) == 1 && f1.frame == 1, "the hello's first frame is due");
    CHECK(lc_session_stream_next(s, now, &f2, &wake) == 0, "one frame at a time while one is rendering");
    finish(s, &f1, false);
    CHECK(lc_session_stream_next(s, now, &f2, &wake) == 1 && f2.frame == 2, "a fading frame continues (window 2)");
    finish(s, &f2, false);
    CHECK(lc_session_stream_next(s, now, &f3, &wake) == 0, "two frames unacked with window 2: nothing more");
    CHECK(s->stream.unacked == 2, "two frames outstanding (%d)", s->stream.unacked);
    CHECK(!lc_session_stream_ack(s, 99), "a blind ack (frame 99 never sent) is refused");
    CHECK(s->stream.unacked == 2, "and opens nothing");
    CHECK(lc_session_stream_ack(s, 1), "ack of frame 1");
    CHECK(lc_session_stream_next(s, now, &f3, &wake) == 1 && f3.frame == 3, "the ack opens the window for frame 3");
    finish(s, &f3, true);
    CHECK(lc_session_stream_ack(s, 3), "ack of frames 2 and 3");
    CHECK(s->stream.unacked == 0, "nothing outstanding (%d)", s->stream.unacked);
}

static void test_latest_wins(lc_stream_conn *conn)
{
    lc_session *s = conn->session;
    /* Fill the window, then move the camera three times. */
    lc_stream_frame a, b, c;
    double wake = 0;
    lc_session_stream_input(s, lc_now());
    CHECK(lc_session_stream_next(s, lc_now(), &a, &wake) == 1, "input: a frame");
    finish(s, &a, true);
    lc_session_stream_input(s, lc_now());
    CHECK(lc_session_stream_next(s, lc_now(), &b, &wake) == 1, "more input: a second frame");
    finish(s, &b, true);
    uint64_t coalesced = s->stream.coalesced;
    for (int k = 1; k <= 3; k++) {
        char msg[256], reply[512];
        snprintf(msg, sizeof msg,
                 "{\"type\":\"camera\",\"seq\":%d,\"camera\":{\"position\":[0,0,%d],\"focalPoint\":[0,0,0],"
                 "\"viewUp\":[0,1,0],\"viewAngle\":30}}",
                 10 + k, 4 + k);
        lc_stream_outcome o = send_text(conn, msg, reply, sizeof reply);
        CHECK(o.valid && !o.bad && o.wake && !reply[0], "camera %d applied (%s)", k, reply);
        CHECK(lc_session_stream_next(s, lc_now(), &c, &wake) == 0, "window full: camera %d waits", k);
    }
    CHECK(lc_session_stream_ack(s, b.frame), "ack opens the window");
    CHECK(lc_session_stream_next(s, lc_now(), &c, &wake) == 1, "one frame for the three updates");
    CHECK(c.req.render.has_camera && c.req.render.camera.position[2] == 7.0,
          "the frame shows the latest camera (z = %g, want 7)", c.req.render.camera.position[2]);
    CHECK(c.camera_seq == 13, "and carries its seq (%llu)", (unsigned long long)c.camera_seq);
    CHECK(s->stream.coalesced == coalesced + 2, "two updates coalesced (%llu)",
          (unsigned long long)(s->stream.coalesced - coalesced));
    finish(s, &c, true);
    lc_session_stream_ack(s, c.frame);
}

static void test_convergence(lc_session *s)
{
    lc_stream_frame f;
    double wake = 0;
    /* Quiet input long ago: no interactive frame, and a converged frame ends the stream. */
    pthread_mutex_lock(&s->lock);
    s->stream.last_input -= 10.0;
    s->stream.dirty = true;
    pthread_mutex_unlock(&s->lock);
    CHECK(lc_session_stream_next(s, lc_now(), &f, &wake) == 1 && !f.interactive, "a still frame after quiet input");
    finish(s, &f, false);
    lc_session_stream_ack(s, f.frame);
    CHECK(lc_session_stream_next(s, lc_now(), &f, &wake) == 1, "not converged: the fade goes on");
    finish(s, &f, true);
    lc_session_stream_ack(s, f.frame);
    wake = -1;
    CHECK(lc_session_stream_next(s, lc_now(), &f, &wake) == 0 && wake == 0, "converged and no input: idle, no timer");

    /* Input: interactive frames, then the still frame when input has been quiet for still_delay. */
    double t0 = lc_now();
    lc_session_stream_input(s, t0);
    CHECK(lc_session_stream_next(s, t0, &f, &wake) == 1 && f.interactive, "input: an interactive frame");
    finish(s, &f, true);
    lc_session_stream_ack(s, f.frame);
    double delay = srv.cfg.still_delay;
    CHECK(lc_session_stream_next(s, t0 + 0.5 * delay, &f, &wake) == 0 && fabs(wake - (t0 + delay)) < 1e-9,
          "converged interactive frame: wait for the still frame at input + still_delay (wake %g)", wake - t0);
    /* (t0 + delay) - t0 may round below delay: ask a microsecond later. */
    CHECK(lc_session_stream_next(s, t0 + delay + 1e-6, &f, &wake) == 1 && !f.interactive, "then the still frame");
    finish(s, &f, true);
    lc_session_stream_ack(s, f.frame);
    CHECK(lc_session_stream_next(s, t0 + 2 * delay, &f, &wake) == 0 && wake == 0, "after it: idle");
}

/* What a render worker reports for a frame of a thinned draw (line_stride) that took wall_ms. */
static void finish_timed(lc_session *s, const lc_stream_frame *f, double wall_ms, int line_stride)
{
    lc_frame_info info;
    memset(&info, 0, sizeof info);
    info.converged = 1;
    info.wall_ms = wall_ms;
    info.line_stride = line_stride;
    info.point_stride = 1;
    info.reused_opacities = f->req.render.detail.reuse_opacities;
    lc_session_stream_done(s, f, true, &info);
    lc_session_stream_sent(s, f->frame, 1000, f->quality, (long)f->req.render.width * f->req.render.height);
    lc_session_stream_ack(s, f->frame);
}

/* One moving frame drawn at line_stride, then the still's frames once input is quiet (up to 3) into out[]; the
 * still's stage 1 takes stage1_ms, its last frame still_ms. Returns the number of still frames. */
static int move_and_settle(lc_session *s, int line_stride, double stage1_ms, double still_ms, lc_stream_frame out[3])
{
    lc_stream_frame f;
    double wake = 0, t0 = lc_now();
    lc_session_stream_input(s, t0);
    if (lc_session_stream_next(s, t0, &f, &wake) != 1 || !f.interactive)
        return -1;
    finish_timed(s, &f, 10, line_stride);
    double later = t0 + srv.cfg.still_delay + 1e-6;
    int n = 0;
    while (n < 3 && lc_session_stream_next(s, later, &out[n], &wake) == 1 && !out[n].interactive) {
        const lc_stream_frame *g = &out[n++];
        finish_timed(s, g, g->stage == 1 ? stage1_ms : still_ms, 1);
    }
    return n;
}

/* The smallest power-of-two stride whose share of full_ms fits the budget. */
static int expected_stride(double full_ms, double budget)
{
    int n = 2;
    while (full_ms * LC_STILL_THINNED_SHARE(n) > budget)
        n *= 2;
    return n;
}

static void test_staged(lc_session *s)
{
    /* Stages need opacities to reuse: a state that is not fresh (the render worker's, in the daemon; its
     * size does not matter here, as nothing renders). */
    pthread_mutex_lock(&s->lock);
    lc_frame_state_destroy(s->frame_state);
    s->frame_state = lc_frame_state_create(4);
    lc_frame_state_load(s->frame_state, (const float[]){0.5f, 0.5f, 0.5f, 0.5f});
    s->stream.input_interval = 0; /* the still waits still_delay, not a pace of input */
    pthread_mutex_unlock(&s->lock);
    lc_stream_frame st[3];
    double budget = LC_STILL_PREVIEW_TARGET_MS - 1000.0 * srv.cfg.still_delay;
    const lc_detail *d0 = &st[0].req.render.detail, *d1 = &st[1].req.render.detail;

    /* A quick still: one piece. A slow one makes the next still staged. */
    int n = move_and_settle(s, 1, 0, 6000, st);
    CHECK(n == 1 && st[0].stages == 0, "a still after quick ones comes in one piece (%d frames, %d stages)", n,
          n > 0 ? st[0].stages : -1);
    /* The moving frames were not thinned: stage 1 reuses their opacities at full detail. */
    n = move_and_settle(s, 1, 3000, 6000, st);
    CHECK(n == 2 && st[0].stage == 1 && st[0].stages == 2 && d0->reuse_opacities && d0->line_stride <= 1 &&
              st[1].stage == 2 && st[1].stages == 2 && !d1->reuse_opacities && d1->line_stride <= 1,
          "unthinned data: stage 1 of 2 reuses the opacities at full detail, stage 2 optimizes (%d frames)", n);
    CHECK(n == 2 && st[0].req.render.foo.fade_half_life == 0 && st[1].req.render.foo.fade_half_life == 0 &&
              s->req.render.foo.fade_half_life > 0,
          "the stages do not fade into each other (the session keeps its half-life)");
    /* Thinned moving frames (1 in 16), and stage 1 took 3 s at full detail: the next stage 1 is a preview
     * thinned by the smallest power-of-two stride that fits (3000 * 1.25 / n <= budget). */
    int want = expected_stride(3000, budget);
    n = move_and_settle(s, 16, 100, 6000, st);
    CHECK(n == 2 && st[0].stage == 1 && st[0].stages == 2 && d0->reuse_opacities && d0->line_stride == want &&
              d0->point_stride == want,
          "thinned data: stage 1 of 2 is a preview at stride %d (%d frames, stride %d)", want, n,
          n > 0 ? d0->line_stride : -1);
    CHECK(n == 2 && st[1].stage == 2 && !d1->reuse_opacities && d1->line_stride <= 1 && d1->point_stride <= 1,
          "then the full still");
    /* That preview took 100 ms at stride `want`: full detail would be 100 / share, within the budget. */
    n = move_and_settle(s, 16, 600, 6000, st);
    CHECK(n == 2 && d0->reuse_opacities && d0->line_stride <= 1,
          "a stage 1 whose full detail fits is not "
          "thinned (stride %d)",
          n > 0 ? d0->line_stride : -1);
    /* Full detail at 600 ms measured; now 4 s: the stride follows, and never thinner than the moving frames. */
    n = move_and_settle(s, 16, 4000, 6000, st);
    n = move_and_settle(s, 2, 100, 6000, st);
    CHECK(n == 2 && d0->line_stride == 2, "the preview's stride is capped by the moving frames' (%d)",
          n > 0 ? d0->line_stride : -1);
    /* Unknown stage 1 time (a new session): the whole still's bounds it. */
    pthread_mutex_lock(&s->lock);
    s->stream.reused_ms = 0;
    pthread_mutex_unlock(&s->lock);
    want = expected_stride(6000, budget);
    n = move_and_settle(s, 64, 100, 6000, st);
    CHECK(n == 2 && d0->line_stride == want,
          "without a measured stage 1 the whole still's time picks the stride "
          "(%d, want %d)",
          n > 0 ? d0->line_stride : -1, want);
    /* A still within the budget comes whole. */
    n = move_and_settle(s, 16, 100, 0.5 * budget, st);
    n = move_and_settle(s, 16, 100, 0.5 * budget, st);
    CHECK(n == 1 && st[0].stages == 0, "a still that fits the budget comes whole (%d frames)", n);

    /* Input during a stage starts the still over. */
    move_and_settle(s, 16, 100, 6000, st);
    lc_stream_frame f;
    double wake = 0, t0 = lc_now();
    lc_session_stream_input(s, t0);
    CHECK(lc_session_stream_next(s, t0, &f, &wake) == 1 && f.interactive, "input: a moving frame");
    finish_timed(s, &f, 10, 16);
    CHECK(lc_session_stream_next(s, t0 + srv.cfg.still_delay + 1e-6, &f, &wake) == 1 && f.stage == 1 && f.stages == 2,
          "the still's stage 1 (%d of %d)", f.stage, f.stages);
    finish_timed(s, &f, 100, 16);
    lc_session_stream_input(s, t0);
    CHECK(lc_session_stream_next(s, t0, &f, &wake) == 1 && f.interactive, "input after stage 1: a moving frame");
    finish_timed(s, &f, 10, 16);
    CHECK(lc_session_stream_next(s, t0 + srv.cfg.still_delay + 1e-6, &f, &wake) == 1 && f.stage == 1,
          "and the still starts again from stage 1 (%d)", f.stage);
    finish_timed(s, &f, 100, 1);
    CHECK(lc_session_stream_next(s, t0 + srv.cfg.still_delay + 1e-6, &f, &wake) == 1 && f.stage == 2,
          "then its stage 2 (%d)", f.stage);
    finish_timed(s, &f, 6000, 1);

    /* A session whose first frame was coarse (a large dataset) and that has no still time yet stages its still
     * all the same: stage 1 at the coarsest rung's line stride (its moving frame drew every line), neither stage
     * fading from the frame before. */
    pthread_mutex_lock(&s->lock);
    s->stream.still_ms = 0, s->stream.reused_ms = 0, s->stream.coarse_first = true;
    pthread_mutex_unlock(&s->lock);
    int coarsest = lc_detail_rung_at(LC_DETAIL_RUNGS - 1)->line_stride;
    n = move_and_settle(s, 1, 100, 3000, st);
    CHECK(n == 2 && st[0].stage == 1 && d0->reuse_opacities && d0->line_stride == coarsest &&
              st[0].req.render.foo.fade_half_life == 0 && st[1].req.render.foo.fade_half_life == 0,
          "no still time after a coarse first frame: 2 stages, stage 1 at stride %d (%d frames, stride %d)", coarsest,
          n, n > 0 ? d0->line_stride : -1);
    pthread_mutex_lock(&s->lock);
    s->stream.coarse_first = false;
    pthread_mutex_unlock(&s->lock);
}

/* The detail controller: an overrun of k times the budget moves ceil(log2 k) rungs coarser at once (a rung about
 * halves the work), a frame under 0.45 of it one rung finer; in between, and at the ends, it stays. */
static void test_ladder(lc_session *s)
{
    static const struct {
        int step;
        double wall_ms;
        int want;
    } cases[] = {{1, 945, 4}, {1, 75, 2}, {1, 140, 2}, {1, 141, 3},  {0, 300, 3}, {2, 30, 1},
                 {2, 40, 2},  {2, 70, 2}, {0, 10, 0},  {4, 9000, 4}, {3, 71, 4}};
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        int got = lc_detail_rung_next(cases[i].step, cases[i].wall_ms, 70);
        CHECK(got == cases[i].want, "rung %d, %g ms against 70: rung %d (want %d)", cases[i].step, cases[i].wall_ms,
              got, cases[i].want);
    }
    CHECK(lc_detail_rung_at(LC_DETAIL_RUNGS - 1)->line_stride == 16 &&
              lc_detail_rung_at(99) == lc_detail_rung_at(LC_DETAIL_RUNGS - 1),
          "the coarsest rung draws one line in 16; beyond the ladder is its end");

    /* Through the session: a drag's first frame (reusing opacities) at 945 ms against the 70 ms budget. */
    pthread_mutex_lock(&s->lock);
    s->stream.detail_step = LC_DETAIL_START;
    pthread_mutex_unlock(&s->lock);
    lc_stream_frame f;
    double wake = 0, t0 = lc_now();
    lc_session_stream_input(s, t0);
    CHECK(lc_session_stream_next(s, t0, &f, &wake) == 1 && f.interactive && f.detail_step == LC_DETAIL_START &&
              f.req.render.detail.reuse_opacities,
          "a moving frame at the session's rung, reusing opacities");
    finish_timed(s, &f, 945, 2);
    CHECK(s->stream.detail_step == LC_DETAIL_RUNGS - 1, "945 ms against 70: the coarsest rung next (%d)",
          s->stream.detail_step);
    lc_session_stream_input(s, t0 + 0.03);
    CHECK(lc_session_stream_next(s, t0 + 0.03, &f, &wake) == 1 && f.detail_step == LC_DETAIL_RUNGS - 1 &&
              f.req.render.detail.line_stride == 16,
          "the next moving frame draws one line in 16 (%d)", f.req.render.detail.line_stride);
    finish_timed(s, &f, 20, 16);
    CHECK(s->stream.detail_step == LC_DETAIL_RUNGS - 2, "20 ms against 70: one rung finer (%d)", s->stream.detail_step);
    double later = t0 + 0.03 + srv.cfg.still_delay + 1e-6; /* let the still come and go */
    for (int n = 0; n < 3 && lc_session_stream_next(s, later, &f, &wake) == 1; n++)
        finish_timed(s, &f, 10, 1);

    /* A session's first drag reads its last still's time as the first moving frame's, an overrun of the budget
     * (lc_detail_rung_next from the start rung); never finer than the session's rung. */
    static const double stills[] = {3000, 300, 100, 50};
    for (int i = 0; i < 4; i++) {
        pthread_mutex_lock(&s->lock);
        s->stream.step_measured = false;
        s->stream.detail_step = LC_DETAIL_START;
        s->stream.still_ms = stills[i];
        pthread_mutex_unlock(&s->lock);
        double k = stills[i] / srv.cfg.frame_budget_ms;
        int want = LC_DETAIL_START;
        for (double m = 1; k > m && want < LC_DETAIL_RUNGS - 1; m *= 2)
            want++;
        double t1 = later + 2.0 + i;
        lc_session_stream_input(s, t1);
        CHECK(lc_session_stream_next(s, t1, &f, &wake) == 1 && f.interactive && f.detail_step == want,
              "still of %g ms: the first drag starts at rung %d (%d)", stills[i], want, f.detail_step);
        finish_timed(s, &f, 10, 1);
        for (int n = 0; n < 3 && lc_session_stream_next(s, t1 + 1.0, &f, &wake) == 1; n++)
            finish_timed(s, &f, 10, 1);
    }

    /* Re-optimizing while moving: frames that reuse opacities take 60 ms, one that runs P1-P3 100 ms; its
     * extra 40 ms spaces the next re-optimization 40 ms / 2 % = 2 s after it instead of 1 s. */
    pthread_mutex_lock(&s->lock);
    s->stream.step_measured = true, s->stream.detail_step = LC_DETAIL_RUNGS - 1;
    s->stream.moving_ms = s->stream.reoptimize_ms = 0;
    pthread_mutex_unlock(&s->lock);
    static const struct {
        double at, wall_ms;
        bool reuse;
    } drag[] = {{0, 60, true}, {0.5, 60, true}, {1.1, 100, false}, {2.9, 60, true}, {3.2, 60, false}};
    double t2 = later + 10.0;
    for (int i = 0; i < 5; i++) {
        if (i == 3) { /* P1-P3 ran at t2 + 1.1 */
            pthread_mutex_lock(&s->lock);
            s->stream.last_optimized = t2 + 1.1;
            pthread_mutex_unlock(&s->lock);
        }
        lc_session_stream_input(s, t2 + drag[i].at);
        CHECK(lc_session_stream_next(s, t2 + drag[i].at, &f, &wake) == 1 && f.interactive &&
                  f.req.render.detail.reuse_opacities == drag[i].reuse,
              "moving frame at %g s: %s", drag[i].at, drag[i].reuse ? "reuses the opacities" : "runs P1-P3");
        finish_timed(s, &f, drag[i].wall_ms, 1);
        if (i == 2)
            CHECK(fabs(s->stream.reoptimize_ms - 40) < 1e-9, "P1-P3 add 40 ms (%g)", s->stream.reoptimize_ms);
    }
}

static void test_budget(lc_stream_conn *conn)
{
    lc_session *s = conn->session;
    char reply[1024];
    lc_request before = s->req;
    double cost = lc_cost_estimate(&s->dataset->cost, &s->req.render);
    srv.cfg.max_cost = cost * 1.01;
    lc_stream_outcome o =
        send_text(conn, "{\"type\":\"params\",\"params\":{\"bands\":8,\"resolutionScale\":1}}", reply, sizeof reply);
    CHECK(!o.wake && strstr(reply, "too_expensive"), "an update beyond --max-cost is refused (%s)", reply);
    CHECK(s->req.render.foo.bands == before.render.foo.bands &&
              s->req.render.foo.resolution_scale == before.render.foo.resolution_scale,
          "and the session keeps its request");
    o = send_text(conn, "{\"type\":\"resize\",\"width\":4000,\"height\":3000}", reply, sizeof reply);
    CHECK(!o.wake && strstr(reply, "too_expensive") && s->stream.css_width == 100, "a resize beyond it too (%s)",
          reply);
    srv.cfg.max_cost = LC_COST_DEFAULT_BUDGET;

    /* The same update path for an HTTP session: refused updates change nothing. */
    lc_session *h = NULL;
    lc_error err = {0};
    lc_request req;
    lc_request_default(&req);
    snprintf(req.dataset, sizeof req.dataset, "demo:points");
    CHECK(lc_session_create(srv.sessions, LC_SESSION_HTTP, 0, s->dataset, &req, &h, &err) == 0, "an HTTP session");
    if (!h)
        return;
    lc_proto_error pe;
    json_error_t je;
    const char *texts[3] = {"{\"dataset\":\"demo:other\"}", "{\"width\":4096,\"height\":4096}",
                            "{\"params\":{\"bands\":5}}"};
    lc_request_patch *patches[3] = {NULL, NULL, NULL};
    for (int i = 0; i < 3; i++) {
        json_t *u = json_loads(texts[i], 0, &je);
        CHECK(u && lc_proto_patch_parse(u, &srv.cfg.limits, &patches[i], &pe) == 0, "update %d parses", i);
        json_decref(u);
    }
    lc_request_patch *bad = patches[0], *wide = patches[1], *ok = patches[2];
    srv.cfg.max_cost = lc_cost_estimate(&s->dataset->cost, &h->req.render) * 2;
    pthread_mutex_lock(&h->lock);
    int rc_bad = lc_session_update_locked(h, bad, &srv.cfg.limits, NULL, &pe);
    bool named = rc_bad != 0 && strcmp(pe.field, "dataset") == 0;
    int rc_wide = lc_session_update_locked(h, wide, &srv.cfg.limits, NULL, &pe);
    bool costly = rc_wide != 0 && strcmp(pe.code, "too_expensive") == 0;
    int w = h->req.render.width;
    lc_request out;
    int rc_ok = lc_session_update_locked(h, ok, &srv.cfg.limits, &out, &pe);
    pthread_mutex_unlock(&h->lock);
    CHECK(named, "a change of dataset is refused naming it");
    CHECK(costly && w == req.render.width, "an HTTP update beyond --max-cost is refused, nothing committed (%d)", w);
    CHECK(rc_ok == 0 && h->req.render.foo.bands == 5 && out.render.foo.bands == 5, "a fitting update is committed");
    if (rc_ok == 0)
        lc_request_release(&out);
    srv.cfg.max_cost = LC_COST_DEFAULT_BUDGET;
    lc_proto_patch_free(bad), lc_proto_patch_free(wide), lc_proto_patch_free(ok);
    lc_session_close(srv.sessions, h);
    lc_session_unref(h);
}

/* n frames of render time frame_s, each acked rtt after it was sent (simulated clock from *t). */
static void flow_frames(lc_stream_flow *f, int n, double frame_s, double rtt, double *t, uint64_t *id)
{
    for (int i = 0; i < n; i++) {
        lc_stream_flow_rendered(f, frame_s);
        *t += frame_s;
        lc_stream_flow_sent(f, ++*id, true, 10000, *t);
        lc_stream_flow_acked(f, *id, *t + rtt);
    }
}

/* The window module alone, on a simulated clock: it grows with the round
 * trip, keeps to the ceiling, shrinks back at once when the round trip does,
 * and one late ack (a frame queued on the link) does not widen it. */
static void test_flow_window(void)
{
    lc_stream_flow f;
    double t = 100;
    uint64_t id = 0;
    lc_stream_flow_init(&f, LC_PROTO_MAX_WINDOW);
    CHECK(f.window == LC_PROTO_DEFAULT_WINDOW, "before any ack: the default window (%d)", f.window);
    flow_frames(&f, 4, 0.030, 0.005, &t, &id);
    CHECK(f.window == 3, "loopback, 30 ms frames: 3, a frame of headroom included (%d)", f.window);
    flow_frames(&f, 1, 0.030, 0.400, &t, &id);
    CHECK(f.window == 3, "one late ack does not widen it (%d, rtt %.3f)", f.window, f.rtt);
    flow_frames(&f, 16, 0.030, 0.100, &t, &id);
    CHECK(f.window == 2, "a longer round trip waits for the lower one to age (%d, rtt %.3f)", f.window, f.rtt);
    t += LC_FLOW_RTT_HORIZON;
    flow_frames(&f, 1, 0.030, 0.100, &t, &id);
    CHECK(fabs(f.rtt - 0.100) < 1e-9 && f.window == 6, "100 ms round trip, 30 ms frames: 6 (%d, rtt %.3f)", f.window,
          f.rtt);
    t += LC_FLOW_RTT_HORIZON;
    flow_frames(&f, 1, 0.030, 0.300, &t, &id);
    CHECK(f.window == LC_PROTO_MAX_WINDOW, "300 ms: the ceiling %d (%d)", LC_PROTO_MAX_WINDOW, f.window);
    flow_frames(&f, 1, 0.030, 0.010, &t, &id);
    CHECK(f.window == 3, "back to 10 ms: 3 at once (%d)", f.window);
    flow_frames(&f, 8, 0.100, 0.100, &t, &id);
    CHECK(f.window == 2, "slower frames need fewer: 2 (%d, frame %.3f s)", f.window, f.frame_s);
    lc_stream_flow_init(&f, 3);
    flow_frames(&f, 4, 0.030, 0.300, &t, &id);
    CHECK(f.window == 3, "the hello's window is the ceiling (%d)", f.window);
    lc_stream_flow_init(&f, 1);
    CHECK(f.window == 1, "a ceiling of 1 holds from the start (%d)", f.window);
    /* A link narrower than the frames: 30 ms frames, but acks 150 ms apart
     * (a frame's transfer), the first 260 ms after it went out and the rest
     * behind one more frame on the link: the window holds what the link
     * carries in a round trip, 2, not 8 by the render time. */
    lc_stream_flow_init(&f, LC_PROTO_MAX_WINDOW);
    for (int i = 0; i < 16; i++, t += 0.150) {
        lc_stream_flow_rendered(&f, 0.030);
        lc_stream_flow_sent(&f, ++id, true, 10000, t);
        lc_stream_flow_acked(&f, id, t + (i ? 0.410 : 0.260));
    }
    CHECK(fabs(f.ack_s - 0.150) < 0.01 && f.window == 2, "narrow link: 2 (%d, acks %.3f s apart)", f.window, f.ack_s);
    /* A still's ack is no sample: its transfer is no round trip of the drag. */
    lc_stream_flow_sent(&f, ++id, false, 10000, t);
    lc_stream_flow_acked(&f, id, t + 2.0);
    t += LC_FLOW_RTT_HORIZON + 1;
    lc_stream_flow_sent(&f, ++id, false, 10000, t);
    lc_stream_flow_acked(&f, id, t + 2.0);
    CHECK(fabs(f.rtt - 0.260) < 1e-9 && f.window == 2, "stills leave the round trip as it was (%.3f, %d)", f.rtt,
          f.window);
    /* Two frames out, the older acked: its own round trip, not the newer one's. */
    lc_stream_flow_init(&f, LC_PROTO_MAX_WINDOW);
    lc_stream_flow_sent(&f, 10, true, 10000, 1.0);
    lc_stream_flow_sent(&f, 11, true, 10000, 1.09);
    lc_stream_flow_acked(&f, 10, 1.1);
    CHECK(fabs(f.rtt - 0.1) < 1e-9 && f.nsent == 1 && f.sent_id[0] == 11, "the older frame's round trip (%.3f)", f.rtt);
    /* A frame that never goes out is forgotten; an ack the server makes itself is no sample. */
    lc_stream_flow_init(&f, LC_PROTO_MAX_WINDOW);
    lc_stream_flow_sent(&f, 7, true, 10000, 1.0);
    lc_stream_flow_acked(&f, 7, -1);
    CHECK(f.nsent == 0 && f.nsamples == 0, "an ack without a time takes no sample (%d, %d)", f.nsent, f.nsamples);
}

/* A session's window through the protocol: no window in the hello (the
 * maximum is the ceiling), frames of 50 ms acked 190 ms after they went out
 * widen it to 6 and six frames go out unacked; acks at once shrink it to 3. */
static void test_session_window(void)
{
    lc_stream_conn conn = {.authed = true};
    char reply[4096];
    lc_stream_outcome o = send_text(
        &conn, "{\"type\":\"hello\",\"dataset\":\"demo:points\",\"width\":100,\"height\":80}", reply, sizeof reply);
    CHECK(o.opened && strstr(reply, "\"window\":8"), "a hello without window: ceiling 8 (%s)", reply);
    lc_session *s = conn.session;
    if (!s)
        return;
    lc_stream_frame f;
    double wake = 0;
    CHECK(s->stream.window == 2, "it starts at 2 (%d)", s->stream.window);
    for (int i = 0; i < 16; i++) {
        lc_session_stream_input(s, lc_now());
        /* Taken 50 ms ago: a moving frame of 50 ms. */
        if (lc_session_stream_next(s, lc_now() - 0.050, &f, &wake) != 1) {
            CHECK(0, "frame %d due", i);
            break;
        }
        finish(s, &f, true);
        CHECK(lc_session_stream_client_ack(s, f.frame, lc_now() + 0.190), "ack of %llu", (unsigned long long)f.frame);
    }
    CHECK(s->stream.window == 6, "190 ms round trip, 50 ms frames: window 6 (%d, rtt %.3f, frame %.3f)",
          s->stream.window, s->stream.flow.rtt, s->stream.flow.frame_s);
    int out = 0;
    uint64_t last = 0;
    for (int i = 0; i < 8; i++) {
        lc_session_stream_input(s, lc_now());
        if (lc_session_stream_next(s, lc_now() - 0.050, &f, &wake) != 1)
            break;
        finish(s, &f, true);
        out++, last = f.frame;
    }
    CHECK(out == 6 && s->stream.unacked == 6, "six frames in flight, no seventh (%d, %d)", out, s->stream.unacked);
    CHECK(lc_session_stream_client_ack(s, last, lc_now()) && s->stream.unacked == 0, "ack of the six");
    CHECK(s->stream.window == 6, "frames that went out behind others give no round trip (%d)", s->stream.window);
    lc_session_stream_input(s, lc_now());
    CHECK(lc_session_stream_next(s, lc_now() - 0.050, &f, &wake) == 1, "one more frame");
    finish(s, &f, true);
    CHECK(lc_session_stream_client_ack(s, f.frame, lc_now()), "acked at once");
    CHECK(s->stream.window == 3, "a short round trip: back to 3 (%d)", s->stream.window);
    lc_stream_stats st;
    memset(&st, 0, sizeof st);
    lc_stream_stats_frame(&st, lc_now(), 1, 1);
    char *text = lc_stream_stats_message(&st, s, 0, lc_now());
    CHECK(text && strstr(text, "\"window\":3") && strstr(text, "\"rttMs\":") && !strstr(text, "\"rttMs\":null"),
          "stats carry the window and the round trip (%s)", text ? text : "");
    free(text);
    lc_session_close(srv.sessions, s);
    lc_session_unref(s);
}

/* A FIFO link on a simulated clock: one-way delay d, rate bytes/s. Frames of
 * `bytes` are made every `interval` (once the window lets them) and handed
 * over at once, each acked d after it arrives; n frames, then every ack. */
static void link_run(lc_stream_flow *f, int n, double interval, double bytes, double d, double rate, double *t,
                     uint64_t *id)
{
    double ack_at[64], link_free = 0;
    uint64_t ack_id[64];
    int head = 0, tail = 0;
    for (int i = 0; i < n && tail < 64; i++) {
        double ready = *t + interval;
        while (head < tail && (ack_at[head] <= ready || f->nsent >= f->window)) {
            if (ack_at[head] > ready)
                ready = ack_at[head];
            lc_stream_flow_acked(f, ack_id[head], ack_at[head]);
            head++;
        }
        *t = ready;
        lc_stream_flow_rendered(f, interval);
        lc_stream_flow_sent(f, ++*id, true, bytes, *t);
        double start = *t > link_free ? *t : link_free;
        link_free = start + bytes / rate;
        ack_at[tail] = link_free + 2 * d;
        ack_id[tail++] = *id;
    }
    for (; head < tail; head++)
        lc_stream_flow_acked(f, ack_id[head], ack_at[head]);
    *t = ack_at[tail - 1];
}

/* The link's throughput from explicit ack sequences, and the rule that fits
 * the moving frames to it (quality first, then size; stills untouched). */
static void test_link_fit(void)
{
    bool rising = true;
    for (int q = 2; q <= 100; q++)
        rising = rising && lc_fit_jpeg_share(q) > lc_fit_jpeg_share(q - 1);
    CHECK(rising && fabs(lc_fit_jpeg_share(70) - 1) < 1e-12, "JPEG bytes rise with quality, 1 at 70");

    /* 2 Mbit/s (250 kB/s), 100 ms round trip, frames of 20 kB every 60 ms: each
     * takes 80 ms on the link, so frames wait and the acks' spacing is the link's. */
    lc_stream_flow f;
    double t = 10;
    uint64_t id = 0;
    bool measured = false;
    lc_stream_flow_init(&f, LC_PROTO_MAX_WINDOW);
    link_run(&f, 40, 0.060, 20000, 0.050, 250000, &t, &id);
    double rate = lc_stream_flow_link_rate(&f, &measured);
    CHECK(measured && fabs(rate - 250000) < 0.03 * 250000, "2 Mbit/s: measured %.0f B/s (%d)", rate, measured);
    /* 20 Mbit/s, 50 ms: a frame takes 8 ms, none waits: a lower bound, the
     * higher of frames over their spacing (20 kB / 60 ms) and one frame's
     * bytes over its send-to-ack time (20 kB / 58 ms). */
    t += 5;
    lc_stream_flow_init(&f, LC_PROTO_MAX_WINDOW);
    link_run(&f, 40, 0.060, 20000, 0.025, 2500000, &t, &id);
    rate = lc_stream_flow_link_rate(&f, &measured);
    CHECK(!measured && fabs(rate - 20000 / 0.058) < 0.01 * 20000 / 0.058,
          "20 Mbit/s: not measured, %.0f B/s carried at least", rate);
    /* One stall on that link (a frame acked 350 ms late, the next one, sent
     * 10 ms after it, just behind): one frame that seems to have waited is no
     * queue, and no rate. */
    lc_stream_flow_sent(&f, ++id, true, 20000, t + 0.060);
    lc_stream_flow_sent(&f, ++id, true, 20000, t + 0.070);
    lc_stream_flow_acked(&f, id - 1, t + 0.410);
    lc_stream_flow_acked(&f, id, t + 0.420);
    lc_stream_flow_link_rate(&f, &measured);
    CHECK(!measured && f.waits == 1, "one stall measures nothing (%d waits)", f.waits);
    /* A still of 200 kB acked 0.9 s after it went out: the link carries 222 kB/s at least. */
    lc_stream_flow_init(&f, LC_PROTO_MAX_WINDOW);
    lc_stream_flow_sent(&f, ++id, false, 200000, t);
    lc_stream_flow_acked(&f, id, t + 0.9);
    rate = lc_stream_flow_link_rate(&f, &measured);
    CHECK(!measured && fabs(rate - 200000 / 0.9) < 1, "a still's bytes over its send-to-ack: %.0f B/s", rate);
    /* A window of 2 that holds the renderer back (30 kB frames, 120 ms on a
     * 2 Mbit/s link, 100 ms base): acks come 2.3 times slower than renders,
     * yet no frame waits on the link, and no rate is read from their pace. */
    lc_stream_flow_init(&f, 2);
    link_run(&f, 40, 0.060, 30000, 0.050, 250000, &t, &id);
    rate = lc_stream_flow_link_rate(&f, &measured);
    CHECK(!measured && f.ack_s > 2 * 0.060, "window-bound: not measured (acks %.0f ms apart, %.0f B/s carried)",
          1000 * f.ack_s, rate);
    /* A wait measured 10 s ago no longer counts. */
    lc_stream_flow_init(&f, LC_PROTO_MAX_WINDOW);
    link_run(&f, 40, 0.060, 20000, 0.050, 250000, &t, &id);
    t += LC_FLOW_RTT_HORIZON + 1;
    link_run(&f, 4, 0.060, 2000, 0.050, 250000, &t, &id);
    lc_stream_flow_link_rate(&f, &measured);
    CHECK(!measured, "a measurement older than the horizon lapses");
    /* 5 Mbit/s (625 kB/s), 100 ms: a still of 136 kB on the idle link, then
     * 12 kB moving frames every 65 ms (19 ms each on the link): none waits,
     * and the larger frame's longer transfer gives the rate,
     * (136 - 12) kB / (317.6 - 119.2) ms. */
    t += LC_FLOW_RTT_HORIZON + 1;
    lc_stream_flow_init(&f, LC_PROTO_MAX_WINDOW);
    lc_stream_flow_sent(&f, ++id, false, 136000, t);
    lc_stream_flow_acked(&f, id, t + 0.100 + 136000 / 625000.0);
    t += 1;
    link_run(&f, 20, 0.065, 12000, 0.050, 625000, &t, &id);
    rate = lc_stream_flow_link_rate(&f, &measured);
    CHECK(measured && f.waits == 0 && fabs(rate - 625000) < 1e-6 * 625000,
          "5 Mbit/s, no frame waited: %.0f B/s from sizes (%d waits)", rate, f.waits);
    /* The still had waited 40 ms behind other frames: a lower figure, never a higher one. */
    lc_stream_flow_init(&f, LC_PROTO_MAX_WINDOW);
    lc_stream_flow_sent(&f, ++id, false, 136000, t);
    lc_stream_flow_acked(&f, id, t + 0.140 + 136000 / 625000.0);
    t += 1;
    link_run(&f, 20, 0.065, 12000, 0.050, 625000, &t, &id);
    rate = lc_stream_flow_link_rate(&f, &measured);
    CHECK(measured && rate < 625000 && rate > 0.8 * 625000, "a still that waited: %.0f B/s, under the rate", rate);
    /* Frames of one size tell nothing (the 20 Mbit/s run above); nor does a
     * larger frame acked sooner than the smaller one (timing noise on a wide
     * link): the lower bound, not measured. */
    lc_stream_flow_init(&f, LC_PROTO_MAX_WINDOW);
    lc_stream_flow_sent(&f, ++id, false, 136000, t);
    lc_stream_flow_acked(&f, id, t + 0.004);
    t += 1;
    link_run(&f, 20, 0.065, 12000, 0.0025, 1e9, &t, &id);
    rate = lc_stream_flow_link_rate(&f, &measured);
    CHECK(!measured && fabs(rate - 136000 / 0.004) < 1, "noise orders the sizes wrong: %.0f B/s at least", rate);

    /* The rule. No moving frame yet: the ceiling. */
    lc_fit fit;
    lc_fit_ref ref = {0, 0, 0, false};
    lc_stream_fit(0, 0, 0.070, &ref, 1e5, 85, &fit);
    CHECK(fit.quality == 85 && fit.scale == 1, "no reference: the ceiling (%d)", fit.quality);
    /* Not measured (a wide link): quality climbs a quarter more bytes a frame to the ceiling. */
    ref = (lc_fit_ref){10000, 50, 1e5, false};
    int steps = 0;
    while (steps < 10 && ref.quality < 85) {
        lc_stream_fit(0, 0, 0.070, &ref, 1e5, 85, &fit);
        CHECK(fit.scale == 1 && fit.target == 1.25 * ref.bytes &&
                  ref.bytes / lc_fit_jpeg_share(ref.quality) * lc_fit_jpeg_share(fit.quality) <= fit.target + 1e-9,
              "a probe step stays within a quarter more bytes (%d -> %d)", ref.quality, fit.quality);
        ref.bytes *= lc_fit_jpeg_share(fit.quality) / lc_fit_jpeg_share(ref.quality);
        ref.quality = fit.quality, steps++;
    }
    CHECK(ref.quality == 85 && steps >= 2 && steps <= 4, "the ceiling after %d frames", steps);
    /* A larger rung of the ladder (twice the pixels) is no probe: its quality stays. */
    lc_stream_fit(0, 0, 0.070, &ref, 2e5, 85, &fit);
    CHECK(fit.quality == 85 && fit.scale == 1, "twice the pixels, not measured: 85 (%d)", fit.quality);
    /* A smaller rung after a gesture's first frame (10 kB at 45, then half the
     * pixels): the probe is a quarter more bytes per pixel, not the ceiling. */
    ref = (lc_fit_ref){10000, 45, 2e5, false};
    lc_stream_fit(0, 0, 0.070, &ref, 1e5, 85, &fit);
    double per_share = 10000 / lc_fit_jpeg_share(45) * 0.5;
    CHECK(fabs(fit.target - 6250) < 1e-6 && fit.quality > 45 && fit.quality < 70 &&
              per_share * lc_fit_jpeg_share(fit.quality) <= 6250 &&
              per_share * lc_fit_jpeg_share(fit.quality + 1) > 6250,
          "half the pixels: quality %d, %.0f B", fit.quality, fit.target);
    /* Measured 2 Mbit/s against a 70 ms budget: 7 kB a frame (28 ms of it).
     * 10 kB at 85 -> quality drops, size stays. */
    double t2 = 250000 * 0.070 * LC_FIT_SHARE;
    ref = (lc_fit_ref){10000, 85, 1e5, false};
    lc_stream_fit(250000, 0, 0.070, &ref, 1e5, 85, &fit);
    per_share = 10000 / lc_fit_jpeg_share(85);
    CHECK(fabs(fit.target - t2) < 1e-6 && fabs(t2 - 7000) < 1e-6 && fit.scale == 1 &&
              fit.quality > LC_FIT_MIN_QUALITY && fit.quality < 70 &&
              per_share * lc_fit_jpeg_share(fit.quality) <= t2 && per_share * lc_fit_jpeg_share(fit.quality + 1) > t2,
          "2 Mbit/s: the highest quality that fits, full size (%d)", fit.quality);
    /* 0.5 Mbit/s: 1.75 kB; quality 30 does not fit: the floor, and the side by the square root. */
    lc_stream_fit(62500, 0, 0.070, &ref, 1e5, 85, &fit);
    double want = sqrt(62500 * 0.070 * LC_FIT_SHARE / (per_share * lc_fit_jpeg_share(LC_FIT_MIN_QUALITY)));
    CHECK(fit.quality == LC_FIT_MIN_QUALITY && fabs(fit.scale - want) < 1e-9 && fit.scale < 1,
          "0.5 Mbit/s: quality %d, side x %.3f (%.3f)", fit.quality, fit.scale, want);
    lc_stream_fit(12500, 0, 0.070, &ref, 1e5, 85, &fit);
    CHECK(fit.quality == LC_FIT_MIN_QUALITY && fit.scale == LC_FIT_MIN_SCALE, "0.1 Mbit/s: the least side (%.3f)",
          fit.scale);
    lc_stream_fit(62500, 0, 0.070, &ref, 1e5, 20, &fit);
    CHECK(fit.quality == 20, "a ceiling under the floor holds (%d)", fit.quality);
    /* Not measured, a lower bound of 2 Mbit/s: probing never aims under the 7 kB it surely carries. */
    ref = (lc_fit_ref){5000, 40, 1e5, false};
    lc_stream_fit(0, 250000, 0.070, &ref, 1e5, 85, &fit);
    CHECK(fabs(fit.target - t2) < 1e-6, "the lower bound over the probe: %.0f B", fit.target);
    /* Before any moving frame: from the still (150 kB at 90, 972x761) and the bound the still gave. */
    ref = (lc_fit_ref){150000, 90, 972.0 * 761, true};
    lc_stream_fit(0, 0, 0.070, &ref, 243.0 * 190, 85, &fit);
    CHECK(fit.quality == 85 && fit.scale == 1, "a still and no bound: the ceiling (%d)", fit.quality);
    lc_stream_fit(0, 125000, 0.070, &ref, 243.0 * 190, 85, &fit);
    per_share = 150000 / lc_fit_jpeg_share(90) * (243.0 * 190) / (972.0 * 761);
    double t1 = 125000 * 0.070 * LC_FIT_SHARE;
    CHECK(fabs(fit.target - t1) < 1e-6 && fit.quality < 85 && per_share * lc_fit_jpeg_share(fit.quality) <= t1 &&
              per_share * lc_fit_jpeg_share(fit.quality + 1) > t1,
          "a still's bound of 1 Mbit/s: the first moving frame at quality %d, not the ceiling", fit.quality);

    /* Through a session: acks of a narrow link make the moving frames
     * smaller and coarser; the still keeps full quality and size. */
    lc_stream_conn conn = {.authed = true};
    char reply[4096];
    lc_stream_outcome o = send_text(
        &conn, "{\"type\":\"hello\",\"dataset\":\"demo:points\",\"width\":200,\"height\":160}", reply, sizeof reply);
    lc_session *s = conn.session;
    CHECK(o.opened && s, "a session (%s)", reply);
    if (!s)
        return;
    lc_stream_frame g;
    double wake = 0, ack = lc_now() + 0.2, first_w = 0;
    int first_q = 0;
    for (int i = 0; i < 12; i++, ack += 0.080) {
        lc_session_stream_input(s, lc_now());
        if (lc_session_stream_next(s, lc_now(), &g, &wake) != 1 || !g.interactive) {
            CHECK(0, "moving frame %d due", i);
            break;
        }
        if (i == 0)
            first_q = g.quality, first_w = g.req.render.width;
        finish(s, &g, true); /* 1000 bytes each, acked 80 ms apart after a 200 ms first: 12.5 kB/s */
        lc_session_stream_client_ack(s, g.frame, ack);
    }
    bool m = false;
    double r = lc_stream_flow_link_rate(&s->stream.flow, &m);
    CHECK(m && fabs(r - 12500) < 0.03 * 12500, "the session measured the link (%.0f B/s)", r);
    lc_session_stream_input(s, lc_now());
    CHECK(lc_session_stream_next(s, lc_now(), &g, &wake) == 1 && g.interactive, "one more moving frame");
    CHECK(first_q == LC_PROTO_DEFAULT_INTERACTIVE_QUALITY && g.quality == LC_FIT_MIN_QUALITY &&
              g.req.render.width < first_w,
          "moving: quality %d -> %d, width %.0f -> %d", first_q, g.quality, first_w, g.req.render.width);
    finish(s, &g, true);
    lc_session_stream_client_ack(s, g.frame, ack);
    CHECK(lc_session_stream_next(s, lc_now() + 2 * srv.cfg.still_delay + 1, &g, &wake) == 1 && !g.interactive,
          "then the still");
    CHECK(g.quality == LC_PROTO_DEFAULT_QUALITY && g.req.render.width == 200 && g.req.render.height == 160,
          "the still: full quality and size (%d, %dx%d)", g.quality, g.req.render.width, g.req.render.height);
    finish(s, &g, true);
    CHECK(!lc_session_stream_sent(s, g.frame - 1, 500, 90, 100) && s->stream.last_sent == g.frame,
          "a frame older than one already handed over does not go out");
    lc_stream_stats st;
    memset(&st, 0, sizeof st);
    lc_stream_stats_frame(&st, lc_now(), 1, 1);
    char *text = lc_stream_stats_message(&st, s, 0, lc_now());
    CHECK(text && strstr(text, "\"linkMbps\":0.1,") && strstr(text, "\"linkMeasured\":true"),
          "stats carry the link's rate, measured (%s)", text ? text : "");
    free(text);
    lc_session_close(srv.sessions, s);
    lc_session_unref(s);
}

/* Until a moving frame has gone out, fits come from the still and never
 * climb: a session's first moving frame starts with the still in flight (the
 * ceiling: nothing known), the still's slow ack brings the next one down, and
 * the one after, at a coarser rung (fewer pixels, which the still's bytes per
 * pixel would fill at a higher quality), keeps that quality. */
static void test_fit_from_still(void)
{
    lc_stream_conn conn = {.authed = true};
    char reply[4096];
    lc_stream_outcome o = send_text(
        &conn, "{\"type\":\"hello\",\"dataset\":\"demo:points\",\"width\":200,\"height\":160}", reply, sizeof reply);
    lc_session *s = conn.session;
    CHECK(o.opened && s, "a session (%s)", reply);
    if (!s)
        return;
    lc_stream_frame still, a, b, c;
    double wake = 0;
    lc_frame_info info;
    memset(&info, 0, sizeof info);
    info.converged = 1;
    info.wall_ms = 10;
    CHECK(lc_session_stream_next(s, lc_now(), &still, &wake) == 1 && !still.interactive, "the first still");
    lc_session_stream_done(s, &still, true, &info);
    lc_session_stream_sent(s, still.frame, 1000, still.quality, 200L * 160);
    lc_session_stream_input(s, lc_now());
    CHECK(lc_session_stream_next(s, lc_now(), &a, &wake) == 1 && a.interactive, "a moving frame");
    CHECK(a.quality == LC_PROTO_DEFAULT_INTERACTIVE_QUALITY, "the still not acked yet: the ceiling (%d)", a.quality);
    info.reused_opacities = 1;
    lc_session_stream_done(s, &a, false, &info); /* it failed: its place in the window is free, nothing went out */
    lc_session_stream_client_ack(s, still.frame, lc_now() + 0.2); /* 1000 bytes in 0.2 s: 5 kB/s at least */
    lc_session_stream_input(s, lc_now());
    CHECK(lc_session_stream_next(s, lc_now(), &b, &wake) == 1 && b.interactive, "a second moving frame");
    CHECK(b.quality < a.quality, "the still's bound brings it down (%d -> %d)", a.quality, b.quality);
    info.wall_ms = 1000; /* over the budget: the ladder goes coarser */
    lc_session_stream_done(s, &b, true, &info);
    lc_session_stream_input(s, lc_now());
    CHECK(lc_session_stream_next(s, lc_now(), &c, &wake) == 1 && c.interactive, "a third moving frame");
    double pb = (double)b.req.render.width * b.req.render.height, pc = (double)c.req.render.width * c.req.render.height;
    bool measured;
    double rate = lc_stream_flow_link_rate(&s->stream.flow, &measured);
    lc_fit again;
    lc_stream_fit(measured ? rate : 0, measured ? 0 : rate, srv.cfg.frame_budget_ms / 1000.0, &s->stream.fit_ref,
                  pc / (s->stream.fit.scale * s->stream.fit.scale), LC_PROTO_DEFAULT_INTERACTIVE_QUALITY, &again);
    CHECK(pc < pb && again.quality > b.quality && c.quality == b.quality,
          "fewer pixels (%.0f -> %.0f) would take %d from the still; it keeps %d (%d)", pb, pc, again.quality,
          b.quality, c.quality);
    lc_session_close(srv.sessions, s);
    lc_session_unref(s);
}

/* The pace of input on the session's own clock: steps 200 ms apart whose
 * params and camera arrive 15 ms apart (a busy client) keep a pace of about
 * 200 ms, so the still waits about 300 ms, past the next step; a drag that
 * follows at 30 ms a message takes its faster pace within a few messages. */
static void test_input_pace(lc_session *s)
{
    pthread_mutex_lock(&s->lock);
    lc_stream saved = s->stream; /* the tests after this one start from the session as hello left it */
    double used = s->last_used, t = lc_now() - 10.0;
    s->stream.any_input = false;
    pthread_mutex_unlock(&s->lock);
    lc_session_stream_input(s, t - 2.0); /* the still before the steps */
    for (int k = 0; k < 12; k++, t += 0.200) {
        lc_session_stream_input(s, t);         /* params */
        lc_session_stream_input(s, t + 0.015); /* camera */
        if (k == 1)
            CHECK(s->stream.input_interval > 0.18 && s->stream.input_interval < 0.22,
                  "the first two split steps give their 200 ms pace (%.3f s)", s->stream.input_interval);
    }
    CHECK(s->stream.input_interval > 0.18 && s->stream.input_interval < 0.22,
          "split steps keep their 200 ms pace (%.3f s)", s->stream.input_interval);
    for (int k = 0; k < 16; k++, t += 0.030)
        lc_session_stream_input(s, t);
    CHECK(s->stream.input_interval < 0.06, "a 30 ms drag after them takes its own pace (%.3f s)",
          s->stream.input_interval);
    for (int k = 0; k < 12; k++, t += 0.016)
        lc_session_stream_input(s, t);
    CHECK(s->stream.input_interval < 0.025, "and a 60 Hz drag its own (%.3f s)", s->stream.input_interval);
    pthread_mutex_lock(&s->lock);
    s->stream = saved;
    s->last_used = used;
    pthread_mutex_unlock(&s->lock);
}

int main(void)
{
    if (test_daemon(&srv, 3000) != 0)
        return 1;
    lc_stream_conn conn = {.authed = true};
    char reply[4096];
    lc_stream_outcome o =
        send_text(&conn, "{\"type\":\"camera\",\"seq\":1,\"camera\":{\"position\":[0,0,5]}}", reply, sizeof reply);
    CHECK(o.bad && strstr(reply, "bad_state"), "a message before hello is refused (%s)", reply);
    o = send_text(&conn, "{not json", reply, sizeof reply);
    CHECK(o.bad && !o.valid && reply[0], "garbage counts as a bad message");
    o = send_text(&conn,
                  "{\"type\":\"hello\",\"dataset\":\"demo:points\",\"width\":100,\"height\":80,\"devicePixelRatio\":1,"
                  "\"window\":2}",
                  reply, sizeof reply);
    CHECK(o.opened && o.valid && o.wake && conn.session && strstr(reply, "\"ready\""), "hello opens a session (%s)",
          reply);
    if (!conn.session)
        return lc_test_finish();
    lc_session *s = conn.session;
    CHECK(s->stream.window == 2 && s->req.render.width == 100 && s->req.render.height == 80,
          "window 2, a 100x80 frame (%d, %dx%d)", s->stream.window, s->req.render.width, s->req.render.height);
    o = send_text(&conn, "{\"type\":\"hello\",\"dataset\":\"demo:points\",\"width\":10,\"height\":10}", reply,
                  sizeof reply);
    CHECK(!o.opened && strstr(reply, "bad_state"), "a second hello is refused");
    test_input_pace(s);
    test_window(s);
    test_latest_wins(&conn);
    test_convergence(s);
    test_staged(s);
    test_ladder(s);
    test_budget(&conn);
    test_flow_window();
    test_session_window();
    test_link_fit();
    test_fit_from_still();
    lc_session_close(srv.sessions, s);
    lc_session_unref(s);
    test_daemon_free(&srv);
    return lc_test_finish();
}
