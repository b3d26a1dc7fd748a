/* WebSocket sessions: connections upgraded by libmicrohttpd, framed by wslay
 * (RFC 6455), all served by one I/O thread with epoll.
 *
 * Threading: wslay contexts and sockets are touched only by the I/O thread.
 * Other threads hand it messages through lc_ws_send() (a locked inbox and an
 * eventfd wake-up). Each connection's outgoing queue is bounded: frames by the
 * session window, everything else by a byte cap after which a client that does
 * not read is disconnected. A connection holds a reference to its session.
 *
 * Stats: about once a second while frames flow, and once more after they stop,
 * the I/O thread sends each session a `stats` text message (websocket.md). It
 * is checked when a frame is queued and on the thread's one-second tick, so an
 * idle stream costs nothing and there is no extra timer. */
#ifndef LC_SERVER_WS_H
#define LC_SERVER_WS_H

#include <stdbool.h>
#include <stddef.h>

#include "server.h"
#include "session.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Starts the I/O thread. Thread: main. */
int lc_ws_create(lc_server *srv, lc_ws **out, lc_error *err);
/* Flushes queued messages, sends every client a close frame (1001, "server
 * shutting down"), waits up to timeout seconds for the closing handshakes,
 * closes the sockets and stops the thread. Thread: main. */
void lc_ws_shutdown(lc_ws *ws, double timeout);
void lc_ws_destroy(lc_ws *ws);

/* Takes over an upgraded socket (called from MHD's upgrade handler). extra
 * holds bytes MHD read past the HTTP header (copied). authed: the handshake
 * carried a valid token (or none is configured); otherwise hello must. */
void lc_ws_adopt(lc_ws *ws, int sock, void *urh, const char *extra, size_t extra_len, bool authed, uint64_t client);

/* Queues a message for s's connection; takes ownership of msg (malloc'd).
 * Dropped silently when the connection is gone. Any thread. */
void lc_ws_send(lc_ws *ws, lc_session *s, unsigned char *msg, size_t len, bool binary);

/* Queues a binary frame message for s's connection, like lc_ws_send(), and
 * records it for the session's `stats` messages: render_ms is the worker's wall
 * time for the frame, encode_ms the encoder's. Any thread. */
void lc_ws_send_frame(lc_ws *ws, lc_session *s, unsigned char *msg, size_t len, double render_ms, double encode_ms);

/* Open connections (for metrics). */
int lc_ws_connections(lc_ws *ws);

#ifdef __cplusplus
}
#endif
#endif
