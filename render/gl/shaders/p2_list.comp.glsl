// P2 over P1's fragment list (fragment_list.glsl): the recorded fragments,
// P2_PER_INVOCATION an invocation (below), the same opacity as the fragment
// shader's (opacity_common.glsl) without a second traversal of the geometry.
// The clarity loop's tries run it again on the same list.
layout(local_size_x = 256) in;
uint linear_invocation() { return gl_GlobalInvocationID.y * gl_NumWorkGroups.x * 256u + gl_GlobalInvocationID.x; }

uniform uint u_fragments;

// Each invocation takes P2_PER_INVOCATION consecutive entries. Entries
// recorded one after another are mostly the same primitive's, so it keeps a
// run's least opacity and its mass behind while the element stays the same
// and adds them to the element once the element changes, and its important
// fragments once at the end: on llvmpipe every atomic is a loop over the
// vector's lanes. Minima and integer sums are the same in any order.
#define P2_PER_INVOCATION 8u
void flush(uint element, uint alpha_bits, uint behind)
{
    if (element == 0xFFFFFFFFu)
        return;
    atomicMin(element_alpha_min[element], alpha_bits);
    add_behind_units(element, behind);
}

void main()
{
    uint first = linear_invocation() * P2_PER_INVOCATION;
    uint run = 0xFFFFFFFFu, run_alpha = 0xFFFFFFFFu, run_behind = 0u;
    uvec2 important = uvec2(0u);
    for (uint i = first; i < first + P2_PER_INVOCATION && i < u_fragments; i++) {
        uvec4 f = fragments[i];
        float c[NTARGETS * 4];
        read_coefficients(ivec2(f.x & 0xffffu, f.x >> 16), c);
        float g = uintBitsToFloat(f.z), behind, front;
        float alpha = fragment_opacity_terms(f.y, g, uintBitsToFloat(f.w), c, behind, front);
        if (f.y != run) {
            flush(run, run_alpha, run_behind);
            run = f.y, run_alpha = 0xFFFFFFFFu, run_behind = 0u;
        }
        run_alpha = min(run_alpha, floatBitsToUint(alpha)); // (non-negative floats order like their bits)
        run_behind += behind_units(behind);
        important += important_counts(g, front);
    }
    flush(run, run_alpha, run_behind);
    add_important(important);
}
