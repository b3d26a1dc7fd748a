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
