// P1's fragment list (render/gl/fragment_list.c): every fragment of P1 as
// (pixel x | y << 16, element, g, series depth), so that P2 evaluates the
// same fragments in a compute pass (p2_list.comp.glsl) instead of drawing
// the geometry again. P2 draws exactly P1's fragments (same resolution,
// primitives and coverage) and reads nothing but its own fragment's values
// and its pixel's final sums, so the two ways give the same bits.
layout(std430, binding = BIND_FRAGMENT_LIST) buffer FragmentList
{
    uint fragment_count; // fragments offered; those past the capacity are not stored
    uint fragment_pad[3];
    uvec4 fragments[];
};
uniform uint u_fragment_capacity;

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
