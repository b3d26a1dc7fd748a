// Exact reference, optimal opacity (DOO): per pixel of the optimization
// resolution, sort the list and evaluate FOO Eq. 10 with the exact sums of
// g^2 strictly in front of (r) and strictly behind (q) each fragment, then
// atomic-min into the fragment's element as P2 does, with P2's density
// normalization. Each pixel's total also goes into the mass histogram.
layout(local_size_x = 8, local_size_y = 8) in;

layout(std430, binding = BIND_ELEMENT_ALPHA_MIN) buffer ElementAlphaMin { uint element_alpha_min[]; };

uniform ivec2 u_size;
uniform float u_q;
uniform float u_r;
uniform float u_lambda;
uniform float u_norm_mass; // as in P2: reference mass of the density normalization, 0 = off
uniform float u_target_opacity; // as in P2: t of OOS Eq. 7

float optimal_alpha(uint element, float g, float front, float behind, float k, float lambda)
{
    float ge = emphasis_importance(element, g); // as in P2
    float emphasis = lambda > 0.0 ? pow(max(1.0 - ge, 0.0), 2.0 * lambda) : 1.0;
    float alpha = 1.0 / (1.0 + k * emphasis * (u_r * front + u_q * behind)); // FOO Eq. 10
    return alpha * u_target_opacity;
}

// The fragments past the layer cap (the farthest of a pixel with more than
// EXACT_MAX_LAYERS) get their opacity too, from sums over the whole list:
// O(length) each, but only in the few pixels that overflow. Ties in depth
// count in front when their node comes earlier in the list, as a stable
// order would put them.
void far_fragments(ivec2 p, int n, float total, float k, float lambda)
{
    float kept_far = list_depth(n - 1); // sorted: the farthest kept fragment
    uint head = imageLoad(u_heads, p).r;
    uint i = head;
    for (uint visited = 0u; i != EXACT_END && i < u_pool_capacity && visited < u_pool_capacity; visited++) {
        uvec4 node = nodes[i];
        uint next = node.x;
        float z = uintBitsToFloat(node.y);
        bool kept = z < kept_far;
        if (z == kept_far) // a tie at the cap: kept or not, the list says
            for (int j = 0; j < n && !kept; j++)
                kept = list[j].y == i;
        if (!kept) {
            float g = uintBitsToFloat(node.z);
            float front = 0.0;
            uint o = head;
            for (uint seen = 0u; o != EXACT_END && o < u_pool_capacity && seen < u_pool_capacity; seen++) {
                uvec4 other = nodes[o];
                float zo = uintBitsToFloat(other.y);
                if (o != i && (zo < z || (zo == z && seen < visited))) {
                    float go = uintBitsToFloat(other.z);
                    front += go * go;
                }
                o = other.x;
            }
            float behind = max(total - front - g * g, 0.0);
            atomicMin(element_alpha_min[node.w], floatBitsToUint(optimal_alpha(node.w, g, front, behind, k, lambda)));
            add_behind(node.w, behind);
        }
        i = next;
    }
}

void main()
{
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    if (p.x >= u_size.x || p.y >= u_size.y)
        return;
    uint list_length;
    int n = gather_list(p, list_length);
    if (n == 0)
        return;
    mass_count(list_importance); // the same normalization as the Fourier path
    sort_list(n);
    // Kept fragments are the nearest ones, so their front sums are exact;
    // far_fragments handles the rest.
    float total = list_importance;
    float k = u_norm_mass > 0.0 && total > u_norm_mass ? u_norm_mass / total : 1.0;
    float lambda = u_norm_mass > 0.0 ? (1.0 + 3.0 * (1.0 - k) * (1.0 - k)) * u_lambda : u_lambda; // as in P2 (foo_math.h)
    float front = 0.0;
    for (int i = 0; i < n; i++) {
        uvec4 node = nodes[list[i].y];
        float g = uintBitsToFloat(node.z);
        float own = g * g;
        float behind = max(total - front - own, 0.0);
        float alpha = optimal_alpha(node.w, g, front, behind, k, lambda);
        // Non-negative floats order like their bit patterns.
        atomicMin(element_alpha_min[node.w], floatBitsToUint(alpha));
        add_behind(node.w, behind);
        front += own;
    }
    if (list_length > uint(n))
        far_fragments(p, n, total, k, lambda);
}
