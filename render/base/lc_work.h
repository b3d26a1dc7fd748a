/* Work budgets: a counter of the work a request has done so far against the
 * budget it was granted, charged as the work happens (RK4 steps of tracing,
 * render time at the renderer's yield points), so that work the estimate did
 * not foresee stops with an error naming the request field to lower instead
 * of running on (docs/ALGORITHM.md "Work budgets").
 *
 * Units are the cost model's (the server's cost.h: about one fragment
 * written by one pass). render/ counts; the owner (the server) sets the
 * limit, the field named when it is exceeded and, for time-based charges,
 * the rate that turns seconds into units.
 *
 * Threading: lc_work_charge and lc_work_charge_elapsed may be called from any
 * number of threads at once (tracing threads share one budget); init and the
 * setters before the work starts. The struct is plain data owned by its
 * caller; the renderer and the tracer only borrow it for one frame. */
#ifndef LC_WORK_H
#define LC_WORK_H

#include <stdatomic.h>
#include <stdbool.h>

#include "lc_base.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct lc_work_budget {
    _Atomic double used;            /* units charged so far */
    double limit;                   /* units granted; <= 0 = no limit (counts only) */
    double rate;                    /* units per second of elapsed work, for lc_work_charge_elapsed; 0 = none */
    double started;                 /* lc_now() when the timed part began */
    _Atomic double timed;           /* units of elapsed time charged so far (part of used) */
    char field[LC_ERROR_FIELD_LEN]; /* the request field to lower, named in the error */
} lc_work_budget;

/* limit in units (<= 0: none); field: the request field to name ("" = none). */
void lc_work_init(lc_work_budget *b, double limit, const char *field);
/* Turns on time charges: from now on, lc_work_charge_elapsed charges
 * (now - started) * rate units in all (rate <= 0: never). */
void lc_work_time(lc_work_budget *b, double rate);

/* Leaves `seconds` out of the elapsed time (a wait that did no work, e.g. a
 * yield point giving the cores to another session). Same thread as the charges' owner. */
void lc_work_exclude(lc_work_budget *b, double seconds);

/* Adds units (b may be NULL: nothing to count). 0 while used <= limit, else
 * LC_ERR_BUDGET; once exceeded it stays exceeded. */
int lc_work_charge(lc_work_budget *b, double units);
/* Brings the timed part up to the elapsed time since lc_work_time times the
 * rate, then checks as lc_work_charge does. */
int lc_work_charge_elapsed(lc_work_budget *b);
/* Whether used > limit (false for NULL or no limit). */
bool lc_work_exceeded(const lc_work_budget *b);
double lc_work_used(const lc_work_budget *b);

/* Fills err with LC_ERR_BUDGET naming b->field: "<field>: <what> used <used>
 * units of work, over the <limit> granted to this request; lower <field>".
 * Returns LC_ERR_BUDGET. */
int lc_work_err(const lc_work_budget *b, lc_error *err, const char *what);

#ifdef __cplusplus
}
#endif
#endif
