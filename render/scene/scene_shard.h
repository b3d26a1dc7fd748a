/* Shards of a scene for rendering one dataset over several processes
 * (docs/MPI.md): a deterministic split of whole points, lines or surface
 * patches by rank. */
#ifndef LC_SCENE_SHARD_H
#define LC_SCENE_SHARD_H

#include "scene.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Builds *out, the share of rank `rank` (0..size-1) of the finalized scene
 * `full`: contiguous points, or whole lines, balanced by vertex count; for
 * surfaces the triangles whose first vertex's primary element falls in the
 * rank's contiguous range of patches (shared vertices are copied). The shard
 * keeps what must agree across ranks from the whole scene: bounds, attribute
 * ranges and percentiles, defaults, the suggested view, and the elements'
 * global numbering and adjacency (per-vertex blends point at global ids), so
 * the union of the shards' fragments is exactly the whole scene's. Every
 * process computes the same split from the same scene; no communication.
 * The caller destroys *out; full is untouched. */
int lc_scene_shard(const lc_scene *full, int rank, int size, lc_scene **out, lc_error *err);

/* The split lc_scene_shard makes, for readers that keep only their share
 * while reading (lc_scene_read_file_part): of n lines with counts[i]
 * vertices, rank's whole lines [*first, *last), balanced by vertex count.
 * LC_ERR_NOMEM when the running sums cannot be allocated. */
int lc_scene_split_lines(const uint32_t *counts, uint32_t n, int rank, int size, uint32_t *first, uint32_t *last);
/* Of n points, the first of rank's contiguous share (rank = size gives n):
 * shares start at multiples of 1024, the chunks in which the compact GPU
 * layout quantizes positions. */
uint32_t lc_scene_split_points(uint64_t n, int rank, int size);

#ifdef __cplusplus
}
#endif
#endif
