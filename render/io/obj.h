/* Wavefront OBJ: v, vt, f, l; vt carries one per-vertex attribute as in the
 * small-doo and LineVis line files, named "vt" or by a comment line
 * "# vt: NAME" ("# vt: time" makes lines timed: docs/ALGORITHM.md §16). The
 * writer puts the default importance in vt. */
#ifndef LC_IO_OBJ_H
#define LC_IO_OBJ_H

#include <stddef.h>

#include "lc_base.h"
#include "scene.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Readers return an un-finalized scene (the caller runs lc_scene_finalize and
 * owns the scene). On error *out is NULL and err names the file, the line or
 * byte offset and the reason. `name` is used in messages and as the scene name. */
int lc_load_obj_memory(const void *data, size_t size, const char *name, lc_scene **out, lc_error *err);
int lc_load_obj(const char *path, lc_scene **out, lc_error *err);
int lc_save_obj(const lc_scene *s, const char *path, lc_error *err);

#ifdef __cplusplus
}
#endif
#endif
