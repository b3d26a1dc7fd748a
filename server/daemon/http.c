/* HTTP routes on libmicrohttpd: health, datasets, one-shot and session renders,
 * metrics, the WebSocket handshake and the embedded web client. */
#include "http.h"

#include <arpa/inet.h>
#include <errno.h>
#include <math.h>
#include <microhttpd.h>
#include <netinet/in.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <unistd.h>

#include "conn_limits.h"
#include "cost.h"
#include "datasets.h"
#include "frame_headers.h"
#include "messages.h"
#include "metrics.h"
#include "session.h"
#include "web_files.h"
#include "workers.h"
#include "ws.h"

#define MOD "http"
#define MAX_QUERY_ARGS 256 /* query parameters of one request (the schema has fewer than 100 keys) */

struct lc_http {
    lc_server *srv;
    struct MHD_Daemon *daemon;
    int port;
};

/* Per-request state (MHD's con_cls), freed by request_completed. */
typedef struct req_ctx {
    lc_server *srv;
    char *body;
    size_t len, cap;
    bool too_large;
    bool headers_seen; /* the first handler call (headers only) is done */
    int query_args;    /* parameters in the query string (counted before MHD parses them) */
    bool ws_authed;    /* read by the upgrade handler */
    struct MHD_Connection *conn;
    lc_render_job *job;      /* a render in flight or finished */
    atomic_int job_finished; /* set by job_done before the connection resumes */
} req_ctx;

/* ---------------------------------------------------------------- responses */

static enum MHD_Result queue(lc_server *srv, struct MHD_Connection *c, unsigned status, struct MHD_Response *r)
{
    if (!r)
        return MHD_NO;
    enum MHD_Result ret = MHD_queue_response(c, status, r);
    MHD_destroy_response(r);
    lc_metrics_http_request(srv->metrics, (int)status);
    return ret;
}

/* Takes ownership of text (malloc'd). */
static enum MHD_Result respond_text(lc_server *srv, struct MHD_Connection *c, unsigned status, char *text,
                                    const char *type)
{
    if (!text)
        return MHD_NO;
    struct MHD_Response *r = MHD_create_response_from_buffer(strlen(text), text, MHD_RESPMEM_MUST_FREE);
    if (!r) {
        free(text);
        return MHD_NO;
    }
    MHD_add_response_header(r, MHD_HTTP_HEADER_CONTENT_TYPE, type);
    MHD_add_response_header(r, MHD_HTTP_HEADER_CACHE_CONTROL, "no-store");
    return queue(srv, c, status, r);
}

static enum MHD_Result respond_json(lc_server *srv, struct MHD_Connection *c, unsigned status, json_t *obj)
{
    char *text = lc_proto_dump(obj);
    json_decref(obj);
    return respond_text(srv, c, status, text, "application/json");
}

static enum MHD_Result respond_error(lc_server *srv, struct MHD_Connection *c, unsigned status, const char *code,
                                     const char *field, const char *fmt, ...) __attribute__((format(printf, 6, 7)));
static enum MHD_Result respond_error(lc_server *srv, struct MHD_Connection *c, unsigned status, const char *code,
                                     const char *field, const char *fmt, ...)
{
    char msg[768];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    lc_metrics_error(srv->metrics, code);
    char *text = lc_proto_error_json(code, msg, field);
    if (!text)
        return MHD_NO;
    struct MHD_Response *r = MHD_create_response_from_buffer(strlen(text), text, MHD_RESPMEM_MUST_FREE);
    if (!r) {
        free(text);
        return MHD_NO;
    }
    MHD_add_response_header(r, MHD_HTTP_HEADER_CONTENT_TYPE, "application/json");
    MHD_add_response_header(r, MHD_HTTP_HEADER_CACHE_CONTROL, "no-store");
    if (status == 429 || status == 503)
        MHD_add_response_header(r, MHD_HTTP_HEADER_RETRY_AFTER, status == 429 ? "1" : "2");
    if (status == 401)
        MHD_add_response_header(r, MHD_HTTP_HEADER_WWW_AUTHENTICATE, "Bearer realm=\"lucent\"");
    return queue(srv, c, status, r);
}

static enum MHD_Result respond_proto_error(lc_server *srv, struct MHD_Connection *c, const lc_proto_error *pe)
{
    unsigned status = strcmp(pe->code, LC_PROTO_TOO_LARGE) == 0 ? 413 : 400;
    return respond_error(srv, c, status, pe->code, pe->field, "%s", pe->message);
}

static enum MHD_Result method_not_allowed(lc_server *srv, struct MHD_Connection *c, const char *method,
                                          const char *allow)
{
    char msg[128];
    snprintf(msg, sizeof msg, "method %.16s not allowed here (allowed: %s)", method, allow);
    lc_metrics_error(srv->metrics, "method_not_allowed");
    char *text = lc_proto_error_json("method_not_allowed", msg, NULL);
    if (!text)
        return MHD_NO;
    struct MHD_Response *r = MHD_create_response_from_buffer(strlen(text), text, MHD_RESPMEM_MUST_FREE);
    MHD_add_response_header(r, MHD_HTTP_HEADER_CONTENT_TYPE, "application/json");
    MHD_add_response_header(r, MHD_HTTP_HEADER_ALLOW, allow);
    return queue(srv, c, 405, r);
}

