/* Encoders of the compact GPU vertex layout; see vertex_pack.h. */
#include "vertex_pack.h"

#include <math.h>
#include <string.h>

/* The octahedral code of the zero vector (degenerate normals): snorm16 -1, -1
 * is also -z, which the encoder therefore writes as +1, +1. */
#define OCT_ZERO 0x80008000u

int lc_pack_attribute_is_unorm16(const lc_attribute *a)
{
    double span = (double)a->max - a->min, robust = (double)a->p98 - a->p02;
    /* 16 bits over [min, max] give the robust range at least 4096 levels. */
    return isfinite(span) && (span == 0 || robust * 16.0 >= span);
}

size_t lc_pack_positions_bytes(uint32_t n) { return ((3 * (size_t)n + 1) / 2) * 4; }
size_t lc_pack_chunks_bytes(uint32_t n, uint32_t phase)
{
    return (((size_t)n + phase + LC_POSITION_CHUNK - 1) >> LC_POSITION_CHUNK_SHIFT) * 32;
}

uint32_t lc_pack_chunk_phase(const lc_scene *s) { return (uint32_t)(s->vertex_base % LC_POSITION_CHUNK); }
size_t lc_pack_unorm16_bytes(uint32_t n) { return (((size_t)n + 1) / 2) * 4; }

size_t lc_pack_blend_bytes(lc_blend_layout layout, uint32_t n)
{
    switch (layout) {
    case LC_BLEND_FULL: return (size_t)n * 32;
    case LC_BLEND_PAIR: return (size_t)n * 8;
    case LC_BLEND_TRIPLE: return (size_t)n * 16;
    default: return 0;
    }
}

lc_blend_layout lc_pack_blend_layout_of_type(lc_prim_type type)
{
    return type == LC_PRIM_POINTS ? LC_BLEND_IMPLICIT : type == LC_PRIM_LINES ? LC_BLEND_PAIR : LC_BLEND_TRIPLE;
}

lc_blend_layout lc_pack_blend_layout(const lc_scene *s)
{
    const lc_elements *e = &s->elements;
    lc_blend_layout want = lc_pack_blend_layout_of_type(s->type);
    if (!e->vertex_elements || !e->vertex_weights)
        return LC_BLEND_FULL;
    for (uint32_t v = 0; v < s->vertex_count; v++) {
        const uint32_t *id = e->vertex_elements + 4 * (size_t)v;
        const float *w = e->vertex_weights + 4 * (size_t)v;
        int ok;
        if (want == LC_BLEND_IMPLICIT)
            ok = id[0] == v && id[3] == v && w[0] == 1.0f && w[1] == 0.0f && w[2] == 0.0f;
        else if (want == LC_BLEND_PAIR)
            ok = w[2] == 0.0f && (w[1] == 0.0f || id[1] == id[0] + 1) && (id[3] == id[0] || id[3] == id[0] + 1) &&
                 id[0] + (w[1] != 0.0f) < e->count;
        else
            ok = id[3] == id[0];
        if (!ok)
            return LC_BLEND_FULL;
    }
    return want;
}

static uint32_t unorm16(double t)
{
    t = t < 0 ? 0 : t > 1 ? 1 : t;
    return (uint32_t)lrint(t * 65535.0);
}

static void put_u16(uint32_t *words, size_t h, uint32_t value)
{
    uint32_t shift = (uint32_t)(h & 1) * 16;
    words[h >> 1] = (words[h >> 1] & ~(0xffffu << shift)) | (value << shift);
}

