// One direction of the shadow map's 7x7 binomial blur (shadow.c; OOS §6 blurs
// its opacity map with a 7x7 Gaussian): the map's sums are linear, so blurring
// each target blurs the series they define. Texels beyond the map count 0.
layout(local_size_x = 8, local_size_y = 8) in;
layout(binding = IMG_SMART_SRC, rgba32f) readonly uniform image2D u_src;
layout(binding = IMG_SMART_DST, rgba32f) writeonly uniform image2D u_dst;
uniform ivec2 u_size;
uniform ivec2 u_step; // (1, 0) or (0, 1)

void main()
{
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(p, u_size)))
        return;
    const float b[7] = float[7](1.0, 6.0, 15.0, 20.0, 15.0, 6.0, 1.0);
    vec4 sum = vec4(0.0);
    for (int i = -3; i <= 3; i++) {
        ivec2 q = p + i * u_step;
        if (all(greaterThanEqual(q, ivec2(0))) && all(lessThan(q, u_size)))
            sum += b[i + 3] / 64.0 * imageLoad(u_src, q);
    }
    imageStore(u_dst, p, sum);
}
