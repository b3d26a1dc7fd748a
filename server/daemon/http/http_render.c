/* HTTP renders: one-shot and session renders on the worker pool, the image
 * with its statistics as headers (http_render.h). */
#include "http_render.h"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "admit.h"
#include "colormap.h"
#include "conn_limits.h"
#include "datasets.h"
#include "fields.h"
#include "messages.h"
#include "metrics.h"
#include "session.h"
#include "traced.h"
#include "workers.h"

#define MOD "http"

/* The statistics of a render as response headers (protocol/openapi.yaml
 * "Image"): X-Lucent-Timings, Server-Timing, X-Lucent-Converged,
 * X-Lucent-Max-Alpha-Change, X-Lucent-Elements, X-Lucent-Progressive
 * (params.progressive), X-Lucent-Visibility (methods
 * with element opacities, and kanzler), X-Lucent-Cost and X-Lucent-Frame (session renders). */
/* X-Lucent-Warning: a scripted render chooses no background for its client,
 * so say when the colour of the highest values (with colour by importance,
 * the most important structures) is lost in the one asked for, e.g.
 * viridis' yellow on the default white: the page opens on a contrasting one. */
static void add_contrast_warning(struct MHD_Response *r, const lc_render_job *job)
{
    const lc_color_map *c = &job->req.render.color;
    if (job->field || lc_request_layer_count(&job->req) > 0 || !job->dataset || !job->dataset->scene)
        return;
    const char *attr = c->attribute[0] ? c->attribute : job->dataset->scene->default_color;
    if (strcmp(attr, "rgb") == 0)
        return;
    const char *name = c->colormap[0] ? c->colormap : "viridis";
    int map = lc_colormap_find(name);
    if (map < 0)
        return;
    float top = c->has_range && c->range[0] > c->range[1] ? 0.0f : 1.0f;
    const double *bg = job->req.render.style.background;
    double ratio = lc_colormap_contrast(map, top, bg);
    if (ratio >= LC_COLORMAP_CLASH_RATIO)
        return;
    double white[3] = {1, 1, 1};
    char text[320];
    snprintf(text, sizeof text,
             "color.colormap: the highest values of %.40s have a contrast of %.2f:1 against style.background; "
             "style.background [%s] shows them",
             name, ratio, lc_colormap_contrast(map, top, white) >= 3.0 ? "1, 1, 1" : "0.1, 0.1, 0.1");
    MHD_add_response_header(r, "X-Lucent-Warning", text);
}

