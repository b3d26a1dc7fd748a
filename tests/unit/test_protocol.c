/* Replays the shared protocol vectors (the JSON files in protocol/vectors/, also read by the
 * browser client's Node tests) and checks round trips and update semantics. */
#include <ctype.h>
#include <math.h>
#include <stdint.h>
#include <string.h>

#include "lc_test.h"
#include "messages.h"
#include "request.h"
#include "request_patch.h"

#define VECTORS LUCENT_SOURCE_DIR "/protocol/vectors/"

static json_t *load_manifest(const char *name)
{
    char path[512];
    snprintf(path, sizeof path, VECTORS "%s", name);
    json_error_t je;
    json_t *m = json_load_file(path, 0, &je);
    CHECK(m != NULL, "%s: %s (line %d)", path, je.text, je.line);
    json_t *cases = m ? json_object_get(m, "cases") : NULL;
    CHECK(json_is_array(cases) && json_array_size(cases) > 0, "%s: no cases", path);
    return m;
}

static int hexval(int c) { return isdigit(c) ? c - '0' : tolower(c) - 'a' + 10; }

/* Decodes hex into a malloc'd buffer. */
static unsigned char *from_hex(const char *hex, size_t *len)
{
    size_t n = strlen(hex) / 2;
    unsigned char *b = malloc(n + 1);
    for (size_t i = 0; i < n; i++)
        b[i] = (unsigned char)(hexval(hex[2 * i]) << 4 | hexval(hex[2 * i + 1]));
    *len = n;
    return b;
}

/* The case's text: "input", "inputHex" or "json" (compact dump). malloc'd. */
static char *case_text(const json_t *c, size_t *len)
{
    const json_t *v;
    if ((v = json_object_get(c, "input"))) {
        *len = json_string_length(v);
        char *s = malloc(*len + 1);
        memcpy(s, json_string_value(v), *len + 1);
        return s;
    }
    if ((v = json_object_get(c, "inputHex")))
        return (char *)from_hex(json_string_value(v), len);
    char *s = json_dumps(json_object_get(c, "json"), JSON_COMPACT | JSON_ENCODE_ANY);
    *len = strlen(s);
    return s;
}

static void case_limits(const json_t *c, lc_proto_limits *lim)
{
    lc_proto_limits_default(lim);
    const json_t *l = json_object_get(c, "limits");
    if (!l)
        return;
    const json_t *v;
    if ((v = json_object_get(l, "minSize")))
        lim->min_size = (int)json_integer_value(v);
    if ((v = json_object_get(l, "maxSize")))
        lim->max_size = (int)json_integer_value(v);
    if ((v = json_object_get(l, "maxPixels")))
        lim->max_pixels = json_integer_value(v);
    if ((v = json_object_get(l, "maxDepth")))
        lim->max_depth = (int)json_integer_value(v);
    if ((v = json_object_get(l, "maxText")))
        lim->max_text = (size_t)json_integer_value(v);
}

/* expect ⊆ actual: objects by key, arrays element-wise, numbers within 1e-9 relative. */
static bool subset(const json_t *expect, const json_t *actual)
{
    if (json_is_number(expect)) {
        if (!json_is_number(actual))
            return false;
        double a = json_number_value(expect), b = json_number_value(actual);
        return fabs(a - b) <= 1e-9 * fmax(1.0, fmax(fabs(a), fabs(b)));
    }
    if (json_is_object(expect)) {
        if (!json_is_object(actual))
            return false;
        const char *key;
        json_t *v;
        json_object_foreach((json_t *)expect, key, v) if (!subset(v, json_object_get(actual, key))) return false;
        return true;
    }
    if (json_is_array(expect)) {
        if (!json_is_array(actual) || json_array_size(expect) != json_array_size(actual))
            return false;
        for (size_t i = 0; i < json_array_size(expect); i++)
            if (!subset(json_array_get(expect, i), json_array_get(actual, i)))
                return false;
        return true;
    }
    return json_equal((json_t *)expect, (json_t *)actual);
}

/* Looks up a dotted path ("importance.range"). */
static const json_t *at_path(const json_t *obj, const char *path)
{
    char buf[128];
    snprintf(buf, sizeof buf, "%s", path);
    const json_t *cur = obj;
    for (char *tok = strtok(buf, "."); tok && cur; tok = strtok(NULL, "."))
        cur = json_object_get(cur, tok);
    return cur;
}

static void check_expect(const char *name, const json_t *c, const json_t *actual)
{
    const json_t *expect = json_object_get(c, "expect");
    if (expect) {
        bool ok = subset(expect, actual);
        char *got = ok ? NULL : json_dumps(actual, JSON_COMPACT);
        CHECK(ok, "%s: output %s does not contain the expected values", name, got ? got : "");
        free(got);
    }
    const json_t *absent = json_object_get(c, "absent");
    for (size_t i = 0; i < json_array_size(absent); i++) {
        const char *p = json_string_value(json_array_get(absent, i));
        CHECK(at_path(actual, p) == NULL, "%s: %s should be absent", name, p);
    }
}

