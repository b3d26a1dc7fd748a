/* The request's array-valued fields, importance.terms and filter: parsed,
 * validated (every error names the element and key) and emitted; request.c's
 * field table routes them here. */
#include "request_lists.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <string.h>

int lc_proto_list_fail(lc_list_error *err, const char *code, const char *field, const char *fmt, ...)
{
    err->code = code;
    snprintf(err->field, sizeof err->field, "%s", field);
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(err->reason, sizeof err->reason, fmt, ap);
    va_end(ap);
    return -1;
}

static const char *const over_names[LC_FILTER_OVER_COUNT] = {"vertex", "min", "max", "mean", "first", "last", "change"};

const char *lc_filter_over_name(lc_filter_over o)
{
    return (unsigned)o < LC_FILTER_OVER_COUNT ? over_names[o] : "vertex";
}

static int get_number(const json_t *v, double lo, double hi, double *out, const char *path, lc_list_error *err)
{
    if (!json_is_number(v) || !isfinite(json_number_value(v)))
        return lc_proto_list_fail(err, LC_PROTO_BAD_FIELD, path, "expected a number");
    double d = json_number_value(v);
    if (d < lo || d > hi)
        return lc_proto_list_fail(err, LC_PROTO_OUT_OF_RANGE, path, "must be in [%g, %g]", lo, hi);
    *out = d;
    return 0;
}

static int get_pair(const json_t *v, double out[2], const char *path, lc_list_error *err)
{
    if (!json_is_array(v) || json_array_size(v) != 2)
        return lc_proto_list_fail(err, LC_PROTO_BAD_FIELD, path, "expected an array of 2 numbers");
    for (size_t i = 0; i < 2; i++) {
        const json_t *x = json_array_get(v, i);
        if (!json_is_number(x) || !isfinite(json_number_value(x)))
            return lc_proto_list_fail(err, LC_PROTO_BAD_FIELD, path, "expected an array of 2 numbers");
        out[i] = json_number_value(x);
    }
    return 0;
}

static int get_name(const json_t *v, char out[LC_NAME_LEN], const char *path, lc_list_error *err)
{
    if (!json_is_string(v))
        return lc_proto_list_fail(err, LC_PROTO_BAD_FIELD, path, "expected a string");
    size_t n = json_string_length(v);
    if (n == 0)
        return lc_proto_list_fail(err, LC_PROTO_BAD_FIELD, path, "must name an attribute");
    if (n >= LC_NAME_LEN)
        return lc_proto_list_fail(err, LC_PROTO_OUT_OF_RANGE, path, "longer than %d bytes", LC_NAME_LEN - 1);
    memcpy(out, json_string_value(v), n + 1);
    return 0;
}

static int parse_term(const json_t *o, lc_importance_term *t, const char *base, lc_list_error *err)
{
    char path[128];
    if (!json_is_object(o))
        return lc_proto_list_fail(err, LC_PROTO_BAD_FIELD, base, "expected an object");
    memset(t, 0, sizeof *t);
    t->weight = 1;
    const char *key;
    const json_t *v;
    json_object_foreach((json_t *)o, key, v)
    {
        snprintf(path, sizeof path, "%s.%s", base, key);
        int rc = 0;
        if (strcmp(key, "attribute") == 0)
            rc = get_name(v, t->attribute, path, err);
        else if (strcmp(key, "range") == 0) {
            rc = get_pair(v, t->range, path, err);
            t->has_range = true;
        } else if (strcmp(key, "weight") == 0)
            rc = get_number(v, -1, 1, &t->weight, path, err);
        else if (strcmp(key, "invert") == 0) {
            if (!json_is_boolean(v))
                rc = lc_proto_list_fail(err, LC_PROTO_BAD_FIELD, path, "expected true or false");
            t->invert = json_is_true(v);
        } else
            rc = lc_proto_list_fail(err, LC_PROTO_UNKNOWN_FIELD, path, "unknown field");
        if (rc)
            return rc;
    }
    if (!t->attribute[0]) {
        snprintf(path, sizeof path, "%s.attribute", base);
        return lc_proto_list_fail(err, LC_PROTO_MISSING_FIELD, path, "every term names an attribute");
    }
    return 0;
}

