/* Render worker pool (one GL context per thread) and encoder threads. */
#include "workers.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "image.h"
#include "lc_mpi.h"
#include "memory.h"
#include "messages.h"
#include "metrics.h"
#include "serve_mpi.h"

#define MOD "workers"

/* A task in the render queue: an HTTP job or a WebSocket session (which
 * holds a reference while queued). */
typedef struct task {
    struct task *next;
    lc_render_job *job;
    lc_session *session;
} task;

/* One client's queued tasks (FIFO). Clients with work form a ring that the
 * workers serve round robin: one task of each client in turn. */
typedef struct flow {
    struct flow *next; /* in the ring of clients with work */
    uint64_t key;
    task *head, *tail;
    int jobs; /* HTTP jobs among the tasks */
} flow;

/* An image to encode. */
typedef struct encode_item {
    struct encode_item *next;
    uint8_t *rgba;
    int width, height;
    lc_image_format format;
    int quality;
    lc_render_job *job;    /* HTTP: finish this job */
    lc_session *session;   /* stream: send a frame message (holds a reference) */
    lc_stream_frame frame; /* stream only */
    lc_frame_info info;    /* stream only */
} encode_item;

typedef struct worker {
    lc_workers *pool;
    int index;
    pthread_t thread;
    bool started;
    lc_gl *gl;
    lc_renderer *renderer;
    /* The frame being rendered (under the pool's lock), for lc_workers_abandon;
     * lost: that function answered the job meanwhile. */
    lc_render_job *job;
    lc_session *session;
    bool lost;
} worker;

struct lc_workers {
    lc_server *srv;
    int nworkers, nencoders, max_queue;
    worker *workers;
    pthread_t *encoders;
    int encoders_started;

    pthread_mutex_t lock; /* guards the render FIFO, the timer list and sessions' sched_* fields */
    pthread_cond_t work;  /* FIFO non-empty, timer list changed, stopping */
    pthread_cond_t ready; /* start-up progress */
    int ready_count, failed;
    lc_error start_err;
    bool stopping;
    bool abandoned; /* lc_workers_abandon ran (the watchdog and mpirun's signal may both call it) */
    flow *ring_head, *ring_tail; /* clients with queued tasks, next to serve first */
    int jobs_queued, tasks_queued, flows;
    double cost_rate; /* learned cost units per second of render time (0 = none measured yet) */
    lc_session *timed; /* sessions waiting for their still frame (linked by sched_next) */

    pthread_mutex_t enc_lock;
    pthread_cond_t enc_work;
    encode_item *enc_head, *enc_tail;
    int enc_depth;
    bool enc_stopping;
};

/* ---------------------------------------------------------------- queues */

static uint64_t task_key(const task *t)
{
    if (t->session)
        return (uint64_t)(uintptr_t)t->session;
    return t->job->session ? (uint64_t)(uintptr_t)t->job->session : t->job->client;
}

static flow *find_flow(lc_workers *w, uint64_t key)
{
    for (flow *f = w->ring_head; f; f = f->next)
        if (f->key == key)
            return f;
    return NULL;
}

static void ring_append(lc_workers *w, flow *f)
{
    f->next = NULL;
    if (w->ring_tail)
        w->ring_tail->next = f;
    else
        w->ring_head = f;
    w->ring_tail = f;
}

/* Queues t behind its client's earlier tasks; a client new to the ring goes
 * to its end. Returns -1 when out of memory (pool lock held). */
static int push_task(lc_workers *w, task *t)
{
    uint64_t key = task_key(t);
    flow *f = find_flow(w, key);
    if (!f) {
        f = calloc(1, sizeof *f);
        if (!f)
            return -1;
        f->key = key;
        ring_append(w, f);
        w->flows++;
    }
    t->next = NULL;
    if (f->tail)
        f->tail->next = t;
    else
        f->head = t;
    f->tail = t;
    if (t->job)
        f->jobs++;
    w->tasks_queued++;
    pthread_cond_signal(&w->work);
    return 0;
}

