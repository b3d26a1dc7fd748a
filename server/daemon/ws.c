/* WebSocket I/O thread: upgraded sockets, wslay framing, the session protocol
 * (hello/camera/params/resize/ack) and delivery of frames from the encoders. */
#include "ws.h"

#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <microhttpd.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/epoll.h>
#include <sys/eventfd.h>
#include <sys/socket.h>
#include <unistd.h>
#include <wslay/wslay.h>

#include "messages.h"
#include "metrics.h"
#include "workers.h"

#define MOD "ws"
#define PING_INTERVAL 15.0           /* seconds of silence before we ping */
#define CLOSE_GRACE 2.0              /* seconds a client gets to answer our close frame */
#define MAX_QUEUED_BYTES (32u << 20) /* per connection, beyond the frame window: not reading */
#define MAX_QUEUED_MSGS 256
#define MAX_CONSECUTIVE_ERRORS 32
#define WS_SNDBUF (256 << 10)
#define HELLO_TIMEOUT 10.0 /* seconds an upgraded connection may hold a slot without a session */
#define STATS_INTERVAL 1.0 /* seconds between stats messages while frames flow */
#define STATS_SAMPLES 256  /* latest frames remembered for fps and timing figures */

/* What a connection's stats messages report (I/O thread only). The rings hold
 * the latest frames, indexed by frame count modulo STATS_SAMPLES. */
typedef struct stream_stats {
    uint64_t frames;                 /* frame messages queued to the socket */
    uint64_t bytes;                  /* bytes of every message queued */
    double sent_at[STATS_SAMPLES];   /* lc_now() when each frame was queued */
    double render_ms[STATS_SAMPLES]; /* its render worker wall time */
    double encode_ms[STATS_SAMPLES]; /* its encode time */
    uint64_t frames_at_report;       /* frames when the last stats message went out */
    double last_report;              /* lc_now() of that message (of hello before the first) */
} stream_stats;

typedef struct conn {
    struct conn *prev, *next;
    lc_ws *ws;
    int fd;
    struct MHD_UpgradeResponseHandle *urh;
    wslay_event_context_ptr ctx;
    char *extra; /* bytes MHD read past the handshake */
    size_t extra_len, extra_off;
    bool authed;
    lc_session *session; /* after hello; holds a reference */
    double last_rx, last_ping;
    double close_deadline; /* > 0 once closing: the connection goes by then at the latest */
    uint16_t close_code;   /* close frame to send once the queued messages are out */
    char close_reason[64];
    int errors;      /* consecutive bad messages */
    bool draining;   /* close sent and our side shut down: read and drop until the peer closes */
    double opened;   /* lc_now() at registration (the hello deadline) */
    uint32_t events; /* registered epoll events */
    stream_stats stats;
} conn;

typedef struct inbox_item {
    struct inbox_item *next;
    conn *adopt;         /* a new connection to register */
    lc_session *session; /* or a message for this session's connection */
    unsigned char *msg;
    size_t len;
    bool binary;
    bool frame; /* a frame message: count it in the stats */
    double render_ms, encode_ms;
} inbox_item;

struct lc_ws {
    lc_server *srv;
    lc_proto_limits limits; /* server limits with max_text = max WS message */
    int epfd, evfd;
    pthread_t thread;
    bool started;
    conn *conns;          /* I/O thread only */
    int nconns;           /* I/O thread writes; read racily for metrics */
    pthread_mutex_t lock; /* guards inbox and shutting_down */
    inbox_item *inbox_head, *inbox_tail;
    bool shutting_down;
    double shutdown_deadline;
};

static void wake(lc_ws *ws)
{
    uint64_t one = 1;
    ssize_t n = write(ws->evfd, &one, sizeof one);
    (void)n; /* a full counter still wakes the thread */
}

static void push_inbox(lc_ws *ws, inbox_item *it)
{
    pthread_mutex_lock(&ws->lock);
    it->next = NULL;
    if (ws->inbox_tail)
        ws->inbox_tail->next = it;
    else
        ws->inbox_head = it;
    ws->inbox_tail = it;
    pthread_mutex_unlock(&ws->lock);
    wake(ws);
}

