// Exact reference, optimal opacity (DOO): per pixel of the optimization
// resolution, sort the list and evaluate FOO Eq. 10 with the exact sums of
// g^2 strictly in front of (r) and strictly behind (q) each fragment, then
// atomic-min into the fragment's element as P2 does, with P2's density
// normalization. Each pixel's total also goes into the mass histogram.
layout(local_size_x = 8, local_size_y = 8) in;

layout(std430, binding = BIND_ELEMENT_ALPHA_MIN) buffer ElementAlphaMin { uint element_alpha_min[]; };

uniform ivec2 u_size; // the width and the last row (exclusive) of this dispatch (u_first_row)
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

// params.excludeSelf: for each entry i of the chunk (depth order), the g^2 of
// its own element's other fragments in front of it (ex_front) and behind it
// (ex_behind), over the whole list. The chunk's entries sorted by (element,
// depth index) put each element's fragments in one run; a scan of the list
// adds the fragments outside the chunk to their run by binary search.
uint ex_elem[EXACT_MAX_LAYERS];
int ex_idx[EXACT_MAX_LAYERS];
float ex_prev[EXACT_MAX_LAYERS]; // per run head: the element's g^2 in front of the chunk
float ex_next[EXACT_MAX_LAYERS]; // per run head: ... behind the chunk
float ex_front[EXACT_MAX_LAYERS];
float ex_behind[EXACT_MAX_LAYERS];

bool ex_before(int a, int b) { return ex_elem[a] < ex_elem[b] || (ex_elem[a] == ex_elem[b] && ex_idx[a] < ex_idx[b]); }

void ex_sink(int x, int n)
{
    for (int first = 4 * x + 1; first < n; first = 4 * x + 1) {
        int c = first;
        int last = min(first + 4, n);
        for (int k = first + 1; k < last; k++)
            if (ex_before(c, k))
                c = k;
        if (!ex_before(x, c))
            break;
        uint e = ex_elem[x];
        int i = ex_idx[x];
        ex_elem[x] = ex_elem[c];
        ex_idx[x] = ex_idx[c];
        ex_elem[c] = e;
        ex_idx[c] = i;
        x = c;
    }
}

// The first sorted position holding element e among n, or -1.
int ex_find(uint e, int n)
{
    int lo = 0, hi = n;
    while (lo < hi) {
        int mid = (lo + hi) / 2;
        if (ex_elem[mid] < e)
            lo = mid + 1;
        else
            hi = mid;
    }
    return lo < n && ex_elem[lo] == e ? lo : -1;
}

// Fills ex_front and ex_behind for the n sorted entries of the chunk of pixel
// p; first: the chunk starts the list, else it follows (after_z, after_node).
void self_sums(ivec2 p, int n, bool first, float after_z, uint after_node, bool whole)
{
    for (int i = 0; i < n; i++) {
        ex_elem[i] = nodes[list_node[i]].w;
        ex_idx[i] = i;
        ex_prev[i] = 0.0;
        ex_next[i] = 0.0;
    }
    for (int i = (n - 2) / 4; i >= 0; i--)
        ex_sink(i, n);
    for (int end = n - 1; end > 0; end--) {
        uint e = ex_elem[0];
        int i = ex_idx[0];
        ex_elem[0] = ex_elem[end];
        ex_idx[0] = ex_idx[end];
        ex_elem[end] = e;
        ex_idx[end] = i;
        ex_sink(0, end);
    }
    if (!whole) { // fragments outside the chunk: in front of it or behind it
        float last_z = list_z[n - 1];
        uint last_node = list_node[n - 1];
        uint i = imageLoad(u_heads, p).r;
        for (uint seen = 0u; i != EXACT_END && i < u_pool_capacity && seen < u_pool_capacity; seen++) {
                uvec4 node = nodes[i];
            float z = uintBitsToFloat(node.y);
            bool in_front = !first && !before(after_z, after_node, z, i);
            bool behind = before(last_z, last_node, z, i);
            if (in_front || behind) {
                int r = ex_find(node.w, n);
                if (r >= 0) {
                    float g = uintBitsToFloat(node.z);
                    if (in_front)
                        ex_prev[r] += g * g;
                    else
                        ex_next[r] += g * g;
                }
            }
            i = node.x;
        }
    }
    for (int head = 0; head < n;) {
        int end = head;
        float run = 0.0;
        for (; end < n && ex_elem[end] == ex_elem[head]; end++) {
                float g = uintBitsToFloat(nodes[list_node[ex_idx[end]]].z);
            run += g * g;
        }
        float before_run = ex_prev[head], sum = 0.0;
        for (int j = head; j < end; j++) {
                float g = uintBitsToFloat(nodes[list_node[ex_idx[j]]].z);
            ex_front[ex_idx[j]] = before_run + sum;
            ex_behind[ex_idx[j]] = ex_next[head] + max(run - sum - g * g, 0.0);
            sum += g * g;
        }
        head = end;
    }
}

