/* The stream protocol: hello, camera, params, resize and ack as session changes (stream.h). */
#include "stream.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "admit.h"
#include "auth.h"
#include "cost.h"
#include "messages.h"
#include "metrics.h"
#include "stream_session.h"
#include "traced.h"

#define MOD "ws"

/* An error answer; a fatal one closes the connection with close_code after it. */
static void answer_error(lc_server *srv, lc_stream_outcome *out, const char *code, const char *message,
                         const char *field, bool fatal, uint16_t close_code)
{
    lc_metrics_error(srv->metrics, code);
    free(out->reply);
    out->reply = lc_proto_error_message_json(code, message, field, fatal);
    if (fatal) {
        out->close_code = close_code;
        snprintf(out->close_reason, sizeof out->close_reason, "%s", code);
    }
}

static void answer_proto_error(lc_server *srv, lc_stream_outcome *out, const lc_proto_error *pe)
{
    answer_error(srv, out, pe->code, pe->message, pe->field, false, 0);
}

static void on_hello(lc_server *srv, const lc_proto_limits *lim, lc_stream_conn *conn, lc_client_msg *m,
                     lc_stream_outcome *out)
{
    if (conn->session) {
        answer_error(srv, out, "bad_state", "hello was already received on this connection", "type", false, 0);
        return;
    }
    if (!conn->authed) {
        if (!m->has_token || !lc_serve_token_ok(srv, m->token)) {
            answer_error(srv, out, "unauthorized", "missing or wrong token", "token", true, 1008);
            return;
        }
        conn->authed = true;
    }
    /* The full-size frame of the viewport: its cost decides, and it is the
     * session's request size from here on (an update cannot set the size). */
    lc_request base, req;
    lc_request_default(&base);
    snprintf(base.dataset, sizeof base.dataset, "%s", m->dataset);
    base.format = LC_FORMAT_JPEG;
    lc_stream_frame_size(&srv->cfg, m->width, m->height, m->device_pixel_ratio, 1.0, &base.render.width,
                         &base.render.height);
    const lc_dataset *layers[LC_MAX_LAYERS], *ds = NULL;
    lc_proto_error pe;
    lc_traced *traced = NULL; /* a vector field's streamline set, traced now and kept by the session (traced.h) */
    int rc = lc_admit_update(srv, &base, m->patch, lim, &ds, &req, layers, &traced, &pe);
    /* A file the daemon holds opens at defaults: where a full-size frame is
     * over --max-cost but the optimization's stride brings it within, the
     * session starts with that params.subset (ready's defaults show it; the
     * client may change it), unless the hello chose a subset itself. */
    const json_t *given = m->update ? json_object_get(json_object_get(m->update, "params"), "subset") : NULL;
    int n = rc && strcmp(pe.code, "too_expensive") == 0 && !lc_request_layer_count(&req) && !given
                ? lc_cost_subset_for(&ds->cost, &req.render, srv->cfg.max_cost)
                : 0;
    if (n > 0) {
        base.render.foo.subset = n;
        ds = NULL;
        lc_traced_free(traced);
        traced = NULL;
        lc_request_release(&req);
        rc = lc_admit_update(srv, &base, m->patch, lim, &ds, &req, layers, &traced, &pe);
        if (rc == 0)
            LC_INFO(MOD, "%s opens with params.subset %d: a full frame of %dx%d is over --max-cost", ds->name, n,
                    req.render.width, req.render.height);
    }
    if (rc != 0) {
        lc_traced_free(traced);
        lc_request_release(&req);
        answer_proto_error(srv, out, &pe);
        return;
    }
    lc_stream_settings ss;
    lc_proto_stream_default(&ss);
    lc_proto_stream_apply(&ss, m);
    lc_error err = {0};
    lc_session *s = NULL;
    if (lc_session_create(srv->sessions, LC_SESSION_WS, conn->client, ds, &req, &s, &err) != 0) {
        lc_traced_free(traced);
        lc_request_release(&req);
        answer_error(srv, out, err.code == LC_ERR_LIMIT ? "too_many_sessions" : "internal", err.msg, NULL, true, 1013);
        return;
    }
    /* The hello's window is the most the client takes; the server keeps
     * fewer in flight while fewer cover the round trip (stream_flow.h).
     * Without one, the protocol's maximum. */
    if (!m->has_window)
        ss.window = LC_PROTO_MAX_WINDOW;
    pthread_mutex_lock(&s->lock);
    s->traced = traced;
    lc_stream_flow_init(&s->stream.flow, ss.window);
    s->stream.window = s->stream.flow.window;
    s->stream.quality = ss.quality;
    s->stream.interactive_quality = ss.interactive_quality;
    s->stream.interactive_scale = ss.interactive_scale;
    s->stream.css_width = m->width;
    s->stream.css_height = m->height;
    s->stream.device_pixel_ratio = m->device_pixel_ratio;
    s->stream.dirty = true; /* the first frame */
    lc_request_assign(&req, &s->req);
    pthread_mutex_unlock(&s->lock);
    conn->session = s;
    out->opened = true;
    json_t *info = lc_dataset_info(ds);
    out->reply = lc_proto_ready_json(s->id, info, &req, lim, &ss);
    json_decref(info);
    lc_request_release(&req);
    LC_INFO(MOD, "session %s: %s, %dx%d css px x %.2f, window %d", s->id, ds->name, m->width, m->height,
            m->device_pixel_ratio, ss.window);
    out->wake = true;
}