/* ---------------------------------------------------------------- auth */

/* The token a request carries (Authorization: Bearer, else ?token=, else a
 * WebSocket token subprotocol decoded into buf), or NULL. */
static const char *given_token(struct MHD_Connection *c, char *buf, size_t n)
{
    const char *auth = MHD_lookup_connection_value(c, MHD_HEADER_KIND, MHD_HTTP_HEADER_AUTHORIZATION);
    if (auth && strncasecmp(auth, "Bearer ", 7) == 0) {
        auth += 7;
        while (*auth == ' ')
            auth++;
        return auth;
    }
    const char *q = MHD_lookup_connection_value(c, MHD_GET_ARGUMENT_KIND, "token");
    if (q)
        return q;
    bool lucent;
    const char *proto = MHD_lookup_connection_value(c, MHD_HEADER_KIND, "Sec-WebSocket-Protocol");
    return lc_serve_subprotocol_token(proto, buf, n, &lucent) ? buf : NULL;
}

/* Whether a request to url needs the token: everything but health and the
 * web client's files. */
static bool needs_token(const lc_server *srv, const char *url)
{
    if (!srv->cfg.token[0] || strcmp(url, "/api/v1/health") == 0)
        return false;
    return strncmp(url, "/api/", 5) == 0 || strcmp(url, "/metrics") == 0;
}

static enum MHD_Result respond_unauthorized(lc_server *srv, struct MHD_Connection *c, bool had_token)
{
    return respond_error(srv, c, 401, "unauthorized", NULL,
                         had_token ? "wrong token"
                                   : "this server needs a token (Authorization: Bearer, ?token= or, for the "
                                     "WebSocket, the subprotocol " LC_SERVE_TOKEN_SUBPROTOCOL "BASE64URL)");
}

/* Counts Content-Length headers (two are refused: which one would frame the body?). */
static enum MHD_Result count_content_length(void *cls, enum MHD_ValueKind kind, const char *key, const char *value)
{
    (void)kind;
    (void)value;
    if (strcasecmp(key, MHD_HTTP_HEADER_CONTENT_LENGTH) == 0)
        (*(int *)cls)++;
    return MHD_YES;
}

/* ---------------------------------------------------------------- simple routes */

static enum MHD_Result route_health(lc_server *srv, struct MHD_Connection *c)
{
    int http = 0, ws = 0;
    lc_sessions_count(srv->sessions, &http, &ws);
    json_t *o = json_object();
    json_object_set_new(o, "status", json_string(atomic_load(&srv->stopping) ? "stopping" : "ok"));
    json_object_set_new(o, "renderer", json_string(srv->gl_renderer));
    json_object_set_new(o, "glVersion", json_string(srv->gl_version));
    json_object_set_new(o, "platform", json_string(srv->gl_platform));
    json_object_set_new(o, "uptime", json_real(lc_now() - srv->start_time));
    json_object_set_new(o, "datasets", json_integer(lc_datasets_count(srv->datasets)));
    json_object_set_new(o, "workers", json_integer(lc_workers_count(srv->workers)));
    json_object_set_new(o, "sessions", json_pack("{s:i, s:i}", "http", http, "ws", ws));
    json_object_set_new(o, "protocolVersion", json_integer(LC_PROTO_VERSION));
    return respond_json(srv, c, 200, o);
}

static enum MHD_Result route_datasets(lc_server *srv, struct MHD_Connection *c, const char *name)
{
    if (name) {
        const lc_dataset *ds = lc_datasets_find(srv->datasets, name);
        if (!ds || !name[0])
            return respond_error(srv, c, 404, "not_found", "dataset", "unknown dataset \"%.300s\"", name);
        return respond_json(srv, c, 200, lc_dataset_info(ds));
    }
    json_t *arr = json_array();
    for (int i = 0; i < lc_datasets_count(srv->datasets); i++)
        json_array_append_new(arr, lc_dataset_info(lc_datasets_at(srv->datasets, i)));
    json_t *o = json_object();
    json_object_set_new(o, "datasets", arr);
    json_object_set_new(o, "memory", lc_datasets_memory_json(srv->datasets));
    return respond_json(srv, c, 200, o);
}

static enum MHD_Result route_metrics(lc_server *srv, struct MHD_Connection *c)
{
    lc_metrics_gauges g = {0};
    lc_sessions_count(srv->sessions, &g.sessions_http, &g.sessions_ws);
    lc_workers_depths(srv->workers, &g.queue_depth, &g.encode_depth);
    g.ws_connections = lc_ws_connections(srv->ws);
    g.datasets = lc_datasets_count(srv->datasets);
    g.workers = lc_workers_count(srv->workers);
    g.queue_clients = lc_workers_clients(srv->workers);
    lc_datasets_budget(srv->datasets, &g.memory_estimated, &g.memory_budget);
    g.resident = lc_memory_resident_bytes();
    return respond_text(srv, c, 200, lc_metrics_render(srv->metrics, &g), "text/plain; version=0.0.4; charset=utf-8");
}

