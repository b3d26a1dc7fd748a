/* The WebSocket handshake (RFC 6455 on libmicrohttpd): a GET /api/v1/ws with
 * an upgrade is answered 101 and its socket goes to the WebSocket transport
 * (stream/ws.c); authed says whether the request carried the token (else the
 * hello must). Thread: MHD's. */
#ifndef LC_SERVER_HTTP_UPGRADE_H
#define LC_SERVER_HTTP_UPGRADE_H

#include <stdbool.h>

#include "http_respond.h"

enum MHD_Result lc_http_upgrade(lc_http_req *ctx, struct MHD_Connection *c, bool authed);

#endif
