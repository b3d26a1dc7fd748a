/* What requests hold of the one memory budget (held.h). */
#include "held.h"

#include <stdatomic.h>

static _Atomic uint64_t total;                  /* every kind's: the one checks compare */
static _Atomic uint64_t by_kind[LC_HELD_KINDS]; /* for the status figures */

void lc_held_add(lc_held_kind k, int64_t bytes)
{
    atomic_fetch_add(&total, (uint64_t)bytes); /* two's complement: a negative count subtracts */
    atomic_fetch_add(&by_kind[k], (uint64_t)bytes);
}

uint64_t lc_held(lc_held_kind k) { return atomic_load(&by_kind[k]); }

uint64_t lc_held_total(void) { return atomic_load(&total); }

int lc_held_reserve(lc_held_kind k, uint64_t *reserved, uint64_t want, uint64_t limit, uint64_t base,
                    uint64_t *free_out)
{
    uint64_t now = atomic_load(&total);
    for (;;) {
        uint64_t rest = now - *reserved; /* everything but this holder's */
        if (want > *reserved && limit && base + rest + want > limit) {
            if (free_out)
                *free_out = limit > base + rest ? limit - base - rest : 0;
            return -1;
        }
        if (atomic_compare_exchange_weak(&total, &now, rest + want))
            break;
    }
    atomic_fetch_add(&by_kind[k], want - *reserved);
    *reserved = want;
    return 0;
}
