/* WebSocket transport: upgraded sockets and wslay framing on one epoll I/O
 * thread, the delivery of frames and stats messages; each text message goes
 * to the stream protocol (stream.c). */
#include "ws.h"

#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <microhttpd.h>
#include <pthread.h>
#include <stdatomic.h>
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
#include "stream.h"
#include "stream_session.h"
#include "workers.h"

#define MOD "ws"
#define PING_INTERVAL 15.0           /* seconds of silence before we ping */
#define CLOSE_GRACE 2.0              /* seconds a client gets to answer our close frame */
#define MAX_QUEUED_BYTES (32u << 20) /* per connection, beyond the frame window: not reading */
#define MAX_QUEUED_MSGS 256
#define MAX_CONSECUTIVE_ERRORS 32
#define WS_SNDBUF (256 << 10)
#define HELLO_TIMEOUT 10.0 /* seconds an upgraded connection may hold a slot without a session */

typedef struct conn {
    struct conn *prev, *next;
    lc_ws *ws;
    int fd;
    struct MHD_UpgradeResponseHandle *urh;
    wslay_event_context_ptr ctx;
    char *extra; /* bytes MHD read past the handshake */
    size_t extra_len, extra_off;
    lc_stream_conn proto; /* the stream protocol's state: the session after hello (a reference), authed */
    double last_rx, last_ping;
    double close_deadline; /* > 0 once closing: the connection goes by then at the latest */
    uint16_t close_code;   /* close frame to send once the queued messages are out */
    char close_reason[64];
    int errors;      /* consecutive bad messages */
    bool draining;   /* close sent and our side shut down: read and drop until the peer closes */
    double opened;   /* lc_now() at registration (the hello deadline) */
    uint32_t events; /* registered epoll events */
    lc_stream_stats stats;
    lc_stream_progress_report progress;
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
    atomic_int nconns;    /* I/O thread writes; /metrics reads */
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

int lc_ws_connections(lc_ws *ws) { return ws ? atomic_load(&ws->nconns) : 0; }

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
                c->proto.session ? c->proto.session->id : "connection", wslay_event_get_queued_msg_length(c->ctx));
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

/* Counts one more bad message in a row; too many close the connection. */
static void count_error(conn *c)
{
    if (++c->errors > MAX_CONSECUTIVE_ERRORS)
        send_error(c, "too_many_errors", "too many invalid messages in a row", NULL, true, 1008);
}

/* ---------------------------------------------------------------- stats */

/* Queues the stats message when one is due (lc_stream_stats_due): checked when
 * a frame is queued and on the thread's one-second tick. Returns 1
 * when a message was queued, 0 when none was due, -1 when c must go (its
 * client is not reading). */
static int maybe_send_stats(conn *c, double now)
{
    if (!c->proto.session || c->close_deadline > 0 || !lc_stream_stats_due(&c->stats, now))
        return 0;
    int render_queue = 0, encode_queue = 0;
    lc_workers_depths(c->ws->srv->workers, &render_queue, &encode_queue);
    char *text = lc_stream_stats_message(&c->stats, c->proto.session, render_queue, now);
    if (!text)
        return 0;
    int rc = queue_msg(c, WSLAY_TEXT_FRAME, text, strlen(text));
    free(text);
    return rc == 0 ? 1 : -1;
}

/* Queues a progress message when one is due (lc_stream_progress_message).
 * Returns as maybe_send_stats. */
static int maybe_send_progress(conn *c, double now)
{
    if (!c->proto.session || c->close_deadline > 0)
        return 0;
    char *text = lc_stream_progress_message(&c->progress, c->proto.session, c->stats.frames, now);
    if (!text)
        return 0;
    int rc = queue_msg(c, WSLAY_TEXT_FRAME, text, strlen(text));
    free(text);
    return rc == 0 ? 1 : -1;
}

/* ---------------------------------------------------------------- messages */

/* A text message goes to the stream protocol (stream.c); this acts on its outcome. */
static void on_text(conn *c, const uint8_t *data, size_t len)
{
    lc_server *srv = c->ws->srv;
    lc_stream_outcome o;
    lc_stream_on_text(srv, &c->ws->limits, &c->proto, (const char *)data, len, c->last_rx, &o);
    if (o.opened) {
        c->proto.session->ws_conn = c;
        c->stats.last_report = c->progress.hello_at = lc_now();
    }
    if (o.reply) {
        queue_msg(c, WSLAY_TEXT_FRAME, o.reply, strlen(o.reply));
        free(o.reply);
    }
    if (o.close_code)
        close_with(c, o.close_code, o.close_reason);
    if (o.valid)
        c->errors = 0;
    if (o.bad)
        count_error(c);
    if (o.wake)
        lc_workers_wake(srv->workers, c->proto.session);
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
    if (!c->proto.session)
        return;
    LC_INFO(MOD, "session %s: closed after %llu frames", c->proto.session->id,
            (unsigned long long)c->proto.session->stream.frames);
    c->proto.session->ws_conn = NULL;
    lc_session_close(ws->srv->sessions, c->proto.session);
    lc_session_unref(c->proto.session);
    c->proto.session = NULL;
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
    if (c->proto.session) {
        bool blocked = wslay_event_get_queued_msg_length(c->ctx) > 0;
        if (lc_session_stream_blocked(c->proto.session, blocked))
            lc_workers_wake(ws->srv->workers, c->proto.session);
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

void lc_ws_adopt(lc_ws *ws, int sock, void *urh, const char *extra, size_t extra_len, bool authed, uint64_t client)
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
    c->proto.authed = authed;
    c->proto.client = client;
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
                        lc_stream_stats_frame(&c->stats, now, it->render_ms, it->encode_ms);
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
        } else if (c->close_deadline == 0 && !c->proto.session && now - c->opened > HELLO_TIMEOUT) {
            LC_INFO(MOD, "connection without hello for %.0f s, closing", HELLO_TIMEOUT);
            lc_metrics_error(ws->srv->metrics, "hello_timeout");
            close_with(c, 1008, "no hello");
            conn_flush(ws, c);
        } else if (c->close_deadline == 0 && now - c->last_rx > cfg->idle_timeout) {
            LC_INFO(MOD, "%s: idle for %.0f s, closing", c->proto.session ? c->proto.session->id : "connection",
                    cfg->idle_timeout);
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
        int n = epoll_wait(ws->epfd, events, 64, stop ? 50 : (int)(LC_STREAM_PROGRESS_INTERVAL * 1000));
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
        for (conn *c = ws->conns, *next; c && !stop; c = next) {
            next = c->next;
            int r = maybe_send_progress(c, now);
            if (r < 0)
                conn_destroy(ws, c);
            else if (r > 0)
                conn_flush(ws, c);
        }
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