/* The error names the expected code and field, and the message starts with the field. */
static void check_error(const char *name, const json_t *c, int rc, const lc_proto_error *err)
{
    const char *code = json_string_value(json_object_get(c, "code"));
    const char *field = json_string_value(json_object_get(c, "field"));
    CHECK(rc < 0, "%s: accepted, expected %s", name, code);
    if (rc >= 0)
        return;
    CHECK(strcmp(err->code, code) == 0, "%s: code %s (%s), expected %s", name, err->code, err->message, code);
    CHECK(strcmp(err->field, field) == 0, "%s: field '%s', expected '%s' (%s)", name, err->field, field, err->message);
    if (field[0]) {
        size_t n = strlen(field);
        CHECK(strncmp(err->message, field, n) == 0 && strncmp(err->message + n, ": ", 2) == 0,
              "%s: message '%s' should start with the field", name, err->message);
    }
    int want = (!strcmp(code, "too_deep") || !strcmp(code, "too_large")) ? LC_ERR_LIMIT : LC_ERR_INVALID;
    CHECK(rc == want, "%s: status %d, expected %d", name, rc, want);
}

static json_t *default_json(void)
{
    lc_request d;
    lc_request_default(&d);
    return lc_proto_request_to_json(&d);
}

/* to_json -> apply onto defaults -> to_json is exact; through text it is within 15 digits. */
static void check_request_round_trip(const char *name, const lc_request *r)
{
    json_t *a = lc_proto_request_to_json(r);
    lc_request back;
    lc_request_default(&back);
    lc_proto_error err;
    int rc = lc_proto_apply_request(a, NULL, &back, &err);
    CHECK(rc == 0, "%s: round trip rejected: %s", name, err.message);
    json_t *b = lc_proto_request_to_json(&back);
    CHECK(json_equal(a, b), "%s: round trip through JSON differs", name);
    char *text = lc_proto_dump(a);
    rc = lc_proto_parse_request(text, strlen(text), NULL, &back, &err);
    CHECK(rc == 0, "%s: text round trip rejected: %s", name, err.message);
    json_t *c = lc_proto_request_to_json(&back);
    CHECK(subset(a, c) && subset(c, a), "%s: text round trip differs", name);
    free(text);
    json_decref(a);
    json_decref(b);
    json_decref(c);
}

/* Every prefix of a valid input must fail cleanly or parse (sanitizer food). */
static void parse_prefixes(const char *text, size_t len, bool message)
{
    for (size_t n = 0; n < len; n++) {
        lc_request r;
        lc_client_msg m;
        lc_proto_error err;
        if (message) {
            if (lc_proto_parse_client_message(text, n, NULL, &m, &err) == 0)
                lc_client_msg_free(&m);
        } else {
            (void)lc_proto_parse_request(text, n, NULL, &r, &err);
        }
    }
}

static int replay_requests(void)
{
    json_t *man = load_manifest("requests.json");
    json_t *cases = json_object_get(man, "cases");
    json_t *defaults = default_json();
    size_t i;
    json_t *c;
    json_array_foreach(cases, i, c)
    {
        const char *name = json_string_value(json_object_get(c, "name"));
        size_t len;
        char *text = case_text(c, &len);
        lc_proto_limits lim;
        case_limits(c, &lim);
        lc_request r;
        lc_proto_error err;
        int rc = lc_proto_parse_request(text, len, &lim, &r, &err);
        json_t *out = lc_proto_request_to_json(&r);
        if (json_is_true(json_object_get(c, "valid"))) {
            CHECK(rc == 0, "%s: rejected: %s", name, err.message);
            check_expect(name, c, out);
            check_request_round_trip(name, &r);
            if (len < 2000)
                parse_prefixes(text, len, false);
        } else {
            check_error(name, c, rc, &err);
            CHECK(json_equal(out, defaults), "%s: a failed parse must leave the defaults", name);
        }
        json_decref(out);
        free(text);
    }
    size_t n = json_array_size(cases);
    json_decref(defaults);
    json_decref(man);
    return (int)n;
}

/* Percent-decodes in place ('+' is a space, as in HTML forms). */
static void url_decode(char *s)
{
    char *o = s;
    for (; *s; s++) {
        if (*s == '%' && isxdigit((unsigned char)s[1]) && isxdigit((unsigned char)s[2])) {
            *o++ = (char)(hexval(s[1]) << 4 | hexval(s[2]));
            s += 2;
        } else {
            *o++ = *s == '+' ? ' ' : *s;
        }
    }
    *o = '\0';
}

