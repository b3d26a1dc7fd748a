// Smart transparency in image space (docs/ALGORITHM.md §29; OOS §6 after
// Carnecky et al.): silhouettes where a transparent layer ends and halos on
// what it ends over, found in P4's optical-depth sums, diffused, and laid over
// the resolved image. STAGE 0 injects, 1 diffuses one step, 2 applies.
layout(local_size_x = 8, local_size_y = 8) in;
layout(binding = IMG_SMART_INJECT, rgba32f) uniform image2D u_inject; // injected silhouette, halo; A0
layout(binding = IMG_SMART_SRC, rgba32f) readonly uniform image2D u_src;
layout(binding = IMG_SMART_DST, rgba32f) writeonly uniform image2D u_dst;
layout(binding = IMG_SMART_OUTPUT, rgba8) uniform image2D u_image;
uniform ivec2 u_size;
uniform float u_strength;

// A layer "ends" between two pixels where the optical depth drops by more than
// this (an opacity of 1/255 or more).
#define SMART_MIN_STEP 0.0039293

const ivec2 NEIGHBOURS[4] = ivec2[4](ivec2(1, 0), ivec2(-1, 0), ivec2(0, 1), ivec2(0, -1));

bool inside(ivec2 q) { return all(greaterThanEqual(q, ivec2(0))) && all(lessThan(q, u_size)); }

#if STAGE == 0
// A0 and the optical-depth-weighted mean depth: the integral of d f(d) over
// [0, 1] is A0/2 - sum_k B_k/(pi k) for the series of common.glsl.
vec2 depth_mass(ivec2 p)
{
    float c[NTARGETS * 4];
    read_coefficients(p, c);
    float m = 0.5 * c[0];
    for (int k = 1; k <= BANDS; k++)
        m -= c[2 * k] / (PI * float(k));
    return vec2(c[0], c[0] > 0.0 ? m / c[0] : 0.0);
}
#endif

void main()
{
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    if (!inside(p))
        return;
#if STAGE == 0
    // Silhouette at p: a neighbour lacks a layer that p has; its opacity
    // 1 - exp(-dA) is the occluder's. Halo at p: a neighbour has a layer p
    // lacks, lying in front of what p shows (its mean depth before p's).
    vec2 a = depth_mass(p);
    float sil = 0.0, halo = 0.0;
    for (int i = 0; i < 4; i++) {
        ivec2 q = p + NEIGHBOURS[i];
        if (!inside(q))
            continue;
        vec2 b = depth_mass(q);
        float d = a.x - b.x;
        if (d > SMART_MIN_STEP)
            sil = max(sil, 1.0 - exp(-d));
        else if (-d > SMART_MIN_STEP && a.x > SMART_MIN_STEP && (b.x * b.y - a.x * a.y) / -d < a.y)
            halo = max(halo, 1.0 - exp(d));
    }
    imageStore(u_inject, p, vec4(sil, halo, a.x, 0.0));
#elif STAGE == 1
    // One diffusion step with the injected values held: a silhouette spreads
    // over the pixels that hold its layer (never down a step of the optical
    // depth), a halo over those that do not (never up one); a neighbour that
    // does not pass counts as 0, so both fade with distance.
    vec4 own = imageLoad(u_inject, p);
    vec2 sum = vec2(0.0);
    for (int i = 0; i < 4; i++) {
        ivec2 q = p + NEIGHBOURS[i];
        if (!inside(q))
            continue;
        float aq = imageLoad(u_inject, q).z;
        vec2 v = imageLoad(u_src, q).xy;
        sum.x += own.z >= aq - SMART_MIN_STEP ? v.x : 0.0;
        sum.y += own.z <= aq + SMART_MIN_STEP ? v.y : 0.0;
    }
    imageStore(u_dst, p, vec4(max(own.xy, 0.25 * sum), 0.0, 0.0));
#else
    // Black silhouettes and white halos, scaled by style.smartTransparency.
    vec2 v = imageLoad(u_src, p).xy * u_strength;
    vec4 c = imageLoad(u_image, p);
    vec3 rgb = c.rgb * (1.0 - v.x);
    rgb += (1.0 - rgb) * v.y;
    imageStore(u_image, p, vec4(rgb, c.a));
#endif
}
