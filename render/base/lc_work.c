/* Work budgets: counted work against a granted limit (lc_work.h). */
#include "lc_work.h"

#include <stdio.h>
#include <string.h>

void lc_work_init(lc_work_budget *b, double limit, const char *field)
{
    memset(b, 0, sizeof *b);
    atomic_init(&b->used, 0.0);
    atomic_init(&b->timed, 0.0);
    b->limit = limit;
    snprintf(b->field, sizeof b->field, "%s", field ? field : "");
}

void lc_work_time(lc_work_budget *b, double rate)
{
    b->rate = rate > 0 ? rate : 0;
    b->started = lc_now();
}

void lc_work_exclude(lc_work_budget *b, double seconds)
{
    if (b && seconds > 0)
        b->started += seconds;
}

/* used += units, lock-free (doubles have no atomic add). */
static double add(_Atomic double *x, double units)
{
    double old = atomic_load(x);
    while (!atomic_compare_exchange_weak(x, &old, old + units))
        ;
    return old + units;
}

int lc_work_charge(lc_work_budget *b, double units)
{
    if (!b)
        return 0;
    double used = units > 0 ? add(&b->used, units) : atomic_load(&b->used);
    return b->limit > 0 && used > b->limit ? LC_ERR_BUDGET : 0;
}

int lc_work_charge_elapsed(lc_work_budget *b)
{
    if (!b)
        return 0;
    if (!(b->rate > 0))
        return lc_work_charge(b, 0);
    double want = (lc_now() - b->started) * b->rate, had = atomic_load(&b->timed);
    /* Only the thread that moves timed forward charges the difference. */
    while (want > had && !atomic_compare_exchange_weak(&b->timed, &had, want))
        ;
    return lc_work_charge(b, want > had ? want - had : 0);
}

bool lc_work_exceeded(const lc_work_budget *b)
{
    return b && b->limit > 0 && atomic_load(&((lc_work_budget *)b)->used) > b->limit;
}

double lc_work_used(const lc_work_budget *b) { return b ? atomic_load(&((lc_work_budget *)b)->used) : 0; }

int lc_work_err(const lc_work_budget *b, lc_error *err, const char *what)
{
    const char *field = b && b->field[0] ? b->field : "";
    double used = lc_work_used(b), limit = b ? b->limit : 0;
    if (field[0])
        return lc_err_field(err, LC_ERR_BUDGET, field,
                            "%s used %.6g units of work, over the %.6g granted to this request; lower %s", what, used,
                            limit, field);
    return lc_err(err, LC_ERR_BUDGET, "%s used %.6g units of work, over the %.6g granted to this request", what, used,
                  limit);
}
