// Exact reference, compositing: per output pixel, sort the list and blend
// front to back over the background, C = sum C_i a_i prod_{j<i}(1 - a_j) + T C_bg.
// A compute pass rather than a full-screen fragment pass: see exact.c.
// With EXACT_EQUALIZE it also measures the visibility-weighted colour
// histogram (DLS Eq. 6) exactly: fragment i's share a_i prod_{j<i}(1 - a_j) is
// taken in fixed point as the difference of the pixel's rounded coverage
// 1 - T after and before it, so the shares of a pixel add up to its rounded
// 1 - T without any rounding of their own (exact.c).
layout(local_size_x = 8, local_size_y = 8) in;

layout(rgba8, binding = IMG_EXACT_OUTPUT) writeonly uniform image2D u_output;
uniform ivec2 u_size; // the frame's width and the last row (exclusive) of this dispatch (u_first_row)
uniform vec3 u_background;
uniform int u_queue;         // 1: pop from the front-to-back queue instead of sorting the whole list
uniform float u_saturation;  // stop once the transmittance is below this (exact.c)
uniform int u_context; // layers: the opaque context's colour replaces the background (p6_resolve.frag.glsl)
layout(binding = TEX_CONTEXT_COLOR) uniform sampler2D u_context_color;

#ifdef EXACT_EQUALIZE
// 64-bit counters as (low, high) words: bins 0-255, EXACT_NO_BIN (halos), then
// the pixels' total coverage; u_eq_scale units per unit of coverage.
layout(std430, binding = BIND_COLOR_HISTOGRAM) buffer ColorHistogram { uint color_histogram[]; };
uniform float u_eq_scale;

void add_units(uint slot, uint units)
{
    if (units == 0u)
        return;
    uint old = atomicAdd(color_histogram[2u * slot], units);
    if (old + units < old) // the low word wrapped: carry (each wrap is seen by exactly one adder)
        atomicAdd(color_histogram[2u * slot + 1u], 1u);
}

uint coverage_units(float transmittance) { return uint((1.0 - transmittance) * u_eq_scale + 0.5); }
#endif

#ifdef EXACT_EQUALIZE
uint covered = 0u; // coverage_units(transmittance) so far, over the pixel's chunks
#endif

// Blends the n entries of a chunk front to back into color and transmittance,
// popped from the queue or in the sorted order, until the pixel saturates
// (returns true then). last_z/last_node: the last entry blended, the bound of
// the next chunk.
bool blend_chunk(int n, bool queue, inout vec3 color, inout float transmittance, out float last_z, out uint last_node)
{
    last_z = 0.0;
    last_node = 0u;
    for (int i = 0; i < n; i++) {
        if (queue) {
            last_z = list_z[0];
            last_node = list_node[0];
            queue_pop(n - i);
        } else {
            last_z = list_z[i];
            last_node = list_node[i];
        }
        uvec4 node = nodes[last_node];
#ifdef EXACT_EQUALIZE
        vec3 c = vec3(uvec3(node.z, node.z >> 10, node.z >> 20) & 1023u) / 1023.0;
        float a = unpackUnorm2x16(node.w & 0xFFFFu).x;
#else
        vec2 rg = unpackUnorm2x16(node.z);
        vec2 ba = unpackUnorm2x16(node.w);
        vec3 c = vec3(rg, ba.x);
        float a = ba.y;
#endif
        color += c * (a * transmittance);
        transmittance *= 1.0 - a;
#ifdef EXACT_EQUALIZE
        uint now = coverage_units(transmittance);
        add_units(node.w >> 16, now - covered);
        covered = now;
#endif
        // What remains changes no channel by u_saturation or more: every
        // colour and the background are within [0, 1].
        if (transmittance < u_saturation)
            return true;
    }
    return false;
}

// A pixel's composite between rounds: colour and transmittance (float bits),
// and its bound (the last fragment blended: depth bits and node; EXACT_END:
// the pixel is done).
layout(rgba32ui, binding = IMG_EXACT_STATE) uniform uimage2D u_state;
layout(rg32ui, binding = IMG_EXACT_BOUND) uniform uimage2D u_bound;

void main()
{
    ivec2 p = ivec2(gl_GlobalInvocationID.xy) + ivec2(0, u_first_row);
    if (p.x >= u_size.x || p.y >= u_size.y)
        return;
    bool first = u_round == 0;
    vec3 color = vec3(0.0);
    float transmittance = 1.0, after_z = 0.0;
    uint after_node = 0u;
    if (!first) {
        uvec2 b = imageLoad(u_bound, p).xy;
        if (b.y == EXACT_END)
            return;
        after_z = uintBitsToFloat(b.x);
        after_node = b.y;
        uvec4 s = imageLoad(u_state, p);
        color = uintBitsToFloat(s.xyz);
        transmittance = uintBitsToFloat(s.w);
    }
#ifdef EXACT_EQUALIZE
    covered = coverage_units(transmittance);
#endif
    uint list_length, beyond;
    int n = gather_chunk(p, first, after_z, after_node, list_length, beyond);
    if (first)
        count_list(list_length);
    bool more = false;
    float last_z = 0.0;
    uint last_node = 0u;
    if (n > 0) {
        // Long chunks go through the queue: the blend pops the nearest
        // fragment until the pixel saturates; short ones are insertion-sorted
        // (cheaper there). color.equalize sorts (its histogram takes each
        // share once).
        bool queue = u_queue != 0 && n > u_insertion_max;
#ifdef EXACT_EQUALIZE
        queue = false;
#endif
        if (queue)
            queue_build(n);
        else
            sort_chunk(n);
        more = !blend_chunk(n, queue, color, transmittance, last_z, last_node) && beyond > uint(n);
    }
#ifdef EXACT_EQUALIZE
    if (!more)
        add_units(EXACT_NO_BIN + 1u, covered);
#endif
    imageStore(u_state, p, uvec4(floatBitsToUint(color), floatBitsToUint(transmittance)));
    imageStore(u_bound, p, uvec2(floatBitsToUint(last_z), more ? last_node : EXACT_END).xyyy);
    vec3 bg = u_background;
    if (u_context != 0) {
        vec4 k = texelFetch(u_context_color, p, 0);
        bg = k.a > 0.0 ? k.rgb : bg;
    }
    imageStore(u_output, p, vec4(color + bg * transmittance, 1.0));
    check_limit();
}