static inbox_item *new_message(lc_ws *ws, lc_session *s, unsigned char *msg, size_t len, bool binary)
{
    inbox_item *it = ws ? calloc(1, sizeof *it) : NULL;
    if (!it) {
        free(msg);
        return NULL;
    }
    lc_session_ref(s);
    it->session = s;
    it->msg = msg;
    it->len = len;
    it->binary = binary;
    return it;
}

void lc_ws_send(lc_ws *ws, lc_session *s, unsigned char *msg, size_t len, bool binary)
{
    inbox_item *it = new_message(ws, s, msg, len, binary);
    if (it)
        push_inbox(ws, it);
}

void lc_ws_send_frame(lc_ws *ws, lc_session *s, unsigned char *msg, size_t len, double render_ms, double encode_ms)
{
    inbox_item *it = new_message(ws, s, msg, len, true);
    if (!it)
        return;
    it->frame = true;
    it->render_ms = render_ms;
    it->encode_ms = encode_ms;
    push_inbox(ws, it);
}

int lc_ws_connections(lc_ws *ws) { return ws ? ws->nconns : 0; }

/* ---------------------------------------------------------------- wslay glue */

static ssize_t recv_cb(wslay_event_context_ptr ctx, uint8_t *buf, size_t len, int flags, void *user)
{
    (void)flags;
    conn *c = user;
    if (c->extra_off < c->extra_len) {
        size_t n = c->extra_len - c->extra_off;
        if (n > len)
            n = len;
        memcpy(buf, c->extra + c->extra_off, n);
        c->extra_off += n;
        return (ssize_t)n;
    }
    ssize_t n;
    do
        n = recv(c->fd, buf, len, 0);
    while (n < 0 && errno == EINTR);
    if (n < 0) {
        wslay_event_set_error(ctx, (errno == EAGAIN || errno == EWOULDBLOCK) ? WSLAY_ERR_WOULDBLOCK
                                                                             : WSLAY_ERR_CALLBACK_FAILURE);
        return -1;
    }
    if (n == 0) { /* peer closed without a close frame */
        wslay_event_set_error(ctx, WSLAY_ERR_CALLBACK_FAILURE);
        return -1;
    }
    c->last_rx = lc_now();
    return n;
}

static ssize_t send_cb(wslay_event_context_ptr ctx, const uint8_t *data, size_t len, int flags, void *user)
{
    (void)flags;
    conn *c = user;
    ssize_t n;
    do
        n = send(c->fd, data, len, MSG_NOSIGNAL);
    while (n < 0 && errno == EINTR);
    if (n < 0) {
        wslay_event_set_error(ctx, (errno == EAGAIN || errno == EWOULDBLOCK) ? WSLAY_ERR_WOULDBLOCK
                                                                             : WSLAY_ERR_CALLBACK_FAILURE);
        return -1;
    }
    return n;
}

/* Queues a message on c (I/O thread). Returns 0, or -1 when c must go. */
static int queue_msg(conn *c, uint8_t opcode, const void *data, size_t len)
{
    if (c->close_deadline > 0)
        return 0; /* closing: nothing more goes out */
    if (wslay_event_get_queued_msg_length(c->ctx) + len > MAX_QUEUED_BYTES ||
        wslay_event_get_queued_msg_count(c->ctx) >= MAX_QUEUED_MSGS) {
        LC_WARN(MOD, "%s: client is not reading (%zu bytes queued), disconnecting",
                c->session ? c->session->id : "connection", wslay_event_get_queued_msg_length(c->ctx));
        return -1;
    }
    struct wslay_event_msg m = {.opcode = opcode, .msg = data, .msg_length = len};
    if (wslay_event_queue_msg(c->ctx, &m) != 0)
        return -1;
    lc_metrics_bytes_sent(c->ws->srv->metrics, len);
    c->stats.bytes += len;
    return 0;
}

/* Closes with a close frame after the messages already queued (wslay sends
 * control frames ahead of data, so the close is queued by conn_flush only once
 * the data queue is empty; a fatal error message thus reaches the client). */
static void close_with(conn *c, uint16_t code, const char *reason)
{
    if (c->close_deadline > 0)
        return;
    c->close_code = code;
    snprintf(c->close_reason, sizeof c->close_reason, "%s", reason);
    c->close_deadline = lc_now() + CLOSE_GRACE;
}

