/* Render worker pool.
 *
 * Each render worker owns one EGL context (worker 0 the primary one that the
 * datasets were uploaded with, the others created with .share = primary) and
 * its own lc_renderer; every GL call of the daemon happens on these threads.
 * Work arrives as tasks: HTTP render jobs and WebSocket sessions that need a
 * frame. Tasks are queued per client (a session, or the address of one-shot
 * HTTP requests) and the clients take turns (round robin), so one client that
 * queues many renders delays each other client by at most one of them. A
 * session is queued at most once and goes back to the end after each frame. Sessions waiting for their still frame sit
 * in a timer list; idle workers sleep on a condition variable (no polling).
 *
 * Workers call the renderer directly (with the server's frame hook, which
 * serve --mpi sets, server.h) and hand the RGBA readback to the encoder
 * threads (encoders.h). Finished HTTP jobs call job->done (from an encoder or
 * worker thread); finished stream frames go to the server's stream sink. */
#ifndef LC_SERVER_WORKERS_H
#define LC_SERVER_WORKERS_H

#include <stddef.h>
#include <stdint.h>

#include "encoders.h"
#include "gl_context.h"
#include "lc_base.h"
#include "renderer.h"
#include "request.h"
#include "server.h"
#include "session.h"
#include "workers_stop.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct lc_workers lc_workers;

/* Starts `workers` render threads and `encoders` encoder threads. primary is a
 * released (not current) context that worker 0 adopts; the pool owns it from
 * here on. Blocks until every worker has its context and renderer (errors are
 * reported here, e.g. shader compile logs). Thread: main. */
int lc_workers_create(lc_server *srv, lc_gl *primary, int workers, int encoders, int max_queue, lc_workers **out,
                      lc_error *err);

/* Queues an HTTP job. LC_ERR_LIMIT when max_queue jobs are waiting or
 * job->client has max_queue_per_client of them (job->refused says which),
 * LC_ERR_UNSUPPORTED while stopping; done() is not called then. A job that
 * waits longer than the render deadline fails with LC_ERR_LIMIT (refused =
 * "deadline") instead of rendering. Any thread. */
int lc_workers_submit(lc_workers *w, lc_render_job *job, lc_error *err);
/* Asks the pool to consider WebSocket session s for a frame (after input, an
 * ack, or a finished frame). Cheap and idempotent. Any thread. */
void lc_workers_wake(lc_workers *w, lc_session *s);

#ifdef __cplusplus
}
#endif
#endif
