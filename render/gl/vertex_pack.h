/* CPU-side encoders of the compact GPU vertex layout (docs/MEMORY.md): positions
 * as 16-bit unorm relative to the bounds of chunks of consecutive vertices,
 * directions octahedral in two snorm16, attributes 16-bit unorm over their
 * range, colours RGBA8, and per-vertex element blends without unused slots.
 * The shaders' decoders are in common.glsl. Plain functions, no GL: the sizes
 * they report serve both the upload and the memory estimate. Not public. */
#ifndef LC_VERTEX_PACK_H
#define LC_VERTEX_PACK_H

#include <stddef.h>
#include <stdint.h>

#include "scene.h"

/* Vertices per position chunk (its own bounds): 1024 keeps the chunk table at
 * 32 bytes per 1024 vertices and, for lines, each chunk spatially small. */
#define LC_POSITION_CHUNK_SHIFT 10
#define LC_POSITION_CHUNK (1u << LC_POSITION_CHUNK_SHIFT)

/* How a vertex finds its element opacities (u_blend in common.glsl). */
typedef enum {
    LC_BLEND_FULL = 0,     /* 4 element ids + 4 float weights (the exact layout) */
    LC_BLEND_IMPLICIT = 1, /* points: element = vertex, no buffer */
    LC_BLEND_PAIR = 2,     /* lines: e0, then unorm16 w0 | primary-is-e0+1 << 16; e1 = e0 + 1 */
    LC_BLEND_TRIPLE = 3    /* surfaces: e0, e1, e2, unorm16 w0 | w1 << 16; primary = e0 */
} lc_blend_layout;

/* An attribute's encoding: 16-bit unorm over [min, max], or float where a few
 * outliers stretch that range so far that 16 bits would not resolve its
 * 2nd-98th percentile range (and so the auto range the importance mapping uses). */
int lc_pack_attribute_is_unorm16(const lc_attribute *a);

/* Bytes of each packed buffer for n vertices. */
size_t lc_pack_positions_bytes(uint32_t n);                     /* 3 x u16 per vertex, in 32-bit words */
size_t lc_pack_chunks_bytes(uint32_t n, uint32_t phase);        /* 2 vec4 per chunk */
size_t lc_pack_unorm16_bytes(uint32_t n);                       /* one u16 per vertex, in 32-bit words */
size_t lc_pack_blend_bytes(lc_blend_layout layout, uint32_t n); /* vertex_elements (+ weights for FULL) */

/* The layout the scene's elements allow: IMPLICIT for points whose element is
 * the point, PAIR for lines whose blends are consecutive elements, TRIPLE for
 * blends whose primary is the first element; FULL otherwise. Needs the
 * scene's element arrays. */
lc_blend_layout lc_pack_blend_layout(const lc_scene *s);
/* The layout a scene of this type gets when its elements are the usual ones
 * (for estimates once the arrays are released). */
lc_blend_layout lc_pack_blend_layout_of_type(lc_prim_type type);

/* words: lc_pack_positions_bytes(n); chunks: lc_pack_chunks_bytes(n, phase)
 * floats as (min xyz, 0), (scale xyz, 0) per chunk. Chunks begin where v +
 * phase (phase < LC_POSITION_CHUNK) is a multiple of LC_POSITION_CHUNK: a
 * shard of a scene split over processes whose first vertex is vertex F of the
 * whole passes phase = F mod LC_POSITION_CHUNK and quantizes every chunk that
 * lies wholly within it exactly as the whole scene does. The phase travels as
 * the bits of the first chunk's fourth float (common.glsl). */
void lc_pack_positions(const float *p, uint32_t n, uint32_t phase, uint32_t *words, float *chunks);
/* The phase of a scene's chunks (its vertex_base). */
uint32_t lc_pack_chunk_phase(const lc_scene *s);
/* Unit (or zero) directions, 3 floats each, to one word each. */
void lc_pack_directions(const float *d, uint32_t n, uint32_t *words);
/* Attribute values to u16 over [a->min, a->max] (non-finite values -> min). */
void lc_pack_attribute(const lc_attribute *a, uint32_t n, uint32_t *words);
/* RGB floats in [0, 1] to RGBA8 words. */
void lc_pack_colors(const float *rgb, uint32_t n, uint32_t *words);
/* The vertex_elements buffer of layout (not FULL, not IMPLICIT). */
void lc_pack_blend(const lc_elements *e, lc_blend_layout layout, uint32_t n, uint32_t *out);

#endif
