/* Shards of a scene: one rank's whole points, lines or surface patches, with
 * the whole scene's bounds, attribute statistics and element numbering. */
#include "scene_shard.h"

#include "lod.h"

#include <stdlib.h>
#include <string.h>

/* First index of rank's share of [0, total) weighted by cumulative[i] (the
 * weight before item i; cumulative has n + 1 entries): the item where the
 * running weight reaches rank/size of the whole. */
static uint32_t split_point(const uint64_t *cumulative, uint32_t n, int rank, int size)
{
    if (rank <= 0)
        return 0;
    if (rank >= size)
        return n;
    uint64_t target = cumulative[n] * (uint64_t)rank / (uint64_t)size;
    uint32_t lo = 0, hi = n; /* first i with cumulative[i] >= target */
    while (lo < hi) {
        uint32_t mid = lo + (hi - lo) / 2;
        if (cumulative[mid] < target)
            lo = mid + 1;
        else
            hi = mid;
    }
    return lo;
}

/* Copies the per-vertex arrays of full for the vertices in map (count of
 * them) into s, and the per-scene data that must agree across ranks. */
static int copy_vertices(const lc_scene *full, const uint32_t *map, uint32_t count, lc_scene *s, lc_error *err)
{
    size_t n = count ? count : 1;
    s->positions = malloc(n * 3 * sizeof(float));
    s->rgb = full->rgb ? malloc(n * 3 * sizeof(float)) : NULL;
    s->normals = full->normals ? malloc(n * 3 * sizeof(float)) : NULL;
    s->tangents = full->tangents ? malloc(n * 3 * sizeof(float)) : NULL;
    s->elements.vertex_elements = malloc(n * 4 * sizeof(uint32_t));
    s->elements.vertex_weights = malloc(n * 4 * sizeof(float));
    int bad = !s->positions || (full->rgb && !s->rgb) || (full->normals && !s->normals) ||
              (full->tangents && !s->tangents) || !s->elements.vertex_elements || !s->elements.vertex_weights;
    s->vertex_count = count;
    for (int a = 0; a < full->attribute_count && !bad; a++) {
        s->attributes[a] = full->attributes[a]; /* name, min, max, percentiles: the whole scene's */
        s->attributes[a].values = malloc(n * sizeof(float));
        s->attribute_count = a + 1;
        bad = !s->attributes[a].values;
    }
    if (bad)
        return lc_err(err, LC_ERR_NOMEM, "%s: out of memory for a shard of %u vertices", full->name, count);
    for (uint32_t i = 0; i < count; i++) {
        uint32_t v = map[i];
        memcpy(s->positions + 3 * (size_t)i, full->positions + 3 * (size_t)v, 3 * sizeof(float));
        if (s->rgb)
            memcpy(s->rgb + 3 * (size_t)i, full->rgb + 3 * (size_t)v, 3 * sizeof(float));
        if (s->normals)
            memcpy(s->normals + 3 * (size_t)i, full->normals + 3 * (size_t)v, 3 * sizeof(float));
        if (s->tangents)
            memcpy(s->tangents + 3 * (size_t)i, full->tangents + 3 * (size_t)v, 3 * sizeof(float));
        memcpy(s->elements.vertex_elements + 4 * (size_t)i, full->elements.vertex_elements + 4 * (size_t)v,
               4 * sizeof(uint32_t));
        memcpy(s->elements.vertex_weights + 4 * (size_t)i, full->elements.vertex_weights + 4 * (size_t)v,
               4 * sizeof(float));
        for (int a = 0; a < full->attribute_count; a++)
            s->attributes[a].values[i] = full->attributes[a].values[v];
    }
    return 0;
}

/* The element numbering and adjacency of the whole scene: smoothing (P3) runs
 * on every rank over all elements, from minima combined over the ranks. */
