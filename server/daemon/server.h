/* The render daemon's shared types: its configuration, the server object
 * that ties the rooms together, and the two hooks through which a lower room
 * reaches a higher one without including it (the stream sink, the frame hook).
 * Every daemon room includes this; each room includes the headers of the rooms
 * below it that it calls (docs/ARCHITECTURE.md "The daemon" draws who calls
 * whom; tests/tools/check_layout.py keeps it free of circles).
 *
 * Rooms (server/daemon/):
 *   start/       `lucent serve`: flags, start-up (datasets before the port opens) and the ordered
 *                shutdown (serve.c); SIGINT/SIGTERM at any time, start-up included (signals.c)
 *   ranks.c      serve --mpi: the one room that speaks MPI; sets the frame hook
 *   http/        libmicrohttpd: dispatch, token gates, the web client (http.c, web_files.c),
 *                renders (http_render.c), health/datasets/metrics/schema (http_status.c), the
 *                WebSocket handshake (http_upgrade.c), responses (http_respond.c), limits on
 *                connections without a whole request (conn_limits.c)
 *   stream/      WebSocket: epoll/wslay transport (ws.c), the stream protocol (stream.c)
 *   pool/        render workers (workers.c), encoder threads (encoders.c), the fair queue
 *                (fair_queue.c), movie jobs rendered through the workers (movies.c)
 *   session.c    per-viewer state: request and its updates, element opacities, stream flow control
 *   data/        registry of loaded scenes, their GPU copies, presets and sidecars (datasets.c);
 *                what a --data folder may reach (data_paths.c)
 *   auth.c       token checks, the WebSocket accept key
 *   cost.c       render cost estimate before queueing (--max-cost)
 *   metrics.c    counters and histograms in Prometheus text format
 *
 * Threads: main (start-up, then waits for a signal and shuts down), MHD's
 * threads (parse, validate, queue; never GL), render workers (all GL), encoder
 * threads (JPEG/PNG), one WebSocket I/O thread. */
#ifndef LC_SERVER_H
#define LC_SERVER_H

#include <stdatomic.h>
#include <stdbool.h>
#include <stddef.h>

#include "messages.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct lc_datasets lc_datasets;
typedef struct lc_workers lc_workers;
typedef struct lc_sessions lc_sessions;
typedef struct lc_metrics lc_metrics;
typedef struct lc_http lc_http;
typedef struct lc_ws lc_ws;
typedef struct lc_session lc_session;

/* Where finished stream messages go: the WebSocket transport, set by start/serve.c,
 * so that the pool delivers frames without knowing the transport. Both
 * calls take ownership of msg (malloc'd) and may be made from any thread. */
typedef struct lc_stream_sink {
    void *ctx;
    /* A text (binary = false) or binary message for s's connection. */
    void (*send)(void *ctx, lc_session *s, unsigned char *msg, size_t len, bool binary);
    /* A packed frame; render_ms and encode_ms feed the session's stats. */
    void (*send_frame)(void *ctx, lc_session *s, unsigned char *msg, size_t len, double render_ms, double encode_ms);
} lc_stream_sink;

struct lc_dataset;
struct lc_frame_state;
struct lc_reducer;
/* What a render worker does around each frame besides rendering: under serve
 * --mpi the announcement to the other ranks and their reduction (ranks.c sets
 * it at start-up, before the workers start); all zero in one process, so that
 * the workers call the renderer without knowing of MPI. */
typedef struct lc_frame_hook {
    void *ctx;
    /* Before each frame, with its arguments; non-zero fails the frame. Thread: a render worker. */
    int (*before)(void *ctx, const struct lc_dataset *ds, const lc_render_params *p, const struct lc_frame_state *state,
                  double dt, lc_error *err);
    /* Before each frame of layers[] (n, their datasets ds), likewise. */
    int (*before_layers)(void *ctx, const struct lc_dataset *const *ds, const lc_layer_params *layers, int n,
                         const lc_render_params *p, const struct lc_frame_state *state, double dt, lc_error *err);
    const struct lc_reducer *reducer; /* every worker's lc_renderer_desc.reducer */
} lc_frame_hook;

