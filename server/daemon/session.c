/* Sessions: the registry, a viewer's request and its one update function, its element opacities. */
#include "session.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/random.h>

#include "admit.h"
#include "datasets.h"
#include "detail_ladder.h"
#include "memory.h"
#include "traced.h"

#define MOD "session"

struct lc_sessions {
    lc_server *srv;
    pthread_mutex_t lock;
    int max;
    int count;
    lc_session **items; /* max entries; open sessions, each holding the registry's reference */
};

lc_sessions *lc_sessions_create(lc_server *srv, int max_sessions)
{
    lc_sessions *reg = calloc(1, sizeof *reg);
    if (!reg)
        return NULL;
    reg->srv = srv;
    reg->max = max_sessions > 0 ? max_sessions : 1;
    reg->items = calloc((size_t)reg->max, sizeof *reg->items);
    if (!reg->items) {
        free(reg);
        return NULL;
    }
    pthread_mutex_init(&reg->lock, NULL);
    return reg;
}

void lc_sessions_destroy(lc_sessions *reg)
{
    if (!reg)
        return;
    for (;;) {
        pthread_mutex_lock(&reg->lock);
        lc_session *s = reg->count ? reg->items[0] : NULL;
        if (s)
            lc_session_ref(s);
        pthread_mutex_unlock(&reg->lock);
        if (!s)
            break;
        lc_session_close(reg, s);
        lc_session_unref(s);
    }
    pthread_mutex_destroy(&reg->lock);
    free(reg->items);
    free(reg);
}

static void random_id(char out[LC_SESSION_ID_LEN])
{
    unsigned char b[16];
    if (getrandom(b, sizeof b, 0) != (ssize_t)sizeof b) {
        /* getrandom on Linux does not fail for 16 bytes once the pool is up;
         * fall back to a clock mix rather than refusing the session. */
        double t = lc_now();
        for (size_t i = 0; i < sizeof b; i++)
            b[i] = (unsigned char)((uint64_t)(t * 1e9) >> (i % 8 * 8)) ^ (unsigned char)(i * 37);
    }
    for (size_t i = 0; i < sizeof b; i++)
        snprintf(out + 2 * i, 3, "%02x", b[i]);
}

int lc_session_create(lc_sessions *reg, lc_session_kind kind, uint64_t client, const lc_dataset *ds,
                      const lc_request *initial, lc_session **out, lc_error *err)
{
    *out = NULL;
    lc_session *s = calloc(1, sizeof *s);
    if (!s)
        return lc_err(err, LC_ERR_NOMEM, "out of memory");
    s->dataset = ds;
    /* The callers resolved the layers' datasets already (lc_admit_resolve_layers). */
    for (int i = 0; i < lc_request_layer_count(initial); i++)
        s->layer_ds[i] = lc_datasets_find(reg->srv->datasets, initial->layers->dataset[i]);
    s->state_layers = -1; /* no state yet */
    int rc = lc_session_prepare_state(s, s->layer_ds, lc_request_layer_count(initial), err);
    if (rc != 0) {
        free(s);
        return rc;
    }
    random_id(s->id);
    s->kind = kind;
    s->client = client;
    s->dataset = ds;
    s->srv = reg->srv;
    atomic_init(&s->refs, 2); /* registry + caller */
    atomic_init(&s->progress.stage, LC_PROGRESS_NONE);
    pthread_mutex_init(&s->lock, NULL);
    s->created = s->last_used = lc_now();
    lc_request_copy(&s->req, initial);
    lc_stream_flow_init(&s->stream.flow, LC_PROTO_DEFAULT_WINDOW);
    s->stream.window = s->stream.flow.window;
    s->stream.quality = LC_PROTO_DEFAULT_QUALITY;
    s->stream.interactive_quality = LC_PROTO_DEFAULT_INTERACTIVE_QUALITY;
    s->stream.interactive_scale = LC_PROTO_DEFAULT_INTERACTIVE_SCALE;
    s->stream.detail_step = LC_DETAIL_START;
    s->stream.device_pixel_ratio = 1.0;
    s->stream.next_frame = 1;
    s->stream.converged = true;

    pthread_mutex_lock(&reg->lock);
    int mine = 0, cap = reg->srv->cfg.max_client_sessions > 0 ? reg->srv->cfg.max_client_sessions : reg->max;
    for (int i = 0; client && i < reg->count; i++)
        mine += reg->items[i]->client == client;
    if (reg->count >= reg->max || mine >= cap) {
        pthread_mutex_unlock(&reg->lock);
        lc_frame_state_destroy(s->frame_state);
        pthread_mutex_destroy(&s->lock);
        lc_request_release(&s->req);
        free(s);
        if (mine >= cap) /* field "client": the caller's own share, not the server's */
            return lc_err_field(err, LC_ERR_LIMIT, "client",
                                "this client has %d sessions open (--max-sessions-per-client %d); close one", mine,
                                cap);
        return lc_err(err, LC_ERR_LIMIT, "too many sessions (%d open, the limit is %d)", reg->max, reg->max);
    }
    reg->items[reg->count++] = s;
    pthread_mutex_unlock(&reg->lock);
    LC_DEBUG(MOD, "session %s opened (%s, %s)", s->id, kind == LC_SESSION_WS ? "ws" : "http", ds->name);
    *out = s;
    return 0;
}