static enum MHD_Result route_static(lc_server *srv, struct MHD_Connection *c, const char *url)
{
    const char *type;
    char etag[LC_WEB_ETAG_LEN];
    const lc_embedded_file *f = lc_web_file(url, &type, etag);
    if (!f)
        return respond_error(srv, c, 404, "not_found", NULL, "no such page: %.300s", url);
    const char *inm = MHD_lookup_connection_value(c, MHD_HEADER_KIND, MHD_HTTP_HEADER_IF_NONE_MATCH);
    struct MHD_Response *r;
    unsigned status = 200;
    if (inm && strstr(inm, etag)) {
        r = MHD_create_response_from_buffer(0, NULL, MHD_RESPMEM_PERSISTENT);
        status = 304;
    } else {
        r = MHD_create_response_from_buffer(f->size, (void *)f->data, MHD_RESPMEM_PERSISTENT);
        MHD_add_response_header(r, MHD_HTTP_HEADER_CONTENT_TYPE, type);
    }
    MHD_add_response_header(r, MHD_HTTP_HEADER_ETAG, etag);
    MHD_add_response_header(r, MHD_HTTP_HEADER_CACHE_CONTROL, "no-cache");
    MHD_add_response_header(r, "X-Content-Type-Options", "nosniff");
    return queue(srv, c, status, r);
}

/* ---------------------------------------------------------------- renders */

/* Called once by the pool (encoder or worker thread) when a job is finished:
 * releases the session for its next frame and resumes the connection, whose
 * handler then sends the image. The pool does not touch the job afterwards. */
static void job_done(lc_render_job *job)
{
    req_ctx *ctx = job->user;
    if (job->session) {
        pthread_mutex_lock(&job->session->lock);
        job->session->http_busy = false;
        if (job->rc == 0)
            job->session->http_frames++;
        pthread_mutex_unlock(&job->session->lock);
    }
    atomic_store(&ctx->job_finished, 1);
    MHD_resume_connection(ctx->conn);
}

static void free_job(lc_render_job *job)
{
    if (!job)
        return;
    free(job->image);
    if (job->session)
        lc_session_unref(job->session);
    free(job);
}

/* The fairness key of a one-shot render: the client's address (not its port,
 * so that many connections of one client still count as one). */
static uint64_t client_key(struct MHD_Connection *c)
{
    const union MHD_ConnectionInfo *ci = MHD_get_connection_info(c, MHD_CONNECTION_INFO_CLIENT_ADDRESS);
    const struct sockaddr *sa = ci ? ci->client_addr : NULL;
    const unsigned char *p = NULL;
    size_t n = 0;
    if (sa && sa->sa_family == AF_INET) {
        p = (const unsigned char *)&((const struct sockaddr_in *)sa)->sin_addr;
        n = 4;
    } else if (sa && sa->sa_family == AF_INET6) {
        p = (const unsigned char *)&((const struct sockaddr_in6 *)sa)->sin6_addr;
        n = 16;
    }
    uint64_t h = 1469598103934665603ULL;
    for (size_t i = 0; i < n; i++)
        h = (h ^ p[i]) * 1099511628211ULL;
    return h | 1; /* never 0, never a session pointer (those are even) */
}

/* Queues a render and suspends the connection until it is done. Takes the
 * session reference (may be NULL); refuses (400, the field named) a request
 * whose estimated cost exceeds --max-cost. */
static enum MHD_Result start_render(req_ctx *ctx, struct MHD_Connection *c, const lc_request *req, const lc_dataset *ds,
                                    lc_session *session, double dt)
{
    lc_server *srv = ctx->srv;
    double cost = 0;
    const char *field = NULL;
    char why[320];
    if (lc_cost_check(&ds->cost, &req->render, srv->cfg.max_cost, &cost, &field, why, sizeof why) != 0) {
        if (session) {
            pthread_mutex_lock(&session->lock);
            session->http_busy = false;
            pthread_mutex_unlock(&session->lock);
            lc_session_unref(session);
        }
        lc_metrics_refused(srv->metrics, "cost");
        return respond_error(srv, c, 400, "too_expensive", field, "%s", why);
    }
    lc_render_job *job = calloc(1, sizeof *job);
    if (!job) {
        if (session)
            lc_session_unref(session);
        return respond_error(srv, c, 503, "overloaded", NULL, "out of memory");
    }
    job->req = *req;
    job->dataset = ds;
    job->session = session;
    job->dt = dt;
    job->cost = cost;
    job->client = client_key(c);
    job->done = job_done;
    job->user = ctx;
    ctx->conn = c;
    ctx->job = job;
    /* Suspend before queueing, so that job_done's resume always follows it. */
    MHD_suspend_connection(c);
    lc_error err = {0};
    int rc = lc_workers_submit(srv->workers, job, &err);
    if (rc != 0) {
        job->rc = rc;
        job->err = err;
        if (session) {
            pthread_mutex_lock(&session->lock);
            session->http_busy = false;
            pthread_mutex_unlock(&session->lock);
        }
        atomic_store(&ctx->job_finished, 1);
        MHD_resume_connection(c);
    }
    return MHD_YES;
}

