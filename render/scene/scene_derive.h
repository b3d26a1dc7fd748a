/* Derived per-vertex data of a scene (tangents, normals, curvature, arc length);
 * internal to render/, called by lc_scene_finalize after validation. */
#ifndef LC_SCENE_DERIVE_H
#define LC_SCENE_DERIVE_H

#include "scene.h"

/* Lines: fills s->tangents and adds "arc_length", "curvature", "line_length".
 * Expects validated line offsets. */
int lc_scene_derive_lines(lc_scene *s, lc_error *err);
/* Triangles: fills s->normals and adds "mean_curvature". Expects validated indices. */
int lc_scene_derive_triangles(lc_scene *s, lc_error *err);

#endif
