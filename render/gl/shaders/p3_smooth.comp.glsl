// P3 smoothing and fading of element opacities (docs/ALGORITHM.md). One dispatch per
// stage; the host swaps the src/dst bindings between smoothing iterations.
layout(local_size_x = 256) in;
// Item index of a 1D dispatch that lc_dispatch_linear may split into rows.
uint linear_invocation() { return gl_GlobalInvocationID.y * gl_NumWorkGroups.x * 256u + gl_GlobalInvocationID.x; }

layout(std430, binding = BIND_ELEMENT_ALPHA_MIN) buffer ElementAlphaMin { uint element_alpha_min[]; };
layout(std430, binding = BIND_ELEMENT_ALPHA) buffer ElementAlpha { float element_alpha[]; }; // current opacities, faded in place
layout(std430, binding = BIND_SMOOTH_SRC) buffer SmoothSrc { float smooth_src[]; };
layout(std430, binding = BIND_SMOOTH_DST) buffer SmoothDst { float smooth_dst[]; };
layout(std430, binding = BIND_ADJ_OFFSETS) readonly buffer AdjacencyOffsets { uint adjacency_offsets[]; };
layout(std430, binding = BIND_ADJ) readonly buffer Adjacency { uint adjacency[]; };
layout(std430, binding = BIND_STATS) buffer Stats { uint max_change_bits; uint max_gap_bits; };
layout(std430, binding = BIND_ADJ_WEIGHTS) readonly buffer AdjacencyWeights { uint adjacency_weight_words[]; }; // 16-bit unorm, 2 per word
float adjacency_weight(uint i) { return float((adjacency_weight_words[i >> 1] >> ((i & 1u) * 16u)) & 0xffffu) / 65535.0; }

uniform int u_stage; // 0 gather targets, 1 smooth step, 2 fade, 3 fade toward the gathered targets (no smoothing)
uniform uint u_count;
uniform uint u_element_offset; // layers: one dispatch per layer, its elements from here (its adjacency is local)
uniform float u_omega;
uniform float u_fade; // 1 - 2^(-dt / half-life); 1 for one-shot renders
uniform int u_weighted; // params.smoothingWeights "distance": neighbours weighted by adjacency_weight()

// Elements with no fragment this frame keep their current value as target.
float target(uint e)
{
    float a = uintBitsToFloat(element_alpha_min[e]);
    return a > 1.0 ? element_alpha[e] : a;
}

void fade(uint invocation);

void main()
{
    uint local = linear_invocation();
    if (u_stage >= 2) {
        fade(local);
        return;
    }
    if (local >= u_count)
        return;
    uint e = u_element_offset + local;
    if (u_stage == 0) {
        smooth_dst[e] = target(e);
    } else {
        // Only elements that received fragments this frame pass their value on,
        // so the targets of seen elements depend on this frame alone and fading
        // converges geometrically to the one-shot result. An element without
        // fragments (e.g. a patch too small for the optimization resolution) is
        // filled with the mean of its seen neighbours instead of its stale value.
        uint begin = adjacency_offsets[local], end = adjacency_offsets[local + 1u];
        bool seen_self = uintBitsToFloat(element_alpha_min[e]) <= 1.0;
        float v = smooth_src[e];
        float sum = 0.0;
        uint seen = 0u;
        for (uint i = begin; i < end; i++) {
            uint n = u_element_offset + adjacency[i];
            if (uintBitsToFloat(element_alpha_min[n]) <= 1.0) {
                sum += smooth_src[n];
                seen++;
            }
        }
        if (u_weighted != 0) {
            // The weighted mean over the seen neighbours (OOS §4.3, lc_foo_smooth_step_weighted).
            float wsum = 0.0;
            sum = 0.0;
            for (uint i = begin; i < end; i++) {
                uint n = u_element_offset + adjacency[i];
                if (uintBitsToFloat(element_alpha_min[n]) <= 1.0) {
                    sum += adjacency_weight(i) * smooth_src[n];
                    wsum += adjacency_weight(i);
                }
            }
            if (wsum > 0.0)
                v = seen_self ? v + u_omega * (sum / wsum - v) : sum / wsum;
        } else if (seen > 0u)
            v = seen_self ? v + u_omega * (sum / float(seen) - v) : sum / float(seen);
        smooth_dst[e] = v;
    }
}

// Stages 2 and 3, fading toward the smoothed targets or, without smoothing
// iterations, toward the targets themselves (one pass fewer over the
// elements, the same values). Each invocation fades u_fade_batch elements, a
// dispatch's width apart, and adds its largest change and gap to the maxima
// once: an atomic per element, on two words every thread shares, cost a
// million points 40 ms of their 80 (llvmpipe runs each as a loop over the
// vector's lanes); on tens of thousands of elements the batches' fewer work
// groups cost more than the atomics (fourier.c picks). The maxima are the
// same in any order.
uniform uint u_fade_batch;
void fade(uint invocation)
{
    uint stride = (u_count + u_fade_batch - 1u) / u_fade_batch;
    float change = 0.0, gap = 0.0;
    for (uint k = 0u; k < u_fade_batch; k++) {
        uint local = invocation + k * stride;
        if (invocation >= stride || local >= u_count)
            break;
        uint e = u_element_offset + local;
        float cur = element_alpha[e];
        float goal = u_stage == 3 ? target(e) : smooth_src[e];
        float next = cur + (goal - cur) * u_fade;
        element_alpha[e] = next;
        change = max(change, abs(next - cur));
        // What fading still has to cover: the next frame's targets are this
        // frame's unless the view or the parameters change.
        gap = max(gap, abs(goal - next));
    }
    if (change > 0.0)
        atomicMax(max_change_bits, floatBitsToUint(change));
    if (gap > 0.0)
        atomicMax(max_gap_bits, floatBitsToUint(gap));
}
