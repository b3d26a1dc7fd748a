/* The exact method's sorts replayed on the CPU (not a pass/fail test): heap_sink, heap_sort and
 * insertion_sort of render/gl/shaders/exact_common.glsl transcribed line for line, run on lists like a
 * pixel's (1..256 entries, depths on 1..64 levels so that ties abound, distinct node indices), and the
 * lists where the binary or 4-ary heap's order differs from the insertion sort's counted. None does: on
 * Mesa 22 llvmpipe the shader's own O(n) check still finds heap-sorted lists of demo:points out of order
 * (docs/EVALUATION.md), which this program shows the algorithm cannot produce.
 *
 *   exact_sort_replay [--lists 200000] [--seed 44]
 *
 * Exit status 1 when a list differs (the transcription or the algorithm is wrong). */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
static float list_z[256];
static uint32_t list_node[256];
static int before(float za, uint32_t ia, float zb, uint32_t ib) { return za < zb || (za == zb && ia > ib); }
static int before_at(int a, int b) { return before(list_z[a], list_node[a], list_z[b], list_node[b]); }
static void swap_entries(int a, int b)
{
    float z = list_z[a];
    uint32_t i = list_node[a];
    list_z[a] = list_z[b];
    list_node[a] = list_node[b];
    list_z[b] = z;
    list_node[b] = i;
}
static void heap_sink(int x, int n, int arity, int min_heap)
{
    float z = list_z[x];
    uint32_t node = list_node[x];
    for (int first = arity * x + 1; first < n; first = arity * x + 1) {
        int c = first, last = first + arity < n ? first + arity : n;
        for (int k = first + 1; k < last; k++)
            if (min_heap ? before_at(k, c) : before_at(c, k))
                c = k;
        int stays = min_heap ? !before(list_z[c], list_node[c], z, node) : !before(z, node, list_z[c], list_node[c]);
        if (stays)
            break;
        list_z[x] = list_z[c];
        list_node[x] = list_node[c];
        x = c;
    }
    list_z[x] = z;
    list_node[x] = node;
}
static void heap_sort(int n, int arity)
{
    for (int i = (n - 2) / arity; i >= 0; i--)
        heap_sink(i, n, arity, 0);
    for (int end = n - 1; end > 0; end--) {
        swap_entries(0, end);
        heap_sink(0, end, arity, 0);
    }
}
static void insertion_sort(float *z, uint32_t *nd, int n)
{
    for (int i = 1; i < n; i++) {
        float zi = z[i];
        uint32_t ni = nd[i];
        int j = i;
        while (j > 0 && before(zi, ni, z[j - 1], nd[j - 1])) {
            z[j] = z[j - 1];
            nd[j] = nd[j - 1];
            j--;
        }
        z[j] = zi;
        nd[j] = ni;
    }
}
int main(int argc, char **argv)
{
    long lists = 200000;
    unsigned seed = 44;
    for (int i = 1; i + 1 < argc; i += 2) {
        if (strcmp(argv[i], "--lists") == 0)
            lists = atol(argv[i + 1]);
        else if (strcmp(argv[i], "--seed") == 0)
            seed = (unsigned)atol(argv[i + 1]);
    }
    srand(seed);
    long trials = 0, bad = 0;
    for (int arity = 2; arity <= 4; arity += 2)
        for (long t = 0; t < lists; t++) {
            int n = 1 + rand() % 256, levels = 1 + rand() % 64;
            float z0[256];
            uint32_t n0[256];
            for (int i = 0; i < n; i++) {
                z0[i] = (float)(rand() % levels) / levels;
                n0[i] = (uint32_t)(rand() % 1000000) * 256u + (uint32_t)i;
            }
            memcpy(list_z, z0, sizeof z0);
            memcpy(list_node, n0, sizeof n0);
            heap_sort(n, arity);
            insertion_sort(z0, n0, n);
            trials++;
            if (memcmp(list_z, z0, n * sizeof *z0) || memcmp(list_node, n0, n * sizeof *n0))
                bad++;
        }
    printf("%ld lists (1..256 entries, 1..64 depth levels, arity 2 and 4): %ld where the heap's order differs from "
           "the insertion sort's\n",
           trials, bad);
    return bad != 0;
}
