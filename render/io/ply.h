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
/* Only process rank's share (of size) of a point cloud: the contiguous
 * vertices lc_scene_shard gives rank (lc_scene_read_file_part); every vertex
 * is still read and checked. LC_ERR_UNSUPPORTED for a file with faces or lines. */
int lc_load_ply_part(const char *path, int rank, int size, lc_scene **out, lc_error *err);
/* 1 when path is a PLY file whose header declares vertices and no faces,
 * lines or edges (a file that cannot be opened or parsed: 0). */
int lc_ply_file_is_point_cloud(const char *path);
int lc_save_ply(const lc_scene *s, const char *path, lc_error *err);

#ifdef __cplusplus
}
#endif
#endif
