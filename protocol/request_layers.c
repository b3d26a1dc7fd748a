/* layers[] of a render request: each layer is a dataset with its own role,
 * visibility, importance, colour and style (protocol/README.md "Layers"). The
 * importance and colour objects take exactly the request's own keys, parsed
 * by request.c's section parser (lc_layer_apply_fn). */
#include "request_layers.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const char *const role_names[] = {"transparent", "context", NULL}; /* lc_layer_role */
static const char *const layer_keys[] = {"dataset", "role",   "visible", "importance", "color",
                                         "style",   "filter", "time",    "lines",      NULL};

/* The style keys that belong to a layer; the rest (background, halos,
 * antialias, silhouettes) are the frame's. */
static const char *const layer_style_keys[] = {"lineWidth", "minLinePixels", "pointSize", "shading", NULL};

static int in_list(const char *const *list, const char *s)
{
    for (int i = 0; list[i]; i++)
        if (strcmp(list[i], s) == 0)
            return i;
    return -1;
}

const lc_request_layers *lc_request_layers_retain(const lc_request_layers *l)
{
    if (l) /* relaxed: the caller already holds a reference, which keeps l alive */
        atomic_fetch_add_explicit(&((lc_request_layers *)l)->refs, 1, memory_order_relaxed);
    return l;
}

void lc_request_layers_release(const lc_request_layers *l)
{
    /* acq_rel: the thread that frees sees every other holder's reads done */
    if (l && atomic_fetch_sub_explicit(&((lc_request_layers *)l)->refs, 1, memory_order_acq_rel) == 1)
        free((void *)l);
}

/* One layer into dataset (LC_LAYER_DATASET_LEN bytes, zeroed) and p. */
static int parse_layer(const json_t *v, char *dataset, lc_layer_params *p, const char *path, lc_layer_apply_fn apply,
                       void *ctx, lc_layer_error *err)
{
    if (!json_is_object(v))
        return lc_proto_list_fail(err, LC_PROTO_BAD_FIELD, path, "expected an object with a dataset");
    lc_layer_params_default(p);
    const char *key;
    json_t *m;
    char field[320];
    json_object_foreach((json_t *)v, key, m)
    {
        snprintf(field, sizeof field, "%s.%s", path, key);
        if (strcmp(key, "dataset") == 0) {
            if (!json_is_string(m) || json_string_length(m) == 0)
                return lc_proto_list_fail(err, LC_PROTO_BAD_FIELD, field, "expected a dataset name");
            if (json_string_length(m) >= LC_LAYER_DATASET_LEN)
                return lc_proto_list_fail(err, LC_PROTO_OUT_OF_RANGE, field, "longer than %d bytes",
                                          LC_LAYER_DATASET_LEN - 1);
            memcpy(dataset, json_string_value(m), json_string_length(m) + 1);
        } else if (strcmp(key, "role") == 0) {
            int role = json_is_string(m) ? in_list(role_names, json_string_value(m)) : -1;
            if (role < 0)
                return lc_proto_list_fail(err, LC_PROTO_BAD_FIELD, field, "expected \"transparent\" or \"context\"");
            p->role = (lc_layer_role)role;
        } else if (strcmp(key, "visible") == 0) {
            if (!json_is_boolean(m))
                return lc_proto_list_fail(err, LC_PROTO_BAD_FIELD, field, "expected true or false");
            p->visible = json_is_true(m);
        } else if (strcmp(key, "importance") == 0 || strcmp(key, "color") == 0 || strcmp(key, "style") == 0 ||
                   strcmp(key, "time") == 0 || strcmp(key, "filter") == 0 || strcmp(key, "lines") == 0) {
            if (strcmp(key, "filter") != 0 && !json_is_object(m)) /* filter: an array, the request's own check */
                return lc_proto_list_fail(err, LC_PROTO_BAD_FIELD, field, "expected an object");
            const char *sk;
            json_t *sv;
            if (strcmp(key, "style") == 0)
                json_object_foreach(m, sk, sv)
                {
                    if (in_list(layer_style_keys, sk) < 0) {
                        snprintf(field, sizeof field, "%s.style.%s", path, sk);
                        return lc_proto_list_fail(
                            err, LC_PROTO_UNKNOWN_FIELD, field,
                            "not a layer's style (a layer takes lineWidth, minLinePixels, pointSize and "
                            "shading; the request's style has the rest)");
                    }
                }
            json_t *wrap = json_object();
            json_object_set(wrap, key, m);
            lc_layer_error inner = {0};
            int rc = apply(ctx, wrap, p, &inner);
            json_decref(wrap);
            if (rc) {
                snprintf(field, sizeof field, "%s.%s", path, inner.field);
                return lc_proto_list_fail(err, inner.code, field, "%s", inner.reason);
            }
        } else {
            return lc_proto_list_fail(
                err, LC_PROTO_UNKNOWN_FIELD, field,
                "unknown field (a layer has dataset, role, visible, importance, color, style, filter, time, "
                "lines)");
        }
    }
    if (!dataset[0]) {
        snprintf(field, sizeof field, "%s.dataset", path);
        return lc_proto_list_fail(err, LC_PROTO_MISSING_FIELD, field, "every layer names its dataset");
    }
    return 0;
}

