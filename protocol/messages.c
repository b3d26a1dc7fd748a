/* WebSocket session messages: client message parsing, server message builders,
 * binary frame packing, and the HTTP error body. */
#include "messages.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static const char *const type_names[] = {"hello", "camera", "params", "resize", "ack"};
#define NTYPES (sizeof type_names / sizeof type_names[0])

const char *lc_proto_msg_type_name(lc_msg_type t) { return (unsigned)t < NTYPES ? type_names[t] : "unknown"; }

/* The render request's sections a message may carry (after camera): one list
 * for what hello and params pass on in m->update and what each allows. */
#define REQUEST_SECTIONS                                                                                               \
    "params", "importance", "color", "style", "method", "filter", "lines", "time", "surface", "streamlines", "layers"

/* Keys of the render request that hello/params/camera pass on in m->update. */
static const char *const update_keys[] = {"camera", REQUEST_SECTIONS};
#define NUPDATE (sizeof update_keys / sizeof update_keys[0])

/* Which keys each message type allows, besides "type". */
static const char *const hello_keys[] = {"dataset",          "width",          "height",
                                         "devicePixelRatio", "window",         "token",
                                         "camera",           "quality",        "interactiveQuality",
                                         "interactiveScale", REQUEST_SECTIONS, NULL};
static const char *const camera_keys[] = {"seq", "camera", NULL};
static const char *const params_keys[] = {"quality", "interactiveQuality", "interactiveScale", REQUEST_SECTIONS, NULL};
static const char *const resize_keys[] = {"width", "height", "devicePixelRatio", NULL};
static const char *const ack_keys[] = {"frame", NULL};
static const char *const *const allowed_keys[] = {hello_keys, camera_keys, params_keys, resize_keys, ack_keys};

static bool in_list(const char *const *list, const char *key)
{
    for (int i = 0; list[i]; i++)
        if (strcmp(list[i], key) == 0)
            return true;
    return false;
}

static bool is_update_key(const char *key)
{
    for (size_t i = 0; i < NUPDATE; i++)
        if (strcmp(update_keys[i], key) == 0)
            return true;
    return false;
}

/* ---- typed getters: absent keys return 1 (not given), errors < 0, 0 = read */

static int get_int(const json_t *obj, const char *key, long long lo, long long hi, int *out, lc_proto_error *err)
{
    const json_t *v = json_object_get(obj, key);
    if (!v)
        return 1;
    double d = json_is_number(v) ? json_number_value(v) : NAN;
    if (!isfinite(d) || d != floor(d))
        return lc_proto_set_error(err, LC_PROTO_BAD_FIELD, key, "expected an integer");
    if (d < (double)lo || d > (double)hi)
        return lc_proto_set_error(err, LC_PROTO_OUT_OF_RANGE, key, "%.15g is outside [%lld, %lld]", d, lo, hi);
    *out = (int)d;
    return 0;
}

/* Sequence numbers and frame ids: integers that a JavaScript number holds exactly. */
static int get_uint(const json_t *obj, const char *key, uint64_t *out, lc_proto_error *err)
{
    const json_t *v = json_object_get(obj, key);
    if (!v)
        return 1;
    if (json_is_integer(v)) {
        json_int_t i = json_integer_value(v);
        if (i < 0 || (uint64_t)i > LC_PROTO_MAX_SEQ)
            return lc_proto_set_error(err, LC_PROTO_OUT_OF_RANGE, key, "must be in [0, 2^53-1]");
        *out = (uint64_t)i;
        return 0;
    }
    double d = json_is_real(v) ? json_real_value(v) : NAN;
    if (!isfinite(d) || d != floor(d))
        return lc_proto_set_error(err, LC_PROTO_BAD_FIELD, key, "expected a non-negative integer");
    if (d < 0 || d > (double)LC_PROTO_MAX_SEQ)
        return lc_proto_set_error(err, LC_PROTO_OUT_OF_RANGE, key, "must be in [0, 2^53-1]");
    *out = (uint64_t)d;
    return 0;
}

/* lo_open: lo itself is excluded. */
static int get_num(const json_t *obj, const char *key, double lo, bool lo_open, double hi, double *out,
                   lc_proto_error *err)
{
    const json_t *v = json_object_get(obj, key);
    if (!v)
        return 1;
    double d = json_is_number(v) ? json_number_value(v) : NAN;
    if (!isfinite(d))
        return lc_proto_set_error(err, LC_PROTO_BAD_FIELD, key, "expected a number");
    if ((lo_open ? !(d > lo) : !(d >= lo)) || !(d <= hi))
        return lc_proto_set_error(err, LC_PROTO_OUT_OF_RANGE, key, "%.15g is outside %s%.15g, %.15g]", d,
                                  lo_open ? "(" : "[", lo, hi);
    *out = d;
    return 0;
}