static int apply_query_string(const char *query, const lc_proto_limits *lim, lc_request *r, lc_proto_error *err)
{
    char *copy = strdup(query);
    int rc = 0;
    char *save = NULL;
    for (char *pair = strtok_r(copy, "&", &save); pair && !rc; pair = strtok_r(NULL, "&", &save)) {
        char *eq = strchr(pair, '=');
        char *value = eq ? eq + 1 : (char *)"";
        if (eq)
            *eq = '\0';
        url_decode(pair);
        url_decode(value);
        rc = lc_proto_apply_query(r, pair, value, lim, err);
    }
    free(copy);
    if (!rc)
        rc = lc_proto_validate_request(r, lim, err);
    return rc;
}

static int replay_query(void)
{
    json_t *man = load_manifest("query.json");
    json_t *cases = json_object_get(man, "cases");
    size_t i;
    json_t *c;
    json_array_foreach(cases, i, c)
    {
        const char *name = json_string_value(json_object_get(c, "name"));
        lc_proto_limits lim;
        case_limits(c, &lim);
        lc_request r;
        lc_request_default(&r);
        lc_proto_error err;
        int rc = apply_query_string(json_string_value(json_object_get(c, "input")), &lim, &r, &err);
        if (json_is_true(json_object_get(c, "valid"))) {
            CHECK(rc == 0, "%s: rejected: %s", name, err.message);
            json_t *out = lc_proto_request_to_json(&r);
            check_expect(name, c, out);
            json_decref(out);
            check_request_round_trip(name, &r);
        } else {
            check_error(name, c, rc, &err);
        }
    }
    size_t n = json_array_size(cases);
    json_decref(man);
    return (int)n;
}

static int replay_client_messages(void)
{
    json_t *man = load_manifest("client_messages.json");
    json_t *cases = json_object_get(man, "cases");
    size_t i;
    json_t *c;
    json_array_foreach(cases, i, c)
    {
        const char *name = json_string_value(json_object_get(c, "name"));
        size_t len;
        char *text = case_text(c, &len);
        lc_proto_limits lim;
        case_limits(c, &lim);
        lc_client_msg m;
        lc_proto_error err;
        int rc = lc_proto_parse_client_message(text, len, &lim, &m, &err);
        if (json_is_true(json_object_get(c, "valid"))) {
            CHECK(rc == 0, "%s: rejected: %s", name, err.message);
            if (rc == 0) {
                json_t *out = lc_proto_client_message_to_json(&m);
                check_expect(name, c, out);
                /* Round trip: dump -> parse -> same message. */
                char *again = lc_proto_dump(out);
                lc_client_msg m2;
                rc = lc_proto_parse_client_message(again, strlen(again), &lim, &m2, &err);
                CHECK(rc == 0, "%s: round trip rejected: %s", name, err.message);
                if (rc == 0) {
                    json_t *out2 = lc_proto_client_message_to_json(&m2);
                    CHECK(json_equal(out, out2), "%s: round trip differs", name);
                    json_decref(out2);
                    lc_client_msg_free(&m2);
                }
                free(again);
                json_decref(out);
                lc_client_msg_free(&m);
            }
            parse_prefixes(text, len, true);
        } else {
            check_error(name, c, rc, &err);
            CHECK(m.update == NULL, "%s: a failed parse must not hold an update", name);
            lc_client_msg_free(&m); /* safe after failure */
        }
        free(text);
    }
    size_t n = json_array_size(cases);
    json_decref(man);
    return (int)n;
}

