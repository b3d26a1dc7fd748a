/* What the renderer refuses of a request on given scenes, checked without GL:
 * the server runs it when a request or an update arrives, so a refusal is an
 * answer to that request (an HTTP 400, a WebSocket error for that update)
 * instead of a later frame's error; the renderer runs the same check at the
 * start of every frame. Thread-safe, reads the scenes' metadata only. */
#ifndef LC_RENDER_FRAME_CHECK_H
#define LC_RENDER_FRAME_CHECK_H

#include "lc_base.h"
#include "lc_params.h"
#include "scene.h"

#ifdef __cplusplus
extern "C" {
#endif

/* The frame of p over scenes[0] alone (layers NULL, n 1) or over the n layers;
 * tile_size as lc_renderer_set_tile_size (0 = the default tiling). Returns 0
 * or LC_ERR_INVALID/LC_ERR_UNSUPPORTED with err->field naming the field. */
int lc_render_check(const lc_scene *const *scenes, const lc_layer_params *layers, int n, const lc_render_params *p,
                    int tile_size, lc_error *err);

/* Whether a frame of p draws the ground plane (style.ground; "auto": for
 * style.shadow when no visible context layer receives it). */
int lc_render_ground_drawn(const lc_render_params *p, int has_context);

#ifdef __cplusplus
}
#endif
#endif
