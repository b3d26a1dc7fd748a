/* layers[] of a render request: each layer is a dataset with its own role,
 * visibility, importance, colour and style (protocol/README.md "Layers"). The
 * importance and colour objects take exactly the request's own keys, parsed
 * by request.c's section parser (lc_layer_apply_fn). */
#include "request_layers.h"

#include <stdio.h>
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

static int parse_layer(const json_t *v, lc_request_layer *out, const char *path, lc_layer_apply_fn apply, void *ctx,
                       lc_layer_error *err)
{
    if (!json_is_object(v))
        return lc_proto_list_fail(err, LC_PROTO_BAD_FIELD, path, "expected an object with a dataset");
    memset(out, 0, sizeof *out); /* whole buffers: a request compares and copies as bytes */
    lc_layer_params_default(&out->p);
    const char *key;
    json_t *m;
    char field[320];
    json_object_foreach((json_t *)v, key, m)
    {
        snprintf(field, sizeof field, "%s.%s", path, key);
        if (strcmp(key, "dataset") == 0) {
            if (!json_is_string(m) || json_string_length(m) == 0)
                return lc_proto_list_fail(err, LC_PROTO_BAD_FIELD, field, "expected a dataset name");
            if (json_string_length(m) >= sizeof out->dataset)
                return lc_proto_list_fail(err, LC_PROTO_OUT_OF_RANGE, field, "longer than %zu bytes",
                                          sizeof out->dataset - 1);
            memcpy(out->dataset, json_string_value(m), json_string_length(m) + 1);
        } else if (strcmp(key, "role") == 0) {
            int role = json_is_string(m) ? in_list(role_names, json_string_value(m)) : -1;
            if (role < 0)
                return lc_proto_list_fail(err, LC_PROTO_BAD_FIELD, field, "expected \"transparent\" or \"context\"");
            out->p.role = (lc_layer_role)role;
        } else if (strcmp(key, "visible") == 0) {
            if (!json_is_boolean(m))
                return lc_proto_list_fail(err, LC_PROTO_BAD_FIELD, field, "expected true or false");
            out->p.visible = json_is_true(m);
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
            int rc = apply(ctx, wrap, &out->p, &inner);
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
    if (!out->dataset[0]) {
        snprintf(field, sizeof field, "%s.dataset", path);
        return lc_proto_list_fail(err, LC_PROTO_MISSING_FIELD, field, "every layer names its dataset");
    }
    return 0;
}

int lc_proto_parse_layers(const json_t *v, lc_request_layer *out, int *count, const char *path, lc_layer_apply_fn apply,
                          void *ctx, lc_layer_error *err)
{
    if (!json_is_array(v))
        return lc_proto_list_fail(err, LC_PROTO_BAD_FIELD, path, "expected an array of layers");
    size_t n = json_array_size(v);
    if (n > LC_MAX_LAYERS)
        return lc_proto_list_fail(err, LC_PROTO_OUT_OF_RANGE, path, "at most %d layers", LC_MAX_LAYERS);
    for (size_t i = 0; i < n; i++) {
        char at[64];
        snprintf(at, sizeof at, "%s[%zu]", path, i);
        if (parse_layer(json_array_get(v, i), &out[i], at, apply, ctx, err) != 0)
            return -1;
    }
    *count = (int)n;
    return 0;
}

json_t *lc_proto_layer_keys_json(void)
{
    json_t *keys = json_array();
    for (int k = 0; layer_keys[k]; k++)
        json_array_append_new(keys, json_string(layer_keys[k]));
    return keys;
}

json_t *lc_proto_layers_json(const lc_request_layer *layers, int n, lc_layer_emit_fn emit)
{
    json_t *arr = json_array();
    for (int i = 0; i < n; i++) {
        const lc_request_layer *l = &layers[i];
        json_t *o = json_object();
        json_object_set_new(o, "dataset", json_string(l->dataset));
        json_object_set_new(o, "role", json_string(role_names[l->p.role]));
        json_object_set_new(o, "visible", json_boolean(l->p.visible));
        json_object_set_new(o, "importance", emit(&l->p, "importance"));
        json_object_set_new(o, "color", emit(&l->p, "color"));
        json_t *style = json_object();
        json_object_set_new(style, "lineWidth", json_real(l->p.style.line_width));
        json_object_set_new(style, "minLinePixels", json_real(l->p.style.min_line_pixels));
        json_object_set_new(style, "pointSize", json_real(l->p.style.point_size));
        json_object_set_new(style, "shading", json_string(l->p.style.shading == LC_SHADING_NONE ? "none" : "phong"));
        json_object_set_new(o, "style", style);
        if (l->p.filter_count > 0)
            json_object_set_new(o, "filter", emit(&l->p, "filter"));
        if (l->p.time.has_window)
            json_object_set_new(o, "time", emit(&l->p, "time"));
        if (l->p.clusters.count > 0)
            json_object_set_new(o, "lines", emit(&l->p, "lines"));
        json_array_append_new(arr, o);
    }
    return arr;
}