/* Sends an error message; fatal ones close the connection afterwards. */
static void send_error(conn *c, const char *code, const char *message, const char *field, bool fatal,
                       uint16_t close_code)
{
    lc_metrics_error(c->ws->srv->metrics, code);
    char *text = lc_proto_error_message_json(code, message, field, fatal);
    if (text) {
        queue_msg(c, WSLAY_TEXT_FRAME, text, strlen(text));
        free(text);
    }
    if (fatal)
        close_with(c, close_code, code);
}

static void send_proto_error(conn *c, const lc_proto_error *pe)
{
    send_error(c, pe->code, pe->message, pe->field, false, 0);
}

/* Counts one more bad message in a row; too many close the connection. */
static void count_error(conn *c)
{
    if (++c->errors > MAX_CONSECUTIVE_ERRORS)
        send_error(c, "too_many_errors", "too many invalid messages in a row", NULL, true, 1008);
}

/* ---------------------------------------------------------------- stats */

static void record_frame(conn *c, double now, double render_ms, double encode_ms)
{
    stream_stats *st = &c->stats;
    size_t i = (size_t)(st->frames % STATS_SAMPLES);
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

/* Sends a stats message when frames went out since the last one and that one
 * is at least STATS_INTERVAL old: about once a second while frames flow, and a
 * last one after they stop (from the tick). Returns 1 when a message was
 * queued, 0 when none was due, -1 when c must go (its client is not reading). */
static int maybe_send_stats(conn *c, double now)
{
    stream_stats *st = &c->stats;
    lc_session *s = c->session;
    uint64_t fresh = st->frames - st->frames_at_report;
    if (!s || fresh == 0 || c->close_deadline > 0 || now - st->last_report < STATS_INTERVAL)
        return 0;
    /* Timing figures over the frames since the last report (the latest
     * STATS_SAMPLES of them); fps over the last second. */
    int n = fresh < STATS_SAMPLES ? (int)fresh : STATS_SAMPLES;
    int held = st->frames < STATS_SAMPLES ? (int)st->frames : STATS_SAMPLES;
    double render[STATS_SAMPLES], render_sum = 0, encode_sum = 0;
    int fps = 0;
    for (int k = 0; k < held; k++) {
        size_t i = (size_t)((st->frames - 1 - (uint64_t)k) % STATS_SAMPLES);
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
    int render_queue = 0, encode_queue = 0;
    lc_workers_depths(c->ws->srv->workers, &render_queue, &encode_queue);
    pthread_mutex_lock(&s->lock);
    uint64_t dropped = s->stream.coalesced;
    int unacked = s->stream.unacked, window = s->stream.window;
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
    json_object_set_new(f, "bytesSent", json_integer((json_int_t)st->bytes));
    json_object_set_new(f, "interval", json_real(round((now - st->last_report) * 1000.0) / 1000.0));
    char *text = lc_proto_stats_json(f);
    json_decref(f);
    st->frames_at_report = st->frames;
    st->last_report = now;
    if (!text)
        return 0;
    int rc = queue_msg(c, WSLAY_TEXT_FRAME, text, strlen(text));
    free(text);
    return rc == 0 ? 1 : -1;
}

/* ---------------------------------------------------------------- protocol */

/* 0 when a full-resolution frame of req fits --max-cost, else an error that
 * names the field to lower (the update is then not applied). */
static int within_budget(lc_server *srv, const lc_dataset *ds, const lc_request *req, lc_proto_error *pe)
{
    double cost;
    const char *field = NULL;
    char why[320];
    if (lc_cost_check(&ds->cost, &req->render, srv->cfg.max_cost, &cost, &field, why, sizeof why) == 0)
        return 0;
    lc_metrics_refused(srv->metrics, "cost");
    return lc_proto_set_error(pe, "too_expensive", field, "%s", why);
}

static void on_hello(conn *c, lc_client_msg *m)
{
    lc_server *srv = c->ws->srv;
    if (c->session) {
        send_error(c, "bad_state", "hello was already received on this connection", "type", false, 0);
        return;
    }
    if (!c->authed) {
        if (!m->has_token || !lc_serve_token_ok(srv, m->token)) {
            send_error(c, "unauthorized", "missing or wrong token", "token", true, 1008);
            return;
        }
        c->authed = true;
    }
    const lc_dataset *ds = lc_datasets_find(srv->datasets, m->dataset);
    if (!ds) {
        char msg[700];
        snprintf(msg, sizeof msg, "unknown dataset \"%s\"", m->dataset);
        send_error(c, "not_found", msg, "dataset", false, 0);
        return;
    }
    lc_request req;
    lc_request_default(&req);
    snprintf(req.dataset, sizeof req.dataset, "%s", ds->name);
    req.format = LC_FORMAT_JPEG;
    lc_proto_error pe;
    if (m->update && lc_proto_apply_request(m->update, &c->ws->limits, &req, &pe) != 0) {
        send_proto_error(c, &pe);
        return;
    }
    lc_session_frame_size(m->width, m->height, m->device_pixel_ratio, 1.0, srv->cfg.max_stream_pixels, &srv->cfg.limits,
                          &req.render.width, &req.render.height);
    if (within_budget(srv, ds, &req, &pe) != 0) {
        send_proto_error(c, &pe);
        return;
    }
    lc_stream_settings ss;
    lc_proto_stream_default(&ss);
    lc_proto_stream_apply(&ss, m);
    lc_error err = {0};
    lc_session *s = NULL;
    if (lc_session_create(srv->sessions, LC_SESSION_WS, ds, &req, &s, &err) != 0) {
        send_error(c, err.code == LC_ERR_LIMIT ? "too_many_sessions" : "internal", err.msg, NULL, true, 1013);
        return;
    }
    pthread_mutex_lock(&s->lock);
    s->stream.window = ss.window;
    s->stream.quality = ss.quality;
    s->stream.interactive_quality = ss.interactive_quality;
    s->stream.interactive_scale = ss.interactive_scale;
    s->stream.css_width = m->width;
    s->stream.css_height = m->height;
    s->stream.device_pixel_ratio = m->device_pixel_ratio;
    lc_session_frame_size(m->width, m->height, m->device_pixel_ratio, 1.0, srv->cfg.max_stream_pixels, &srv->cfg.limits,
                          &s->req.render.width, &s->req.render.height);
    s->stream.dirty = true; /* the first frame */
    req = s->req;
    pthread_mutex_unlock(&s->lock);
    c->session = s;
    s->ws_conn = c;
    c->stats.last_report = lc_now();
    json_t *info = lc_dataset_info(ds);
    char *ready = lc_proto_ready_json(s->id, info, &req, &c->ws->limits, &ss);
    json_decref(info);
    if (ready) {
        queue_msg(c, WSLAY_TEXT_FRAME, ready, strlen(ready));
        free(ready);
    }
    LC_INFO(MOD, "session %s: %s, %dx%d css px x %.2f, window %d", s->id, ds->name, m->width, m->height,
            m->device_pixel_ratio, ss.window);
    lc_workers_wake(srv->workers, s);
}

/* Applies a camera or params update to the session's request (latest wins). */
static int apply_update(conn *c, lc_client_msg *m)
{
    lc_session *s = c->session;
    lc_proto_error pe;
    int rc = 0;
    pthread_mutex_lock(&s->lock);
    lc_request req = s->req;
    if (m->update && (rc = lc_proto_apply_request(m->update, &c->ws->limits, &req, &pe)) == 0)
        rc = within_budget(c->ws->srv, s->dataset, &req, &pe);
    if (rc == 0)
        s->req = req;
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
    if (rc != 0)
        send_proto_error(c, &pe);
    return rc;
}

static void on_text(conn *c, const uint8_t *data, size_t len)
{
    lc_server *srv = c->ws->srv;
    lc_client_msg m;
    lc_proto_error pe;
    if (lc_proto_parse_client_message((const char *)data, len, &c->ws->limits, &m, &pe) != 0) {
        send_proto_error(c, &pe);
        count_error(c);
        return;
    }
    if (m.type != LC_MSG_HELLO && !c->session) {
        send_error(c, "bad_state", "the first message must be a hello", "type", false, 0);
        lc_client_msg_free(&m);
        count_error(c);
        return;
    }
    c->errors = 0;
    lc_session *s = c->session;
    double now = lc_now();
    switch (m.type) {
    case LC_MSG_HELLO: on_hello(c, &m); break;
    case LC_MSG_CAMERA:
    case LC_MSG_PARAMS:
        if (apply_update(c, &m) == 0) {
            lc_session_stream_input(s, now);
            lc_workers_wake(srv->workers, s);
        }
        break;
    case LC_MSG_RESIZE: {
        lc_proto_error pe;
        pthread_mutex_lock(&s->lock);
        double dpr = m.has_device_pixel_ratio ? m.device_pixel_ratio : s->stream.device_pixel_ratio;
        lc_request req = s->req; /* a larger frame costs more (wider ribbons): check it as an update */
        lc_session_frame_size(m.width, m.height, dpr, 1.0, srv->cfg.max_stream_pixels, &srv->cfg.limits,
                              &req.render.width, &req.render.height);
        int rc = within_budget(srv, s->dataset, &req, &pe);
        if (rc == 0) {
            s->stream.css_width = m.width;
            s->stream.css_height = m.height;
            s->stream.device_pixel_ratio = dpr;
        }
        pthread_mutex_unlock(&s->lock);
        if (rc != 0) {
            send_proto_error(c, &pe);
            break;
        }
        lc_session_stream_input(s, now);
        lc_workers_wake(srv->workers, s);
        break;
    }
    case LC_MSG_ACK:
        if (!lc_session_stream_ack(s, m.frame)) {
            char msg[128];
            snprintf(msg, sizeof msg, "frame %llu has not been sent", (unsigned long long)m.frame);
            send_error(c, LC_PROTO_OUT_OF_RANGE, msg, "frame", false, 0);
            count_error(c);
            break;
        }
        lc_workers_wake(srv->workers, s);
        break;
    }
    lc_client_msg_free(&m);
}

static void on_msg(wslay_event_context_ptr ctx, const struct wslay_event_on_msg_recv_arg *arg, void *user)
{
    (void)ctx;
    conn *c = user;
    if (c->close_deadline > 0)
        return;
    if (arg->opcode == WSLAY_TEXT_FRAME)
        on_text(c, arg->msg, arg->msg_length);
    else if (arg->opcode == WSLAY_BINARY_FRAME)
        send_error(c, "bad_json", "binary messages are not accepted; send JSON text", NULL, false, 0);
    /* ping/pong/close are answered by wslay */
}

/* ---------------------------------------------------------------- connections */

/* Ends c's session (its frames stop); the connection may linger closing. */
static void release_session(lc_ws *ws, conn *c)
{
    if (!c->session)
        return;
    LC_INFO(MOD, "session %s: closed after %llu frames", c->session->id, (unsigned long long)c->session->stream.frames);
    c->session->ws_conn = NULL;
    lc_session_close(ws->srv->sessions, c->session);
    lc_session_unref(c->session);
    c->session = NULL;
}

static void conn_destroy(lc_ws *ws, conn *c)
{
    epoll_ctl(ws->epfd, EPOLL_CTL_DEL, c->fd, NULL);
    if (c->prev)
        c->prev->next = c->next;
    else
        ws->conns = c->next;
    if (c->next)
        c->next->prev = c->prev;
    ws->nconns--;
    release_session(ws, c);
    wslay_event_context_free(c->ctx);
    MHD_upgrade_action(c->urh, MHD_UPGRADE_ACTION_CLOSE);
    free(c->extra);
    free(c);
}

/* Sends what wslay has queued and keeps the epoll interest in step. Returns -1
 * after destroying c. */
static int conn_flush(lc_ws *ws, conn *c)
{
    if (wslay_event_want_write(c->ctx) && wslay_event_send(c->ctx) != 0) {
        conn_destroy(ws, c);
        return -1;
    }
    if (c->close_code && wslay_event_get_queued_msg_count(c->ctx) == 0) {
        wslay_event_queue_close(c->ctx, c->close_code, (const uint8_t *)c->close_reason, strlen(c->close_reason));
        c->close_code = 0;
        if (wslay_event_send(c->ctx) != 0) {
            conn_destroy(ws, c);
            return -1;
        }
    }
    /* Data left in wslay's queue means the socket would block: the client is
     * not reading. Render nothing more for it until the queue drains, whatever
     * its acks say (they could be blind). */
    if (c->session) {
        bool blocked = wslay_event_get_queued_msg_length(c->ctx) > 0;
        if (lc_session_stream_blocked(c->session, blocked))
            lc_workers_wake(ws->srv->workers, c->session);
    }
    int r = wslay_event_want_read(c->ctx), w = wslay_event_want_write(c->ctx);
    if (!r && !w) {
        /* Both close frames are out (or ours is, after an oversized message).
         * Closing now with unread input would reset the connection and the
         * client could lose our close frame: shut down our side, then read
         * and drop until the peer closes or the grace period ends. */
        if (c->draining) {
            r = 1;
        } else if (shutdown(c->fd, SHUT_WR) == 0) {
            release_session(ws, c);
            c->draining = true;
            double until = lc_now() + CLOSE_GRACE;
            if (c->close_deadline == 0 || c->close_deadline > until)
                c->close_deadline = until;
            r = 1;
        } else {
            conn_destroy(ws, c);
            return -1;
        }
    }
    uint32_t ev = (r ? EPOLLIN : 0) | (w ? EPOLLOUT : 0) | EPOLLRDHUP;
    if (ev != c->events) {
        struct epoll_event e = {.events = ev, .data.ptr = c};
        epoll_ctl(ws->epfd, EPOLL_CTL_MOD, c->fd, &e);
        c->events = ev;
    }
    return 0;
}

/* Reads and drops what a closing peer still sends; -1 after destroying c. */
static int drain_input(lc_ws *ws, conn *c)
{
    char buf[4096];
    for (;;) {
        ssize_t n = recv(c->fd, buf, sizeof buf, 0);
        if (n > 0)
            continue;
        if (n < 0 && errno == EINTR)
            continue;
        if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK))
            return 0;
        conn_destroy(ws, c); /* EOF or error: the peer is done */
        return -1;
    }
}