/* The next client's oldest task; that client moves to the end of the ring. */
static task *pop_task(lc_workers *w)
{
    flow *f = w->ring_head;
    if (!f)
        return NULL;
    task *t = f->head;
    f->head = t->next;
    if (!f->head)
        f->tail = NULL;
    if (t->job) {
        f->jobs--;
        w->jobs_queued--;
    }
    w->tasks_queued--;
    w->ring_head = f->next;
    if (!w->ring_head)
        w->ring_tail = NULL;
    if (f->head) {
        ring_append(w, f);
    } else {
        free(f);
        w->flows--;
    }
    return t;
}

int lc_workers_submit(lc_workers *w, lc_render_job *job, lc_error *err)
{
    task *t = calloc(1, sizeof *t);
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
    if (w->jobs_queued >= w->max_queue) {
        int q = w->jobs_queued;
        pthread_mutex_unlock(&w->lock);
        free(t);
        job->refused = "queue";
        return lc_err(err, LC_ERR_LIMIT, "render queue full (%d requests waiting)", q);
    }
    flow *f = find_flow(w, task_key(t));
    int per_client = w->srv->cfg.max_queue_per_client;
    if (f && per_client > 0 && f->jobs >= per_client) {
        int q = f->jobs;
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
    w->jobs_queued++;
    pthread_mutex_unlock(&w->lock);
    return 0;
}

/* Removes s from the timer list if present; pool lock held. */
static void untime(lc_workers *w, lc_session *s)
{
    if (!s->sched_timed)
        return;
    for (lc_session **p = &w->timed; *p; p = &(*p)->sched_next) {
        if (*p == s) {
            *p = s->sched_next;
            break;
        }
    }
    s->sched_timed = false;
    s->sched_next = NULL;
    lc_session_unref(s); /* the timer list's reference */
}

/* Queues s unless it is queued already; pool lock held. */
static void enqueue_session(lc_workers *w, lc_session *s)
{
    if (s->sched_queued || w->stopping)
        return;
    task *t = calloc(1, sizeof *t);
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
    untime(w, s);
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

static void wait_until(pthread_cond_t *c, pthread_mutex_t *m, double when_monotonic)
{
    /* The condition variable uses CLOCK_MONOTONIC (see create), as does lc_now(). */
    double secs = when_monotonic;
    struct timespec ts;
    ts.tv_sec = (time_t)secs;
    ts.tv_nsec = (long)((secs - (double)ts.tv_sec) * 1e9);
    if (ts.tv_nsec >= 1000000000L) {
        ts.tv_sec++;
        ts.tv_nsec -= 1000000000L;
    }
    pthread_cond_timedwait(c, m, &ts);
}

static void push_encode(lc_workers *w, encode_item *e)
{
    pthread_mutex_lock(&w->enc_lock);
    e->next = NULL;
    if (w->enc_tail)
        w->enc_tail->next = e;
    else
        w->enc_head = e;
    w->enc_tail = e;
    w->enc_depth++;
    pthread_cond_signal(&w->enc_work);
    pthread_mutex_unlock(&w->enc_lock);
}

/* ---------------------------------------------------------------- rendering */

int lc_workers_timings(const lc_frame_info *info, lc_frame_timing *out, int cap)
{
    int n = 0;
    for (int p = 0; p < LC_PASS_COUNT && n < cap; p++) {
        if (info->pass_ms[p] < 0)
            continue;
        snprintf(out[n].pass, sizeof out[n].pass, "%s", lc_pass_name(p));
        out[n].ms = info->pass_ms[p];
        n++;
    }
    return n;
}

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

static void finish_job(lc_render_job *job)
{
    if (job->done)
        job->done(job); /* the job belongs to its submitter again from here */
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
        finish_job(job);
        return;
    }
    /* While in hand the frame reads and writes only its own copies (and holds
     * the session): lc_workers_abandon may hand the job back meanwhile. */
    const lc_render_params params = job->req.render, *p = &params;
    const lc_dataset *dataset = job->dataset;
    double dt = job->dt;
    lc_session *session = job->session;
    uint8_t *rgba = malloc((size_t)p->width * (size_t)p->height * 4);
    if (!rgba) {
        job->rc = lc_err(&job->err, LC_ERR_NOMEM, "out of memory for a %dx%d image", p->width, p->height);
        finish_job(job);
        return;
    }
    if (session)
        lc_session_ref(session);
    lc_frame_info info;
    in_hand(wk, job, NULL);
    int rc = lc_server_render_frame(w->srv, wk->renderer, dataset, p, session ? session->frame_state : NULL, dt, rgba,
                                    &info, &err);
    if (!w->srv->mpi) /* a large frame keeps no targets (collective frames under MPI keep them) */
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
        finish_job(job);
        return;
    }
    lc_metrics_frame(w->srv->metrics, job->session ? "session" : "http", &job->info);
    learn_rate(w, job->cost, job->info.wall_ms);
    encode_item *e = calloc(1, sizeof *e);
    if (!e) {
        free(job->rgba);
        job->rgba = NULL;
        job->rc = lc_err(&job->err, LC_ERR_NOMEM, "out of memory");
        finish_job(job);
        return;
    }
    e->rgba = job->rgba;
    job->rgba = NULL;
    e->width = p->width;
    e->height = p->height;
    e->format = job->req.format;
    e->quality = job->req.quality;
    e->job = job;
    push_encode(w, e);
}

