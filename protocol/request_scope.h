/* Where each request field applies (request_scope.c): a table of the methods
 * and primitive kinds whose frames read a field. No state; reentrant. */
#ifndef LC_PROTOCOL_REQUEST_SCOPE_H
#define LC_PROTOCOL_REQUEST_SCOPE_H

#include <stddef.h>

#include "lc_params.h"

#define LC_PROTO_ALL_METHODS ((1u << LC_METHOD_COUNT) - 1u)
#define LC_PROTO_ALL_PRIMS ((1u << LC_PRIM_POINTS) | (1u << LC_PRIM_LINES) | (1u << LC_PRIM_TRIANGLES))

/* The methods (bits 1 << lc_method) and primitive kinds (1 << lc_prim_type)
 * whose frames read the field section.name (section NULL = top level). */
void lc_proto_field_scope(const char *section, const char *name, unsigned *methods, unsigned *prims);

/* A field that applies only while another field of the request holds one
 * value (the direct method's opacity parameters under params.alphaSource):
 * returns 1 with *when_path ("params.alphaSource") and *when_value
 * ("constant"); 0 for every other field. */
int lc_proto_field_condition(const char *section, const char *name, const char **when_path, const char **when_value);

/* "points", "lines" or "surfaces". */
const char *lc_proto_prim_name(int prim);

/* The methods of mask as text: "fourier, exact or wboit". */
void lc_proto_method_list(unsigned mask, char *out, size_t size);

#endif