static void conn_io(lc_ws *ws, conn *c, uint32_t events)
{
    if (c->draining) {
        drain_input(ws, c);
        return;
    }
    if (events & (EPOLLIN | EPOLLERR | EPOLLHUP | EPOLLRDHUP)) {
        if (wslay_event_recv(c->ctx) != 0) {
            conn_destroy(ws, c);
            return;
        }
    }
    conn_flush(ws, c);
}

static void conn_register(lc_ws *ws, conn *c)
{
    static const struct wslay_event_callbacks callbacks = {
        .recv_callback = recv_cb, .send_callback = send_cb, .on_msg_recv_callback = on_msg};
    if (wslay_event_context_server_init(&c->ctx, &callbacks, c) != 0) {
        MHD_upgrade_action(c->urh, MHD_UPGRADE_ACTION_CLOSE);
        free(c->extra);
        free(c);
        return;
    }
    /* Beyond this wslay queues a close frame with 1009 (message too big). */
    wslay_event_config_set_max_recv_msg_length(c->ctx, ws->srv->cfg.max_ws_message);
    c->ws = ws;
    c->last_rx = c->last_ping = c->opened = lc_now();
    c->events = EPOLLIN | EPOLLRDHUP;
    struct epoll_event e = {.events = c->events, .data.ptr = c};
    if (epoll_ctl(ws->epfd, EPOLL_CTL_ADD, c->fd, &e) != 0) {
        wslay_event_context_free(c->ctx);
        MHD_upgrade_action(c->urh, MHD_UPGRADE_ACTION_CLOSE);
        free(c->extra);
        free(c);
        return;
    }
    c->next = ws->conns;
    if (ws->conns)
        ws->conns->prev = c;
    ws->conns = c;
    ws->nconns++;
    if (ws->shutting_down)
        close_with(c, 1001, "server shutting down");
    /* Bytes that arrived with the handshake (a hello sent eagerly). */
    if (c->extra_len > 0)
        conn_io(ws, c, EPOLLIN);
    else if (ws->shutting_down)
        conn_flush(ws, c);
}