static void add_frame_headers(struct MHD_Response *r, const lc_render_job *job)
{
    add_contrast_warning(r, job);
    const lc_frame_info *info = &job->info;
    /* X-Lucent-Timings: pass=ms pairs (openapi.yaml); Server-Timing shows the
     * same in browser dev tools. */
    char timings[768], server_timing[1024];
    size_t tn = 0, sn = 0;
    timings[0] = server_timing[0] = '\0';
    for (int p = 0; p < LC_PASS_COUNT; p++) {
        if (info->pass_ms[p] < 0)
            continue;
        tn += (size_t)snprintf(timings + tn, sizeof timings - tn, "%s%s=%.3f", tn ? "," : "", lc_pass_name(p),
                               info->pass_ms[p]);
        sn += (size_t)snprintf(server_timing + sn, sizeof server_timing - sn, "%s%s;dur=%.3f", sn ? ", " : "",
                               lc_pass_name(p), info->pass_ms[p]);
        if (tn >= sizeof timings || sn >= sizeof server_timing)
            break;
    }
    if (tn < sizeof timings)
        snprintf(timings + tn, sizeof timings - tn, "%sgpu=%.3f,wall=%.3f,encode=%.3f,queue=%.3f", tn ? "," : "",
                 info->gpu_ms, info->wall_ms, job->encode_ms, job->queue_ms);
    if (sn < sizeof server_timing)
        snprintf(server_timing + sn, sizeof server_timing - sn, "%sencode;dur=%.3f, queue;dur=%.3f", sn ? ", " : "",
                 job->encode_ms, job->queue_ms);
    MHD_add_response_header(r, "X-Lucent-Timings", timings);
    MHD_add_response_header(r, "Server-Timing", server_timing);
    char buf[64];
    snprintf(buf, sizeof buf, "%s", info->converged ? "true" : "false");
    MHD_add_response_header(r, "X-Lucent-Converged", buf);
    snprintf(buf, sizeof buf, "%.6g", info->max_alpha_change);
    MHD_add_response_header(r, "X-Lucent-Max-Alpha-Change", buf);
    snprintf(buf, sizeof buf, "%u", info->element_count);
    MHD_add_response_header(r, "X-Lucent-Elements", buf);
    if (info->batches > 0) { /* params.progressive: batch n of n, and when the first batch's picture was ready */
        char prog[128];
        snprintf(prog, sizeof prog, "batch=%d,of=%d,firstMs=%.3f,wallMs=%.3f", info->batch, info->batches,
                 info->first_batch_ms, info->wall_ms);
        MHD_add_response_header(r, "X-Lucent-Progressive", prog);
    }
    if (info->has_visibility) {
        char vis[224];
        snprintf(vis, sizeof vis,
                 "topDecileAlpha=%.4f,bottomHalfAlpha=%.4f,coveredFraction=%.4f,occluderAlpha=%.4f,"
                 "importantOccluded=%.4f",
                 info->top_decile_alpha, info->bottom_half_alpha, info->covered_fraction, info->occluder_alpha,
                 info->important_occluded);
        if (info->has_reach) /* the fourier method measures it (docs/ALGORITHM.md §8) */
            snprintf(vis + strlen(vis), sizeof vis - strlen(vis), ",topDecileReach=%.4f", info->top_decile_reach);
        MHD_add_response_header(r, "X-Lucent-Visibility", vis);
        char layers[LC_MAX_LAYERS * 48] = "";
        for (int i = 0; i < info->layer_count && i < LC_MAX_LAYERS;
             i++) { /* layered frames: "top/bottom/occluder;..." */
            size_t len = strlen(layers);
            snprintf(layers + len, sizeof layers - len, "%s%.4f/%.4f/%.4f", i ? ";" : "",
                     info->layers[i].top_decile_alpha, info->layers[i].bottom_half_alpha,
                     info->layers[i].occluder_alpha);
        }
        if (layers[0])
            MHD_add_response_header(r, "X-Lucent-Layer-Visibility", layers);
    }
    if (info->clarity_tries > 0) { /* params.clarity: the strength used, and whether it met the goal */
        char cl[128];
        snprintf(cl, sizeof cl, "lambdaFactor=%.4g,penaltyFactor=%.4g,reached=%s", info->clarity_lambda,
                 info->clarity_penalty, info->clarity_reached ? "true" : "false");
        if (info->clarity_smoothing_cut) /* the loop cut params.smoothing (docs/ALGORITHM.md §25) */
            snprintf(cl + strlen(cl), sizeof cl - strlen(cl), ",smoothing=%d", info->clarity_smoothing);
        MHD_add_response_header(r, "X-Lucent-Clarity", cl);
    }
    if (info->has_color_ticks) { /* color.equalize: the legend's data values at 0, 1/4, ..., 1 of the bar */
        char ticks[160];
        snprintf(ticks, sizeof ticks, "%.6g,%.6g,%.6g,%.6g,%.6g", info->color_ticks[0], info->color_ticks[1],
                 info->color_ticks[2], info->color_ticks[3], info->color_ticks[4]);
        MHD_add_response_header(r, "X-Lucent-Color-Ticks", ticks);
    }
    if (info->has_surface) { /* method surface-layers: what the layers hold */
        char surf[256];
        snprintf(surf, sizeof surf,
                 "curves=%llu,layersPerPixel=%.3f,maxLayers=%u,k=%d,overflow=%llu,traceMs=%.1f,drawnFragments=%llu",
                 (unsigned long long)info->surface_curves, info->surface_mean_layers, info->surface_max_layers,
                 info->surface_k, (unsigned long long)info->surface_overflow, info->surface_trace_ms,
                 (unsigned long long)info->surface_drawn_fragments);
        MHD_add_response_header(r, "X-Lucent-Surface", surf);
    }
    if (info->tiles > 0) { /* composited in tiles (a large one-shot frame) */
        snprintf(buf, sizeof buf, "%d", info->tiles);
        MHD_add_response_header(r, "X-Lucent-Tiles", buf);
    }
    snprintf(buf, sizeof buf, "%.4g", job->cost); /* the estimate --max-cost is compared with */
    MHD_add_response_header(r, "X-Lucent-Cost", buf);
    if (job->session) {
        snprintf(buf, sizeof buf, "%llu", (unsigned long long)job->session->http_frames);
        MHD_add_response_header(r, "X-Lucent-Frame", buf);
    }
}