static int replay_frames(void)
{
    json_t *man = load_manifest("frames.json");
    json_t *cases = json_object_get(man, "cases");
    size_t i;
    json_t *c;
    json_array_foreach(cases, i, c)
    {
        const char *name = json_string_value(json_object_get(c, "name"));
        size_t plen;
        unsigned char *packed = from_hex(json_string_value(json_object_get(c, "packedHex")), &plen);
        lc_frame_header h;
        const unsigned char *img;
        size_t img_len;
        lc_proto_error err;
        int rc = lc_proto_unpack_frame(packed, plen, &h, &img, &img_len, &err);
        if (!json_is_true(json_object_get(c, "valid"))) {
            CHECK(rc < 0, "%s: unpack accepted an invalid frame", name);
            free(packed);
            continue;
        }
        CHECK(rc == 0, "%s: unpack failed: %s", name, err.message);
        const json_t *hj = json_object_get(c, "header");
        size_t ilen;
        unsigned char *image = from_hex(json_string_value(json_object_get(c, "imageHex")), &ilen);
        CHECK(img_len == ilen && (ilen == 0 || memcmp(img, image, ilen) == 0), "%s: image bytes differ", name);
        CHECK(h.frame == (uint64_t)json_integer_value(json_object_get(hj, "frame")), "%s: frame", name);
        CHECK(h.width == json_integer_value(json_object_get(hj, "width")), "%s: width", name);
        CHECK(h.height == json_integer_value(json_object_get(hj, "height")), "%s: height", name);
        CHECK(h.quality == json_integer_value(json_object_get(hj, "quality")), "%s: quality", name);
        CHECK(h.camera_seq == (uint64_t)json_integer_value(json_object_get(hj, "cameraSeq")), "%s: cameraSeq", name);
        CHECK(h.converged == json_is_true(json_object_get(hj, "converged")), "%s: converged", name);
        CHECK((h.format == LC_FORMAT_PNG) == !strcmp(json_string_value(json_object_get(hj, "format")), "png"),
              "%s: format", name);
        CHECK_NEAR(h.encode_ms, json_number_value(json_object_get(hj, "encodeMs")), 1e-12, "encodeMs");
        const json_t *t = json_object_get(hj, "timings");
        CHECK((size_t)h.timing_count == json_object_size(t), "%s: %d timings", name, h.timing_count);
        for (int k = 0; k < h.timing_count; k++)
            CHECK_NEAR(h.timings[k].ms, json_number_value(json_object_get(t, h.timings[k].pass)), 1e-12, "timing");
        /* Packing the unpacked header gives the vector's bytes exactly. */
        unsigned char *out;
        size_t out_len;
        rc = lc_proto_pack_frame(&h, image, ilen, &out, &out_len);
        CHECK(rc == 0 && out_len == plen && memcmp(out, packed, plen) == 0, "%s: pack differs from packedHex", name);
        if (rc == 0 && (out_len != plen || memcmp(out, packed, plen) != 0))
            fprintf(stderr, "  packed: %.*s\n", (int)(out_len - 4 - ilen), out + 4);
        free(out);
        free(image);
        free(packed);
    }
    size_t n = json_array_size(cases);
    json_decref(man);
    return (int)n;
}

static const char *opt_str(const json_t *o, const char *key) { return json_string_value(json_object_get(o, key)); }

static int replay_server_messages(void)
{
    json_t *man = load_manifest("server_messages.json");
    json_t *cases = json_object_get(man, "cases");
    size_t i;
    json_t *c;
    json_array_foreach(cases, i, c)
    {
        const char *name = opt_str(c, "name"), *kind = opt_str(c, "kind");
        const json_t *a = json_object_get(c, "args");
        char *text = NULL;
        if (!strcmp(kind, "error"))
            text = lc_proto_error_message_json(opt_str(a, "code"), opt_str(a, "message"), opt_str(a, "field"),
                                               json_is_true(json_object_get(a, "fatal")));
        else if (!strcmp(kind, "httpError"))
            text = lc_proto_error_json(opt_str(a, "code"), opt_str(a, "message"), opt_str(a, "field"));
        else if (!strcmp(kind, "stats"))
            text = lc_proto_stats_json(json_object_get(a, "fields"));
        else if (!strcmp(kind, "progress"))
            text = lc_proto_progress_json(opt_str(a, "stage"), json_number_value(json_object_get(a, "fraction")),
                                          json_number_value(json_object_get(a, "elapsed")));
        CHECK(text && !strcmp(text, opt_str(c, "output")), "%s: got %s", name, text ? text : "NULL");
        free(text);
    }
    size_t n = json_array_size(cases);
    json_decref(man);
    return (int)n;
}

/* ---- behaviour the vectors cannot express */

static void test_defaults(void)
{
    lc_proto_limits l;
    lc_proto_limits_default(&l);
    CHECK(l.min_size == 16 && l.max_size == 8192 && l.max_pixels == 8192LL * 4608 && l.max_depth == 16,
          "limit defaults");
    lc_request r;
    lc_request_default(&r);
    lc_render_params p;
    lc_render_params_default(&p);
    /* The clarity loop is a request's default, not the renderer's (ALGORITHM §25). */
    CHECK(p.foo.clarity == 0 && r.render.foo.clarity == LC_DEFAULT_CLARITY, "clarity default %g / %g", p.foo.clarity,
          r.render.foo.clarity);
    p.foo.clarity = LC_DEFAULT_CLARITY;
    CHECK(memcmp(&r.render.foo, &p.foo, sizeof p.foo) == 0, "FOO defaults come from lc_render_params_default");
    CHECK(r.format == LC_FORMAT_PNG && r.quality == 90 && !r.has_dt && !r.render.has_camera, "request defaults");
}

