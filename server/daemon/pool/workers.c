/* Render worker pool: one GL context per thread calling the renderer, the
 * queue (fair_queue.c) and the still-frame timers. */
#include "workers.h"
#include "workers_internal.h"

#include <errno.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "cost.h"
#include "encoders.h"
#include "fair_queue.h"
#include "memory.h"
#include "messages.h"
#include "metrics.h"
#include "queue_deadline.h"
#include "stream_session.h"
#include "surface_job.h"
#include "surface_memory.h"
#include "traced.h"
#include "yield.h"

#define MOD "workers"

/* ---------------------------------------------------------------- queues */

/* One flow per client address: its sessions and one-shot renders share it, so
 * many sessions of one client get one share (keys | 1: never a pointer). */
static uint64_t task_key(const lc_task *t)
{
    const lc_session *s = t->session ? t->session : t->job->session;
    if (s)
        return s->client ? s->client | 1 : (uint64_t)(uintptr_t)s;
    return t->job->client;
}

/* Queues t for its client and wakes a worker; pool lock held. -1 when out of memory. */
static int push_task(lc_workers *w, lc_task *t)
{
    t->key = task_key(t);
    if (lc_fair_push(&w->queue, t) != 0)
        return -1;
    pthread_cond_signal(&w->work);
    return 0;
}

int lc_workers_submit(lc_workers *w, lc_render_job *job, lc_error *err)
{
    lc_task *t = calloc(1, sizeof *t);
    if (!t)
        return lc_err(err, LC_ERR_NOMEM, "out of memory");
    t->job = job;
    job->submitted = lc_now();
    job->rc = 0;
    pthread_mutex_lock(&w->lock);
    if (w->stopping) {
        pthread_mutex_unlock(&w->lock);
        free(t);
        return lc_err(err, LC_ERR_UNSUPPORTED, "the server is shutting down");
    }
    if (w->queue.jobs >= w->max_queue) {
        int q = w->queue.jobs;
        pthread_mutex_unlock(&w->lock);
        free(t);
        job->refused = "queue";
        return lc_err(err, LC_ERR_LIMIT, "render queue full (%d requests waiting)", q);
    }
    int per_client = w->srv->cfg.max_queue_per_client, q = lc_fair_jobs_of(&w->queue, task_key(t));
    if (per_client > 0 && q >= per_client) {
        pthread_mutex_unlock(&w->lock);
        free(t);
        job->refused = "client_queue";
        return lc_err(err, LC_ERR_LIMIT, "this client has %d renders waiting already (the limit is %d)", q, per_client);
    }
    double deadline = w->srv->cfg.render_deadline;
    if (deadline > 0 && w->cost_rate > 0 && job->cost / w->cost_rate > deadline) {
        double est = job->cost / w->cost_rate;
        pthread_mutex_unlock(&w->lock);
        free(t);
        job->refused = "deadline";
        return lc_err(err, LC_ERR_LIMIT, "the render would take about %.0f s here, beyond the %.0f s render deadline",
                      est, deadline);
    }
    if (push_task(w, t) != 0) {
        pthread_mutex_unlock(&w->lock);
        free(t);
        return lc_err(err, LC_ERR_NOMEM, "out of memory");
    }
    pthread_mutex_unlock(&w->lock);
    return 0;
}

/* Queues s unless it is queued already; pool lock held. */
static void enqueue_session(lc_workers *w, lc_session *s)
{
    if (s->sched_queued || w->stopping)
        return;
    lc_task *t = calloc(1, sizeof *t);
    if (!t)
        return; /* the next input or ack retries */
    t->session = s;
    if (push_task(w, t) != 0) {
        free(t);
        return;
    }
    lc_session_ref(s);
    s->sched_queued = true;
}

void lc_workers_wake(lc_workers *w, lc_session *s)
{
    pthread_mutex_lock(&w->lock);
    lc_workers_untime(w, s);
    enqueue_session(w, s);
    pthread_mutex_unlock(&w->lock);
}

