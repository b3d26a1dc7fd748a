// Writes a pixel's Fourier coefficient sums into the coefficient targets as
// images: the compute passes over recorded fragments (p1_list.comp.glsl,
// p4_list.comp.glsl), which make what a drawn P1 or P4 blends.
layout(binding = IMG_COEF_FIRST, rgba32f) writeonly uniform image2D u_out0;
layout(binding = IMG_COEF_FIRST + 1, rgba32f) writeonly uniform image2D u_out1;
layout(binding = IMG_COEF_FIRST + 2, rgba32f) writeonly uniform image2D u_out2;
layout(binding = IMG_COEF_FIRST + 3, rgba32f) writeonly uniform image2D u_out3;
layout(binding = IMG_COEF_FIRST + 4, rgba32f) writeonly uniform image2D u_out4;

void store_coefficients(ivec2 xy, float sum[NTARGETS * 4])
{
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