static void test_partial_update(void)
{
    lc_request r;
    lc_request_default(&r);
    lc_proto_error err;
    json_t *u = json_loads("{\"params\":{\"bands\":3},\"style\":{\"lineWidth\":0.5}}", 0, NULL);
    CHECK(lc_proto_apply_request(u, NULL, &r, &err) == 0, "update: %s", err.message);
    json_decref(u);
    CHECK(r.render.foo.bands == 3 && r.render.style.line_width == 0.5 && r.render.foo.q == 60,
          "only given fields change");

    /* All or nothing: a bad field after a good one changes nothing. */
    u = json_loads("{\"params\":{\"bands\":4,\"q\":-1}}", 0, NULL);
    CHECK(lc_proto_apply_request(u, NULL, &r, &err) == LC_ERR_INVALID, "bad update rejected");
    json_decref(u);
    CHECK(r.render.foo.bands == 3, "a rejected update leaves the request untouched");

    /* Camera updates merge; null drops the camera. */
    u = json_loads("{\"camera\":{\"position\":[0,0,5]}}", 0, NULL);
    CHECK(lc_proto_apply_request(u, NULL, &r, &err) == 0, "camera: %s", err.message);
    json_decref(u);
    u = json_loads("{\"camera\":{\"viewAngle\":50}}", 0, NULL);
    CHECK(lc_proto_apply_request(u, NULL, &r, &err) == 0, "camera merge: %s", err.message);
    json_decref(u);
    CHECK(r.render.has_camera && r.render.camera.position[2] == 5 && r.render.camera.view_angle == 50,
          "camera fields merge");
    u = json_loads("{\"camera\":null}", 0, NULL);
    CHECK(lc_proto_apply_request(u, NULL, &r, &err) == 0, "camera null: %s", err.message);
    json_decref(u);
    CHECK(!r.render.has_camera, "camera null drops the camera");

    /* A camera update that makes the merged camera degenerate is rejected. */
    u = json_loads("{\"camera\":{\"position\":[0,0,5]}}", 0, NULL);
    lc_proto_apply_request(u, NULL, &r, &err);
    json_decref(u);
    u = json_loads("{\"camera\":{\"viewUp\":[0,0,1]}}", 0, NULL);
    CHECK(lc_proto_apply_request(u, NULL, &r, &err) < 0 && !strcmp(err.field, "camera.viewUp"),
          "merged camera checked: %s", err.message);
    json_decref(u);
    CHECK(r.render.camera.view_up[1] == 1, "merged camera untouched after rejection");

    /* NULL err and NULL limits are allowed. */
    CHECK(lc_proto_parse_request("{\"width\":1}", 11, NULL, &r, NULL) == LC_ERR_INVALID, "NULL err");
    CHECK(lc_proto_parse_request("[[[[[[[[[[[[[[[[[[[]]]]]]]]]]]]]]]]]]]", 38, NULL, &r, NULL) == LC_ERR_LIMIT,
          "NULL err, limit");
}

/* Whether a packed frame's header text holds needle (the frame is not NUL-terminated). */
static bool frame_text_has(const unsigned char *out, size_t out_len, const char *needle)
{
    char json[2048];
    snprintf(json, sizeof json, "%.*s", out_len > 4 ? (int)(out_len - 4) : 0, (const char *)out + 4);
    return strstr(json, needle) != NULL;
}

