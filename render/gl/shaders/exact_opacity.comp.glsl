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
// params.excludeSelf (OOS §4.3, h_ii = 0): a fragment's sums leave out the
// fragments of its own element, so that a line or patch folding over itself
// does not fade for hiding itself.
uniform int u_exclude_self;

float optimal_alpha(uint element, float g, float front, float behind, float k, float lambda)
{
    float ge = emphasis_importance(element, g); // as in P2
    float emphasis = lambda > 0.0 ? pow(max(1.0 - ge, 0.0), 2.0 * lambda) : 1.0;
    float alpha = 1.0 / (1.0 + k * emphasis * (u_r * front + u_q * behind)); // FOO Eq. 10
    return alpha * u_target_opacity;
}

// Whether node i (at depth z) is one of the n kept nearest fragments: all
// nearer than the farthest kept one are, and a tie at the cap is looked up.
bool is_kept(uint i, float z, int n, float kept_far)
{
    bool kept = z < kept_far;
    if (z == kept_far)
        for (int j = 0; j < n && !kept; j++)
            kept = list_node[j] == i;
    return kept;
}

// excludeSelf: the mass of g^2 of element's fragments past the layer cap of
// pixel p (all behind the kept ones).
float far_mass_of(ivec2 p, uint element, int n, float kept_far)
{
    float mass = 0.0;
    uint i = imageLoad(u_heads, p).r;
    for (uint visited = 0u; i != EXACT_END && i < u_pool_capacity && visited < u_pool_capacity; visited++) {
        uvec4 node = nodes[i];
        if (node.w == element && !is_kept(i, uintBitsToFloat(node.y), n, kept_far)) {
            float g = uintBitsToFloat(node.z);
            mass += g * g;
        }
        i = node.x;
    }
    return mass;
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
        if (!is_kept(i, z, n, kept_far)) {
            float g = uintBitsToFloat(node.z);
            // excludeSelf: the own element's mass in front and behind leaves both sums.
            float front = 0.0, self_front = 0.0, self_behind = 0.0;
            uint o = head;
            for (uint seen = 0u; o != EXACT_END && o < u_pool_capacity && seen < u_pool_capacity; seen++) {
                uvec4 other = nodes[o];
                float zo = uintBitsToFloat(other.y);
                float go = uintBitsToFloat(other.z);
                bool in_front = zo < z || (zo == z && seen < visited);
                if (o == i) {
                } else if (u_exclude_self != 0 && other.w == node.w) {
                    if (in_front)
                        self_front += go * go;
                    else
                        self_behind += go * go;
                } else if (in_front) {
                    front += go * go;
                }
                o = other.x;
            }
            float behind = max(total - front - self_front - g * g - self_behind, 0.0);
            atomicMin(element_alpha_min[node.w], floatBitsToUint(optimal_alpha(node.w, g, front, behind, k, lambda)));
            add_behind(node.w, behind);
            count_important(g, front);
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
    int n = gather_list(p, list_length, true);
    if (n == 0)
        return;
    mass_count(list_importance); // the same normalization as the Fourier path
    sort_list(p, n);
    // Kept fragments are the nearest ones, so their front sums are exact;
    // far_fragments handles the rest.
    float total = list_importance;
    float k = u_norm_mass > 0.0 && total > u_norm_mass ? u_norm_mass / total : 1.0;
    float lambda = u_norm_mass > 0.0 ? (1.0 + 3.0 * (1.0 - k) * (1.0 - k)) * u_lambda : u_lambda; // as in P2 (foo_math.h)
    float front = 0.0;
    bool overflow = list_length > uint(n);
    float kept_far = list_depth(n - 1);
    for (int i = 0; i < n; i++) {
        uvec4 node = nodes[list_node[i]];
        float g = uintBitsToFloat(node.z);
        float own = g * g;
        float f = front, behind = max(total - front - own, 0.0);
        if (u_exclude_self != 0) { // O(n) more per fragment, only with the option
            float self_front = 0.0, self_behind = overflow ? far_mass_of(p, node.w, n, kept_far) : 0.0;
            for (int j = 0; j < n; j++) {
                if (j == i || nodes[list_node[j]].w != node.w)
                    continue;
                float gj = uintBitsToFloat(nodes[list_node[j]].z);
                if (j < i)
                    self_front += gj * gj;
                else
                    self_behind += gj * gj;
            }
            f = max(front - self_front, 0.0);
            behind = max(behind - self_behind, 0.0);
        }
        float alpha = optimal_alpha(node.w, g, f, behind, k, lambda);
        // Non-negative floats order like their bit patterns.
        atomicMin(element_alpha_min[node.w], floatBitsToUint(alpha));
        add_behind(node.w, behind);
        count_important(g, f);
        front += own;
    }
    if (overflow)
        far_fragments(p, n, total, k, lambda);
}
