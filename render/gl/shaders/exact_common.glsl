// Exact reference (DOO) shared declarations: the per-pixel fragment linked
// lists (head-pointer image, node pool, counters) and the gather + sort of one
// pixel's list. Indices here must match the COUNTER_* enum in exact.c.

#define EXACT_END 0xFFFFFFFFu
#ifndef EXACT_MAX_LAYERS
#define EXACT_MAX_LAYERS 256
#endif

// Counters: per list pass p (0 = optimization resolution, 1 = full resolution).
#define COUNTER_NODES 0        // + p: fragments offered to the pool (stored or not)
#define COUNTER_DROP_POOL 2    // + p: fragments that found the pool full
#define COUNTER_DROP_LAYERS 4  // + p: fragments beyond EXACT_MAX_LAYERS of their pixel
#define COUNTER_MAX_LAYERS 6   // + p: longest list
#define COUNTER_COVERED 8      // + p: pixels with at least one fragment

// Node: (next, view depth bits, payload a, payload b).
//   pass 0: a = importance g bits, b = element
//   pass 1: a = packUnorm2x16(r, g), b = packUnorm2x16(b, alpha)
//   pass 1 with EXACT_EQUALIZE: a = r | g << 10 | b << 20 (10 bits each),
//           b = unorm16 alpha | colour bin << 16 (EXACT_NO_BIN: a halo)
#define EXACT_NO_BIN 256u
layout(std430, binding = BIND_EXACT_NODES) coherent buffer ExactNodes { uvec4 nodes[]; };
layout(std430, binding = BIND_EXACT_COUNTERS) coherent buffer ExactCounters { uint counters[16]; };
layout(r32ui, binding = IMG_EXACT_HEADS) coherent uniform uimage2D u_heads;

uniform uint u_pool_capacity; // nodes
uniform int u_list_pass;      // 0 or 1, as above

#ifndef EXACT_BUILD
// One pixel's list in local memory: (depth bits, node index) pairs.
uvec2 list[EXACT_MAX_LAYERS];

uniform int u_sort_mode;     // 0 auto, 1 insertion only, 2 heap only
uniform int u_insertion_max; // auto: insertion sort up to this length

float list_depth(int k) { return uintBitsToFloat(list[k].x); }

#ifdef EXACT_SUM_IMPORTANCE
// Sum of g^2 over the whole list, dropped fragments included, so that the
// "behind" sums of the kept (nearest) fragments stay exact past the cap.
float list_importance;
#endif

// Loads the list of pixel p. Beyond EXACT_MAX_LAYERS the nearest fragments are
// kept (the far ones matter least front to back); compositing counts the rest
// as dropped, the opacity pass handles them one by one (far_fragments).
// Returns the number kept; list_length is the full length.
int gather_list(ivec2 p, out uint list_length)
{
    uint i = imageLoad(u_heads, p).r;
    int n = 0;
    list_length = 0u;
#ifdef EXACT_SUM_IMPORTANCE
    list_importance = 0.0;
#endif
    // A list can never be longer than the pool: guards a corrupt pointer.
    while (i != EXACT_END && i < u_pool_capacity && list_length < u_pool_capacity) {
        uvec4 node = nodes[i];
        float z = uintBitsToFloat(node.y);
#ifdef EXACT_SUM_IMPORTANCE
        float g = uintBitsToFloat(node.z);
        list_importance += g * g;
#endif
        if (n < EXACT_MAX_LAYERS) {
            list[n] = uvec2(node.y, i);
            n++;
        } else {
            int far = 0;
            for (int k = 1; k < EXACT_MAX_LAYERS; k++)
                if (list_depth(k) > list_depth(far))
                    far = k;
            if (z < list_depth(far))
                list[far] = uvec2(node.y, i);
        }
        list_length++;
        i = node.x;
    }
#ifndef EXACT_SUM_IMPORTANCE // the opacity pass handles the fragments past the cap (far_fragments)
    if (list_length > uint(EXACT_MAX_LAYERS))
        atomicAdd(counters[COUNTER_DROP_LAYERS + u_list_pass], list_length - uint(EXACT_MAX_LAYERS));
#endif
    if (list_length > 0u) {
        atomicMax(counters[COUNTER_MAX_LAYERS + u_list_pass], list_length);
        atomicAdd(counters[COUNTER_COVERED + u_list_pass], 1u);
    }
    return n;
}

void insertion_sort(int n)
{
    for (int i = 1; i < n; i++) {
        uvec2 e = list[i];
        float z = uintBitsToFloat(e.x);
        int j = i;
        while (j > 0) {
            uvec2 prev = list[j - 1];
            if (uintBitsToFloat(prev.x) <= z)
                break;
            list[j] = prev;
            j--;
        }
        list[j] = e;
    }
}

// Sift-down in a max-heap of n entries rooted at x.
void heap_sink(int x, int n)
{
    uvec2 e = list[x];
    float z = uintBitsToFloat(e.x);
    int c;
    while ((c = 2 * x + 1) < n) {
        if (c + 1 < n && list_depth(c) < list_depth(c + 1))
            c++;
        if (z >= list_depth(c))
            break;
        list[x] = list[c];
        x = c;
    }
    list[x] = e;
}

// O(n log n) in place, no recursion (Met.3D thesis A.2.4).
void heap_sort(int n)
{
    for (int i = n / 2 - 1; i >= 0; i--)
        heap_sink(i, n);
    for (int end = n - 1; end > 0; end--) {
        uvec2 e = list[0];
        list[0] = list[end];
        list[end] = e;
        heap_sink(0, end);
    }
}

// Front to back by view depth.
void sort_list(int n)
{
    if (u_sort_mode == 1 || (u_sort_mode == 0 && n <= u_insertion_max))
        insertion_sort(n);
    else
        heap_sort(n);
}
#endif
