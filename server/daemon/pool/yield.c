/* The yield gate: large renders wait at their yield points while other
 * sessions' interactive frames render (yield.h). */
#include "yield.h"

#include <time.h>

#include "lc_base.h"

void lc_yield_gate_init(lc_yield_gate *g, double gap, double max_wait)
{
    *g = (lc_yield_gate){.gap = gap, .max_wait = max_wait};
    pthread_mutex_init(&g->lock, NULL);
    pthread_condattr_t ca;
    pthread_condattr_init(&ca);
    pthread_condattr_setclock(&ca, CLOCK_MONOTONIC); /* lc_now()'s clock */
    pthread_cond_init(&g->calm, &ca);
    pthread_condattr_destroy(&ca);
}

void lc_yield_gate_destroy(lc_yield_gate *g)
{
    pthread_mutex_destroy(&g->lock);
    pthread_cond_destroy(&g->calm);
}

void lc_yield_interactive_begin(lc_yield_gate *g, const void *owner)
{
    (void)owner;
    pthread_mutex_lock(&g->lock);
    g->in_hand++;
    pthread_mutex_unlock(&g->lock);
}

void lc_yield_interactive_end(lc_yield_gate *g, const void *owner)
{
    pthread_mutex_lock(&g->lock);
    if (g->in_hand > 0)
        g->in_hand--;
    g->last_end = lc_now();
    g->last_owner = owner;
    pthread_cond_broadcast(&g->calm);
    pthread_mutex_unlock(&g->lock);
}

/* Lock held. The owner's own moving frames never run beside its large one (a
 * session renders one frame at a time), so in_hand counts other owners'. */
static bool busy_locked(const lc_yield_gate *g, const void *owner, double now)
{
    if (g->released)
        return false;
    if (g->in_hand > 0)
        return true;
    return g->last_end > 0 && g->last_owner != owner && now - g->last_end < g->gap;
}

bool lc_yield_busy(lc_yield_gate *g, const void *owner, double now)
{
    pthread_mutex_lock(&g->lock);
    bool busy = busy_locked(g, owner, now);
    pthread_mutex_unlock(&g->lock);
    return busy;
}

void lc_cond_wait_until(pthread_cond_t *c, pthread_mutex_t *m, double when)
{
    struct timespec ts;
    ts.tv_sec = (time_t)when;
    ts.tv_nsec = (long)((when - (double)ts.tv_sec) * 1e9);
    if (ts.tv_nsec >= 1000000000L) {
        ts.tv_sec++;
        ts.tv_nsec -= 1000000000L;
    }
    pthread_cond_timedwait(c, m, &ts);
}

double lc_yield_wait(lc_yield_gate *g, const void *owner)
{
    double start = lc_now(), limit = start + g->max_wait, now = start;
    pthread_mutex_lock(&g->lock);
    bool waited = false;
    while (busy_locked(g, owner, now) && now < limit) {
        waited = true;
        /* Wake when the quiet gap after the last frame would be over, or at an end. */
        double until = g->in_hand > 0 ? limit : g->last_end + g->gap;
        lc_cond_wait_until(&g->calm, &g->lock, until < limit ? until : limit);
        now = lc_now();
    }
    if (waited)
        g->waits++;
    pthread_mutex_unlock(&g->lock);
    return waited ? now - start : 0.0;
}

void lc_yield_release(lc_yield_gate *g)
{
    pthread_mutex_lock(&g->lock);
    g->released = true;
    pthread_cond_broadcast(&g->calm);
    pthread_mutex_unlock(&g->lock);
}

bool lc_yield_large(double cost, double rate)
{
    if (!(cost > 0))
        return false;
    return rate > 0 ? cost / rate >= LC_YIELD_LARGE_SECONDS : cost >= LC_YIELD_LARGE_COST;
}
