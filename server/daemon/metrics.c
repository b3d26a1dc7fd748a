/* Counters and fixed-bucket histograms in Prometheus text format. */
#include "metrics.h"

#include <pthread.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define NBUCKETS 14
/* Milliseconds: from a small GPU frame to a big llvmpipe one. */
static const double bucket_ms[NBUCKETS] = {0.5, 1, 2, 5, 10, 20, 50, 100, 200, 500, 1000, 2000, 5000, 10000};

typedef struct histogram {
    uint64_t counts[NBUCKETS + 1]; /* last = +Inf */
    double sum_ms;
    uint64_t n;
} histogram;

#define MAX_CODES 48
#define MAX_STATUSES 24

struct lc_metrics {
    pthread_mutex_t lock;
    uint64_t frames_http, frames_session, frames_ws;
    histogram total;
    histogram pass[LC_PASS_COUNT];
    histogram encode;
    uint64_t encoded_pixels, encoded_bytes;
    uint64_t bytes_sent;
    uint64_t coalesced;
    uint64_t yielded;     /* stills pre-empted by newer input */
    uint64_t yield_waits; /* large renders' waits for other sessions' moving frames */
    double yield_wait_seconds;
    int code_count;
    char codes[MAX_CODES][32];
    uint64_t code_n[MAX_CODES];
    uint64_t refused[4]; /* by refusal_reasons */
    double cost_total, cost_rate;
    int status_count;
    int statuses[MAX_STATUSES];
    uint64_t status_n[MAX_STATUSES];
};

lc_metrics *lc_metrics_create(void)
{
    lc_metrics *m = calloc(1, sizeof *m);
    if (m)
        pthread_mutex_init(&m->lock, NULL);
    return m;
}

void lc_metrics_destroy(lc_metrics *m)
{
    if (!m)
        return;
    pthread_mutex_destroy(&m->lock);
    free(m);
}

static void observe(histogram *h, double ms)
{
    int i = 0;
    while (i < NBUCKETS && ms > bucket_ms[i])
        i++;
    h->counts[i]++;
    h->sum_ms += ms;
    h->n++;
}

void lc_metrics_frame(lc_metrics *m, const char *kind, const lc_frame_info *info)
{
    pthread_mutex_lock(&m->lock);
    if (strcmp(kind, "ws") == 0)
        m->frames_ws++;
    else if (strcmp(kind, "session") == 0)
        m->frames_session++;
    else
        m->frames_http++;
    if (info) {
        observe(&m->total, info->wall_ms);
        for (int p = 0; p < LC_PASS_COUNT; p++)
            if (info->pass_ms[p] >= 0)
                observe(&m->pass[p], info->pass_ms[p]);
    }
    pthread_mutex_unlock(&m->lock);
}

void lc_metrics_encode(lc_metrics *m, double ms, long long pixels, size_t bytes)
{
    pthread_mutex_lock(&m->lock);
    observe(&m->encode, ms);
    m->encoded_pixels += (uint64_t)pixels;
    m->encoded_bytes += bytes;
    pthread_mutex_unlock(&m->lock);
}

void lc_metrics_bytes_sent(lc_metrics *m, size_t bytes)
{
    pthread_mutex_lock(&m->lock);
    m->bytes_sent += bytes;
    pthread_mutex_unlock(&m->lock);
}

void lc_metrics_coalesced(lc_metrics *m, uint64_t frames)
{
    pthread_mutex_lock(&m->lock);
    m->coalesced += frames;
    pthread_mutex_unlock(&m->lock);
}

void lc_metrics_yielded(lc_metrics *m)
{
    pthread_mutex_lock(&m->lock);
    m->yielded++;
    pthread_mutex_unlock(&m->lock);
}

void lc_metrics_yield_wait(lc_metrics *m, double seconds)
{
    pthread_mutex_lock(&m->lock);
    m->yield_waits++;
    m->yield_wait_seconds += seconds;
    pthread_mutex_unlock(&m->lock);
}

void lc_metrics_error(lc_metrics *m, const char *code)
{
    pthread_mutex_lock(&m->lock);
    int i = 0;
    while (i < m->code_count && strcmp(m->codes[i], code) != 0)
        i++;
    if (i == m->code_count && m->code_count < MAX_CODES) {
        snprintf(m->codes[i], sizeof m->codes[i], "%s", code);
        m->code_count++;
    }
    if (i < m->code_count)
        m->code_n[i]++;
    pthread_mutex_unlock(&m->lock);
}

void lc_metrics_http_request(lc_metrics *m, int status)
{
    pthread_mutex_lock(&m->lock);
    int i = 0;
    while (i < m->status_count && m->statuses[i] != status)
        i++;
    if (i == m->status_count && m->status_count < MAX_STATUSES)
        m->statuses[m->status_count++] = status;
    if (i < m->status_count)
        m->status_n[i]++;
    pthread_mutex_unlock(&m->lock);
}

static const char *const refusal_reasons[4] = {"cost", "deadline", "queue", "client_queue"};