static void test_messages(void)
{
    lc_client_msg m;
    lc_proto_error err;
    const char *hello = "{\"type\":\"hello\",\"width\":800,\"height\":600,\"params\":{\"q\":80},\"quality\":95}";
    CHECK(lc_proto_parse_client_message(hello, strlen(hello), NULL, &m, &err) == 0, "hello: %s", err.message);
    CHECK(m.type == LC_MSG_HELLO && m.window == 2 && !m.has_window && m.device_pixel_ratio == 1.0 &&
              !m.has_device_pixel_ratio,
          "hello defaults");
    CHECK(json_object_size(m.update) == 1 && json_object_get(m.update, "params"), "update holds only params");
    lc_request r;
    lc_request_default(&r);
    CHECK(lc_proto_apply_request(m.update, NULL, &r, &err) == 0 && r.render.foo.q == 80, "update applies");
    lc_stream_settings s;
    lc_proto_stream_default(&s);
    lc_proto_stream_apply(&s, &m);
    CHECK(s.quality == 95 && s.window == 2 && s.interactive_quality == LC_PROTO_DEFAULT_INTERACTIVE_QUALITY,
          "stream settings");
    lc_client_msg_free(&m);
    lc_client_msg_free(&m); /* idempotent */

    const char *ack = "{\"type\":\"ack\",\"frame\":41}";
    CHECK(lc_proto_parse_client_message(ack, strlen(ack), NULL, &m, NULL) == 0 && m.frame == 41 && !m.update, "ack");

    json_t *info = json_pack("{s:s, s:i}", "name", "demo:tornado", "lines", 100);
    char *ready = lc_proto_ready_json("s1", info, NULL, NULL, NULL);
    json_t *rj = json_loads(ready, 0, NULL);
    json_t *def = default_json();
    CHECK(rj && !strcmp(json_string_value(json_object_get(rj, "type")), "ready") &&
              !strcmp(json_string_value(json_object_get(rj, "session")), "s1") &&
              json_equal(json_object_get(rj, "dataset"), info),
          "ready: %s", ready);
    lc_request back;
    CHECK(lc_proto_apply_request(json_object_get(rj, "defaults"), NULL, (lc_request_default(&back), &back), &err) == 0,
          "ready defaults parse back: %s", err.message);
    json_t *bj = lc_proto_request_to_json(&back);
    CHECK(json_equal(bj, def), "ready defaults are the default request");
    CHECK(json_integer_value(at_path(rj, "limits.maxSize")) == 8192 &&
              json_integer_value(at_path(rj, "stream.window")) == 2,
          "ready limits and stream");
    json_decref(bj);
    json_decref(def);
    json_decref(rj);
    json_decref(info);
    free(ready);

    lc_proto_error e;
    lc_proto_set_error(&e, LC_PROTO_UNKNOWN_FIELD, "params.bandz", "unknown field");
    CHECK(!strcmp(e.message, "params.bandz: unknown field"), "message format: %s", e.message);
    char *body = lc_proto_error_json_from(&e);
    CHECK(!strcmp(body, "{\"error\":{\"code\":\"unknown_field\",\"message\":\"params.bandz: unknown field\","
                        "\"field\":\"params.bandz\"}}"),
          "error body %s", body);
    free(body);

    /* Frame packing rejects what a client could not represent. */
    lc_frame_header h = {.frame = LC_PROTO_MAX_SEQ + 1, .width = 1, .height = 1};
    unsigned char *out;
    size_t out_len;
    CHECK(lc_proto_pack_frame(&h, NULL, 0, &out, &out_len) == LC_ERR_INVALID, "frame id above 2^53-1");

    /* colorTicks (color.equalize): five numbers round trip; anything else is refused naming the key. */
    lc_frame_header t = {
        .frame = 3, .width = 4, .height = 2, .has_color_ticks = true, .color_ticks = {-1.5, 0.25, 2, 3.125, 1e3}};
    CHECK(lc_proto_pack_frame(&t, NULL, 0, &out, &out_len) == 0, "pack colorTicks");
    lc_frame_header tb;
    const unsigned char *img;
    size_t img_len;
    lc_proto_error perr;
    CHECK(lc_proto_unpack_frame(out, out_len, &tb, &img, &img_len, &perr) == 0 && tb.has_color_ticks &&
              memcmp(tb.color_ticks, t.color_ticks, sizeof t.color_ticks) == 0,
          "colorTicks round trip");
    CHECK(frame_text_has(out, out_len, "\"colorTicks\":[-1.5,0.25,2.0,3.125,1000.0]"), "colorTicks JSON: %.*s",
          (int)out_len - 4, (const char *)out + 4);
    free(out);
    /* visibility.importantOccluded round trips; a header without it (an older server) reads 0. */
    lc_frame_header v = {.frame = 5,
                         .width = 4,
                         .height = 2,
                         .has_visibility = true,
                         .top_decile_alpha = 0.75,
                         .bottom_half_alpha = 0.125,
                         .covered_fraction = 0.5,
                         .occluder_alpha = 0.25,
                         .important_occluded = 0.375};
    CHECK(lc_proto_pack_frame(&v, NULL, 0, &out, &out_len) == 0, "pack visibility");
    CHECK(lc_proto_unpack_frame(out, out_len, &tb, &img, &img_len, &perr) == 0 && tb.has_visibility &&
              tb.important_occluded == 0.375 && tb.occluder_alpha == 0.25,
          "importantOccluded round trip");
    CHECK(frame_text_has(out, out_len, "\"importantOccluded\":0.375"), "importantOccluded JSON: %.*s", (int)out_len - 4,
          (const char *)out + 4);
    /* visibility.topDecileReach (fourier frames) round trips, may pass 1, and is absent without it. */
    CHECK(!tb.has_reach && !frame_text_has(out, out_len, "topDecileReach"), "no topDecileReach unless measured");
    free(out);
    v.has_reach = true, v.top_decile_reach = 1.375;
    CHECK(lc_proto_pack_frame(&v, NULL, 0, &out, &out_len) == 0, "pack topDecileReach");
    CHECK(lc_proto_unpack_frame(out, out_len, &tb, &img, &img_len, &perr) == 0 && tb.has_reach &&
              tb.top_decile_reach == 1.375,
          "topDecileReach round trip");
    free(out);
    /* clarity.smoothing: only where the loop cut the smoothing. */
    lc_frame_header c = {.frame = 6,
                         .width = 4,
                         .height = 2,
                         .has_clarity = true,
                         .clarity_lambda = 3,
                         .clarity_penalty = 2.5,
                         .has_clarity_smoothing = true,
                         .clarity_smoothing = 7};
    CHECK(lc_proto_pack_frame(&c, NULL, 0, &out, &out_len) == 0, "pack clarity.smoothing");
    CHECK(lc_proto_unpack_frame(out, out_len, &tb, &img, &img_len, &perr) == 0 && tb.has_clarity_smoothing &&
              tb.clarity_smoothing == 7 && tb.clarity_penalty == 2.5,
          "clarity.smoothing round trip");
    free(out);
    c.has_clarity_smoothing = false;
    CHECK(lc_proto_pack_frame(&c, NULL, 0, &out, &out_len) == 0 && !frame_text_has(out, out_len, "smoothing"),
          "no clarity.smoothing unless cut");
    free(out);
    v.top_decile_reach = -0.5;
    CHECK(lc_proto_pack_frame(&v, NULL, 0, &out, &out_len) == LC_ERR_INVALID, "a negative topDecileReach is refused");
    {
        char text[200];
        int n = snprintf(text + 4, sizeof text - 4,
                         "{\"frame\":1,\"width\":1,\"height\":1,\"format\":\"jpeg\",\"quality\":80,\"cameraSeq\":0,"
                         "\"converged\":true,\"visibility\":{\"topDecileAlpha\":0.5,\"bottomHalfAlpha\":0.1,"
                         "\"coveredFraction\":0.2}}");
        text[0] = (char)n, text[1] = text[2] = text[3] = 0; /* little-endian length, n < 256 */
        CHECK(lc_proto_unpack_frame((const unsigned char *)text, (size_t)n + 4, &tb, &img, &img_len, &perr) == 0 &&
                  tb.important_occluded == 0 && tb.occluder_alpha == 0,
              "a visibility without occluderAlpha and importantOccluded reads 0: %s", perr.message);
    }
    t.color_ticks[2] = NAN;
    CHECK(lc_proto_pack_frame(&t, NULL, 0, &out, &out_len) == LC_ERR_INVALID, "a non-finite tick is refused");
    static const char *const bad[] = {"[1,2,3,4]", "[1,2,3,4,\"5\"]", "{}"};
    for (int i = 0; i < 3; i++) {
        char text[160];
        int n = snprintf(text + 4, sizeof text - 4,
                         "{\"frame\":1,\"width\":1,\"height\":1,\"format\":\"jpeg\",\"quality\":80,"
                         "\"cameraSeq\":0,\"converged\":true,\"colorTicks\":%s}",
                         bad[i]);
        text[0] = (char)n, text[1] = text[2] = text[3] = 0;
        CHECK(lc_proto_unpack_frame((const unsigned char *)text, (size_t)n + 4, &tb, &img, &img_len, &perr) != 0 &&
                  !strcmp(perr.field, "colorTicks"),
              "colorTicks %s refused naming the key", bad[i]);
    }
}

