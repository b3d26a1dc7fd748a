// P1 importance projection (FOO Eq. 11): additive sum of g^2 in the Fourier basis
// at the fragment's normalized depth, at the optimization resolution.

uniform float u_weight; // subset stride n: every n-th primitive counts n times

void main()
{
    if (outside_primitive())
        discard;
    float g = fragment_importance();
    float c[NTARGETS * 4];
    fourier_project(series_depth(v_zview), g * g * draw_weight(u_weight), c);
    write_coefficients(c);
}