void lc_metrics_refused(lc_metrics *m, const char *reason)
{
    pthread_mutex_lock(&m->lock);
    for (int i = 0; i < 4; i++)
        if (strcmp(reason, refusal_reasons[i]) == 0)
            m->refused[i]++;
    pthread_mutex_unlock(&m->lock);
}

void lc_metrics_cost(lc_metrics *m, double cost, double rate)
{
    pthread_mutex_lock(&m->lock);
    m->cost_total += cost;
    m->cost_rate = rate;
    pthread_mutex_unlock(&m->lock);
}

/* Growable text buffer for the exposition. */
typedef struct text {
    char *s;
    size_t len, cap;
} text;

static void put(text *t, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
static void put(text *t, const char *fmt, ...)
{
    for (;;) {
        va_list ap;
        va_start(ap, fmt);
        int n = vsnprintf(t->s ? t->s + t->len : NULL, t->s ? t->cap - t->len : 0, fmt, ap);
        va_end(ap);
        if (n < 0)
            return;
        if (t->s && t->len + (size_t)n < t->cap) {
            t->len += (size_t)n;
            return;
        }
        size_t cap = t->cap ? t->cap * 2 : 8192;
        while (cap < t->len + (size_t)n + 1)
            cap *= 2;
        char *s = realloc(t->s, cap);
        if (!s)
            return;
        t->s = s;
        t->cap = cap;
    }
}

static void put_histogram(text *t, const char *name, const char *labels, const histogram *h)
{
    uint64_t cum = 0;
    const char *sep = labels[0] ? "," : "";
    for (int i = 0; i < NBUCKETS; i++) {
        cum += h->counts[i];
        put(t, "%s_bucket{%s%sle=\"%g\"} %llu\n", name, labels, sep, bucket_ms[i] / 1000.0, (unsigned long long)cum);
    }
    cum += h->counts[NBUCKETS];
    put(t, "%s_bucket{%s%sle=\"+Inf\"} %llu\n", name, labels, sep, (unsigned long long)cum);
    if (labels[0]) {
        put(t, "%s_sum{%s} %.6f\n", name, labels, h->sum_ms / 1000.0);
        put(t, "%s_count{%s} %llu\n", name, labels, (unsigned long long)h->n);
    } else {
        put(t, "%s_sum %.6f\n", name, h->sum_ms / 1000.0);
        put(t, "%s_count %llu\n", name, (unsigned long long)h->n);
    }
}

char *lc_metrics_render(lc_metrics *m, const lc_metrics_gauges *g)
{
    text t = {0};
    pthread_mutex_lock(&m->lock);
    put(&t, "# HELP lucent_frames_rendered_total Frames rendered, by kind of request.\n");
    put(&t, "# TYPE lucent_frames_rendered_total counter\n");
    put(&t, "lucent_frames_rendered_total{kind=\"http\"} %llu\n", (unsigned long long)m->frames_http);
    put(&t, "lucent_frames_rendered_total{kind=\"session\"} %llu\n", (unsigned long long)m->frames_session);
    put(&t, "lucent_frames_rendered_total{kind=\"ws\"} %llu\n", (unsigned long long)m->frames_ws);
    put(&t, "# HELP lucent_render_seconds Wall time of lc_render_frame.\n# TYPE lucent_render_seconds histogram\n");
    put_histogram(&t, "lucent_render_seconds", "", &m->total);
    put(&t, "# HELP lucent_pass_seconds GPU time per pass (timer queries).\n# TYPE lucent_pass_seconds histogram\n");
    for (int p = 0; p < LC_PASS_COUNT; p++) {
        char labels[64];
        snprintf(labels, sizeof labels, "pass=\"%s\"", lc_pass_name(p));
        put_histogram(&t, "lucent_pass_seconds", labels, &m->pass[p]);
    }
    put(&t, "# HELP lucent_encode_seconds Image encode time.\n# TYPE lucent_encode_seconds histogram\n");
    put_histogram(&t, "lucent_encode_seconds", "", &m->encode);
    put(&t,
        "# HELP lucent_encoded_pixels_total Pixels encoded (JPEG/PNG).\n# TYPE lucent_encoded_pixels_total counter\n");
    put(&t, "lucent_encoded_pixels_total %llu\n", (unsigned long long)m->encoded_pixels);
    put(&t, "# HELP lucent_encoded_bytes_total Bytes of encoded images.\n# TYPE lucent_encoded_bytes_total counter\n");
    put(&t, "lucent_encoded_bytes_total %llu\n", (unsigned long long)m->encoded_bytes);
    put(&t, "# HELP lucent_bytes_sent_total Image and frame bytes handed to clients.\n");
    put(&t, "# TYPE lucent_bytes_sent_total counter\nlucent_bytes_sent_total %llu\n",
        (unsigned long long)m->bytes_sent);
    put(&t,
        "# HELP lucent_frames_coalesced_total Camera/params updates overwritten by a newer one before rendering.\n");
    put(&t, "# TYPE lucent_frames_coalesced_total counter\nlucent_frames_coalesced_total %llu\n",
        (unsigned long long)m->coalesced);
    put(&t, "# HELP lucent_frames_yielded_total Still frames abandoned at a yield point for newer input.\n");
    put(&t, "# TYPE lucent_frames_yielded_total counter\nlucent_frames_yielded_total %llu\n",
        (unsigned long long)m->yielded);
    put(&t, "# HELP lucent_yield_waits_total Yield points at which a large render waited for other sessions' moving "
            "frames.\n");
    put(&t, "# TYPE lucent_yield_waits_total counter\nlucent_yield_waits_total %llu\n",
        (unsigned long long)m->yield_waits);
    put(&t, "# HELP lucent_yield_wait_seconds_total Seconds large renders waited so.\n");
    put(&t, "# TYPE lucent_yield_wait_seconds_total counter\nlucent_yield_wait_seconds_total %.3f\n",
        m->yield_wait_seconds);
    put(&t, "# HELP lucent_errors_total Errors answered, by code.\n# TYPE lucent_errors_total counter\n");
    for (int i = 0; i < m->code_count; i++)
        put(&t, "lucent_errors_total{code=\"%s\"} %llu\n", m->codes[i], (unsigned long long)m->code_n[i]);
    put(&t, "# HELP lucent_renders_refused_total Renders refused before running, by reason (cost over --max-cost, "
            "render deadline, full queue, the client's queue share).\n# TYPE lucent_renders_refused_total counter\n");
    for (int i = 0; i < 4; i++)
        put(&t, "lucent_renders_refused_total{reason=\"%s\"} %llu\n", refusal_reasons[i],
            (unsigned long long)m->refused[i]);
    put(&t,
        "# HELP lucent_render_cost_units_total Estimated cost of the HTTP renders that ran.\n"
        "# TYPE lucent_render_cost_units_total counter\nlucent_render_cost_units_total %.0f\n",
        m->cost_total);
    put(&t,
        "# HELP lucent_render_cost_rate Cost units rendered per second (moving average).\n"
        "# TYPE lucent_render_cost_rate gauge\nlucent_render_cost_rate %.0f\n",
        m->cost_rate);
    put(&t,
        "# HELP lucent_http_responses_total HTTP responses, by status.\n# TYPE lucent_http_responses_total counter\n");
    for (int i = 0; i < m->status_count; i++)
        put(&t, "lucent_http_responses_total{status=\"%d\"} %llu\n", m->statuses[i],
            (unsigned long long)m->status_n[i]);
    pthread_mutex_unlock(&m->lock);
    if (g) {
        put(&t, "# HELP lucent_sessions_active Open sessions.\n# TYPE lucent_sessions_active gauge\n");
        put(&t, "lucent_sessions_active{kind=\"http\"} %d\n", g->sessions_http);
        put(&t, "lucent_sessions_active{kind=\"ws\"} %d\n", g->sessions_ws);
        put(&t, "# HELP lucent_queue_depth Render tasks waiting for a worker.\n# TYPE lucent_queue_depth gauge\n");
        put(&t, "lucent_queue_depth %d\n", g->queue_depth);
        put(&t, "# HELP lucent_encode_queue_depth Frames waiting for an encoder.\n# TYPE lucent_encode_queue_depth "
                "gauge\n");
        put(&t, "lucent_encode_queue_depth %d\n", g->encode_depth);
        put(&t, "# HELP lucent_ws_connections Open WebSocket connections.\n# TYPE lucent_ws_connections gauge\n");
        put(&t, "lucent_ws_connections %d\n", g->ws_connections);
        put(&t, "# TYPE lucent_datasets gauge\nlucent_datasets %d\n", g->datasets);
        put(&t, "# TYPE lucent_workers gauge\nlucent_workers %d\n", g->workers);
        put(&t,
            "# HELP lucent_queue_clients Clients with queued renders (served round robin).\n"
            "# TYPE lucent_queue_clients gauge\nlucent_queue_clients %d\n",
            g->queue_clients);
        put(&t,
            "# HELP lucent_memory_budget_bytes --max-memory (0 = no limit).\n"
            "# TYPE lucent_memory_budget_bytes gauge\nlucent_memory_budget_bytes %llu\n",
            (unsigned long long)g->memory_budget);
        put(&t,
            "# HELP lucent_memory_estimated_bytes Estimated resident bytes of the datasets with their state and what "
            "requests hold (--max-memory counts them).\n"
            "# TYPE lucent_memory_estimated_bytes gauge\nlucent_memory_estimated_bytes %llu\n",
            (unsigned long long)g->memory_estimated);
        put(&t,
            "# HELP lucent_resident_bytes Resident memory of the process.\n"
            "# TYPE lucent_resident_bytes gauge\nlucent_resident_bytes %llu\n",
            (unsigned long long)g->resident);
    }
    if (g)
        put(&t,
            "# HELP lucent_http_unfinished_closed_total Connections closed before a whole request header: past the "
            "header deadline, or the oldest beyond the caps.\n"
            "# TYPE lucent_http_unfinished_closed_total counter\n"
            "lucent_http_unfinished_closed_total{reason=\"deadline\"} %llu\n"
            "lucent_http_unfinished_closed_total{reason=\"cap\"} %llu\n",
            (unsigned long long)g->unfinished_deadline, (unsigned long long)g->unfinished_evicted);
    return t.s;
}
