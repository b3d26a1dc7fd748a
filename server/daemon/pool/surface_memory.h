/* What surface-layers frames hold of --max-memory (docs/ALGORITHM.md §33,
 * "Memory held by requests"): the curves a WebSocket surface session keeps between frames and
 * those a one-shot surface traces while it renders. Each holder reserves its
 * bytes before tracing them, as what requests hold (held.h), checked against
 * the one memory budget: --max-memory less the loaded datasets and fields
 * (lc_datasets_budget) and everything requests hold (streamline sets, other
 * surfaces). Locking: atomics only; any thread. */
#ifndef LC_SERVER_SURFACE_MEMORY_H
#define LC_SERVER_SURFACE_MEMORY_H

#include <stdint.h>

#include "field.h"
#include "request.h"
#include "server.h"

#ifdef __cplusplus
extern "C" {
#endif

/* The budget a reservation is checked against: limit 0 = none; others: the
 * datasets' and fields' estimate (what requests hold is added by held.h). */
typedef struct lc_surface_budget {
    uint64_t limit, others;
} lc_surface_budget;

/* srv's budget: --max-memory and the datasets' and fields' estimate. */
void lc_surface_budget_of(lc_server *srv, lc_surface_budget *b);

/* Resident bytes of one traced curve of n vertices: position, normal, time
 * and speed (8 floats a vertex) in arrays grown by doubling from 64
 * (render/field/trace.c), and the curve itself. */
uint64_t lc_surface_curve_bytes(uint64_t n);
/* The estimate of one curve of surface s on field f before it is traced:
 * the steps the cost model assumes (lc_cost_surface_steps, both halves for a
 * two-way surface). */
uint64_t lc_surface_curve_estimate(const lc_field *f, const lc_surface_request *s);

/* Grows (or shrinks) a holder's reservation *reserved to `want` bytes
 * (lc_held_reserve; b NULL = unchecked). Growth fails (-1, nothing changed)
 * when everything held with want would exceed b's limit beside b->others;
 * *free_out (may be NULL) is then what was left for this holder. */
int lc_surface_memory_reserve(uint64_t *reserved, uint64_t want, const lc_surface_budget *b, uint64_t *free_out);

#ifdef __cplusplus
}
#endif
#endif