void lc_ws_adopt(lc_ws *ws, int sock, void *urh, const char *extra, size_t extra_len, bool authed)
{
    conn *c = calloc(1, sizeof *c);
    inbox_item *it = calloc(1, sizeof *it);
    if (c && extra_len > 0 && (c->extra = malloc(extra_len)))
        memcpy(c->extra, extra, extra_len);
    if (!c || !it || (extra_len > 0 && !c->extra)) {
        if (c)
            free(c->extra);
        free(c);
        free(it);
        MHD_upgrade_action(urh, MHD_UPGRADE_ACTION_CLOSE);
        return;
    }
    int fl = fcntl(sock, F_GETFL, 0);
    fcntl(sock, F_SETFL, fl | O_NONBLOCK);
    /* A fixed kernel send buffer: autotuning would let a client that does not
     * read park up to tcp_wmem's maximum (4 MiB) per socket before the server
     * sees back-pressure (conn_flush stops rendering at the first byte wslay
     * cannot hand over). 256 KiB (the kernel doubles it) still holds several
     * large frames in flight. */
    int sndbuf = WS_SNDBUF;
    setsockopt(sock, SOL_SOCKET, SO_SNDBUF, &sndbuf, sizeof sndbuf);
    c->fd = sock;
    c->urh = urh;
    c->extra_len = extra_len;
    c->authed = authed;
    it->adopt = c;
    push_inbox(ws, it);
}

