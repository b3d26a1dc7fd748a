/* The yield gate in process (pool/yield.c): a large render waits while
 * another owner's moving frame renders or ended less than the gap ago, never
 * for its own, never longer than max_wait, and not at all once released;
 * which frames count as large. */
#include <pthread.h>
#include <time.h>

#include "lc_base.h"
#include "lc_test.h"
#include "yield.h"

/* Long enough that a busy machine's scheduling (tens of milliseconds) never
 * looks like a wait or its absence: each check's margin is most of a second. */
#define GAP 1.0
#define MAX_WAIT 3.0

static const int A = 1, B = 2; /* two owners (sessions) */

typedef struct ender {
    lc_yield_gate *g;
    double after;
} ender;

/* Ends A's moving frame `after` seconds from now, on another thread. */
static void *end_later(void *arg)
{
    ender *e = arg;
    struct timespec ts = {(time_t)e->after, (long)((e->after - (time_t)e->after) * 1e9)};
    nanosleep(&ts, NULL);
    lc_yield_interactive_end(e->g, &A);
    return NULL;
}

int main(void)
{
    lc_yield_gate g;
    lc_yield_gate_init(&g, GAP, MAX_WAIT);
    double waited = lc_yield_wait(&g, &B);
    CHECK(waited < 0.5 * GAP && g.waits == 0, "nobody drags: no wait (%.3f s)", waited);

    /* A drags without end: B waits max_wait, then goes on. */
    lc_yield_interactive_begin(&g, &A);
    CHECK(lc_yield_busy(&g, &B, lc_now()), "busy for B while A's moving frame renders");
    waited = lc_yield_wait(&g, &B);
    CHECK(waited >= MAX_WAIT - 0.01 && waited < MAX_WAIT + GAP, "bounded wait: %.3f s (max %.2f)", waited, MAX_WAIT);
    CHECK(g.waits == 1, "the wait is counted (%llu)", g.waits);

    /* A's frame ends 0.1 s from now: B waits that and the gap after it, not max_wait. */
    ender e = {&g, 0.1};
    pthread_t th;
    pthread_create(&th, NULL, end_later, &e);
    waited = lc_yield_wait(&g, &B);
    pthread_join(th, NULL);
    CHECK(waited >= 0.1 + GAP - 0.02 && waited < MAX_WAIT - 0.5, "waits for the frame and the gap: %.3f s", waited);
    double now = lc_now();
    CHECK(!lc_yield_busy(&g, &B, now), "quiet after the gap");

    /* An owner never waits for its own moving frames. */
    lc_yield_interactive_begin(&g, &A);
    lc_yield_interactive_end(&g, &A);
    CHECK(lc_yield_busy(&g, &B, lc_now()) && !lc_yield_busy(&g, &A, lc_now()), "A's own gap holds B only");

    /* Released (stopping, abandoned): nobody waits, even while a moving frame renders. */
    lc_yield_interactive_begin(&g, &A);
    lc_yield_release(&g);
    waited = lc_yield_wait(&g, &B);
    CHECK(waited < 0.5 * GAP, "released: no wait (%.3f s)", waited);

    /* Large: 0.5 s at the learned rate, or 2.5e7 units before one is learned. */
    CHECK(lc_yield_large(3e7, 0) && !lc_yield_large(2e7, 0), "without a rate: the cost threshold");
    CHECK(lc_yield_large(1e7, 1e7) && !lc_yield_large(4e6, 1e7), "with a rate: half a second");
    CHECK(!lc_yield_large(0, 1e7), "no cost estimate: not large");
    lc_yield_gate_destroy(&g);
    return lc_test_finish();
}
