/* Streamline sets that requests ask for (traced.h). */
#include "traced.h"

#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "cost.h"
#include "fields.h"
#include "held.h"
#include "memory.h"
#include "metrics.h"
#include "streamlines.h"

#define MOD "traced"
#define SPEC_LEN 8192 /* 64 seeds of 3 round-trip doubles and the other keys */

struct lc_traced {
    lc_dataset ds; /* what frames draw: named after the field, source = the spec */
    const lc_field_entry *fe;
    char spec[SPEC_LEN]; /* the set ds holds (ds.source: its first 511 characters) */
    lc_scene *pending;   /* a re-trace the next frame swaps in (owner's lock) */
    lc_scene_measures pending_cost;
    uint64_t bytes, pending_bytes; /* their resident estimates, held (held.h) */
    char pending_spec[SPEC_LEN];
    uint64_t traces;
};

/* GPU copies of freed sets, for the next worker (any thread adds). */
static pthread_mutex_t grave_lock = PTHREAD_MUTEX_INITIALIZER;
static lc_gpu_scene **grave;
static size_t grave_count, grave_cap;

/* err (an lc_error naming its field) as the protocol's refusal. */
static int refusal(lc_proto_error *pe, const lc_error *e)
{
    const char *field = e->field[0] ? e->field : "streamlines.seeds";
    size_t len = strlen(e->field); /* e->msg may start with "field: " */
    const char *why = len && strncmp(e->msg, e->field, len) == 0 && e->msg[len] == ':' ? e->msg + len + 2 : e->msg;
    return lc_proto_set_error(pe, e->code == LC_ERR_LIMIT ? "too_expensive" : LC_PROTO_BAD_FIELD, field, "%s", why);
}

/* The spec of req's section on field fe, checked and priced. */
static int spec_of(lc_server *srv, const lc_field_entry *fe, const lc_request *req, char *spec, lc_proto_error *pe)
{
    if (lc_proto_streamlines_spec(req, fe->field->name, spec, SPEC_LEN) < 0)
        return lc_proto_set_error(pe, LC_PROTO_BAD_FIELD, "streamlines.seeds", "the set's settings are too long");
    lc_error e = {0};
    double vertices = 0;
    if (lc_streamlines_check(spec, fe->field, &vertices, NULL, &e) != 0)
        return refusal(pe, &e);
    double cost = lc_cost_trace(vertices);
    if (srv->cfg.max_cost > 0 && cost > srv->cfg.max_cost) {
        lc_metrics_refused(srv->metrics, "cost");
        return lc_proto_set_error(pe, "too_expensive", "streamlines.count",
                                  "tracing about %.3g vertices costs %.3g units, over --max-cost %.3g: trace fewer or "
                                  "shorter curves (count, length) or take a larger step",
                                  vertices, cost, srv->cfg.max_cost);
    }
    return 0;
}

/* Traces spec through fe's field (the load-time code path) and counts its
 * resident estimate in *bytes: refused naming streamlines.count when it does
 * not fit --max-memory beside the loaded datasets and what requests hold
 * (held.h: the sets alive, surfaces' curves). */
static int trace(lc_server *srv, lc_traced *t, const char *spec, lc_scene **out, lc_scene_measures *cost,
                 uint64_t *bytes, lc_proto_error *pe)
{
    long cpus = sysconf(_SC_NPROCESSORS_ONLN);
    lc_error e = {0};
    double t0 = lc_now();
    if (lc_streamlines_load_field(spec, t->fe->field, cpus > 0 ? (int)cpus : 1, out, &e) != 0)
        return refusal(pe, &e);
    /* GPU buffers and one session's state (lc_memory_estimate) and the vertex arrays the set keeps */
    lc_gpu_scene_desc desc = {.exact_positions = t->ds.exact_positions};
    const lc_scene *s = *out;
    uint64_t need = lc_memory_estimate(s, &desc, srv->cfg.workers > 0 ? srv->cfg.workers : 1, 1) +
                    (uint64_t)s->vertex_count * (3 + (uint64_t)s->attribute_count) * sizeof(float);
    uint64_t estimated = 0, limit = 0;
    lc_datasets_budget(srv->datasets, &estimated, &limit);
    uint64_t held = lc_held_total();
    if (limit && estimated + held + need > limit) {
        lc_scene_destroy(*out);
        *out = NULL;
        lc_metrics_refused(srv->metrics, "memory");
        return lc_proto_set_error(
            pe, "too_expensive", "streamlines.count",
            "the set needs an estimated %.1f MB resident; with the datasets (%.1f MB) and the "
            "sets and surfaces other renders hold (%.1f MB) it exceeds --max-memory %.1f MB: trace fewer or "
            "shorter curves",
            need / 1e6, estimated / 1e6, held / 1e6, limit / 1e6);
    }
    lc_held_add(LC_HELD_STREAMLINE_SETS, (int64_t)need);
    *bytes = need;
    lc_scene_measure(*out, cost);
    t->traces++;
    LC_INFO(MOD, "traced %s: %u lines, %u vertices in %.3f s", spec, (*out)->line_count, (*out)->vertex_count,
            lc_now() - t0);
    return 0;
}

