// P1's fragment list (render/gl/fragment_list.c): every fragment of P1 as
// (pixel x | y << 16, element, g, series depth), so that P2 evaluates the
// same fragments in a compute pass (p2_list.comp.glsl) instead of drawing
// the geometry again. P2 draws exactly P1's fragments (same resolution,
// primitives and coverage) and reads nothing but its own fragment's values
// and its pixel's final sums, so the two ways give the same bits.
#ifndef COMPOSITE_LIST
layout(std430, binding = BIND_FRAGMENT_LIST) buffer FragmentList
{
    uint fragment_count; // fragments offered; those past the capacity are not stored
    uint fragment_pad[3];
    uvec4 fragments[];
};
uniform uint u_fragment_capacity;
#endif

// HEADS_FETCH (fragment_list.c, where GL_EXT_shader_framebuffer_fetch is
// there): the recording passes keep their pixels' chain heads in an R32UI
// target that the fragment shader reads and writes through framebuffer
// fetch, in the order the pixel's fragments are shaded, instead of swapping
// them into a storage word atomically; on llvmpipe the target's load and
// store are vector operations where an atomic is a loop over the vector's
// lanes. The heads are copied into the chains' buffer after the draw, so the
// walks read them as they read the swapped ones, and the lists are the same
// bit for bit.
#if defined(HEADS_FETCH) && defined(FRAGMENT_STAGE)
layout(location = 0) inout uint o_chain_head;
// Every path of a recording fragment that is not discarded writes the head:
// llvmpipe stores an undefined value for an inout output that the shader
// leaves alone, or writes back as it read it (a copy onto itself, which the
// compiler drops). The paths that record nothing write "none": their frame's
// heads are not walked (the empty-shader floor records no entry; a frame
// past its list's room records again or draws).
void drop_chain_head() { o_chain_head = 0xFFFFFFFFu; }
#endif

// The chains' buffer of P0's list or of P4's: word p = x + y * width holds
// pixel p's last entry (P0's moments pass turns it into the first).
#if defined(FRAGMENT_CHAINS) || defined(COMPOSITE_LIST)
#define FRAGMENT_NONE 0xFFFFFFFFu
layout(std430, binding = BIND_FRAGMENT_CHAINS) buffer FragmentChains { uint chain_words[]; };
uniform uint u_chain_pixels; // width * height of the pass
uniform uint u_chain_width;

#ifdef FRAGMENT_STAGE
// The fragment's pixel's last entry, replaced by entry i.
uint swap_chain_head(uint i)
{
#ifdef HEADS_FETCH
    uint before = o_chain_head;
    o_chain_head = i;
    return before;
#else
    uvec2 xy = uvec2(gl_FragCoord.xy);
    return atomicExchange(chain_words[xy.x + xy.y * u_chain_width], i);
#endif
}
#endif
#endif

// P0's list (FRAGMENT_CHAINS): per pixel of the optimization resolution a
// chain of its entries. P0 records each fragment as one uvec4 in one store
// (on llvmpipe every storage access of a fragment shader is a loop over the
// vector's lanes: the count and the entry, and the pixel's word where the
// head is swapped): x the entry recorded before it at its pixel, y the
// element, z g, w the normalized depth; word p of the chains' buffer holds
// pixel p's last entry (FRAGMENT_NONE before P0). P0's
// moments pass over the list (p0_list.comp.glsl) turns each chain around, so
// that word p holds the first entry and each x the entry after it (the last:
// FRAGMENT_NONE), in the order the fragment shader ran them; P1's pass
// replaces x by the pixel and w by the series depth. On llvmpipe one thread
// shades a pixel's fragments, in primitive order, which is the order blending
// adds them in; the passes add them in chain order.
#if defined(FRAGMENT_CHAINS) && defined(FRAGMENT_STAGE)
void record_chained_fragment(uint element, float g, float d)
{
    uint i = atomicAdd(fragment_count, 1u);
    if (i >= u_fragment_capacity) {
#ifdef HEADS_FETCH
        drop_chain_head();
#endif
        return; // the frame records again, or draws P0's moments and P1 (fragment_list.c)
    }
    uint before = swap_chain_head(i);
    fragments[i] = uvec4(before, element, floatBitsToUint(g), floatBitsToUint(d));
}
#endif

// P4's list (COMPOSITE_LIST, render/gl/fragment_list.c): every fragment of P4
// at full resolution with what P4's sums and P5's fragment shader need of it,
// so that both are compute passes over them (p4_list.comp.glsl,
// p5_list.comp.glsl). An entry is one uvec4, written by one store: on
// llvmpipe every storage-buffer access of a fragment shader is a loop over
// the vector's lanes, so the recording costs about as many loops as it has
// accesses (the count and the entry, and the pixel's head where it is
// swapped). Each
// pixel's entries are chained from the last back to the first (x: the entry
// before it), its head word holding the last (swapped atomically, or kept
// through framebuffer fetch: HEADS_FETCH above). The entry:
//   y  the normalized depth (float bits, in [0, 1]), its sign bit set for a
//      halo's fragment; the walks warp it into the series depth once per
//      fragment with the warp made once per pixel (composite_depth), which
//      the fragment shader would read and warp by per fragment
//   z  the opacity as a half float in the low 16 bits, of alpha up to 1/2
//      and of -(1 - alpha) above (both keep 11 significant bits where P5's
//      weight alpha / (1 - alpha) needs them), the importance g as 16-bit
//      unorm in the high 16 bits (topDecileReach's sums)
//   w  lines through the colormap: the colormap coordinate and <n, l> as
//      unorm 16 bits each (coordinate low), from which P5's walk looks the
//      colour up and shades it (composite_color: a thin line's fragments
//      leave most lanes of the fragment shader's blocks idle, and the fetch
//      and the shading cost less in the walk); else the lit colour as unorm
//      11, 11 and 10 bits (r low): points, whose splats fill the blocks,
//      surfaces and per-vertex RGB. A halo's fragment takes the halo's colour
//      in the walk.
#ifdef COMPOSITE_LIST
layout(std430, binding = BIND_FRAGMENT_LIST) buffer CompositeList
{
    uint composite_count; // fragments offered; those past the capacity are not stored
    uint composite_pad[3];
    uvec4 composites[];
};
uniform uint u_composite_capacity;