/* Every cap and knob of the daemon; filled from flags by start/serve.c. */
typedef struct lc_serve_config {
    char listen_host[128]; /* "127.0.0.1", "0.0.0.0", "::1" */
    int port;              /* 0 = pick a free port (logged) */
    const char **data;     /* paths or demo:NAME; borrowed from argv */
    int data_count;
    bool demo;                      /* also serve every demo (default when data_count == 0) */
    unsigned long long demo_size;   /* lc_demo_desc.count for demos; 0 = default */
    unsigned elements;              /* --elements: line elements / patches of every dataset; 0 = derived */
    int device;                     /* EGL device index, -1 = auto / LUCENT_EGL_DEVICE */
    int workers;                    /* render threads; 0 = 2 (1 on llvmpipe under 8 GiB of memory, serve.c) */
    int encoders;                   /* encoder threads; 0 = 2 */
    char token[LC_PROTO_TOKEN_LEN]; /* "" = no authentication */
    lc_proto_limits limits;         /* image size, pixel count, JSON depth */
    size_t max_body;                /* HTTP request body bytes (413 beyond) */
    size_t max_ws_message;          /* WebSocket message bytes (close 1009 beyond) */
    int max_sessions;               /* HTTP + WebSocket sessions together */
    int max_client_sessions;        /* of them, from one client address (--max-sessions-per-client) */
    int max_queue;                  /* queued HTTP render jobs (503 beyond) */
    int max_connections;            /* HTTP connections held by MHD */
    double idle_timeout;            /* seconds without use before a session is dropped */
    long long max_stream_pixels;    /* cap of viewport x devicePixelRatio for WS frames */
    double still_delay;             /* seconds of quiet input before the still frame */
    double pass_delay;              /* tests: seconds slept before each pass (--pass-delay) */
    double frame_budget_ms;         /* interactive frames: render time the detail controller aims under */
    double max_cost;                /* estimated cost units of one frame (cost.h); 0 = no limit */
    double render_deadline;         /* seconds an HTTP render may wait for a worker (503 beyond); 0 = none */
    int max_queue_per_client;       /* queued HTTP renders of one client (429 beyond) */
    bool mpi;                       /* --mpi: one image from every rank's shard (docs/MPI.md) */
    bool exact_positions;           /* --exact-positions: float GPU buffers and session opacities */
    bool follow_symlinks;           /* --follow-symlinks: a --data folder's links may leave it */
    unsigned long long max_memory;  /* --max-memory: estimated resident bytes of all datasets; 0 = no limit */
    double load_timeout;            /* --load-timeout: seconds one dataset may take to load; 0 = none */
    const char *cache;              /* --cache: scene cache folder, "off" = none; NULL = the XDG default */
    unsigned long long movie_disk; /* --movie-disk: bytes of movie files kept at once (finished evicted oldest first) */
} lc_serve_config;

/* The daemon: one per process, created by start/serve.c. Modules keep a pointer to
 * it; fields are set during start-up and read-only afterwards except those
 * marked atomic. */
typedef struct lc_server {
    lc_serve_config cfg;
    lc_datasets *datasets;
    lc_workers *workers;
    lc_sessions *sessions;
    lc_metrics *metrics;
    lc_http *http;
    lc_ws *ws;
    lc_stream_sink sink; /* frame delivery of the pool (stream/ws.c behind it) */
    double start_time;   /* lc_now() at start-up */
    char gl_renderer[256];
    char gl_version[256];
    char gl_platform[128];
    atomic_int stopping;      /* set once shutdown begins: refuse new work */
    struct lc_mpi *mpi;       /* --mpi (ranks.c; opaque here); NULL in one process */
    lc_frame_hook frame_hook; /* set by ranks.c under --mpi, else zero */
    struct lc_movies *movies; /* movie jobs (pool/movies.c) */
} lc_server;

#ifdef __cplusplus
}
#endif
#endif