static int get_str(const json_t *obj, const char *key, char *out, size_t size, lc_proto_error *err)
{
    const json_t *v = json_object_get(obj, key);
    if (!v)
        return 1;
    if (!json_is_string(v))
        return lc_proto_set_error(err, LC_PROTO_BAD_FIELD, key, "expected a string");
    size_t n = json_string_length(v);
    if (n >= size)
        return lc_proto_set_error(err, LC_PROTO_OUT_OF_RANGE, key, "longer than %zu bytes", size - 1);
    memcpy(out, json_string_value(v), n + 1);
    return 0;
}

/* Marks has_ when read; passes errors on. */
#define READ(call, has)                                                                                                \
    do {                                                                                                               \
        int rc_ = (call);                                                                                              \
        if (rc_ < 0) {                                                                                                 \
            status = rc_;                                                                                              \
            goto fail;                                                                                                 \
        }                                                                                                              \
        if (rc_ == 0)                                                                                                  \
            (has) = true;                                                                                              \
    } while (0)

#define REQUIRE(call, key)                                                                                             \
    do {                                                                                                               \
        int rc_ = (call);                                                                                              \
        if (rc_ < 0) {                                                                                                 \
            status = rc_;                                                                                              \
            goto fail;                                                                                                 \
        }                                                                                                              \
        if (rc_ == 1) {                                                                                                \
            status = lc_proto_set_error(err, LC_PROTO_MISSING_FIELD, key, "required");                                 \
            goto fail;                                                                                                 \
        }                                                                                                              \
    } while (0)

static void msg_defaults(lc_client_msg *m)
{
    memset(m, 0, sizeof *m);
    m->window = LC_PROTO_DEFAULT_WINDOW;
    m->device_pixel_ratio = 1.0;
    m->quality = LC_PROTO_DEFAULT_QUALITY;
    m->interactive_quality = LC_PROTO_DEFAULT_INTERACTIVE_QUALITY;
    m->interactive_scale = LC_PROTO_DEFAULT_INTERACTIVE_SCALE;
}

int lc_proto_parse_client_message(const char *text, size_t len, const lc_proto_limits *lim, lc_client_msg *m,
                                  lc_proto_error *err)
{
    lc_proto_limits dl;
    if (!lim) {
        lc_proto_limits_default(&dl);
        lim = &dl;
    }
    lc_proto_error local;
    if (!err)
        err = &local;
    msg_defaults(m);
    json_t *root = lc_proto_load(text, len, lim, err);
    if (!root)
        return strcmp(err->code, LC_PROTO_BAD_JSON) == 0 ? LC_ERR_INVALID : LC_ERR_LIMIT;

    int status = 0;
    json_t *update = NULL;
    if (!json_is_object(root)) {
        status = lc_proto_set_error(err, LC_PROTO_BAD_FIELD, "", "expected a JSON object");
        goto fail;
    }
    const json_t *type = json_object_get(root, "type");
    if (!type) {
        status = lc_proto_set_error(err, LC_PROTO_MISSING_FIELD, "type", "required");
        goto fail;
    }
    int t = -1;
    for (size_t i = 0; i < NTYPES; i++)
        if (json_is_string(type) && strcmp(json_string_value(type), type_names[i]) == 0)
            t = (int)i;
    if (t < 0) {
        status = lc_proto_set_error(err, LC_PROTO_BAD_FIELD, "type",
                                    "expected one of \"hello\", \"camera\", \"params\", \"resize\", \"ack\"");
        goto fail;
    }
    m->type = (lc_msg_type)t;

    /* Unknown keys first, so a typo is named even when a required key is missing. */
    const char *key;
    json_t *v;
    json_object_foreach(root, key, v)
    {
        if (strcmp(key, "type") != 0 && !in_list(allowed_keys[t], key)) {
            status =
                lc_proto_set_error(err, LC_PROTO_UNKNOWN_FIELD, key, "unknown field in a %s message", type_names[t]);
            goto fail;
        }
        if (is_update_key(key)) {
            if (!update && !(update = json_object())) {
                status = LC_ERR_NOMEM;
                lc_proto_set_error(err, LC_PROTO_BAD_JSON, "", "out of memory");
                goto fail;
            }
            json_object_set(update, key, v);
        }
    }

    switch (m->type) {
    case LC_MSG_HELLO:
        READ(get_str(root, "dataset", m->dataset, sizeof m->dataset, err), m->has_dataset);
        READ(get_str(root, "token", m->token, sizeof m->token, err), m->has_token);
        READ(get_int(root, "window", 1, LC_PROTO_MAX_WINDOW, &m->window, err), m->has_window);
        /* hello also carries the viewport (as resize) and the stream settings (as params) */
        /* fall through */
    case LC_MSG_RESIZE:
        REQUIRE(get_int(root, "width", 1, lim->max_size, &m->width, err), "width");
        REQUIRE(get_int(root, "height", 1, lim->max_size, &m->height, err), "height");
        READ(get_num(root, "devicePixelRatio", 0, true, LC_PROTO_MAX_DEVICE_PIXEL_RATIO, &m->device_pixel_ratio, err),
             m->has_device_pixel_ratio);
        if (m->type == LC_MSG_RESIZE)
            break;
        /* fall through */
    case LC_MSG_PARAMS:
        READ(get_int(root, "quality", 1, 100, &m->quality, err), m->has_quality);
        READ(get_int(root, "interactiveQuality", 1, 100, &m->interactive_quality, err), m->has_interactive_quality);
        READ(get_num(root, "interactiveScale", LC_PROTO_MIN_INTERACTIVE_SCALE, false, 1.0, &m->interactive_scale, err),
             m->has_interactive_scale);
        break;
    case LC_MSG_CAMERA:
        REQUIRE(get_uint(root, "seq", &m->seq, err), "seq");
        if (!json_object_get(root, "camera")) {
            status = lc_proto_set_error(err, LC_PROTO_MISSING_FIELD, "camera", "required");
            goto fail;
        }
        break;
    case LC_MSG_ACK: REQUIRE(get_uint(root, "frame", &m->frame, err), "frame"); break;
    }

    /* The render-request parts are checked by the request schema, so their
     * errors carry the same dotted paths as in POST /api/v1/render. */
    if (update && (status = lc_proto_patch_parse(update, lim, &m->patch, err)) != 0)
        goto fail;
    m->update = update;
    json_decref(root);
    return 0;

fail:
    json_decref(update);
    json_decref(root);
    msg_defaults(m);
    return status < 0 ? status : LC_ERR_INVALID;
}

