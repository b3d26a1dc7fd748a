/* The render worker pool's end and its queue figures (workers_stop.c):
 * stopping, abandoning and destroying the pool that workers.h creates. */
#ifndef LC_SERVER_WORKERS_STOP_H
#define LC_SERVER_WORKERS_STOP_H

#include "datasets.h"

typedef struct lc_workers lc_workers;

/* Stops accepting work, lets the frames in hand finish and be encoded and
 * delivered, fails queued HTTP jobs with LC_ERR_UNSUPPORTED ("shutting down"),
 * and joins every thread. Thread: main. */
void lc_workers_stop(lc_workers *w);
/* For a service that cannot go on (serve --mpi when a rank died): answers
 * every queued HTTP job and the ones being rendered now with LC_ERR_UNSUPPORTED
 * and `why`, sends `why` as an error to the WebSocket sessions being rendered
 * or queued for a frame, and accepts no more work. A worker stuck in its frame never touches an
 * answered job again. Call lc_workers_stop afterwards as usual, unless the
 * process is about to exit. Any thread. */
void lc_workers_abandon(lc_workers *w, const char *why);
/* After stop: destroys renderers, releases the datasets' GPU copies with the
 * primary context current on the calling thread, destroys the contexts. */
void lc_workers_destroy(lc_workers *w, lc_datasets *datasets);

int lc_workers_count(const lc_workers *w);
/* Clients (fairness keys) with queued work now. */
int lc_workers_clients(lc_workers *w);
void lc_workers_depths(lc_workers *w, int *render_queue, int *encode_queue);

#endif
