/* A worker's frame of method "surface-layers", one-shot or a session's
 * (surface_job.h). */
#include "surface_job.h"

#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "admit.h"
#include "cost.h"
#include "session.h"
#include "surface_memory.h"
#include "surface_render.h"

#define TRACE_THREADS_MAX 8

static int trace_threads(void)
{
    /* Tracing is CPU work on the worker's thread and a few more: the frame waits for it anyway. */
    long cpus = sysconf(_SC_NPROCESSORS_ONLN);
    return cpus < 1 ? 1 : cpus > TRACE_THREADS_MAX ? TRACE_THREADS_MAX : (int)cpus;
}

static int to_params(const lc_surface_request *s, lc_surface_params *sp, lc_seed *seed, lc_error *err)
{
    if (s->seed_count < 2 || s->seed_count > LC_SEED_MAX_POINTS)
        return lc_err_field(err, LC_ERR_INVALID, "surface.seed", "surface.seed: 2 to %d points", LC_SEED_MAX_POINTS);
    memset(seed, 0, sizeof *seed);
    seed->count = s->seed_count;
    memcpy(seed->points, s->seed, (size_t)s->seed_count * sizeof s->seed[0]);
    *sp = (lc_surface_params){.particles = s->particles,
                              .step = s->step,
                              .length = s->length,
                              .direction = s->direction,
                              .epsilon = s->epsilon,
                              .opacity = s->opacity,
                              .max_layers = s->max_layers,
                              .composite = (int)s->composite};
    memcpy(sp->color, s->color, sizeof sp->color);
    return 0;
}

/* The frame info of a surface frame from its statistics. */
static void fill_info(lc_frame_info *info, const lc_surface_info *si)
{
    info->element_count = (uint32_t)si->stats.curves;
    info->has_surface = 1;
    info->surface_curves = si->stats.curves;
    info->surface_overflow = si->stats.overflow;
    info->surface_k = si->k;
    info->surface_max_layers = si->stats.max_layers;
    info->surface_mean_layers = si->stats.mean_layers;
    info->surface_trace_ms = si->trace_ms;
    info->fragments = si->stats.fragments;
    info->dropped_fragments = si->stats.pool_dropped;
    info->surface_drawn_curves = si->drawn_curves;
    info->surface_drawn_fragments = si->drawn_fragments;
    info->surface_kept = si->kept;
}

static void reset_info(lc_frame_info *info, const lc_render_params *p)
{
    memset(info, 0, sizeof *info);
    for (int i = 0; i < LC_PASS_COUNT; i++)
        info->pass_ms[i] = -1;
    info->width = p->width, info->height = p->height;
}

/* The refusal of a surface whose curves do not fit the memory budget. */
static int memory_refusal(lc_error *err, uint32_t particles, uint32_t have, uint64_t need, uint64_t each,
                          uint64_t free_bytes, const lc_surface_budget *mem)
{
    uint64_t fit = free_bytes / (each ? each : 1);
    return lc_err_field(err, LC_ERR_LIMIT, "surface.particles",
                        "%u curves need %.1f MB (%.1f kB each); %.1f MB of --max-memory %.1f MB is free: at most %llu "
                        "particles fit now",
                        particles, need / 1e6, each / 1e3, free_bytes / 1e6, mem->limit / 1e6,
                        (unsigned long long)(have + fit));
}