void lc_client_msg_free(lc_client_msg *m)
{
    if (!m)
        return;
    json_decref(m->update);
    m->update = NULL;
    lc_proto_patch_free(m->patch);
    m->patch = NULL;
}

json_t *lc_proto_client_message_to_json(const lc_client_msg *m)
{
    json_t *o = json_object();
    if (!o)
        return NULL;
    json_object_set_new(o, "type", json_string(lc_proto_msg_type_name(m->type)));
    switch (m->type) {
    case LC_MSG_HELLO:
        if (m->has_dataset)
            json_object_set_new(o, "dataset", json_string(m->dataset));
        if (m->has_token)
            json_object_set_new(o, "token", json_string(m->token));
        if (m->has_window)
            json_object_set_new(o, "window", json_integer(m->window));
        /* fall through */
    case LC_MSG_RESIZE:
        json_object_set_new(o, "width", json_integer(m->width));
        json_object_set_new(o, "height", json_integer(m->height));
        if (m->has_device_pixel_ratio)
            json_object_set_new(o, "devicePixelRatio", json_real(m->device_pixel_ratio));
        if (m->type == LC_MSG_RESIZE)
            break;
        /* fall through */
    case LC_MSG_PARAMS:
        if (m->has_quality)
            json_object_set_new(o, "quality", json_integer(m->quality));
        if (m->has_interactive_quality)
            json_object_set_new(o, "interactiveQuality", json_integer(m->interactive_quality));
        if (m->has_interactive_scale)
            json_object_set_new(o, "interactiveScale", json_real(m->interactive_scale));
        break;
    case LC_MSG_CAMERA: json_object_set_new(o, "seq", json_integer((json_int_t)m->seq)); break;
    case LC_MSG_ACK: json_object_set_new(o, "frame", json_integer((json_int_t)m->frame)); break;
    }
    if (m->update)
        json_object_update(o, m->update); /* copies references to the sections */
    return o;
}

/* ---- stream settings */

void lc_proto_stream_default(lc_stream_settings *s)
{
    s->window = LC_PROTO_DEFAULT_WINDOW;
    s->quality = LC_PROTO_DEFAULT_QUALITY;
    s->interactive_quality = LC_PROTO_DEFAULT_INTERACTIVE_QUALITY;
    s->interactive_scale = LC_PROTO_DEFAULT_INTERACTIVE_SCALE;
}

void lc_proto_stream_apply(lc_stream_settings *s, const lc_client_msg *m)
{
    if (m->has_window)
        s->window = m->window;
    if (m->has_quality)
        s->quality = m->quality;
    if (m->has_interactive_quality)
        s->interactive_quality = m->interactive_quality;
    if (m->has_interactive_scale)
        s->interactive_scale = m->interactive_scale;
}

/* ---- server -> client */

/* Dumps and releases obj: the builders below own what they build. */
static char *dump_and_free(json_t *obj)
{
    if (!obj)
        return NULL;
    char *text = lc_proto_dump(obj);
    json_decref(obj);
    return text;
}

