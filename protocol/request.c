/* Render request schema: one field table drives JSON parsing, query parameters,
 * validation and emission, so the four cannot drift apart. */
#include "request.h"

#include "request_layers.h"
#include "request_lists.h"

#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "request_scope.h"
#include "request_table.h"

/* lim, or the defaults in *dl when NULL. */
static const lc_proto_limits *limits_or_default(const lc_proto_limits *lim, lc_proto_limits *dl)
{
    if (!lim)
        lc_proto_limits_default(dl);
    return lim ? lim : dl;
}

void lc_request_default(lc_request *r)
{
    memset(r, 0, sizeof *r);
    lc_render_params_default(&r->render);
    /* The loop is the requests' default; renderer callers (tests) opt in. */
    r->render.foo.clarity = LC_DEFAULT_CLARITY;
    r->format = LC_FORMAT_PNG;
    r->quality = LC_PROTO_DEFAULT_QUALITY;
    r->surface.particles = 2000;
    r->surface.epsilon = 1e-2;
    r->surface.opacity = 0.3;
    r->surface.max_layers = 8;
    r->surface.curves_per_frame = 200;
    r->surface.color[0] = 0.95, r->surface.color[1] = 0.6, r->surface.color[2] = 0.2;
    r->streamlines.seeding = 3, r->streamlines.count = 64; /* density, as a load-time set's defaults */
}

void lc_request_copy(lc_request *dst, const lc_request *src)
{
    *dst = *src;
    lc_request_layers_retain(src->layers);
}

void lc_request_assign(lc_request *dst, const lc_request *src)
{
    const lc_request_layers *old = dst->layers; /* after the retain: dst may be src */
    lc_request_copy(dst, src);
    lc_request_layers_release(old);
}

void lc_request_release(lc_request *r)
{
    lc_request_layers_release(r->layers);
    r->layers = NULL;
}

/* *r = *tmp, taking over tmp's reference and dropping r's (the all-or-nothing
 * commit of a change worked on a copy). */
static void commit(lc_request *r, lc_request *tmp)
{
    lc_request_layers_release(r->layers);
    *r = *tmp;
}

/* ---- the schema */
/* The field table and its types: request_table.c, request_table.h. */

static bool same(const char *a, const char *b) { return (a == NULL && b == NULL) || (a && b && strcmp(a, b) == 0); }

static const field *find_field(const char *section, const char *name)
{
    for (size_t i = 0; i < lc_request_nfields; i++)
        if (same(lc_request_fields[i].section, section) && strcmp(lc_request_fields[i].name, name) == 0)
            return &lc_request_fields[i];
    return NULL;
}

static bool is_section(const char *key)
{
    for (size_t i = 0; i < lc_request_nsections; i++)
        if (strcmp(lc_request_sections[i], key) == 0)
            return true;
    return false;
}

/* "a" + "." + "b", truncated to the error field size. */
static void join_path(char *out, size_t size, const char *prefix, const char *key)
{
    if (!prefix || !prefix[0]) {
        lc_proto_copy_str(out, size, key);
        return;
    }
    lc_proto_copy_str(out, size, prefix);
    size_t n = strlen(out);
    if (n + 1 < size) {
        out[n] = '.';
        lc_proto_copy_str(out + n + 1, size - n - 1, key);
    }
}

static const char *enum_list(const enum_name *names, char *buf, size_t size)
{
    buf[0] = '\0';
    size_t n = 0;
    for (int i = 0; names[i].name; i++) {
        int w = snprintf(buf + n, size - n, "%s\"%s\"", i ? ", " : "", names[i].name);
        if (w < 0 || (size_t)w >= size - n)
            break;
        n += (size_t)w;
    }
    return buf;
}

static const char *enum_to_name(const enum_name *names, int value)
{
    for (int i = 0; names[i].name; i++)
        if (names[i].value == value)
            return names[i].name;
    return "unknown";
}

/* Numbers arrive as JSON integers or reals; both mean the same quantity. */
static int get_finite(const json_t *v, double *out)
{
    if (!json_is_number(v))
        return -1;
    double d = json_number_value(v);
    if (!isfinite(d))
        return -1;
    *out = d;
    return 0;
}

