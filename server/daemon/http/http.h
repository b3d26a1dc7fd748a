/* HTTP front end on libmicrohttpd: the /api/v1 routes, /metrics, the
 * WebSocket handshake and the embedded web client.
 *
 * Threading: MHD's threads run the handlers; they only parse, validate and
 * queue. Render requests suspend their connection, go to the worker pool and
 * are resumed by the job's done callback (an encoder or worker thread). */
#ifndef LC_SERVER_HTTP_H
#define LC_SERVER_HTTP_H

#include "server.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Opens the listening socket (cfg.listen_host:cfg.port) and starts MHD.
 * *port_out receives the bound port (useful with port 0). Thread: main. */
int lc_http_start(lc_server *srv, lc_http **out, int *port_out, lc_error *err);
/* Stops accepting new connections (shutdown step 1); the listening socket
 * itself closes in lc_http_stop, after MHD has let go of it. */
void lc_http_quiesce(lc_http *h);
/* Stops MHD; every suspended connection must have been resumed (the worker pool
 * is stopped first) and every upgraded one closed (lc_ws_shutdown). */
void lc_http_stop(lc_http *h);

#ifdef __cplusplus
}
#endif
#endif