int lc_surface_job_render(const lc_field *field, const lc_surface_request *s, const lc_render_params *p,
                          const lc_surface_budget *mem, lc_work_budget *work, uint8_t *rgba, lc_frame_info *info,
                          lc_error *err)
{
    reset_info(info, p);
    lc_surface_params sp;
    lc_seed seed;
    int rc = to_params(s, &sp, &seed, err);
    if (rc)
        return rc;
    sp.work = work, sp.step_units = lc_cost_surface_step_units(p);
    /* The curves live while the frame renders: reserved before they are traced. */
    uint64_t each = lc_surface_curve_estimate(field, s), need = each * (uint64_t)s->particles, reserved = 0, left = 0;
    if (lc_surface_memory_reserve(&reserved, need, mem, &left) != 0)
        return memory_refusal(err, (uint32_t)s->particles, 0, need, each, left, mem);
    lc_surface_info si;
    double t0 = lc_now();
    rc = lc_surface_render(field, &seed, &sp, p, trace_threads(), rgba, &si, &info->camera, err);
    info->wall_ms = (lc_now() - t0) * 1000.0;
    lc_surface_memory_reserve(&reserved, 0, NULL, NULL);
    if (rc)
        return rc;
    fill_info(info, &si);
    info->converged = 1; /* every curve is in: the one-shot image is the converged surface */
    return 0;
}

struct lc_surface_stream {
    const lc_field *field;
    lc_surface_request traced_for; /* seed, step and length of the curves below */
    uint64_t curves_id;            /* names the curves below for kept layers (lc_surface_keep); unique */
    lc_trace_curve *curves;
    uint32_t count, cap;
    uint64_t bytes;    /* what the curves hold (lc_surface_curve_bytes: their arrays and slots) */
    uint64_t reserved; /* of the memory budget (surface_memory.h): the whole surface's before it is traced */
};

void lc_surface_stream_free(lc_surface_stream *st)
{
    if (!st)
        return;
    lc_surface_memory_reserve(&st->reserved, 0, NULL, NULL);
    lc_trace_curves_free(st->curves, st->count);
    free(st->curves);
    free(st);
}

uint64_t lc_surface_stream_id(const lc_surface_stream *st) { return st ? st->curves_id : 0; }

/* Whether the curves traced so far belong to s's surface. */
static int same_surface(const lc_surface_stream *st, const lc_field *field, const lc_surface_request *s)
{
    const lc_surface_request *t = &st->traced_for;
    return st->field == field && t->seed_count == s->seed_count &&
           memcmp(t->seed, s->seed, (size_t)s->seed_count * sizeof s->seed[0]) == 0 && t->step == s->step &&
           t->length == s->length && t->direction == s->direction;
}

#define MEAN_CURVES 32 /* curves traced before their mean size replaces the model's */

/* Reserves what st's surface will hold once all `want` curves are in, before
 * the next batch is traced: the curves so far as they are, the rest at the
 * model's size per curve until MEAN_CURVES are in (the larger of the two
 * before), then at their mean size: the particles' order samples the seed
 * evenly (lc_seed_param), and curves leave the domain early or crawl through
 * slow regions where the model assumes the top speed. */
static int reserve_rest(lc_surface_stream *st, const lc_field *field, const lc_surface_request *s, uint32_t want,
                        const lc_surface_budget *mem, lc_error *err)
{
    uint64_t each = lc_surface_curve_estimate(field, s), mean = st->count ? st->bytes / st->count : 0;
    if (st->count >= MEAN_CURVES || mean > each)
        each = mean;
    uint64_t need = st->bytes + (uint64_t)(want - st->count) * each, left = 0;
    if (lc_surface_memory_reserve(&st->reserved, need, mem, &left) == 0) /* shrinking never fails */
        return 0;
    return memory_refusal(err, want, st->count, need, each, left > st->bytes ? left - st->bytes : 0, mem);
}

