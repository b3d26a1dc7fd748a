/* The stream protocol (protocol/websocket.md): a connection's text messages
 * (hello, camera, params, resize, ack) turned into session changes, and the
 * answer to each. No sockets here: the WebSocket transport (ws.c) hands in
 * every text message and acts on the outcome, and the unit tests drive it
 * alone. Thread: the WebSocket I/O thread (one connection at a time). */
#ifndef LC_SERVER_STREAM_H
#define LC_SERVER_STREAM_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "server.h"
#include "session.h"

/* What the protocol keeps of one connection. */
typedef struct lc_stream_conn {
    lc_session *session; /* after hello; holds a reference */
    bool authed;         /* the handshake or the hello carried the token (or none is configured) */
    uint64_t client;     /* the peer's address key (lc_conn_client_key): its sessions' share and limit */
} lc_stream_conn;

/* What the transport does after a message. */
typedef struct lc_stream_outcome {
    char *reply;         /* JSON text to send (ready, or an error; malloc'd), NULL = none */
    bool opened;         /* this hello opened conn->session */
    bool valid;          /* a well-formed message in order: the bad-messages-in-a-row count starts over */
    bool bad;            /* the message counts as one more bad one in a row */
    uint16_t close_code; /* non-zero: close the connection after the reply */
    char close_reason[64];
    bool wake; /* conn->session may need a frame now */
} lc_stream_outcome;

/* ---- The stats messages (websocket.md "stats"): about once a second while
 * frames flow, and once more after they stop. */
#define LC_STREAM_STATS_INTERVAL 1.0     /* seconds between stats messages while frames flow */
#define LC_STREAM_STATS_SAMPLES 256      /* latest frames remembered for fps and timing figures */
#define LC_STREAM_PROGRESS_AFTER 0.3     /* seconds a frame is awaited before progress messages start */
#define LC_STREAM_PROGRESS_INTERVAL 0.25 /* seconds between progress messages of a connection */

/* What a connection's stats messages report (I/O thread only). The rings hold
 * the latest frames, indexed by frame count modulo LC_STREAM_STATS_SAMPLES. */
typedef struct lc_stream_stats {
    uint64_t frames;                           /* frame messages queued to the socket */
    uint64_t bytes;                            /* bytes of every message queued */
    double sent_at[LC_STREAM_STATS_SAMPLES];   /* lc_now() when each frame was queued */
    double render_ms[LC_STREAM_STATS_SAMPLES]; /* its render worker wall time */
    double encode_ms[LC_STREAM_STATS_SAMPLES]; /* its encode time */
    uint64_t frames_at_report;                 /* frames when the last stats message went out */
    double last_report;                        /* lc_now() of that message (of hello before the first) */
} lc_stream_stats;

/* What a connection's progress messages went by (lc_stream_progress_message). */
typedef struct lc_stream_progress_report {
    double hello_at; /* lc_now() of the session's hello */
    double sent_at;  /* when the latest progress message was made */
    uint64_t frame;  /* id of the frame it reported on */
    double fraction; /* its fraction (-1 = none; fractions only grow within a frame) */
} lc_stream_progress_report;

/* A progress message (malloc'd) when one is due, else NULL: the client waits
 * longer than LC_STREAM_PROGRESS_AFTER for the session's first frame
 * (frames_sent == 0; counted from hello, stage "queued" until a worker takes
 * it) or for a frame being rendered or encoded and not yet handed to the
 * connection (counted from its render's start); at most one every
 * LC_STREAM_PROGRESS_INTERVAL. Thread: the connection's I/O thread. */
char *lc_stream_progress_message(lc_stream_progress_report *pr, lc_session *s, uint64_t frames_sent, double now);

/* A frame message was queued at now, rendered in render_ms and encoded in encode_ms. */
void lc_stream_stats_frame(lc_stream_stats *st, double now, double render_ms, double encode_ms);
/* A stats message is due: frames went out since the last one, which is at
 * least LC_STREAM_STATS_INTERVAL old. */
bool lc_stream_stats_due(const lc_stream_stats *st, double now);
/* The stats message of s (render_queue: the tasks queued for the workers),
 * malloc'd; marks it reported. NULL when out of memory. */
char *lc_stream_stats_message(lc_stream_stats *st, lc_session *s, int render_queue, double now);

/* Handles one text message (len bytes, not NUL-terminated) of conn under the
 * WebSocket limits lim, read from the socket at `arrived` (lc_now's clock):
 * the pace of input is measured in arrival times, so messages read together
 * (a time step's params and camera) stay one burst however long the first
 * takes to apply; fills out (free out->reply). */
void lc_stream_on_text(lc_server *srv, const lc_proto_limits *lim, lc_stream_conn *conn, const char *data, size_t len,
                       double arrived, lc_stream_outcome *out);

#endif
