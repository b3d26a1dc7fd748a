// P1 over P0's fragments (fragment_list.glsl, FRAGMENT_CHAINS): one invocation
// a pixel of the optimization resolution walks its chain of fragments in the
// order P0's fragment shader ran them, projects each as p1_importance.frag.glsl
// does (series_depth_at's warp, made once a pixel, and the same
// fourier_project) and adds them up in that order, starting from the cleared
// 0, as additive blending would: the sums are
// the drawn P1's, bit for bit, without a traversal of the geometry. Each entry's
// link becomes its pixel and its normalized depth its series depth, so that P2
// over the list (p2_list.comp.glsl) reads what it reads after a recording P1.
layout(local_size_x = 64) in;
uint linear_invocation() { return gl_GlobalInvocationID.y * gl_NumWorkGroups.x * 64u + gl_GlobalInvocationID.x; }

uniform float u_weight; // 1: P0 and P1 draw every primitive

void main()
{
    uint p = linear_invocation();
    if (p >= u_chain_pixels)
        return;
    uint i = chain_words[p]; // the first entry (p0_list.comp.glsl turned the chain around)
    if (i == FRAGMENT_NONE)
        return; // no fragment: the target keeps its cleared 0
    ivec2 xy = ivec2(p % u_chain_width, p / u_chain_width);
    vec2 frag_xy = vec2(xy) + 0.5;
    uint packed_xy = uint(xy.x) | (uint(xy.y) << 16);
    vec3 warp = series_warp_of(series_moments_at(frag_xy)); // once a pixel: series_depth_at's
    float sum[NTARGETS * 4];
    for (int j = 0; j < NTARGETS * 4; j++)
        sum[j] = 0.0;
    while (i != FRAGMENT_NONE) {
        uvec4 f = fragments[i];
        float g = uintBitsToFloat(f.z);
        float d = series_depth_warped(warp, uintBitsToFloat(f.w));
        float c[NTARGETS * 4];
        fourier_project(d, g * g * u_weight, c);
        for (int j = 0; j < NTARGETS * 4; j++)
            sum[j] += c[j];
        fragments[i] = uvec4(packed_xy, f.y, f.z, floatBitsToUint(d));
        i = f.x;
    }
    store_coefficients(xy, sum);
}