/* Called once by the pool (encoder or worker thread) when a job is finished:
 * releases the session for its next frame and resumes the connection, whose
 * handler then sends the image. The pool does not touch the job afterwards. */
static void job_done(lc_render_job *job)
{
    lc_http_req *ctx = job->user;
    if (job->session) {
        pthread_mutex_lock(&job->session->lock);
        job->session->http_busy = false;
        if (job->rc == 0)
            job->session->http_frames++;
        pthread_mutex_unlock(&job->session->lock);
    }
    atomic_store(&ctx->job_finished, 1);
    MHD_resume_connection(ctx->conn);
}

void lc_http_free_job(lc_render_job *job)
{
    if (!job)
        return;
    free(job->image);
    lc_traced_free(job->traced);
    lc_request_release(&job->req);
    if (job->session)
        lc_session_unref(job->session);
    free(job);
}

/* The fairness key of a one-shot render: the client (lc_conn_client_key). */
static uint64_t client_key(struct MHD_Connection *c)
{
    return lc_conn_client_key(c) | 1; /* never 0, never a session pointer (those are even) */
}

static enum MHD_Result queue_job(lc_http_req *ctx, struct MHD_Connection *c, const lc_request *req,
                                 const lc_dataset *ds, const lc_dataset *const *layers, lc_session *session, double dt,
                                 double cost, const lc_field *field);

/* Queues a render and suspends the connection until it is done. Takes the
 * session reference (may be NULL); refuses (400, the field named) a request
 * that admit.h refuses: a field where it does not apply, what the renderer
 * would refuse, a cost above --max-cost. */
static enum MHD_Result start_render(lc_http_req *ctx, struct MHD_Connection *c, const lc_request *req,
                                    const lc_dataset *ds, const lc_dataset *const *layers, lc_session *session,
                                    double dt)
{
    lc_server *srv = ctx->srv;
    double cost = 0;
    lc_proto_error pe;
    /* A session's update was admitted as it was applied (lc_session_update_locked);
     * a one-shot request is judged whole here. */
    int refused = session ? lc_admit_frame_budget(srv, ds, layers, req, &cost, &pe)
                          : lc_request_admit(srv, NULL, req, ds, layers, &cost, &pe);
    if (refused != 0) {
        if (session) {
            pthread_mutex_lock(&session->lock);
            session->http_busy = false;
            pthread_mutex_unlock(&session->lock);
            lc_session_unref(session);
        }
        return lc_http_proto_error(srv, c, &pe);
    }
    return queue_job(ctx, c, req, ds, layers, session, dt, cost, NULL);
}

/* method surface-layers (docs/ALGORITHM.md §23): the field must be loaded (404
 * naming surface.field), the seed must start inside it (400 naming
 * surface.seed) and the frame fit --max-cost; not under serve --mpi, whose
 * ranks hold scene shards. */
static enum MHD_Result start_surface(lc_http_req *ctx, struct MHD_Connection *c, const lc_request *req)
{
    lc_server *srv = ctx->srv;
    if (srv->mpi)
        return lc_http_error(srv, c, 400, LC_PROTO_BAD_FIELD, "method",
                             "method: surface-layers is not served under --mpi");
    double cost = 0;
    lc_proto_error pe;
    if (lc_request_admit(srv, NULL, req, NULL, NULL, &cost, &pe) != 0)
        return strcmp(pe.code, "not_found") == 0 ? lc_http_error(srv, c, 404, "not_found", pe.field, "%s", pe.message)
                                                 : lc_http_proto_error(srv, c, &pe);
    /* admitted, so the field is loaded (lc_admit_surface found it) */
    const lc_field *field = lc_fields_find(lc_datasets_fields(srv->datasets), req->surface.field)->field;
    return queue_job(ctx, c, req, NULL, NULL, NULL, 0.0, cost, field);
}