/* The finished job's response: the image with timing headers, or an error. */
static enum MHD_Result finish_render(req_ctx *ctx, struct MHD_Connection *c)
{
    lc_server *srv = ctx->srv;
    lc_render_job *job = ctx->job;
    if (job->rc != 0) {
        if (job->refused)
            lc_metrics_refused(srv->metrics, job->refused);
        switch (job->rc) {
        case LC_ERR_LIMIT:
            return respond_error(srv, c, job->refused && strcmp(job->refused, "client_queue") == 0 ? 429 : 503,
                                 "overloaded", NULL, "%s", job->err.msg);
        case LC_ERR_UNSUPPORTED:
        case LC_ERR_NOMEM: return respond_error(srv, c, 503, "overloaded", NULL, "%s", job->err.msg);
        case LC_ERR_NOT_FOUND: return respond_error(srv, c, 404, "not_found", NULL, "%s", job->err.msg);
        case LC_ERR_INVALID: /* a value only the renderer can check, e.g. an attribute name */
            return respond_error(srv, c, 400, LC_PROTO_BAD_FIELD, job->err.field[0] ? job->err.field : NULL, "%s",
                                 job->err.msg);
        default: return respond_error(srv, c, 500, "internal", NULL, "render failed: %s", job->err.msg);
        }
    }
    struct MHD_Response *r = MHD_create_response_from_buffer(job->image_size, job->image, MHD_RESPMEM_MUST_FREE);
    if (!r)
        return MHD_NO;
    size_t bytes = job->image_size;
    job->image = NULL; /* MHD frees it now */
    MHD_add_response_header(r, MHD_HTTP_HEADER_CONTENT_TYPE,
                            job->req.format == LC_FORMAT_PNG ? "image/png" : "image/jpeg");
    MHD_add_response_header(r, MHD_HTTP_HEADER_CACHE_CONTROL, "no-store");
    lc_frame_headers_add(r, job);
    lc_metrics_bytes_sent(srv->metrics, bytes);
    return queue(srv, c, 200, r);
}

typedef struct query_state {
    lc_request *req;
    const lc_proto_limits *lim;
    lc_proto_error err;
    int rc;
} query_state;

static enum MHD_Result query_arg(void *cls, enum MHD_ValueKind kind, const char *key, const char *value)
{
    (void)kind;
    query_state *q = cls;
    q->rc = lc_proto_apply_query(q->req, key, value, q->lim, &q->err);
    return q->rc == 0 ? MHD_YES : MHD_NO;
}

static enum MHD_Result route_render(req_ctx *ctx, struct MHD_Connection *c, const char *method)
{
    lc_server *srv = ctx->srv;
    lc_request req;
    lc_proto_error pe;
    if (strcmp(method, "POST") == 0) {
        if (lc_proto_parse_request(ctx->body ? ctx->body : "", ctx->len, &srv->cfg.limits, &req, &pe) != 0)
            return respond_proto_error(srv, c, &pe);
    } else {
        lc_request_default(&req);
        query_state q = {.req = &req, .lim = &srv->cfg.limits};
        MHD_get_connection_values(c, MHD_GET_ARGUMENT_KIND, query_arg, &q);
        if (q.rc != 0)
            return respond_proto_error(srv, c, &q.err);
        if (lc_proto_validate_request(&req, &srv->cfg.limits, &pe) != 0)
            return respond_proto_error(srv, c, &pe);
    }
    const lc_dataset *ds = lc_datasets_find(srv->datasets, req.dataset);
    if (!ds)
        return respond_error(srv, c, 404, "not_found", "dataset", "unknown dataset \"%.300s\"", req.dataset);
    return start_render(ctx, c, &req, ds, NULL, 0.0);
}

static enum MHD_Result route_session_create(req_ctx *ctx, struct MHD_Connection *c)
{
    lc_server *srv = ctx->srv;
    lc_request req;
    lc_proto_error pe;
    if (ctx->len > 0) {
        if (lc_proto_parse_request(ctx->body, ctx->len, &srv->cfg.limits, &req, &pe) != 0)
            return respond_proto_error(srv, c, &pe);
    } else {
        lc_request_default(&req);
    }
    const lc_dataset *ds = lc_datasets_find(srv->datasets, req.dataset);
    if (!ds)
        return respond_error(srv, c, 404, "not_found", "dataset", "unknown dataset \"%.300s\"", req.dataset);
    snprintf(req.dataset, sizeof req.dataset, "%s", ds->name);
    req.has_dt = false;
    lc_session *s = NULL;
    lc_error err = {0};
    if (lc_session_create(srv->sessions, LC_SESSION_HTTP, ds, &req, &s, &err) != 0)
        return respond_error(srv, c, 503, "overloaded", NULL, "%s", err.msg);
    json_t *o = json_object();
    json_object_set_new(o, "session", json_string(s->id));
    json_object_set_new(o, "dataset", lc_dataset_info(ds));
    json_object_set_new(o, "defaults", lc_proto_request_to_json(&req));
    char location[128];
    snprintf(location, sizeof location, "/api/v1/sessions/%s", s->id);
    LC_INFO(MOD, "session %s: scripted, %s", s->id, ds->name);
    lc_session_unref(s);
    char *text = lc_proto_dump(o);
    json_decref(o);
    if (!text)
        return MHD_NO;
    struct MHD_Response *r = MHD_create_response_from_buffer(strlen(text), text, MHD_RESPMEM_MUST_FREE);
    MHD_add_response_header(r, MHD_HTTP_HEADER_CONTENT_TYPE, "application/json");
    MHD_add_response_header(r, MHD_HTTP_HEADER_LOCATION, location);
    return queue(srv, c, 201, r);
}

