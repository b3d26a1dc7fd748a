// P5 accumulation (FOO Eq. 19 numerator and weights): w C and w, additively.
// FOO weight: alpha/(1-alpha) exp(-tau(d_i)); midpoint: alpha exp(-max(tau - f/2, 0)).
// TAU_BINS: tau(d) from P4's depth bins (method "binning").

uniform int u_estimator;

layout(location = 0) out vec4 o_accum;

void main()
{
    if (outside_primitive())
        discard;
    FLOOR_RETURN
    float alpha = fragment_alpha();
    float c[NTARGETS * 4];
    read_coefficients(ivec2(gl_FragCoord.xy), c);
#ifdef TAU_BINS
    float tau = bins_eval(c, fragment_series_depth());
#else
    float tau = max(fourier_eval(c, fragment_series_depth()), 0.0);
#endif
    float w = composite_weight(alpha, tau, u_estimator);
    o_accum = vec4(fragment_color() * w, w);
}
