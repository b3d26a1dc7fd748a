// P5 accumulation (FOO Eq. 19 numerator and weights): w C and w, additively.
// FOO weight: alpha/(1-alpha) exp(-tau(d_i)); midpoint: alpha exp(-max(tau - f/2, 0)).
// TAU_BINS: tau(d) from P4's depth bins (method "binning").

uniform int u_estimator;

#ifndef RASTER_STAGE
layout(location = 0) out vec4 o_accum;
#endif

void main()
{
    if (outside_primitive())
        DISCARD;
    FLOOR_RETURN
    float alpha = fragment_alpha();
    float c[NTARGETS * 4];
    read_coefficients(ivec2(FRAG_COORD.xy), c);
#ifdef TAU_BINS
    float tau = bins_eval(c, fragment_series_depth());
#else
    float tau = max(fourier_eval(c, fragment_series_depth()), 0.0);
#endif
    float w = composite_weight(alpha, tau, u_estimator);
#ifdef RASTER_STAGE
    vec3 cw = fragment_color() * w;
    raster_add(0, cw.r);
    raster_add(1, cw.g);
    raster_add(2, cw.b);
    raster_add(3, w);
#else
    o_accum = vec4(fragment_color() * w, w);
#endif
}
