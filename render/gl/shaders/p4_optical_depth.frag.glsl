// P4 optical-depth projection: f = -ln(1 - alpha) of the fragment's blended
// element opacity (or alpha = g^k for the "direct" baseline), full resolution.

uniform float u_weight; // subset stride

void main()
{
    if (outside_primitive())
        discard;
    FLOOR_RETURN
    float c[NTARGETS * 4];
    fourier_project(fragment_series_depth(), -log(1.0 - fragment_alpha()) * draw_weight(u_weight), c);
    write_coefficients(c);
}
