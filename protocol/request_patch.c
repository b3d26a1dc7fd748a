/* A partial update parsed once into a typed patch and merged into requests (request_patch.h). */
#include "request_patch.h"

#include <stdlib.h>
#include <string.h>

struct lc_request_patch {
    json_t *given;     /* the update object: which fields it gives */
    lc_request values; /* their values, checked, on a default request (layers: their snapshot, shared) */
};

/* The members obj gives, copied from values (lc_proto_apply_request's merge
 * without its checks, which ran when the patch was parsed). Top-level objects
 * are sections: no top-level field takes an object. */
static void merge_members(const json_t *obj, const char *section, lc_request *r, const lc_request *values)
{
    const char *key;
    const json_t *v;
    json_object_foreach((json_t *)obj, key, v)
    {
        bool camera = !section && strcmp(key, "camera") == 0;
        if (camera && (json_is_null(v) || !r->render.has_camera)) {
            lc_render_params def; /* null: back to fitting the data; else merge onto the default camera */
            lc_render_params_default(&def);
            r->render.camera = def.camera;
            r->render.has_camera = !json_is_null(v);
        }
        if (!section && json_is_object(v))
            merge_members(v, key, r, values);
        else if (!camera)
            lc_proto_copy_field(section, key, r, values);
    }
}

int lc_proto_patch_parse(json_t *obj, const lc_proto_limits *lim, lc_request_patch **out, lc_proto_error *err)
{
    *out = NULL;
    lc_request_patch *p = malloc(sizeof *p);
    if (!p)
        return lc_proto_set_error(err, LC_PROTO_BAD_FIELD, "", "out of memory");
    lc_request_default(&p->values);
    int rc = lc_proto_check_fields(obj, lim, &p->values, err);
    if (rc) {
        lc_request_release(&p->values);
        free(p);
        return rc;
    }
    p->given = json_incref(obj);
    *out = p;
    return 0;
}

int lc_proto_patch_apply(const lc_request_patch *p, const lc_proto_limits *lim, lc_request *r, lc_proto_error *err)
{
    lc_request tmp; /* all or nothing; the layers are shared, not copied */
    lc_request_copy(&tmp, r);
    if (p)
        merge_members(p->given, NULL, &tmp, &p->values);
    int rc = lc_proto_validate_request(&tmp, lim, err);
    if (!rc) {
        lc_request_release(r);
        *r = tmp; /* takes over tmp's reference */
    } else {
        lc_request_release(&tmp);
    }
    return rc;
}

const json_t *lc_proto_patch_json(const lc_request_patch *p) { return p ? p->given : NULL; }

void lc_proto_patch_free(lc_request_patch *p)
{
    if (p) {
        json_decref(p->given);
        lc_request_release(&p->values);
    }
    free(p);
}