/* Hands a checked render to the pool (field: method surface-layers). */
static enum MHD_Result queue_job(lc_http_req *ctx, struct MHD_Connection *c, const lc_request *req,
                                 const lc_dataset *ds, const lc_dataset *const *layers, lc_session *session, double dt,
                                 double cost, const lc_field *field)
{
    lc_server *srv = ctx->srv;
    lc_render_job *job = calloc(1, sizeof *job);
    if (!job) {
        if (session)
            lc_session_unref(session);
        return lc_http_error(srv, c, 503, "overloaded", NULL, "out of memory");
    }
    lc_request_copy(&job->req, req); /* the layers by reference (lc_http_free_job drops it) */
    job->dataset = ds;
    job->field = field;
    job->traced = ctx->traced; /* freed with the job (lc_http_free_job) */
    ctx->traced = NULL;
    for (int i = 0; layers && i < lc_request_layer_count(req); i++)
        job->layers[i] = layers[i];
    job->session = session;
    job->dt = dt;
    job->cost = cost;
    job->client = client_key(c);
    job->done = job_done;
    job->user = ctx;
    ctx->conn = c;
    ctx->job = job;
    /* Suspend before queueing, so that job_done's resume always follows it. */
    MHD_suspend_connection(c);
    lc_error err = {0};
    int rc = lc_workers_submit(srv->workers, job, &err);
    if (rc != 0) {
        job->rc = rc;
        job->err = err;
        if (session) {
            pthread_mutex_lock(&session->lock);
            session->http_busy = false;
            pthread_mutex_unlock(&session->lock);
        }
        atomic_store(&ctx->job_finished, 1);
        MHD_resume_connection(c);
    }
    return MHD_YES;
}

/* The finished job's response: the image with timing headers, or an error. */
enum MHD_Result lc_http_finish_render(lc_http_req *ctx, struct MHD_Connection *c)
{
    lc_server *srv = ctx->srv;
    lc_render_job *job = ctx->job;
    if (job->rc != 0) {
        if (job->refused)
            lc_metrics_refused(srv->metrics, job->refused);
        switch (job->rc) {
        case LC_ERR_LIMIT:
            if (!job->refused && job->err.field[0]) { /* the memory budget, naming what to lower (surface_memory.h) */
                lc_metrics_refused(srv->metrics, "memory");
                return lc_http_error(srv, c, 400, "too_expensive", job->err.field, "%s", job->err.msg);
            }
            return lc_http_error(srv, c, job->refused && strcmp(job->refused, "client_queue") == 0 ? 429 : 503,
                                 "overloaded", NULL, "%s", job->err.msg);
        case LC_ERR_UNSUPPORTED:
        case LC_ERR_NOMEM: return lc_http_error(srv, c, 503, "overloaded", NULL, "%s", job->err.msg);
        case LC_ERR_NOT_FOUND: return lc_http_error(srv, c, 404, "not_found", NULL, "%s", job->err.msg);
        case LC_ERR_BUDGET: /* the work ran past what its estimate was granted (cost.h) */
            lc_metrics_refused(srv->metrics, "cost");
            return lc_http_error(srv, c, 400, "too_expensive", job->err.field[0] ? job->err.field : NULL, "%s",
                                 job->err.msg);
        case LC_ERR_INVALID: /* a value only the renderer can check, e.g. an attribute name */
            return lc_http_error(srv, c, 400, LC_PROTO_BAD_FIELD, job->err.field[0] ? job->err.field : NULL, "%s",
                                 job->err.msg);
        default: return lc_http_error(srv, c, 500, "internal", NULL, "render failed: %s", job->err.msg);
        }
    }
    struct MHD_Response *r = MHD_create_response_from_buffer(job->image_size, job->image, MHD_RESPMEM_MUST_FREE);
    if (!r)
        return MHD_NO;
    size_t bytes = job->image_size;
    job->image = NULL; /* MHD frees it now */
    MHD_add_response_header(r, MHD_HTTP_HEADER_CONTENT_TYPE,
                            job->req.format == LC_FORMAT_PNG ? "image/png" : "image/jpeg");
    MHD_add_response_header(r, MHD_HTTP_HEADER_CACHE_CONTROL, "no-store");
    add_frame_headers(r, job);
    lc_metrics_bytes_sent(srv->metrics, bytes);
    return lc_http_queue(srv, c, 200, r);
}

