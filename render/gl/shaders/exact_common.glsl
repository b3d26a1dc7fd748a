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
#define COUNTER_MAX_LAYERS 6   // + p: longest list
#define COUNTER_COVERED 8      // + p: pixels with at least one fragment
#define COUNTER_REDUCED 10     // + p: fragments left out below 1/255 opacity (pass 1 only)
#define COUNTER_LIMITED 12     // + p: invocations the driver's loop limit stopped (check_limit)

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
// One chunk of a pixel's list in local memory as two arrays (Met.3D thesis
// §2.4.3): the depths that the sorts compare and the node indices that they
// only move. A list longer than EXACT_MAX_LAYERS is taken in chunks, nearest
// first (gather_chunk), so every fragment is sorted and counted exactly.
float list_z[EXACT_MAX_LAYERS];
uint list_node[EXACT_MAX_LAYERS];

uniform int u_sort_mode;     // see sort_chunk
uniform int u_insertion_max; // auto: insertion sort up to this length
// The chunk this dispatch takes of each pixel's list: 0 the nearest
// EXACT_MAX_LAYERS, then each round the next ones (exact.c dispatches as many
// rounds as the longest list needs; a pixel's state image carries its sums and
// where its next chunk starts). One chunk an invocation keeps every loop short:
// Mesa's llvmpipe ends every loop of an invocation once its loops together
// have run 65535 iterations (gallivm's loop limiter, shared by the lanes of a
// SIMD group), which a whole long list would pass, leaving it half sorted.
uniform int u_round;
// The first row of a sort pass's dispatch: where the pool could not hold a
// list pass's whole frame, it is built and sorted in bands of rows (exact.c).
uniform int u_first_row;

// Whether the driver's loop limit is still intact at the end of a pass: once
// spent, every loop stops after one iteration, so a two-iteration loop (its
// bound a uniform, which no compiler unrolls) tells. Counted, never silent.
uniform int u_two;
void check_limit()
{
    int k = 0;
    for (int j = 0; j < u_two; j++)
        k++;
    if (k != u_two)
        atomicAdd(counters[COUNTER_LIMITED + u_list_pass], 1u);
}

float list_depth(int k) { return list_z[k]; }

#ifdef EXACT_SUM_IMPORTANCE
// Sum of g^2 over the whole list (taken by the first chunk's gather).
float list_importance;
#endif

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
// sort, and the gather's nearest-n selection) or, with min_heap, a min-heap
// (the nearest on top: the front-to-back queue) of n entries, each node with
// `arity` children: 2 (the binary heap, kept as a measurement mode) or 4, half
// as deep, fewer moves for more comparisons a level, which the Met.3D thesis
// measured fastest (§2.4.3, Table 2.8).
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

void heap_build(int n, int arity, bool min_heap)
{
    for (int i = (n - 2) / arity; i >= 0; i--)
        heap_sink(i, n, arity, min_heap);
}

// The second half of a heap sort (Met.3D thesis A.2.4): from a max-heap of n
// entries to front-to-back order, in place, no recursion.
void heap_unwind(int n, int arity)
{
    for (int end = n - 1; end > 0; end--) {
        swap_entries(0, end);
        heap_sink(0, end, arity, false);
    }
}

// Whether the list was left as a max-heap by its gather (longer than a chunk).
bool chunk_heaped;

// Gathers the next chunk of pixel p's list: the nearest EXACT_MAX_LAYERS
// fragments strictly after (after_z, after_node) in the front-to-back order, or
// from the front when first. Past a full chunk the kept ones form a max-heap
// (the farthest on top), so that each further fragment costs a comparison and,
// when nearer, one sift-down. list_length is the whole list's length, beyond
// the number of fragments after the bound (the chunk holds min(beyond, cap)).
int gather_chunk(ivec2 p, bool first, float after_z, uint after_node, out uint list_length, out uint beyond)
{
    uint i = imageLoad(u_heads, p).r;
    int n = 0;
    list_length = 0u;
    beyond = 0u;
    chunk_heaped = false;
#ifdef EXACT_SUM_IMPORTANCE
    if (first)
        list_importance = 0.0;
#endif
    // A list can never be longer than the pool: guards a corrupt pointer.
    while (i != EXACT_END && i < u_pool_capacity && list_length < u_pool_capacity) {
        uvec4 node = nodes[i];
        float z = uintBitsToFloat(node.y);
#ifdef EXACT_SUM_IMPORTANCE
        if (first) {
            float g = uintBitsToFloat(node.z);
            list_importance += g * g;
        }
#endif
        if (first || before(after_z, after_node, z, i)) {
            beyond++;
            if (n < EXACT_MAX_LAYERS) {
                list_z[n] = z;
                list_node[n] = i;
                n++;
            } else {
                if (!chunk_heaped) {
                    heap_build(n, 4, false);
                    chunk_heaped = true;
                }
                if (before(z, i, list_z[0], list_node[0])) {
                    list_z[0] = z;
                    list_node[0] = i;
                    heap_sink(0, n, 4, false);
                }
            }
        }
        list_length++;
        i = node.x;
    }
    return n;
}

// Counts a pixel's list once (longest list, covered pixels).
void count_list(uint list_length)
{
    if (list_length > 0u) {
        atomicMax(counters[COUNTER_MAX_LAYERS + u_list_pass], list_length);
        atomicAdd(counters[COUNTER_COVERED + u_list_pass], 1u);
    }
}

// Sorts the gathered chunk front to back. Sort modes (u_sort_mode, exact.c):
// 0 auto (insertion sort up to u_insertion_max, 4-ary heap sort above), 1
// insertion only, 2 binary heap only, 3 4-ary heap only, 4 auto with the
// binary heap. A chunk its gather left as a 4-ary max-heap only unwinds.
void sort_chunk(int n)
{
    int mode = u_sort_mode;
    if (chunk_heaped) {
        heap_unwind(n, 4);
        return;
    }
    if (mode == 1 || ((mode == 0 || mode == 4) && n <= u_insertion_max)) {
        insertion_sort(n);
        return;
    }
    int arity = mode == 2 || mode == 4 ? 2 : 4;
    heap_build(n, arity, false);
    heap_unwind(n, arity);
}

// The front-to-back queue (Met.3D thesis §2.4.4): a 4-ary min-heap over the
// chunk from which the blend pops the nearest fragment until the pixel
// saturates, so a pixel that turns opaque early never sorts its far part.
void queue_build(int n) { heap_build(n, 4, true); }

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