/* Parks s until `when` (its still frame); pool lock held. */
static void park_session(lc_workers *w, lc_session *s, double when)
{
    if (s->sched_queued || w->stopping)
        return;
    if (s->sched_timed) {
        if (when < s->sched_due)
            s->sched_due = when;
        return;
    }
    lc_session_ref(s);
    s->sched_timed = true;
    s->sched_due = when;
    s->sched_next = w->timed;
    w->timed = s;
    pthread_cond_signal(&w->work);
}

/* Moves due timers to the FIFO; returns the earliest remaining due time or 0. */
static double run_timers(lc_workers *w, double now)
{
    double next = 0;
    lc_session **p = &w->timed;
    while (*p) {
        lc_session *s = *p;
        if (s->sched_due <= now) {
            *p = s->sched_next;
            s->sched_timed = false;
            s->sched_next = NULL;
            enqueue_session(w, s);
            lc_session_unref(s);
        } else {
            if (next == 0 || s->sched_due < next)
                next = s->sched_due;
            p = &s->sched_next;
        }
    }
    return next;
}

/* ---------------------------------------------------------------- rendering */

/* Cost units per second of render time, a moving average over renders that
 * took long enough to time well; the submit-time deadline check uses it. */
static void learn_rate(lc_workers *w, double cost, double wall_ms)
{
    if (!(cost > 0) || wall_ms < 20.0)
        return;
    double rate = cost / (wall_ms / 1000.0);
    pthread_mutex_lock(&w->lock);
    w->cost_rate = w->cost_rate > 0 ? 0.8 * w->cost_rate + 0.2 * rate : rate;
    pthread_mutex_unlock(&w->lock);
    lc_metrics_cost(w->srv->metrics, cost, w->cost_rate);
}

/* Every frame of a render worker: the frame hook (serve --mpi announces the
 * frame to the other ranks), then the renderer. */
static int render_frame(lc_workers *w, lc_renderer *r, const lc_dataset *ds, const lc_render_params *p,
                        lc_frame_state *state, double dt, uint8_t *rgba, lc_frame_info *info, lc_error *err)
{
    const lc_frame_hook *h = &w->srv->frame_hook;
    int rc = h->before ? h->before(h->ctx, ds, p, state, dt, err) : 0;
    return rc ? rc : lc_render_frame(r, ds->gpu, p, state, dt, rgba, info, err);
}

/* A frame of layers, likewise: the hook (serve --mpi announces the layers), then the renderer. */
static int render_layers(lc_workers *w, lc_renderer *r, const lc_dataset *const *ds, const lc_gpu_scene *const *scenes,
                         const lc_layer_params *layers, int n, const lc_render_params *p, lc_frame_state *state,
                         double dt, uint8_t *rgba, lc_frame_info *info, lc_error *err)
{
    const lc_frame_hook *h = &w->srv->frame_hook;
    int rc = h->before_layers ? h->before_layers(h->ctx, ds, layers, n, p, state, dt, err) : 0;
    return rc ? rc : lc_render_layers(r, scenes, layers, n, p, state, dt, rgba, info, err);
}

/* layers[] (docs/ALGORITHM.md "Layers"): the scenes of their datasets ds. */
static void layer_scenes(int n, const lc_dataset *const *ds, const lc_gpu_scene **scenes)
{
    for (int i = 0; i < n; i++)
        scenes[i] = ds[i]->gpu;
}

/* How many layers the job carries: its request's count only when the
 * submitter resolved every layer's dataset (a surface frame carries none).
 * -1 when the request names layers the job does not hold. */
static int job_layer_count(const lc_render_job *job)
{
    if (job->field)
        return lc_request_layer_count(&job->req) ? -1 : 0;
    for (int i = 0; i < lc_request_layer_count(&job->req); i++)
        if (!job->layers[i] || !job->layers[i]->gpu)
            return -1;
    return lc_request_layer_count(&job->req);
}

