// Stores the compute rasterizer's sums (raster.comp.glsl; 64-bit fixed point
// as (low, high) word pairs, high * 4096 + low / 2^20: fragment_common.glsl
// raster_add) into the pass's
// targets, which the later passes read as the fixed pipeline left them: channel
// 4i + j of a pixel's sums becomes channel j of target i (compute_raster.c binds the targets).
layout(local_size_x = 64) in;

layout(std430, binding = BIND_RASTER_SUMS) readonly buffer RasterSums { int raster_sums[]; };
uniform ivec2 u_raster_size;
uniform int u_planes;  // planes summed; the rest of the last target's channels are 0
uniform int u_targets; // 1..5
#ifdef ADD_FORMAT // params.progressive: a later batch adds its sums to the targets' (compute_raster.c)
layout(ADD_FORMAT, binding = IMG_COEF_FIRST) uniform image2D u_out0;
layout(ADD_FORMAT, binding = IMG_COEF_FIRST + 1) uniform image2D u_out1;
layout(ADD_FORMAT, binding = IMG_COEF_FIRST + 2) uniform image2D u_out2;
layout(ADD_FORMAT, binding = IMG_COEF_FIRST + 3) uniform image2D u_out3;
layout(ADD_FORMAT, binding = IMG_COEF_FIRST + 4) uniform image2D u_out4;
#define STORE(img, p, v) imageStore(img, p, imageLoad(img, p) + (v))
#else
layout(binding = IMG_COEF_FIRST) writeonly uniform image2D u_out0;
layout(binding = IMG_COEF_FIRST + 1) writeonly uniform image2D u_out1;
layout(binding = IMG_COEF_FIRST + 2) writeonly uniform image2D u_out2;
layout(binding = IMG_COEF_FIRST + 3) writeonly uniform image2D u_out3;
layout(binding = IMG_COEF_FIRST + 4) writeonly uniform image2D u_out4;
#define STORE(img, p, v) imageStore(img, p, v)
#endif

vec4 target_value(int t, int pixel, int n)
{
    vec4 v = vec4(0.0);
    for (int j = 0; j < 4; j++)
        if (4 * t + j < u_planes) {
            int i = 2 * (pixel * u_planes + 4 * t + j);
            v[j] = float(double(raster_sums[i + 1]) * 4096.0lf + double(raster_sums[i]) * (1.0lf / 1048576.0lf));
        }
    return v;
}

void main()
{
    int n = u_raster_size.x * u_raster_size.y;
    int pixel = int(gl_GlobalInvocationID.x + gl_GlobalInvocationID.y * gl_NumWorkGroups.x * gl_WorkGroupSize.x);
    if (pixel >= n)
        return;
    ivec2 p = ivec2(pixel % u_raster_size.x, pixel / u_raster_size.x);
    STORE(u_out0, p, target_value(0, pixel, n));
    if (u_targets > 1)
        STORE(u_out1, p, target_value(1, pixel, n));
    if (u_targets > 2)
        STORE(u_out2, p, target_value(2, pixel, n));
    if (u_targets > 3)
        STORE(u_out3, p, target_value(3, pixel, n));
    if (u_targets > 4)
        STORE(u_out4, p, target_value(4, pixel, n));
}