int lc_proto_parse_layers(const json_t *v, const lc_request_layers **out, const char *path, lc_layer_apply_fn apply,
                          void *ctx, lc_layer_error *err)
{
    *out = NULL;
    if (!json_is_array(v))
        return lc_proto_list_fail(err, LC_PROTO_BAD_FIELD, path, "expected an array of layers");
    size_t n = json_array_size(v);
    if (n > LC_MAX_LAYERS)
        return lc_proto_list_fail(err, LC_PROTO_OUT_OF_RANGE, path, "at most %d layers", LC_MAX_LAYERS);
    if (n == 0)
        return 0;
    lc_request_layers *l = calloc(1, sizeof *l); /* zeroed: the names' unused bytes too */
    if (!l)
        return lc_proto_list_fail(err, LC_PROTO_OUT_OF_RANGE, path, "out of memory");
    for (size_t i = 0; i < n; i++) {
        char at[64];
        snprintf(at, sizeof at, "%s[%zu]", path, i);
        if (parse_layer(json_array_get(v, i), l->dataset[i], &l->p[i], at, apply, ctx, err) != 0) {
            free(l);
            return -1;
        }
    }
    l->count = (int)n;
    atomic_init(&l->refs, 1);
    *out = l; /* published: never written again */
    return 0;
}

json_t *lc_proto_layer_keys_json(void)
{
    json_t *keys = json_array();
    for (int k = 0; layer_keys[k]; k++)
        json_array_append_new(keys, json_string(layer_keys[k]));
    return keys;
}

json_t *lc_proto_layers_json(const lc_request_layers *layers, lc_layer_emit_fn emit)
{
    json_t *arr = json_array();
    for (int i = 0; layers && i < layers->count; i++) {
        const lc_layer_params *p = &layers->p[i];
        json_t *o = json_object();
        json_object_set_new(o, "dataset", json_string(layers->dataset[i]));
        json_object_set_new(o, "role", json_string(role_names[p->role]));
        json_object_set_new(o, "visible", json_boolean(p->visible));
        json_object_set_new(o, "importance", emit(p, "importance"));
        json_object_set_new(o, "color", emit(p, "color"));
        json_t *style = json_object();
        json_object_set_new(style, "lineWidth", json_real(p->style.line_width));
        json_object_set_new(style, "minLinePixels", json_real(p->style.min_line_pixels));
        json_object_set_new(style, "pointSize", json_real(p->style.point_size));
        json_object_set_new(style, "shading", json_string(p->style.shading == LC_SHADING_NONE ? "none" : "phong"));
        json_object_set_new(o, "style", style);
        if (p->filter_count > 0)
            json_object_set_new(o, "filter", emit(p, "filter"));
        if (p->time.has_window)
            json_object_set_new(o, "time", emit(p, "time"));
        if (p->clusters.count > 0)
            json_object_set_new(o, "lines", emit(p, "lines"));
        json_array_append_new(arr, o);
    }
    return arr;
}