/* The field a frame over its measured budget names: the one whose lowering
 * helps its estimate most (cost.h lc_cost_field), "layers" for layers[]. */
static const char *budget_field(const lc_dataset *ds, const lc_render_params *p, double cost)
{
    return ds ? lc_cost_field(&ds->cost, p, 0.5 * cost) : "layers";
}

/* A long job: LC_LONG_JOB_SECONDS or more by the learned rate (without one,
 * LC_LONG_JOB_COST units or more). Long jobs may hold every worker but one,
 * so that a drag's frames and other short work always find a worker and wait
 * at most for one short job. */
static bool long_job(lc_workers *w, const lc_render_job *job)
{
    if (!job)
        return false;
    double rate = atomic_load(&w->cost_rate);
    return rate > 0 ? job->cost / rate >= LC_LONG_JOB_SECONDS : job->cost >= LC_LONG_JOB_COST;
}

static bool short_task(const lc_task *t, void *ctx) { return !long_job(ctx, t->job); }
static bool stream_task(const lc_task *t, void *ctx)
{
    (void)ctx;
    return t->session && !t->job;
}

/* The next task for a free worker (pool lock held): any, unless every other
 * worker holds a long job; then this is the worker kept for short work, and
 * it serves WebSocket frames first (a drag's next frame waits for no HTTP
 * job), then other short tasks (NULL: none queued). */
static lc_task *next_task(lc_workers *w)
{
    if (w->nworkers > 1 && w->long_running >= w->nworkers - 1) {
        lc_task *t = lc_fair_pop_where(&w->queue, stream_task, w);
        return t ? t : lc_fair_pop_where(&w->queue, short_task, w);
    }
    return lc_fair_pop(&w->queue);
}

/* The frame a worker renders is "in hand" while the renderer runs: under MPI
 * that is where a dead rank leaves it waiting, and lc_workers_abandon answers
 * it from another thread. */
static void in_hand(worker *wk, lc_render_job *job, lc_session *s)
{
    pthread_mutex_lock(&wk->pool->lock);
    wk->job = job, wk->session = s;
    pthread_mutex_unlock(&wk->pool->lock);
}

/* false when the job was abandoned meanwhile: it is answered (and perhaps
 * freed by its submitter), hands off. */
static bool out_of_hand(worker *wk)
{
    pthread_mutex_lock(&wk->pool->lock);
    bool mine = !wk->lost;
    wk->job = NULL, wk->session = NULL, wk->lost = false;
    pthread_mutex_unlock(&wk->pool->lock);
    return mine;
}

