// topDecileReach (docs/ALGORITHM.md §8): a drawn P5 blends each pixel's four
// sums (g w, g alpha, and both over the top decile's fragments) into an
// RGBA32F target; this pass adds them into the 64 slots that the compute
// rasterizer's P5 adds to fragment by fragment, in the same units (1/65536,
// each 64-bit as a low word and its carries). An invocation sums a row in
// registers, so the atomics are a few per row, not per fragment.

layout(local_size_x = 64) in;

layout(binding = TEX_REACH_SUMS) uniform sampler2D u_sums;
layout(std430, binding = BIND_TOP_REACH) buffer TopReach { uint top_reach[64 * 8]; };
uniform ivec2 u_size;

void main()
{
    int y = int(gl_GlobalInvocationID.x);
    if (y >= u_size.y)
        return;
    uvec4 lo = uvec4(0u), hi = uvec4(0u);
    for (int x = 0; x < u_size.x; x++) {
        // A pixel's sums are at most its fragment count: far below 2^16.
        uvec4 add = uvec4(clamp(texelFetch(u_sums, ivec2(x, y), 0), 0.0, 65535.0) * 65536.0 + 0.5);
        uvec4 sum = lo + add;
        hi += uvec4(lessThan(sum, add));
        lo = sum;
    }
    uint at = 8u * (uint(y) & 63u);
    for (int k = 0; k < 4; k++) {
        uint old = atomicAdd(top_reach[at + 2u * uint(k)], lo[k]);
        uint carry = hi[k] + (old > 0xFFFFFFFFu - lo[k] ? 1u : 0u);
        if (carry != 0u)
            atomicAdd(top_reach[at + 2u * uint(k) + 1u], carry);
    }
}