static int check_range(const field *f, double v, double lo, double hi, const char *path, lc_proto_error *err)
{
    bool lo_bad = (f->bounds & LO_OPEN) ? !(v > lo) : !(v >= lo);
    bool hi_bad = (f->bounds & HI_OPEN) ? !(v < hi) : !(v <= hi);
    if (lo_bad || hi_bad) {
        const char *lb = (f->bounds & LO_OPEN) ? "(" : "[";
        const char *hb = (f->bounds & HI_OPEN) ? ")" : "]";
        if (hi >= BIG)
            return lc_proto_set_error(err, LC_PROTO_OUT_OF_RANGE, path, "%.15g is not %s %.15g", v,
                                      (f->bounds & LO_OPEN) ? ">" : ">=", lo);
        return lc_proto_set_error(err, LC_PROTO_OUT_OF_RANGE, path, "%.15g is outside %s%.15g, %.15g%s", v, lb, lo, hi,
                                  hb);
    }
    return 0;
}

/* Reads a fixed-length array of finite numbers. */
static int get_vector(const json_t *v, double *out, size_t n, const char *path, lc_proto_error *err)
{
    if (!json_is_array(v) || json_array_size(v) != n)
        return lc_proto_set_error(err, LC_PROTO_BAD_FIELD, path, "expected an array of %zu numbers", n);
    for (size_t i = 0; i < n; i++)
        if (get_finite(json_array_get(v, i), &out[i]) < 0)
            return lc_proto_set_error(err, LC_PROTO_BAD_FIELD, path, "expected an array of %zu numbers", n);
    return 0;
}

/* Validates v against f and stores it into r. */
static int apply_layer_section(void *lim, const json_t *obj, lc_layer_params *p, lc_layer_error *err);
static json_t *emit_section(const lc_request *r, const char *section);

static int set_field(const field *f, const json_t *v, const lc_proto_limits *lim, lc_request *r, const char *path,
                     lc_proto_error *err)
{
    char *base = (char *)r + f->offset;
    double lo = f->lo, hi = f->hi;
    if (f->bounds & SIZE_LIMIT) {
        lo = lim->min_size;
        hi = lim->max_size;
    }
    switch (f->type) {
    case T_INT: {
        double d;
        /* 5.0 is accepted: JavaScript cannot tell it from 5 anyway. */
        if (get_finite(v, &d) < 0 || d != floor(d))
            return lc_proto_set_error(err, LC_PROTO_BAD_FIELD, path, "expected an integer");
        int rc = check_range(f, d, lo, hi, path, err);
        if (rc)
            return rc;
        if (!(f->bounds & CHECK_ONLY))
            *(int *)base = (int)d;
        break;
    }
    case T_NUM: {
        double d;
        if (get_finite(v, &d) < 0)
            return lc_proto_set_error(err, LC_PROTO_BAD_FIELD, path, "expected a number");
        int rc = check_range(f, d, lo, hi, path, err);
        if (rc)
            return rc;
        *(double *)base = d;
        break;
    }
    case T_BOOL:
        if (!json_is_boolean(v))
            return lc_proto_set_error(err, LC_PROTO_BAD_FIELD, path, "expected true or false");
        *(bool *)base = json_is_true(v);
        break;
    case T_STR: {
        if (!json_is_string(v))
            return lc_proto_set_error(err, LC_PROTO_BAD_FIELD, path, "expected a string");
        size_t n = json_string_length(v);
        if (n >= f->size)
            return lc_proto_set_error(err, LC_PROTO_OUT_OF_RANGE, path, "longer than %zu bytes", f->size - 1);
        memcpy(base, json_string_value(v), n + 1); /* jansson rejects embedded NULs on load */
        break;
    }
    case T_ENUM:
    case T_NAME: {
        char list[160];
        if (!json_is_string(v))
            return lc_proto_set_error(err, LC_PROTO_BAD_FIELD, path, "expected one of %s",
                                      enum_list(f->names, list, sizeof list));
        const char *s = json_string_value(v);
        const enum_name *e = NULL;
        for (int i = 0; f->names[i].name; i++)
            if (strcmp(f->names[i].name, s) == 0)
                e = &f->names[i];
        if (!e)
            return lc_proto_set_error(err, LC_PROTO_BAD_FIELD, path, "expected one of %s",
                                      enum_list(f->names, list, sizeof list));
        if (f->type == T_ENUM)
            *(int *)base = e->value;
        else
            lc_proto_copy_str(base, f->size, e->name);
        break;
    }
    case T_VEC3:
    case T_COLOR: {
        double vec[3];
        int rc = get_vector(v, vec, 3, path, err);
        if (rc)
            return rc;
        if (f->type == T_COLOR)
            for (int i = 0; i < 3; i++)
                if (!(vec[i] >= 0 && vec[i] <= 1))
                    return lc_proto_set_error(err, LC_PROTO_OUT_OF_RANGE, path, "components must be in [0, 1]");
        memcpy(base, vec, sizeof vec);
        break;
    }
    case T_RANGE: {
        double vec[2];
        int rc = get_vector(v, vec, 2, path, err);
        if (rc)
            return rc;
        memcpy(base, vec, sizeof vec);
        break;
    }
    case T_LAYERS: { /* a new snapshot replaces r's reference (copy on write) */
        lc_layer_error le = {0};
        const lc_request_layers *layers;
        if (lc_proto_parse_layers(v, &layers, path, apply_layer_section, (void *)lim, &le) != 0)
            return lc_proto_set_error(err, le.code, le.field, "%s", le.reason);
        lc_request_layers_release(r->layers);
        r->layers = layers;
        break;
    }
    case T_SEED: { /* offset: the point count; size: the offset of the points */
        lc_list_error le;
        if (lc_proto_parse_seed(v, (double(*)[3])((char *)r + f->size), (int *)base, (int)f->lo, (int)f->hi, path,
                                &le) != 0)
            return lc_proto_set_error(err, le.code, le.field, "%s", le.reason);
        break;
    }
    case T_TERMS:
    case T_FILTERS:
    case T_CURVE:
    case T_RANGES: {
        lc_list_error le;
        int rc = f->type == T_TERMS     ? lc_proto_parse_terms(v, (lc_importance_map *)base, path, &le)
                 : f->type == T_FILTERS ? lc_proto_parse_filters(v, (lc_render_params *)base, path, &le)
                 : f->type == T_RANGES  ? lc_proto_parse_fixed(v, (lc_color_map *)base, path, &le)
                                        : lc_proto_parse_curve(v, (lc_curve *)base, path, &le);
        if (rc)
            return lc_proto_set_error(err, le.code, le.field, "%s", le.reason);
        break;
    }
    }
    if (f->flag >= 0)
        *((bool *)((char *)r + f->flag)) = true;
    return 0;
}

