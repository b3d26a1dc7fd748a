/* One viewer's element opacities between frames: the CPU side of temporal
 * fading, so any worker context can render any viewer's next frame. */
#include <stdlib.h>

#include "renderer_internal.h"

lc_frame_state *lc_frame_state_create(uint32_t element_count)
{
    lc_frame_state *st = calloc(1, sizeof *st);
    if (!st)
        return NULL;
    st->count = element_count;
    st->alpha = malloc((element_count ? element_count : 1) * sizeof(float));
    if (!st->alpha) {
        free(st);
        return NULL;
    }
    lc_frame_state_reset(st);
    return st;
}

void lc_frame_state_destroy(lc_frame_state *st)
{
    if (st) {
        free(st->alpha);
        free(st);
    }
}

void lc_frame_state_reset(lc_frame_state *st)
{
    st->fresh = 1;
    for (uint32_t i = 0; i < st->count; i++)
        st->alpha[i] = 1.0f;
}

const float *lc_frame_state_alphas(const lc_frame_state *st) { return st->alpha; }

int lc_frame_state_is_fresh(const lc_frame_state *st) { return st->fresh; }

void lc_frame_state_load(lc_frame_state *st, const float *alpha)
{
    for (uint32_t i = 0; i < st->count; i++)
        st->alpha[i] = alpha[i];
    st->fresh = 0;
}