static int copy_elements(const lc_scene *full, lc_scene *s, lc_error *err)
{
    const lc_elements *e = &full->elements;
    s->elements.count = e->count;
    s->elements.adjacency_count = e->adjacency_count;
    if (e->adjacency_offsets) {
        s->elements.adjacency_offsets = malloc(((size_t)e->count + 1) * sizeof(uint32_t));
        s->elements.adjacency = malloc(((size_t)e->adjacency_count + 1) * sizeof(uint32_t));
        if (!s->elements.adjacency_offsets || !s->elements.adjacency)
            return lc_err(err, LC_ERR_NOMEM, "%s: out of memory for the element adjacency", full->name);
        memcpy(s->elements.adjacency_offsets, e->adjacency_offsets, ((size_t)e->count + 1) * sizeof(uint32_t));
        if (e->adjacency_count)
            memcpy(s->elements.adjacency, e->adjacency, (size_t)e->adjacency_count * sizeof(uint32_t));
    }
    return 0;
}

/* Points split at multiples of this: the compact GPU layout quantizes
 * positions in chunks of LC_POSITION_CHUNK (1024) vertices with their own
 * bounds (render/gl/vertex_pack.h), so aligned shards quantize every point
 * exactly as one process does. */
#define POINT_ALIGN 1024u

static uint32_t aligned_split(uint64_t n, int rank, int size)
{
    if (rank >= size)
        return (uint32_t)n;
    uint64_t chunks = (n + POINT_ALIGN - 1) / POINT_ALIGN, at = chunks * (uint64_t)rank / (uint64_t)size * POINT_ALIGN;
    return (uint32_t)(at < n ? at : n);
}

static int shard_points(const lc_scene *full, int rank, int size, lc_scene *s, uint32_t **map, uint32_t *count)
{
    uint64_t n = full->vertex_count;
    uint32_t first = aligned_split(n, rank, size), last = aligned_split(n, rank + 1, size);
    s->vertex_base = first;
    *count = last - first;
    *map = malloc(((size_t)*count + 1) * sizeof(uint32_t));
    if (!*map)
        return LC_ERR_NOMEM;
    for (uint32_t i = 0; i < *count; i++)
        (*map)[i] = first + i;
    return 0;
}

int lc_scene_split_lines(const uint32_t *counts, uint32_t n, int rank, int size, uint32_t *first, uint32_t *last)
{
    uint64_t *cumulative = malloc(((size_t)n + 1) * sizeof *cumulative);
    if (!cumulative)
        return LC_ERR_NOMEM;
    cumulative[0] = 0;
    for (uint32_t l = 0; l < n; l++)
        cumulative[l + 1] = cumulative[l] + counts[l];
    *first = split_point(cumulative, n, rank, size);
    *last = split_point(cumulative, n, rank + 1, size);
    free(cumulative);
    return 0;
}

uint32_t lc_scene_split_points(uint64_t n, int rank, int size) { return aligned_split(n, rank, size); }

static int shard_lines(const lc_scene *full, int rank, int size, lc_scene *s, uint32_t **map, uint32_t *count)
{
    uint32_t nl = full->line_count, first, last;
    uint32_t *counts = malloc(((size_t)nl + 1) * sizeof *counts);
    if (!counts)
        return LC_ERR_NOMEM;
    for (uint32_t l = 0; l < nl; l++)
        counts[l] = full->line_offsets[l + 1] - full->line_offsets[l];
    int rc = lc_scene_split_lines(counts, nl, rank, size, &first, &last);
    free(counts);
    if (rc)
        return rc;
    uint32_t v0 = full->line_offsets[first], v1 = full->line_offsets[last];
    s->vertex_base = v0;
    s->line_count = last - first;
    s->line_offsets = malloc(((size_t)s->line_count + 1) * sizeof(uint32_t));
    *count = v1 - v0;
    *map = malloc(((size_t)*count + 1) * sizeof(uint32_t));
    if (!s->line_offsets || !*map)
        return LC_ERR_NOMEM;
    for (uint32_t l = 0; l <= s->line_count; l++)
        s->line_offsets[l] = full->line_offsets[first + l] - v0;
    for (uint32_t i = 0; i < *count; i++)
        (*map)[i] = v0 + i;
    return 0;
}