char *lc_proto_ready_json(const char *session, const json_t *dataset_info, const lc_request *defaults,
                          const lc_proto_limits *lim, const lc_stream_settings *stream)
{
    lc_proto_limits dl;
    if (!lim) {
        lc_proto_limits_default(&dl);
        lim = &dl;
    }
    lc_stream_settings ds;
    if (!stream) {
        lc_proto_stream_default(&ds);
        stream = &ds;
    }
    lc_request dr;
    if (!defaults) {
        lc_request_default(&dr);
        defaults = &dr;
    }
    json_t *o = json_object();
    if (!o)
        return NULL;
    json_object_set_new(o, "type", json_string("ready"));
    json_object_set_new(o, "session", json_string(session ? session : ""));
    json_object_set_new(o, "dataset", dataset_info ? json_deep_copy(dataset_info) : json_null());
    json_object_set_new(o, "defaults", lc_proto_request_to_json(defaults));
    json_object_set_new(o, "limits",
                        json_pack("{s:i, s:i, s:I, s:i, s:I, s:i}", "minSize", lim->min_size, "maxSize", lim->max_size,
                                  "maxPixels", (json_int_t)lim->max_pixels, "maxDepth", lim->max_depth, "maxText",
                                  (json_int_t)lim->max_text, "maxWindow", LC_PROTO_MAX_WINDOW));
    json_object_set_new(o, "stream",
                        json_pack("{s:i, s:i, s:i, s:f}", "window", stream->window, "quality", stream->quality,
                                  "interactiveQuality", stream->interactive_quality, "interactiveScale",
                                  stream->interactive_scale));
    return dump_and_free(o);
}

/* A JSON string of text, with each byte that is not part of valid UTF-8
 * replaced by '?': messages quote client input (a URL, a dataset name), and
 * json_string() refuses invalid UTF-8, which would drop the message. */
static json_t *text_json(const char *text)
{
    json_t *v = json_string(text);
    if (v)
        return v;
    size_t n = strlen(text);
    char *clean = malloc(n + 1);
    if (!clean)
        return json_string("");
    const unsigned char *p = (const unsigned char *)text;
    size_t i = 0, o = 0;
    while (i < n) {
        unsigned c = p[i];
        size_t len = c < 0x80 ? 1 : (c & 0xE0) == 0xC0 ? 2 : (c & 0xF0) == 0xE0 ? 3 : (c & 0xF8) == 0xF0 ? 4 : 0;
        bool ok = len > 0 && i + len <= n;
        for (size_t k = 1; ok && k < len; k++)
            ok = (p[i + k] & 0xC0) == 0x80;
        if (ok && len > 1) { /* overlong forms, surrogates and code points beyond U+10FFFF */
            unsigned cp = c & (0xFF >> (len + 1));
            for (size_t k = 1; k < len; k++)
                cp = cp << 6 | (p[i + k] & 0x3F);
            static const unsigned min_cp[5] = {0, 0, 0x80, 0x800, 0x10000};
            ok = cp >= min_cp[len] && cp <= 0x10FFFF && !(cp >= 0xD800 && cp <= 0xDFFF);
        }
        if (ok) {
            memcpy(clean + o, p + i, len);
            o += len;
            i += len;
        } else {
            clean[o++] = '?';
            i++;
        }
    }
    clean[o] = '\0';
    v = json_string(clean);
    free(clean);
    return v ? v : json_string("");
}

char *lc_proto_error_message_json(const char *code, const char *message, const char *field, bool fatal)
{
    json_t *o = json_object();
    if (!o)
        return NULL;
    json_object_set_new(o, "type", json_string("error"));
    json_object_set_new(o, "code", json_string(code ? code : "error"));
    json_object_set_new(o, "message", text_json(message ? message : ""));
    if (field && field[0])
        json_object_set_new(o, "field", text_json(field));
    json_object_set_new(o, "fatal", json_boolean(fatal));
    return dump_and_free(o);
}

char *lc_proto_stats_json(const json_t *fields)
{
    json_t *o = json_object();
    if (!o)
        return NULL;
    json_object_set_new(o, "type", json_string("stats"));
    const char *key;
    json_t *v;
    if (json_is_object(fields))
        json_object_foreach((json_t *)fields, key, v) if (strcmp(key, "type") != 0) json_object_set(o, key, v);
    return dump_and_free(o);
}

char *lc_proto_progress_json(const char *stage, double fraction, double elapsed)
{
    json_t *o = json_object();
    if (!o)
        return NULL;
    json_object_set_new(o, "type", json_string("progress"));
    json_object_set_new(o, "stage", json_string(stage));
    json_object_set_new(o, "fraction", fraction >= 0 ? json_real(round(fraction * 1000.0) / 1000.0) : json_null());
    json_object_set_new(o, "elapsed", json_real(round(elapsed * 1000.0) / 1000.0));
    return dump_and_free(o);
}

char *lc_proto_error_json(const char *code, const char *message, const char *field)
{
    json_t *e = json_object();
    json_t *o = json_object();
    if (!e || !o) {
        json_decref(e);
        json_decref(o);
        return NULL;
    }
    json_object_set_new(e, "code", json_string(code ? code : "error"));
    json_object_set_new(e, "message", text_json(message ? message : ""));
    if (field && field[0])
        json_object_set_new(e, "field", text_json(field));
    json_object_set_new(o, "error", e);
    return dump_and_free(o);
}

