/* Untrusted JSON in and out: the caps, the protocol's error, loading under the caps, dumping (json_input.h). */
#include "json_input.h"

#include <stdarg.h>
#include <stdbool.h>
#include <stdio.h>
#include <string.h>

#include "lc_base.h"

void lc_proto_limits_default(lc_proto_limits *l)
{
    l->min_size = 16;
    /* 8K stills (8192 x 4608, 16:9); above 4096^2 pixels the renderer
     * composites in tiles (render/gl/frame.c), so GPU memory stays bounded. */
    l->max_size = 8192;
    l->max_pixels = 8192LL * 4608LL;
    l->max_depth = 16;
    l->max_text = 64 * 1024;
}

void lc_proto_copy_str(char *dst, size_t size, const char *src)
{
    size_t n = strlen(src);
    if (n >= size)
        n = size - 1;
    memcpy(dst, src, n);
    dst[n] = '\0';
}

int lc_proto_set_error(lc_proto_error *err, const char *code, const char *field, const char *fmt, ...)
{
    int status =
        (strcmp(code, LC_PROTO_TOO_LARGE) == 0 || strcmp(code, LC_PROTO_TOO_DEEP) == 0) ? LC_ERR_LIMIT : LC_ERR_INVALID;
    if (!err)
        return status;
    char reason[256];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(reason, sizeof reason, fmt, ap);
    va_end(ap);
    lc_proto_copy_str(err->code, sizeof err->code, code);
    lc_proto_copy_str(err->field, sizeof err->field, field ? field : "");
    if (err->field[0]) {
        size_t n = strlen(err->field);
        lc_proto_copy_str(err->message, sizeof err->message, err->field);
        if (n + 2 < sizeof err->message) {
            memcpy(err->message + n, ": ", 3);
            lc_proto_copy_str(err->message + n + 2, sizeof err->message - n - 2, reason);
        }
    } else {
        lc_proto_copy_str(err->message, sizeof err->message, reason);
    }
    return status;
}

/* Deepest {}/[] nesting of raw JSON text, ignoring brackets inside strings; stops
 * counting once past max (the exact depth of a hostile document is irrelevant). */
static int nesting_depth(const char *s, size_t len, int max)
{
    int depth = 0, deepest = 0;
    bool in_string = false;
    for (size_t i = 0; i < len; i++) {
        char c = s[i];
        if (in_string) {
            if (c == '\\')
                i++;
            else if (c == '"')
                in_string = false;
        } else if (c == '"') {
            in_string = true;
        } else if (c == '{' || c == '[') {
            if (++depth > deepest) {
                deepest = depth;
                if (deepest > max)
                    return deepest;
            }
        } else if (c == '}' || c == ']') {
            depth--;
        }
    }
    return deepest;
}

json_t *lc_proto_load(const char *text, size_t len, const lc_proto_limits *lim, lc_proto_error *err)
{
    lc_proto_limits dl;
    if (!lim)
        lc_proto_limits_default(&dl), lim = &dl;
    if (!text)
        len = 0;
    if (len > lim->max_text) {
        lc_proto_set_error(err, LC_PROTO_TOO_LARGE, "", "document of %zu bytes exceeds the limit of %zu bytes", len,
                           lim->max_text);
        return NULL;
    }
    /* Checked before jansson, whose recursion is bounded only at 2048 levels. */
    if (nesting_depth(text, len, lim->max_depth) > lim->max_depth) {
        lc_proto_set_error(err, LC_PROTO_TOO_DEEP, "", "nesting deeper than %d levels", lim->max_depth);
        return NULL;
    }
    json_error_t je;
    json_t *root = json_loadb(text ? text : "", len, JSON_REJECT_DUPLICATES | JSON_DECODE_ANY, &je);
    if (!root) {
        /* jansson already rejects NaN/Infinity (not JSON) and numbers that
         * overflow a double or a 64-bit integer. */
        lc_proto_set_error(err, LC_PROTO_BAD_JSON, "", "invalid JSON at line %d, column %d: %s", je.line, je.column,
                           je.text);
        return NULL;
    }
    return root;
}

char *lc_proto_dump(const json_t *value)
{
    return json_dumps(value, JSON_COMPACT | JSON_ENCODE_ANY | JSON_REAL_PRECISION(15));
}