lc_session *lc_session_find(lc_sessions *reg, const char *id, lc_session_kind kind)
{
    lc_session *found = NULL;
    pthread_mutex_lock(&reg->lock);
    for (int i = 0; i < reg->count; i++) {
        lc_session *s = reg->items[i];
        if (s->kind == kind && strcmp(s->id, id) == 0) {
            lc_session_ref(s);
            found = s;
            break;
        }
    }
    pthread_mutex_unlock(&reg->lock);
    if (found) {
        pthread_mutex_lock(&found->lock);
        found->last_used = lc_now();
        pthread_mutex_unlock(&found->lock);
    }
    return found;
}

void lc_session_close(lc_sessions *reg, lc_session *s)
{
    int removed = 0;
    pthread_mutex_lock(&reg->lock);
    for (int i = 0; i < reg->count; i++) {
        if (reg->items[i] == s) {
            reg->items[i] = reg->items[--reg->count];
            removed = 1;
            break;
        }
    }
    pthread_mutex_unlock(&reg->lock);
    pthread_mutex_lock(&s->lock);
    s->closed = true;
    pthread_mutex_unlock(&s->lock);
    if (removed) {
        LC_DEBUG(MOD, "session %s closed", s->id);
        lc_session_unref(s);
    }
}

void lc_session_ref(lc_session *s) { atomic_fetch_add(&s->refs, 1); }

void lc_session_unref(lc_session *s)
{
    if (!s || atomic_fetch_sub(&s->refs, 1) != 1)
        return;
    lc_frame_state_destroy(s->frame_state);
    if (s->surface_free)
        s->surface_free(s->surface);
    lc_traced_free(s->traced);
    lc_request_release(&s->req);
    pthread_mutex_destroy(&s->lock);
    free(s);
    /* A session's frames were built on several threads' heaps; hand what they
     * leave free back to the system now rather than at the next large frame. */
    lc_memory_trim();
}

void lc_sessions_count(lc_sessions *reg, int *http, int *ws)
{
    int h = 0, w = 0;
    pthread_mutex_lock(&reg->lock);
    for (int i = 0; i < reg->count; i++)
        if (reg->items[i]->kind == LC_SESSION_WS)
            w++;
        else
            h++;
    pthread_mutex_unlock(&reg->lock);
    if (http)
        *http = h;
    if (ws)
        *ws = w;
}

int lc_sessions_sweep(lc_sessions *reg, double now, double idle)
{
    int closed = 0;
    for (;;) {
        lc_session *victim = NULL;
        pthread_mutex_lock(&reg->lock);
        for (int i = 0; i < reg->count && !victim; i++) {
            lc_session *s = reg->items[i];
            if (s->kind != LC_SESSION_HTTP)
                continue; /* WebSocket connections time out on the I/O thread */
            pthread_mutex_lock(&s->lock);
            if (!s->http_busy && now - s->last_used > idle)
                victim = s;
            pthread_mutex_unlock(&s->lock);
        }
        if (victim)
            lc_session_ref(victim);
        pthread_mutex_unlock(&reg->lock);
        if (!victim)
            return closed;
        LC_INFO(MOD, "session %s idle for more than %.0f s, closed", victim->id, idle);
        lc_session_close(reg, victim);
        lc_session_unref(victim);
        closed++;
    }
}

int lc_session_prepare_state(lc_session *s, const lc_dataset *const *layers, int n, lc_error *err)
{
    if (n == s->state_layers && memcmp(layers, s->state_ds, (size_t)n * sizeof *layers) == 0)
        return 0;
    /* Compact opacities unless every dataset keeps exact ones (--exact-positions). */
    uint64_t count = n ? 0 : s->dataset->scene->elements.count;
    int exact = n ? 1 : s->dataset->exact_positions;
    for (int i = 0; i < n; i++)
        count += layers[i]->scene->elements.count, exact &= layers[i]->exact_positions;
    if (count > UINT32_MAX) /* the renderer refuses such layers itself, naming them */
        count = 0;
    lc_frame_state *st =
        exact ? lc_frame_state_create((uint32_t)count) : lc_frame_state_create_compact((uint32_t)count);
    if (!st)
        return lc_err(err, LC_ERR_NOMEM, "out of memory for %llu element opacities", (unsigned long long)count);
    lc_frame_state_destroy(s->frame_state);
    s->frame_state = st;
    memcpy(s->state_ds, layers, (size_t)n * sizeof *layers);
    s->state_layers = n;
    return 0;
}

int lc_session_kind_check(lc_session_kind kind, const lc_request *req, lc_proto_error *pe)
{
    if (kind != LC_SESSION_HTTP || req->render.method != LC_METHOD_SURFACE_LAYERS)
        return 0;
    return lc_proto_set_error(pe, LC_PROTO_BAD_FIELD, "method",
                              "HTTP sessions do not render surface-layers; POST /api/v1/render draws it in one "
                              "request, a WebSocket session streams it");
}

int lc_session_update_locked(lc_session *s, const lc_request_patch *patch, const lc_proto_limits *lim, lc_request *out,
                             lc_proto_error *pe)
{
    const lc_dataset *layers[LC_MAX_LAYERS], *ds = s->dataset;
    lc_request req; /* the candidate; its layers are shared with s->req or the patch */
    int rc = lc_admit_update(s->srv, &s->req, patch, lim, &ds, &req, layers, NULL, pe);
    if (rc == 0)
        rc = lc_session_kind_check(s->kind, &req, pe);
    if (rc == 0) { /* every rule passed: the candidate replaces the request whole */
        lc_request_release(&s->req);
        s->req = req; /* takes over req's reference */
        memcpy(s->layer_ds, layers, (size_t)lc_request_layer_count(&req) * sizeof *layers);
        if (out)
            lc_request_copy(out, &s->req);
    } else {
        lc_request_release(&req);
    }
    return rc;
}