static void render_job(worker *wk, lc_render_job *job)
{
    lc_workers *w = wk->pool;
    lc_error err = {0};
    job->queue_ms = (lc_now() - job->submitted) * 1000.0;
    double deadline = w->srv->cfg.render_deadline;
    if (deadline > 0 && job->queue_ms > deadline * 1000.0) {
        job->refused = "deadline";
        job->rc = lc_err(&job->err, LC_ERR_LIMIT, "waited %.1f s for a worker, beyond the %.0f s render deadline",
                         job->queue_ms / 1000.0, deadline);
        lc_workers_finish_job(job);
        return;
    }
    /* While in hand the frame reads and writes only its own copies (and holds
     * the session): lc_workers_abandon may hand the job back meanwhile. */
    const lc_render_params params = job->req.render, *p = &params;
    const lc_dataset *dataset = job->dataset;
    const lc_field *field = job->field;
    const lc_surface_request surface = job->req.surface;
    double dt = job->dt;
    lc_session *session = job->session;
    /* layers[]: the request's snapshot by reference (immutable; the job may be handed back meanwhile) */
    int layer_count = job_layer_count(job);
    if (layer_count < 0 || (!field && !layer_count && !dataset)) {
        job->rc = lc_err(&job->err, LC_ERR_INVALID, "the render names data it does not carry");
        lc_workers_finish_job(job);
        return;
    }
    const lc_dataset *layer_ds[LC_MAX_LAYERS];
    const lc_gpu_scene *scenes[LC_MAX_LAYERS];
    memcpy(layer_ds, job->layers, (size_t)layer_count * sizeof *layer_ds);
    layer_scenes(layer_count, layer_ds, scenes);
    const lc_request_layers *layers = layer_count ? lc_request_layers_retain(job->req.layers) : NULL;
    uint8_t *rgba = malloc((size_t)p->width * (size_t)p->height * 4);
    if (!rgba) {
        lc_request_layers_release(layers);
        job->rc = lc_err(&job->err, LC_ERR_NOMEM, "out of memory for a %dx%d image", p->width, p->height);
        lc_workers_finish_job(job);
        return;
    }
    if (session)
        lc_session_ref(session);
    lc_frame_info info;
    /* A long job gives the cores to other sessions' moving frames at its yield points (yield.h). */
    wk->large = w->nworkers > 1 && long_job(w, job);
    bool tiled = w->nworkers > 1 && !w->srv->mpi && !layer_count && /* not collective: every rank must tile alike */
                 !(p->time.markers && p->time.has_window) &&        /* drawn once over the whole image */
                 (long long)p->width * p->height > LC_LARGE_FRAME_PIXELS;
    lc_renderer_set_tile_size(wk->renderer, tiled ? LC_YIELD_TILE : 0);
    wk->owner = session ? (const void *)session : (const void *)job;
    /* What the job may spend as it runs (cost.h): tracing's counted steps, or the frame's measured time. */
    lc_work_budget work;
    if (field)
        lc_cost_surface_budget(&work, job->cost, w->srv->cfg.max_cost);
    else
        lc_cost_frame_budget(&work, job->cost, atomic_load(&w->cost_rate), w->srv->cfg.max_cost,
                             budget_field(dataset, p, job->cost));
    lc_renderer_set_work(wk->renderer, field ? NULL : &work);
    wk->work = field ? NULL : &work;
    in_hand(wk, job, NULL);
    if (wk->large) { /* its start is a yield point too: a drag's frame under way keeps the cores */
        double waited = lc_yield_wait(&w->gate, wk->owner);
        if (waited > 0)
            lc_metrics_yield_wait(w->srv->metrics, waited);
    }
    /* A field's streamline set: uploaded here, a session's re-trace swapped in (its opacities start again). */
    bool retraced = false;
    int rc = field ? 0 : lc_traced_ready(dataset, session ? &session->lock : NULL, &retraced, &err);
    if (retraced && session)
        session->state_layers = -1;
    /* A session's opacities span its layers (lc_session_prepare_state). */
    lc_frame_state *state = NULL;
    if (rc == 0)
        rc = session ? lc_session_prepare_state(session, layer_ds, layer_count, &err) : 0;
    if (session && rc == 0)
        state = session->frame_state;
    lc_surface_budget mem; /* a surface's curves, reserved in the memory budget while it renders */
    lc_surface_budget_of(w->srv, &mem);
    if (rc == 0)
        rc = field         ? lc_surface_job_render(field, &surface, p, &mem, &work, rgba, &info, &err)
             : layer_count ? render_layers(w, wk->renderer, layer_ds, scenes, layers->p, layer_count, p, state, dt,
                                           rgba, &info, &err)
                           : render_frame(w, wk->renderer, dataset, p, state, dt, rgba, &info, &err);
    lc_request_layers_release(layers);
    lc_renderer_set_work(wk->renderer, NULL);
    wk->work = NULL;
    wk->large = false, wk->owner = NULL, lc_renderer_set_tile_size(wk->renderer, 0);
    if (!w->srv->mpi && dataset) /* a large frame keeps no targets (collective frames under MPI keep them) */
        lc_renderer_release_after(wk->renderer, dataset->gpu, p);
    int mine = out_of_hand(wk);
    if (session)
        lc_session_unref(session);
    if (!mine) { /* lc_workers_abandon answered it; the job is not ours to touch */
        free(rgba);
        return;
    }
    job->rgba = rgba;
    job->info = info;
    job->rc = rc;
    job->err = err;
    if (job->rc != 0) {
        free(job->rgba);
        job->rgba = NULL;
        lc_workers_finish_job(job);
        return;
    }
    lc_metrics_frame(w->srv->metrics, job->session ? "session" : "http", &job->info);
    learn_rate(w, job->cost, job->info.wall_ms);
    job->rgba = NULL;
    lc_encoders_job(w->encoders, rgba, job);
}

