/* A partial update parsed once (a typed patch): which fields an update object
 * gives, and their values, checked when parsed (types, ranges, unknown keys, a
 * camera as far as the update pins it down). Applying it copies those values
 * into a request and runs only the cross-field checks that need the state it
 * meets, so a WebSocket or HTTP session update runs the field rules once.
 *
 * Threading: reentrant; a patch is immutable once parsed and may be applied
 * from any thread. */
#ifndef LC_PROTOCOL_REQUEST_PATCH_H
#define LC_PROTOCOL_REQUEST_PATCH_H

#include <jansson.h>

#include "request.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct lc_request_patch lc_request_patch;

/* Parses obj (an object of request sections and fields; the patch keeps a
 * reference) into *out, to be freed with lc_proto_patch_free. 0, or an error
 * naming the field with *out NULL. */
int lc_proto_patch_parse(json_t *obj, const lc_proto_limits *lim, lc_request_patch **out, lc_proto_error *err);
/* Merges p (NULL = no field) into r as lc_proto_apply_request would (a camera
 * merges into the current one or, without one, the default; null drops it),
 * then lc_proto_validate_request on the result; all or nothing. */
int lc_proto_patch_apply(const lc_request_patch *p, const lc_proto_limits *lim, lc_request *r, lc_proto_error *err);
/* The update object p was parsed from (borrowed; NULL for NULL): the fields
 * given, as the scope check judges them. */
const json_t *lc_proto_patch_json(const lc_request_patch *p);
void lc_proto_patch_free(lc_request_patch *p);

#ifdef __cplusplus
}
#endif
#endif