char *lc_proto_error_json_from(const lc_proto_error *err)
{
    return lc_proto_error_json(err->code, err->message, err->field);
}

/* ---- binary frames */

int lc_proto_pack_frame(const lc_frame_header *h, const unsigned char *image, size_t image_len, unsigned char **out,
                        size_t *out_len)
{
    *out = NULL;
    *out_len = 0;
    if (h->frame > LC_PROTO_MAX_SEQ || h->camera_seq > LC_PROTO_MAX_SEQ || h->width <= 0 || h->height <= 0 ||
        h->timing_count < 0 || h->timing_count > LC_PROTO_MAX_TIMINGS || !isfinite(h->encode_ms) ||
        (image_len && !image))
        return LC_ERR_INVALID;
    json_t *timings = json_object();
    for (int i = 0; i < h->timing_count; i++) {
        if (!h->timings[i].pass[0] || !isfinite(h->timings[i].ms)) {
            json_decref(timings);
            return LC_ERR_INVALID;
        }
        json_object_set_new(timings, h->timings[i].pass, json_real(h->timings[i].ms));
    }
    /* Key order is part of the shared vectors (frames.json packs byte-exactly). */
    json_t *o = json_pack("{s:I, s:i, s:i, s:s, s:i, s:I, s:b, s:o, s:f}", "frame", (json_int_t)h->frame, "width",
                          h->width, "height", h->height, "format", h->format == LC_FORMAT_PNG ? "png" : "jpeg",
                          "quality", h->quality, "cameraSeq", (json_int_t)h->camera_seq, "converged", (int)h->converged,
                          "timings", timings, "encodeMs", h->encode_ms);
    if (o && h->has_visibility) {
        if (!isfinite(h->top_decile_alpha) || !isfinite(h->bottom_half_alpha) || !isfinite(h->covered_fraction) ||
            !isfinite(h->occluder_alpha) || !isfinite(h->important_occluded)) {
            json_decref(o);
            return LC_ERR_INVALID;
        }
        json_t *vis = json_pack("{s:f, s:f, s:f, s:f, s:f}", "topDecileAlpha", h->top_decile_alpha, "bottomHalfAlpha",
                                h->bottom_half_alpha, "coveredFraction", h->covered_fraction, "occluderAlpha",
                                h->occluder_alpha, "importantOccluded", h->important_occluded);
        if (vis && h->has_reach) {
            if (!isfinite(h->top_decile_reach) || h->top_decile_reach < 0) {
                json_decref(vis);
                json_decref(o);
                return LC_ERR_INVALID;
            }
            json_object_set_new(vis, "topDecileReach", json_real(h->top_decile_reach));
        }
        if (vis && h->layer_count > 0 && h->layer_count <= LC_MAX_LAYERS) {
            json_t *layers = json_array();
            for (int i = 0; i < h->layer_count; i++)
                json_array_append_new(layers, json_pack("{s:f, s:f, s:f}", "topDecileAlpha", h->layer_visibility[i][0],
                                                        "bottomHalfAlpha", h->layer_visibility[i][1], "occluderAlpha",
                                                        h->layer_visibility[i][2]));
            json_object_set_new(vis, "layers", layers);
        }
        json_object_set_new(o, "visibility", vis);
    }
    if (o && h->has_detail) {
        if (!isfinite(h->lod_pixels) || !isfinite(h->render_ms) || h->level < 0 || h->point_stride < 1 ||
            h->line_stride < 0 || h->primitives > LC_PROTO_MAX_SEQ) {
            json_decref(o);
            return LC_ERR_INVALID;
        }
        json_object_set_new(o, "detail",
                            json_pack("{s:b, s:b, s:i, s:f, s:i, s:i, s:I, s:f}", "interactive", (int)h->interactive,
                                      "reusedOpacities", (int)h->reused, "level", h->level, "lodPixels", h->lod_pixels,
                                      "pointStride", h->point_stride, "lineStride",
                                      h->line_stride > 1 ? h->line_stride : 1, "primitives", (json_int_t)h->primitives,
                                      "renderMs", h->render_ms));
    }
    if (o && h->has_color_ticks) {
        json_t *ticks = json_array();
        for (int i = 0; i < 5 && ticks; i++) {
            if (!isfinite(h->color_ticks[i])) {
                json_decref(ticks);
                json_decref(o);
                return LC_ERR_INVALID;
            }
            json_array_append_new(ticks, json_real(h->color_ticks[i]));
        }
        json_object_set_new(o, "colorTicks", ticks);
    }
    if (o && h->has_clarity) {
        if (!isfinite(h->clarity_lambda) || !isfinite(h->clarity_penalty)) {
            json_decref(o);
            return LC_ERR_INVALID;
        }
        json_t *c = json_pack("{s:f, s:f, s:b}", "lambdaFactor", h->clarity_lambda, "penaltyFactor", h->clarity_penalty,
                              "reached", (int)h->clarity_reached);
        if (c && h->has_clarity_smoothing)
            json_object_set_new(c, "smoothing", json_integer(h->clarity_smoothing));
        json_object_set_new(o, "clarity", c);
    }
    if (o && h->has_surface) {
        if (!isfinite(h->surface_layers)) {
            json_decref(o);
            return LC_ERR_INVALID;
        }
        json_object_set_new(o, "surface",
                            json_pack("{s:I, s:I, s:f, s:I, s:i, s:I, s:I, s:b}", "curves",
                                      (json_int_t)h->surface_curves, "particles", (json_int_t)h->surface_particles,
                                      "layersPerPixel", h->surface_layers, "overflow", (json_int_t)h->surface_overflow,
                                      "k", h->surface_k, "drawnCurves", (json_int_t)h->surface_drawn_curves,
                                      "drawnFragments", (json_int_t)h->surface_drawn_fragments, "kept",
                                      (int)h->surface_kept));
    }
    if (o && h->stages > 0) {
        if (h->stage < 1 || h->stage > h->stages) {
            json_decref(o);
            return LC_ERR_INVALID;
        }
        json_object_set_new(o, "stage", json_integer(h->stage));
        json_object_set_new(o, "stages", json_integer(h->stages));
        json_object_set_new(o, "final", json_boolean(h->stage == h->stages));
    }
    char *text = dump_and_free(o);
    if (!text)
        return LC_ERR_NOMEM;
    size_t n = strlen(text);
    unsigned char *buf = malloc(4 + n + image_len);
    if (!buf) {
        free(text);
        return LC_ERR_NOMEM;
    }
    buf[0] = (unsigned char)(n & 0xff);
    buf[1] = (unsigned char)((n >> 8) & 0xff);
    buf[2] = (unsigned char)((n >> 16) & 0xff);
    buf[3] = (unsigned char)((n >> 24) & 0xff);
    memcpy(buf + 4, text, n);
    if (image_len)
        memcpy(buf + 4 + n, image, image_len);
    free(text);
    *out = buf;
    *out_len = 4 + n + image_len;
    return 0;
}