/* desc.progress of every worker's renderer: publishes the pass to the
 * stream session being rendered (the I/O thread sends it, ws.c). */
static void on_progress(void *ctx, int next_pass, int done, int planned)
{
    worker *wk = ctx;
    double delay = wk->pool->srv->cfg.pass_delay;
    if (delay > 0 && next_pass >= 0) /* --pass-delay: a slow frame on demand, for tests */
        nanosleep(&(struct timespec){(time_t)delay, (long)((delay - (time_t)delay) * 1e9)}, NULL);
    lc_session *s = wk->progress;
    if (!s)
        return; /* an HTTP render */
    atomic_store(&s->progress.planned, planned);
    atomic_store(&s->progress.done, done);
    atomic_store(&s->progress.stage, next_pass < 0 ? LC_PROGRESS_ENCODE : next_pass);
}

/* desc.preempted: a session's still gives way to its newer input; an
 * abandoned frame stops. Never blocks (called between a pass's batches). */
static int on_preempted(void *ctx)
{
    worker *wk = ctx;
    lc_workers *w = wk->pool;
    if (wk->preempt && lc_session_stream_preempted(wk->preempt))
        return 1;
    pthread_mutex_lock(&w->lock);
    bool lost = wk->lost;
    pthread_mutex_unlock(&w->lock);
    return lost;
}

/* desc.yield: as on_preempted, and first a large frame waits while other
 * sessions' moving frames render (yield.h). */
static int on_yield(void *ctx)
{
    worker *wk = ctx;
    lc_workers *w = wk->pool;
    double waited = wk->large ? lc_yield_wait(&w->gate, wk->owner) : 0;
    if (waited > 0) {
        lc_metrics_yield_wait(w->srv->metrics, waited);
        lc_work_exclude(wk->work, waited); /* waiting is no work of the frame's */
    }
    return on_preempted(wk); /* input may have come while it waited */
}

/* A surface-layers frame of s, continuing the layers of its frame before
 * when a slot of the pool's kept layers still holds them. */
static int surface_frame(lc_workers *w, lc_session *s, const lc_request *req, uint8_t *rgba, lc_frame_info *info,
                         lc_error *err)
{
    lc_surface_keep *keep = lc_surface_keeps_take(w->surface_keeps, lc_surface_job_session_id(s));
    int rc = lc_surface_job_session_frame(w->srv, s, req, keep, rgba, info, err);
    lc_surface_keeps_give(w->surface_keeps, keep, lc_now());
    return rc;
}

