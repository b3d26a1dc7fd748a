/* One viewer's element opacities between frames: the CPU side of temporal
 * fading, so any worker context can render any viewer's next frame; and the
 * transfer of its equalized colour (color.equalize). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "equalize.h"
#include "renderer_internal.h"

/* Elements converted per transfer: the conversions need no O(elements) scratch. */
#define TRANSFER_CHUNK 16384u

static lc_frame_state *create(uint32_t element_count, int compact)
{
    lc_frame_state *st = calloc(1, sizeof *st);
    if (!st)
        return NULL;
    st->count = element_count;
    size_t n = element_count ? element_count : 1;
    if (compact)
        st->alpha16 = malloc(n * sizeof *st->alpha16);
    else
        st->alpha = malloc(n * sizeof *st->alpha);
    if (!st->alpha && !st->alpha16) {
        free(st);
        return NULL;
    }
    lc_frame_state_reset(st);
    return st;
}

lc_frame_state *lc_frame_state_create(uint32_t element_count) { return create(element_count, 0); }

lc_frame_state *lc_frame_state_create_compact(uint32_t element_count) { return create(element_count, 1); }

void lc_frame_state_destroy(lc_frame_state *st)
{
    if (st) {
        free(st->alpha);
        free(st->alpha16);
        free(st);
    }
}

void lc_frame_state_reset(lc_frame_state *st)
{
    st->fresh = 1;
    for (int i = 0; i < LC_MAX_LAYERS; i++)
        st->eq[i].valid = 0;
    for (uint32_t i = 0; i < st->count; i++) {
        if (st->alpha)
            st->alpha[i] = 1.0f;
        else
            st->alpha16[i] = 65535;
    }
}

const float *lc_frame_state_alphas(const lc_frame_state *st) { return st->alpha; }

uint64_t lc_frame_state_bytes(const lc_frame_state *st)
{
    return sizeof *st + (uint64_t)(st->count ? st->count : 1) * (st->alpha ? 4u : 2u);
}

void lc_frame_state_upload(const lc_frame_state *st, GLuint buffer)
{
    if (st->alpha) {
        glNamedBufferSubData(buffer, 0, (GLsizeiptr)st->count * 4, st->alpha);
        return;
    }
    float tmp[TRANSFER_CHUNK];
    for (uint32_t first = 0; first < st->count; first += TRANSFER_CHUNK) {
        uint32_t n = st->count - first < TRANSFER_CHUNK ? st->count - first : TRANSFER_CHUNK;
        for (uint32_t i = 0; i < n; i++)
            tmp[i] = st->alpha16[first + i] * (1.0f / 65535.0f);
        glNamedBufferSubData(buffer, (GLintptr)first * 4, (GLsizeiptr)n * 4, tmp);
    }
}

void lc_frame_state_download(lc_frame_state *st, GLuint buffer)
{
    if (st->alpha) {
        glGetNamedBufferSubData(buffer, 0, (GLsizeiptr)st->count * 4, st->alpha);
        return;
    }
    float tmp[TRANSFER_CHUNK];
    for (uint32_t first = 0; first < st->count; first += TRANSFER_CHUNK) {
        uint32_t n = st->count - first < TRANSFER_CHUNK ? st->count - first : TRANSFER_CHUNK;
        glGetNamedBufferSubData(buffer, (GLintptr)first * 4, (GLsizeiptr)n * 4, tmp);
        for (uint32_t i = 0; i < n; i++) {
            float a = tmp[i] < 0 ? 0 : tmp[i] > 1 ? 1 : tmp[i];
            st->alpha16[first + i] = (uint16_t)lrintf(a * 65535.0f);
        }
    }
}

int lc_frame_state_is_fresh(const lc_frame_state *st) { return st->fresh; }

void lc_frame_state_load(lc_frame_state *st, const float *alpha)
{
    for (uint32_t i = 0; i < st->count; i++) {
        float a = alpha[i] < 0 ? 0 : alpha[i] > 1 ? 1 : alpha[i];
        if (st->alpha)
            st->alpha[i] = alpha[i];
        else
            st->alpha16[i] = (uint16_t)lrintf(a * 65535.0f);
    }
    st->fresh = 0;
}

void lc_frame_state_copy(const lc_frame_state *st, float *out)
{
    for (uint32_t i = 0; i < st->count; i++)
        out[i] = st->alpha ? st->alpha[i] : st->alpha16[i] * (1.0f / 65535.0f);
}

void lc_frame_state_equalize_slot(lc_frame_state *st, int slot, const float *target, double dt, double half_life)
{
    if (!st->eq[slot].valid) {
        memcpy(st->eq[slot].knots, target, sizeof st->eq[slot].knots);
        st->eq[slot].valid = 1;
        return;
    }
    lc_equalize_approach(st->eq[slot].knots, target, LC_EQUALIZE_BINS, dt, half_life);
}

const float *lc_frame_state_equalize_knots_slot(const lc_frame_state *st, int slot)
{
    return st->eq[slot].valid ? st->eq[slot].knots : NULL;
}

void lc_frame_state_equalize(lc_frame_state *st, const float *target, double dt, double half_life)
{
    lc_frame_state_equalize_slot(st, 0, target, dt, half_life);
}

const float *lc_frame_state_equalize_knots(const lc_frame_state *st)
{
    return lc_frame_state_equalize_knots_slot(st, 0);
}
