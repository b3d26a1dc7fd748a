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
#define COUNTER_REDUCED 10     // + p: fragments left out below 1/255 opacity (pass 1 only)
#define COUNTER_SORT_REPAIRS 12 // + p: lists the heap left out of order (heap_sort)

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
// One pixel's list in local memory as two arrays (Met.3D thesis §2.4.3): the
// depths that the sorts compare and the node indices that they only move.
float list_z[EXACT_MAX_LAYERS];
uint list_node[EXACT_MAX_LAYERS];

uniform int u_sort_mode;     // see sort_list
uniform int u_insertion_max; // auto: insertion sort up to this length

float list_depth(int k) { return list_z[k]; }

#ifdef EXACT_SUM_IMPORTANCE
// Sum of g^2 over the whole list, dropped fragments included, so that the
// "behind" sums of the kept (nearest) fragments stay exact past the cap.
float list_importance;
#endif

// Loads the list of pixel p (count: into the list counters). Beyond EXACT_MAX_LAYERS the nearest fragments are
// kept (the far ones matter least front to back); compositing counts the rest
// as dropped, the opacity pass handles them one by one (far_fragments).
// Returns the number kept; list_length is the full length.
int gather_list(ivec2 p, out uint list_length, bool count)
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
            list_z[n] = z;
            list_node[n] = i;
            n++;
        } else {
            int far = 0;
            for (int k = 1; k < EXACT_MAX_LAYERS; k++)
                if (list_z[k] > list_z[far])
                    far = k;
            if (z < list_z[far]) {
                list_z[far] = z;
                list_node[far] = i;
            }
        }
        list_length++;
        i = node.x;
    }
    if (!count) // a second gather of the same pixel (exact_blend.comp.glsl)
        return n;
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

// The front-to-back order: by view depth, ties by node index (the later node
// first, as the list holds them), so that every sort below agrees on one
// order and the images are the same bits whatever the algorithm.
bool before(float za, uint ia, float zb, uint ib) { return za < zb || (za == zb && ia > ib); }
bool before_at(int a, int b) { return before(list_z[a], list_node[a], list_z[b], list_node[b]); }

void swap_entries(int a, int b)
{
    float z = list_z[a];
    uint i = list_node[a];
    list_z[a] = list_z[b];
    list_node[a] = list_node[b];
    list_z[b] = z;
    list_node[b] = i;
}

void insertion_sort(int n)
{
    for (int i = 1; i < n; i++) {
        float z = list_z[i];
        uint node = list_node[i];
        int j = i;
        while (j > 0 && before(z, node, list_z[j - 1], list_node[j - 1])) {
            list_z[j] = list_z[j - 1];
            list_node[j] = list_node[j - 1];
            j--;
        }
        list_z[j] = z;
        list_node[j] = node;
    }
}

// Sift-down of entry x in a max-heap (the last in order on top: the in-place
// sort) or, with min_heap, a min-heap (the nearest on top: the front-to-back
// queue) of n entries, each node with `arity` children: 2 (the sort before
// the 4-ary heap, kept as a measurement mode) or 4, half as deep, fewer moves
// for more comparisons a level, which the Met.3D thesis measured fastest
// (§2.4.3, Table 2.8).
void heap_sink(int x, int n, int arity, bool min_heap)
{
    float z = list_z[x];
    uint node = list_node[x];
    for (int first = arity * x + 1; first < n; first = arity * x + 1) {
        int c = first;
        int last = min(first + arity, n);
        for (int k = first + 1; k < last; k++)
            if (min_heap ? before_at(k, c) : before_at(c, k))
                c = k;
        bool stays = min_heap ? !before(list_z[c], list_node[c], z, node) : !before(z, node, list_z[c], list_node[c]);
        if (stays)
            break;
        list_z[x] = list_z[c];
        list_node[x] = list_node[c];
        x = c;
    }
    list_z[x] = z;
    list_node[x] = node;
}

// Whether the first n entries are in front-to-back order.
bool is_sorted(int n)
{
    for (int i = 0; i + 1 < n; i++)
        if (!before_at(i, i + 1))
            return false;
    return true;
}

// A checksum of the first n entries' node indices (two wrapping sums), to
// tell whether the heap kept the entries it was given (sort_list).
uvec2 list_checksum(int n)
{
    uvec2 c = uvec2(0u);
    for (int k = 0; k < n; k++) {
        uint v = list_node[k];
        c += uvec2(v, v * 2654435761u + (v >> 7));
    }
    return c;
}

// O(n log n) in place, no recursion (Met.3D thesis A.2.4).
void heap_sort(int n, int arity)
{
    for (int i = (n - 2) / arity; i >= 0; i--)
        heap_sink(i, n, arity, false);
    for (int end = n - 1; end > 0; end--) {
        swap_entries(0, end);
        heap_sink(0, end, arity, false);
    }
}

// Sort modes (u_sort_mode, exact.c): 0 auto (insertion sort up to
// u_insertion_max, 4-ary heap sort above), 1 insertion only, 2 binary heap
// only, 3 4-ary heap only, 4 auto with the binary heap (the sort before the
// 4-ary heap). The heap's result is checked in O(n), order and checksum, and
// a list that fails is gathered again from pixel p and insertion-sorted
// (counted): on Mesa 22 llvmpipe an invocation runs 65,535 loop iterations in
// all, and a pixel past the layer cap spends them in gather_list, so its later
// loops stop after one iteration (docs/ALGORITHM.md §12, tests/bench/loop_budget).
void sort_list(ivec2 p, int n)
{
    int mode = u_sort_mode;
    if (mode == 1 || ((mode == 0 || mode == 4) && n <= u_insertion_max)) {
        insertion_sort(n);
        return;
    }
    uvec2 sum = list_checksum(n);
    heap_sort(n, mode == 2 || mode == 4 ? 2 : 4);
    if (!is_sorted(n) || list_checksum(n) != sum) {
        atomicAdd(counters[COUNTER_SORT_REPAIRS + u_list_pass], 1u);
        uint list_length;
        n = gather_list(p, list_length, false);
        insertion_sort(n);
    }
}

// The front-to-back queue (Met.3D thesis §2.4.4): a 4-ary min-heap over the
// list from which the blend pops the nearest fragment until the pixel
// saturates, so a pixel that turns opaque early never sorts its far part.
void queue_build(int n)
{
    for (int i = (n - 2) / 4; i >= 0; i--)
        heap_sink(i, n, 4, true);
}

// Removes the nearest of the n entries (n > 0) and returns its node.
uint queue_pop(int n)
{
    uint node = list_node[0];
    list_z[0] = list_z[n - 1];
    list_node[0] = list_node[n - 1];
    heap_sink(0, n - 1, 4, true);
    return node;
}
#endif
