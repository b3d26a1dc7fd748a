/* The request's layers[] (protocol/README.md "Layers"): parsed, validated
 * (errors name layers[i].key) and emitted, and held as one shared, immutable
 * snapshot that request copies reference instead of copying. request.c's
 * field table routes the field here and lends its section parser and emitter
 * for a layer's importance, colour, style, filter and time window, so this
 * module sits below request.c.
 *
 * Threading: a snapshot never changes once parsed; its reference count is
 * atomic, so copies of a request may be taken and dropped on any thread. */
#ifndef LC_PROTOCOL_REQUEST_LAYERS_H
#define LC_PROTOCOL_REQUEST_LAYERS_H

#include <jansson.h>
#include <stdatomic.h>

#include "lc_params.h"
#include "request_lists.h"

#define LC_LAYER_DATASET_LEN 512 /* = LC_PROTO_DATASET_LEN */

/* The layers of a scene of several datasets: 35 KiB at most, so a request
 * holds a reference (lc_request.layers) and a change of layers makes a new
 * snapshot rather than editing this one (copy on write). */
typedef struct lc_request_layers {
    atomic_int refs;
    int count;                                         /* 1 .. LC_MAX_LAYERS */
    lc_layer_params p[LC_MAX_LAYERS];                  /* role, visibility, mapping and style: the renderer's array */
    char dataset[LC_MAX_LAYERS][LC_LAYER_DATASET_LEN]; /* each as lc_request.dataset */
} lc_request_layers;

/* Another reference to l (NULL gives NULL); returns l. */
const lc_request_layers *lc_request_layers_retain(const lc_request_layers *l);
/* Drops a reference (NULL: nothing); the last one frees the snapshot. */
void lc_request_layers_release(const lc_request_layers *l);

/* Errors name layers[i].key; the same error as the list fields. */
typedef lc_list_error lc_layer_error;

/* request.c's section parser: applies obj ({"importance": {...}} and the
 * like) to p's mapping and style, field checks only; err->field relative to
 * the layer. Its emitter: p's "importance" or "color" as an object. */
typedef int (*lc_layer_apply_fn)(void *ctx, const json_t *obj, lc_layer_params *p, lc_layer_error *err);
typedef json_t *(*lc_layer_emit_fn)(const lc_layer_params *p, const char *section);

/* Parses the array v into *out: a new snapshot holding one reference, or NULL
 * for [] (no layers). Returns 0, or -1 with err filled and *out NULL. */
int lc_proto_parse_layers(const json_t *v, const lc_request_layers **out, const char *path, lc_layer_apply_fn apply,
                          void *ctx, lc_layer_error *err);
/* The keys a layer takes, as an array (the schema publishes them). */
json_t *lc_proto_layer_keys_json(void);
/* The layers as an array, each with every field ([] for NULL). */
json_t *lc_proto_layers_json(const lc_request_layers *layers, lc_layer_emit_fn emit);

#endif
