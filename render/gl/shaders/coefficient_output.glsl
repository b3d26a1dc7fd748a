// Render targets of the passes that accumulate Fourier coefficients (P1, P4):
// NTARGETS RGBA32F attachments, additively blended; in the compute
// rasterizer (RASTER_STAGE) one plane of sums per coefficient.
#ifdef RASTER_STAGE
void write_coefficients(float c[NTARGETS * 4])
{
    for (int j = 0; j < NCOEF; j++)
        raster_add(j, c[j]);
}
#elif defined(COMPOSITE_LIST)
// The recording P4 writes no coefficient target (fragment_list.glsl).
void write_coefficients(float c[NTARGETS * 4]) {}
#else
layout(location = 0) out vec4 o_coef0;
#if NTARGETS > 1
layout(location = 1) out vec4 o_coef1;
#endif
#if NTARGETS > 2
layout(location = 2) out vec4 o_coef2;
#endif
#if NTARGETS > 3
layout(location = 3) out vec4 o_coef3;
#endif
#if NTARGETS > 4
layout(location = 4) out vec4 o_coef4;
#endif

void write_coefficients(float c[NTARGETS * 4])
{
    o_coef0 = vec4(c[0], c[1], c[2], c[3]);
#if NTARGETS > 1
    o_coef1 = vec4(c[4], c[5], c[6], c[7]);
#endif
#if NTARGETS > 2
    o_coef2 = vec4(c[8], c[9], c[10], c[11]);
#endif
#if NTARGETS > 3
    o_coef3 = vec4(c[12], c[13], c[14], c[15]);
#endif
#if NTARGETS > 4
    o_coef4 = vec4(c[16], c[17], c[18], c[19]);
#endif
}
#endif
