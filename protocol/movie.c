/* Parsing and validation of movie requests (movie.h). */
#include "movie.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const char *const PATHS[] = {"turntable", "orbit", "keyframes"};
static const char *const CODECS[] = {"h264", "vp9"};

static int bad(lc_proto_error *err, const char *code, const char *field, const char *reason)
{
    return lc_proto_set_error(err, code, field, "%s", reason);
}

/* err = pe nested under prefix: field "prefix.field", message "prefix.field: reason". */
static int nest(lc_proto_error *err, const char *prefix, const lc_proto_error *pe)
{
    size_t n = strlen(pe->field);
    const char *reason = pe->message;
    if (n && strncmp(reason, pe->field, n) == 0 && strncmp(reason + n, ": ", 2) == 0)
        reason += n + 2;
    char f[320];
    snprintf(f, sizeof f, "%s%s%s", prefix, n ? "." : "", pe->field);
    return lc_proto_set_error(err, pe->code, f, "%s", reason);
}

/* A number field in [lo, hi] (lo_open: lo excluded); absent keeps *out. */
static int number(const json_t *o, const char *key, double lo, bool lo_open, double hi, double *out,
                  lc_proto_error *err)
{
    const json_t *v = json_object_get(o, key);
    if (!v)
        return 0;
    if (!json_is_number(v))
        return bad(err, LC_PROTO_BAD_FIELD, key, "expected a number");
    double x = json_number_value(v);
    if ((lo_open ? x <= lo : x < lo) || x > hi)
        return lc_proto_set_error(err, LC_PROTO_OUT_OF_RANGE, key, "%g is outside %s%g, %g]", x, lo_open ? "(" : "[",
                                  lo, hi);
    *out = x;
    return 0;
}

static int integer(const json_t *o, const char *key, int lo, int hi, int *out, lc_proto_error *err)
{
    double x = *out;
    int rc = number(o, key, lo, false, hi, &x, err);
    if (rc)
        return rc;
    if (x != floor(x))
        return bad(err, LC_PROTO_BAD_FIELD, key, "expected an integer");
    *out = (int)x;
    return 0;
}

/* A keyframe: a camera object (merged onto the default camera, as a one-shot
 * request's) or the web page's URL state ("#position=...&focalPoint=..."),
 * whose camera keys are applied as query parameters; other keys of a page
 * link (dataset, params, stream settings) are skipped, unknown ones refused. */
static int keyframe(const json_t *v, int i, const lc_proto_limits *lim, lc_camera *out, lc_proto_error *err)
{
    char field[48];
    snprintf(field, sizeof field, "keyframes[%d]", i);
    lc_request r;
    lc_request_default(&r);
    lc_proto_error pe;
    int rc = 0;
    if (json_is_object(v)) {
        json_t *wrap = json_pack("{sO}", "camera", (json_t *)v);
        rc = wrap ? lc_proto_apply_request(wrap, lim, &r, &pe) : bad(&pe, LC_PROTO_BAD_FIELD, "", "out of memory");
        json_decref(wrap);
    } else if (json_is_string(v)) {
        const char *s = json_string_value(v);
        const char *hash = strchr(s, '#');
        char *text = strdup(hash ? hash + 1 : s);
        char *save = NULL;
        for (char *part = text ? strtok_r(text, "&", &save) : NULL; part && rc == 0;
             part = strtok_r(NULL, "&", &save)) {
            char *eq = strchr(part, '=');
            const char *value = eq ? eq + 1 : "";
            if (eq)
                *eq = 0;
            static const char *const skip[] = {"dataset", "method", "quality", "interactiveQuality",
                                               "interactiveScale"};
            bool skipped = false;
            for (size_t k = 0; k < sizeof skip / sizeof skip[0]; k++)
                skipped |= strcmp(part, skip[k]) == 0;
            if (!skipped)
                rc = lc_proto_apply_query(&r, part, value, lim, &pe); /* values of page links are not %-encoded */
        }
        free(text);
        if (rc == 0)
            rc = lc_proto_validate_request(&r, lim, &pe);
        if (rc == 0 && !r.render.has_camera)
            rc = bad(&pe, LC_PROTO_BAD_FIELD, "", "the link has no camera (position, focalPoint, viewUp)");
    } else {
        return lc_proto_set_error(err, LC_PROTO_BAD_FIELD, field, "expected a camera object or a URL state string");
    }
    lc_request_release(&r); /* a page link may name layers */
    if (rc != 0)
        return nest(err, field, &pe);
    *out = r.render.camera;
    return 0;
}

