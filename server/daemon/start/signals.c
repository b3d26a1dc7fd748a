/* SIGINT/SIGTERM watcher: cancels start-up, wakes the shutdown (signals.h). */
#include "signals.h"

#include <errno.h>
#include <pthread.h>
#include <signal.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#define MOD "serve"

static pthread_mutex_t lock = PTHREAD_MUTEX_INITIALIZER;
static pthread_cond_t changed = PTHREAD_COND_INITIALIZER;
static sigset_t watched;
static int received, serving;

const char *lc_signals_name(int sig) { return sig == SIGINT ? "SIGINT" : sig == SIGTERM ? "SIGTERM" : "signal"; }

/* During start-up: waits LC_SIGNALS_GRACE seconds for serve to exit or to
 * reach lc_signals_serving; ends the process when neither happens. */
static void grace(int sig)
{
    struct timespec until;
    clock_gettime(CLOCK_REALTIME, &until);
    until.tv_sec += (time_t)LC_SIGNALS_GRACE;
    pthread_mutex_lock(&lock);
    while (!serving && pthread_cond_timedwait(&changed, &lock, &until) != ETIMEDOUT)
        ;
    int done = serving;
    pthread_mutex_unlock(&lock);
    if (!done) {
        LC_ERROR(MOD, "%s: start-up did not stop within %.0f s; exiting now", lc_signals_name(sig), LC_SIGNALS_GRACE);
        _exit(1);
    }
}

static void *watch(void *arg)
{
    (void)arg;
    for (;;) {
        int sig = 0;
        if (sigwait(&watched, &sig) != 0)
            continue;
        pthread_mutex_lock(&lock);
        int first = !received, starting = !serving;
        if (first)
            received = sig;
        pthread_cond_broadcast(&changed);
        pthread_mutex_unlock(&lock);
        if (!first && starting) {
            LC_ERROR(MOD, "%s again during start-up: exiting now", lc_signals_name(sig));
            _exit(1);
        }
        if (first && starting) {
            LC_WARN(MOD, "%s during start-up: stopping the load", lc_signals_name(sig));
            lc_cancel(sig);
            grace(sig);
        }
    }
    return NULL;
}

int lc_signals_start(lc_error *err)
{
    sigemptyset(&watched);
    sigaddset(&watched, SIGINT);
    sigaddset(&watched, SIGTERM);
    pthread_sigmask(SIG_BLOCK, &watched, NULL); /* every thread started later inherits it */
    pthread_t t;
    int e = pthread_create(&t, NULL, watch, NULL);
    if (e)
        return lc_err(err, LC_ERR_INTERNAL, "cannot start the signal thread: %s", strerror(e));
    pthread_detach(t);
    return 0;
}

void lc_signals_serving(void)
{
    pthread_mutex_lock(&lock);
    serving = 1;
    pthread_cond_broadcast(&changed);
    pthread_mutex_unlock(&lock);
}

int lc_signals_wait(void)
{
    pthread_mutex_lock(&lock);
    while (!received)
        pthread_cond_wait(&changed, &lock);
    int sig = received;
    pthread_mutex_unlock(&lock);
    return sig;
}

int lc_signals_received(void)
{
    pthread_mutex_lock(&lock);
    int sig = received;
    pthread_mutex_unlock(&lock);
    return sig;
}