int lc_proto_parse_terms(const json_t *v, lc_importance_map *m, const char *path, lc_list_error *err)
{
    if (!json_is_array(v))
        return lc_proto_list_fail(err, LC_PROTO_BAD_FIELD, path, "expected an array of terms");
    size_t n = json_array_size(v);
    if (n > LC_MAX_IMPORTANCE_TERMS)
        return lc_proto_list_fail(err, LC_PROTO_OUT_OF_RANGE, path, "at most %d terms", LC_MAX_IMPORTANCE_TERMS);
    lc_importance_term terms[LC_MAX_IMPORTANCE_TERMS];
    double sum_abs = 0;
    for (size_t i = 0; i < n; i++) {
        char base[96];
        snprintf(base, sizeof base, "%s[%zu]", path, i);
        int rc = parse_term(json_array_get(v, i), &terms[i], base, err);
        if (rc)
            return rc;
        sum_abs += fabs(terms[i].weight);
    }
    if (n > 0 && !(sum_abs > 0))
        return lc_proto_list_fail(err, LC_PROTO_BAD_FIELD, path, "at least one weight must be non-zero");
    memcpy(m->terms, terms, n * sizeof terms[0]);
    m->term_count = (int)n;
    return 0;
}

static int parse_filter(const json_t *o, lc_filter *f, const char *base, lc_list_error *err)
{
    char path[128];
    if (!json_is_object(o))
        return lc_proto_list_fail(err, LC_PROTO_BAD_FIELD, base, "expected an object");
    memset(f, 0, sizeof *f);
    f->lo = -HUGE_VAL, f->hi = HUGE_VAL;
    int bounded = 0;
    const char *key;
    const json_t *v;
    json_object_foreach((json_t *)o, key, v)
    {
        snprintf(path, sizeof path, "%s.%s", base, key);
        int rc = 0;
        if (strcmp(key, "attribute") == 0)
            rc = get_name(v, f->attribute, path, err);
        else if (strcmp(key, "over") == 0) {
            int found = -1;
            for (int i = 0; json_is_string(v) && i < LC_FILTER_OVER_COUNT; i++)
                if (strcmp(json_string_value(v), over_names[i]) == 0)
                    found = i;
            if (found < 0)
                rc = lc_proto_list_fail(err, LC_PROTO_BAD_FIELD, path,
                                        "expected one of vertex, min, max, mean, first, last, change");
            f->over = (lc_filter_over)(found < 0 ? 0 : found);
        } else if (strcmp(key, "gt") == 0) {
            rc = get_number(v, -HUGE_VAL, HUGE_VAL, &f->lo, path, err);
            f->lo_open = true, bounded |= 1;
        } else if (strcmp(key, "lt") == 0) {
            rc = get_number(v, -HUGE_VAL, HUGE_VAL, &f->hi, path, err);
            f->hi_open = true, bounded |= 2;
        } else if (strcmp(key, "range") == 0) {
            double r[2];
            rc = get_pair(v, r, path, err);
            if (!rc && r[0] > r[1])
                rc = lc_proto_list_fail(err, LC_PROTO_BAD_FIELD, path, "range [%g, %g] is empty", r[0], r[1]);
            f->lo = r[0], f->hi = r[1], bounded |= 4;
        } else
            rc = lc_proto_list_fail(err, LC_PROTO_UNKNOWN_FIELD, path, "unknown field");
        if (rc)
            return rc;
    }
    if (!f->attribute[0]) {
        snprintf(path, sizeof path, "%s.attribute", base);
        return lc_proto_list_fail(err, LC_PROTO_MISSING_FIELD, path, "every filter names an attribute");
    }
    if (!bounded || ((bounded & 4) && (bounded & 3)))
        return lc_proto_list_fail(err, LC_PROTO_BAD_FIELD, base, "give \"gt\" and/or \"lt\", or \"range\"");
    return 0;
}

