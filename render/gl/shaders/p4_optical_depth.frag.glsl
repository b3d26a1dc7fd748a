// P4 optical-depth projection: f = -ln(1 - alpha) of the fragment's blended
// element opacity (or alpha = g^k for the "direct" baseline), full resolution.
// COMPOSITE_LIST: also records what P5 needs of the fragment (fragment_list.glsl).

uniform float u_weight; // subset stride

void main()
{
    if (outside_primitive())
        DISCARD;
    FLOOR_RETURN
    float c[NTARGETS * 4];
    fourier_project(fragment_series_depth(), -log(1.0 - fragment_alpha()) * draw_weight(u_weight), c);
    write_coefficients(c);
#ifdef COMPOSITE_LIST
    record_composite_fragment(fragment_alpha(), fragment_series_depth(), fragment_color());
#endif
}