/* A camera or params message: the session's update (latest wins), then what
 * only the stream keeps (the camera's sequence number, the qualities). */
static void on_update(lc_server *srv, const lc_proto_limits *lim, lc_session *s, lc_client_msg *m, double now,
                      lc_stream_outcome *out)
{
    lc_proto_error pe;
    pthread_mutex_lock(&s->lock);
    int rc = lc_session_update_locked(s, m->patch, lim, NULL, &pe);
    if (rc == 0 && m->type == LC_MSG_CAMERA && m->seq > s->stream.camera_seq)
        s->stream.camera_seq = m->seq;
    if (rc == 0 && m->type == LC_MSG_PARAMS) {
        if (m->has_quality)
            s->stream.quality = m->quality;
        if (m->has_interactive_quality)
            s->stream.interactive_quality = m->interactive_quality;
        if (m->has_interactive_scale)
            s->stream.interactive_scale = m->interactive_scale;
    }
    pthread_mutex_unlock(&s->lock);
    if (rc != 0) {
        answer_proto_error(srv, out, &pe);
        return;
    }
    LC_DEBUG(MOD, "flow %s input %s seq %llu at %.4f", s->id, m->type == LC_MSG_CAMERA ? "camera" : "params",
             (unsigned long long)(m->type == LC_MSG_CAMERA ? m->seq : 0), now);
    lc_session_stream_input(s, now);
    out->wake = true;
}

/* A resize: the new viewport's full-size frame must fit the budget, as an update would. */
static void on_resize(lc_server *srv, lc_session *s, lc_client_msg *m, double now, lc_stream_outcome *out)
{
    lc_proto_error pe;
    pthread_mutex_lock(&s->lock);
    double dpr = m->has_device_pixel_ratio ? m->device_pixel_ratio : s->stream.device_pixel_ratio;
    lc_request req[2]; /* the size as base, the candidate; both share the session's layers */
    const lc_dataset *layers[LC_MAX_LAYERS], *ds = s->dataset;
    /* no field changes: the size's own refusals (a larger frame costs more: wider ribbons) */
    lc_request_copy(&req[0], &s->req);
    lc_stream_frame_size(&srv->cfg, m->width, m->height, dpr, 1.0, &req[0].render.width, &req[0].render.height);
    int rc = lc_admit_update(srv, &req[0], NULL, &srv->cfg.limits, &ds, &req[1], layers, NULL, &pe);
    lc_request_release(&req[0]);
    lc_request_release(&req[1]);
    if (rc == 0) {
        s->stream.css_width = m->width;
        s->stream.css_height = m->height;
        s->stream.device_pixel_ratio = dpr;
    }
    pthread_mutex_unlock(&s->lock);
    if (rc != 0) {
        answer_proto_error(srv, out, &pe);
        return;
    }
    lc_session_stream_input(s, now);
    out->wake = true;
}

