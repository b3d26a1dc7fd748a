/* HTTP renders: one-shot (/api/v1/render) and scripted sessions
 * (/api/v1/sessions), queued on the worker pool with the connection
 * suspended until the image is encoded. Thread: MHD's. */
#ifndef LC_SERVER_HTTP_RENDER_H
#define LC_SERVER_HTTP_RENDER_H

#include "http_respond.h"

/* GET (query) or POST (JSON) /api/v1/render. */
enum MHD_Result lc_http_route_render(lc_http_req *ctx, struct MHD_Connection *c, const char *method);
/* POST /api/v1/sessions. */
enum MHD_Result lc_http_route_session_create(lc_http_req *ctx, struct MHD_Connection *c);
/* /api/v1/sessions/ID (GET, DELETE) and /api/v1/sessions/ID/render (POST); rest = "ID...". */
enum MHD_Result lc_http_route_session(lc_http_req *ctx, struct MHD_Connection *c, const char *method, const char *rest);
/* The response of ctx's finished render (the handler's call after the resume). */
enum MHD_Result lc_http_finish_render(lc_http_req *ctx, struct MHD_Connection *c);
/* Frees a render job and its image (NULL: nothing). */
void lc_http_free_job(struct lc_render_job *job);

#endif
