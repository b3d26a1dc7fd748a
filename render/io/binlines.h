/* LineVis .binlines (little endian): u32 version (1 or 2), u32 line count, u32
 * attribute count; version 2 then names each attribute (u32 byte length, the
 * bytes: sgl's string encoding); then per line u32 n, n xyz float triples and,
 * per attribute, n floats. Every line a polyline with its attributes (named
 * attribute_K in version 1). Points with a non-finite coordinate are dropped
 * with a warning; lines of fewer than two points too. */
#ifndef LC_IO_BINLINES_H
#define LC_IO_BINLINES_H

#include <stddef.h>

#include "lc_base.h"
#include "scene.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Readers return an un-finalized scene (the caller runs lc_scene_finalize and
 * owns the scene). On error *out is NULL and err names the file, the byte
 * offset and the reason. `name` is used in messages and as the scene name. */
int lc_load_binlines_memory(const void *data, size_t size, const char *name, lc_scene **out, lc_error *err);
int lc_load_binlines(const char *path, lc_scene **out, lc_error *err);
/* Only the whole lines of process rank's share of size (lc_scene_read_file_part). */
int lc_load_binlines_part(const char *path, int rank, int size, lc_scene **out, lc_error *err);

#ifdef __cplusplus
}
#endif
#endif
