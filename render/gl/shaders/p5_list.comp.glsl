// P5 over P4's fragments (fragment_list.glsl, COMPOSITE_LIST): one invocation a
// pixel walks its chain in the order P4's fragment shader ran them, weighs each
// fragment as p5_accumulate.frag.glsl does (the same fourier_eval and
// composite_weight on the recorded opacity, depth and colour) and adds
// (w C, w) in that order as additive blending into the RGBA16F target does:
// each sum is converted to half precision after every addition, as below.
layout(local_size_x = 64) in;
uint linear_invocation() { return gl_GlobalInvocationID.y * gl_NumWorkGroups.x * 64u + gl_GlobalInvocationID.x; }

uniform int u_estimator;
layout(binding = IMG_EXACT_OUTPUT, rgba16f) writeonly uniform image2D u_accum;

// The sum's conversion to half precision as llvmpipe's blending stores an
// RGBA16F target: rounded toward zero (measured: round-to-nearest-even, the
// rounding of packHalf2x16, changed 1.4 % of demo:abc's pixels by one 8-bit
// step; truncation reproduces every image bit for bit), with halves below
// 2^-14 subnormal. The fragment's (w C, w) is added unrounded.
float half_toward_zero(float x)
{
    float a = abs(x);
    if (a < 6.103515625e-05) // below the smallest normal half: steps of 2^-24
        return sign(x) * floor(a * 16777216.0) / 16777216.0;
    return uintBitsToFloat(floatBitsToUint(x) & 0xFFFFE000u); // 10 of 23 mantissa bits
}

vec4 half_toward_zero(vec4 v)
{
    return vec4(half_toward_zero(v.x), half_toward_zero(v.y), half_toward_zero(v.z), half_toward_zero(v.w));
}

void main()
{
    uint p = linear_invocation();
    if (p >= u_chain_pixels)
        return;
    uint last = composite_chain_words[2u * p + 1u];
    if (last == FRAGMENT_NONE)
        return; // no fragment: the target keeps its cleared 0
    ivec2 xy = ivec2(p % u_chain_width, p / u_chain_width);
    float c[NTARGETS * 4];
    read_coefficients(xy, c);
    vec4 sum = vec4(0.0);
    uint i = composite_chain_words[2u * p];
    for (;;) {
        CompositeFragment f = composites[i];
        float tau = max(fourier_eval(c, f.depth), 0.0);
        float w = composite_weight(f.alpha, tau, u_estimator);
        sum = half_toward_zero(sum + vec4(vec3(f.r, f.g, f.b) * w, w));
        if (i == last)
            break;
        i = f.next;
    }
    imageStore(u_accum, xy, sum);
}