int lc_proto_parse_filters(const json_t *v, lc_render_params *p, const char *path, lc_list_error *err)
{
    if (!json_is_array(v))
        return lc_proto_list_fail(err, LC_PROTO_BAD_FIELD, path, "expected an array of filters");
    size_t n = json_array_size(v);
    if (n > LC_MAX_FILTERS)
        return lc_proto_list_fail(err, LC_PROTO_OUT_OF_RANGE, path, "at most %d filters", LC_MAX_FILTERS);
    lc_filter filters[LC_MAX_FILTERS];
    for (size_t i = 0; i < n; i++) {
        char base[96];
        snprintf(base, sizeof base, "%s[%zu]", path, i);
        int rc = parse_filter(json_array_get(v, i), &filters[i], base, err);
        if (rc)
            return rc;
    }
    memcpy(p->filters, filters, n * sizeof filters[0]);
    p->filter_count = (int)n;
    return 0;
}

int lc_proto_parse_curve(const json_t *v, lc_curve *c, const char *path, lc_list_error *err)
{
    if (!json_is_array(v))
        return lc_proto_list_fail(err, LC_PROTO_BAD_FIELD, path, "expected an array of [x, y] points");
    size_t n = json_array_size(v);
    if (n == 1 || n > LC_MAX_CURVE_POINTS)
        return lc_proto_list_fail(err, LC_PROTO_OUT_OF_RANGE, path, "2 to %d points (none: the identity)",
                                  LC_MAX_CURVE_POINTS);
    lc_curve tmp = {0};
    for (size_t i = 0; i < n; i++) {
        char at[96];
        snprintf(at, sizeof at, "%s[%zu]", path, i);
        double xy[2];
        int rc = get_pair(json_array_get(v, i), xy, at, err);
        if (rc)
            return rc;
        if (!(xy[0] >= 0 && xy[0] <= 1 && xy[1] >= 0 && xy[1] <= 1))
            return lc_proto_list_fail(err, LC_PROTO_OUT_OF_RANGE, at, "x and y must lie in [0, 1]");
        if (i > 0 && !(xy[0] >= tmp.points[i - 1][0]))
            return lc_proto_list_fail(err, LC_PROTO_BAD_FIELD, at, "x must not decrease");
        tmp.points[i][0] = xy[0], tmp.points[i][1] = xy[1];
    }
    tmp.count = (int)n;
    *c = tmp;
    return 0;
}

#define SEED_CAP 256 /* points a seed may have at most, whatever max says */

int lc_proto_parse_seed(const json_t *v, double (*points)[3], int *count, int min, int max, const char *path,
                        lc_list_error *err)
{
    if (!json_is_array(v))
        return lc_proto_list_fail(err, LC_PROTO_BAD_FIELD, path, "expected an array of [x, y, z] points");
    size_t n = json_array_size(v);
    if (max > SEED_CAP)
        max = SEED_CAP;
    if (n < (size_t)min || n > (size_t)max)
        return lc_proto_list_fail(err, LC_PROTO_OUT_OF_RANGE, path, "%d to %d points (got %zu)", min, max, n);
    double tmp[SEED_CAP][3];
    for (size_t i = 0; i < n; i++) {
        char at[96];
        snprintf(at, sizeof at, "%s[%zu]", path, i);
        const json_t *p = json_array_get(v, i);
        if (!json_is_array(p) || json_array_size(p) != 3)
            return lc_proto_list_fail(err, LC_PROTO_BAD_FIELD, at, "expected an array of 3 numbers");
        for (size_t a = 0; a < 3; a++) {
            const json_t *x = json_array_get(p, a);
            if (!json_is_number(x) || !isfinite(json_number_value(x)))
                return lc_proto_list_fail(err, LC_PROTO_BAD_FIELD, at, "expected an array of 3 finite numbers");
            tmp[i][a] = json_number_value(x);
        }
        if (i > 0 && tmp[i][0] == tmp[i - 1][0] && tmp[i][1] == tmp[i - 1][1] && tmp[i][2] == tmp[i - 1][2])
            return lc_proto_list_fail(err, LC_PROTO_BAD_FIELD, at,
                                      "repeats the point before it (a segment of length 0)");
    }
    memcpy(points, tmp, n * sizeof tmp[0]);
    *count = (int)n;
    return 0;
}

