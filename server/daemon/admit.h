/* Admission of a parsed request: everything that can refuse it before a frame
 * is queued, run once where a request or an update arrives (a one-shot
 * render and a movie by lc_request_admit; a session's creation, each update
 * and a resize by lc_admit_update, which refuses params.progressive until the
 * sessions' stills draw in batches): where each given
 * field applies (protocol's scope table), what the renderer would refuse of
 * it on these datasets (lc_render_check), and the cost budget (cost.h). A
 * refusal is the answer to that request, never a later frame's error. */
#ifndef LC_SERVER_ADMIT_H
#define LC_SERVER_ADMIT_H

#include <jansson.h>

#include "datasets.h"
#include "request.h"
#include "request_patch.h"
#include "server.h"

/* 0 when a frame of req on ds fits --max-cost (cost.h); else too_expensive
 * naming the field to lower, counted in the metrics. *cost (if given): the
 * estimate. */
/* Method surface-layers (docs/ALGORITHM.md §23): the field must be loaded
 * (not_found naming surface.field), the seed must start inside it (naming
 * surface.seed), the frame must fit --max-cost (too_expensive naming
 * surface.particles); not under serve --mpi (naming method). *field (if
 * given): the field. lc_admit_budget
 * calls it for such requests. */
int lc_admit_surface(lc_server *srv, const lc_request *req, double *cost, const lc_field **field, lc_proto_error *pe);
int lc_admit_budget(lc_server *srv, const lc_dataset *ds, const lc_request *req, double *cost, lc_proto_error *pe);
/* The same for a request with layers[] over their datasets (ds[i] of
 * req->layers[i]). */
int lc_admit_layers_budget(lc_server *srv, const lc_dataset *const *ds, const lc_request *req, double *cost,
                           lc_proto_error *pe);
/* Either of the two: layers (may be NULL) when req has layers[], else ds. */
int lc_admit_frame_budget(lc_server *srv, const lc_dataset *ds, const lc_dataset *const *layers, const lc_request *req,
                          double *cost, lc_proto_error *pe);
/* layers[] (docs/ALGORITHM.md "Layers") in sessions: the dataset of each of
 * req's layers into out[i]; not_found naming layers[i].dataset for one not
 * loaded. 0 without layers. */
int lc_admit_resolve_layers(lc_server *srv, const lc_request *req, const lc_dataset **out, lc_proto_error *pe);

/* req as merged (an update applied to the session's request); given: the JSON
 * as received (NULL = every field, for requests from query parameters); ds the
 * request's dataset, layers[i] its layers' (lc_request_layer_count(req) of them). *cost
 * (may be NULL): the budget's estimate. 0 or a protocol error naming the field. */
int lc_request_admit(lc_server *srv, const json_t *given, const lc_request *req, const lc_dataset *ds,
                     const lc_dataset *const *layers, double *cost, lc_proto_error *pe);

/* The one validation of a session's update, a new session's request or a
 * resize, before anything changes: patch (NULL = no field given) merged into
 * a copy of base with the cross-field rules (lc_proto_patch_apply; its field
 * rules ran once when it was parsed), the layers' datasets resolved into
 * layers[], the dataset checked, then lc_request_admit (scope, what the
 * renderer would refuse, the budget). *ds: a session's dataset, which the
 * update may not change; NULL for a new session, which takes the one base
 * names (or layers[0]'s when it names none) and returns it in *ds. *out holds
 * the candidate however it ends, with a reference to its layers (the caller
 * commits it by swapping on 0, else lc_request_release). 0 or
 * a protocol error naming the field (not_found naming dataset or
 * layers[i].dataset). A new session's dataset may be a vector field where
 * traced is given: its streamline set is traced into *traced (the caller's,
 * however it ends: lc_traced_free); a session's update re-traces a changed
 * set (lc_traced_update, under the session's lock). */
struct lc_traced;
int lc_admit_update(lc_server *srv, const lc_request *base, const lc_request_patch *patch, const lc_proto_limits *lim,
                    const lc_dataset **ds, lc_request *out, const lc_dataset **layers, struct lc_traced **traced,
                    lc_proto_error *pe);

#endif
