/* The one CPU fan-out of render/: a loop of independent jobs over threads it starts and joins before returning. */
#ifndef LC_PARALLEL_H
#define LC_PARALLEL_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Most threads one lc_parallel_for starts; further jobs run on the caller's thread. */
#define LC_PARALLEL_MAX 64

/* Runs fn on each of the n jobs (job t at (char *)jobs + t * size): job 0 and
 * any job whose thread could not start (or beyond LC_PARALLEL_MAX) run on the
 * calling thread, every other job on a thread of its own, all joined before
 * it returns. Jobs must not depend on each other's order; each writes only its
 * own job (and what the caller partitioned for it), so a result is the same
 * whatever threads were granted. Callable from any thread; keeps no state. */
void lc_parallel_for(uint32_t n, void (*fn)(void *job), void *jobs, size_t size);

/* Online CPU cores, clamped to [1, max]. */
uint32_t lc_parallel_cores(uint32_t max);

#ifdef __cplusplus
}
#endif

#endif
