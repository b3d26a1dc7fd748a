/* What requests hold of the one memory budget (--max-memory) beside the
 * loaded datasets and fields (lc_datasets_budget): the streamline sets they
 * trace (traced.h) and the curves of their surfaces (surface_memory.h), by
 * kind. Every holder adds its bytes here before it allocates them, so that
 * each check sees the others. Locking: atomics only; any thread. */
#ifndef LC_SERVER_HELD_H
#define LC_SERVER_HELD_H

#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef enum { LC_HELD_STREAMLINE_SETS, LC_HELD_SURFACES, LC_HELD_KINDS } lc_held_kind;

/* Counts bytes (negative: gives them back) for kind k, unchecked. */
void lc_held_add(lc_held_kind k, int64_t bytes);
/* Bytes kind k holds now; lc_held_total: every kind's. */
uint64_t lc_held(lc_held_kind k);
uint64_t lc_held_total(void);
/* Sets a holder's count *reserved (part of kind k's) to want. Growth fails
 * (-1, nothing changed) when `base` (the datasets' estimate) and every
 * kind's bytes with want would exceed limit (0 = none); *free_out (may be
 * NULL) is then what was left for this holder. Shrinking never fails. */
int lc_held_reserve(lc_held_kind k, uint64_t *reserved, uint64_t want, uint64_t limit, uint64_t base,
                    uint64_t *free_out);

#ifdef __cplusplus
}
#endif
#endif
