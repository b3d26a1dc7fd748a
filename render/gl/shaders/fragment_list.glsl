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

// P0's list (FRAGMENT_CHAINS): per pixel of the optimization resolution a
// chain of its entries in the order the fragment shader ran them. Words 2p
// and 2p + 1 of the chains' buffer hold pixel p's (p = x + y * width) first
// and last entry (the last cleared to FRAGMENT_NONE before P0); an entry's x
// holds the entry after it in its chain (written by that fragment: no entry
// writes its own x) until P1's compute pass replaces it by the pixel, and
// its w holds the normalized depth until P1 replaces it by the series depth.
// On llvmpipe one thread shades a pixel's fragments, in primitive order,
// which is the order blending adds them in; P1 adds them in chain order.
#ifdef FRAGMENT_CHAINS
#define FRAGMENT_NONE 0xFFFFFFFFu
layout(std430, binding = BIND_FRAGMENT_CHAINS) buffer FragmentChains { uint chain_words[]; };
uniform uint u_chain_pixels; // width * height of the pass
uniform uint u_chain_width;

#ifdef FRAGMENT_STAGE
void record_chained_fragment(uint element, float g, float d)
{
    uint i = atomicAdd(fragment_count, 1u);
    if (i >= u_fragment_capacity)
        return; // the frame draws P1 instead (fragment_list.c)
    fragments[i].yzw = uvec3(element, floatBitsToUint(g), floatBitsToUint(d));
    uvec2 xy = uvec2(gl_FragCoord.xy);
    uint p = xy.x + xy.y * u_chain_width;
    uint prev = atomicExchange(chain_words[2u * p + 1u], i);
    if (prev == FRAGMENT_NONE)
        chain_words[2u * p] = i;
    else
        fragments[prev].x = i;
}
#endif
#endif

// P4's list (COMPOSITE_LIST, render/gl/fragment_list.c): every fragment of P4
// at full resolution with what P5's fragment shader computes of it before
// reading P4's sums (its opacity, series depth and colour), chained per pixel
// as P0's (FRAGMENT_CHAINS, the same buffer at full resolution), so that P5
// is a compute pass over them (p5_list.comp.glsl).
#ifdef COMPOSITE_LIST
struct CompositeFragment
{
    uint next; // the entry after it in its pixel's chain (written by that fragment)
    float alpha, depth, r, g, b;
};
layout(std430, binding = BIND_FRAGMENT_LIST) buffer CompositeList
{
    uint composite_count; // fragments offered; those past the capacity are not stored
    uint composite_pad[3];
    CompositeFragment composites[];
};
uniform uint u_composite_capacity;
#define FRAGMENT_NONE 0xFFFFFFFFu
layout(std430, binding = BIND_FRAGMENT_CHAINS) buffer CompositeChains { uint composite_chain_words[]; };
uniform uint u_chain_pixels;
uniform uint u_chain_width;

#ifdef FRAGMENT_STAGE
void record_composite_fragment(float alpha, float depth, vec3 color)
{
    uint i = atomicAdd(composite_count, 1u);
    if (i >= u_composite_capacity)
        return; // the frame draws P5 instead (fragment_list.c)
    composites[i].alpha = alpha;
    composites[i].depth = depth;
    composites[i].r = color.r;
    composites[i].g = color.g;
    composites[i].b = color.b;
    uvec2 xy = uvec2(gl_FragCoord.xy);
    uint p = xy.x + xy.y * u_chain_width;
    uint prev = atomicExchange(composite_chain_words[2u * p + 1u], i);
    if (prev == FRAGMENT_NONE)
        composite_chain_words[2u * p] = i;
    else
        composites[prev].next = i;
}
#endif
#endif