/* params.clarity: the loop acts only while q, r and lambda are not given, so
 * the parser records whether any was; emission still writes them. */
static void test_clarity(void)
{
    lc_request r;
    lc_proto_error err = {0};
    const char *plain = "{\"params\":{\"clarity\":0.7}}";
    CHECK(lc_proto_parse_request(plain, strlen(plain), NULL, &r, &err) == 0, "%s", err.message);
    CHECK(r.render.foo.clarity == 0.7 && !r.render.foo.strength_given, "clarity alone: %g, given %d",
          r.render.foo.clarity, r.render.foo.strength_given);
    json_t *j = lc_proto_request_to_json(&r);
    json_t *params = json_object_get(j, "params");
    CHECK(json_number_value(json_object_get(params, "q")) == 60 &&
              json_number_value(json_object_get(params, "lambda")) == 1 &&
              json_number_value(json_object_get(params, "clarity")) == 0.7,
          "q, lambda and clarity emitted");
    json_decref(j);
    static const char *const given[] = {"{\"params\":{\"q\":60}}", "{\"params\":{\"r\":10}}",
                                        "{\"params\":{\"lambda\":1}}"};
    for (int i = 0; i < 3; i++) {
        CHECK(lc_proto_parse_request(given[i], strlen(given[i]), NULL, &r, &err) == 0, "%s", err.message);
        CHECK(r.render.foo.strength_given && r.render.foo.clarity == LC_DEFAULT_CLARITY, "%s: strength given",
              given[i]);
    }
    const char *bad = "{\"params\":{\"clarity\":1.5}}";
    CHECK(lc_proto_parse_request(bad, strlen(bad), NULL, &r, &err) != 0 && strcmp(err.field, "params.clarity") == 0,
          "clarity 1.5 refused naming the field (%s)", err.field);
}

/* A typed patch (request_patch.h) merges exactly as lc_proto_apply_request
 * applies the same update: equal requests (as emitted) or the same refused
 * field, on a request without a camera and on one with a camera and lists set.
 * The updates: every valid client message of the vectors that carries one, and
 * explicit ones for each kind of field (lists, flags, layers, camera merge and
 * drop, a camera that only the merged state refuses). */
