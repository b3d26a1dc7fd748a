/* Streamline sets that requests ask for (docs/ALGORITHM.md §22): a request
 * whose dataset names a loaded vector field draws the set its streamlines
 * section describes, traced by the load-time code path (the section becomes
 * a "streamlines:FIELD?..." spec, render/io/streamlines.h) into a dataset of
 * its own that the normal pipeline renders as any line dataset.
 *
 * A one-shot render's set lives as long as its job; a session keeps its set
 * and re-traces only when an update changes the section (camera moves and
 * every other field reuse it). The GPU copy is made, replaced and destroyed
 * on render workers (a context of the share group current): sets freed
 * elsewhere leave their copy for the next worker that readies a set.
 *
 * Locking: a set's pending re-trace and the swap into its dataset happen
 * under the lock its owner passes (the session's); the set's dataset is
 * otherwise read by the one worker rendering its frame. */
#ifndef LC_SERVER_TRACED_H
#define LC_SERVER_TRACED_H

#include <pthread.h>
#include <stdbool.h>
#include <stdint.h>

#include "datasets.h"
#include "request.h"
#include "server.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct lc_traced lc_traced;

/* The dataset req->dataset names: a loaded one (*owned NULL), or for a loaded
 * vector field a new set traced now (*owned, the caller's: lc_traced_free);
 * its dataset is named after the field, so that the request's dataset
 * stays valid in a session's updates. NULL with pe set when neither: 404
 * "not_found" naming "dataset", or the set's refusal naming its field
 * ("streamlines.seeds", "streamlines.count": too costly, ...). */
const lc_dataset *lc_traced_resolve(lc_server *srv, const lc_request *req, lc_traced **owned, lc_proto_error *pe);

/* The admission's part (admit.c): on a loaded dataset a streamlines section
 * away from its defaults is refused naming its first field; on a traced set
 * the section is checked against the field (its keys, the seeds, the trace
 * budget) and its tracing priced (lc_cost_trace) against --max-cost, refused
 * naming "streamlines.count". A traced set's resident estimate counts with the
 * loaded datasets' and every set alive against --max-memory (refused, also
 * naming "streamlines.count", once traced). */
int lc_traced_check(lc_server *srv, const lc_request *req, const lc_dataset *ds, lc_proto_error *pe);

/* A session's update (under lock): when req's section differs from the set
 * the session draws, traces the new one now (refusals name its field) and
 * leaves it for lc_traced_ready to swap in. */
int lc_traced_update(lc_server *srv, const lc_dataset *ds, const lc_request *req, lc_proto_error *pe);

/* On a render worker before a frame of ds (nothing for a loaded dataset):
 * swaps a pending re-trace in (under lock, may be NULL for one-shot jobs;
 * *replaced set: the session's element opacities must start again) and
 * uploads the set's GPU copy when it has none. Destroys the GPU copies of
 * sets freed or replaced since. */
int lc_traced_ready(const lc_dataset *ds, pthread_mutex_t *lock, bool *replaced, lc_error *err);

/* How often the set was traced (its first trace and each re-trace). */
uint64_t lc_traced_traces(const lc_dataset *ds);

/* Frees t (any thread); its GPU copy waits for the next lc_traced_ready. */
void lc_traced_free(lc_traced *t);
/* Destroys what freed sets left on the GPU (a worker, context current). */
void lc_traced_collect(void);

#ifdef __cplusplus
}
#endif
#endif
