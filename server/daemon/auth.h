/* Who may use the daemon: the token checks (the Authorization header, the
 * WebSocket subprotocol that carries a token, a hello's token) and the
 * WebSocket handshake's accept key. */
#ifndef LC_SERVER_AUTH_H
#define LC_SERVER_AUTH_H

#include <stdbool.h>
#include <stddef.h>

#include "server.h"

#define LC_SERVE_WS_ACCEPT_LEN 29 /* base64 of a SHA-1 digest + NUL */
/* Sec-WebSocket-Accept for a client's Sec-WebSocket-Key (SHA-1 + base64). */
void lc_serve_ws_accept_key(const char *client_key, char out[LC_SERVE_WS_ACCEPT_LEN]);

/* Constant-time token comparison; true when no token is configured. */
bool lc_serve_token_ok(const lc_server *srv, const char *given);

/* The WebSocket subprotocol that carries a token (browsers cannot set headers
 * on a WebSocket): "lucent.token." + base64url(token), offered next to
 * LC_SERVE_SUBPROTOCOL, which the server then selects. */
#define LC_SERVE_SUBPROTOCOL "lucent"
#define LC_SERVE_TOKEN_SUBPROTOCOL "lucent.token."
/* Reads a Sec-WebSocket-Protocol header value (comma-separated): the decoded
 * token of the first token subprotocol into out (size n; false when there is
 * none or it does not decode or fit), and whether LC_SERVE_SUBPROTOCOL is
 * offered. header may be NULL. */
bool lc_serve_subprotocol_token(const char *header, char *out, size_t n, bool *offers_lucent);

#endif
