// Visibility-weighted colour histogram (DLS Eq. 6) after P5 (color_equalize.c):
// each fragment's share of its pixel's colour, (w_i / sum w) (1 - T) with w_i
// P5's weight and T = exp(-A''_0), added in fixed point to the bin of its
// colormap coordinate. Halo fragments carry no colour value and add nothing.
layout(std430, binding = BIND_COLOR_HISTOGRAM) buffer ColorHistogram { uint color_histogram[]; };
layout(binding = TEX_EQUALIZE_ACCUM) uniform sampler2D u_eq_accum; // P5's sums: .a = sum w
#ifndef u_estimator
uniform int u_estimator;
#endif
uniform float u_eq_scale; // fixed-point units per unit of visible share

void main()
{
    if (outside_primitive() || halo_position() >= 0.0)
        discard;
    FLOOR_RETURN
    ivec2 p = ivec2(gl_FragCoord.xy);
    float sum_w = texelFetch(u_eq_accum, p, 0).a;
    if (!(sum_w > 0.0))
        return;
    float alpha = fragment_alpha();
    float c[NTARGETS * 4];
    read_coefficients(p, c);
    float tau = max(fourier_eval(c, fragment_series_depth()), 0.0);
    float w = composite_weight(alpha, tau, u_estimator);
    float share = w / sum_w * (1.0 - exp(-c[0]));
    int bin = clamp(int(clamp(v_cscalar, 0.0, 1.0) * 256.0), 0, 255);
    uint units = uint(share * u_eq_scale + 0.5);
    if (units > 0u)
        atomicAdd(color_histogram[bin], units);
}
