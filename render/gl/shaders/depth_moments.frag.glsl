// P0 "moments" (depthRange "moments"): the pixel's importance mass and its first
// two moments in depth, sum g^2 (1, u, u^2) with u = d - 1/2 (centred, so that
// the variance keeps its digits), additively at the optimization resolution.
// series_depth (common.glsl) warps every later Fourier pass's depth by them.
// The fourth channel, sum g^4, gives params.autoSubset the effective number of
// fragments in P1's sums, (sum g^2)^2 / sum g^4 (render/gl/fourier.c).
// FRAGMENT_CHAINS: appends the fragment (element, g, normalized depth) to the
// fragment list and to its pixel's chain instead, so that the moments and P1
// become compute passes over them (p0_list.comp.glsl, p1_list.comp.glsl,
// render/gl/fragment_list.c).

uniform float u_weight; // subset stride n, as P1

#ifndef FRAGMENT_CHAINS
layout(location = 0) out vec4 o_moments;
#endif

void main()
{
    if (outside_primitive())
        DISCARD;
    FLOOR_RETURN
    float g = fragment_importance();
    float w = g * g * draw_weight(u_weight);
    float u = normalized_depth(v_zview) - 0.5;
#ifdef FRAGMENT_CHAINS
    // The moments come from the list (p0_list.comp.glsl): nothing is blended.
    record_chained_fragment(fragment_element(), g, normalized_depth(v_zview));
#else
    o_moments = vec4(w, w * u, w * u * u, w * g * g);
#endif
}