const lc_dataset *lc_traced_resolve(lc_server *srv, const lc_request *req, lc_traced **owned, lc_proto_error *pe)
{
    *owned = NULL;
    const lc_dataset *ds = lc_datasets_find(srv->datasets, req->dataset);
    if (ds)
        return ds;
    const lc_field_entry *fe = req->dataset[0] ? lc_fields_find(lc_datasets_fields(srv->datasets), req->dataset) : NULL;
    if (!fe) {
        lc_proto_set_error(pe, "not_found", "dataset", "unknown dataset \"%.300s\"", req->dataset);
        return NULL;
    }
    if (srv->mpi) { /* the ranks hold scene shards; a traced set is one process's */
        lc_proto_set_error(pe, LC_PROTO_BAD_FIELD, "dataset",
                           "%s is a vector field: its streamline sets are not traced under --mpi", fe->field->name);
        return NULL;
    }
    char *spec = malloc(SPEC_LEN);
    lc_traced *t = calloc(1, sizeof *t);
    if (!spec || !t) {
        free(spec), free(t);
        lc_proto_set_error(pe, LC_PROTO_TOO_LARGE, "dataset", "out of memory");
        return NULL;
    }
    t->fe = fe;
    lc_dataset *d = &t->ds;
    const lc_dataset *first = lc_datasets_at(srv->datasets, 0);
    d->exact_positions = first ? first->exact_positions : 0; /* the daemon's layout (--exact-positions) */
    int rc = spec_of(srv, fe, req, spec, pe);
    if (rc == 0)
        rc = trace(srv, t, spec, &d->scene, &d->cost, &t->bytes, pe);
    if (rc != 0) {
        free(spec), free(t);
        return NULL;
    }
    snprintf(d->name, sizeof d->name, "%s", fe->field->name);
    snprintf(t->spec, sizeof t->spec, "%s", spec);
    snprintf(d->source, sizeof d->source, "%.511s", spec);
    d->traced = t;
    free(spec);
    *owned = t;
    return d;
}

int lc_traced_check(lc_server *srv, const lc_request *req, const lc_dataset *ds, lc_proto_error *pe)
{
    if (!ds || !ds->traced) {
        const char *field = NULL;
        if (!lc_proto_streamlines_given(req, &field))
            return 0;
        return lc_proto_set_error(pe, LC_PROTO_BAD_FIELD, field,
                                  "applies when dataset names a vector field (GET /api/v1/datasets lists them under "
                                  "\"fields\"); %s%.200s%s is not one",
                                  ds ? "\"" : "", ds ? ds->name : "this render", ds ? "\"" : "");
    }
    if (lc_request_layer_count(req) > 0) /* layers draw loaded datasets; the set would be left out */
        return lc_proto_set_error(pe, LC_PROTO_BAD_FIELD, "layers",
                                  "%.200s is a vector field whose streamline set draws alone: drop layers, or name "
                                  "loaded datasets in them",
                                  ds->name);
    char *spec = malloc(SPEC_LEN);
    if (!spec)
        return lc_proto_set_error(pe, LC_PROTO_TOO_LARGE, "streamlines", "out of memory");
    int rc = spec_of(srv, ds->traced->fe, req, spec, pe);
    free(spec);
    return rc;
}