static enum MHD_Result route_session_render(req_ctx *ctx, struct MHD_Connection *c, lc_session *s)
{
    lc_server *srv = ctx->srv;
    lc_proto_error pe;
    json_t *update = NULL;
    if (ctx->len > 0) {
        update = lc_proto_load(ctx->body, ctx->len, &srv->cfg.limits, &pe);
        if (!update) {
            lc_session_unref(s);
            return respond_proto_error(srv, c, &pe);
        }
        if (!json_is_object(update)) {
            json_decref(update);
            lc_session_unref(s);
            return respond_error(srv, c, 400, LC_PROTO_BAD_FIELD, "", "expected a JSON object");
        }
    }
    pthread_mutex_lock(&s->lock);
    if (s->http_busy) {
        pthread_mutex_unlock(&s->lock);
        json_decref(update);
        lc_session_unref(s);
        return respond_error(srv, c, 429, "overloaded", NULL,
                             "session %s is rendering a frame; send the next one after it", s->id);
    }
    lc_request req = s->req;
    req.has_dt = false;
    int rc = update ? lc_proto_apply_request(update, &srv->cfg.limits, &req, &pe) : 0;
    json_decref(update);
    if (rc == 0 && strcmp(req.dataset, s->dataset->name) != 0 &&
        lc_datasets_find(srv->datasets, req.dataset) != s->dataset) {
        rc = lc_proto_set_error(&pe, LC_PROTO_BAD_FIELD, "dataset", "cannot change within a session (it is \"%s\")",
                                s->dataset->name);
    }
    if (rc != 0) {
        pthread_mutex_unlock(&s->lock);
        lc_session_unref(s);
        return respond_proto_error(srv, c, &pe);
    }
    /* Without dt the frame shows the targets, as a one-shot render would
     * (openapi.yaml): a dt far beyond any half-life completes the fade. */
    double dt = req.has_dt ? req.dt : 1e6;
    s->req = req;
    s->req.has_dt = false;
    s->http_busy = true;
    s->last_frame_time = lc_now();
    pthread_mutex_unlock(&s->lock);
    return start_render(ctx, c, &req, s->dataset, s, dt);
}

static enum MHD_Result route_session(req_ctx *ctx, struct MHD_Connection *c, const char *method, const char *rest)
{
    lc_server *srv = ctx->srv;
    char id[LC_SESSION_ID_LEN + 1];
    size_t n = strcspn(rest, "/");
    const char *tail = rest + n;
    if (n == 0 || n >= sizeof id)
        return respond_error(srv, c, 404, "not_found", NULL, "unknown session \"%.*s\"", (int)(n > 64 ? 64 : n), rest);
    memcpy(id, rest, n);
    id[n] = '\0';
    bool render = strcmp(tail, "/render") == 0;
    if (!render && tail[0])
        return respond_error(srv, c, 404, "not_found", NULL, "no such route");
    if (render && strcmp(method, "POST") != 0)
        return method_not_allowed(srv, c, method, "POST");
    if (!render && strcmp(method, "DELETE") != 0 && strcmp(method, "GET") != 0)
        return method_not_allowed(srv, c, method, "GET, DELETE");
    lc_session *s = lc_session_find(srv->sessions, id, LC_SESSION_HTTP);
    if (!s)
        return respond_error(srv, c, 404, "not_found", NULL, "unknown session \"%s\"", id);
    if (render)
        return route_session_render(ctx, c, s);
    if (strcmp(method, "DELETE") == 0) {
        lc_session_close(srv->sessions, s);
        LC_INFO(MOD, "session %s: deleted after %llu frames", s->id, (unsigned long long)s->http_frames);
        lc_session_unref(s);
        struct MHD_Response *r = MHD_create_response_from_buffer(0, NULL, MHD_RESPMEM_PERSISTENT);
        return queue(srv, c, 204, r);
    }
    pthread_mutex_lock(&s->lock);
    json_t *o = json_object();
    json_object_set_new(o, "session", json_string(s->id));
    json_object_set_new(o, "dataset", json_string(s->dataset->name));
    json_object_set_new(o, "frames", json_integer((json_int_t)s->http_frames));
    json_object_set_new(o, "request", lc_proto_request_to_json(&s->req));
    pthread_mutex_unlock(&s->lock);
    lc_session_unref(s);
    return respond_json(srv, c, 200, o);
}

/* ---------------------------------------------------------------- WebSocket */

static void upgrade_handler(void *cls, struct MHD_Connection *connection, void *con_cls, const char *extra_in,
                            size_t extra_in_size, MHD_socket sock, struct MHD_UpgradeResponseHandle *urh)
{
    (void)connection;
    lc_server *srv = cls;
    req_ctx *ctx = con_cls;
    lc_ws_adopt(srv->ws, sock, urh, extra_in, extra_in_size, ctx && ctx->ws_authed);
}

