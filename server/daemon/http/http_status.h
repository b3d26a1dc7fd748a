/* The daemon's status routes: GET /api/v1/health, /api/v1/datasets[/NAME]
 * and /metrics (protocol/openapi.yaml). Thread: MHD's. */
#ifndef LC_SERVER_HTTP_STATUS_H
#define LC_SERVER_HTTP_STATUS_H

#include "http_respond.h"

enum MHD_Result lc_http_health(lc_server *srv, struct MHD_Connection *c);
/* name: one dataset's description, NULL: the list with the memory budget. */
enum MHD_Result lc_http_datasets(lc_server *srv, struct MHD_Connection *c, const char *name);
enum MHD_Result lc_http_metrics(lc_server *srv, struct MHD_Connection *c);

#endif
