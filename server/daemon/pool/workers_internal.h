/* The render worker pool's private state, shared by workers.c (the threads
 * and their frames) and workers_stop.c (abandon, stop, destroy, and the two
 * helpers below that workers.c calls there): nothing outside
 * server/daemon/pool includes it. */
#ifndef LC_SERVER_WORKERS_INTERNAL_H
#define LC_SERVER_WORKERS_INTERNAL_H

#include <pthread.h>
#include <stdbool.h>

#include "encoders.h"
#include "fair_queue.h"
#include "gl_context.h"
#include "renderer.h"
#include "server.h"
#include "session.h"
#include "surface_keeps.h"
#include "yield.h"

typedef struct lc_workers lc_workers;

#define LC_IDLE_TRIM_DELAY 1.0 /* seconds after a large frame (worker.trim_at) */
/* Jobs this long (seconds by the learned rate; without one, units of cost.h)
 * never hold every worker (workers.c long_job): about two frames of a drag. */
#define LC_LONG_JOB_SECONDS 0.1
#define LC_LONG_JOB_COST 5e6

typedef struct worker {
    lc_workers *pool;
    int index;
    pthread_t thread;
    bool started;
    lc_gl *gl;
    lc_renderer *renderer;
    /* The frame being rendered (under the pool's lock), for lc_workers_abandon;
     * lost: that function answered the job meanwhile. */
    lc_render_job *job;
    lc_session *session;
    bool lost;
    lc_session *progress; /* the stream session whose frame the renderer reports on (render thread only) */
    /* The frame's yield points (render thread only, yield.h): the session whose input pre-empts
     * it; large: it waits for other sessions' moving frames (owner: whose frame it is). */
    lc_session *preempt;
    lc_work_budget *work; /* the frame's measured budget (cost.h), its waits left out (render thread only) */
    bool large;
    const void *owner;
    /* After a large frame: when the idle worker returns the heap to the
     * system once more (0 = not due). The driver's own threads free some of
     * the frame's memory after the frame has been read back, later than the
     * trim right after it. Render thread only. */
    double trim_at;
} worker;

struct lc_workers {
    lc_server *srv;
    int nworkers, max_queue;
    worker *workers;
    lc_encoders *encoders; /* where the readbacks go (encoders.c) */

    pthread_mutex_t lock; /* guards the render FIFO, the timer list and sessions' sched_* fields */
    pthread_cond_t work;  /* FIFO non-empty, timer list changed, stopping */
    pthread_cond_t ready; /* start-up progress */
    int ready_count, failed;
    lc_error start_err;
    bool stopping;
    bool abandoned;           /* lc_workers_abandon ran (the watchdog and mpirun's signal may both call it) */
    lc_fair_queue queue;      /* the render tasks, by client (fair_queue.h) */
    _Atomic double cost_rate; /* learned cost units per second of render (0 = none yet); written under lock */
    /* Workers rendering a long job now (under lock): with two or more workers,
     * a long job never takes the last one (workers.c long_job). */
    int long_running;
    lc_session *timed;               /* sessions waiting for their still frame (linked by sched_next) */
    lc_yield_gate gate;              /* large renders wait here for other sessions' moving frames (yield.h) */
    lc_surface_keeps *surface_keeps; /* surface sessions' layers across frames (surface_keeps.h); NULL: none kept */
    /* The queue's deadline thread (queue_deadline.h), woken to stop. */
    pthread_t deadline_thread;
    pthread_cond_t deadline_wake;
    bool deadline_started;
};

/* workers_stop.c: removes s from the timer list if present (pool lock
 * held); hands an answered job back to its submitter (its done callback). */
void lc_workers_untime(lc_workers *w, lc_session *s);
void lc_workers_finish_job(lc_render_job *job);

#endif