void lc_stream_on_text(lc_server *srv, const lc_proto_limits *lim, lc_stream_conn *conn, const char *data, size_t len,
                       double arrived, lc_stream_outcome *out)
{
    memset(out, 0, sizeof *out);
    lc_client_msg m;
    lc_proto_error pe;
    if (lc_proto_parse_client_message(data, len, lim, &m, &pe) != 0) {
        answer_proto_error(srv, out, &pe);
        out->bad = true;
        return;
    }
    if (m.type != LC_MSG_HELLO && !conn->session) {
        answer_error(srv, out, "bad_state", "the first message must be a hello", "type", false, 0);
        lc_client_msg_free(&m);
        out->bad = true;
        return;
    }
    out->valid = true;
    lc_session *s = conn->session;
    double now = arrived;
    switch (m.type) {
    case LC_MSG_HELLO: on_hello(srv, lim, conn, &m, out); break;
    case LC_MSG_CAMERA:
    case LC_MSG_PARAMS: on_update(srv, lim, s, &m, now, out); break;
    case LC_MSG_RESIZE: on_resize(srv, s, &m, now, out); break;
    case LC_MSG_ACK:
        if (!lc_session_stream_client_ack(s, m.frame, now)) {
            char msg[128];
            snprintf(msg, sizeof msg, "frame %llu has not been sent", (unsigned long long)m.frame);
            answer_error(srv, out, LC_PROTO_OUT_OF_RANGE, msg, "frame", false, 0);
            out->bad = true;
            break;
        }
        out->wake = true;
        break;
    }
    lc_client_msg_free(&m);
}

/* ---------------------------------------------------------------- stats */

