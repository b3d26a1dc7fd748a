/* The request's array-valued fields (importance.terms, filter, the curves): parse with
 * errors that name the element and key ("filter[1].gt: expected a number"),
 * and emit. The parsers return 0, or -1 with err filled. Used by request.c's
 * field table; protocol/README.md specifies them. */
#ifndef LC_PROTOCOL_REQUEST_LISTS_H
#define LC_PROTOCOL_REQUEST_LISTS_H

#include <jansson.h>

#include "json_input.h" /* the protocol's error codes: the base of protocol/, below this module */
#include "lc_params.h"

/* What went wrong (here and in request_layers.c): request.c turns it into an
 * lc_proto_error. */
typedef struct lc_list_error {
    const char *code; /* LC_PROTO_BAD_FIELD, LC_PROTO_UNKNOWN_FIELD, LC_PROTO_MISSING_FIELD or LC_PROTO_OUT_OF_RANGE */
    char field[128];
    char reason[256];
} lc_list_error;

/* Fills err (field and a printf-style reason) and returns -1. */
int lc_proto_list_fail(lc_list_error *err, const char *code, const char *field, const char *fmt, ...)
    __attribute__((format(printf, 4, 5)));

/* Replaces m's terms with the array v (at most LC_MAX_IMPORTANCE_TERMS; an
 * empty array goes back to the single form). m is untouched on error. */
int lc_proto_parse_terms(const json_t *v, lc_importance_map *m, const char *path, lc_list_error *err);
/* Replaces p's filters with the array v (at most LC_MAX_FILTERS). */
int lc_proto_parse_filters(const json_t *v, lc_render_params *p, const char *path, lc_list_error *err);
/* A transfer function: [] (identity) or 2..LC_MAX_CURVE_POINTS [x, y] in
 * [0, 1] with x not decreasing. */
int lc_proto_parse_curve(const json_t *v, lc_curve *c, const char *path, lc_list_error *err);
json_t *lc_proto_curve_json(const lc_curve *c);
/* color.fixed: [] or up to LC_MAX_COLOR_FIXED [lo, hi] ranges, finite, lo <= hi. */
int lc_proto_parse_fixed(const json_t *v, lc_color_map *c, const char *path, lc_list_error *err);
json_t *lc_proto_fixed_json(const lc_color_map *c);
json_t *lc_proto_terms_json(const lc_importance_map *m);
json_t *lc_proto_filters_json(const lc_render_params *p);
/* surface.seed, streamlines.seeds: min..max finite [x, y, z] points,
 * consecutive points distinct; points holds max. Untouched on error. */
int lc_proto_parse_seed(const json_t *v, double (*points)[3], int *count, int min, int max, const char *path,
                        lc_list_error *err);
json_t *lc_proto_seed_json(const double (*points)[3], int count);
/* "vertex", "min", "max", "mean", "first", "last" or "change". */
const char *lc_filter_over_name(lc_filter_over o);

#endif
