/* Scene cache: a finalized scene (arrays, attribute ranges and percentiles,
 * elements and adjacency, levels of detail) written to one file and read back
 * without parsing or deriving anything, so that a restart skips the reader,
 * finalize and the level-of-detail build (docs/ARCHITECTURE.md "Scene cache").
 * A cache file is trusted only when its key (the data file's size, mtime and
 * content hash, and the settings that shaped the scene) equals the caller's,
 * its payload hash matches and every index in it is in range; anything else
 * is a miss that the caller answers by loading the data file again.
 * Threading: reentrant; the scene read belongs to the caller. */
#ifndef LC_SCENE_CACHE_H
#define LC_SCENE_CACHE_H

#include <stddef.h>
#include <stdint.h>

#include "elements.h"
#include "lc_base.h"
#include "scene.h"

#ifdef __cplusplus
extern "C" {
#endif

/* What a cached scene was derived from: the data file as it was, and the
 * settings that shape the derived scene (the element options of finalize and
 * a caller's own string, e.g. a reader option), folded into one hash. */
typedef struct lc_scene_cache_key {
    uint64_t file_size;
    int64_t mtime_sec, mtime_nsec;
    uint64_t content_hash; /* lc_scene_cache_hash_file */
    uint64_t settings_hash;
} lc_scene_cache_key;

/* 64-bit hash of n bytes (4 lanes of multiply-rotate rounds, about a byte a
 * cycle per lane), seeded. Not cryptographic: it detects change and damage. */
uint64_t lc_scene_cache_hash(const void *data, size_t n, uint64_t seed);
/* The key of the data file at path under the settings desc (NULL = defaults)
 * and extra (NULL = none): stat plus a hash of every byte of the file.
 * LC_ERR_IO naming the path when it cannot be read. */
int lc_scene_cache_key_of(const char *path, const lc_elements_desc *desc, const char *extra, lc_scene_cache_key *out,
                          lc_error *err);

/* Writes s (finalized, vertex arrays present) with its levels of detail to
 * cache_path, through a temporary file renamed into place so that a reader
 * never sees half a file. Levels not yet in s->lod are built here and kept
 * there, so that the upload does not build them again. */
int lc_scene_cache_write(const char *cache_path, const lc_scene_cache_key *key, lc_scene *s, lc_error *err);
/* Reads cache_path into a new finalized scene whose lod holds the cached
 * levels. A missing file is LC_ERR_NOT_FOUND; another key (a changed file or
 * setting) LC_ERR_INVALID "stale: ..."; a truncated, damaged or inconsistent
 * file LC_ERR_INVALID "corrupt: ...". *out is NULL on every error. */
int lc_scene_cache_read(const char *cache_path, const lc_scene_cache_key *key, lc_scene **out, lc_error *err);

/* Tests and the fuzz harness: recomputes the payload hash of a cache file
 * whose header and counts are consistent, so that an edited or generated
 * file reaches the reader's structural checks; *key (may be NULL) gets the
 * key the file claims. LC_ERR_INVALID when the file is not a cache with
 * consistent counts. */
int lc_scene_cache_seal(const char *cache_path, lc_scene_cache_key *key, lc_error *err);

#ifdef __cplusplus
}
#endif
#endif
