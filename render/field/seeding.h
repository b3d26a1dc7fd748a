/* Seeding of streamline sets (docs/ALGORITHM.md §22): the seed points of a
 * set (given points, a rake, a volume box, or density-driven evenly spaced
 * seeds) and the set's curves traced from them with trace.h.
 * Threading: lc_seeding_trace runs on the caller's thread and `threads` more;
 * it only reads the field. */
#ifndef LC_FIELD_SEEDING_H
#define LC_FIELD_SEEDING_H

#include <stdint.h>

#include "field.h"
#include "lc_base.h"
#include "trace.h"

#ifdef __cplusplus
extern "C" {
#endif

#define LC_SEEDING_MAX_LINES 100000 /* curves of one set */
#define LC_SEEDING_CANDIDATES 64    /* density: candidates tried per line wanted */

typedef enum {
    LC_SEEDING_POINTS = 0, /* the given points */
    LC_SEEDING_RAKE,       /* count points evenly from `from` to `to`, both ends included */
    LC_SEEDING_BOX,        /* count Halton points in the box [from, to] */
    LC_SEEDING_DENSITY     /* the box's Halton points, each kept only beyond `separation` of the lines so far */
} lc_seeding_kind;

/* A streamline set; zero = defaults. */
typedef struct lc_seeding_desc {
    lc_seeding_kind kind;
    uint32_t count;       /* rake, box, density: curves wanted (1 .. LC_SEEDING_MAX_LINES); 0 = 64 */
    const double *points; /* points: 3 per seed (the caller's; read only during the call) */
    uint32_t point_count;
    double from[3], to[3]; /* rake: its ends; box, density: min and max corners (all 0 = the field's bounds) */
    double separation;     /* density: d_sep; 0 = half the edge of a cube of the box's volume / count */
    lc_trace_desc trace;   /* step, direction, length, ... of every curve */
} lc_seeding_desc;

/* What a traced set took. */
typedef struct lc_seeding_stats {
    uint32_t candidates; /* seed points considered (density: Halton points tried) */
    double separation;   /* density: the d_sep used */
} lc_seeding_stats;

/* Rake: count points from a to b at a + (b - a) i / (count - 1), both ends
 * included (count 1: the midpoint), into out (3 * count doubles). */
void lc_seeding_rake(const double a[3], const double b[3], uint32_t count, double *out);
/* The k-th point (k from 0) of the box [lo, hi]: the Halton point of index
 * k + 1 in bases 2, 3 and 5 scaled into the box, so that any prefix of the
 * sequence spreads evenly over it. */
void lc_seeding_halton(const double lo[3], const double hi[3], uint64_t k, double out[3]);

/* Validates desc against f: a count in range, finite points and corners, a
 * box of positive extent, a positive separation. Errors name the setting
 * ("seeding.count", "seeding.points", "seeding.box", ...). */
int lc_seeding_check(const lc_field *f, const lc_seeding_desc *desc, lc_error *err);

/* Traces the set: *curves (malloc'd array; free with lc_trace_curves_free
 * then free) holds *count curves, seeds (when not NULL) their seed points
 * (malloc'd, 3 per curve). Density seeding traces a candidate only once it is
 * at least d_sep from every vertex of the curves kept before it, and stops
 * after count curves or LC_SEEDING_CANDIDATES * count candidates. A seed
 * outside the domain gives a curve of 1 vertex (points, rake, box). */
int lc_seeding_trace(const lc_field *f, const lc_seeding_desc *desc, int threads, lc_trace_curve **curves,
                     uint32_t *count, double **seeds, lc_seeding_stats *stats, lc_error *err);

#ifdef __cplusplus
}
#endif
#endif
