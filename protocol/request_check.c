/* Judges a parsed request against the scope table (request_check.h). */
#include <stdio.h>
#include <string.h>

#include "request_check.h"
#include "request_scope.h"

/* One field: refused when it holds a non-default value where it does not apply. */
static int check_field(const char *section, const char *name, const lc_request *r, const lc_request *def,
                       unsigned prims, lc_proto_error *err)
{
    unsigned ms, ps;
    lc_proto_field_scope(section, name, &ms, &ps);
    bool method_ok = (ms >> r->render.method) & 1u;
    bool prims_ok = prims == 0 || (ps & prims) != 0;
    const char *when_path = NULL, *when_value = NULL;
    const char *held = NULL;
    json_t *w = NULL;
    if (method_ok && prims_ok && lc_proto_field_condition(section, name, &when_path, &when_value)) {
        char wsec[32];
        const char *dot = strchr(when_path, '.');
        snprintf(wsec, sizeof wsec, "%.*s", (int)(dot - when_path), when_path);
        w = lc_proto_field_json(r, wsec, dot + 1);
        held = json_is_string(w) ? json_string_value(w) : "";
        if (strcmp(held, when_value) == 0) {
            json_decref(w);
            return 0;
        }
    } else if (method_ok && prims_ok) {
        return 0;
    }
    json_t *v = lc_proto_field_json(r, section, name), *d = lc_proto_field_json(def, section, name);
    bool is_default = v == NULL || (d != NULL && json_equal(v, d));
    json_decref(v);
    json_decref(d);
    if (is_default) {
        json_decref(w);
        return 0;
    }
    char path[96];
    snprintf(path, sizeof path, "%s%s%s", section ? section : "", section ? "." : "", name);
    if (method_ok && prims_ok) { /* its condition does not hold */
        int rc = lc_proto_set_error(err, LC_PROTO_BAD_FIELD, path,
                                    "applies with %s \"%s\", not \"%s\": leave it at its default or change %s in "
                                    "the same request",
                                    when_path, when_value, held, when_path);
        json_decref(w);
        return rc;
    }
    if (!method_ok) {
        char list[160];
        lc_proto_method_list(ms, list, sizeof list);
        return lc_proto_set_error(err, LC_PROTO_BAD_FIELD, path,
                                  "applies to method %s, not %s: leave it at its default or change method in the "
                                  "same request",
                                  list, lc_method_name(r->render.method));
    }
    char kinds[64] = "";
    for (int k = 0; k < 3; k++)
        if (ps & (1u << k)) {
            size_t len = strlen(kinds);
            snprintf(kinds + len, sizeof kinds - len, "%s%s", len ? " and " : "", lc_proto_prim_name(k));
        }
    char drawn[64] = "";
    for (int k = 0; k < 3; k++)
        if (prims & (1u << k)) {
            size_t len = strlen(drawn);
            snprintf(drawn + len, sizeof drawn - len, "%s%s", len ? " and " : "", lc_proto_prim_name(k));
        }
    return lc_proto_set_error(err, LC_PROTO_BAD_FIELD, path,
                              "applies to %s; this frame draws %s: leave it at its default", kinds, drawn);
}

int lc_proto_check_scope(const json_t *given, const lc_request *r, unsigned prims, lc_proto_error *err)
{
    lc_request d, *def = &d;
    lc_request_default(def);
    int rc = 0;
    if (given == NULL) { /* every field of the table */
        const char *section, *name;
        for (size_t i = 0; rc == 0 && lc_proto_field_at(i, &section, &name); i++)
            rc = check_field(section, name, r, def, prims, err);
    } else if (json_is_object(given)) {
        const char *key;
        const json_t *v;
        json_object_foreach((json_t *)given, key, v)
        {
            if (json_is_object(v) && strcmp(key, "camera") != 0) { /* a section; layers are an array */
                const char *name;
                const json_t *m;
                json_object_foreach((json_t *)v, name, m)
                {
                    if ((rc = check_field(key, name, r, def, prims, err)) != 0)
                        break;
                }
            } else if (strcmp(key, "camera") != 0) {
                rc = check_field(NULL, key, r, def, prims, err);
            }
            if (rc)
                break;
        }
    }
    return rc;
}
