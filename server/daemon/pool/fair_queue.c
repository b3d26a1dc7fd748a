/* The render queue's order: per-client FIFOs served round robin (fair_queue.h). */
#include "fair_queue.h"

#include <stdbool.h>
#include <stdlib.h>

struct lc_flow {
    lc_flow *next; /* in the ring of clients with work */
    uint64_t key;
    lc_task *head, *tail;
    int jobs; /* HTTP jobs among the tasks */
};

static lc_flow *find_flow(const lc_fair_queue *q, uint64_t key)
{
    for (lc_flow *f = q->ring_head; f; f = f->next)
        if (f->key == key)
            return f;
    return NULL;
}

static void ring_append(lc_fair_queue *q, lc_flow *f)
{
    f->next = NULL;
    if (q->ring_tail)
        q->ring_tail->next = f;
    else
        q->ring_head = f;
    q->ring_tail = f;
}

int lc_fair_push(lc_fair_queue *q, lc_task *t)
{
    lc_flow *f = find_flow(q, t->key);
    if (!f) {
        f = calloc(1, sizeof *f);
        if (!f)
            return -1;
        f->key = t->key;
        ring_append(q, f);
        q->clients++;
    }
    t->next = NULL;
    if (f->tail)
        f->tail->next = t;
    else
        f->head = t;
    f->tail = t;
    if (t->job) {
        f->jobs++;
        q->jobs++;
    }
    q->tasks++;
    return 0;
}

lc_task *lc_fair_pop(lc_fair_queue *q) { return lc_fair_pop_where(q, NULL, NULL); }

/* The first task for which take holds, out of the queue; its client goes to
 * the end of the ring (served) or keeps its place (not served: removed). */
static lc_task *take_where(lc_fair_queue *q, bool (*take)(const lc_task *t, void *ctx), void *ctx, bool served)
{
    lc_flow *fp = NULL, *f = q->ring_head; /* fp: the flow before f in the ring */
    lc_task *tp = NULL, *t = NULL;         /* tp: the task before t in f */
    for (; f; fp = f, f = f->next) {
        for (tp = NULL, t = f->head; t && take && !take(t, ctx); tp = t, t = t->next)
            ;
        if (t)
            break;
    }
    if (!t)
        return NULL;
    if (tp)
        tp->next = t->next;
    else
        f->head = t->next;
    if (f->tail == t)
        f->tail = tp;
    if (t->job) {
        f->jobs--;
        q->jobs--;
    }
    q->tasks--;
    /* f leaves its place in the ring: to the end when it has more, else gone */
    t->next = NULL;
    if (f->head && !served)
        return t;
    if (fp)
        fp->next = f->next;
    else
        q->ring_head = f->next;
    if (q->ring_tail == f)
        q->ring_tail = fp;
    if (f->head) {
        ring_append(q, f);
    } else {
        free(f);
        q->clients--;
    }
    return t;
}

lc_task *lc_fair_pop_where(lc_fair_queue *q, bool (*take)(const lc_task *t, void *ctx), void *ctx)
{
    return take_where(q, take, ctx, true);
}

lc_task *lc_fair_remove_where(lc_fair_queue *q, bool (*take)(const lc_task *t, void *ctx), void *ctx)
{
    return take_where(q, take, ctx, false);
}

void lc_fair_each(const lc_fair_queue *q, void (*fn)(const lc_task *t, void *ctx), void *ctx)
{
    for (const lc_flow *f = q->ring_head; f; f = f->next)
        for (const lc_task *t = f->head; t; t = t->next)
            fn(t, ctx);
}

int lc_fair_jobs_of(const lc_fair_queue *q, uint64_t key)
{
    const lc_flow *f = find_flow(q, key);
    return f ? f->jobs : 0;
}
