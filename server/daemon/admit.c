/* Admission of a parsed request (admit.h). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "admit.h"
#include "cost.h"
#include "fields.h"
#include "frame_check.h"
#include "metrics.h"
#include "request_check.h"
#include "surface_render.h"
#include "traced.h"

int lc_admit_surface(lc_server *srv, const lc_request *req, double *cost_out, const lc_field **field_out,
                     lc_proto_error *pe)
{
    const lc_surface_request *s = &req->surface;
    if (srv->mpi) /* the ranks hold scene shards; a field's surface is one process's work */
        return lc_proto_set_error(pe, LC_PROTO_BAD_FIELD, "method", "surface-layers is not served under --mpi");
    const lc_field_entry *fe = lc_fields_find(lc_datasets_fields(srv->datasets), s->field);
    if (!fe)
        return lc_proto_set_error(pe, "not_found", "surface.field",
                                  "unknown field \"%.200s\" (GET /api/v1/datasets lists the fields)", s->field);
    lc_seed seed = {.count = s->seed_count};
    memcpy(seed.points, s->seed, (size_t)s->seed_count * sizeof s->seed[0]);
    lc_error e = {0};
    if (lc_seed_check(&seed, fe->field, &e) != 0)
        return lc_proto_set_error(pe, LC_PROTO_BAD_FIELD, "surface.seed", "%s", e.msg);
    const double *b = fe->field->bounds;
    double diag = sqrt((b[3] - b[0]) * (b[3] - b[0]) + (b[4] - b[1]) * (b[4] - b[1]) + (b[5] - b[2]) * (b[5] - b[2]));
    int k = 1;
    lc_surface_bytes(req->render.width, req->render.height, s->max_layers, &k);
    double steps = lc_cost_surface_steps(diag, fe->field->mag_max, s->step, s->length), cost = 0;
    if (s->direction == LC_TRACE_BOTH) /* two halves, each up to the length */
        steps *= 2;
    const char *field = NULL;
    char why[320];
    int rc =
        lc_cost_check_surface(&req->render, s->particles, steps, k, srv->cfg.max_cost, &cost, &field, why, sizeof why);
    if (cost_out)
        *cost_out = cost;
    if (field_out)
        *field_out = fe->field;
    if (rc == 0)
        return 0;
    lc_metrics_refused(srv->metrics, "cost");
    return lc_proto_set_error(pe, "too_expensive", field, "%s", why);
}

int lc_admit_budget(lc_server *srv, const lc_dataset *ds, const lc_request *req, double *cost_out, lc_proto_error *pe)
{
    if (req->render.method == LC_METHOD_SURFACE_LAYERS)
        return lc_admit_surface(srv, req, cost_out, NULL, pe);
    double cost;
    const char *field = NULL;
    char why[320];
    int rc = lc_cost_check(&ds->cost, &req->render, srv->cfg.max_cost, &cost, &field, why, sizeof why);
    if (cost_out)
        *cost_out = cost;
    if (rc == 0)
        return 0;
    lc_metrics_refused(srv->metrics, "cost");
    return lc_proto_set_error(pe, "too_expensive", field, "%s", why);
}

int lc_admit_resolve_layers(lc_server *srv, const lc_request *req, const lc_dataset **out, lc_proto_error *pe)
{
    for (int i = 0; i < lc_request_layer_count(req); i++) {
        out[i] = lc_datasets_find(srv->datasets, req->layers->dataset[i]);
        if (!out[i]) {
            char field[32];
            snprintf(field, sizeof field, "layers[%d].dataset", i);
            if (req->layers->dataset[i][0] &&
                lc_fields_find(lc_datasets_fields(srv->datasets), req->layers->dataset[i]))
                return lc_proto_set_error(
                    pe, LC_PROTO_BAD_FIELD, field,
                    "\"%.300s\" is a vector field: its streamline set draws alone, not as a layer",
                    req->layers->dataset[i]);
            return lc_proto_set_error(pe, "not_found", field, "unknown dataset \"%.300s\"", req->layers->dataset[i]);
        }
    }
    return 0;
}

int lc_admit_frame_budget(lc_server *srv, const lc_dataset *ds, const lc_dataset *const *layers, const lc_request *req,
                          double *cost, lc_proto_error *pe)
{
    return lc_request_layer_count(req) > 0 && layers ? lc_admit_layers_budget(srv, layers, req, cost, pe)
                                                     : lc_admit_budget(srv, ds, req, cost, pe);
}

int lc_admit_layers_budget(lc_server *srv, const lc_dataset *const *ds, const lc_request *req, double *cost,
                           lc_proto_error *pe)
{
    const lc_scene_measures *st[LC_MAX_LAYERS];
    const lc_layer_params *layers[LC_MAX_LAYERS];
    for (int i = 0; i < lc_request_layer_count(req); i++)
        st[i] = &ds[i]->cost, layers[i] = &req->layers->p[i];
    const char *field = NULL;
    char why[320];
    double c = 0;
    int rc = lc_cost_check_layers(st, layers, lc_request_layer_count(req), &req->render, srv->cfg.max_cost, &c, &field,
                                  why, sizeof why);
    if (cost)
        *cost = c;
    if (rc == 0)
        return 0;
    lc_metrics_refused(srv->metrics, "cost");
    return lc_proto_set_error(pe, "too_expensive", field, "%s", why);
}