static bool header_has_token(const char *value, const char *token)
{
    /* Comma-separated, case-insensitive ("keep-alive, Upgrade"). */
    size_t n = strlen(token);
    for (const char *p = value; p && *p;) {
        while (*p == ' ' || *p == ',')
            p++;
        if (strncasecmp(p, token, n) == 0 && (p[n] == '\0' || p[n] == ',' || p[n] == ' '))
            return true;
        p = strchr(p, ',');
    }
    return false;
}

static enum MHD_Result route_ws(req_ctx *ctx, struct MHD_Connection *c, bool authed)
{
    lc_server *srv = ctx->srv;
    const char *upgrade = MHD_lookup_connection_value(c, MHD_HEADER_KIND, MHD_HTTP_HEADER_UPGRADE);
    const char *connection = MHD_lookup_connection_value(c, MHD_HEADER_KIND, MHD_HTTP_HEADER_CONNECTION);
    const char *key = MHD_lookup_connection_value(c, MHD_HEADER_KIND, "Sec-WebSocket-Key");
    const char *version = MHD_lookup_connection_value(c, MHD_HEADER_KIND, "Sec-WebSocket-Version");
    if (!upgrade || !header_has_token(upgrade, "websocket") || !connection || !header_has_token(connection, "upgrade"))
        return respond_error(srv, c, 400, "bad_field", "Upgrade",
                             "expected a WebSocket upgrade (Connection: Upgrade, Upgrade: websocket)");
    if (!key || strlen(key) != 24)
        return respond_error(srv, c, 400, "bad_field", "Sec-WebSocket-Key", "missing or malformed Sec-WebSocket-Key");
    if (!version || strcmp(version, "13") != 0) {
        lc_metrics_error(srv->metrics, "bad_field");
        char *text =
            lc_proto_error_json("bad_field", "only WebSocket version 13 is supported", "Sec-WebSocket-Version");
        struct MHD_Response *r = MHD_create_response_from_buffer(strlen(text), text, MHD_RESPMEM_MUST_FREE);
        MHD_add_response_header(r, MHD_HTTP_HEADER_CONTENT_TYPE, "application/json");
        MHD_add_response_header(r, "Sec-WebSocket-Version", "13");
        return queue(srv, c, 426, r);
    }
    if (atomic_load(&srv->stopping))
        return respond_error(srv, c, 503, "overloaded", NULL, "the server is shutting down");
    int http = 0, ws = 0;
    lc_sessions_count(srv->sessions, &http, &ws);
    if (http + ws >= srv->cfg.max_sessions)
        return respond_error(srv, c, 503, "overloaded", NULL, "too many sessions (the limit is %d)",
                             srv->cfg.max_sessions);
    char accept[LC_SERVE_WS_ACCEPT_LEN];
    lc_serve_ws_accept_key(key, accept);
    struct MHD_Response *r = MHD_create_response_for_upgrade(upgrade_handler, srv);
    if (!r)
        return MHD_NO;
    MHD_add_response_header(r, MHD_HTTP_HEADER_UPGRADE, "websocket");
    MHD_add_response_header(r, MHD_HTTP_HEADER_CONNECTION, "Upgrade");
    MHD_add_response_header(r, "Sec-WebSocket-Accept", accept);
    /* A client that offers subprotocols must get one back (browsers fail the
     * handshake otherwise); never echo the one that carries the token. */
    char unused[LC_PROTO_TOKEN_LEN];
    bool lucent = false;
    lc_serve_subprotocol_token(MHD_lookup_connection_value(c, MHD_HEADER_KIND, "Sec-WebSocket-Protocol"), unused,
                               sizeof unused, &lucent);
    if (lucent)
        MHD_add_response_header(r, "Sec-WebSocket-Protocol", LC_SERVE_SUBPROTOCOL);
    ctx->ws_authed = authed;
    return queue(srv, c, MHD_HTTP_SWITCHING_PROTOCOLS, r);
}

/* ---------------------------------------------------------------- dispatch */

static enum MHD_Result route(req_ctx *ctx, struct MHD_Connection *c, const char *url, const char *method)
{
    lc_server *srv = ctx->srv;
    bool get = strcmp(method, "GET") == 0 || strcmp(method, "HEAD") == 0;
    bool post = strcmp(method, "POST") == 0;
    bool api = strncmp(url, "/api/", 5) == 0 || strcmp(url, "/metrics") == 0;
    if (!api) {
        if (!get)
            return method_not_allowed(srv, c, method, "GET, HEAD");
        return route_static(srv, c, url);
    }
    if (strcmp(url, "/api/v1/health") == 0)
        return get ? route_health(srv, c) : method_not_allowed(srv, c, method, "GET");

    /* Everything else needs the token when one is configured, the WebSocket
     * included: an upgrade without it would hold a connection slot (the
     * handler refused it before reading a body; this is the same check). */
    char buf[LC_PROTO_TOKEN_LEN];
    const char *token = given_token(c, buf, sizeof buf);
    bool authed = lc_serve_token_ok(srv, token ? token : "");
    bool is_ws = strcmp(url, "/api/v1/ws") == 0;
    if (!authed)
        return respond_unauthorized(srv, c, token != NULL);