/* Delivers inbox items on the I/O thread. */
static void drain_inbox(lc_ws *ws)
{
    pthread_mutex_lock(&ws->lock);
    inbox_item *it = ws->inbox_head;
    ws->inbox_head = ws->inbox_tail = NULL;
    pthread_mutex_unlock(&ws->lock);
    while (it) {
        inbox_item *next = it->next;
        if (it->adopt) {
            conn_register(ws, it->adopt);
        } else {
            conn *c = it->session->ws_conn;
            if (c) {
                bool counted = it->frame && c->close_deadline == 0;
                if (queue_msg(c, it->binary ? WSLAY_BINARY_FRAME : WSLAY_TEXT_FRAME, it->msg, it->len) != 0) {
                    conn_destroy(ws, c);
                } else {
                    double now = lc_now();
                    if (counted)
                        record_frame(c, now, it->render_ms, it->encode_ms);
                    if (maybe_send_stats(c, now) < 0)
                        conn_destroy(ws, c);
                    else
                        conn_flush(ws, c);
                }
            }
            free(it->msg);
            lc_session_unref(it->session);
        }
        free(it);
        it = next;
    }
}

/* Once a second: idle timeouts, pings, overdue close handshakes, the stats
 * message that follows the end of a frame burst, idle HTTP sessions. */
