// P5 over P4's fragments (fragment_list.glsl, COMPOSITE_LIST): one invocation a
// pixel reads its coefficients once (SUMS_IN_WALK: sums them from its chain
// first, as p4_list.comp.glsl does, and stores them), walks its chain (last
// fragment first), weighs each fragment as p5_accumulate.frag.glsl does (the
// same fourier_eval and composite_weight) and adds (w C, w) as blending into
// the RGBA16F target does, converting the sum to half precision after every
// addition (in the chain's order, the reverse of the drawn P5's). With u_reach_g <= 1 it also
// sums the pixel's topDecileReach terms as the drawn P5 blends them
// (p5_accumulate.frag.glsl) into the reach target that reach_reduce.comp.glsl
// adds up.
layout(local_size_x = 64) in;
uint linear_invocation() { return gl_GlobalInvocationID.y * gl_NumWorkGroups.x * 64u + gl_GlobalInvocationID.x; }

uniform int u_estimator;
uniform float u_reach_g;
layout(binding = IMG_EXACT_OUTPUT, rgba16f) writeonly uniform image2D u_accum;
layout(binding = IMG_P5_REACH, rgba32f) writeonly uniform image2D u_reach;

// The sum's conversion to half precision as llvmpipe's blending stores an
// RGBA16F target: rounded toward zero, with halves below 2^-14 subnormal (a
// float sum stored once instead turns pixels whose every weight is below
// half's least subnormal from the background to black where the drawn P5
// leaves them empty). The fragment's (w C, w) is added unrounded.
float half_toward_zero(float x)
{
    float a = abs(x);
    if (a < 6.103515625e-05) // below the smallest normal half: steps of 2^-24
        return sign(x) * floor(a * 16777216.0) / 16777216.0;
    return uintBitsToFloat(floatBitsToUint(x) & 0xFFFFE000u); // 10 of 23 mantissa bits
}

vec4 half_toward_zero(vec4 v)
{
    return vec4(half_toward_zero(v.x), half_toward_zero(v.y), half_toward_zero(v.z), half_toward_zero(v.w));
}

void main()
{
    ivec2 xy;
    vec3 warp;
    uint i = composite_pixel(linear_invocation(), xy, warp);
    if (i == FRAGMENT_NONE)
        return; // no fragment: the targets keep their cleared 0
    float c[NTARGETS * 4];
#ifdef SUMS_IN_WALK
    // One process: P4's sums from the same chain first (what p4_list.comp.glsl
    // stores, for the resolve and smartTransparency), so that the chain is
    // read twice in a row where two passes streamed the whole list twice.
    composite_sums(i, warp, c);
    store_coefficients(xy, c);
#else
    read_coefficients(xy, c);
#endif
    vec4 sum = vec4(0.0), reach = vec4(0.0);
    // The top decile's bound in g's 16 bits, so that a fragment at the bound
    // (an element's own g, as often) stays in it.
    uint top_q = uint(clamp(u_reach_g, 0.0, 1.0) * 65535.0 + 0.5);
    while (i != FRAGMENT_NONE) {
        uvec4 f = composites[i];
        float alpha = unpack_opacity(f.z);
        float tau = max(fourier_eval(c, composite_depth(warp, f.y)), 0.0);
        float w = composite_weight(alpha, tau, u_estimator);
        sum = half_toward_zero(sum + vec4(composite_color(f.y, f.w) * w, w));
        float g = unpack_importance(f.z);
        float top = f.z >> 16 >= top_q ? 1.0 : 0.0;
        reach += vec4(g * w, g * alpha, top * g * w, top * g * alpha);
        i = f.x;
    }
    imageStore(u_accum, xy, sum);
    if (u_reach_g <= 1.0)
        imageStore(u_reach, xy, reach);
}
