/* The render queue's order: tasks queued per client, the clients served round
 * robin (one task of each client in turn), so that one client that queues
 * many renders delays each other client by at most one of them. A plain data
 * structure: the worker pool's lock guards it (workers.c), and the unit tests
 * drive it without threads. */
#ifndef LC_SERVER_FAIR_QUEUE_H
#define LC_SERVER_FAIR_QUEUE_H

#include <stdbool.h>
#include <stdint.h>

struct lc_render_job;
struct lc_session;

/* A queued task: an HTTP job or a WebSocket session that needs a frame. */
typedef struct lc_task {
    struct lc_task *next;
    uint64_t key;              /* the client: a session's address, or a one-shot request's client key */
    struct lc_render_job *job; /* counted among the client's queued jobs */
    struct lc_session *session;
} lc_task;

typedef struct lc_flow lc_flow; /* one client's queued tasks (FIFO) */

typedef struct lc_fair_queue {
    lc_flow *ring_head, *ring_tail; /* clients with queued tasks, next to serve first */
    int tasks, jobs, clients;
} lc_fair_queue;

/* Queues t (t->key set) behind its client's earlier tasks; a client new to
 * the ring goes to its end. -1 when out of memory (t not queued). */
int lc_fair_push(lc_fair_queue *q, lc_task *t);
/* The next client's oldest task, or NULL; that client moves to the end of the ring. */
lc_task *lc_fair_pop(lc_fair_queue *q);
/* The same among the tasks for which take(t, ctx) holds (take NULL: all):
 * the first client in ring order with such a task gives its oldest one and
 * moves to the end of the ring; clients passed over keep their places. The
 * pool takes only short tasks this way when every other worker holds a long
 * one (workers.c). */
lc_task *lc_fair_pop_where(lc_fair_queue *q, bool (*take)(const lc_task *t, void *ctx), void *ctx);
/* The same without serving: the task leaves the queue, its client keeps its
 * place in the ring (queued work that will not run, e.g. past its deadline). */
lc_task *lc_fair_remove_where(lc_fair_queue *q, bool (*take)(const lc_task *t, void *ctx), void *ctx);
/* Calls fn for every queued task (ring order, each client's oldest first). */
void lc_fair_each(const lc_fair_queue *q, void (*fn)(const lc_task *t, void *ctx), void *ctx);
/* Jobs queued by the client `key`. */
int lc_fair_jobs_of(const lc_fair_queue *q, uint64_t key);

#endif
