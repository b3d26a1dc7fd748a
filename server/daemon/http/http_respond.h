/* HTTP responses, and the per-request state that the route files share
 * (http.c dispatches, http_render.c renders). Thread: MHD's. */
#ifndef LC_SERVER_HTTP_RESPOND_H
#define LC_SERVER_HTTP_RESPOND_H

#include <microhttpd.h>
#include <stdatomic.h>
#include <stdbool.h>
#include <stddef.h>

#include "server.h"

struct lc_render_job;

/* Per-request state (MHD's con_cls), freed by request_completed. */
typedef struct lc_http_req {
    lc_server *srv;
    char *body;
    size_t len, cap;
    bool too_large;
    bool headers_seen; /* the first handler call (headers only) is done */
    int query_args;    /* parameters in the query string (counted before MHD parses them) */
    bool ws_authed;    /* read by the upgrade handler */
    struct MHD_Connection *conn;
    struct lc_render_job *job; /* a render in flight or finished */
    atomic_int job_finished;   /* set by job_done before the connection resumes */
    struct lc_traced *traced;  /* a one-shot render's streamline set until its job takes it (traced.h) */
} lc_http_req;

/* Queues response r with status and releases it; counts the status. */
enum MHD_Result lc_http_queue(lc_server *srv, struct MHD_Connection *c, unsigned status, struct MHD_Response *r);
/* A text body (takes text, malloc'd) of the given content type. */
enum MHD_Result lc_http_text(lc_server *srv, struct MHD_Connection *c, unsigned status, char *text,
                             const char *content_type);
/* A JSON body (takes obj). */
enum MHD_Result lc_http_json(lc_server *srv, struct MHD_Connection *c, unsigned status, json_t *obj);
/* An error body {error: {code, message, field}} (protocol/openapi.yaml), counted
 * in the metrics; 429 and 503 say when to retry, 401 how to authenticate. */
enum MHD_Result lc_http_error(lc_server *srv, struct MHD_Connection *c, unsigned status, const char *code,
                              const char *field, const char *fmt, ...) __attribute__((format(printf, 6, 7)));
/* A request the protocol refused: 413 when too large, else 400, naming the field. */
enum MHD_Result lc_http_proto_error(lc_server *srv, struct MHD_Connection *c, const lc_proto_error *pe);
/* 405 with the methods allowed. */
enum MHD_Result lc_http_not_allowed(lc_server *srv, struct MHD_Connection *c, const char *method, const char *allow);

#endif
