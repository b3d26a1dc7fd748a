/* Dataset file formats: PLY (ASCII, binary little/big endian) and OBJ (v, f, l
 * with a per-vertex attribute in vt), reading and writing. */
#ifndef LC_LOADERS_H
#define LC_LOADERS_H

#include <stddef.h>

#include "scene.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Loaders return an un-finalized scene (caller runs lc_scene_finalize and owns
 * the scene). On error *out is NULL and err names the file, the line or byte
 * offset and the reason, e.g. "a.ply: line 12: vertex count 4000000000 exceeds
 * the file size". `name` is used in messages and as the scene name. */
int lc_load_ply_memory(const void *data, size_t size, const char *name, lc_scene **out, lc_error *err);
int lc_load_obj_memory(const void *data, size_t size, const char *name, lc_scene **out, lc_error *err);
int lc_load_ply(const char *path, lc_scene **out, lc_error *err);
int lc_load_obj(const char *path, lc_scene **out, lc_error *err);
/* Picks the loader by extension (.ply, .obj); the scene is named after the file
 * stem. Finalizes the scene with default element options. */
int lc_scene_load_file(const char *path, lc_scene **out, lc_error *err);

/* Writers: binary little-endian PLY with every attribute as a float property
 * and rgb as uchar red/green/blue; OBJ with v, f or l, and the default
 * importance attribute in vt. */
int lc_save_ply(const lc_scene *s, const char *path, lc_error *err);
int lc_save_obj(const lc_scene *s, const char *path, lc_error *err);

#ifdef __cplusplus
}
#endif
#endif
