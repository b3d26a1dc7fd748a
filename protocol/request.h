/* The render request (version 1): parse, validate, partially update and emit it
 * as JSON or URL query parameters. Shared by the CLI, POST/GET /api/v1/render,
 * HTTP sessions and WebSocket sessions; protocol/README.md is its spec.
 *
 * Threading: every function is reentrant; nothing here keeps global state.
 * Knows nothing of GL or HTTP: it fills the plain-data types of lc_params.h. */
#ifndef LC_PROTOCOL_REQUEST_H
#define LC_PROTOCOL_REQUEST_H

#include <jansson.h>
#include <stdbool.h>
#include <stddef.h>

#include "json_input.h" /* lc_proto_limits, lc_proto_error, lc_proto_load */
#include "lc_base.h"
#include "lc_params.h"
#include "request_types.h" /* lc_request and its sections */

#ifdef __cplusplus
extern "C" {
#endif

/* lc_render_params_default() plus format png, quality 90, dataset "", no dt,
 * no layers. r holds no reference before (release a used request first). */
void lc_request_default(lc_request *r);
/* dst = src, sharing src's layers (one more reference); dst holds none before. */
void lc_request_copy(lc_request *dst, const lc_request *src);
/* dst = src where dst holds a request already (its layers are released). */
void lc_request_assign(lc_request *dst, const lc_request *src);
/* Drops r's reference to its layers (r then has none); r stays a valid request. */
void lc_request_release(lc_request *r);
/* The number of layers (0: the one dataset). */
static inline int lc_request_layer_count(const lc_request *r) { return r->layers ? r->layers->count : 0; }

/* Parses a whole request: r = defaults + the fields given. lim NULL = defaults,
 * err may be NULL. Returns 0, LC_ERR_INVALID (malformed/invalid) or LC_ERR_LIMIT
 * (too_large/too_deep); on error r holds the defaults. json need not be
 * NUL-terminated. */
int lc_proto_parse_request(const char *json, size_t len, const lc_proto_limits *lim, lc_request *r,
                           lc_proto_error *err);

/* Partial update with a parsed object: only the fields present change; every
 * field and the result as a whole (pixel cap, camera) are validated and on any
 * error r is left untouched (all or nothing). A "camera" object merges into the
 * current camera; "camera": null drops it (fit the data). obj is borrowed. */
int lc_proto_apply_request(const json_t *obj, const lc_proto_limits *lim, lc_request *r, lc_proto_error *err);

/* Applies one URL query parameter (GET /api/v1/render): key is a flat alias
 * ("q", "bands", "colormap", "importanceRange") or a dotted path ("params.q",
 * "camera.position"); value is the decoded text ("1,2,3" for vectors, "true"/"false"
 * or "1"/"0" for booleans). "token" and keys starting with '_' are ignored (the
 * server reads the token; '_' keys are cache busters). Field checks happen here;
 * call lc_proto_validate_request() after the last key for the cross-field ones. */
int lc_proto_apply_query(lc_request *r, const char *key, const char *value, const lc_proto_limits *lim,
                         lc_proto_error *err);

/* Cross-field checks: pixel cap, camera (position != focalPoint, viewUp not
 * parallel to the view direction). apply/parse already call it. */
int lc_proto_validate_request(const lc_request *r, const lc_proto_limits *lim, lc_proto_error *err);

/* The streamlines section: 1 when any of its fields holds a value other than
 * its default (lc_request_default: density seeding, 64 curves, the tracer's
 * own step, length and separation), *field (may be NULL) naming the first
 * ("streamlines.count"); 0 otherwise. */
static inline int lc_proto_streamlines_given(const lc_request *r, const char **field)
{
    const lc_streamlines_request *a = &r->streamlines;
    const char *f = a->seeding != 3      ? "streamlines.seeding"
                    : a->seed_count > 0  ? "streamlines.seeds"
                    : a->has_count       ? "streamlines.count"
                    : a->step != 0       ? "streamlines.step"
                    : a->length != 0     ? "streamlines.length"
                    : a->direction != 0  ? "streamlines.direction"
                    : a->separation != 0 ? "streamlines.separation"
                                         : (const char *)0;
    if (field)
        *field = f;
    return f != 0;
}
/* A session's update that holds a streamlines object describes the whole
 * set: r's section goes back to its defaults before the update applies, so
 * that a key it leaves out (count, when it turns to point seeding) takes its
 * default rather than the value of an earlier update (request_streamlines.c). */
void lc_proto_streamlines_replace(const json_t *update, lc_request *r);
/* The section as a streamline-set spec of the field named field_name
 * ("streamlines:FIELD?seeding=...", render/io/streamlines.h): the same keys
 * and checks as a set named at load time, numbers written to round-trip.
 * The spec's length, or -1 when it does not fit n. */
int lc_proto_streamlines_spec(const lc_request *r, const char *field_name, char *out, size_t n);

/* The full request as a new JSON object (caller json_decref()s); parsing it gives
 * back an equal lc_request. camera/ranges/dt appear only when set. */
json_t *lc_proto_request_to_json(const lc_request *r);

/* The request schema as a JSON array, one object per field: section (null at
 * the top level), name, alias, type (int, num, bool, str, enum, vec3, color,
 * range), min/max with loOpen/hiOpen, maxLength, values. It is the field table
 * that parsing uses, so clients and docs can be checked against it (`lucent
 * schema`). Width and height ranges come from lim (NULL = defaults). */
json_t *lc_proto_schema(const lc_proto_limits *lim);

/* One field's value as the request emits it (a new reference), or NULL when
 * it is unset (an optional value, an empty list). */
json_t *lc_proto_field_json(const lc_request *r, const char *section, const char *name);
/* The i-th field of the table (0 past its end): its section (NULL = top level) and name. */
int lc_proto_field_at(size_t i, const char **section, const char **name);

/* ---- partial updates (request_patch.h keeps them as typed patches) */

/* The field checks of a partial request object (types, ranges, unknown keys, a
 * camera as far as obj pins it down), storing the values given into r, without
 * the cross-field checks that need the state it will be applied to. */
int lc_proto_check_fields(const json_t *obj, const lc_proto_limits *lim, lc_request *r, lc_proto_error *err);
/* Copies field section.name (section NULL = top level) of src into dst, as
 * parsing stores it (a list field its whole list, a range its flag); no checks.
 * -1 for a name the table does not have. */
int lc_proto_copy_field(const char *section, const char *name, lc_request *dst, const lc_request *src);

#ifdef __cplusplus
}
#endif
#endif