int lc_proto_unpack_frame(const unsigned char *msg, size_t len, lc_frame_header *h, const unsigned char **image,
                          size_t *image_len, lc_proto_error *err)
{
    memset(h, 0, sizeof *h);
    *image = NULL;
    *image_len = 0;
    if (!msg || len < 4)
        return lc_proto_set_error(err, LC_PROTO_BAD_FIELD, "", "frame message shorter than its 4-byte length");
    size_t n = (size_t)msg[0] | (size_t)msg[1] << 8 | (size_t)msg[2] << 16 | (size_t)msg[3] << 24;
    if (n > len - 4)
        return lc_proto_set_error(err, LC_PROTO_BAD_FIELD, "", "header length %zu exceeds the message (%zu bytes)", n,
                                  len - 4);
    lc_proto_limits lim;
    lc_proto_limits_default(&lim);
    lim.max_text = LC_PROTO_MAX_FRAME_HEADER;
    lim.max_depth = 4; /* header { visibility { layers [ { } ] } } */
    json_t *o = lc_proto_load((const char *)msg + 4, n, &lim, err);
    if (!o)
        return LC_ERR_INVALID;
    int status = 0;
    bool has_encode_ms = false; /* optional: 0 when absent */
    if (!json_is_object(o)) {
        status = lc_proto_set_error(err, LC_PROTO_BAD_FIELD, "", "frame header is not a JSON object");
        goto done;
    }
    REQUIRE(get_uint(o, "frame", &h->frame, err), "frame");
    REQUIRE(get_int(o, "width", 1, 1 << 30, &h->width, err), "width");
    REQUIRE(get_int(o, "height", 1, 1 << 30, &h->height, err), "height");
    REQUIRE(get_int(o, "quality", 0, 100, &h->quality, err), "quality");
    REQUIRE(get_uint(o, "cameraSeq", &h->camera_seq, err), "cameraSeq");
    const json_t *fmt = json_object_get(o, "format");
    if (!json_is_string(fmt) || (strcmp(json_string_value(fmt), "jpeg") && strcmp(json_string_value(fmt), "png"))) {
        status = lc_proto_set_error(err, LC_PROTO_BAD_FIELD, "format", "expected \"jpeg\" or \"png\"");
        goto done;
    }
    h->format = strcmp(json_string_value(fmt), "png") == 0 ? LC_FORMAT_PNG : LC_FORMAT_JPEG;
    const json_t *conv = json_object_get(o, "converged");
    if (!json_is_boolean(conv)) {
        status = lc_proto_set_error(err, LC_PROTO_BAD_FIELD, "converged", "expected true or false");
        goto done;
    }
    h->converged = json_is_true(conv);
    double ems = 0;
    READ(get_num(o, "encodeMs", 0, false, 1e12, &ems, err), has_encode_ms);
    h->encode_ms = has_encode_ms ? ems : 0;
    const json_t *timings = json_object_get(o, "timings");
    if (timings) {
        const char *key;
        json_t *v;
        if (!json_is_object(timings)) {
            status = lc_proto_set_error(err, LC_PROTO_BAD_FIELD, "timings", "expected an object");
            goto done;
        }
        json_object_foreach((json_t *)timings, key, v)
        {
            if (!json_is_number(v) || h->timing_count >= LC_PROTO_MAX_TIMINGS ||
                strlen(key) >= sizeof h->timings[0].pass) {
                status = lc_proto_set_error(err, LC_PROTO_BAD_FIELD, "timings",
                                            "expected at most %d pass names with numbers", LC_PROTO_MAX_TIMINGS);
                goto done;
            }
            lc_frame_timing *t = &h->timings[h->timing_count++];
            strcpy(t->pass, key);
            t->ms = json_number_value(v);
        }
    }
    const json_t *vis = json_object_get(o, "visibility");
    if (vis) {
        static const char *const keys[] = {"topDecileAlpha", "bottomHalfAlpha", "coveredFraction", "occluderAlpha",
                                           "importantOccluded"};
        double *dst[] = {&h->top_decile_alpha, &h->bottom_half_alpha, &h->covered_fraction, &h->occluder_alpha,
                         &h->important_occluded};
        for (int i = 0; i < 5; i++) {
            const json_t *v = json_is_object(vis) ? json_object_get(vis, keys[i]) : NULL;
            /* occluderAlpha and importantOccluded came later: 0 when absent */
            double x = json_is_number(v) ? json_number_value(v) : i >= 3 && !v ? 0 : -1;
            if (!(x >= 0 && x <= 1)) {
                status = lc_proto_set_error(err, LC_PROTO_BAD_FIELD, "visibility",
                                            "expected an object of numbers in [0, 1] (%s)", keys[i]);
                goto done;
            }
            *dst[i] = x;
        }
        const json_t *reach = json_object_get(vis, "topDecileReach");
        if (reach) {
            double x = json_is_number(reach) ? json_number_value(reach) : -1;
            if (!(x >= 0 && isfinite(x))) {
                status =
                    lc_proto_set_error(err, LC_PROTO_BAD_FIELD, "visibility.topDecileReach", "expected a number >= 0");
                goto done;
            }
            h->has_reach = true, h->top_decile_reach = x;
        }
        const json_t *layers = json_object_get(vis, "layers");
        size_t n = json_is_array(layers) ? json_array_size(layers) : 0;
        if (layers && (!json_is_array(layers) || n > LC_MAX_LAYERS)) {
            status = lc_proto_set_error(err, LC_PROTO_BAD_FIELD, "visibility.layers", "expected an array of at most %d",
                                        LC_MAX_LAYERS);
            goto done;
        }
        for (size_t i = 0; i < n; i++)
            for (int k = 0; k < 3; k++) {
                const json_t *v = json_object_get(json_array_get(layers, i), keys[k == 2 ? 3 : k]);
                double x = json_is_number(v) ? json_number_value(v) : -1;
                if (!(x >= 0 && x <= 1)) {
                    status = lc_proto_set_error(err, LC_PROTO_BAD_FIELD, "visibility.layers",
                                                "expected objects of numbers in [0, 1] (%s)", keys[k == 2 ? 3 : k]);
                    goto done;
                }
                h->layer_visibility[i][k] = x;
            }
        h->layer_count = (int)n;
        h->has_visibility = true;
    }
    const json_t *det = json_object_get(o, "detail");
    if (det) {
        const json_t *lv = json_object_get(det, "level"), *px = json_object_get(det, "lodPixels"),
                     *st = json_object_get(det, "pointStride"), *pr = json_object_get(det, "primitives"),
                     *ms = json_object_get(det, "renderMs"), *in = json_object_get(det, "interactive"),
                     *re = json_object_get(det, "reusedOpacities"), *ls = json_object_get(det, "lineStride");
        if (ls && (!json_is_integer(ls) || json_integer_value(ls) < 1 || json_integer_value(ls) > 1 << 20)) {
            status = lc_proto_set_error(err, LC_PROTO_BAD_FIELD, "detail.lineStride", "expected an integer >= 1");
            goto done;
        }
        if (!json_is_object(det) || !json_is_integer(lv) || json_integer_value(lv) < 0 ||
            json_integer_value(lv) > 255 || !json_is_number(px) || json_number_value(px) < 0 || !json_is_integer(st) ||
            json_integer_value(st) < 1 || json_integer_value(st) > 1 << 20 || !json_is_integer(pr) ||
            json_integer_value(pr) < 0 || !json_is_number(ms) || json_number_value(ms) < 0 || !json_is_boolean(in) ||
            !json_is_boolean(re)) {
            status = lc_proto_set_error(err, LC_PROTO_BAD_FIELD, "detail",
                                        "expected interactive, reusedOpacities (booleans), level, pointStride, "
                                        "primitives (integers) and lodPixels, renderMs (numbers >= 0)");
            goto done;
        }
        h->level = (int)json_integer_value(lv);
        h->lod_pixels = json_number_value(px);
        h->point_stride = (int)json_integer_value(st);
        h->line_stride = ls ? (int)json_integer_value(ls) : 1;
        h->primitives = (uint64_t)json_integer_value(pr);
        h->render_ms = json_number_value(ms);
        h->interactive = json_is_true(in);
        h->reused = json_is_true(re);
        h->has_detail = true;
    }
    const json_t *ticks = json_object_get(o, "colorTicks");
    if (ticks) {
        bool ok = json_is_array(ticks) && json_array_size(ticks) == 5;
        for (int i = 0; i < 5 && ok; i++) {
            const json_t *v = json_array_get(ticks, (size_t)i);
            ok = json_is_number(v) && isfinite(json_number_value(v));
            h->color_ticks[i] = ok ? json_number_value(v) : 0;
        }
        if (!ok) {
            status = lc_proto_set_error(err, LC_PROTO_BAD_FIELD, "colorTicks", "expected an array of 5 numbers");
            goto done;
        }
        h->has_color_ticks = true;
    }
    const json_t *cl = json_object_get(o, "clarity");
    if (cl) {
        const json_t *lf = json_object_get(cl, "lambdaFactor"), *pf = json_object_get(cl, "penaltyFactor"),
                     *re = json_object_get(cl, "reached");
        if (!json_is_number(lf) || !json_is_number(pf) || !json_is_boolean(re) || !(json_number_value(lf) >= 1) ||
            !(json_number_value(pf) >= 1)) {
            status = lc_proto_set_error(err, LC_PROTO_BAD_FIELD, "clarity",
                                        "expected lambdaFactor and penaltyFactor >= 1 and reached");
            goto done;
        }
        h->clarity_lambda = json_number_value(lf), h->clarity_penalty = json_number_value(pf);
        h->clarity_reached = json_is_true(re);
        const json_t *sm = json_object_get(cl, "smoothing");
        if (sm && !(json_is_integer(sm) && json_integer_value(sm) >= 0 && json_integer_value(sm) <= 1000)) {
            status =
                lc_proto_set_error(err, LC_PROTO_BAD_FIELD, "clarity.smoothing", "expected an integer in [0, 1000]");
            goto done;
        }
        h->has_clarity_smoothing = sm != NULL;
        h->clarity_smoothing = sm ? (int)json_integer_value(sm) : 0;
        h->has_clarity = true;
    }
    const json_t *surf = json_object_get(o, "surface");
    if (surf) {
        const json_t *c = json_object_get(surf, "curves"), *pa = json_object_get(surf, "particles"),
                     *l = json_object_get(surf, "layersPerPixel"), *ov = json_object_get(surf, "overflow"),
                     *k = json_object_get(surf, "k");
        if (!json_is_integer(c) || !json_is_integer(pa) || !json_is_number(l) || !json_is_integer(ov) ||
            !json_is_integer(k)) {
            status = lc_proto_set_error(err, LC_PROTO_BAD_FIELD, "surface",
                                        "expected curves, particles, layersPerPixel, overflow and k");
            goto done;
        }
        h->surface_curves = (uint64_t)json_integer_value(c);
        h->surface_particles = (uint64_t)json_integer_value(pa);
        h->surface_layers = json_number_value(l);
        h->surface_overflow = (uint64_t)json_integer_value(ov);
        h->surface_k = (int)json_integer_value(k);
        const json_t *dc = json_object_get(surf, "drawnCurves"), *df = json_object_get(surf, "drawnFragments");
        h->surface_drawn_curves = json_is_integer(dc) ? (uint64_t)json_integer_value(dc) : 0;
        h->surface_drawn_fragments = json_is_integer(df) ? (uint64_t)json_integer_value(df) : 0;
        h->surface_kept = json_is_true(json_object_get(surf, "kept"));
        h->has_surface = true;
    }
    const json_t *stage = json_object_get(o, "stage"), *stages = json_object_get(o, "stages");
    if (stage || stages) {
        if (!json_is_integer(stage) || !json_is_integer(stages) || json_integer_value(stage) < 1 ||
            json_integer_value(stage) > json_integer_value(stages) || json_integer_value(stages) > 16) {
            status = lc_proto_set_error(err, LC_PROTO_BAD_FIELD, "stage", "expected stage 1..stages (at most 16)");
            goto done;
        }
        h->stage = (int)json_integer_value(stage), h->stages = (int)json_integer_value(stages);
    }
    *image = msg + 4 + n;
    *image_len = len - 4 - n;
done:
fail:
    json_decref(o);
    if (status)
        memset(h, 0, sizeof *h);
    return status < 0 ? status : 0;
}
