/* The request's layers[] (protocol/README.md "Layers"): parsed, validated
 * (errors name layers[i].key) and emitted. request.c's field table routes the
 * field here and lends its section parser and emitter for a layer's
 * importance, colour, style, filter and time window, so this module sits below request.c. */
#ifndef LC_PROTOCOL_REQUEST_LAYERS_H
#define LC_PROTOCOL_REQUEST_LAYERS_H

#include <jansson.h>

#include "lc_params.h"
#include "request_lists.h"

#define LC_LAYER_DATASET_LEN 512 /* = LC_PROTO_DATASET_LEN */

/* One layer of a scene of several datasets. */
typedef struct lc_request_layer {
    char dataset[LC_LAYER_DATASET_LEN]; /* as lc_request.dataset */
    lc_layer_params p;                  /* role, visibility, mapping and style */
} lc_request_layer;

/* Errors name layers[i].key; the same error as the list fields. */
typedef lc_list_error lc_layer_error;

/* request.c's section parser: applies obj ({"importance": {...}} and the
 * like) to p's mapping and style, field checks only; err->field relative to
 * the layer. Its emitter: p's "importance" or "color" as an object. */
typedef int (*lc_layer_apply_fn)(void *ctx, const json_t *obj, lc_layer_params *p, lc_layer_error *err);
typedef json_t *(*lc_layer_emit_fn)(const lc_layer_params *p, const char *section);

/* Parses the array v into out[0..*count-1] (at most LC_MAX_LAYERS; [] gives
 * 0 layers). Returns 0, or -1 with err filled (out then unspecified). */
int lc_proto_parse_layers(const json_t *v, lc_request_layer *out, int *count, const char *path, lc_layer_apply_fn apply,
                          void *ctx, lc_layer_error *err);
/* The keys a layer takes, as an array (the schema publishes them). */
json_t *lc_proto_layer_keys_json(void);
/* The n layers as an array, each with every field. */
json_t *lc_proto_layers_json(const lc_request_layer *layers, int n, lc_layer_emit_fn emit);

#endif
