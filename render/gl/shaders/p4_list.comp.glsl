// P4 over its own recorded fragments (fragment_list.glsl, COMPOSITE_LIST): a
// recording P4 writes no target; one invocation a pixel then walks the
// pixel's chain (last fragment first) and sums what p4_optical_depth.frag.glsl
// would have blended, f = -ln(1 - alpha) projected at the series depth, into
// the coefficient targets (cleared before P4), which P5 over the same chain
// (p5_list.comp.glsl) reads after they are summed over MPI ranks.
layout(local_size_x = 64) in;
uint linear_invocation() { return gl_GlobalInvocationID.y * gl_NumWorkGroups.x * 64u + gl_GlobalInvocationID.x; }

layout(binding = IMG_COEF_FIRST, rgba32f) writeonly uniform image2D u_out0;
layout(binding = IMG_COEF_FIRST + 1, rgba32f) writeonly uniform image2D u_out1;
layout(binding = IMG_COEF_FIRST + 2, rgba32f) writeonly uniform image2D u_out2;
layout(binding = IMG_COEF_FIRST + 3, rgba32f) writeonly uniform image2D u_out3;
layout(binding = IMG_COEF_FIRST + 4, rgba32f) writeonly uniform image2D u_out4;

void main()
{
    uint p = linear_invocation();
    if (p >= u_chain_pixels)
        return;
    uint i = composite_heads[p];
    if (i == FRAGMENT_NONE)
        return; // no fragment: the targets keep their cleared 0
    float sum[NTARGETS * 4];
    for (int j = 0; j < NTARGETS * 4; j++)
        sum[j] = 0.0;
    while (i != FRAGMENT_NONE) {
        uvec4 f = composites[i];
        float c[NTARGETS * 4];
        fourier_project(uintBitsToFloat(f.y), -log(1.0 - unpack_opacity(f.z)), c);
        for (int j = 0; j < NTARGETS * 4; j++)
            sum[j] += c[j];
        i = f.x;
    }
    ivec2 xy = ivec2(p % u_chain_width, p / u_chain_width);
    imageStore(u_out0, xy, vec4(sum[0], sum[1], sum[2], sum[3]));
#if NTARGETS > 1
    imageStore(u_out1, xy, vec4(sum[4], sum[5], sum[6], sum[7]));
#endif
#if NTARGETS > 2
    imageStore(u_out2, xy, vec4(sum[8], sum[9], sum[10], sum[11]));
#endif
#if NTARGETS > 3
    imageStore(u_out3, xy, vec4(sum[12], sum[13], sum[14], sum[15]));
#endif
#if NTARGETS > 4
    imageStore(u_out4, xy, vec4(sum[16], sum[17], sum[18], sum[19]));
#endif
}
