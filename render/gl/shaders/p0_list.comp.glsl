// P0's moments over its recorded fragments (fragment_list.glsl,
// FRAGMENT_CHAINS): a recording P0 writes no target; one invocation a pixel
// of the optimization resolution turns its chain around (recorded from the
// last fragment back, it then runs from the first, word p holding the first
// entry) and adds up what depth_moments.frag.glsl would have blended,
// g^2 (1, u, u^2, g^2) with u = d - 1/2, in the order its fragment shader ran
// them, starting from the cleared 0, as additive blending would: the moments
// are the drawn P0's bit for bit (`precise` keeps the products and the sums
// apart, as blending does). The chain is then P1's (p1_list.comp.glsl).
layout(local_size_x = 64) in;
uint linear_invocation() { return gl_GlobalInvocationID.y * gl_NumWorkGroups.x * 64u + gl_GlobalInvocationID.x; }

layout(binding = IMG_COEF_FIRST, rgba32f) writeonly uniform image2D u_moments_out;

void main()
{
    uint p = linear_invocation();
    if (p >= u_chain_pixels)
        return;
    uint i = chain_words[p];
    if (i == FRAGMENT_NONE)
        return; // no fragment: the target keeps its cleared 0
    uint after = FRAGMENT_NONE;
    while (i != FRAGMENT_NONE) {
        uint before = fragments[i].x;
        fragments[i].x = after;
        after = i;
        i = before;
    }
    chain_words[p] = after;
    precise vec4 sum = vec4(0.0);
    for (i = after; i != FRAGMENT_NONE;) {
        uvec4 f = fragments[i];
        float g = uintBitsToFloat(f.z);
        precise float w = g * g;
        precise float u = uintBitsToFloat(f.w) - 0.5;
        precise vec4 m = vec4(w, w * u, w * u * u, w * g * g);
        sum = sum + m;
        i = f.x;
    }
    imageStore(u_moments_out, ivec2(p % u_chain_width, p / u_chain_width), sum);
}
