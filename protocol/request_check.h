/* A parsed request judged against the scope table (request_scope.h): nothing
 * given where it does not apply is accepted and ignored. */
#ifndef LC_PROTOCOL_REQUEST_CHECK_H
#define LC_PROTOCOL_REQUEST_CHECK_H

#include <jansson.h>

#include "request.h"

/* Refuses (bad_field, naming it) a field that r's method or the frame's
 * primitive kinds do not read, when it holds a value other than its default:
 * nothing is accepted and ignored. given is the JSON as received, an update or
 * a whole request: only its fields are judged, so a value an earlier update
 * set stays in the session for when it applies again; NULL judges every field
 * (a request from query parameters). prims: the kinds the frame draws
 * (1 << lc_prim_type, or-ed over layers); 0 = not known yet (no kind check). */
int lc_proto_check_scope(const json_t *given, const lc_request *r, unsigned prims, lc_proto_error *err);

#endif
