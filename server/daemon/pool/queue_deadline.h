/* The render queue's deadline: a queued HTTP render that no worker took
 * within its wait limit is answered 503 "overloaded" with Retry-After and a
 * JSON error while it is still queued, by a thread of its own (every worker
 * may be busy), never left for the client or a proxy to give up on. The wait
 * limit is --render-deadline, at most LC_QUEUE_WAIT_MAX: HTTP clients commonly
 * wait about as long as the daemon's own 30 s connection timeout. WebSocket
 * frames are not HTTP renders and stay queued. Locking: the pool's lock. */
#ifndef LC_SERVER_QUEUE_DEADLINE_H
#define LC_SERVER_QUEUE_DEADLINE_H

#include "workers_internal.h"

#ifdef __cplusplus
extern "C" {
#endif

#define LC_QUEUE_WAIT_MAX 25.0 /* seconds a queued HTTP render waits for a worker at most */

/* The wait limit of w's queued HTTP renders in seconds (0 = none: --render-deadline 0). */
double lc_queue_wait_limit(const lc_workers *w);
/* Starts the thread (none without a limit; w->deadline_wake initialized by
 * the pool); 0, or -1 when it cannot start. */
int lc_queue_deadline_start(lc_workers *w);
/* Stops and joins it: call with w->stopping set and the pool's lock free. */
void lc_queue_deadline_stop(lc_workers *w);

#ifdef __cplusplus
}
#endif
#endif
