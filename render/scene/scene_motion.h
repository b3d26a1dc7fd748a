/* Derived motion attributes of timed lines: speed, turning and ascent angles,
 * and the per-segment change and rate of file attributes, for line files
 * whose vertices carry a time or frame attribute (docs/ALGORITHM.md §16).
 * Internal to render/, called by lc_scene_finalize after lc_scene_derive_lines. */
#ifndef LC_SCENE_MOTION_H
#define LC_SCENE_MOTION_H

#include "scene.h"

/* File attributes that get NAME_delta and NAME_rate (the first ones in file
 * order that are measured, not categorical): each costs 8 bytes a vertex. */
#define LC_MOTION_MAX_RATES 4

/* For a line scene that is not a geographic trajectory and has a time
 * attribute (lc_scene_time_attribute: time, t, frame, timestep) adds
 * "speed" (|Δp| / Δt, the mean over the segments meeting at a vertex; kept
 * when the reader gave one), "turning_angle" (degrees between the incoming
 * and outgoing segment, 0 at the ends), "ascent_angle" (degrees of the
 * outgoing segment over the xy plane, the last vertex: the incoming one) and,
 * for up to LC_MOTION_MAX_RATES measured file attributes A, "A_delta" (A of
 * the next vertex minus A here; the last vertex: the incoming segment's) and
 * "A_rate" (A_delta / Δt of that segment; 0 where Δt is 0 or not finite;
 * none when s->trajectory.no_rates). *applied says whether the scene
 * qualified. Expects validated line offsets and categories marked (a second
 * finalize recomputes the same values). */
int lc_scene_derive_motion(lc_scene *s, int *applied, lc_error *err);

#endif