int lc_surface_stream_frame(lc_surface_stream **stp, lc_surface_keep *keep, const lc_field *field,
                            const lc_surface_request *s, const lc_render_params *p, const lc_surface_budget *mem,
                            lc_work_budget *work, uint8_t *rgba, lc_frame_info *info, lc_error *err)
{
    reset_info(info, p);
    lc_surface_params sp;
    lc_seed seed;
    int rc = to_params(s, &sp, &seed, err);
    if (!rc && (rc = lc_seed_check(&seed, field, err)) != 0 && err)
        snprintf(err->field, sizeof err->field, "surface.seed");
    if (rc)
        return rc;
    if (!*stp && !(*stp = calloc(1, sizeof **stp)))
        return lc_err(err, LC_ERR_NOMEM, "out of memory");
    lc_surface_stream *st = *stp;
    if (!same_surface(st, field, s) || st->count > (uint32_t)s->particles) { /* a new surface: start again */
        lc_trace_curves_free(st->curves, st->count);
        st->count = 0, st->bytes = 0;
        lc_surface_memory_reserve(&st->reserved, 0, NULL, NULL);
        st->field = field;
        st->traced_for = *s;
        static atomic_ullong next_id;
        st->curves_id = (uint64_t)atomic_fetch_add(&next_id, 1) + 1;
    }
    double t0 = lc_now();
    uint32_t want = (uint32_t)s->particles, add = want - st->count;
    if (add > (uint32_t)s->curves_per_frame)
        add = (uint32_t)s->curves_per_frame;
    if (add && (rc = reserve_rest(st, field, s, want, mem, err)) != 0)
        return rc;
    if (st->count + add > st->cap) {
        uint32_t cap = st->cap ? st->cap : 256;
        while (cap < st->count + add)
            cap *= 2;
        lc_trace_curve *c = realloc(st->curves, cap * sizeof *c);
        if (!c)
            return lc_err(err, LC_ERR_NOMEM, "out of memory for %u curves", cap);
        st->curves = c, st->cap = cap;
    }
    lc_surface_info si = {0};
    lc_trace_desc td = {.step = s->step,
                        .max_length = s->length,
                        .direction = (lc_trace_direction)s->direction,
                        .work = work,
                        .step_units = lc_cost_surface_step_units(p)};
    if (add &&
        (rc = lc_trace_curves(field, &seed, &td, st->count, add, trace_threads(), st->curves + st->count, err))) {
        lc_surface_memory_reserve(&st->reserved, st->bytes, NULL, NULL); /* the batch is gone: hold what is kept */
        return rc;
    }
    for (uint32_t i = st->count; i < st->count + add; i++)
        st->bytes += lc_surface_curve_bytes(st->curves[i].n);
    st->count += add;
    /* Counted as traced: past the reservation (a batch longer than reserved) it grows unchecked, since the
     * curves exist; once converged the reservation is what they hold. */
    if (st->bytes > st->reserved || st->count >= want)
        lc_surface_memory_reserve(&st->reserved, st->bytes, NULL, NULL);
    si.trace_ms = (lc_now() - t0) * 1000.0;
    rc = lc_surface_draw(field, st->curves, st->count, st->curves_id, keep, &sp, p, field->bounds, rgba, &si,
                         &info->camera, err);
    info->wall_ms = (lc_now() - t0) * 1000.0;
    if (rc)
        return rc;
    fill_info(info, &si);
    info->converged = st->count >= want;
    return 0;
}

int lc_surface_job_session_frame(lc_server *srv, lc_session *s, const lc_request *req, lc_surface_keep *keep,
                                 uint8_t *rgba, lc_frame_info *info, lc_error *err)
{
    const lc_field *field = NULL; /* looked up again: the session's request may have changed since it was checked */
    lc_proto_error pe;
    double cost = 0;
    if (lc_admit_surface(srv, req, &cost, &field, &pe) != 0)
        return lc_err_field(err, LC_ERR_INVALID, pe.field, "%s", pe.message);
    s->surface_free = lc_surface_stream_free;
    lc_work_budget work; /* this frame's tracing, against what its estimate was granted */
    lc_cost_surface_budget(&work, cost, srv->cfg.max_cost);
    lc_surface_budget mem;
    lc_surface_budget_of(srv, &mem);
    return lc_surface_stream_frame(&s->surface, keep, field, &req->surface, &req->render, &mem, &work, rgba, info, err);
}

uint64_t lc_surface_job_session_id(const lc_session *s) { return lc_surface_stream_id(s->surface); }