typedef struct query_state {
    lc_request *req;
    const lc_proto_limits *lim;
    lc_proto_error err;
    int rc;
} query_state;

static enum MHD_Result query_arg(void *cls, enum MHD_ValueKind kind, const char *key, const char *value)
{
    (void)kind;
    query_state *q = cls;
    q->rc = lc_proto_apply_query(q->req, key, value, q->lim, &q->err);
    return q->rc == 0 ? MHD_YES : MHD_NO;
}

/* layers[] (docs/ALGORITHM.md "Layers"): each layer's dataset must be loaded
 * (404 naming layers[i].dataset); under --mpi the ranks draw their shards of each. */
static enum MHD_Result start_layers(lc_http_req *ctx, struct MHD_Connection *c, const lc_request *req)
{
    lc_server *srv = ctx->srv;
    const lc_dataset *layers[LC_MAX_LAYERS];
    for (int i = 0; i < lc_request_layer_count(req); i++) {
        layers[i] = lc_datasets_find(srv->datasets, req->layers->dataset[i]);
        if (!layers[i]) {
            char field[48];
            snprintf(field, sizeof field, "layers[%d].dataset", i);
            return lc_http_error(srv, c, 404, "not_found", field, "%s: unknown dataset \"%.300s\"", field,
                                 req->layers->dataset[i]);
        }
    }
    return start_render(ctx, c, req, layers[0], layers, NULL, 0.0);
}

/* A one-shot render of *req, which the caller releases. */
static enum MHD_Result route_render(lc_http_req *ctx, struct MHD_Connection *c, const char *method, lc_request *req)
{
    lc_server *srv = ctx->srv;
    lc_proto_error pe;
    if (strcmp(method, "POST") == 0) {
        if (lc_proto_parse_request(ctx->body ? ctx->body : "", ctx->len, &srv->cfg.limits, req, &pe) != 0)
            return lc_http_proto_error(srv, c, &pe);
    } else {
        lc_request_default(req);
        query_state q = {.req = req, .lim = &srv->cfg.limits};
        MHD_get_connection_values(c, MHD_GET_ARGUMENT_KIND, query_arg, &q);
        if (q.rc != 0)
            return lc_http_proto_error(srv, c, &q.err);
        if (lc_proto_validate_request(req, &srv->cfg.limits, &pe) != 0)
            return lc_http_proto_error(srv, c, &pe);
    }
    if (req->render.method == LC_METHOD_SURFACE_LAYERS)
        return start_surface(ctx, c, req);
    if (lc_request_layer_count(req) > 0)
        return start_layers(ctx, c, req);
    /* a loaded dataset, or a vector field's streamline set traced for this render (traced.h) */
    const lc_dataset *ds = lc_traced_resolve(srv, req, &ctx->traced, &pe);
    if (!ds)
        return strcmp(pe.code, "not_found") == 0 ? lc_http_error(srv, c, 404, "not_found", pe.field, "%s", pe.message)
                                                 : lc_http_proto_error(srv, c, &pe);
    enum MHD_Result r = start_render(ctx, c, req, ds, NULL, NULL, 0.0);
    lc_traced_free(ctx->traced); /* refused before its job took it */
    ctx->traced = NULL;
    return r;
}

enum MHD_Result lc_http_route_render(lc_http_req *ctx, struct MHD_Connection *c, const char *method)
{
    lc_request req;
    lc_request_default(&req);
    enum MHD_Result r = route_render(ctx, c, method, &req);
    lc_request_release(&req); /* a queued job holds its own reference */
    return r;
}