json_t *lc_proto_seed_json(const double (*points)[3], int count)
{
    json_t *a = json_array();
    for (int i = 0; a && i < count; i++) {
        json_t *p = json_array();
        for (int k = 0; k < 3; k++)
            json_array_append_new(p, json_real(points[i][k]));
        json_array_append_new(a, p);
    }
    return a;
}

int lc_proto_parse_fixed(const json_t *v, lc_color_map *c, const char *path, lc_list_error *err)
{
    if (!json_is_array(v))
        return lc_proto_list_fail(err, LC_PROTO_BAD_FIELD, path, "expected an array of [lo, hi] ranges");
    size_t n = json_array_size(v);
    if (n > LC_MAX_COLOR_FIXED)
        return lc_proto_list_fail(err, LC_PROTO_OUT_OF_RANGE, path, "at most %d ranges", LC_MAX_COLOR_FIXED);
    double tmp[LC_MAX_COLOR_FIXED][2];
    for (size_t i = 0; i < n; i++) {
        char at[96];
        snprintf(at, sizeof at, "%s[%zu]", path, i);
        int rc = get_pair(json_array_get(v, i), tmp[i], at, err);
        if (rc)
            return rc;
        if (!(tmp[i][0] <= tmp[i][1]))
            return lc_proto_list_fail(err, LC_PROTO_BAD_FIELD, at, "lo must not exceed hi");
    }
    memcpy(c->fixed, tmp, n * sizeof tmp[0]);
    c->fixed_count = (int)n;
    return 0;
}

/* [[a, b], ...] of n pairs. */
static json_t *pairs_json(const double (*v)[2], int n)
{
    json_t *a = json_array();
    for (int i = 0; a && i < n; i++) {
        json_t *p = json_array();
        json_array_append_new(p, json_real(v[i][0]));
        json_array_append_new(p, json_real(v[i][1]));
        json_array_append_new(a, p);
    }
    return a;
}

json_t *lc_proto_fixed_json(const lc_color_map *c) { return pairs_json((const double(*)[2])c->fixed, c->fixed_count); }

json_t *lc_proto_curve_json(const lc_curve *c) { return pairs_json((const double(*)[2])c->points, c->count); }

json_t *lc_proto_terms_json(const lc_importance_map *m)
{
    json_t *a = json_array();
    for (int i = 0; a && i < m->term_count; i++) {
        const lc_importance_term *t = &m->terms[i];
        json_t *o = json_object();
        json_object_set_new(o, "attribute", json_string(t->attribute));
        if (t->has_range) {
            json_t *r = json_array();
            json_array_append_new(r, json_real(t->range[0]));
            json_array_append_new(r, json_real(t->range[1]));
            json_object_set_new(o, "range", r);
        }
        json_object_set_new(o, "weight", json_real(t->weight));
        if (t->invert)
            json_object_set_new(o, "invert", json_true());
        json_array_append_new(a, o);
    }
    return a;
}

json_t *lc_proto_filters_json(const lc_render_params *p)
{
    json_t *a = json_array();
    for (int i = 0; a && i < p->filter_count; i++) {
        const lc_filter *f = &p->filters[i];
        json_t *o = json_object();
        json_object_set_new(o, "attribute", json_string(f->attribute));
        json_object_set_new(o, "over", json_string(lc_filter_over_name(f->over)));
        if (f->lo_open || f->hi_open) {
            if (f->lo_open)
                json_object_set_new(o, "gt", json_real(f->lo));
            if (f->hi_open)
                json_object_set_new(o, "lt", json_real(f->hi));
        } else {
            json_t *r = json_array();
            json_array_append_new(r, json_real(f->lo));
            json_array_append_new(r, json_real(f->hi));
            json_object_set_new(o, "range", r);
        }
        json_array_append_new(a, o);
    }
    return a;
}
