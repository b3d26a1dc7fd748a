/* The WebSocket handshake on libmicrohttpd: checks the upgrade, answers 101
 * and hands the socket to the WebSocket transport (http_upgrade.h). */
#include "http_upgrade.h"

#include <stdatomic.h>
#include <string.h>
#include <strings.h>

#include "auth.h"
#include "conn_limits.h"
#include "messages.h"
#include "metrics.h"
#include "session.h"
#include "ws.h"

static void upgrade_handler(void *cls, struct MHD_Connection *connection, void *con_cls, const char *extra_in,
                            size_t extra_in_size, MHD_socket sock, struct MHD_UpgradeResponseHandle *urh)
{
    lc_server *srv = cls;
    lc_http_req *ctx = con_cls;
    lc_ws_adopt(srv->ws, sock, urh, extra_in, extra_in_size, ctx && ctx->ws_authed, lc_conn_client_key(connection));
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

enum MHD_Result lc_http_upgrade(lc_http_req *ctx, struct MHD_Connection *c, bool authed)
{
    lc_server *srv = ctx->srv;
    const char *upgrade = MHD_lookup_connection_value(c, MHD_HEADER_KIND, MHD_HTTP_HEADER_UPGRADE);
    const char *connection = MHD_lookup_connection_value(c, MHD_HEADER_KIND, MHD_HTTP_HEADER_CONNECTION);
    const char *key = MHD_lookup_connection_value(c, MHD_HEADER_KIND, "Sec-WebSocket-Key");
    const char *version = MHD_lookup_connection_value(c, MHD_HEADER_KIND, "Sec-WebSocket-Version");
    if (!upgrade || !header_has_token(upgrade, "websocket") || !connection || !header_has_token(connection, "upgrade"))
        return lc_http_error(srv, c, 400, "bad_field", "Upgrade",
                             "expected a WebSocket upgrade (Connection: Upgrade, Upgrade: websocket)");
    if (!key || strlen(key) != 24)
        return lc_http_error(srv, c, 400, "bad_field", "Sec-WebSocket-Key", "missing or malformed Sec-WebSocket-Key");
    if (!version || strcmp(version, "13") != 0) {
        lc_metrics_error(srv->metrics, "bad_field");
        char *text =
            lc_proto_error_json("bad_field", "only WebSocket version 13 is supported", "Sec-WebSocket-Version");
        struct MHD_Response *r = MHD_create_response_from_buffer(strlen(text), text, MHD_RESPMEM_MUST_FREE);
        MHD_add_response_header(r, MHD_HTTP_HEADER_CONTENT_TYPE, "application/json");
        MHD_add_response_header(r, "Sec-WebSocket-Version", "13");
        return lc_http_queue(srv, c, 426, r);
    }
    if (atomic_load(&srv->stopping))
        return lc_http_error(srv, c, 503, "overloaded", NULL, "the server is shutting down");
    int http = 0, ws = 0;
    lc_sessions_count(srv->sessions, &http, &ws);
    if (http + ws >= srv->cfg.max_sessions)
        return lc_http_error(srv, c, 503, "overloaded", NULL, "too many sessions (the limit is %d)",
                             srv->cfg.max_sessions);
    char accept[LC_SERVE_WS_ACCEPT_LEN];
    lc_serve_ws_accept_key(key, accept);
    struct MHD_Response *r = MHD_create_response_for_upgrade(upgrade_handler, srv);
    if (!r)
        return MHD_NO;
    /* libmicrohttpd adds "Connection: Upgrade" to an upgrade response itself:
     * a second one makes strict clients refuse the handshake. */
    MHD_add_response_header(r, MHD_HTTP_HEADER_UPGRADE, "websocket");
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
    return lc_http_queue(srv, c, MHD_HTTP_SWITCHING_PROTOCOLS, r);
}
