/* HTTP front end on libmicrohttpd: the daemon, the checks made from the headers
 * alone (query size, body length, token), the dispatch to the routes beside it
 * (http_render.c, http_status.c, http_upgrade.c) and the embedded web client. */
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

#include "auth.h"
#include "conn_limits.h"
#include "http_render.h"
#include "http_respond.h"
#include "http_status.h"
#include "http_upgrade.h"
#include "messages.h"
#include "movies.h"
#include "web_files.h"

#define MOD "http"
#define MAX_QUERY_ARGS 256 /* query parameters of one request (the schema has fewer than 100 keys) */

struct lc_http {
    lc_server *srv;
    struct MHD_Daemon *daemon;
    int port;
    /* The listening socket MHD_quiesce_daemon handed back: closed only after
     * MHD_stop_daemon, since MHD's polling thread still takes it out of its
     * epoll set after the quiesce, and a closed descriptor there is MHD's
     * fatal "Failed to remove listen FD from epoll set" (seen at shutdown). */
    MHD_socket quiesced;
};

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
    return lc_http_error(srv, c, 401, "unauthorized", NULL,
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

/* ---------------------------------------------------------------- the web client */

static enum MHD_Result route_static(lc_server *srv, struct MHD_Connection *c, const char *url)
{
    const char *type;
    char etag[LC_WEB_ETAG_LEN];
    const lc_embedded_file *f = lc_web_file(url, &type, etag);
    if (!f)
        return lc_http_error(srv, c, 404, "not_found", NULL, "no such page: %.300s", url);
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
    return lc_http_queue(srv, c, status, r);
}

/* ---------------------------------------------------------------- dispatch */

static enum MHD_Result route(lc_http_req *ctx, struct MHD_Connection *c, const char *url, const char *method)
{
    lc_server *srv = ctx->srv;
    bool get = strcmp(method, "GET") == 0 || strcmp(method, "HEAD") == 0;
    bool post = strcmp(method, "POST") == 0;
    bool api = strncmp(url, "/api/", 5) == 0 || strcmp(url, "/metrics") == 0;
    if (!api) {
        if (!get)
            return lc_http_not_allowed(srv, c, method, "GET, HEAD");
        return route_static(srv, c, url);
    }
    if (strcmp(url, "/api/v1/health") == 0)
        return get ? lc_http_health(srv, c) : lc_http_not_allowed(srv, c, method, "GET");

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
        return get ? lc_http_upgrade(ctx, c, authed) : lc_http_not_allowed(srv, c, method, "GET");
    if (strcmp(url, "/metrics") == 0)
        return get ? lc_http_metrics(srv, c) : lc_http_not_allowed(srv, c, method, "GET");
    if (strcmp(url, "/api/v1/datasets") == 0)
        return get ? lc_http_datasets(srv, c, NULL) : lc_http_not_allowed(srv, c, method, "GET");
    if (strncmp(url, "/api/v1/datasets/", 17) == 0)
        return get ? lc_http_datasets(srv, c, url + 17) : lc_http_not_allowed(srv, c, method, "GET");
    if (strcmp(url, "/api/v1/schema") == 0) /* the request field table, for clients that validate before sending */
        return get ? lc_http_json(srv, c, 200, lc_proto_schema(&srv->cfg.limits))
                   : lc_http_not_allowed(srv, c, method, "GET");
    if (atomic_load(&srv->stopping) && (post || strcmp(method, "DELETE") == 0))
        return lc_http_error(srv, c, 503, "overloaded", NULL, "the server is shutting down");
    if (strncmp(url, "/api/v1/movies", 14) == 0 && (url[14] == 0 || url[14] == '/'))
        return (enum MHD_Result)lc_movies_answer(srv->movies, c, lc_conn_client_key(c), method, url + 14, ctx->body,
                                                 ctx->len);
    if (strcmp(url, "/api/v1/render") == 0) /* HEAD would cost a whole render for no image */
        return ((get && strcmp(method, "HEAD") != 0) || post) ? lc_http_route_render(ctx, c, method)
                                                              : lc_http_not_allowed(srv, c, method, "GET, POST");
    if (strcmp(url, "/api/v1/sessions") == 0)
        return post ? lc_http_route_session_create(ctx, c) : lc_http_not_allowed(srv, c, method, "POST");
    if (strncmp(url, "/api/v1/sessions/", 17) == 0)
        return lc_http_route_session(ctx, c, method, url + 17);
    return lc_http_error(srv, c, 404, "not_found", NULL, "no such route: %.300s", url);
}

static enum MHD_Result handler(void *cls, struct MHD_Connection *c, const char *url, const char *method,
                               const char *version, const char *upload_data, size_t *upload_data_size, void **con_cls)
{
    (void)version;
    lc_server *srv = cls;
    lc_http_req *ctx = *con_cls;
    if (!ctx)
        return MHD_NO; /* uri_log made it; NULL means out of memory */
    if (!ctx->headers_seen) {
        ctx->headers_seen = true;
        lc_conn_limits_request(c); /* a whole header: no longer held to the header deadline */
        /* Refuse what can be refused from the headers before reading a body
         * or queueing anything: too many query parameters, an ambiguous
         * body length, a missing token, an announced oversized body. */
        if (ctx->query_args > MAX_QUERY_ARGS)
            return lc_http_error(srv, c, 414, LC_PROTO_TOO_LARGE, "query", "%d query parameters exceed the limit of %d",
                                 ctx->query_args, MAX_QUERY_ARGS);
        int lengths = 0;
        MHD_get_connection_values(c, MHD_HEADER_KIND, count_content_length, &lengths);
        if (lengths > 1)
            return lc_http_error(srv, c, 400, LC_PROTO_BAD_FIELD, "Content-Length",
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
                return lc_http_error(srv, c, 413, LC_PROTO_TOO_LARGE, NULL,
                                     "request body of %s bytes exceeds the limit of %zu bytes", cl, srv->cfg.max_body);
        }
        return MHD_YES;
    }
    if (ctx->job) {
        /* Resumed after the worker pool finished (or refused) the render. */
        if (!atomic_load(&ctx->job_finished))
            return MHD_YES;
        return lc_http_finish_render(ctx, c);
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
        return lc_http_error(srv, c, 413, LC_PROTO_TOO_LARGE, NULL, "request body exceeds the limit of %zu bytes",
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
    lc_http_req *ctx = calloc(1, sizeof *ctx);
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
    lc_http_req *ctx = *con_cls;
    if (!ctx)
        return;
    if (toe != MHD_REQUEST_TERMINATED_COMPLETED_OK && ctx->job)
        LC_DEBUG(MOD, "client left before its image was sent (termination %d)", (int)toe);
    lc_http_free_job(ctx->job);
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

/* libmicrohttpd found its own state inconsistent: it cannot go on, but the
 * log says where before the abort (whose stack start/crash.c prints). */
static void mhd_panic(void *cls, const char *file, unsigned int line, const char *reason)
{
    (void)cls;
    LC_ERROR(MOD, "libmicrohttpd panic at %s:%u: %s", file ? file : "?", line, reason ? reason : "no reason given");
    abort();
}

int lc_http_start(lc_server *srv, lc_http **out, int *port_out, lc_error *err)
{
    *out = NULL;
    MHD_set_panic_func(mhd_panic, NULL);
    const lc_serve_config *cfg = &srv->cfg;
    struct sockaddr_storage ss;
    memset(&ss, 0, sizeof ss);
    /* poll(), not epoll (which MHD_USE_AUTO picks on Linux): with epoll and
     * internal threads, MHD_quiesce_daemon (the shutdown's first step)
     * races each worker's own removal of the listening socket from its epoll
     * set, and the loser's epoll_ctl fails and panics (libmicrohttpd 0.9.75:
     * a shutdown aborted with "Failed to remove listen FD from epoll set").
     * Under poll a quiesce is a message to each worker. The daemon holds at
     * most --max-connections HTTP connections (WebSockets move to ws.c's own
     * epoll loop), which poll serves as well. */
    unsigned flags = MHD_USE_INTERNAL_POLLING_THREAD | MHD_USE_POLL | MHD_ALLOW_SUSPEND_RESUME | MHD_ALLOW_UPGRADE |
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
    h->quiesced = MHD_INVALID_SOCKET;
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
    if (h->quiesced == MHD_INVALID_SOCKET)
        h->quiesced = MHD_quiesce_daemon(h->daemon);
}

void lc_http_stop(lc_http *h)
{
    if (!h)
        return;
    if (h->daemon)
        MHD_stop_daemon(h->daemon);
    if (h->quiesced != MHD_INVALID_SOCKET)
        close(h->quiesced);
    free(h);
}
