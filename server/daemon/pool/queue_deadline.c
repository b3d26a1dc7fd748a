/* The render queue's deadline (queue_deadline.h). */
#include "queue_deadline.h"

#include <stdlib.h>

#include "lc_base.h"
#include "yield.h"

double lc_queue_wait_limit(const lc_workers *w)
{
    double d = w->srv->cfg.render_deadline;
    return d <= 0 ? 0 : d < LC_QUEUE_WAIT_MAX ? d : LC_QUEUE_WAIT_MAX;
}

static bool waited_out(const lc_task *t, void *ctx) { return t->job && t->job->submitted <= *(const double *)ctx; }

static void oldest_job(const lc_task *t, void *ctx)
{
    double *oldest = ctx;
    if (t->job && (*oldest == 0 || t->job->submitted < *oldest))
        *oldest = t->job->submitted;
}

/* Answers t's job: it waited `limit` seconds and no worker took it. */
static void answer(lc_task *t, double limit, int others)
{
    lc_render_job *job = t->job;
    free(t);
    job->queue_ms = (lc_now() - job->submitted) * 1000.0;
    job->refused = "deadline";
    job->rc = lc_err(&job->err, LC_ERR_LIMIT,
                     "waited %.1f s for a worker (%d other render%s queued), beyond its %.0f s deadline: the server is "
                     "busy, retry later",
                     job->queue_ms / 1000.0, others, others == 1 ? "" : "s", limit);
    if (job->done)
        job->done(job); /* the job belongs to its submitter again from here */
}

static void *deadline_main(void *arg)
{
    lc_workers *w = arg;
    double limit = lc_queue_wait_limit(w);
    pthread_mutex_lock(&w->lock);
    while (!w->stopping) {
        double cut = lc_now() - limit;
        lc_task *t = lc_fair_remove_where(&w->queue, waited_out, &cut);
        if (t) {
            int others = w->queue.jobs;
            pthread_mutex_unlock(&w->lock);
            answer(t, limit, others);
            pthread_mutex_lock(&w->lock);
            continue;
        }
        double oldest = 0; /* a job queued later expires no sooner than `limit` from now */
        lc_fair_each(&w->queue, oldest_job, &oldest);
        lc_cond_wait_until(&w->deadline_wake, &w->lock, (oldest > 0 ? oldest : lc_now()) + limit);
    }
    pthread_mutex_unlock(&w->lock);
    return NULL;
}

int lc_queue_deadline_start(lc_workers *w)
{
    if (lc_queue_wait_limit(w) <= 0)
        return 0;
    if (pthread_create(&w->deadline_thread, NULL, deadline_main, w) != 0)
        return -1;
    w->deadline_started = true;
    return 0;
}

void lc_queue_deadline_stop(lc_workers *w)
{
    if (!w->deadline_started)
        return;
    pthread_mutex_lock(&w->lock);
    pthread_cond_broadcast(&w->deadline_wake);
    pthread_mutex_unlock(&w->lock);
    pthread_join(w->deadline_thread, NULL);
    w->deadline_started = false;
}
