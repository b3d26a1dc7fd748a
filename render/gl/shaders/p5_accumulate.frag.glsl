// P5 accumulation (FOO Eq. 19 numerator and weights): w C and w, additively.
// FOO weight: alpha/(1-alpha) exp(-tau(d_i)); midpoint: alpha exp(-max(tau - f/2, 0)).
// TAU_BINS: tau(d) from P4's depth bins (method "binning").

#ifndef u_estimator
uniform int u_estimator;
#endif

#if defined(READ_ALPHA) && !defined(DIRECT_ALPHA) && !defined(TAU_BINS)
// topDecileReach (docs/ALGORITHM.md §8): the sums of g w (w = alpha T, T the
// transmittance in front: composite_weight is that with either estimator)
// and of g alpha, over every fragment and over those at or above the top
// decile's importance u_reach_g (> 1: not measured). Drawn, they blend per
// pixel into a second target (reach_reduce.comp.glsl adds its pixels up);
// computed, they go in 1/65536 units, each 64-bit as a low word and its
// carries, into 64 slots by pixel so that the atomics do not all meet on one
// word. Atomics per fragment cost a drawn P5 a fifth of its time on lines.
uniform float u_reach_g;
#ifndef RASTER_STAGE
layout(location = 1) out vec4 o_reach;

void reach(float alpha, float w)
{
    float g = u_reach_g > 1.0 ? 0.0 : fragment_importance();
    float top = g >= u_reach_g ? 1.0 : 0.0;
    o_reach = vec4(g * w, g * alpha, top * g * w, top * g * alpha);
}
#else
layout(std430, binding = BIND_TOP_REACH) buffer TopReach { uint top_reach[64 * 8]; };

void reach_add(uint at, float value)
{
    uint add = uint(clamp(value, 0.0, 1.0) * 65536.0 + 0.5);
    uint old = atomicAdd(top_reach[at], add);
    if (old > 0xFFFFFFFFu - add)
        atomicAdd(top_reach[at + 1u], 1u);
}

void reach(float alpha, float w)
{
    if (u_reach_g > 1.0)
        return;
    float g = fragment_importance();
    uint at = 8u * ((uint(FRAG_COORD.x) + 7u * uint(FRAG_COORD.y)) & 63u);
    reach_add(at, g * w);
    reach_add(at + 2u, g * alpha);
    if (g >= u_reach_g) {
        reach_add(at + 4u, g * w);
        reach_add(at + 6u, g * alpha);
    }
}
#endif
#else
void reach(float alpha, float w) {}
#endif

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
    reach(alpha, w);
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
