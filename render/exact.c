/* Exact reference (DOO): per-pixel fragment linked lists. */
#include "renderer_internal.h"

int lc_render_exact(lc_renderer *r, lc_frame_setup *fs, lc_frame_state *state, double dt, uint8_t *rgba,
                    lc_frame_info *info, lc_error *err)
{
    (void)r, (void)fs, (void)state, (void)dt, (void)rgba, (void)info;
    return lc_err(err, LC_ERR_UNSUPPORTED, "method \"exact\" is not implemented yet");
}

void lc_exact_destroy(lc_renderer *r) { (void)r; }