/* Applies the members of one object (the request or one of its sections). */
static int apply_members(const json_t *obj, const char *section, const lc_proto_limits *lim, lc_request *r,
                         lc_proto_error *err)
{
    const char *key;
    const json_t *v;
    char path[128];
    json_object_foreach((json_t *)obj, key, v)
    {
        join_path(path, sizeof path, section, key);
        if (!section && is_section(key)) {
            if (strcmp(key, "camera") == 0) {
                if (json_is_null(v)) { /* sessions: back to fitting the data */
                    lc_render_params def;
                    lc_render_params_default(&def);
                    r->render.camera = def.camera;
                    r->render.has_camera = false;
                    continue;
                }
                if (json_is_object(v) && !r->render.has_camera) {
                    /* Merge onto the default camera, not stale values. */
                    lc_render_params def;
                    lc_render_params_default(&def);
                    r->render.camera = def.camera;
                    r->render.has_camera = true;
                }
            }
            if (!json_is_object(v))
                return lc_proto_set_error(err, LC_PROTO_BAD_FIELD, path, "expected an object");
            int rc = apply_members(v, key, lim, r, err);
            if (rc)
                return rc;
            continue;
        }
        const field *f = find_field(section, key);
        if (!f)
            return lc_proto_set_error(err, LC_PROTO_UNKNOWN_FIELD, path, "unknown field");
        int rc = set_field(f, v, lim, r, path, err);
        if (rc)
            return rc;
    }
    return 0;
}

