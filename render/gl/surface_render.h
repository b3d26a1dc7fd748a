/* One frame of a vector field's integral surface (method "surface-layers",
 * docs/ALGORITHM.md §23): particles traced from a seed polyline on CPU
 * threads, their curves drawn into surface layers in batches and composited,
 * with the render parameters' size, camera and background.
 * Threading: runs on the thread whose GL 4.5 context is current (a render
 * worker); the field and seed are only read. */
#ifndef LC_GL_SURFACE_RENDER_H
#define LC_GL_SURFACE_RENDER_H

#include <stdint.h>

#include "lc_base.h"
#include "lc_params.h"
#include "surface_layers.h"
#include "trace.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Layer memory one frame may take (width * height * K * 32 bytes); K is
 * lowered to fit (at least 1), so that a full-HD frame keeps 4 layers. */
#define LC_SURFACE_LAYER_BUDGET (256ull << 20)
#define LC_SURFACE_POOL_FRAGMENTS (2ull << 20) /* fragment pool of one batch (64 MiB) */
#define LC_SURFACE_BATCH 1000                  /* curves drawn per batch */

typedef struct lc_surface_params {
    int particles;   /* curves traced along the seed, >= 1 */
    double step;     /* RK4 step, 0 = the tracer's default */
    double length;   /* arc length of a curve (each half of a two-way one), 0 = the tracer's default */
    int direction;   /* lc_trace_direction: forward, backward or both ways from the seed */
    double epsilon;  /* merge distance, a fraction of the field's diagonal, >= 0 */
    double opacity;  /* every layer's alpha in (0, 1] */
    int max_layers;  /* K asked for (1..LC_SURFACE_LAYERS_MAX_K), lowered to the budget */
    int composite;   /* LC_SURFACE_COMPOSITE_* */
    double color[3]; /* base colour in [0, 1] */
    /* Tracing's work budget (NULL = none; lc_trace_desc.work): each RK4 step
     * charges step_units (0 = LC_TRACE_STEP_UNITS). Borrowed for the call. */
    lc_work_budget *work;
    double step_units;
} lc_surface_params;

typedef struct lc_surface_info {
    lc_surface_layers_stats stats;
    int k;             /* layers per pixel used (max_layers under the budget) */
    double trace_ms;   /* CPU tracing */
    double draw_ms;    /* batches and composite, read back */
    uint64_t vertices; /* of all curves */
    /* This frame's work: curves drawn and fragments rasterized into the
     * layers (all curves unless kept layers held the others), and whether
     * the layers came from the frame before (lc_surface_keep). */
    uint64_t drawn_curves, drawn_fragments;
    int kept;
} lc_surface_info;

/* A surface's layers kept across a session's frames (PRT §2.2, progressive
 * insertion; docs/ALGORITHM.md §23): a frame whose camera, size and surface
 * parameters equal the kept layers' and whose curves extend the ones drawn
 * into them adds only the new curves; anything else empties them and draws
 * every curve. Holds one surface's layers (the GPU memory of one frame).
 * Threading: one thread at a time, with a context of the share group of the
 * one current at its first frame (lc_surface_layers.h). */
typedef struct lc_surface_keep lc_surface_keep;
lc_surface_keep *lc_surface_keep_create(void);
/* Frees the layers (GL objects: a context of the group current), keeps the object. */
void lc_surface_keep_release(lc_surface_keep *keep);
/* Whether it holds layers now. */
int lc_surface_keep_holds(const lc_surface_keep *keep);
/* The curves_id of the layers it holds (0 = none). */
uint64_t lc_surface_keep_id(const lc_surface_keep *keep);
void lc_surface_keep_destroy(lc_surface_keep *keep);

/* Bytes a frame of w x h with K layers holds on the GPU (layers, pixel words,
 * fragment pool), and the K it would use for max_layers. */
uint64_t lc_surface_bytes(int width, int height, int max_layers, int *k_used);

/* Draws n traced curves at p's size with p's camera (when p->has_camera;
 * else one fitted to fit_box, in *camera_out when not NULL) over p's
 * background into rgba (top row first); info->trace_ms is kept, the rest set.
 * A session's frame: the curves traced so far. With keep (may be NULL) and
 * curves_id != 0 (names this sequence of curves: the same id promises the
 * same first curves), layers kept from an earlier frame of the same id and
 * view take only the curves they lack. */
int lc_surface_draw(const lc_field *field, const lc_trace_curve *curves, uint32_t n, uint64_t curves_id,
                    lc_surface_keep *keep, const lc_surface_params *sp, const lc_render_params *p,
                    const double fit_box[6], uint8_t *rgba, lc_surface_info *info, lc_camera *camera_out,
                    lc_error *err);

/* Traces sp->particles curves of field from seed (checked by lc_seed_check)
 * on `threads` threads and renders them at p's size with p's camera (when
 * p->has_camera; else one fitted to the curves' bounds, the fitted camera in
 * *camera_out when not NULL) over p's background into rgba (top row first).
 * Errors name the request field ("surface.seed", ...). */
int lc_surface_render(const lc_field *field, const lc_seed *seed, const lc_surface_params *sp,
                      const lc_render_params *p, int threads, uint8_t *rgba, lc_surface_info *info,
                      lc_camera *camera_out, lc_error *err);

#ifdef __cplusplus
}
#endif
#endif
