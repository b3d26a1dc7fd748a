/* Sessions: one viewer's render request, element opacities (fading state) and,
 * for WebSocket viewers, the stream's flow control (window of unacknowledged
 * frames, latest-wins coalescing, interactive vs still frames).
 *
 * Ownership: sessions are reference counted. The registry holds one reference
 * while the session is open; a queued render task, an HTTP job and a WebSocket
 * connection each hold their own. lc_session_unref() frees at zero.
 *
 * Locking: `lock` guards the request and stream fields. frame_state is used
 * only by the worker that owns the session's current frame (stream.rendering
 * for WebSocket sessions, http_busy for HTTP sessions), so the lock is not held
 * while rendering. The sched_* fields belong to the worker pool and are guarded
 * by its lock. ws_conn is touched only on the WebSocket I/O thread.
 *
 * Memory per session is O(elements): the frame state plus a fixed struct. */
#ifndef LC_SERVER_SESSION_H
#define LC_SERVER_SESSION_H

#include <pthread.h>
#include <stdatomic.h>
#include <stdbool.h>
#include <stdint.h>

#include "datasets.h"
#include "messages.h"
#include "renderer.h"
#include "request.h"
#include "request_patch.h"
#include "server.h"
#include "stream_fit.h"
#include "stream_flow.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct lc_surface_keep lc_surface_keep; /* surface_render.h */

typedef enum { LC_SESSION_HTTP = 0, LC_SESSION_WS = 1 } lc_session_kind;

#define LC_SESSION_ID_LEN 33 /* 32 hex digits + NUL */

/* WebSocket stream state (all guarded by the session lock). */
typedef struct lc_stream {
    int window;               /* max unacknowledged frames now, 1..8 (flow.window) */
    lc_stream_flow flow;      /* what the window follows: round trip, render time, the hello's ceiling */
    double render_began;      /* lc_now() when the frame being rendered was taken (stream_next) */
    int quality;              /* still-frame JPEG quality */
    int interactive_quality;  /* JPEG quality while input is active: the most; lower where the link needs (stream_fit.h)
                               */
    double interactive_scale; /* resolution factor while input is active */
    lc_fit_ref fit_ref;       /* the latest moving frame sent: what the next one's fit predicts from */
    lc_fit fit;               /* the latest moving frame's fit (stats) */
    bool fit_from_still;      /* a moving frame was fitted from fit_ref, a still, and none has gone out since */
    int css_width, css_height; /* viewport in CSS pixels */
    double device_pixel_ratio;
    uint64_t outstanding[LC_PROTO_MAX_WINDOW]; /* frame ids sent or in flight, not acked */
    int unacked;
    uint64_t next_frame;          /* id of the next frame (from 1) */
    uint64_t camera_seq;          /* latest camera seq received */
    bool dirty;                   /* input arrived since the last snapshot */
    uint64_t updates_since_frame; /* for the coalescing metric */
    uint64_t coalesced;           /* updates overwritten before a frame showed them (stats) */
    bool rendering;               /* a worker owns the frame state right now */
    bool converged;               /* the last frame's opacities stopped fading */
    bool last_interactive;        /* the last frame used interactive quality/scale */
    bool any_input;               /* camera/params/resize seen since hello */
    double last_input;            /* lc_now() of the latest input */
    double input_interval;        /* recent spacing of input, seconds (0: none yet); stills wait 1.5x it */
    bool input_split;             /* the last gap was taken for a burst split in two (lc_session_stream_input) */
    uint64_t frames;              /* frames rendered */
    uint64_t last_sent;           /* newest frame id handed to the connection; acks beyond it are refused */
    bool send_blocked;            /* the socket does not take more: render nothing until it drains */
    /* Interactive detail (docs/ALGORITHM.md "Level of detail and interactive
     * frames"): a step of the session's ladder, moved by the render times of
     * the frames that reused opacities, and when P1-P3 last ran. */
    int detail_step;
    bool step_measured; /* a moving frame has moved detail_step; until then a drag starts from the still's time */
    double last_optimized;
    /* Re-optimization while moving (stream_session.c reoptimize_seconds): the
     * mean time of the moving frames that reused opacities at rung moving_step,
     * and the mean extra time of those that ran P1-P3 at that rung; 0 = none. */
    double moving_ms, reoptimize_ms;
    int moving_step;
    bool lines_thinned; /* moving frames draw line subsets (dense lines): the ladder's line_scale applies */
    uint64_t yielded;   /* still/refinement frames abandoned for newer input (stats) */
    bool moving_next;   /* after such a frame: the next frame is a moving one, however long the pass took */
    int still_stage;    /* staged stills: 1 = stage 1 sent, stage 2 due (0 otherwise) */
    int preview_stride; /* the still under way: its stage 1's line/point stride (1: no preview; still_stages.h) */
    double still_ms;    /* render time of the last still (not interactive, not a stage 1), 0 = none yet */
    double reused_ms;   /* a stage 1 at full detail: its time, or the last thinned one's over its share; 0 = none */
    int moving_stride;  /* the line or point stride the last moving frame drew at (1: not thinned) */
    bool coarse_first;  /* the session's first frame was a coarse one (a large dataset): stills are staged */
} lc_stream;

/* Progress of the frame a render worker makes for a WebSocket session, for
 * the I/O thread's progress messages (stream.c): written by the worker at the
 * frame's start and its pass boundaries, read by the I/O thread, no lock. */