static void send_stream_error(lc_server *srv, lc_session *s, const char *code, const char *message, const char *field)
{
    char *msg = lc_proto_error_message_json(code, message, field, false);
    lc_metrics_error(srv->metrics, code);
    if (msg)
        srv->sink.send(srv->sink.ctx, s, (unsigned char *)msg, strlen(msg), false);
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
    in_hand(wk, NULL, s);
    int rc = rgba ? lc_server_render_frame(w->srv, wk->renderer, s->dataset, p, s->frame_state, f.dt, rgba, &info, &err)
                  : lc_err(&err, LC_ERR_NOMEM, "out of memory for a %dx%d frame", p->width, p->height);
    out_of_hand(wk);
    lc_session_stream_done(s, &f, rc == 0, rc == 0 ? &info : NULL);
    if (rc != 0) {
        free(rgba);
        LC_WARN(MOD, "session %s: frame %llu failed: %s", s->id, (unsigned long long)f.frame, err.msg);
        if (rc == LC_ERR_INVALID)
            send_stream_error(w->srv, s, LC_PROTO_BAD_FIELD, err.msg, err.field[0] ? err.field : NULL);
        else
            send_stream_error(w->srv, s, "render_failed", err.msg, NULL);
        return;
    }
    lc_metrics_frame(w->srv->metrics, "ws", &info);
    encode_item *e = calloc(1, sizeof *e);
    if (!e) {
        free(rgba);
        return;
    }
    e->rgba = rgba;
    e->width = p->width;
    e->height = p->height;
    e->format = LC_FORMAT_JPEG;
    e->quality = f.quality;
    e->frame = f;
    e->info = info;
    lc_session_ref(s);
    e->session = s;
    push_encode(w, e);
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
        rc = lc_renderer_create(&(lc_renderer_desc){.reducer = w->srv->mpi ? lc_mpi_reducer(w->srv->mpi) : NULL},
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
        task *t = NULL;
        while (!w->stopping) {
            double next = run_timers(w, lc_now());
            t = pop_task(w);
            if (t)
                break;
            if (next > 0)
                wait_until(&w->work, &w->lock, next);
            else
                pthread_cond_wait(&w->work, &w->lock);
        }
        if (!t)
            break; /* stopping: queued leftovers are failed by lc_workers_stop */
        if (t->session)
            t->session->sched_queued = false;
        pthread_mutex_unlock(&w->lock);
        if (t->job)
            render_job(wk, t->job);
        else {
            render_session(wk, t->session);
            lc_session_unref(t->session);
        }
        free(t);
        pthread_mutex_lock(&w->lock);
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

/* ---------------------------------------------------------------- encoding */

static void encode_one(lc_workers *w, encode_item *e)
{
    lc_server *srv = w->srv;
    unsigned char *img = NULL;
    size_t size = 0;
    lc_error err = {0};
    double t0 = lc_now();
    int rc = e->format == LC_FORMAT_PNG
                 ? lc_image_encode_png(e->rgba, e->width, e->height, &img, &size, &err)
                 : lc_image_encode_jpeg(e->rgba, e->width, e->height, e->quality, &img, &size, &err);
    double ms = (lc_now() - t0) * 1000.0;
    free(e->rgba);
    e->rgba = NULL;
    if ((long long)e->width * e->height > LC_LARGE_FRAME_PIXELS)
        lc_memory_trim(); /* what the large frame's buffers leave in the heap goes back too */
    if (rc == 0)
        lc_metrics_encode(srv->metrics, ms, (long long)e->width * e->height, size);
    if (e->job) {
        lc_render_job *job = e->job;
        job->rc = rc;
        if (rc != 0)
            job->err = err;
        job->image = img;
        job->image_size = size;
        job->encode_ms = ms;
        finish_job(job);
        return;
    }
    lc_session *s = e->session;
    if (rc != 0) {
        LC_WARN(MOD, "session %s: encode failed: %s", s->id, err.msg);
        send_stream_error(srv, s, "render_failed", err.msg, NULL);
        lc_session_stream_sent(s, e->frame.frame);
        lc_session_stream_ack(s, e->frame.frame); /* nothing to ack for this id */
        lc_workers_wake(w, s);
        return;
    }
    lc_frame_header h;
    memset(&h, 0, sizeof h);
    h.frame = e->frame.frame;
    h.width = e->width;
    h.height = e->height;
    h.format = LC_FORMAT_JPEG;
    h.quality = e->quality;
    h.camera_seq = e->frame.camera_seq;
    h.converged = e->info.converged != 0;
    h.timing_count = lc_workers_timings(&e->info, h.timings, LC_PROTO_MAX_TIMINGS);
    h.encode_ms = ms;
    h.has_detail = true;
    h.interactive = e->frame.interactive;
    h.reused = e->info.reused_opacities != 0;
    h.level = e->info.lod_level;
    h.lod_pixels = e->frame.req.render.detail.lod_pixels;
    h.point_stride = e->info.point_stride > 0 ? e->info.point_stride : 1;
    h.primitives = e->info.primitives_drawn;
    h.render_ms = e->info.wall_ms;
    if (e->info.has_visibility) {
        h.has_visibility = true;
        h.top_decile_alpha = e->info.top_decile_alpha;
        h.bottom_half_alpha = e->info.bottom_half_alpha;
        h.covered_fraction = e->info.covered_fraction;
    }
    unsigned char *msg = NULL;
    size_t len = 0;
    rc = lc_proto_pack_frame(&h, img, size, &msg, &len);
    free(img);
    if (rc == 0) {
        lc_session_stream_sent(s, e->frame.frame);
        srv->sink.send_frame(srv->sink.ctx, s, msg, len, e->info.wall_ms, ms);
    }
}

static void *encoder_main(void *arg)
{
    lc_workers *w = arg;
    pthread_mutex_lock(&w->enc_lock);
    for (;;) {
        while (!w->enc_head && !w->enc_stopping)
            pthread_cond_wait(&w->enc_work, &w->enc_lock);
        encode_item *e = w->enc_head;
        if (!e)
            break; /* stopping and drained */
        w->enc_head = e->next;
        if (!w->enc_head)
            w->enc_tail = NULL;
        w->enc_depth--;
        pthread_mutex_unlock(&w->enc_lock);
        encode_one(w, e);
        if (e->session)
            lc_session_unref(e->session);
        free(e);
        pthread_mutex_lock(&w->enc_lock);
    }
    pthread_mutex_unlock(&w->enc_lock);
    return NULL;
}

/* ---------------------------------------------------------------- life cycle */

int lc_workers_create(lc_server *srv, lc_gl *primary, int nworkers, int nencoders, int max_queue, lc_workers **out,
                      lc_error *err)
{
    *out = NULL;
    lc_workers *w = calloc(1, sizeof *w);
    if (!w)
        return lc_err(err, LC_ERR_NOMEM, "out of memory");
    w->srv = srv;
    w->nworkers = nworkers > 0 ? nworkers : 1;
    w->nencoders = nencoders > 0 ? nencoders : 1;
    w->max_queue = max_queue > 0 ? max_queue : 1;
    w->workers = calloc((size_t)w->nworkers, sizeof *w->workers);
    w->encoders = calloc((size_t)w->nencoders, sizeof *w->encoders);
    if (!w->workers || !w->encoders) {
        free(w->workers);
        free(w->encoders);
        free(w);
        return lc_err(err, LC_ERR_NOMEM, "out of memory");
    }
    pthread_mutex_init(&w->lock, NULL);
    pthread_condattr_t ca;
    pthread_condattr_init(&ca);
    pthread_condattr_setclock(&ca, CLOCK_MONOTONIC);
    pthread_cond_init(&w->work, &ca);
    pthread_condattr_destroy(&ca);
    pthread_cond_init(&w->ready, NULL);
    pthread_mutex_init(&w->enc_lock, NULL);
    pthread_cond_init(&w->enc_work, NULL);
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
    for (int i = 0; !failed && i < w->nencoders; i++)
        if (pthread_create(&w->encoders[i], NULL, encoder_main, w) == 0)
            w->encoders_started++;
    if (failed || w->encoders_started == 0) {
        if (!failed)
            lc_err(&w->start_err, LC_ERR_INTERNAL, "cannot start encoder threads");
        if (err)
            *err = w->start_err;
        int code = w->start_err.code ? w->start_err.code : LC_ERR_INTERNAL;
        *out = w; /* the caller stops and destroys it (contexts need the same teardown) */
        lc_workers_stop(w);
        return code;
    }
    LC_INFO(MOD, "%d render worker(s), %d encoder thread(s)", w->nworkers, w->encoders_started);
    *out = w;
    return 0;
}

/* A queued task that will not run: its HTTP job fails with `why`; a session
 * leaves the queue, told `why` as an error when `tell`. Frees t. */
static void fail_task(lc_workers *w, task *t, const char *why, bool tell)
{
    if (t->job) {
        t->job->rc = lc_err(&t->job->err, LC_ERR_UNSUPPORTED, "%s", why);
        finish_job(t->job);
    } else {
        t->session->sched_queued = false;
        if (tell)
            send_stream_error(w->srv, t->session, "render_failed", why, NULL);
        lc_session_unref(t->session);
    }
    free(t);
}

void lc_workers_abandon(lc_workers *w, const char *why)
{
    if (!w)
        return;
    lc_render_job *jobs[64];
    lc_session *sessions[64];
    int nj = 0, ns = 0;
    task *queued = NULL;
    pthread_mutex_lock(&w->lock);
    if (w->abandoned) {
        pthread_mutex_unlock(&w->lock);
        return;
    }
    w->abandoned = w->stopping = true;
    pthread_cond_broadcast(&w->work);
    for (int i = 0; i < w->nworkers; i++) {
        worker *wk = &w->workers[i];
        if (wk->job && nj < 64) {
            jobs[nj++] = wk->job;
            wk->job = NULL, wk->lost = true;
        }
        if (wk->session && ns < 64) {
            lc_session_ref(wk->session);
            sessions[ns++] = wk->session;
        }
    }
    task *t;
    while ((t = pop_task(w))) {
        t->next = queued;
        queued = t;
    }
    pthread_mutex_unlock(&w->lock);
    for (int i = 0; i < nj; i++) {
        jobs[i]->rc = lc_err(&jobs[i]->err, LC_ERR_UNSUPPORTED, "%s", why);
        finish_job(jobs[i]);
    }
    for (int i = 0; i < ns; i++)
        send_stream_error(w->srv, sessions[i], "render_failed", why, NULL);
    while ((t = queued)) {
        queued = t->next;
        bool told = false; /* a session can be queued again while its frame is in hand */
        for (int i = 0; i < ns; i++)
            told |= sessions[i] == t->session;
        fail_task(w, t, why, !told);
    }
    for (int i = 0; i < ns; i++)
        lc_session_unref(sessions[i]);
}

void lc_workers_stop(lc_workers *w)
{
    if (!w)
        return;
    pthread_mutex_lock(&w->lock);
    w->stopping = true;
    pthread_cond_broadcast(&w->work);
    pthread_cond_broadcast(&w->ready);
    pthread_mutex_unlock(&w->lock);
    for (int i = 0; i < w->nworkers; i++) {
        if (w->workers[i].started)
            pthread_join(w->workers[i].thread, NULL);
        w->workers[i].started = false;
    }
    /* Workers are gone: fail what is still queued, drop parked sessions. */
    pthread_mutex_lock(&w->lock);
    task *t;
    while ((t = pop_task(w))) {
        pthread_mutex_unlock(&w->lock);
        fail_task(w, t, "the server is shutting down", false);
        pthread_mutex_lock(&w->lock);
    }
    while (w->timed)
        untime(w, w->timed);
    pthread_mutex_unlock(&w->lock);
    /* Encoders finish what the workers handed them, then exit. */
    pthread_mutex_lock(&w->enc_lock);
    w->enc_stopping = true;
    pthread_cond_broadcast(&w->enc_work);
    pthread_mutex_unlock(&w->enc_lock);
    for (int i = 0; i < w->encoders_started; i++)
        pthread_join(w->encoders[i], NULL);
    w->encoders_started = 0;
}

void lc_workers_destroy(lc_workers *w, lc_datasets *datasets)
{
    if (!w)
        return;
    lc_workers_stop(w);
    lc_gl *primary = w->workers[0].gl;
    lc_error err = {0};
    if (primary && lc_gl_make_current(primary, &err) == 0) {
        lc_datasets_release_gpu(datasets);
        lc_gl_release_current(primary);
    }
    for (int i = w->nworkers - 1; i >= 0; i--)
        if (w->workers[i].gl)
            lc_gl_destroy(w->workers[i].gl);
    pthread_mutex_destroy(&w->lock);
    pthread_cond_destroy(&w->work);
    pthread_cond_destroy(&w->ready);
    pthread_mutex_destroy(&w->enc_lock);
    pthread_cond_destroy(&w->enc_work);
    free(w->workers);
    free(w->encoders);
    free(w);
}

int lc_workers_count(const lc_workers *w) { return w ? w->nworkers : 0; }

int lc_workers_clients(lc_workers *w)
{
    pthread_mutex_lock(&w->lock);
    int n = w->flows;
    pthread_mutex_unlock(&w->lock);
    return n;
}

void lc_workers_depths(lc_workers *w, int *render_queue, int *encode_queue)
{
    pthread_mutex_lock(&w->lock);
    *render_queue = w->tasks_queued;
    pthread_mutex_unlock(&w->lock);
    pthread_mutex_lock(&w->enc_lock);
    *encode_queue = w->enc_depth;
    pthread_mutex_unlock(&w->enc_lock);
}
