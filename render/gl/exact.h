/* The exact reference method (per-pixel fragment linked lists, sorted; exact
 * sums and compositing) on the renderer's context. Internal to render/gl/. */
#ifndef LC_GL_EXACT_H
#define LC_GL_EXACT_H

#include "renderer_internal.h"

/* Renders one frame by the exact method into rgba (top-down rows). */
int lc_render_exact(lc_renderer *r, lc_frame_setup *fs, lc_frame_state *state, double dt, uint8_t *rgba,
                    lc_frame_info *info, lc_error *err);
/* Frees the node pool and the list heads, keeping the programs: after a large
 * frame (lc_renderer_release_after) the heads are sized to it and the pool's
 * pages it touched stay resident otherwise. The next exact frame reallocates. */
void lc_exact_release(lc_renderer *r);
/* Records the pool size this renderer's exact frames will take (lc_exact_pool_nodes). */
void lc_exact_configure(const lc_renderer *r);
/* Frees the method's pool, lists and programs (called by lc_renderer_destroy). */
void lc_exact_destroy(lc_renderer *r);

#endif
