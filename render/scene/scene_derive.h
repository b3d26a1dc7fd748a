/* Derived per-vertex data of a scene (tangents, normals, curvature, arc length);
 * internal to render/, called by lc_scene_finalize after validation. */
#ifndef LC_SCENE_DERIVE_H
#define LC_SCENE_DERIVE_H

#include "scene.h"
#include "scene_part.h"

/* Lines: fills s->tangents and adds "arc_length", "curvature", "line_length".
 * Expects validated line offsets. */
int lc_scene_derive_lines(lc_scene *s, lc_error *err);
/* Lines (scene_measures.c, after lc_scene_derive_lines): adds FOO's importance
 * measures "boundary_distance", "direction_variance", "linear_entropy" and
 * "angular_entropy" (docs/ALGORITHM.md "Derived attributes"); total = the
 * vertices of the whole scene; with c (a part) the directions' grid is summed
 * over the processes (collective). Adds nothing when they would pass
 * LC_MAX_ATTRIBUTES. */
int lc_scene_derive_line_measures(lc_scene *s, uint64_t total, const lc_scene_collective *c, lc_error *err);
/* Trajectories (s->trajectory.geographic): adds, from metric distances
 * (docs/ALGORITHM.md "Derived trajectory attributes"), "pressure" (hPa),
 * "pressure_change" (last - first over the line), "pressure_change_48h" (to
 * the vertex 48 h later, or the line's last; with a known time step),
 * "speed" (km/h; without a time step "segment_length", km), "turning_angle"
 * and "ascent_angle" (degrees). Expects validated line offsets. */
int lc_scene_derive_trajectories(lc_scene *s, lc_error *err);
/* Triangles: fills s->normals and adds "mean_curvature". Expects validated indices. */
int lc_scene_derive_triangles(lc_scene *s, lc_error *err);
/* Points: adds "density", the points in a uniform grid cell (about 8 per cell
 * on average, cubic cells over the bounds, at most 128 along an axis) summed
 * over its 3x3x3 neighbourhood, divided by the largest such sum: without any
 * attribute every point would get g = 1, and dense structure is what a point
 * cloud shows. total = the points of the whole scene; with c (a part) the grid
 * is summed over the processes. Expects the whole scene's bounds. */
int lc_scene_derive_points(lc_scene *s, uint64_t total, const lc_scene_collective *c, lc_error *err);

#endif
