/* Daemon metrics: counters and histograms, rendered in the Prometheus text
 * exposition format for GET /metrics.
 *
 * Threading: every function may be called from any thread (one mutex; the
 * updates are a few additions, far cheaper than the frames they describe). */
#ifndef LC_SERVER_METRICS_H
#define LC_SERVER_METRICS_H

#include <stddef.h>
#include <stdint.h>

#include "renderer.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct lc_metrics lc_metrics;

/* Gauges sampled at scrape time by the caller of lc_metrics_render. */
typedef struct lc_metrics_gauges {
    int sessions_http, sessions_ws;
    int queue_depth;  /* render tasks waiting for a worker */
    int encode_depth; /* frames waiting for an encoder */
    int ws_connections;
    int datasets;
    int workers;
    int queue_clients; /* clients with queued work (fair queueing) */
    uint64_t memory_estimated,
        memory_budget; /* the datasets' estimate and what requests hold; --max-memory (0 = none) */
    uint64_t resident; /* the process's resident bytes */
    /* HTTP connections closed before a whole request header: past the header
     * deadline, or the oldest beyond the caps (http/conn_limits.h). */
    uint64_t unfinished_deadline, unfinished_evicted;
} lc_metrics_gauges;

lc_metrics *lc_metrics_create(void);
void lc_metrics_destroy(lc_metrics *m);

/* kind: "http", "session" or "ws". */
void lc_metrics_frame(lc_metrics *m, const char *kind, const lc_frame_info *info);
void lc_metrics_encode(lc_metrics *m, double ms, long long pixels, size_t bytes);
void lc_metrics_bytes_sent(lc_metrics *m, size_t bytes);
void lc_metrics_coalesced(lc_metrics *m, uint64_t frames); /* requests overwritten while pending */
void lc_metrics_yielded(lc_metrics *m);                    /* a still pre-empted by newer input */
void lc_metrics_yield_wait(lc_metrics *m, double seconds); /* a large render waited at a yield point */
void lc_metrics_error(lc_metrics *m, const char *code);    /* errors answered, by code */
void lc_metrics_http_request(lc_metrics *m, int status);
/* A render refused before it ran: "cost" (over --max-cost), "deadline",
 * "queue", "client_queue". */
void lc_metrics_refused(lc_metrics *m, const char *reason);
/* A rendered request's estimated cost and the learned cost units per second. */
void lc_metrics_cost(lc_metrics *m, double cost, double rate);

/* Prometheus text (malloc'd, caller frees). */
char *lc_metrics_render(lc_metrics *m, const lc_metrics_gauges *g);

#ifdef __cplusplus
}
#endif
#endif
