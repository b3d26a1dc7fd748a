/* A worker's frame of method "surface-layers" (surface_job.h). */
#include "surface_job.h"

#include <string.h>
#include <unistd.h>

#include "surface_render.h"

#define TRACE_THREADS_MAX 8

int lc_surface_job_render(const lc_field *field, const lc_surface_request *s, const lc_render_params *p,
                          uint8_t *rgba, lc_frame_info *info, lc_error *err)
{
    memset(info, 0, sizeof *info);
    for (int i = 0; i < LC_PASS_COUNT; i++)
        info->pass_ms[i] = -1;
    lc_seed seed = {.count = s->seed_count};
    if (s->seed_count < 2 || s->seed_count > LC_SEED_MAX_POINTS)
        return lc_err_field(err, LC_ERR_INVALID, "surface.seed", "surface.seed: 2 to %d points", LC_SEED_MAX_POINTS);
    memcpy(seed.points, s->seed, (size_t)s->seed_count * sizeof s->seed[0]);
    lc_surface_params sp = {.particles = s->particles,
                            .step = s->step,
                            .length = s->length,
                            .epsilon = s->epsilon,
                            .opacity = s->opacity,
                            .max_layers = s->max_layers,
                            .composite = (int)s->composite};
    memcpy(sp.color, s->color, sizeof sp.color);
    /* Tracing is CPU work on the worker's thread and a few more: the frame waits for it anyway. */
    long cpus = sysconf(_SC_NPROCESSORS_ONLN);
    int threads = cpus < 1 ? 1 : cpus > TRACE_THREADS_MAX ? TRACE_THREADS_MAX : (int)cpus;
    lc_surface_info si;
    double t0 = lc_now();
    int rc = lc_surface_render(field, &seed, &sp, p, threads, rgba, &si, &info->camera, err);
    info->wall_ms = (lc_now() - t0) * 1000.0;
    info->width = p->width, info->height = p->height;
    if (rc)
        return rc;
    info->element_count = (uint32_t)si.stats.curves;
    info->has_surface = 1;
    info->surface_curves = si.stats.curves;
    info->surface_overflow = si.stats.overflow;
    info->surface_k = si.k;
    info->surface_max_layers = si.stats.max_layers;
    info->surface_mean_layers = si.stats.mean_layers;
    info->surface_trace_ms = si.trace_ms;
    info->fragments = si.stats.fragments;
    info->dropped_fragments = si.stats.pool_dropped;
    info->converged = 1; /* every curve is in: the one-shot image is the converged surface */
    return 0;
}