    if (is_ws)
        return get ? route_ws(ctx, c, authed) : method_not_allowed(srv, c, method, "GET");
    if (strcmp(url, "/metrics") == 0)
        return get ? route_metrics(srv, c) : method_not_allowed(srv, c, method, "GET");
    if (strcmp(url, "/api/v1/datasets") == 0)
        return get ? route_datasets(srv, c, NULL) : method_not_allowed(srv, c, method, "GET");
    if (strncmp(url, "/api/v1/datasets/", 17) == 0)
        return get ? route_datasets(srv, c, url + 17) : method_not_allowed(srv, c, method, "GET");
    if (atomic_load(&srv->stopping) && (post || strcmp(method, "DELETE") == 0))
        return respond_error(srv, c, 503, "overloaded", NULL, "the server is shutting down");
    if (strcmp(url, "/api/v1/render") == 0) /* HEAD would cost a whole render for no image */
        return ((get && strcmp(method, "HEAD") != 0) || post) ? route_render(ctx, c, method)
                                                              : method_not_allowed(srv, c, method, "GET, POST");
    if (strcmp(url, "/api/v1/sessions") == 0)
        return post ? route_session_create(ctx, c) : method_not_allowed(srv, c, method, "POST");
    if (strncmp(url, "/api/v1/sessions/", 17) == 0)
        return route_session(ctx, c, method, url + 17);
    return respond_error(srv, c, 404, "not_found", NULL, "no such route: %.300s", url);
}

static enum MHD_Result handler(void *cls, struct MHD_Connection *c, const char *url, const char *method,
                               const char *version, const char *upload_data, size_t *upload_data_size, void **con_cls)
{
    (void)version;
    lc_server *srv = cls;
    req_ctx *ctx = *con_cls;
    if (!ctx)
        return MHD_NO; /* uri_log made it; NULL means out of memory */
    if (!ctx->headers_seen) {
        ctx->headers_seen = true;
        lc_conn_limits_request(c); /* a whole header: no longer held to the header deadline */
        /* Refuse what can be refused from the headers before reading a body
         * or queueing anything: too many query parameters, an ambiguous
         * body length, a missing token, an announced oversized body. */
        if (ctx->query_args > MAX_QUERY_ARGS)
            return respond_error(srv, c, 414, LC_PROTO_TOO_LARGE, "query", "%d query parameters exceed the limit of %d",
                                 ctx->query_args, MAX_QUERY_ARGS);
        int lengths = 0;
        MHD_get_connection_values(c, MHD_HEADER_KIND, count_content_length, &lengths);
        if (lengths > 1)
            return respond_error(srv, c, 400, LC_PROTO_BAD_FIELD, "Content-Length",
                                 "%d Content-Length headers; send one", lengths);
        if (needs_token(srv, url)) {
            char buf[LC_PROTO_TOKEN_LEN];
            const char *token = given_token(c, buf, sizeof buf);
            if (!lc_serve_token_ok(srv, token ? token : ""))
                return respond_unauthorized(srv, c, token != NULL);
        }
        const char *cl = MHD_lookup_connection_value(c, MHD_HEADER_KIND, MHD_HTTP_HEADER_CONTENT_LENGTH);
        if (cl) {
            char *end;
            errno = 0;
            unsigned long long n = strtoull(cl, &end, 10);
            if (errno || *end || n > srv->cfg.max_body)
                return respond_error(srv, c, 413, LC_PROTO_TOO_LARGE, NULL,
                                     "request body of %s bytes exceeds the limit of %zu bytes", cl, srv->cfg.max_body);
        }
        return MHD_YES;
    }
    if (ctx->job) {
        /* Resumed after the worker pool finished (or refused) the render. */
        if (!atomic_load(&ctx->job_finished))
            return MHD_YES;
        return finish_render(ctx, c);
    }
    if (*upload_data_size > 0) {
        size_t n = *upload_data_size;
        *upload_data_size = 0;
        if (ctx->too_large || ctx->len + n > srv->cfg.max_body) {
            ctx->too_large = true; /* keep reading (and dropping) so the 413 can be sent */
            return MHD_YES;
        }
        if (ctx->len + n + 1 > ctx->cap) {
            size_t cap = ctx->cap ? ctx->cap : 1024;
            while (cap < ctx->len + n + 1)
                cap *= 2;
            char *b = realloc(ctx->body, cap);
            if (!b)
                return MHD_NO;
            ctx->body = b;
            ctx->cap = cap;
        }
        memcpy(ctx->body + ctx->len, upload_data, n);
        ctx->len += n;
        ctx->body[ctx->len] = '\0';
        return MHD_YES;
    }
    if (ctx->too_large)
        return respond_error(srv, c, 413, LC_PROTO_TOO_LARGE, NULL, "request body exceeds the limit of %zu bytes",
                             srv->cfg.max_body);
    return route(ctx, c, url, method);
}

/* Called by MHD with the raw request URI before it parses the query; what it
 * returns becomes the request's con_cls. MHD keeps every query parameter in
 * the connection's fixed memory pool, and when the pool runs out (about 1000
 * short parameters in 64 KiB) libmicrohttpd 0.9.75 neither answers nor closes
 * until the connection timeout. So parameters beyond MAX_QUERY_ARGS are
 * counted here and the query is cut off in MHD's own buffer (the URI is
 * writable there; MHD parses the query only after this call), and the handler
 * answers 414. */