uint pack_opacity_importance(float alpha, float g)
{
    float a = alpha <= 0.5 ? alpha : -(1.0 - alpha);
    return (packHalf2x16(vec2(a, 0.0)) & 0xFFFFu) | (uint(clamp(g, 0.0, 1.0) * 65535.0 + 0.5) << 16);
}

uint pack_color(vec3 c)
{
    uvec3 q = uvec3(clamp(c, 0.0, 1.0) * vec3(2047.0, 2047.0, 1023.0) + 0.5);
    return q.x | (q.y << 11) | (q.z << 22);
}

float unpack_opacity(uint z)
{
    float a = unpackHalf2x16(z).x;
    return a >= 0.0 ? a : 1.0 + a;
}

float unpack_importance(uint z) { return float(z >> 16) / 65535.0; }

// The series depth of an entry's y at a pixel of warp w (series_warp_of), as
// fragment_series_depth gives it in the drawn P4.
float composite_depth(vec3 w, uint y)
{
    float d = series_depth_warped(w, uintBitsToFloat(y & 0x7FFFFFFFu));
    return (y & 0x80000000u) != 0u ? min(d, 1.0 - max(u_depth_margin, 0.01)) : d;
}

// Pixel p's last entry (FRAGMENT_NONE: no fragment, or past the last pixel).
uint composite_head(uint p) { return p < u_chain_pixels ? chain_words[p] : FRAGMENT_NONE; }

#ifndef FRAGMENT_STAGE
// A walk's start at pixel p (one invocation a pixel): its last entry, its
// position and its depth warp for composite_depth.
uint composite_pixel(uint p, out ivec2 xy, out vec3 w)
{
    xy = ivec2(p % u_chain_width, p / u_chain_width);
    uint head = composite_head(p);
    // (no fetch past the last pixel)
    w = head != FRAGMENT_NONE ? series_warp_of(series_moments_at(vec2(xy) + 0.5)) : vec3(0.0);
    return head;
}
#endif

#ifndef FRAGMENT_STAGE
// P4's sums at a pixel (one invocation a pixel): what p4_optical_depth.frag.glsl
// would have blended, f = -ln(1 - alpha) projected at the series depth, over the
// chain from entry i (its last) in chain order.
void composite_sums(uint i, vec3 w, out float sum[NTARGETS * 4])
{
    for (int j = 0; j < NTARGETS * 4; j++)
        sum[j] = 0.0;
    while (i != FRAGMENT_NONE) {
        uvec4 f = composites[i];
        float c[NTARGETS * 4];
        fourier_project(composite_depth(w, f.y), -log(1.0 - unpack_opacity(f.z)), c);
        for (int j = 0; j < NTARGETS * 4; j++)
            sum[j] += c[j];
        i = f.x;
    }
}
#endif

vec3 unpack_color(uint w)
{
    return vec3(float(w & 0x7FFu), float((w >> 11) & 0x7FFu), float(w >> 22)) / vec3(2047.0, 2047.0, 1023.0);
}

#ifndef FRAGMENT_STAGE
uniform int u_deferred_color; // 1: w holds the colormap coordinate and <n, l> (lc_composite_list_p5)
uniform vec3 u_halo_color;

// The colour of an entry with words y and w (see above).
vec3 composite_color(uint y, uint w)
{
    if ((y & 0x80000000u) != 0u)
        return u_halo_color;
    if (u_deferred_color == 0)
        return unpack_color(w);
    vec2 c = unpackUnorm2x16(w);
    return shade_color(colormap_lookup(c.x), c.y);
}
#endif

#ifdef FRAGMENT_STAGE
// The entry's w (see above): the colormap's coordinate and <n, l> where the
// fragment is a line's coloured through the colormap (the walk's
// u_deferred_color then holds), else the lit colour.
uint fragment_color_word()
{
#if PRIM == PRIM_LINES
    if (u_color_mode != 2)
        return packUnorm2x16(vec2(clamp(v_cscalar, 0.0, 1.0), fragment_ndotl()));
#endif
    return pack_color(fragment_color());
}

void record_composite_fragment(float alpha, float g, float depth, bool halo, uint color)
{
    uint i = atomicAdd(composite_count, 1u);
    if (i >= u_composite_capacity) {
#ifdef HEADS_FETCH
        drop_chain_head();
#endif
        return; // the frame records again, or draws P4 and P5 (fragment_list.c)
    }
    uint before = swap_chain_head(i);
    uint y = floatBitsToUint(depth) | (halo ? 0x80000000u : 0u);
    composites[i] = uvec4(before, y, pack_opacity_importance(alpha, g), color);
}
#endif
#endif