int lc_traced_update(lc_server *srv, const lc_dataset *ds, const lc_request *req, lc_proto_error *pe)
{
    if (!ds || !ds->traced)
        return 0;
    lc_traced *t = ds->traced;
    char *spec = malloc(SPEC_LEN);
    if (!spec)
        return lc_proto_set_error(pe, LC_PROTO_TOO_LARGE, "streamlines", "out of memory");
    int rc = spec_of(srv, t->fe, req, spec, pe);
    const char *now = t->pending ? t->pending_spec : t->spec;
    if (rc == 0 && strcmp(spec, now) != 0 && strcmp(spec, t->spec) == 0) { /* back to the set it draws */
        lc_scene_destroy(t->pending);
        lc_held_add(LC_HELD_STREAMLINE_SETS, -(int64_t)t->pending_bytes);
        t->pending = NULL, t->pending_bytes = 0;
    } else if (rc == 0 && strcmp(spec, now) != 0) { /* the seeding changed: a new set */
        lc_scene *scene = NULL;
        lc_scene_measures cost;
        uint64_t bytes = 0;
        rc = trace(srv, t, spec, &scene, &cost, &bytes, pe);
        if (rc == 0) {
            lc_scene_destroy(t->pending);
            lc_held_add(LC_HELD_STREAMLINE_SETS, -(int64_t)t->pending_bytes);
            t->pending = scene, t->pending_cost = cost, t->pending_bytes = bytes;
            snprintf(t->pending_spec, sizeof t->pending_spec, "%s", spec);
        }
    }
    free(spec);
    return rc;
}

/* Leaves gs for a worker to destroy. */
static void bury(lc_gpu_scene *gs)
{
    if (!gs)
        return;
    pthread_mutex_lock(&grave_lock);
    if (grave_count == grave_cap) {
        size_t cap = grave_cap ? 2 * grave_cap : 8;
        lc_gpu_scene **g = realloc(grave, cap * sizeof *g);
        if (g)
            grave = g, grave_cap = cap;
    }
    if (grave_count < grave_cap)
        grave[grave_count++] = gs;
    else
        LC_WARN(MOD, "out of memory: a freed set's GPU copy stays until exit");
    pthread_mutex_unlock(&grave_lock);
}

void lc_traced_collect(void)
{
    pthread_mutex_lock(&grave_lock);
    size_t n = grave_count;
    lc_gpu_scene **g = grave;
    grave = NULL, grave_count = grave_cap = 0;
    pthread_mutex_unlock(&grave_lock);
    for (size_t i = 0; i < n; i++)
        lc_gpu_scene_destroy(g[i]);
    free(g);
}

int lc_traced_ready(const lc_dataset *ds, pthread_mutex_t *lock, bool *replaced, lc_error *err)
{
    lc_traced_collect();
    if (!ds || !ds->traced)
        return 0;
    lc_traced *t = ds->traced;
    lc_scene *old_scene = NULL;
    lc_gpu_scene *old_gpu = NULL;
    if (lock)
        pthread_mutex_lock(lock);
    if (t->pending) {
        old_scene = t->ds.scene, old_gpu = t->ds.gpu;
        lc_held_add(LC_HELD_STREAMLINE_SETS, -(int64_t)t->bytes);
        t->bytes = t->pending_bytes, t->pending_bytes = 0;
        t->ds.scene = t->pending, t->ds.gpu = NULL, t->ds.cost = t->pending_cost;
        snprintf(t->spec, sizeof t->spec, "%s", t->pending_spec);
        snprintf(t->ds.source, sizeof t->ds.source, "%.511s", t->spec);
        t->pending = NULL;
        if (replaced)
            *replaced = true;
    }
    if (lock)
        pthread_mutex_unlock(lock);
    if (old_gpu)
        lc_gpu_scene_destroy(old_gpu);
    lc_scene_destroy(old_scene);
    if (t->ds.gpu)
        return 0;
    lc_gpu_scene_desc desc = {.exact_positions = t->ds.exact_positions};
    lc_gpu_scene *gs = NULL;
    int rc = lc_gpu_scene_create_ex(t->ds.scene, &desc, &gs, err);
    if (rc != 0)
        return rc;
    if (lock)
        pthread_mutex_lock(lock);
    t->ds.gpu = gs;
    if (lock)
        pthread_mutex_unlock(lock);
    return 0;
}

uint64_t lc_traced_traces(const lc_dataset *ds) { return ds && ds->traced ? ds->traced->traces : 0; }

void lc_traced_free(lc_traced *t)
{
    if (!t)
        return;
    bury(t->ds.gpu);
    lc_scene_destroy(t->ds.scene);
    lc_scene_destroy(t->pending);
    lc_held_add(LC_HELD_STREAMLINE_SETS, -(int64_t)(t->bytes + t->pending_bytes));
    free(t);
}
