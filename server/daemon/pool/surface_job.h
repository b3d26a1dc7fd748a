/* A render worker's frame of method "surface-layers": the request's surface
 * object turned into the renderer's terms (render/gl/surface_render.h), the
 * statistics into the frame info that the response headers report. */
#ifndef LC_SERVER_SURFACE_JOB_H
#define LC_SERVER_SURFACE_JOB_H

#include <stdint.h>

#include "field.h"
#include "renderer.h"
#include "request.h"
#include "server.h"
#include "surface_memory.h"
#include "surface_render.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Renders the surface s of field with p's size, camera and background into
 * rgba (p's width x height, top row first) on the calling worker's GL context. Errors name the
 * request field. work (NULL = none; cost.h lc_cost_surface_budget): the
 * tracing's RK4 steps are charged to it at lc_cost_surface_step_units each,
 * and past its limit the frame fails with LC_ERR_BUDGET naming its field.
 * mem (NULL = none): the memory budget its curves are reserved in while it
 * renders (surface_memory.h); short of it the frame fails with LC_ERR_LIMIT
 * naming surface.particles and how many fit, before tracing. */
int lc_surface_job_render(const lc_field *field, const lc_surface_request *s, const lc_render_params *p,
                          const lc_surface_budget *mem, lc_work_budget *work, uint8_t *rgba, lc_frame_info *info,
                          lc_error *err);

/* A WebSocket session's surface (method surface-layers): the curves traced
 * so far, kept on the CPU between frames. Owned by the session, touched only
 * by the worker rendering its frame. */
typedef struct lc_surface_stream lc_surface_stream;
void lc_surface_stream_free(lc_surface_stream *st);
/* The id naming its curves (lc_surface_draw's curves_id); 0 for NULL. */
uint64_t lc_surface_stream_id(const lc_surface_stream *st);

/* One session frame: traces the next s->curves_per_frame particles (all
 * traced ones are dropped first when the field, seed, step or length
 * changed: a new surface) and shows every curve traced so far with p's
 * camera (no camera: fitted to the field's bounds, so that the view stays
 * put while the surface grows). keep (the worker's, may be NULL) holds the
 * layers of an earlier frame: with the same camera and parameters only the
 * new curves are drawn into them (PRT's progressive insertion), else all
 * are. info->converged once all s->particles are in. *st is created on the
 * first frame. work: this frame's tracing budget, as lc_surface_job_render's
 * (a frame over it keeps the curves of the frames before and adds none).
 * mem (NULL = none): before a batch is traced the whole surface's curves are
 * reserved in it (surface_memory.h), and held until the surface changes or
 * the stream is freed; short of it the frame fails with LC_ERR_LIMIT naming
 * surface.particles and how many fit, keeping the curves traced so far. */
int lc_surface_stream_frame(lc_surface_stream **st, lc_surface_keep *keep, const lc_field *field,
                            const lc_surface_request *s, const lc_render_params *p, const lc_surface_budget *mem,
                            lc_work_budget *work, uint8_t *rgba, lc_frame_info *info, lc_error *err);

/* Worker side: one frame of method surface-layers for session s (the next
 * batch of curves of req's surface, drawn with req's camera into the worker's
 * kept layers `keep`, may be NULL): the field is looked up again (admit.h),
 * then lc_surface_stream_frame on the session's curves. Errors name the field. */
int lc_surface_job_session_frame(lc_server *srv, lc_session *s, const lc_request *req, lc_surface_keep *keep,
                                 uint8_t *rgba, lc_frame_info *info, lc_error *err);
/* Worker side: the id of the curves s's surface frames draw (0 = none yet;
 * lc_surface_draw's curves_id), to find the layers kept from its last frame. */
uint64_t lc_surface_job_session_id(const lc_session *s);

#ifdef __cplusplus
}
#endif
#endif
