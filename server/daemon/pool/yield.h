/* Yielding between render workers (docs/ARCHITECTURE.md "Yielding"): the
 * gate that large renders (HTTP renders, movie frames and session stills of
 * high estimated cost) pass at each of the renderer's yield points. While
 * another session's interactive (moving) frame is rendering, or one ended
 * less than `gap` seconds ago (a drag's next frame is due), a large render
 * waits, so that on a CPU host the drag gets the cores; it waits at most
 * `max_wait` seconds per yield point, so it always finishes (one pass or tile
 * per max_wait under continuous interaction). A plain structure with its own
 * lock: the worker pool (workers.c) drives it, unit tests drive it directly. */
#ifndef LC_SERVER_YIELD_H
#define LC_SERVER_YIELD_H

#include <pthread.h>
#include <stdbool.h>

/* Seconds of render time (cost / learned rate, cost.h) from which a frame yields. */
#define LC_YIELD_LARGE_SECONDS 0.5
/* Without a learned rate: the cost units from which a frame yields (cost.h
 * measures 2e7..5e7 units per second on llvmpipe). */
#define LC_YIELD_LARGE_COST 2.5e7
/* One-shot frames above LC_LARGE_FRAME_PIXELS (renderer.h) composite in tiles
 * of at most this side when the pool has 2 or more workers: a yield point per
 * tile. By pixels alone, so that a request's image never depends on the load. */
#define LC_YIELD_TILE 1024
/* The longest wait at one yield point. */
#define LC_YIELD_MAX_WAIT 2.0

typedef struct lc_yield_gate {
    pthread_mutex_t lock;
    pthread_cond_t calm; /* an interactive frame ended, or the gate was released */
    double gap, max_wait;
    int in_hand;              /* interactive frames rendering now */
    double last_end;          /* lc_now() when the latest one ended (0: none yet) */
    const void *last_owner;   /* whose it was (a session) */
    bool released;            /* stopping: nobody waits any more */
    unsigned long long waits; /* yield points that waited (stats, tests) */
} lc_yield_gate;

void lc_yield_gate_init(lc_yield_gate *g, double gap, double max_wait);
void lc_yield_gate_destroy(lc_yield_gate *g);
/* An interactive frame of owner begins / ends on some worker. Any thread. */
void lc_yield_interactive_begin(lc_yield_gate *g, const void *owner);
void lc_yield_interactive_end(lc_yield_gate *g, const void *owner);
/* Whether a large render of owner should wait at time now: another owner's
 * interactive frame is in hand or ended less than gap ago. */
bool lc_yield_busy(lc_yield_gate *g, const void *owner, double now);
/* Blocks while lc_yield_busy holds, at most max_wait seconds; returns the
 * seconds waited (0: it did not wait). A large render's yield point. Any thread. */
double lc_yield_wait(lc_yield_gate *g, const void *owner);
/* Wakes every waiter and lets nobody wait again (the pool stops or is abandoned). */
void lc_yield_release(lc_yield_gate *g);
/* Whether a frame of estimated `cost` is large enough to yield, given the
 * learned rate (cost units per second; 0 = none measured yet). */
bool lc_yield_large(double cost, double rate);
/* pthread_cond_timedwait until lc_now() time `when`, for condition variables
 * created on CLOCK_MONOTONIC (lc_now()'s clock). */
void lc_cond_wait_until(pthread_cond_t *c, pthread_mutex_t *m, double when);

#endif