int lc_proto_parse_movie(const char *json, size_t len, const lc_proto_limits *lim, lc_movie_spec *m,
                         lc_proto_error *err)
{
    lc_proto_limits dl;
    if (!lim) {
        lc_proto_limits_default(&dl);
        lim = &dl;
    }
    memset(m, 0, sizeof *m);
    lc_request_default(&m->request);
    m->request.render.width = 960;
    m->request.render.height = 540;
    m->path = LC_MOVIE_TURNTABLE;
    m->degrees = 360;
    m->elevation = 20;
    m->fps = 30;
    m->duration = 10;
    snprintf(m->codec, sizeof m->codec, "h264");

    json_t *o = lc_proto_load(json, len, lim, err);
    if (!o)
        return LC_ERR_INVALID;
    int rc = 0;
    if (!json_is_object(o))
        rc = bad(err, LC_PROTO_BAD_FIELD, "", "expected a JSON object");
    static const char *const keys[] = {"request", "path",   "keyframes", "degrees", "elevation", "duration",
                                       "fps",     "frames", "width",     "height",  "codec"};
    const char *key;
    json_t *v;
    json_object_foreach(o, key, v)
    {
        bool known = false;
        for (size_t i = 0; i < sizeof keys / sizeof keys[0]; i++)
            known |= strcmp(key, keys[i]) == 0;
        if (!known && rc == 0)
            rc = lc_proto_set_error(err, LC_PROTO_UNKNOWN_FIELD, key, "unknown field");
    }
    json_t *req = json_object_get(o, "request");
    if (rc == 0 && req) {
        lc_proto_error pe;
        if (!json_is_object(req))
            rc = bad(err, LC_PROTO_BAD_FIELD, "request", "expected a render request object");
        else if (json_object_get(req, "width") || json_object_get(req, "height"))
            rc = bad(err, LC_PROTO_BAD_FIELD, json_object_get(req, "width") ? "request.width" : "request.height",
                     "give the size as the movie's width and height");
        else if (lc_proto_apply_request(req, lim, &m->request, &pe) != 0)
            rc = nest(err, "request", &pe);
    }
    const json_t *path = json_object_get(o, "path");
    if (rc == 0 && path) {
        int found = -1;
        for (int i = 0; i < 3; i++)
            if (json_is_string(path) && strcmp(json_string_value(path), PATHS[i]) == 0)
                found = i;
        if (found < 0)
            rc = bad(err, LC_PROTO_BAD_FIELD, "path", "expected \"turntable\", \"orbit\" or \"keyframes\"");
        else
            m->path = (lc_movie_path)found;
    }
    const json_t *keys_v = json_object_get(o, "keyframes");
    if (rc == 0 && keys_v && !path)
        m->path = LC_MOVIE_KEYFRAMES;
    if (rc == 0 && m->path == LC_MOVIE_KEYFRAMES) {
        if (!json_is_array(keys_v))
            rc = bad(err, LC_PROTO_BAD_FIELD, "keyframes", "a keyframe path needs an array of at least two keyframes");
        else if (json_array_size(keys_v) < 2)
            rc = lc_proto_set_error(err, LC_PROTO_OUT_OF_RANGE, "keyframes",
                                    "a path needs at least two keyframes (got %zu)", json_array_size(keys_v));
        else if (json_array_size(keys_v) > LC_MOVIE_MAX_KEYFRAMES)
            rc = lc_proto_set_error(err, LC_PROTO_OUT_OF_RANGE, "keyframes", "%zu keyframes exceed the limit of %d",
                                    json_array_size(keys_v), LC_MOVIE_MAX_KEYFRAMES);
        for (size_t i = 0; rc == 0 && i < json_array_size(keys_v); i++)
            rc = keyframe(json_array_get(keys_v, i), (int)i, lim, &m->keyframes[i], err);
        if (rc == 0)
            m->keyframe_count = (int)json_array_size(keys_v);
    } else if (rc == 0 && keys_v) {
        rc = bad(err, LC_PROTO_BAD_FIELD, "keyframes", "only a \"keyframes\" path takes keyframes");
    }
    if (rc == 0)
        rc = number(o, "degrees", -3600, false, 3600, &m->degrees, err);
    if (rc == 0)
        rc = number(o, "elevation", -89, false, 89, &m->elevation, err);
    if (rc == 0)
        rc = integer(o, "fps", 1, 120, &m->fps, err);
    if (rc == 0)
        rc = number(o, "duration", 0, true, LC_MOVIE_MAX_DURATION, &m->duration, err);
    m->frames = (int)lround(m->duration * m->fps);
    if (rc == 0 && json_object_get(o, "frames")) {
        if (json_object_get(o, "duration"))
            rc = bad(err, LC_PROTO_BAD_FIELD, "frames", "give frames or duration, not both");
        else
            rc = integer(o, "frames", 1, LC_MOVIE_MAX_FRAMES, &m->frames, err);
        m->duration = (double)m->frames / m->fps;
    }
    if (rc == 0 && m->frames < 1)
        rc = lc_proto_set_error(err, LC_PROTO_OUT_OF_RANGE, "duration", "%g s at %d fps is no frame", m->duration,
                                m->fps);
    if (rc == 0 && m->frames > LC_MOVIE_MAX_FRAMES)
        rc = lc_proto_set_error(err, LC_PROTO_OUT_OF_RANGE, "duration", "%d frames exceed the limit of %d", m->frames,
                                LC_MOVIE_MAX_FRAMES);
    if (rc == 0 && m->path == LC_MOVIE_KEYFRAMES && m->frames < 2)
        rc = bad(err, LC_PROTO_OUT_OF_RANGE, "frames", "a keyframe path needs at least two frames");
    int size[2] = {m->request.render.width, m->request.render.height};
    static const char *const dims[] = {"width", "height"};
    for (int i = 0; i < 2 && rc == 0; i++) {
        rc = integer(o, dims[i], lim->min_size, lim->max_size, &size[i], err);
        if (rc == 0 && size[i] % 2)
            rc = lc_proto_set_error(err, LC_PROTO_OUT_OF_RANGE, dims[i], "%d is odd; video (4:2:0) needs even sizes",
                                    size[i]);
    }
    long long pixels = (long long)size[0] * size[1];
    long long cap = lim->max_pixels < LC_MOVIE_MAX_PIXELS ? lim->max_pixels : LC_MOVIE_MAX_PIXELS;
    if (rc == 0 && pixels > cap)
        rc = lc_proto_set_error(err, LC_PROTO_OUT_OF_RANGE, "width",
                                "%d x %d = %lld pixels exceeds the limit %lld "
                                "of a movie frame",
                                size[0], size[1], pixels, cap);
    if (rc == 0 && pixels * m->frames > LC_MOVIE_MAX_PIXEL_FRAMES)
        rc = lc_proto_set_error(err, LC_PROTO_OUT_OF_RANGE, json_object_get(o, "frames") ? "frames" : "duration",
                                "%d frames of %d x %d exceed a job's limit of %.3g pixel-frames (a minute of 4K at "
                                "30 fps): at most %lld frames at this size",
                                m->frames, size[0], size[1], (double)LC_MOVIE_MAX_PIXEL_FRAMES,
                                LC_MOVIE_MAX_PIXEL_FRAMES / pixels);
    m->request.render.width = size[0];
    m->request.render.height = size[1];
    const json_t *codec = json_object_get(o, "codec");
    if (rc == 0 && codec) {
        const char *c = json_is_string(codec) ? json_string_value(codec) : "";
        if (strcmp(c, CODECS[0]) != 0 && strcmp(c, CODECS[1]) != 0)
            rc = lc_proto_set_error(err, LC_PROTO_BAD_FIELD, "codec", "\"%.32s\" is not one of h264, vp9", c);
        else
            snprintf(m->codec, sizeof m->codec, "%s", c);
    }
    json_decref(o);
    if (rc)
        lc_request_release(&m->request);
    return rc;
}