static double dot3(const double *a, const double *b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

/* position != focalPoint and, when check_up, viewUp not parallel to the view
 * direction. */
#define MAX_COORD 1e30 /* camera coordinates: far beyond any scene, and their squares stay finite */

static int check_camera(const lc_camera *c, bool check_up, lc_proto_error *err)
{
    static const char *const names[3] = {"camera.position", "camera.focalPoint", "camera.viewUp"};
    const double *vecs[3] = {c->position, c->focal_point, c->view_up};
    for (int v = 0; v < 3; v++)
        for (int k = 0; k < 3; k++)
            if (!(fabs(vecs[v][k]) <= MAX_COORD))
                return lc_proto_set_error(err, LC_PROTO_OUT_OF_RANGE, names[v], "coordinate %.6g is outside [-%g, %g]",
                                          vecs[v][k], MAX_COORD, MAX_COORD);
    double d[3] = {c->focal_point[0] - c->position[0], c->focal_point[1] - c->position[1],
                   c->focal_point[2] - c->position[2]};
    const double *u = c->view_up;
    double dd = dot3(d, d), uu = dot3(u, u);
    if (!(dd > 0) || !isfinite(dd))
        return lc_proto_set_error(err, LC_PROTO_BAD_FIELD, "camera.focalPoint", "must differ from camera.position");
    if (!check_up)
        return 0;
    if (!(uu > 0) || !isfinite(uu))
        return lc_proto_set_error(err, LC_PROTO_BAD_FIELD, "camera.viewUp", "must not be zero");
    double cx = d[1] * u[2] - d[2] * u[1], cy = d[2] * u[0] - d[0] * u[2], cz = d[0] * u[1] - d[1] * u[0];
    /* sin² of the angle between them; below 1e-12 (≈1e-6 rad) the camera basis
     * would be numerically meaningless. */
    if (!((cx * cx + cy * cy + cz * cz) > 1e-12 * dd * uu))
        return lc_proto_set_error(err, LC_PROTO_BAD_FIELD, "camera.viewUp",
                                  "must not be parallel to the view direction");
    return 0;
}

int lc_proto_validate_request(const lc_request *r, const lc_proto_limits *lim, lc_proto_error *err)
{
    lc_proto_limits dl;
    lim = limits_or_default(lim, &dl);
    long long px = (long long)r->render.width * r->render.height;
    if (px > lim->max_pixels)
        return lc_proto_set_error(err, LC_PROTO_OUT_OF_RANGE, "width", "%d x %d = %lld pixels exceeds the limit %lld",
                                  r->render.width, r->render.height, px, lim->max_pixels);
    if (r->render.method == LC_METHOD_SURFACE_LAYERS && !r->surface.field[0])
        return lc_proto_set_error(err, LC_PROTO_MISSING_FIELD, "surface.field",
                                  "method surface-layers needs a vector field (GET /api/v1/datasets lists them)");
    if (r->render.method == LC_METHOD_SURFACE_LAYERS && r->surface.seed_count < 2)
        return lc_proto_set_error(err, LC_PROTO_MISSING_FIELD, "surface.seed",
                                  "method surface-layers needs a seed polyline of 2 or more [x, y, z] points");
    /* The surface is the frame's only geometry: no path draws datasets beside it. */
    if (r->render.method == LC_METHOD_SURFACE_LAYERS && r->layers)
        return lc_proto_set_error(err, LC_PROTO_BAD_FIELD, "layers",
                                  "method surface-layers draws the field's surface alone; drop layers or choose "
                                  "another method");
    if (r->render.has_camera)
        return check_camera(&r->render.camera, true, err);
    return 0;
}

static int apply(const json_t *obj, const lc_proto_limits *lim, lc_request *r, bool cross_checks, lc_proto_error *err)
{
    lc_proto_limits dl;
    lim = limits_or_default(lim, &dl);
    if (!json_is_object(obj))
        return lc_proto_set_error(err, LC_PROTO_BAD_FIELD, "", "expected a JSON object");
    lc_request tmp; /* all or nothing */
    lc_request_copy(&tmp, r);
    int rc = apply_members(obj, NULL, lim, &tmp, err);
    if (!rc && cross_checks)
        rc = lc_proto_validate_request(&tmp, lim, err);
    if (!rc)
        commit(r, &tmp);
    else
        lc_request_release(&tmp);
    return rc;
}

/* A default request with a layer's sections: what the request's own field
 * table checks and emits them on. */
static void layer_request(lc_request *r, const lc_layer_params *p)
{
    lc_request_default(r);
    r->render.importance = p->importance, r->render.color = p->color, r->render.style = p->style;
    r->render.filter_count = p->filter_count, r->render.time = p->time, r->render.clusters = p->clusters;
    memcpy(r->render.filters, p->filters, sizeof p->filters);
}

/* A layer's importance, colour, style, filter or time object (request_layers.c),
 * field checks only, on a scratch request that holds the layer's sections. */
static int apply_layer_section(void *lim, const json_t *obj, lc_layer_params *p, lc_layer_error *err)
{
    lc_request s, *scratch = &s; /* no layers: nothing to release */
    layer_request(scratch, p);
    lc_proto_error pe;
    int rc = apply(obj, lim, scratch, false, &pe);
    if (rc) {
        err->code = pe.code[0] == 'o'   ? LC_PROTO_OUT_OF_RANGE
                    : pe.code[0] == 'u' ? LC_PROTO_UNKNOWN_FIELD
                                        : LC_PROTO_BAD_FIELD;
        snprintf(err->field, sizeof err->field, "%s", pe.field);
        size_t n = strlen(pe.field);
        const char *reason =
            strncmp(pe.message, pe.field, n) == 0 && pe.message[n] == ':' ? pe.message + n + 2 : pe.message;
        snprintf(err->reason, sizeof err->reason, "%s", reason);
    } else {
        p->importance = scratch->render.importance, p->color = scratch->render.color, p->style = scratch->render.style;
        p->filter_count = scratch->render.filter_count, p->time = scratch->render.time;
        p->clusters = scratch->render.clusters;
        memcpy(p->filters, scratch->render.filters, sizeof p->filters);
    }
    return rc ? -1 : 0;
}

/* A layer's importance, colour, time window or filter list as the request's
 * own section (or, for filter, field) emits it. */
static json_t *emit_layer_section(const lc_layer_params *p, const char *section)
{
    lc_request s, *scratch = &s;
    layer_request(scratch, p);
    json_t *o =
        strcmp(section, "filter") == 0 ? lc_proto_field_json(scratch, NULL, section) : emit_section(scratch, section);
    return o ? o : json_array();
}

int lc_proto_apply_request(const json_t *obj, const lc_proto_limits *lim, lc_request *r, lc_proto_error *err)
{
    return apply(obj, lim, r, true, err);
}

/* ---- partial updates (request_patch.c keeps them as typed patches) */

int lc_proto_check_fields(const json_t *obj, const lc_proto_limits *lim, lc_request *r, lc_proto_error *err)
{
    int rc = apply(obj, lim, r, false, err);
    /* The state the update will meet is unknown, so check the camera only as far
     * as the update itself pins it down. */
    const json_t *cam = rc ? NULL : json_object_get(obj, "camera");
    if (json_is_object(cam) && json_object_get(cam, "position") && json_object_get(cam, "focalPoint"))
        rc = check_camera(&r->render.camera, json_object_get(cam, "viewUp") != NULL, err);
    return rc;
}

int lc_proto_copy_field(const char *section, const char *name, lc_request *dst, const lc_request *src)
{
    const field *f = find_field(section, name);
    if (!f)
        return -1;
    const char *s = (const char *)src + f->offset;
    char *d = (char *)dst + f->offset;
    switch (f->type) {
    case T_INT:
    case T_ENUM: memcpy(d, s, (f->bounds & CHECK_ONLY) ? 0 : sizeof(int)); break;
    case T_NUM: memcpy(d, s, sizeof(double)); break;
    case T_BOOL: memcpy(d, s, sizeof(bool)); break;
    case T_STR:
    case T_NAME: memcpy(d, s, f->size); break;
    case T_VEC3:
    case T_COLOR: memcpy(d, s, 3 * sizeof(double)); break;
    case T_RANGE: memcpy(d, s, 2 * sizeof(double)); break;
    case T_CURVE: memcpy(d, s, sizeof(lc_curve)); break;
    /* The list types, one field each, replace their whole list. */
    case T_TERMS:
        dst->render.importance.term_count = src->render.importance.term_count;
        memcpy(dst->render.importance.terms, src->render.importance.terms, sizeof src->render.importance.terms);
        break;
    case T_FILTERS:
        dst->render.filter_count = src->render.filter_count;
        memcpy(dst->render.filters, src->render.filters, sizeof src->render.filters);
        break;
    case T_RANGES:
        dst->render.color.fixed_count = src->render.color.fixed_count;
        memcpy(dst->render.color.fixed, src->render.color.fixed, sizeof src->render.color.fixed);
        break;
    case T_LAYERS: /* the snapshot is shared, never copied */
        lc_request_layers_retain(src->layers);
        lc_request_layers_release(dst->layers);
        dst->layers = src->layers;
        break;
    case T_SEED: /* offset: the point count; size: the offset of the points (surface.seed, streamlines.seeds) */
        memcpy(d, s, sizeof(int));
        memcpy((char *)dst + f->size, (const char *)src + f->size, (size_t)f->hi * 3 * sizeof(double));
        break;
    }
    if (f->flag >= 0)
        *((bool *)((char *)dst + f->flag)) = true;
    return 0;
}

int lc_proto_parse_request(const char *json, size_t len, const lc_proto_limits *lim, lc_request *r, lc_proto_error *err)
{
    lc_proto_error local;
    if (!err)
        err = &local;
    lc_request_default(r);
    json_t *root = lc_proto_load(json, len, lim, err);
    if (!root)
        return strcmp(err->code, LC_PROTO_BAD_JSON) == 0 ? LC_ERR_INVALID : LC_ERR_LIMIT;
    int rc = lc_proto_apply_request(root, lim, r, err);
    json_decref(root);
    return rc;
}

/* ---- query parameters */

static const field *find_query_field(const char *key)
{
    const char *dot = strchr(key, '.');
    if (dot) {
        char section[32];
        size_t n = (size_t)(dot - key);
        if (n >= sizeof section)
            return NULL;
        memcpy(section, key, n);
        section[n] = '\0';
        return is_section(section) ? find_field(section, dot + 1) : NULL;
    }
    const field *f = find_field(NULL, key);
    if (f)
        return f;
    for (size_t i = 0; i < lc_request_nfields; i++)
        if (lc_request_fields[i].alias && strcmp(lc_request_fields[i].alias, key) == 0)
            return &lc_request_fields[i];
    return NULL;
}

/* strtod accepts "nan", "inf" and hex; a URL parameter gets plain decimal only. */
static int parse_decimal(const char *s, size_t n, double *out)
{
    if (n == 0 || n > 64)
        return -1;
    char buf[65];
    for (size_t i = 0; i < n; i++) {
        char c = s[i];
        if (!((c >= '0' && c <= '9') || c == '+' || c == '-' || c == '.' || c == 'e' || c == 'E'))
            return -1;
        buf[i] = c;
    }
    buf[n] = '\0';
    char *end;
    double d = strtod(buf, &end);
    if (*end || !isfinite(d))
        return -1;
    *out = d;
    return 0;
}

/* Converts the text of a query value into the JSON value the field expects, so
 * that both paths share set_field(). Returns NULL when the text has the wrong
 * shape; set_field() then reports the expected type. */
static json_t *query_value(const field *f, const char *value)
{
    switch (f->type) {
    case T_INT:
    case T_NUM: {
        double d;
        return parse_decimal(value, strlen(value), &d) < 0 ? NULL : json_real(d);
    }
    case T_BOOL:
        if (!strcmp(value, "true") || !strcmp(value, "1"))
            return json_true();
        if (!strcmp(value, "false") || !strcmp(value, "0"))
            return json_false();
        return NULL;
    case T_STR:
    case T_ENUM:
    case T_NAME: return json_string(value); /* NULL for invalid UTF-8 */
    case T_VEC3:
    case T_COLOR:
    case T_RANGE: {
        json_t *arr = json_array();
        const char *s = value;
        for (;;) {
            const char *comma = strchr(s, ',');
            size_t n = comma ? (size_t)(comma - s) : strlen(s);
            double d;
            if (parse_decimal(s, n, &d) < 0 || json_array_size(arr) >= 3) {
                json_decref(arr);
                return NULL;
            }
            json_array_append_new(arr, json_real(d));
            if (!comma)
                break;
            s = comma + 1;
        }
        return arr;
    }
    case T_TERMS:
    case T_FILTERS:
    case T_CURVE:
    case T_RANGES:
    case T_SEED:
    case T_LAYERS: return json_loads(value, JSON_REJECT_DUPLICATES, NULL); /* the array as JSON text */
    }
    return NULL;
}

int lc_proto_apply_query(lc_request *r, const char *key, const char *value, const lc_proto_limits *lim,
                         lc_proto_error *err)
{
    lc_proto_limits dl;
    lim = limits_or_default(lim, &dl);
    if (!key || !key[0] || key[0] == '_' || strcmp(key, "token") == 0)
        return 0;
    if (!value)
        value = "";
    const field *f = find_query_field(key);
    if (!f)
        return lc_proto_set_error(err, LC_PROTO_UNKNOWN_FIELD, key, "unknown query parameter");
    json_t *v = query_value(f, value);
    if (!v) {
        /* A JSON null fails every type check with the right "expected ..." text. */
        v = json_null();
    }
    lc_request tmp;
    lc_request_copy(&tmp, r);
    if (f->section && strcmp(f->section, "camera") == 0 && !tmp.render.has_camera) {
        lc_render_params def;
        lc_render_params_default(&def);
        tmp.render.camera = def.camera;
        tmp.render.has_camera = true;
    }
    int rc = set_field(f, v, lim, &tmp, key, err);
    json_decref(v);
    if (!rc)
        commit(r, &tmp);
    else
        lc_request_release(&tmp);
    return rc;
}

/* ---- emission */

static json_t *vec_json(const double *v, size_t n)
{
    json_t *a = json_array();
    for (size_t i = 0; i < n; i++)
        json_array_append_new(a, json_real(v[i]));
    return a;
}

/* Emits one field from the table, so names and types match the parser. */
static void emit(json_t *obj, const lc_request *r, const char *section, const char *name)
{
    const field *f = find_field(section, name);
    const char *base = (const char *)r + f->offset;
    json_t *v = NULL;
    switch (f->type) {
    case T_INT: v = json_integer(*(const int *)base); break;
    case T_NUM: v = json_real(*(const double *)base); break;
    case T_BOOL: v = json_boolean(*(const bool *)base); break;
    case T_STR:
    case T_NAME: v = json_string(base); break;
    case T_ENUM: v = json_string(enum_to_name(f->names, *(const int *)base)); break;
    case T_VEC3:
    case T_COLOR: v = vec_json((const double *)base, 3); break;
    case T_RANGE: v = vec_json((const double *)base, 2); break;
    case T_TERMS:
        if (((const lc_importance_map *)base)->term_count > 0)
            v = lc_proto_terms_json((const lc_importance_map *)base);
        break;
    case T_FILTERS:
        if (((const lc_render_params *)base)->filter_count > 0)
            v = lc_proto_filters_json((const lc_render_params *)base);
        break;
    case T_CURVE:
        if (((const lc_curve *)base)->count > 0)
            v = lc_proto_curve_json((const lc_curve *)base);
        break;
    case T_RANGES:
        if (((const lc_color_map *)base)->fixed_count > 0)
            v = lc_proto_fixed_json((const lc_color_map *)base);
        break;
    case T_LAYERS:
        if (r->layers)
            v = lc_proto_layers_json(r->layers, emit_layer_section);
        break;
    case T_SEED:
        if (*(const int *)base > 0)
            v = lc_proto_seed_json((const double(*)[3])((const char *)r + f->size), *(const int *)base);
        break;
    }
    if (v)
        json_object_set_new(obj, name, v);
}

int lc_proto_field_at(size_t i, const char **section, const char **name)
{
    if (i >= lc_request_nfields)
        return 0;
    *section = lc_request_fields[i].section, *name = lc_request_fields[i].name;
    return 1;
}

json_t *lc_proto_field_json(const lc_request *r, const char *section, const char *name)
{
    if (!find_field(section, name))
        return NULL;
    json_t *o = json_object(), *v = NULL;
    emit(o, r, section, name);
    if ((v = json_object_get(o, name)))
        json_incref(v);
    json_decref(o);
    return v;
}

static json_t *emit_section(const lc_request *r, const char *section)
{
    json_t *obj = json_object();
    for (size_t i = 0; i < lc_request_nfields; i++) {
        const field *f = &lc_request_fields[i];
        if (!same(f->section, section))
            continue;
        if (f->flag >= 0 && !(f->bounds & ALWAYS_EMIT) && !*(const bool *)((const char *)r + f->flag))
            continue; /* optional value not set: the renderer's default applies */
        emit(obj, r, section, f->name);
    }
    return obj;
}

json_t *lc_proto_schema(const lc_proto_limits *lim)
{
    static const char *const type_names[] = {
        [T_INT] = "int",         [T_NUM] = "num",     [T_BOOL] = "bool",     [T_STR] = "str",       [T_ENUM] = "enum",
        [T_NAME] = "enum",       [T_VEC3] = "vec3",   [T_COLOR] = "color",   [T_RANGE] = "range",   [T_TERMS] = "terms",
        [T_FILTERS] = "filters", [T_CURVE] = "curve", [T_RANGES] = "ranges", [T_LAYERS] = "layers", [T_SEED] = "seed"};
    lc_proto_limits dl;
    lim = limits_or_default(lim, &dl);
    json_t *arr = json_array();
    lc_request d, *def = &d;
    lc_request_default(def);
    for (size_t i = 0; arr && i < lc_request_nfields; i++) {
        const field *f = &lc_request_fields[i];
        json_t *o = json_object();
        json_t *dv = !(f->bounds & CHECK_ONLY) ? lc_proto_field_json(def, f->section, f->name) : NULL;
        if (dv)
            json_object_set_new(o, "default", dv);
        json_object_set_new(o, "section", f->section ? json_string(f->section) : json_null());
        json_object_set_new(o, "name", json_string(f->name));
        json_object_set_new(o, "alias", json_string(f->alias ? f->alias : f->name));
        json_object_set_new(o, "type", json_string(type_names[f->type]));
        if (f->type == T_INT || f->type == T_NUM) {
            double lo = f->bounds & SIZE_LIMIT ? lim->min_size : f->lo;
            double hi = f->bounds & SIZE_LIMIT ? lim->max_size : f->hi;
            json_object_set_new(o, "min", json_real(lo));
            if (hi < BIG)
                json_object_set_new(o, "max", json_real(hi));
            if (f->bounds & LO_OPEN)
                json_object_set_new(o, "loOpen", json_true());
            if (f->bounds & HI_OPEN)
                json_object_set_new(o, "hiOpen", json_true());
            if (f->bounds & SIZE_LIMIT)
                json_object_set_new(o, "sizeLimit", json_true());
        }
        if (f->type == T_STR)
            json_object_set_new(o, "maxLength", json_integer((json_int_t)f->size - 1));
        if (f->type == T_TERMS || f->type == T_FILTERS || f->type == T_CURVE || f->type == T_RANGES ||
            f->type == T_LAYERS || f->type == T_SEED)
            json_object_set_new(o, "maxItems", json_integer((json_int_t)f->hi));
        if (f->type == T_LAYERS)
            json_object_set_new(o, "keys", lc_proto_layer_keys_json());
        unsigned ms, ps;
        lc_proto_field_scope(f->section, f->name, &ms, &ps);
        if (ms != LC_PROTO_ALL_METHODS) {
            json_t *a = json_array();
            for (const enum_name *n = lc_request_method_names; n->name; n++)
                if (ms & (1u << n->value))
                    json_array_append_new(a, json_string(n->name));
            json_object_set_new(o, "methods", a);
        }
        const char *when_path, *when_value;
        if (lc_proto_field_condition(f->section, f->name, &when_path, &when_value))
            json_object_set_new(o, "when", json_pack("[ss]", when_path, when_value));
        if (ps != LC_PROTO_ALL_PRIMS) {
            json_t *a = json_array();
            for (int k = 0; k < 3; k++)
                if (ps & (1u << k))
                    json_array_append_new(a, json_string(lc_proto_prim_name(k)));
            json_object_set_new(o, "primitives", a);
        }
        if (f->names) {
            json_t *values = json_array();
            for (const enum_name *n = f->names; n->name; n++)
                json_array_append_new(values, json_string(n->name));
            json_object_set_new(o, "values", values);
        }
        json_array_append_new(arr, o);
    }
    return arr;
}

json_t *lc_proto_request_to_json(const lc_request *r)
{
    json_t *o = json_object();
    if (!o)
        return NULL;
    emit(o, r, NULL, "dataset");
    emit(o, r, NULL, "width");
    emit(o, r, NULL, "height");
    emit(o, r, NULL, "method");
    emit(o, r, NULL, "format");
    emit(o, r, NULL, "quality");
    if (r->has_dt)
        emit(o, r, NULL, "dt");
    if (r->render.has_camera)
        json_object_set_new(o, "camera", emit_section(r, "camera"));
    json_object_set_new(o, "params", emit_section(r, "params"));
    json_object_set_new(o, "importance", emit_section(r, "importance"));
    json_object_set_new(o, "color", emit_section(r, "color"));
    json_object_set_new(o, "style", emit_section(r, "style"));
    emit(o, r, NULL, "filter");
    json_object_set_new(o, "lines", emit_section(r, "lines"));
    emit(o, r, NULL, "layers");
    json_object_set_new(o, "time", emit_section(r, "time"));
    if (r->render.method == LC_METHOD_SURFACE_LAYERS || r->surface.field[0] || r->surface.seed_count)
        json_object_set_new(o, "surface", emit_section(r, "surface"));
    if (lc_proto_streamlines_given(r, NULL))
        json_object_set_new(o, "streamlines", emit_section(r, "streamlines"));
    return o;
}