static int shard_triangles(const lc_scene *full, int rank, int size, lc_scene *s, uint32_t **map, uint32_t *count)
{
    uint64_t ne = full->elements.count ? full->elements.count : 1;
    uint32_t e_first = (uint32_t)(ne * (uint64_t)rank / (uint64_t)size);
    uint32_t e_last = (uint32_t)(ne * (uint64_t)(rank + 1) / (uint64_t)size);
    const uint32_t *ve = full->elements.vertex_elements;
    uint32_t nv = full->vertex_count, nt = 0;
    uint32_t *local = malloc(((size_t)nv + 1) * sizeof(uint32_t)); /* full vertex -> shard vertex + 1 */
    s->triangles = malloc(((size_t)full->triangle_count * 3 + 1) * sizeof(uint32_t));
    *map = malloc(((size_t)nv + 1) * sizeof(uint32_t));
    if (!local || !s->triangles || !*map) {
        free(local);
        return LC_ERR_NOMEM;
    }
    memset(local, 0, ((size_t)nv + 1) * sizeof(uint32_t));
    *count = 0;
    for (uint32_t t = 0; t < full->triangle_count; t++) {
        const uint32_t *tri = full->triangles + 3 * (size_t)t;
        /* The fragment's element is the provoking (last) vertex's primary one. */
        uint32_t e = ve ? ve[4 * (size_t)tri[2] + 3] : 0;
        if (e < e_first || e >= e_last)
            continue;
        for (int k = 0; k < 3; k++) {
            if (!local[tri[k]]) {
                (*map)[*count] = tri[k];
                local[tri[k]] = ++*count;
            }
            s->triangles[3 * (size_t)nt + k] = local[tri[k]] - 1;
        }
        nt++;
    }
    s->triangle_count = nt;
    free(local);
    return 0;
}

/* The ladder steps of the whole scene's line levels of detail (lod.h), for
 * every shard to simplify alike. 0 when they cannot be computed: the shard
 * then decides for itself (a finer level on some ranks, still within bound). */
static uint32_t whole_lod_steps(const lc_scene *full)
{
    uint64_t counts[LC_LOD_COUNTS];
    if (full->lod_steps)
        return full->lod_steps;
    return lc_lod_line_counts(full, counts, NULL) == 0 ? lc_lod_line_steps(counts) : 0;
}

int lc_scene_shard(const lc_scene *full, int rank, int size, lc_scene **out, lc_error *err)
{
    *out = NULL;
    if (!full->finalized)
        return lc_err(err, LC_ERR_INVALID, "%s: scene is not finalized", full->name);
    if (size < 1 || rank < 0 || rank >= size)
        return lc_err(err, LC_ERR_INVALID, "%s: rank %d of %d processes", full->name, rank, size);
    lc_scene *s = lc_scene_create(full->name, full->type);
    if (!s)
        return lc_err(err, LC_ERR_NOMEM, "%s: out of memory for a shard", full->name);
    uint32_t *map = NULL, count = 0;
    int rc = full->type == LC_PRIM_LINES       ? shard_lines(full, rank, size, s, &map, &count)
             : full->type == LC_PRIM_TRIANGLES ? shard_triangles(full, rank, size, s, &map, &count)
                                               : shard_points(full, rank, size, s, &map, &count);
    if (rc)
        rc = lc_err(err, LC_ERR_NOMEM, "%s: out of memory for the shard of rank %d", full->name, rank);
    if (!rc)
        rc = copy_vertices(full, map, count, s, err);
    if (!rc)
        rc = copy_elements(full, s, err);
    free(map);
    if (rc) {
        lc_scene_destroy(s);
        return rc;
    }
    memcpy(s->bounds, full->bounds, sizeof s->bounds);
    memcpy(s->default_importance, full->default_importance, sizeof s->default_importance);
    memcpy(s->default_color, full->default_color, sizeof s->default_color);
    if (full->type == LC_PRIM_LINES)
        s->lod_steps = whole_lod_steps(full);
    s->has_view = full->has_view;
    memcpy(s->view_direction, full->view_direction, sizeof s->view_direction);
    memcpy(s->view_up, full->view_up, sizeof s->view_up);
    s->finalized = 1;
    *out = s;
    return 0;
}
