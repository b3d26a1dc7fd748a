/* Helpers of the shared server object. */
#include "server.h"

#include <string.h>

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