enum MHD_Result lc_http_route_session_create(lc_http_req *ctx, struct MHD_Connection *c)
{
    lc_server *srv = ctx->srv;
    lc_proto_error pe;
    lc_request_patch *patch = NULL; /* the body's fields, checked once as parsed; none: the defaults */
    if (ctx->len > 0) {
        json_t *body = lc_proto_load(ctx->body, ctx->len, &srv->cfg.limits, &pe);
        int rc = body ? lc_proto_patch_parse(body, &srv->cfg.limits, &patch, &pe) : -1;
        json_decref(body);
        if (rc != 0)
            return lc_http_proto_error(srv, c, &pe);
    }
    /* The session's one validation, as its updates will have (admit.h); with
     * layers[] the request may leave dataset out: the session's is layers[0]'s.
     * A vector field's streamline set is traced now and kept by the session. */
    lc_request base, req;
    lc_request_default(&base);
    const lc_dataset *layers[LC_MAX_LAYERS], *ds = NULL;
    lc_traced *traced = NULL;
    int rc = lc_admit_update(srv, &base, patch, &srv->cfg.limits, &ds, &req, layers, &traced, &pe);
    lc_proto_patch_free(patch);
    if (rc == 0)
        rc = lc_session_kind_check(LC_SESSION_HTTP, &req, &pe);
    if (rc != 0) {
        lc_traced_free(traced);
        lc_request_release(&req);
        return strcmp(pe.code, "not_found") == 0 ? lc_http_error(srv, c, 404, "not_found", pe.field, "%s", pe.message)
                                                 : lc_http_proto_error(srv, c, &pe);
    }
    req.has_dt = false;
    lc_session *s = NULL;
    lc_error err = {0};
    if (lc_session_create(srv->sessions, LC_SESSION_HTTP, lc_conn_client_key(c), ds, &req, &s, &err) != 0) {
        lc_traced_free(traced);
        lc_request_release(&req);
        return lc_http_error(srv, c, strcmp(err.field, "client") == 0 ? 429 : 503, "overloaded", NULL, "%s", err.msg);
    }
    s->traced = traced;
    json_t *o = json_object();
    json_object_set_new(o, "session", json_string(s->id));
    json_object_set_new(o, "dataset", lc_dataset_info(ds));
    json_object_set_new(o, "defaults", lc_proto_request_to_json(&req));
    lc_request_release(&req);
    char location[128];
    snprintf(location, sizeof location, "/api/v1/sessions/%s", s->id);
    LC_INFO(MOD, "session %s: scripted, %s", s->id, ds->name);
    lc_session_unref(s);
    char *text = lc_proto_dump(o);
    json_decref(o);
    if (!text)
        return MHD_NO;
    struct MHD_Response *r = MHD_create_response_from_buffer(strlen(text), text, MHD_RESPMEM_MUST_FREE);
    MHD_add_response_header(r, MHD_HTTP_HEADER_CONTENT_TYPE, "application/json");
    MHD_add_response_header(r, MHD_HTTP_HEADER_LOCATION, location);
    return lc_http_queue(srv, c, 201, r);
}

