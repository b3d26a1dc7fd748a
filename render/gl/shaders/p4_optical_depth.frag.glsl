// P4 optical-depth projection: f = -ln(1 - alpha) of the fragment's blended
// element opacity (or alpha = g^k for the "direct" baseline), full resolution.
// COMPOSITE_LIST: also records what P5 needs of the fragment (fragment_list.glsl).

uniform float u_weight; // subset stride
#ifdef SHADOW_MAP
// shadow.c's light pass: also the colour weighted by optical depth, (sum f C, sum f).
layout(location = NTARGETS) out vec4 o_shadow_color;
#endif

void main()
{
    if (outside_primitive())
        discard;
    FLOOR_RETURN
    float c[NTARGETS * 4];
    float f = -log(1.0 - fragment_alpha()) * draw_weight(u_weight);
    fourier_project(fragment_series_depth(), f, c);
    write_coefficients(c);
#ifdef SHADOW_MAP
    o_shadow_color = vec4(f * fragment_color(), f);
#endif
#ifdef COMPOSITE_LIST
    record_composite_fragment(fragment_alpha(), fragment_series_depth(), fragment_color());
#endif
}
