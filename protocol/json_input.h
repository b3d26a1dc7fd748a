/* Untrusted JSON in and out: the caps on it (lc_proto_limits), the protocol's
 * error (lc_proto_error, its stable codes), loading a document under the caps
 * and dumping one for the wire. The base of protocol/: includes nothing of it.
 *
 * Threading: every function is reentrant. */
#ifndef LC_PROTOCOL_JSON_INPUT_H
#define LC_PROTOCOL_JSON_INPUT_H

#include <jansson.h>
#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Caps on untrusted input. Zero-initialised fields are NOT defaults: always start
 * from lc_proto_limits_default() and override. */
typedef struct lc_proto_limits {
    int min_size, max_size; /* image width and height, each (default 16..8192) */
    long long max_pixels;   /* width*height (default 8192*4608 = 37.7M) */
    int max_depth;          /* JSON nesting: {} and [] levels (default 16) */
    size_t max_text;        /* bytes of one JSON document (default 64 KiB) */
} lc_proto_limits;

/* Stable machine-readable error codes (the "code" of error bodies/messages). */
#define LC_PROTO_BAD_JSON "bad_json"           /* not JSON, NaN/Infinity, number overflow, duplicate key */
#define LC_PROTO_BAD_FIELD "bad_field"         /* wrong type, unknown enum name, inconsistent values */
#define LC_PROTO_UNKNOWN_FIELD "unknown_field" /* a key the schema does not define */
#define LC_PROTO_MISSING_FIELD "missing_field" /* a required key is absent (messages only) */
#define LC_PROTO_OUT_OF_RANGE "out_of_range"   /* a number or string length outside its range */
#define LC_PROTO_TOO_DEEP "too_deep"           /* nesting deeper than max_depth */
#define LC_PROTO_TOO_LARGE "too_large"         /* text longer than max_text */

/* Filled by a failing call. field is the dotted path of the offending key
 * ("params.bands", "camera.position"; "" when it concerns the whole document);
 * message is a complete human sentence that starts with the field:
 * "params.bands: expected an integer". */
typedef struct lc_proto_error {
    char code[32];
    char field[128];
    char message[256];
} lc_proto_error;

void lc_proto_limits_default(lc_proto_limits *l);

/* Copies src into dst[size], truncated to fit and terminated (snprintf("%s")
 * would trip -Wformat-truncation). */
void lc_proto_copy_str(char *dst, size_t size, const char *src);

/* Fills err (may be NULL): code, field, and message = "field: reason" (just the
 * reason when field is empty). Returns LC_ERR_LIMIT for too_large/too_deep,
 * LC_ERR_INVALID otherwise, so callers can `return lc_proto_set_error(...)`. */
int lc_proto_set_error(lc_proto_error *err, const char *code, const char *field, const char *fmt, ...)
    __attribute__((format(printf, 4, 5)));

/* Dumps JSON for the wire: compact, reals with 15 significant digits (so 0.1
 * prints as 0.1). Returns malloc'd text (free()) or NULL on allocation failure. */
char *lc_proto_dump(const json_t *value);

/* Loads a JSON document under the limits: text length (too_large), nesting
 * depth checked on the raw text before jansson recurses (too_deep), duplicate
 * keys, NaN/Infinity and overflowing numbers rejected (bad_json). Returns a new
 * reference or NULL with err filled. */
json_t *lc_proto_load(const char *text, size_t len, const lc_proto_limits *lim, lc_proto_error *err);

#ifdef __cplusplus
}
#endif
#endif