static void tick(lc_ws *ws, double now)
{
    const lc_serve_config *cfg = &ws->srv->cfg;
    conn *c = ws->conns;
    while (c) {
        conn *next = c->next;
        if (c->close_deadline > 0 && now > c->close_deadline) {
            conn_destroy(ws, c);
        } else if (c->close_deadline == 0 && !c->session && now - c->opened > HELLO_TIMEOUT) {
            LC_INFO(MOD, "connection without hello for %.0f s, closing", HELLO_TIMEOUT);
            lc_metrics_error(ws->srv->metrics, "hello_timeout");
            close_with(c, 1008, "no hello");
            conn_flush(ws, c);
        } else if (c->close_deadline == 0 && now - c->last_rx > cfg->idle_timeout) {
            LC_INFO(MOD, "%s: idle for %.0f s, closing", c->session ? c->session->id : "connection", cfg->idle_timeout);
            close_with(c, 1001, "idle timeout");
            conn_flush(ws, c);
        } else if (c->close_deadline == 0 && now - c->last_rx > PING_INTERVAL && now - c->last_ping > PING_INTERVAL) {
            c->last_ping = now;
            struct wslay_event_msg m = {.opcode = WSLAY_PING, .msg = NULL, .msg_length = 0};
            wslay_event_queue_msg(c->ctx, &m);
            conn_flush(ws, c);
        } else {
            int r = maybe_send_stats(c, now);
            if (r < 0)
                conn_destroy(ws, c);
            else if (r > 0)
                conn_flush(ws, c);
        }
        c = next;
    }
    lc_sessions_sweep(ws->srv->sessions, now, cfg->idle_timeout);
}

