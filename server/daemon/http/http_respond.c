/* HTTP responses: JSON and text bodies, errors that name the field (http_respond.h). */
#include "http_respond.h"

#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "messages.h"
#include "metrics.h"

enum MHD_Result lc_http_queue(lc_server *srv, struct MHD_Connection *c, unsigned status, struct MHD_Response *r)
{
    if (!r)
        return MHD_NO;
    enum MHD_Result ret = MHD_queue_response(c, status, r);
    MHD_destroy_response(r);
    lc_metrics_http_request(srv->metrics, (int)status);
    return ret;
}

/* Takes ownership of text (malloc'd). */
enum MHD_Result lc_http_text(lc_server *srv, struct MHD_Connection *c, unsigned status, char *text, const char *type)
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
    return lc_http_queue(srv, c, status, r);
}

enum MHD_Result lc_http_json(lc_server *srv, struct MHD_Connection *c, unsigned status, json_t *obj)
{
    char *text = lc_proto_dump(obj);
    json_decref(obj);
    return lc_http_text(srv, c, status, text, "application/json");
}

enum MHD_Result lc_http_error(lc_server *srv, struct MHD_Connection *c, unsigned status, const char *code,
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
    return lc_http_queue(srv, c, status, r);
}

enum MHD_Result lc_http_proto_error(lc_server *srv, struct MHD_Connection *c, const lc_proto_error *pe)
{
    unsigned status = strcmp(pe->code, LC_PROTO_TOO_LARGE) == 0 ? 413 : strcmp(pe->code, "not_found") == 0 ? 404 : 400;
    return lc_http_error(srv, c, status, pe->code, pe->field, "%s", pe->message);
}

enum MHD_Result lc_http_not_allowed(lc_server *srv, struct MHD_Connection *c, const char *method, const char *allow)
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
    return lc_http_queue(srv, c, 405, r);
}
