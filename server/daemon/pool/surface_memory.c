/* What surface-layers frames hold of --max-memory (surface_memory.h). */
#include "surface_memory.h"

#include <math.h>

#include "cost.h"
#include "datasets.h"
#include "held.h"
#include "trace.h"

uint64_t lc_surface_curve_bytes(uint64_t n)
{
    uint64_t cap = 64;
    while (cap < n)
        cap *= 2;
    return cap * 8 * sizeof(float) + sizeof(lc_trace_curve);
}

uint64_t lc_surface_curve_estimate(const lc_field *f, const lc_surface_request *s)
{
    const double *b = f->bounds;
    double diag = sqrt((b[3] - b[0]) * (b[3] - b[0]) + (b[4] - b[1]) * (b[4] - b[1]) + (b[5] - b[2]) * (b[5] - b[2]));
    double steps = lc_cost_surface_steps(diag, f->mag_max, s->step, s->length);
    if (s->direction == LC_TRACE_BOTH) /* the backward half, the seed, the forward half */
        return lc_surface_curve_bytes((uint64_t)(2 * ceil(steps)) + 1);
    return lc_surface_curve_bytes((uint64_t)ceil(steps) + 1);
}

int lc_surface_memory_reserve(uint64_t *reserved, uint64_t want, const lc_surface_budget *b, uint64_t *free_out)
{
    return lc_held_reserve(LC_HELD_SURFACES, reserved, want, b ? b->limit : 0, b ? b->others : 0, free_out);
}

void lc_surface_budget_of(lc_server *srv, lc_surface_budget *b)
{
    uint64_t estimated = 0, limit = 0;
    lc_datasets_budget(srv->datasets, &estimated, &limit);
    *b = (lc_surface_budget){.limit = limit, .others = estimated};
}
