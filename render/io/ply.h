/* PLY: reader (ASCII, binary little and big endian) and binary little-endian
 * writer (every attribute a float property, rgb as uchar red/green/blue). */
#ifndef LC_IO_PLY_H
#define LC_IO_PLY_H

#include <stddef.h>

#include "lc_base.h"
#include "scene.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Readers return an un-finalized scene (the caller runs lc_scene_finalize and
 * owns the scene). On error *out is NULL and err names the file, the line or
 * byte offset and the reason. `name` is used in messages and as the scene name. */
int lc_load_ply_memory(const void *data, size_t size, const char *name, lc_scene **out, lc_error *err);
int lc_load_ply(const char *path, lc_scene **out, lc_error *err);
int lc_save_ply(const lc_scene *s, const char *path, lc_error *err);

#ifdef __cplusplus
}
#endif
#endif