/* The renderer's refusals, checked on the loaded scenes without a frame. */
static int check_render(const lc_request *req, const lc_dataset *ds, const lc_dataset *const *layers,
                        lc_proto_error *pe)
{
    int n = lc_request_layer_count(req);
    const lc_scene *scenes[LC_MAX_LAYERS];
    lc_layer_params *lp = NULL;
    if (n > 0) {
        lp = malloc((size_t)n * sizeof *lp);
        if (!lp)
            return lc_proto_set_error(pe, LC_PROTO_BAD_FIELD, "layers", "out of memory");
        for (int i = 0; i < n; i++)
            scenes[i] = layers[i]->scene, lp[i] = req->layers->p[i];
    } else {
        if (!ds || !ds->scene)
            return 0; /* a field without a scene: the surface path checks its own */
        scenes[0] = ds->scene;
    }
    lc_error err = {0};
    int rc = lc_render_check(scenes, lp, n > 0 ? n : 1, &req->render, 0, &err);
    free(lp);
    if (rc == 0)
        return 0;
    size_t len = strlen(err.field); /* err.msg is "field: reason" */
    const char *why = len && strncmp(err.msg, err.field, len) == 0 && err.msg[len] == ':' ? err.msg + len + 2 : err.msg;
    return lc_proto_set_error(pe, LC_PROTO_BAD_FIELD, err.field, "%s", why);
}

int lc_request_admit(lc_server *srv, const json_t *given, const lc_request *req, const lc_dataset *ds,
                     const lc_dataset *const *layers, double *cost, lc_proto_error *pe)
{
    unsigned prims = 0;
    if (req->render.method != LC_METHOD_SURFACE_LAYERS) {
        for (int i = 0; i < lc_request_layer_count(req); i++)
            prims |= 1u << layers[i]->scene->type;
        if (lc_request_layer_count(req) == 0 && ds && ds->scene)
            prims = 1u << ds->scene->type;
    }
    int rc = lc_proto_check_scope(given, req, prims, pe);
    if (rc == 0) /* the streamlines section: a field's set only, its seeding checked and priced */
        rc = lc_traced_check(srv, req, ds, pe);
    if (rc == 0 && req->render.method != LC_METHOD_SURFACE_LAYERS)
        rc = check_render(req, ds, layers, pe);
    if (rc == 0)
        rc = lc_admit_frame_budget(srv, ds, layers, req, cost, pe);
    return rc;
}

int lc_admit_update(lc_server *srv, const lc_request *base, const lc_request_patch *patch, const lc_proto_limits *lim,
                    const lc_dataset **ds, lc_request *out, const lc_dataset **layers, lc_traced **traced,
                    lc_proto_error *pe)
{
    lc_request_copy(out, base); /* shares base's layers */
    if (patch) /* a streamlines object is the whole set: keys it leaves out go back to their defaults */
        lc_proto_streamlines_replace(lc_proto_patch_json(patch), out);
    int rc = lc_proto_patch_apply(patch, lim, out, pe);
    if (rc == 0)
        rc = lc_admit_resolve_layers(srv, out, layers, pe);
    if (rc != 0)
        return rc;
    bool existing = *ds != NULL;
    if (existing) { /* a session's: the update may name it (or another name of it), not change it */
        if (strcmp(out->dataset, (*ds)->name) != 0 && lc_datasets_find(srv->datasets, out->dataset) != *ds)
            return lc_proto_set_error(pe, LC_PROTO_BAD_FIELD, "dataset",
                                      "cannot change within a session (it is \"%s\")", (*ds)->name);
    } else {
        /* A new session's: the one named, or with layers[] and none named layers[0]'s; where
         * the caller keeps one, a vector field's streamline set traced now (traced.h). */
        if (!out->dataset[0] && lc_request_layer_count(out) > 0)
            *ds = layers[0];
        else if (traced)
            *ds = lc_traced_resolve(srv, out, traced, pe);
        else
            *ds = lc_datasets_find(srv->datasets, out->dataset);
        if (!*ds)
            return traced && !(!out->dataset[0] && lc_request_layer_count(out) > 0)
                       ? -1
                       : lc_proto_set_error(pe, "not_found", "dataset", "unknown dataset \"%.300s\"", out->dataset);
        snprintf(out->dataset, sizeof out->dataset, "%s", (*ds)->name);
    }
    if (out->render.foo.progressive > 1) /* not connected to the sessions' still stages yet (docs/ALGORITHM.md §34) */
        return lc_proto_set_error(pe, LC_PROTO_BAD_FIELD, "params.progressive",
                                  "a session's frames do not draw in batches yet; POST /api/v1/render and lucent "
                                  "render do (leave it 1 here)");
    json_t *none = patch ? NULL : json_object(); /* no field given: only the request's own refusals (size, cost) */
    const json_t *given = patch ? lc_proto_patch_json(patch) : none;
    rc = given ? lc_request_admit(srv, given, out, *ds, layers, NULL, pe)
               : lc_proto_set_error(pe, LC_PROTO_BAD_FIELD, "", "out of memory");
    json_decref(none);
    if (rc == 0 && existing) /* a session's set: a changed streamlines section traces the new one */
        rc = lc_traced_update(srv, *ds, out, pe);
    return rc;
}