void lc_stream_stats_frame(lc_stream_stats *st, double now, double render_ms, double encode_ms)
{
    size_t i = (size_t)(st->frames % LC_STREAM_STATS_SAMPLES);
    st->sent_at[i] = now;
    st->render_ms[i] = render_ms;
    st->encode_ms[i] = encode_ms;
    st->frames++;
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* Milliseconds rounded to the microsecond: enough for a status line. */
static json_t *ms_json(double ms) { return json_real(round(ms * 1000.0) / 1000.0); }

bool lc_stream_stats_due(const lc_stream_stats *st, double now)
{
    return st->frames > st->frames_at_report && now - st->last_report >= LC_STREAM_STATS_INTERVAL;
}

char *lc_stream_stats_message(lc_stream_stats *st, lc_session *s, int render_queue, double now)
{
    uint64_t fresh = st->frames - st->frames_at_report;
    /* Timing figures over the frames since the last report (the latest
     * LC_STREAM_STATS_SAMPLES of them); fps over the last second. */
    int n = fresh < LC_STREAM_STATS_SAMPLES ? (int)fresh : LC_STREAM_STATS_SAMPLES;
    int held = st->frames < LC_STREAM_STATS_SAMPLES ? (int)st->frames : LC_STREAM_STATS_SAMPLES;
    double render[LC_STREAM_STATS_SAMPLES], render_sum = 0, encode_sum = 0;
    int fps = 0;
    for (int k = 0; k < held; k++) {
        size_t i = (size_t)((st->frames - 1 - (uint64_t)k) % LC_STREAM_STATS_SAMPLES);
        if (now - st->sent_at[i] <= 1.0)
            fps++;
        if (k < n) {
            render[k] = st->render_ms[i];
            render_sum += st->render_ms[i];
            encode_sum += st->encode_ms[i];
        }
    }
    qsort(render, (size_t)n, sizeof render[0], cmp_double);
    double p50 = n % 2 ? render[n / 2] : 0.5 * (render[n / 2 - 1] + render[n / 2]);
    pthread_mutex_lock(&s->lock);
    uint64_t dropped = s->stream.coalesced;
    int unacked = s->stream.unacked, window = s->stream.window;
    double rtt = s->stream.flow.rtt, frame_s = s->stream.flow.frame_s;
    bool measured;
    double rate = lc_stream_flow_link_rate(&s->stream.flow, &measured);
    pthread_mutex_unlock(&s->lock);

    json_t *f = json_object();
    json_object_set_new(f, "framesSent", json_integer((json_int_t)st->frames));
    json_object_set_new(f, "framesDropped", json_integer((json_int_t)dropped));
    json_object_set_new(f, "fps", json_integer(fps));
    json_object_set_new(f, "renderMs", ms_json(render_sum / n));
    json_object_set_new(f, "renderP50Ms", ms_json(p50));
    json_object_set_new(f, "encodeMs", ms_json(encode_sum / n));
    json_object_set_new(f, "queue", json_integer(render_queue));
    json_object_set_new(f, "unacked", json_integer(unacked));
    json_object_set_new(f, "window", json_integer(window));
    json_object_set_new(f, "rttMs", rtt > 0 ? ms_json(1000.0 * rtt) : json_null());
    json_object_set_new(f, "frameMs", frame_s > 0 ? ms_json(1000.0 * frame_s) : json_null());
    /* Megabits per second to the kilobit: the link's rate, or what it carried. */
    json_object_set_new(f, "linkMbps", rate > 0 ? json_real(round(rate * 8e-3) / 1000.0) : json_null());
    json_object_set_new(f, "linkMeasured", json_boolean(measured));
    json_object_set_new(f, "bytesSent", json_integer((json_int_t)st->bytes));
    json_object_set_new(f, "interval", json_real(round((now - st->last_report) * 1000.0) / 1000.0));
    char *text = lc_proto_stats_json(f);
    json_decref(f);
    st->frames_at_report = st->frames;
    st->last_report = now;
    return text;
}

/* ---------------------------------------------------------------- progress */

/* The stage of a progress message: a pass (named as in the frame header's
 * timings), or the work around the passes. */
static const char *stage_name(int stage)
{
    if (stage == LC_PROGRESS_ENCODE)
        return "encode";
    if (stage == LC_PROGRESS_PREPARE)
        return "prepare";
    return lc_pass_name(stage);
}

char *lc_stream_progress_message(lc_stream_progress_report *pr, lc_session *s, uint64_t frames_sent, double now)
{
    if (now - pr->sent_at < LC_STREAM_PROGRESS_INTERVAL)
        return NULL;
    uint64_t frame = atomic_load(&s->progress.frame);
    double begun = (double)atomic_load(&s->progress.begun_us) * 1e-6;
    pthread_mutex_lock(&s->lock);
    uint64_t sent = s->stream.last_sent;
    pthread_mutex_unlock(&s->lock);
    bool under_way = frame > sent; /* frame ids start at 1 */
    bool first = frames_sent == 0;
    double since = first ? pr->hello_at : begun;
    if ((!first && !under_way) || now - since < LC_STREAM_PROGRESS_AFTER)
        return NULL;
    if (first && !under_way && frame != 0)
        return NULL; /* the first frame is rendered and on its way out, not queued (nor sent: frames_sent is 0) */
    int stage = under_way ? atomic_load(&s->progress.stage) : LC_PROGRESS_PREPARE;
    if (stage == LC_PROGRESS_NONE)
        return NULL; /* the frame failed: an error message says so */
    int done = atomic_load(&s->progress.done), planned = atomic_load(&s->progress.planned);
    double fraction = under_way && planned > 0 && stage != LC_PROGRESS_PREPARE ? (double)done / planned : -1;
    if (frame != pr->frame)
        pr->frame = frame, pr->fraction = -1;
    /* The worker writes stage, done and planned one by one: never step back. */
    if (fraction < pr->fraction)
        fraction = pr->fraction;
    pr->fraction = fraction;
    pr->sent_at = now;
    return lc_proto_progress_json(under_way ? stage_name(stage) : "queued", fraction, now - since);
}
