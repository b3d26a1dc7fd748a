/* The render worker pool's end: abandoning the frames in hand (a dead MPI
 * rank, the watchdog), stopping and destroying the pool, and its queue
 * figures for /metrics and /api/v1/health. */
#include "workers_stop.h"

#include "workers_internal.h"

#include <stdlib.h>

#include "encoders.h"
#include "fair_queue.h"
#include "queue_deadline.h"
#include "traced.h"

void lc_workers_untime(lc_workers *w, lc_session *s)
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

void lc_workers_finish_job(lc_render_job *job)
{
    if (job->done)
        job->done(job); /* the job belongs to its submitter again from here */
}

/* A queued task that will not run: its HTTP job fails with `why`; a session
 * leaves the queue, told `why` as an error when `tell`. Frees t. */
static void fail_task(lc_workers *w, lc_task *t, const char *why, bool tell)
{
    if (t->job) {
        t->job->rc = lc_err(&t->job->err, LC_ERR_UNSUPPORTED, "%s", why);
        lc_workers_finish_job(t->job);
    } else {
        t->session->sched_queued = false;
        if (tell)
            lc_stream_error(w->srv, t->session, "render_failed", why, NULL);
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
    lc_task *queued = NULL;
    pthread_mutex_lock(&w->lock);
    if (w->abandoned) {
        pthread_mutex_unlock(&w->lock);
        return;
    }
    w->abandoned = w->stopping = true;
    pthread_cond_broadcast(&w->work);
    lc_yield_release(&w->gate);
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
    lc_task *t;
    while ((t = lc_fair_pop(&w->queue))) {
        t->next = queued;
        queued = t;
    }
    pthread_mutex_unlock(&w->lock);
    for (int i = 0; i < nj; i++) {
        jobs[i]->rc = lc_err(&jobs[i]->err, LC_ERR_UNSUPPORTED, "%s", why);
        lc_workers_finish_job(jobs[i]);
    }
    for (int i = 0; i < ns; i++)
        lc_stream_error(w->srv, sessions[i], "render_failed", why, NULL);
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
    lc_yield_release(&w->gate); /* the frames in hand finish without waiting */
    lc_queue_deadline_stop(w);  /* what is queued now fails below */
    for (int i = 0; i < w->nworkers; i++) {
        if (w->workers[i].started)
            pthread_join(w->workers[i].thread, NULL);
        w->workers[i].started = false;
    }
    /* Workers are gone: fail what is still queued, drop parked sessions. */
    pthread_mutex_lock(&w->lock);
    lc_task *t;
    while ((t = lc_fair_pop(&w->queue))) {
        pthread_mutex_unlock(&w->lock);
        fail_task(w, t, "the server is shutting down", false);
        pthread_mutex_lock(&w->lock);
    }
    while (w->timed)
        lc_workers_untime(w, w->timed);
    pthread_mutex_unlock(&w->lock);
    /* Encoders finish what the workers handed them, then exit. */
    lc_encoders_stop(w->encoders);
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
        lc_traced_collect();                        /* the GPU copies of streamline sets freed since the last frame */
        lc_surface_keeps_destroy(w->surface_keeps); /* GL buffers of the share group */
        w->surface_keeps = NULL;
        lc_gl_release_current(primary);
    }
    for (int i = w->nworkers - 1; i >= 0; i--)
        if (w->workers[i].gl)
            lc_gl_destroy(w->workers[i].gl);
    pthread_mutex_destroy(&w->lock);
    pthread_cond_destroy(&w->work);
    pthread_cond_destroy(&w->deadline_wake);
    pthread_cond_destroy(&w->ready);
    lc_yield_gate_destroy(&w->gate);
    lc_surface_keeps_destroy(w->surface_keeps); /* still here: no GL context started, so no layers either */
    free(w->workers);
    lc_encoders_destroy(w->encoders);
    free(w);
}

int lc_workers_count(const lc_workers *w) { return w ? w->nworkers : 0; }

int lc_workers_clients(lc_workers *w)
{
    pthread_mutex_lock(&w->lock);
    int n = w->queue.clients;
    pthread_mutex_unlock(&w->lock);
    return n;
}

void lc_workers_depths(lc_workers *w, int *render_queue, int *encode_queue)
{
    pthread_mutex_lock(&w->lock);
    *render_queue = w->queue.tasks;
    pthread_mutex_unlock(&w->lock);
    *encode_queue = w->encoders ? lc_encoders_depth(w->encoders) : 0;
}
