// P2's optimal opacity of one fragment (FOO Eq. 10; r weighs importance in
// front, q behind) from the reconstructed importance sum, atomic-min into its
// element. Shared by the fragment shader (p2_opacity.frag.glsl) and the
// compute pass over P1's fragment list (p2_list.comp.glsl), so that both
// compute the same bits from the same g, depth and pixel sums.

layout(std430, binding = BIND_ELEMENT_ALPHA_MIN) buffer ElementAlphaMin { uint element_alpha_min[]; };

uniform float u_q;
uniform float u_r;
uniform float u_lambda;
#ifndef u_estimator
uniform int u_estimator; // 0 foo, 1 midpoint
#endif
uniform float u_norm_mass; // normalize auto: reference mass (docs/ALGORITHM.md "Density normalization"); 0 = off
uniform float u_target_opacity; // t of OOS Eq. 7 (lc_foo_target_opacity); 1 = the paper's

// The fragment's opacity, and the importance mass behind and in front of it.
float fragment_opacity_terms(uint element, float g, float d, float c[NTARGETS * 4], out float behind, out float front)
{
    float G = fourier_eval(c, d);
    float g2 = g * g;
    // The midpoint estimator removes the half of the fragment's own step that
    // the truncated series attributes to F(d_i) (docs/ALGORITHM.md).
    float own = u_estimator == 1 ? 0.5 * g2 : g2;
    front = max(G - own, 0.0);
    behind = max(c[0] - G - (u_estimator == 1 ? 0.5 * g2 : 0.0), 0.0);
    // Density normalization: in a pixel whose total mass exceeds the reference
    // the sums count as fractions of it, so the layer count stops mattering,
    // and the emphasis exponent grows with the density (foo_math.h).
    float k = u_norm_mass > 0.0 && c[0] > u_norm_mass ? u_norm_mass / c[0] : 1.0;
    float lambda = u_norm_mass > 0.0 ? (1.0 + 3.0 * (1.0 - k) * (1.0 - k)) * u_lambda : u_lambda;
    float ge = emphasis_importance(element, g);
    float emphasis = lambda > 0.0 ? pow(max(1.0 - ge, 0.0), 2.0 * lambda) : 1.0;
    float alpha = 1.0 / (1.0 + k * emphasis * (u_r * front + u_q * behind));
    return alpha * u_target_opacity;
}

void fragment_opacity(uint element, float g, float d, float c[NTARGETS * 4])
{
    float behind, front;
    float alpha = fragment_opacity_terms(element, g, d, c, behind, front);
    // Non-negative floats order like their bit patterns.
    atomicMin(element_alpha_min[element], floatBitsToUint(alpha));
    add_behind(element, behind);
    count_important(g, front);
}
