// Method "kanzler": the maps' last step (M3D §3.2). C is the pixel's fragment
// count; V = 1 - |sum t|/C of its unit tangents (lines; 0 for points, which
// have no direction); M and D are the unpacked maximum and its depth averaged
// over the 5x5 pixels around (those inside the image), the thesis's blur that
// softens the edges where D jumps. Output (C, M, D, V) per pixel.

layout(local_size_x = 8, local_size_y = 8) in;

layout(binding = TEX_KANZLER_SUMS) uniform sampler2D u_sums;
layout(binding = IMG_KANZLER_MAX, r32ui) readonly uniform uimage2D u_max;
layout(binding = IMG_KANZLER_MAPS, rgba32f) writeonly uniform image2D u_maps;
uniform ivec2 u_size;
uniform int u_has_tangents;

void main()
{
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    if (p.x >= u_size.x || p.y >= u_size.y)
        return;
    vec4 s = texelFetch(u_sums, p, 0);
    float c = s.w;
    float v = u_has_tangents != 0 && c > 0.5 ? clamp(1.0 - length(s.xyz) / c, 0.0, 1.0) : 0.0;
    vec2 sum = vec2(0.0);
    float n = 0.0;
    for (int dy = -2; dy <= 2; dy++)
        for (int dx = -2; dx <= 2; dx++) {
            ivec2 q = p + ivec2(dx, dy);
            if (q.x < 0 || q.y < 0 || q.x >= u_size.x || q.y >= u_size.y)
                continue;
            sum += unpackUnorm2x16(imageLoad(u_max, q).r); // (d, g)
            n += 1.0;
        }
    sum /= n;
    imageStore(u_maps, p, vec4(c, sum.y, sum.x, v));
}