static enum MHD_Result route_session_render(lc_http_req *ctx, struct MHD_Connection *c, lc_session *s)
{
    lc_server *srv = ctx->srv;
    lc_proto_error pe;
    lc_request_patch *patch = NULL; /* the body's fields, checked once as parsed */
    if (ctx->len > 0) {
        json_t *update = lc_proto_load(ctx->body, ctx->len, &srv->cfg.limits, &pe);
        if (!update) {
            lc_session_unref(s);
            return lc_http_proto_error(srv, c, &pe);
        }
        if (!json_is_object(update)) {
            json_decref(update);
            lc_session_unref(s);
            return lc_http_error(srv, c, 400, LC_PROTO_BAD_FIELD, "", "expected a JSON object");
        }
        int rc = lc_proto_patch_parse(update, &srv->cfg.limits, &patch, &pe);
        json_decref(update);
        if (rc != 0) {
            lc_session_unref(s);
            return lc_http_proto_error(srv, c, &pe);
        }
    }
    pthread_mutex_lock(&s->lock);
    if (s->http_busy) {
        pthread_mutex_unlock(&s->lock);
        lc_proto_patch_free(patch);
        lc_session_unref(s);
        return lc_http_error(srv, c, 429, "overloaded", NULL,
                             "session %s is rendering a frame; send the next one after it", s->id);
    }
    lc_request req; /* s->req never keeps a dt: without one in the update, req has none */
    int rc = lc_session_update_locked(s, patch, &srv->cfg.limits, &req, &pe);
    lc_proto_patch_free(patch);
    if (rc != 0) {
        pthread_mutex_unlock(&s->lock);
        lc_session_unref(s);
        return lc_http_proto_error(srv, c, &pe);
    }
    /* Without dt the frame shows the targets, as a one-shot render would
     * (openapi.yaml): a dt far beyond any half-life completes the fade. */
    double dt = req.has_dt ? req.dt : 1e6;
    s->req.has_dt = false;
    s->http_busy = true;
    s->last_frame_time = lc_now();
    const lc_dataset *layers[LC_MAX_LAYERS];
    memcpy(layers, s->layer_ds, (size_t)lc_request_layer_count(&req) * sizeof *layers);
    pthread_mutex_unlock(&s->lock);
    enum MHD_Result r = start_render(ctx, c, &req, s->dataset, lc_request_layer_count(&req) ? layers : NULL, s, dt);
    lc_request_release(&req); /* a queued job holds its own reference */
    return r;
}

enum MHD_Result lc_http_route_session(lc_http_req *ctx, struct MHD_Connection *c, const char *method, const char *rest)
{
    lc_server *srv = ctx->srv;
    char id[LC_SESSION_ID_LEN + 1];
    size_t n = strcspn(rest, "/");
    const char *tail = rest + n;
    if (n == 0 || n >= sizeof id)
        return lc_http_error(srv, c, 404, "not_found", NULL, "unknown session \"%.*s\"", (int)(n > 64 ? 64 : n), rest);
    memcpy(id, rest, n);
    id[n] = '\0';
    bool render = strcmp(tail, "/render") == 0;
    if (!render && tail[0])
        return lc_http_error(srv, c, 404, "not_found", NULL, "no such route");
    if (render && strcmp(method, "POST") != 0)
        return lc_http_not_allowed(srv, c, method, "POST");
    if (!render && strcmp(method, "DELETE") != 0 && strcmp(method, "GET") != 0)
        return lc_http_not_allowed(srv, c, method, "GET, DELETE");
    lc_session *s = lc_session_find(srv->sessions, id, LC_SESSION_HTTP);
    if (!s)
        return lc_http_error(srv, c, 404, "not_found", NULL, "unknown session \"%s\"", id);
    if (render)
        return route_session_render(ctx, c, s);
    if (strcmp(method, "DELETE") == 0) {
        lc_session_close(srv->sessions, s);
        LC_INFO(MOD, "session %s: deleted after %llu frames", s->id, (unsigned long long)s->http_frames);
        lc_session_unref(s);
        struct MHD_Response *r = MHD_create_response_from_buffer(0, NULL, MHD_RESPMEM_PERSISTENT);
        return lc_http_queue(srv, c, 204, r);
    }
    pthread_mutex_lock(&s->lock);
    json_t *o = json_object();
    json_object_set_new(o, "session", json_string(s->id));
    json_object_set_new(o, "dataset", json_string(s->dataset->name));
    json_object_set_new(o, "frames", json_integer((json_int_t)s->http_frames));
    if (s->traced) /* a field's streamline set: how often it was traced (only seeding changes re-trace) */
        json_object_set_new(o, "traces", json_integer((json_int_t)lc_traced_traces(s->dataset)));
    json_object_set_new(o, "request", lc_proto_request_to_json(&s->req));
    pthread_mutex_unlock(&s->lock);
    lc_session_unref(s);
    return lc_http_json(srv, c, 200, o);
}