/* One frame of a WebSocket session, if it needs one. */
static void render_session(worker *wk, lc_session *s)
{
    lc_workers *w = wk->pool;
    lc_stream_frame f;
    double wake_at = 0;
    if (!lc_session_stream_next(s, lc_now(), &f, &wake_at)) {
        if (wake_at > 0) {
            pthread_mutex_lock(&w->lock);
            park_session(w, s, wake_at);
            pthread_mutex_unlock(&w->lock);
        }
        return;
    }
    const lc_render_params *p = &f.req.render;
    uint8_t *rgba = malloc((size_t)p->width * (size_t)p->height * 4);
    lc_frame_info info;
    lc_error err = {0};
    lc_session_progress_begin(s, f.frame);
    wk->progress = s;
    /* Stills and refinements give way to newer input; moving frames are short
     * and tell the yield gate that a drag is under way. */
    wk->preempt = f.interactive ? NULL : s;
    double cost = lc_cost_estimate(&s->dataset->cost, p);
    wk->large = !f.interactive && w->nworkers > 1 && lc_yield_large(cost, atomic_load(&w->cost_rate)), wk->owner = s;
    /* A still's measured budget (cost.h); moving frames are short and surfaces count their own. */
    lc_work_budget work;
    bool budgeted = !f.interactive && p->method != LC_METHOD_SURFACE_LAYERS;
    if (budgeted)
        lc_cost_frame_budget(&work, cost, atomic_load(&w->cost_rate), w->srv->cfg.max_cost,
                             budget_field(lc_request_layer_count(&f.req) ? NULL : s->dataset, p, cost));
    lc_renderer_set_work(wk->renderer, budgeted ? &work : NULL);
    wk->work = budgeted ? &work : NULL;
    if (f.interactive)
        lc_yield_interactive_begin(&w->gate, s);
    in_hand(wk, NULL, s);
    /* layers[]: the frame's snapshot by reference, the opacities spanning them (lc_session_prepare_state) */
    int n = p->method == LC_METHOD_SURFACE_LAYERS ? 0 : lc_request_layer_count(&f.req); /* validation refuses both */
    const lc_gpu_scene *scenes[LC_MAX_LAYERS];
    layer_scenes(n, f.layers, scenes);
    /* A field's streamline set: uploaded here, an update's re-trace swapped in (its opacities start again). */
    bool retraced = false;
    int rc = p->method == LC_METHOD_SURFACE_LAYERS ? 0 : lc_traced_ready(s->dataset, &s->lock, &retraced, &err);
    if (retraced)
        s->state_layers = -1;
    if (rc == 0)
        rc = rgba ? lc_session_prepare_state(s, f.layers, n, &err)
                  : lc_err(&err, LC_ERR_NOMEM, "out of memory for a %dx%d frame", p->width, p->height);
    if (rc == 0)
        rc = p->method == LC_METHOD_SURFACE_LAYERS ? surface_frame(w, s, &f.req, rgba, &info, &err)
             : n ? render_layers(w, wk->renderer, f.layers, scenes, f.req.layers->p, n, p, s->frame_state, f.dt, rgba,
                                 &info, &err)
                 : render_frame(w, wk->renderer, s->dataset, p, s->frame_state, f.dt, rgba, &info, &err);
    lc_request_release(&f.req); /* what follows reads the frame's numbers, not its layers */
    lc_renderer_set_work(wk->renderer, NULL);
    wk->work = NULL;
    out_of_hand(wk);
    if (f.interactive)
        lc_yield_interactive_end(&w->gate, s);
    wk->progress = NULL, wk->preempt = NULL, wk->large = false, wk->owner = NULL;
    if (rc == LC_ERR_CANCELLED && !f.interactive) { /* pre-empted: the moving frame for the new input follows */
        free(rgba);
        lc_session_stream_yielded(s, &f);
        lc_metrics_yielded(w->srv->metrics);
        lc_workers_wake(w, s);
        return;
    }
    atomic_store(&s->progress.stage, rc == 0 ? LC_PROGRESS_ENCODE : LC_PROGRESS_NONE);
    lc_session_stream_done(s, &f, rc == 0, rc == 0 ? &info : NULL);
    if (rc != 0) {
        free(rgba);
        LC_WARN(MOD, "session %s: frame %llu failed: %s", s->id, (unsigned long long)f.frame, err.msg);
        if (rc == LC_ERR_INVALID)
            lc_stream_error(w->srv, s, LC_PROTO_BAD_FIELD, err.msg, err.field[0] ? err.field : NULL);
        else if (rc == LC_ERR_BUDGET || (rc == LC_ERR_LIMIT && err.field[0])) /* past its grant (cost.h), or
                                                                               * short of memory (surface_memory.h) */
            lc_stream_error(w->srv, s, "too_expensive", err.msg, err.field[0] ? err.field : NULL);
        else
            lc_stream_error(w->srv, s, "render_failed", err.msg, NULL);
        return;
    }
    lc_metrics_frame(w->srv->metrics, "ws", &info);
    lc_encoders_frame(w->encoders, rgba, s, &f, &info);
    /* Back to the tail of the FIFO: fading or newer input continues after the
     * other sessions had their turn. */
    lc_workers_wake(w, s);
}

