/* Token checks (header, subprotocol, hello) and the WebSocket handshake's accept key. */
#include "auth.h"

#include <nettle/base64.h>
#include <nettle/sha1.h>
#include <string.h>

#define LC_SERVE_WS_GUID "258EAFA5-E914-47DA-95CA-C5AB0DC85B11" /* RFC 6455 */

bool lc_serve_token_ok(const lc_server *srv, const char *given)
{
    const char *want = srv->cfg.token;
    if (!want[0])
        return true;
    if (!given)
        return false;
    /* Compare every byte of the longer string, so timing does not leak a prefix. */
    size_t a = strlen(want), b = strlen(given), n = a > b ? a : b;
    unsigned diff = (unsigned)(a ^ b);
    for (size_t i = 0; i < n; i++)
        diff |= (unsigned)(unsigned char)(i < a ? want[i] : 0) ^ (unsigned)(unsigned char)(i < b ? given[i] : 0);
    return diff == 0;
}

bool lc_serve_subprotocol_token(const char *header, char *out, size_t n, bool *offers_lucent)
{
    bool found = false;
    *offers_lucent = false;
    if (n)
        out[0] = '\0';
    const size_t plen = strlen(LC_SERVE_TOKEN_SUBPROTOCOL);
    for (const char *p = header; p && *p;) {
        while (*p == ' ' || *p == '\t' || *p == ',')
            p++;
        size_t len = strcspn(p, ", \t");
        if (len == strlen(LC_SERVE_SUBPROTOCOL) && strncmp(p, LC_SERVE_SUBPROTOCOL, len) == 0)
            *offers_lucent = true;
        else if (!found && len > plen && strncmp(p, LC_SERVE_TOKEN_SUBPROTOCOL, plen) == 0) {
            const char *enc = p + plen;
            size_t enc_len = len - plen;
            /* BASE64_DECODE_LENGTH bounds the output; refuse what cannot fit. */
            if (BASE64_DECODE_LENGTH(enc_len) < n) {
                struct base64_decode_ctx ctx;
                size_t out_len = n - 1;
                base64url_decode_init(&ctx);
                /* Unpadded ('=' is not allowed in a subprotocol name), so no
                 * base64_decode_final: it wants the padding. */
                if (base64_decode_update(&ctx, &out_len, (uint8_t *)out, enc_len, enc) &&
                    memchr(out, '\0', out_len) == NULL) {
                    out[out_len] = '\0';
                    found = true;
                } else {
                    out[0] = '\0';
                }
            }
        }
        p += len;
    }
    return found;
}

void lc_serve_ws_accept_key(const char *client_key, char out[LC_SERVE_WS_ACCEPT_LEN])
{
    struct sha1_ctx sha;
    uint8_t digest[SHA1_DIGEST_SIZE];
    sha1_init(&sha);
    sha1_update(&sha, strlen(client_key), (const uint8_t *)client_key);
    sha1_update(&sha, strlen(LC_SERVE_WS_GUID), (const uint8_t *)LC_SERVE_WS_GUID);
    sha1_digest(&sha, SHA1_DIGEST_SIZE, digest);
    base64_encode_raw(out, SHA1_DIGEST_SIZE, digest);
    out[BASE64_ENCODE_RAW_LENGTH(SHA1_DIGEST_SIZE)] = '\0';
}
