/* The pool's kept surface layers (surface_keeps.h). */
#include "surface_keeps.h"

#include <pthread.h>
#include <stdbool.h>
#include <stdlib.h>

typedef struct slot {
    lc_surface_keep *keep;
    bool busy;
    double used; /* lc_now() when its last frame ended */
} slot;

struct lc_surface_keeps {
    pthread_mutex_t lock;
    int n;
    slot *slots;
};

lc_surface_keeps *lc_surface_keeps_create(int slots)
{
    lc_surface_keeps *ks = calloc(1, sizeof *ks);
    if (!ks)
        return NULL;
    ks->n = slots > 0 ? slots : 1;
    ks->slots = calloc((size_t)ks->n, sizeof *ks->slots);
    for (int i = 0; ks->slots && i < ks->n; i++)
        if (!(ks->slots[i].keep = lc_surface_keep_create()))
            ks->n = i; /* fewer slots: frames beyond them draw all their curves */
    if (!ks->slots) {
        free(ks);
        return NULL;
    }
    pthread_mutex_init(&ks->lock, NULL);
    return ks;
}

lc_surface_keep *lc_surface_keeps_take(lc_surface_keeps *ks, uint64_t curves_id)
{
    if (!ks)
        return NULL;
    pthread_mutex_lock(&ks->lock);
    slot *best = NULL;
    int best_rank = 0; /* 3: holds these curves, 2: empty, 1: the oldest other */
    for (int i = 0; i < ks->n; i++) {
        slot *s = &ks->slots[i];
        if (s->busy)
            continue;
        uint64_t id = lc_surface_keep_id(s->keep);
        int rank = curves_id && id == curves_id ? 3 : id == 0 ? 2 : 1;
        if (rank > best_rank || (rank == best_rank && rank == 1 && s->used < best->used))
            best = s, best_rank = rank;
    }
    if (best)
        best->busy = true;
    pthread_mutex_unlock(&ks->lock);
    return best ? best->keep : NULL;
}

void lc_surface_keeps_give(lc_surface_keeps *ks, lc_surface_keep *k, double now)
{
    if (!ks || !k)
        return;
    pthread_mutex_lock(&ks->lock);
    for (int i = 0; i < ks->n; i++)
        if (ks->slots[i].keep == k)
            ks->slots[i].busy = false, ks->slots[i].used = now;
    pthread_mutex_unlock(&ks->lock);
}

double lc_surface_keeps_due(lc_surface_keeps *ks)
{
    if (!ks)
        return 0;
    double due = 0;
    pthread_mutex_lock(&ks->lock);
    for (int i = 0; i < ks->n; i++) {
        const slot *s = &ks->slots[i];
        if (!s->busy && lc_surface_keep_holds(s->keep) && (due == 0 || s->used + LC_SURFACE_KEEP_IDLE < due))
            due = s->used + LC_SURFACE_KEEP_IDLE;
    }
    pthread_mutex_unlock(&ks->lock);
    return due;
}

void lc_surface_keeps_trim(lc_surface_keeps *ks, double now)
{
    if (!ks)
        return;
    pthread_mutex_lock(&ks->lock); /* held while freeing: a take meanwhile waits, briefly */
    for (int i = 0; i < ks->n; i++) {
        slot *s = &ks->slots[i];
        if (!s->busy && lc_surface_keep_holds(s->keep) && s->used + LC_SURFACE_KEEP_IDLE <= now)
            lc_surface_keep_release(s->keep);
    }
    pthread_mutex_unlock(&ks->lock);
}

void lc_surface_keeps_destroy(lc_surface_keeps *ks)
{
    if (!ks)
        return;
    for (int i = 0; i < ks->n; i++)
        lc_surface_keep_destroy(ks->slots[i].keep);
    pthread_mutex_destroy(&ks->lock);
    free(ks->slots);
    free(ks);
}