static void *worker_main(void *arg)
{
    worker *wk = arg;
    lc_workers *w = wk->pool;
    lc_error err = {0};
    int rc = 0;
    if (!wk->gl) {
        lc_gl_desc desc = {.device = w->srv->cfg.device, .share = w->workers[0].gl};
        rc = lc_gl_create(&desc, &wk->gl, &err);
    }
    if (rc == 0)
        rc = lc_gl_make_current(wk->gl, &err);
    if (rc == 0)
        rc = lc_renderer_create(&(lc_renderer_desc){.reducer = w->srv->frame_hook.reducer,
                                                    .progress = on_progress,
                                                    .progress_ctx = wk,
                                                    .yield = on_yield,
                                                    .preempted = on_preempted,
                                                    .yield_ctx = wk},
                                &wk->renderer, &err);
    pthread_mutex_lock(&w->lock);
    if (rc != 0 && !w->failed) {
        w->failed = 1;
        w->start_err = err;
        lc_err_prefix(&w->start_err, "render worker %d", wk->index);
    }
    w->ready_count++;
    pthread_cond_broadcast(&w->ready);
    while (rc == 0 && !w->failed && w->ready_count < w->nworkers)
        pthread_cond_wait(&w->ready, &w->lock);
    if (rc != 0 || w->failed) {
        pthread_mutex_unlock(&w->lock);
        goto out;
    }
    for (;;) {
        lc_task *t = NULL;
        while (!w->stopping) {
            double now = lc_now(), next = run_timers(w, now);
            t = next_task(w);
            if (t)
                break;
            if (wk->trim_at > 0 && now >= wk->trim_at) { /* idle after a large frame */
                wk->trim_at = 0;
                pthread_mutex_unlock(&w->lock);
                lc_memory_trim();
                pthread_mutex_lock(&w->lock);
                continue;
            }
            double keep_due = lc_surface_keeps_due(w->surface_keeps);
            if (keep_due > 0 && now >= keep_due) { /* a surface session's layers no frame continued */
                pthread_mutex_unlock(&w->lock);
                lc_surface_keeps_trim(w->surface_keeps, now);
                pthread_mutex_lock(&w->lock);
                continue;
            }
            if (wk->trim_at > 0 && (next <= 0 || wk->trim_at < next))
                next = wk->trim_at;
            if (keep_due > 0 && (next <= 0 || keep_due < next))
                next = keep_due;
            if (next > 0)
                lc_cond_wait_until(&w->work, &w->lock, next);
            else
                pthread_cond_wait(&w->work, &w->lock);
        }
        if (!t)
            break; /* stopping: queued leftovers are failed by lc_workers_stop */
        if (t->session)
            t->session->sched_queued = false;
        bool is_long = long_job(w, t->job);
        w->long_running += is_long;
        pthread_mutex_unlock(&w->lock);
        if (t->job) {
            const lc_render_params *p = &t->job->req.render;
            bool large = (long long)p->width * p->height > LC_LARGE_FRAME_PIXELS;
            render_job(wk, t->job); /* the job may be its submitter's again from here */
            if (large)
                wk->trim_at = lc_now() + LC_IDLE_TRIM_DELAY;
        } else {
            render_session(wk, t->session);
            lc_session_unref(t->session);
        }
        free(t);
        pthread_mutex_lock(&w->lock);
        if (is_long) { /* a worker held back for short tasks may take a long one now */
            w->long_running--;
            pthread_cond_broadcast(&w->work);
        }
    }
    pthread_mutex_unlock(&w->lock);
out:
    if (wk->renderer)
        lc_renderer_destroy(wk->renderer);
    wk->renderer = NULL;
    if (wk->gl)
        lc_gl_release_current(wk->gl);
    return NULL;
}