#define LC_PROGRESS_NONE (-1)                   /* no frame under way (or it failed) */
#define LC_PROGRESS_ENCODE LC_PASS_COUNT        /* rendered, being encoded */
#define LC_PROGRESS_PREPARE (LC_PASS_COUNT + 1) /* set-up before the first pass (clusters, filters, subsets) */
typedef struct lc_stream_progress {
    _Atomic unsigned long long frame; /* id of the frame (lc_stream.next_frame); written last, read first */
    _Atomic long long begun_us;       /* lc_now() of its start, in microseconds */
    atomic_int stage;                 /* a pass (lc_pass), or LC_PROGRESS_* */
    atomic_int done, planned;         /* passes of the frame's plan done and planned */
} lc_stream_progress;

typedef struct lc_session lc_session;
struct lc_session {
    /* Immutable after creation. */
    char id[LC_SESSION_ID_LEN];
    lc_session_kind kind;
    uint64_t client; /* the client address's key (lc_conn_client_key): its sessions' fair share and limit */
    const lc_dataset *dataset;
    lc_server *srv;
    atomic_int refs;

    pthread_mutex_t lock;
    bool closed;                               /* removed from the registry; render nothing more */
    double created, last_used;                 /* lc_now() */
    lc_request req;                            /* the latest requested state (latest wins) */
    const lc_dataset *layer_ds[LC_MAX_LAYERS]; /* the datasets of req.layers (lc_request_layer_count(&req) of them) */
    lc_frame_state *frame_state;               /* element opacities; see "Locking" above */
    /* Method surface-layers: the curves traced so far (pool/surface_job.h);
     * only the worker rendering the session's frame touches it, and it sets
     * surface_free, so the session frees them without knowing the pool. */
    struct lc_surface_stream *surface;
    void (*surface_free)(struct lc_surface_stream *surface);
    /* A field's streamline set (data/traced.h) that `dataset` points into,
     * owned; NULL for a loaded dataset. */
    struct lc_traced *traced;
    /* The datasets frame_state's elements belong to, in order (state_layers
     * of them; 0 = the session's dataset alone): owned like frame_state. */
    const lc_dataset *state_ds[LC_MAX_LAYERS];
    int state_layers;
    double last_frame_time; /* lc_now() of the previous frame, 0 = none */
    bool http_busy;         /* an HTTP session render is queued or running */
    uint64_t http_frames;
    lc_stream stream;
    lc_stream_progress progress;

    /* Worker pool scheduling (pool lock). */
    bool sched_queued, sched_timed;
    double sched_due;
    lc_session *sched_next;

    /* WebSocket I/O thread only. */
    void *ws_conn;
};

/* One WebSocket frame to render: a snapshot taken by the worker. */
typedef struct lc_stream_frame {
    lc_request req;                          /* with width/height already set for this frame */
    const lc_dataset *layers[LC_MAX_LAYERS]; /* the datasets of req.layers */
    uint64_t frame;
    uint64_t camera_seq;
    int quality;
    bool interactive;
    int detail_step; /* interactive frames: the ladder step used */
    double dt;
    int stage, stages; /* a staged still: stage 1 or 2 of 2 (0, 0: not staged) */
} lc_stream_frame;

typedef struct lc_sessions lc_sessions;

lc_sessions *lc_sessions_create(lc_server *srv, int max_sessions);
/* Closes every session still open (their memory goes when the last reference does). */
void lc_sessions_destroy(lc_sessions *reg);

/* Creates an open session of the given kind on ds with request initial (copied;
 * its layers' datasets must be loaded: lc_session_resolve_layers first).
 * *out gets a reference for the caller. LC_ERR_LIMIT when max_sessions are open,
 * LC_ERR_NOMEM. Any thread. */
int lc_session_create(lc_sessions *reg, lc_session_kind kind, uint64_t client, const lc_dataset *ds,
                      const lc_request *initial, lc_session **out, lc_error *err);
/* Finds an open session by id and kind, refreshing its idle clock; returns a
 * reference (unref it) or NULL. */
lc_session *lc_session_find(lc_sessions *reg, const char *id, lc_session_kind kind);
/* Removes s from the registry and marks it closed (idempotent). */
void lc_session_close(lc_sessions *reg, lc_session *s);
void lc_session_ref(lc_session *s);
void lc_session_unref(lc_session *s);

/* Open sessions by kind. */
void lc_sessions_count(lc_sessions *reg, int *http, int *ws);
/* Closes HTTP sessions unused for longer than idle seconds; returns how many. */
int lc_sessions_sweep(lc_sessions *reg, double now, double idle);

/* ---- Updates (HTTP session renders and stream camera/params alike). */

/* Worker side, before a frame of s (the caller owns frame_state): makes
 * frame_state hold the elements of the n layers' datasets, in order (n = 0:
 * those of the session's dataset). A change of that set starts a new state,
 * so fading begins afresh; the same set keeps it. LC_ERR_NOMEM keeps the old. */
int lc_session_prepare_state(lc_session *s, const lc_dataset *const *layers, int n, lc_error *err);
/* What a session of this kind cannot render, whatever its request allows:
 * HTTP sessions render one frame per request with the dataset's frame state,
 * so method surface-layers (which a WebSocket session streams) is refused
 * naming method. 0 otherwise. */
int lc_session_kind_check(lc_session_kind kind, const lc_request *req, lc_proto_error *pe);
/* The one update function of a session (HTTP session renders and stream
 * camera/params alike): patch (NULL = none) is admitted once against s's
 * request by lc_admit_update (admit.h: the cross-field rules, a change of
 * dataset refused, layers[] resolved into s->layer_ds, scope, what the
 * renderer would refuse, the budget at the request's size), then
 * lc_session_kind_check, and only then
 * replaces it, latest wins; *out (if given) is a copy of the new request (lc_request_release it). On failure s
 * is unchanged and pe names the field. Caller holds s->lock. */
int lc_session_update_locked(lc_session *s, const lc_request_patch *patch, const lc_proto_limits *lim, lc_request *out,
                             lc_proto_error *pe);

#ifdef __cplusplus
}
#endif
#endif
