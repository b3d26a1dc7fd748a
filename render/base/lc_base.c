/* Error helpers, leveled logging and the monotonic clock. */
#define _POSIX_C_SOURCE 200809L
#include "lc_base.h"

#include <pthread.h>
#include <stdatomic.h>
#include <stdio.h>
#include <string.h>
#include <time.h>

int lc_log_threshold = LC_LOG_INFO;
static pthread_mutex_t log_lock = PTHREAD_MUTEX_INITIALIZER;

int lc_err(lc_error *err, int code, const char *fmt, ...)
{
    if (err) {
        va_list ap;
        va_start(ap, fmt);
        err->code = code;
        err->field[0] = '\0';
        vsnprintf(err->msg, sizeof err->msg, fmt, ap);
        va_end(ap);
    }
    return code;
}

int lc_err_field(lc_error *err, int code, const char *field, const char *fmt, ...)
{
    if (err) {
        char reason[LC_ERROR_MSG_LEN];
        va_list ap;
        va_start(ap, fmt);
        vsnprintf(reason, sizeof reason, fmt, ap);
        va_end(ap);
        err->code = code;
        snprintf(err->field, sizeof err->field, "%s", field);
        snprintf(err->msg, sizeof err->msg, "%.63s: %.190s", field, reason);
    }
    return code;
}

void lc_err_prefix(lc_error *err, const char *fmt, ...)
{
    if (!err)
        return;
    char prefix[LC_ERROR_MSG_LEN], old[LC_ERROR_MSG_LEN];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(prefix, sizeof prefix, fmt, ap);
    va_end(ap);
    memcpy(old, err->msg, sizeof old);
    snprintf(err->msg, sizeof err->msg, "%.120s: %.130s", prefix, old);
}

const char *lc_status_name(int code)
{
    switch (code) {
    case LC_OK: return "ok";
    case LC_ERR_INVALID: return "invalid";
    case LC_ERR_IO: return "io";
    case LC_ERR_NOMEM: return "nomem";
    case LC_ERR_LIMIT: return "limit";
    case LC_ERR_GL: return "gl";
    case LC_ERR_NOT_FOUND: return "not_found";
    case LC_ERR_UNSUPPORTED: return "unsupported";
    case LC_ERR_CANCELLED: return "cancelled";
    case LC_ERR_BUDGET: return "budget";
    default: return "internal";
    }
}

void lc_log_set_level(lc_log_level level) { lc_log_threshold = (int)level; }

int lc_log_parse_level(const char *name)
{
    static const char *names[] = {"error", "warn", "info", "debug"};
    for (int i = 0; i < 4; i++)
        if (name && strcmp(name, names[i]) == 0)
            return i;
    return -1;
}

void lc_log_write(lc_log_level level, const char *module, const char *fmt, ...)
{
    static const char *tags[] = {"ERROR", "WARN ", "INFO ", "DEBUG"};
    char text[1024];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(text, sizeof text, fmt, ap);
    va_end(ap);

    struct timespec ts;
    clock_gettime(CLOCK_REALTIME, &ts);
    struct tm tm;
    gmtime_r(&ts.tv_sec, &tm);
    char when[32];
    strftime(when, sizeof when, "%Y-%m-%dT%H:%M:%S", &tm);

    /* One event, one line: control characters in the text (a file name with a
     * newline or an escape sequence) are written as \n, \xHH, never raw. */
    char safe[4 * sizeof text];
    size_t k = 0;
    for (const unsigned char *c = (const unsigned char *)text; *c && k + 5 < sizeof safe; c++) {
        if (*c >= 32 && *c != 127)
            safe[k++] = (char)*c;
        else if (*c == '\n' || *c == '\t' || *c == '\r')
            safe[k++] = '\\', safe[k++] = *c == '\n' ? 'n' : *c == '\t' ? 't' : 'r';
        else
            k += (size_t)snprintf(safe + k, sizeof safe - k, "\\x%02x", *c);
    }
    safe[k] = '\0';

    pthread_mutex_lock(&log_lock);
    fprintf(stderr, "%s.%03ldZ %s [%s] %s\n", when, ts.tv_nsec / 1000000L,
            tags[level < 0   ? 0
                 : level > 3 ? 3
                             : level],
            module ? module : "-", safe);
    fflush(stderr);
    pthread_mutex_unlock(&log_lock);
}

static atomic_int cancel_flag;

void lc_cancel(int sig) { atomic_store(&cancel_flag, sig ? sig : 1); }

/* The calling thread's load budget: datasets load one at a time on the
 * thread that starts the daemon, so one deadline per thread. */
static _Thread_local double budget_seconds, budget_deadline;

void lc_load_budget(double seconds)
{
    budget_seconds = seconds > 0 ? seconds : 0;
    budget_deadline = seconds > 0 ? lc_now() + seconds : 0;
}

int lc_cancelled(void)
{
    int sig = atomic_load_explicit(&cancel_flag, memory_order_relaxed);
    if (sig)
        return sig;
    return budget_deadline > 0 && lc_now() > budget_deadline ? -1 : 0;
}

int lc_err_cancelled(lc_error *err, const char *what)
{
    if (!atomic_load_explicit(&cancel_flag, memory_order_relaxed) && budget_deadline > 0)
        return lc_err(err, LC_ERR_LIMIT, "%s: stopped after %.0f s, over the load budget of %g s",
                      what ? what : "loading", lc_now() - (budget_deadline - budget_seconds), budget_seconds);
    return lc_err(err, LC_ERR_CANCELLED, "%s: stopped by a signal", what ? what : "loading");
}

double lc_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}