/* ---------------------------------------------------------------- life cycle */

static void wake_cb(void *ctx, lc_session *s) { lc_workers_wake(ctx, s); }

int lc_workers_create(lc_server *srv, lc_gl *primary, int nworkers, int nencoders, int max_queue, lc_workers **out,
                      lc_error *err)
{
    *out = NULL;
    lc_workers *w = calloc(1, sizeof *w);
    if (!w)
        return lc_err(err, LC_ERR_NOMEM, "out of memory");
    w->srv = srv;
    w->nworkers = nworkers > 0 ? nworkers : 1;
    w->max_queue = max_queue > 0 ? max_queue : 1;
    w->workers = calloc((size_t)w->nworkers, sizeof *w->workers);
    if (!w->workers) {
        free(w);
        return lc_err(err, LC_ERR_NOMEM, "out of memory");
    }
    pthread_mutex_init(&w->lock, NULL);
    pthread_condattr_t ca;
    pthread_condattr_init(&ca);
    pthread_condattr_setclock(&ca, CLOCK_MONOTONIC);
    pthread_cond_init(&w->work, &ca);
    pthread_cond_init(&w->deadline_wake, &ca);
    pthread_condattr_destroy(&ca);
    pthread_cond_init(&w->ready, NULL);
    lc_yield_gate_init(&w->gate, srv->cfg.still_delay, LC_YIELD_MAX_WAIT);
    w->surface_keeps = lc_surface_keeps_create(w->nworkers); /* NULL: surface frames draw all their curves */
    w->workers[0].gl = primary;
    for (int i = 0; i < w->nworkers; i++) {
        worker *wk = &w->workers[i];
        wk->pool = w;
        wk->index = i;
        if (pthread_create(&wk->thread, NULL, worker_main, wk) != 0) {
            pthread_mutex_lock(&w->lock);
            w->failed = 1;
            lc_err(&w->start_err, LC_ERR_INTERNAL, "cannot start render worker %d", i);
            w->ready_count++;
            pthread_cond_broadcast(&w->ready);
            pthread_mutex_unlock(&w->lock);
            continue;
        }
        wk->started = true;
    }
    pthread_mutex_lock(&w->lock);
    while (w->ready_count < w->nworkers)
        pthread_cond_wait(&w->ready, &w->lock);
    int failed = w->failed;
    pthread_mutex_unlock(&w->lock);
    if (!failed && lc_encoders_create(w->srv, nencoders, wake_cb, w, &w->encoders, &w->start_err) != 0)
        failed = 1;
    if (!failed && lc_queue_deadline_start(w) != 0)
        failed = 1, lc_err(&w->start_err, LC_ERR_INTERNAL, "cannot start the render queue's deadline thread");
    if (failed) {
        if (err)
            *err = w->start_err;
        int code = w->start_err.code ? w->start_err.code : LC_ERR_INTERNAL;
        *out = w; /* the caller stops and destroys it (contexts need the same teardown) */
        lc_workers_stop(w);
        return code;
    }
    LC_INFO(MOD, "%d render worker(s), %d encoder thread(s)", w->nworkers, nencoders > 0 ? nencoders : 1);
    *out = w;
    return 0;
}