static int patch_case(const char *name, json_t *update, const lc_request *base)
{
    lc_request ra_req, rb_req, *a = &ra_req, *b = &rb_req; /* copies share base's layers */
    lc_request_copy(a, base), lc_request_copy(b, base);
    lc_proto_error ea = {0}, eb = {0};
    int ra = lc_proto_apply_request(update, NULL, a, &ea);
    lc_request_patch *p = NULL;
    int rb = lc_proto_patch_parse(update, NULL, &p, &eb);
    if (rb == 0)
        rb = lc_proto_patch_apply(p, NULL, b, &eb);
    lc_proto_patch_free(p);
    json_t *ja = lc_proto_request_to_json(a), *jb = lc_proto_request_to_json(b);
    CHECK((ra == 0) == (rb == 0), "%s: apply %d, patch %d (%s | %s)", name, ra, rb, ea.message, eb.message);
    if (ra == 0 && rb == 0)
        CHECK(json_equal(ja, jb), "%s: the patched request differs from the applied one", name);
    else if (ra != 0 && rb != 0)
        CHECK(strcmp(ea.field, eb.field) == 0, "%s: refused naming %s, the patch %s", name, ea.field, eb.field);
    json_decref(ja), json_decref(jb);
    lc_request_release(a), lc_request_release(b);
    return 1;
}

static void test_patch(void)
{
    lc_request base[2];
    lc_request_default(&base[0]);
    const char *setup = "{\"camera\":{\"position\":[0,0,5],\"focalPoint\":[0,0,0],\"viewUp\":[0,1,0]},"
                        "\"importance\":{\"range\":[0,1],\"terms\":[{\"attribute\":\"a\"}]},"
                        "\"filter\":[{\"attribute\":\"b\",\"gt\":1}],\"color\":{\"fixed\":[[0,1]]}}";
    lc_proto_error err;
    CHECK(lc_proto_parse_request(setup, strlen(setup), NULL, &base[1], &err) == 0, "patch base: %s", err.message);
    static const char *const updates[] = {
        "{\"params\":{\"q\":3,\"bands\":7},\"method\":\"direct\"}",
        "{\"camera\":{\"viewAngle\":40}}",
        "{\"camera\":{\"position\":[1,2,3]}}",
        "{\"camera\":null}",
        "{\"camera\":{\"position\":[0,5,0],\"focalPoint\":[0,0,0]}}",
        "{\"importance\":{\"range\":[2,3],\"terms\":[]},\"filter\":[]}",
        "{\"importance\":{\"curve\":[[0,0],[0.5,0.8],[1,1]]},\"color\":{\"fixed\":[[1,2],[3,4]]}}",
        "{\"filter\":[{\"attribute\":\"c\",\"range\":[0,2]}],\"time\":{\"window\":[0,1]}}",
        "{\"layers\":[{\"dataset\":\"demo:points\",\"color\":{\"equalize\":true}},{\"dataset\":\"x\"}]}",
        "{\"surface\":{\"seed\":[[0,0,0],[1,1,1]],\"field\":\"demo:abc-flow\"},\"method\":\"surface-layers\"}",
        "{\"style\":{\"background\":[0.1,0.2,0.3],\"shadowLight\":[1,1,0]},\"lines\":{\"clusters\":4}}",
        "{\"params\":{\"bands\":9}}",
    };
    int n = 0;
    for (size_t i = 0; i < sizeof updates / sizeof updates[0]; i++) {
        json_error_t je;
        json_t *u = json_loads(updates[i], 0, &je);
        CHECK(u != NULL, "update %zu: %s", i, je.text);
        for (int k = 0; u && k < 2; k++)
            n += patch_case(updates[i], u, &base[k]);
        json_decref(u);
    }
    json_t *man = load_manifest("client_messages.json");
    json_t *cases = json_object_get(man, "cases");
    size_t i;
    json_t *c;
    json_array_foreach(cases, i, c)
    {
        size_t len;
        char *text = case_text(c, &len);
        lc_client_msg m;
        if (lc_proto_parse_client_message(text, len, NULL, &m, &err) == 0 && m.update) {
            CHECK(m.patch != NULL, "%s: a parsed update carries its patch", opt_str(c, "name"));
            for (int k = 0; k < 2; k++)
                n += patch_case(opt_str(c, "name"), m.update, &base[k]);
        }
        lc_client_msg_free(&m);
        free(text);
    }
    printf("patches: %d cases merged as lc_proto_apply_request applies them\n", n);
    json_decref(man);
    lc_request_release(&base[0]), lc_request_release(&base[1]);
}

int main(void)
{
    int nreq = replay_requests();
    int nq = replay_query();
    int nmsg = replay_client_messages();
    int nfr = replay_frames();
    int nsv = replay_server_messages();
    printf("vectors: %d requests, %d query, %d client messages, %d frames, %d server messages\n", nreq, nq, nmsg, nfr,
           nsv);
    test_defaults();
    test_clarity();
    test_partial_update();
    test_messages();
    test_patch();
    return lc_test_finish();
}