static void *io_main(void *arg)
{
    lc_ws *ws = arg;
    struct epoll_event events[64];
    double last_tick = lc_now();
    bool closing_all = false;
    for (;;) {
        pthread_mutex_lock(&ws->lock);
        bool stop = ws->shutting_down;
        double deadline = ws->shutdown_deadline;
        pthread_mutex_unlock(&ws->lock);
        drain_inbox(ws);
        double now = lc_now();
        if (stop) {
            if (!closing_all) {
                closing_all = true;
                for (conn *c = ws->conns, *next; c; c = next) {
                    next = c->next;
                    close_with(c, 1001, "server shutting down");
                    conn_flush(ws, c);
                }
            }
            if (!ws->conns || now > deadline) {
                while (ws->conns)
                    conn_destroy(ws, ws->conns);
                break;
            }
        }
        int n = epoll_wait(ws->epfd, events, 64, stop ? 50 : 1000);
        for (int i = 0; i < n; i++) {
            if (events[i].data.ptr == NULL) {
                uint64_t v;
                ssize_t r = read(ws->evfd, &v, sizeof v);
                (void)r;
                continue;
            }
            conn *c = events[i].data.ptr;
            /* c may have been destroyed by an earlier event of this batch only
             * through its own events, which epoll reports once per wait. */
            conn_io(ws, c, events[i].events);
        }
        now = lc_now();
        if (now - last_tick >= 1.0) {
            last_tick = now;
            tick(ws, now);
        }
    }
    return NULL;
}

int lc_ws_create(lc_server *srv, lc_ws **out, lc_error *err)
{
    *out = NULL;
    lc_ws *ws = calloc(1, sizeof *ws);
    if (!ws)
        return lc_err(err, LC_ERR_NOMEM, "out of memory");
    ws->srv = srv;
    ws->limits = srv->cfg.limits;
    ws->limits.max_text = srv->cfg.max_ws_message;
    pthread_mutex_init(&ws->lock, NULL);
    ws->epfd = epoll_create1(EPOLL_CLOEXEC);
    ws->evfd = eventfd(0, EFD_NONBLOCK | EFD_CLOEXEC);
    struct epoll_event e = {.events = EPOLLIN, .data.ptr = NULL};
    if (ws->epfd < 0 || ws->evfd < 0 || epoll_ctl(ws->epfd, EPOLL_CTL_ADD, ws->evfd, &e) != 0 ||
        pthread_create(&ws->thread, NULL, io_main, ws) != 0) {
        int e2 = errno;
        lc_ws_destroy(ws);
        return lc_err(err, LC_ERR_INTERNAL, "cannot start the WebSocket thread: %s", strerror(e2));
    }
    ws->started = true;
    *out = ws;
    return 0;
}

void lc_ws_shutdown(lc_ws *ws, double timeout)
{
    if (!ws || !ws->started)
        return;
    pthread_mutex_lock(&ws->lock);
    ws->shutting_down = true;
    ws->shutdown_deadline = lc_now() + timeout;
    pthread_mutex_unlock(&ws->lock);
    wake(ws);
    pthread_join(ws->thread, NULL);
    ws->started = false;
}

void lc_ws_destroy(lc_ws *ws)
{
    if (!ws)
        return;
    lc_ws_shutdown(ws, 0);
    /* Leftovers (messages queued after the thread stopped). */
    inbox_item *it = ws->inbox_head;
    while (it) {
        inbox_item *next = it->next;
        if (it->adopt) {
            MHD_upgrade_action(it->adopt->urh, MHD_UPGRADE_ACTION_CLOSE);
            free(it->adopt->extra);
            free(it->adopt);
        } else {
            free(it->msg);
            lc_session_unref(it->session);
        }
        free(it);
        it = next;
    }
    if (ws->epfd >= 0)
        close(ws->epfd);
    if (ws->evfd >= 0)
        close(ws->evfd);
    pthread_mutex_destroy(&ws->lock);
    free(ws);
}
