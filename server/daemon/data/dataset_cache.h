/* The scene cache of the daemon's data files: where cache files live, and a
 * load that takes a valid cache file or reads the data file and writes one
 * (render/scene/scene_cache.h holds the file format and its checks). */
#ifndef LC_SERVER_DATASET_CACHE_H
#define LC_SERVER_DATASET_CACHE_H

#include <stddef.h>

#include "lc_base.h"
#include "scene.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Data files smaller than this are read without a cache: parsing them costs
 * less than a cache file would save, and they would litter the folder. */
#define LC_DATASET_CACHE_MIN_BYTES (1u << 20)

/* The default cache folder: $XDG_CACHE_HOME/lucent, else $HOME/.cache/lucent;
 * "" when neither variable is set (no cache). */
void lc_dataset_cache_default_dir(char *out, size_t len);

/* The finalized scene of the data file at path, as lc_scene_load_file gives
 * it: from cache_dir's cache file for path when its key matches (size,
 * mtime, content hash, settings) and it reads back intact; otherwise loaded
 * from path and written to the cache for the next start (a stale or damaged
 * cache file is logged and replaced, never used). cache_dir NULL or "", a
 * folder, or a file under LC_DATASET_CACHE_MIN_BYTES: a plain load. A cache
 * that cannot be written is logged; the load still succeeds. *hit says
 * whether the cache served it. Errors are lc_scene_load_file's. */
int lc_dataset_cache_load(const char *cache_dir, const char *path, lc_scene **out, int *hit, lc_error *err);

#ifdef __cplusplus
}
#endif
#endif