void lc_pack_positions(const float *p, uint32_t n, uint32_t phase, uint32_t *words, float *chunks)
{
    memset(words, 0, lc_pack_positions_bytes(n));
    phase %= LC_POSITION_CHUNK;
    for (uint32_t first = 0, k = 0; first < n; k++) {
        uint32_t room = LC_POSITION_CHUNK - (k == 0 ? phase : 0);
        uint32_t end = n - first > room ? first + room : n;
        float lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
        for (uint32_t v = first; v < end; v++)
            for (int c = 0; c < 3; c++) {
                float x = p[3 * (size_t)v + c];
                lo[c] = x < lo[c] ? x : lo[c];
                hi[c] = x > hi[c] ? x : hi[c];
            }
        float *ch = chunks + 8 * (size_t)k;
        double scale[3];
        for (int c = 0; c < 3; c++) {
            if (!(lo[c] <= hi[c])) /* no finite value (finalize rejects those; stay defined) */
                lo[c] = hi[c] = 0;
            scale[c] = ((double)hi[c] - lo[c]) / 65535.0;
            ch[c] = lo[c];
            ch[4 + c] = (float)scale[c];
        }
        ch[3] = ch[7] = 0;
        for (uint32_t v = first; v < end; v++)
            for (int c = 0; c < 3; c++) {
                double x = p[3 * (size_t)v + c];
                /* Decoded as lo + scale * q in float (common.glsl): round to the nearest code. */
                put_u16(words, 3 * (size_t)v + c, scale[c] > 0 ? unorm16((x - lo[c]) / (scale[c] * 65535.0)) : 0);
            }
        first = end;
    }
    if (n > 0)
        memcpy(&chunks[3], &phase, sizeof phase); /* 0 for a whole scene: the float 0 */
}

static uint32_t snorm16(double x)
{
    long q = lrint((x < -1 ? -1 : x > 1 ? 1 : x) * 32767.0);
    if (q < -32767) /* -32768 pairs are reserved for the zero vector */
        q = -32767;
    return (uint32_t)(uint16_t)(int16_t)q;
}

void lc_pack_directions(const float *d, uint32_t n, uint32_t *words)
{
    for (uint32_t v = 0; v < n; v++) {
        double x = d[3 * (size_t)v], y = d[3 * (size_t)v + 1], z = d[3 * (size_t)v + 2];
        double l1 = fabs(x) + fabs(y) + fabs(z);
        if (!(l1 > 1e-30)) {
            words[v] = OCT_ZERO;
            continue;
        }
        double px = x / l1, py = y / l1;
        if (z < 0) { /* fold the lower hemisphere over the diagonals */
            double fx = (1 - fabs(py)) * (px >= 0 ? 1 : -1), fy = (1 - fabs(px)) * (py >= 0 ? 1 : -1);
            px = fx, py = fy;
        }
        words[v] = snorm16(px) | snorm16(py) << 16;
    }
}

void lc_pack_attribute(const lc_attribute *a, uint32_t n, uint32_t *words)
{
    memset(words, 0, lc_pack_unorm16_bytes(n));
    double lo = a->min, span = (double)a->max - a->min;
    for (uint32_t v = 0; v < n; v++) {
        double x = a->values[v];
        put_u16(words, v, isfinite(x) && span > 0 ? unorm16((x - lo) / span) : 0);
    }
}

void lc_pack_colors(const float *rgb, uint32_t n, uint32_t *words)
{
    for (uint32_t v = 0; v < n; v++) {
        uint32_t w = 0xff000000u;
        for (int c = 0; c < 3; c++) {
            double x = rgb[3 * (size_t)v + c];
            w |= (uint32_t)lrint((isfinite(x) ? (x < 0 ? 0 : x > 1 ? 1 : x) : 0) * 255.0) << (8 * c);
        }
        words[v] = w;
    }
}

void lc_pack_blend(const lc_elements *e, lc_blend_layout layout, uint32_t n, uint32_t *out)
{
    for (uint32_t v = 0; v < n; v++) {
        const uint32_t *id = e->vertex_elements + 4 * (size_t)v;
        const float *w = e->vertex_weights + 4 * (size_t)v;
        if (layout == LC_BLEND_PAIR) {
            out[2 * (size_t)v] = id[0];
            out[2 * (size_t)v + 1] = unorm16(w[0]) | (uint32_t)(id[3] != id[0]) << 16;
        } else if (layout == LC_BLEND_TRIPLE) {
            uint32_t *o = out + 4 * (size_t)v;
            o[0] = id[0], o[1] = id[1], o[2] = id[2];
            o[3] = unorm16(w[0]) | unorm16(w[1]) << 16;
        }
    }
}