// A pixel's sums between rounds: g^2 in front of the next chunk, the chunk's
// bound (the last fragment taken: depth bits and node; EXACT_END: the list is
// done) and the whole list's g^2.
layout(rgba32ui, binding = IMG_EXACT_STATE) uniform uimage2D u_state;

void main()
{
    ivec2 p = ivec2(gl_GlobalInvocationID.xy) + ivec2(0, u_first_row);
    if (p.x >= u_size.x || p.y >= u_size.y)
        return;
    bool first = u_round == 0;
    float front = 0.0, total = 0.0, after_z = 0.0;
    uint after_node = 0u;
    if (!first) {
        uvec4 s = imageLoad(u_state, p);
        if (s.z == EXACT_END)
            return;
        front = uintBitsToFloat(s.x);
        after_z = uintBitsToFloat(s.y);
        after_node = s.z;
        total = uintBitsToFloat(s.w);
    }
    uint list_length, beyond;
    int n = gather_chunk(p, first, after_z, after_node, list_length, beyond);
    if (first) {
        if (n == 0) {
            imageStore(u_state, p, uvec4(0u, 0u, EXACT_END, 0u));
            return;
        }
        count_list(list_length);
        mass_count(list_importance); // the same normalization as the Fourier path
        total = list_importance;
    }
    float k = u_norm_mass > 0.0 && total > u_norm_mass ? u_norm_mass / total : 1.0;
    float lambda = u_norm_mass > 0.0 ? (1.0 + 3.0 * (1.0 - k) * (1.0 - k)) * u_lambda : u_lambda; // as in P2 (foo_math.h)
    sort_chunk(n);
    if (u_exclude_self != 0)
        self_sums(p, n, first, after_z, after_node, list_length == uint(n));
    // front holds the g^2 of every fragment before this one, over the whole
    // list, so each fragment's sums are the exact ones.
    for (int i = 0; i < n; i++) {
        uvec4 node = nodes[list_node[i]];
        float g = uintBitsToFloat(node.z);
        float own = g * g;
        float f = front, behind = max(total - front - own, 0.0);
        if (u_exclude_self != 0) { // O(list length) more a chunk, only with the option
            f = max(front - ex_front[i], 0.0);
            behind = max(behind - ex_behind[i], 0.0);
        }
        float alpha = optimal_alpha(node.w, g, f, behind, k, lambda);
        // Non-negative floats order like their bit patterns.
        atomicMin(element_alpha_min[node.w], floatBitsToUint(alpha));
        add_behind(node.w, behind);
        count_important(g, f);
        front += own;
    }
    uint next = beyond > uint(n) ? list_node[n - 1] : EXACT_END;
    imageStore(u_state, p, uvec4(floatBitsToUint(front), floatBitsToUint(list_z[n - 1]), next, floatBitsToUint(total)));
    check_limit();
}