static void *uri_log(void *cls, const char *uri, struct MHD_Connection *c)
{
    (void)c;
    req_ctx *ctx = calloc(1, sizeof *ctx);
    if (!ctx)
        return NULL;
    ctx->srv = cls;
    char *q = strchr(uri, '?');
    if (q) {
        int args = 1;
        for (const char *p = q + 1; *p; p++)
            args += *p == '&' || *p == ';';
        ctx->query_args = args;
        if (args > MAX_QUERY_ARGS)
            q[1] = '\0';
    }
    return ctx;
}

static void request_completed(void *cls, struct MHD_Connection *c, void **con_cls, enum MHD_RequestTerminationCode toe)
{
    (void)cls;
    (void)c;
    req_ctx *ctx = *con_cls;
    if (!ctx)
        return;
    if (toe != MHD_REQUEST_TERMINATED_COMPLETED_OK && ctx->job)
        LC_DEBUG(MOD, "client left before its image was sent (termination %d)", (int)toe);
    free_job(ctx->job);
    free(ctx->body);
    free(ctx);
    *con_cls = NULL;
}

static void mhd_log(void *cls, const char *fmt, va_list ap)
{
    (void)cls;
    char msg[512];
    vsnprintf(msg, sizeof msg, fmt, ap);
    size_t n = strlen(msg);
    while (n > 0 && (msg[n - 1] == '\n' || msg[n - 1] == '\r'))
        msg[--n] = '\0';
    LC_DEBUG(MOD, "libmicrohttpd: %s", msg);
}

int lc_http_start(lc_server *srv, lc_http **out, int *port_out, lc_error *err)
{
    *out = NULL;
    const lc_serve_config *cfg = &srv->cfg;
    struct sockaddr_storage ss;
    memset(&ss, 0, sizeof ss);
    unsigned flags = MHD_USE_INTERNAL_POLLING_THREAD | MHD_USE_AUTO | MHD_ALLOW_SUSPEND_RESUME | MHD_ALLOW_UPGRADE |
                     MHD_USE_ERROR_LOG;
    if (strchr(cfg->listen_host, ':')) {
        struct sockaddr_in6 *a = (struct sockaddr_in6 *)&ss;
        a->sin6_family = AF_INET6;
        a->sin6_port = htons((uint16_t)cfg->port);
        if (inet_pton(AF_INET6, cfg->listen_host, &a->sin6_addr) != 1)
            return lc_err(err, LC_ERR_INVALID, "--listen: \"%s\" is not an IPv6 address", cfg->listen_host);
        flags |= MHD_USE_IPv6;
    } else {
        struct sockaddr_in *a = (struct sockaddr_in *)&ss;
        a->sin_family = AF_INET;
        a->sin_port = htons((uint16_t)cfg->port);
        const char *host = strcmp(cfg->listen_host, "localhost") == 0 ? "127.0.0.1" : cfg->listen_host;
        if (inet_pton(AF_INET, host, &a->sin_addr) != 1)
            return lc_err(err, LC_ERR_INVALID, "--listen: \"%s\" is not an IPv4 address", cfg->listen_host);
    }
    lc_http *h = calloc(1, sizeof *h);
    if (!h)
        return lc_err(err, LC_ERR_NOMEM, "out of memory");
    h->srv = srv;
    h->daemon = MHD_start_daemon(
        flags, 0, NULL, NULL, handler, srv, MHD_OPTION_SOCK_ADDR, (struct sockaddr *)&ss, MHD_OPTION_NOTIFY_COMPLETED,
        request_completed, srv, MHD_OPTION_URI_LOG_CALLBACK, uri_log, srv, MHD_OPTION_THREAD_POOL_SIZE, (unsigned)2,
        MHD_OPTION_CONNECTION_LIMIT, (unsigned)cfg->max_connections, MHD_OPTION_CONNECTION_TIMEOUT, (unsigned)30,
        MHD_OPTION_CONNECTION_MEMORY_LIMIT, (size_t)(64 * 1024), MHD_OPTION_EXTERNAL_LOGGER, mhd_log, NULL,
        MHD_OPTION_NOTIFY_CONNECTION, lc_conn_limits_notify, NULL, MHD_OPTION_END);
    if (!h->daemon) {
        int e = errno;
        free(h);
        return lc_err(err, LC_ERR_IO, "cannot listen on %s:%d: %s", cfg->listen_host, cfg->port,
                      e ? strerror(e) : "libmicrohttpd failed to start");
    }
    const union MHD_DaemonInfo *info = MHD_get_daemon_info(h->daemon, MHD_DAEMON_INFO_BIND_PORT);
    h->port = info ? info->port : cfg->port;
    *port_out = h->port;
    *out = h;
    return 0;
}

void lc_http_quiesce(lc_http *h)
{
    if (!h || !h->daemon)
        return;
    MHD_socket s = MHD_quiesce_daemon(h->daemon);
    if (s != MHD_INVALID_SOCKET)
        close(s);
}

void lc_http_stop(lc_http *h)
{
    if (!h)
        return;
    if (h->daemon)
        MHD_stop_daemon(h->daemon);
    free(h);
}
