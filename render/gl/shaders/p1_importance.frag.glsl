// P1 importance projection (FOO Eq. 11): additive sum of g^2 in the Fourier basis
// at the fragment's normalized depth, at the optimization resolution.
// RECORD_FRAGMENTS: also appends the fragment to P1's fragment list.

uniform float u_weight; // subset stride n: every n-th primitive counts n times

void main()
{
    if (outside_primitive())
        discard;
    FLOOR_RETURN
    float g = fragment_importance();
    float d = series_depth(v_zview);
    float c[NTARGETS * 4];
    fourier_project(d, g * g * draw_weight(u_weight), c);
    write_coefficients(c);
#ifdef RECORD_FRAGMENTS
    uint i = atomicAdd(fragment_count, 1u);
    if (i < u_fragment_capacity)
        fragments[i] = uvec4(uint(gl_FragCoord.x) | (uint(gl_FragCoord.y) << 16), fragment_element(),
                             floatBitsToUint(g), floatBitsToUint(d));
#endif
}
