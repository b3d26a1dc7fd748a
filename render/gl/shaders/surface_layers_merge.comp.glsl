// Surface layers, merge (PRT Alg. 1 on a sorted array instead of a tree): per
// pixel, each fragment of this batch's list joins the layer nearest in view
// depth when closer than epsilon (running mean of colour, depth and normal,
// with a count), else it is inserted in depth order; with K layers already
// it is counted as overflow. The layers persist across batches.
// Joining a layer moves its mean, so the result depends on the order of the
// fragments: they are merged in drawing order (curve, then segment; the
// list's own order is the rasterizer's), so that curves added over several
// batches give the layers one batch of the same curves gives.
layout(local_size_x = 64) in;

layout(std430, binding = BIND_SURFACE_LAYERS) buffer SurfaceLayers { SurfaceLayer layers[]; };

uniform uint u_max_layers; // K
uniform float u_epsilon;

float layer_depth(uint k) { return layers[k].color_depth.w; }

#define MERGE_CHUNK 32u // fragments put in order per pass over a pixel's list

// Drawing order of fragments: (order, node index), lexicographic.
bool before(uint a, uint ai, uint b, uint bi) { return a < b || (a == b && ai < bi); }

void swap_layers(uint a, uint b)
{
    SurfaceLayer t = layers[a];
    layers[a] = layers[b];
    layers[b] = t;
}

// Merges fragment f into the pixel's n layers at base (PRT Alg. 1 on a sorted array).
void merge_fragment(SurfaceFragment f, uint base, inout uint n, inout uint merged, inout uint overflow)
{
    int best = -1;
    float best_d = u_epsilon;
    for (uint k = 0u; k < n; k++) {
        float d = abs(layer_depth(base + k) - f.depth);
        if (d < best_d) {
            best_d = d;
            best = int(k);
        }
    }
    vec3 rgb = unpackUnorm4x8(f.color).rgb;
    if (best >= 0) {
        uint b = base + uint(best);
        SurfaceLayer l = layers[b];
        float c = l.normal_count.w + 1.0;
        // The ghost normal's side is arbitrary: align it with the layer's before averaging.
        vec3 nf = dot(f.normal.xyz, l.normal_count.xyz) < 0.0 ? -f.normal.xyz : f.normal.xyz;
        l.color_depth += (vec4(rgb, f.depth) - l.color_depth) / c;
        l.normal_count.xyz += (nf - l.normal_count.xyz) / c;
        l.normal_count.w = c;
        layers[b] = l;
        merged++;
        // The mean moved by less than epsilon: one neighbour swap at most keeps the order.
        while (b > base && layer_depth(b - 1u) > layer_depth(b)) {
            swap_layers(b - 1u, b);
            b--;
        }
        while (b + 1u < base + n && layer_depth(b + 1u) < layer_depth(b)) {
            swap_layers(b, b + 1u);
            b++;
        }
    } else if (n < u_max_layers) {
        uint k = base + n;
        while (k > base && layer_depth(k - 1u) > f.depth) {
            layers[k] = layers[k - 1u];
            k--;
        }
        layers[k].color_depth = vec4(rgb, f.depth);
        layers[k].normal_count = vec4(f.normal.xyz, 1.0);
        n++;
    } else {
        overflow++;
    }
}

void main()
{
    uint pix = gl_GlobalInvocationID.x;
    if (pix >= u_pixel_count)
        return;
    uint head = pixels[heads_at(pix)];
    if (head == SURFACE_END)
        return;
    uint n = pixels[counts_at(pix)];
    uint base = pix * u_max_layers;
    uint merged = 0u, overflow = 0u;
    // Each pass takes the MERGE_CHUNK earliest fragments after the last one
    // merged (an insertion into a short sorted array) and merges them.
    uint last_o = 0u, last_i = 0u;
    bool first = true;
    for (;;) {
        uint ord[MERGE_CHUNK], idx[MERGE_CHUNK];
        uint c = 0u, later = 0u;
        uint i = head;
        // A list is never longer than the pool: guards a corrupt pointer.
        for (uint guard = 0u; i != SURFACE_END && i < u_pool_capacity && guard < u_pool_capacity; guard++) {
            uint at = i, o = frags[i].order;
            i = frags[i].next;
            if (!first && !before(last_o, last_i, o, at))
                continue; /* merged in an earlier pass */
            later++;
            if (c == MERGE_CHUNK && !before(o, at, ord[c - 1u], idx[c - 1u]))
                continue;
            uint k = c < MERGE_CHUNK ? c++ : c - 1u; /* full: the latest drops out */
            while (k > 0u && before(o, at, ord[k - 1u], idx[k - 1u])) {
                ord[k] = ord[k - 1u];
                idx[k] = idx[k - 1u];
                k--;
            }
            ord[k] = o;
            idx[k] = at;
        }
        for (uint j = 0u; j < c; j++)
            merge_fragment(frags[idx[j]], base, n, merged, overflow);
        if (later <= c)
            break;
        last_o = ord[c - 1u];
        last_i = idx[c - 1u];
        first = false;
    }
    pixels[counts_at(pix)] = n;
    if (merged > 0u)
        atomicAdd(pixels[SURFACE_COUNTER_MERGED], merged);
    if (overflow > 0u)
        atomicAdd(pixels[SURFACE_COUNTER_OVERFLOW], overflow);
}
