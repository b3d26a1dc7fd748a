/* Data files through the scene cache: the cache file's name and folder, and
 * load-or-rebuild (dataset_cache.h). */
#include "dataset_cache.h"

#include <errno.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "loaders.h"
#include "scene_cache.h"

#define MOD "cache"

void lc_dataset_cache_default_dir(char *out, size_t len)
{
    const char *xdg = getenv("XDG_CACHE_HOME"), *home = getenv("HOME");
    if (xdg && xdg[0] == '/')
        snprintf(out, len, "%s/lucent", xdg);
    else if (home && home[0] == '/')
        snprintf(out, len, "%s/.cache/lucent", home);
    else if (len)
        out[0] = 0;
}

/* mkdir -p of dir (0700: the cache holds the data's content). */
static int make_dirs(const char *dir)
{
    char p[PATH_MAX];
    if (snprintf(p, sizeof p, "%s", dir) >= (int)sizeof p)
        return -1;
    for (char *c = p + 1; *c; c++)
        if (*c == '/') {
            *c = 0;
            if (mkdir(p, 0700) != 0 && errno != EEXIST)
                return -1;
            *c = '/';
        }
    return mkdir(p, 0700) != 0 && errno != EEXIST ? -1 : 0;
}

/* DIR/STEM-HASH.lcscene: the stem for a reader, the hash of the data file's
 * real path so that two files of one name do not share a cache file. */
static int cache_path(const char *dir, const char *path, char *out, size_t len)
{
    char real[PATH_MAX];
    if (!realpath(path, real))
        return -1;
    const char *base = strrchr(real, '/');
    base = base ? base + 1 : real;
    uint64_t h = lc_scene_cache_hash(real, strlen(real), 0);
    int n = snprintf(out, len, "%s/%.80s-%016llx.lcscene", dir, base, (unsigned long long)h);
    return n > 0 && (size_t)n < len ? 0 : -1;
}

int lc_dataset_cache_load(const char *cache_dir, const char *path, lc_scene **out, int *hit, lc_error *err)
{
    *out = NULL;
    *hit = 0;
    struct stat st;
    char cache[PATH_MAX + 128];
    lc_scene_cache_key key;
    lc_error e = {0};
    if (!cache_dir || !cache_dir[0] || stat(path, &st) != 0 || !S_ISREG(st.st_mode) ||
        (uint64_t)st.st_size < LC_DATASET_CACHE_MIN_BYTES || cache_path(cache_dir, path, cache, sizeof cache) != 0 ||
        lc_scene_cache_key_of(path, NULL, NULL, &key, &e) != 0)
        return lc_scene_load_file(path, out, err);
    double t0 = lc_now();
    int rc = lc_scene_cache_read(cache, &key, out, &e);
    if (rc == 0) {
        *hit = 1;
        LC_INFO(MOD, "%s: from the scene cache %s in %.0f ms", path, cache, (lc_now() - t0) * 1e3);
        return 0;
    }
    if (rc == LC_ERR_NOT_FOUND) {
        LC_INFO(MOD, "%s: no scene cache yet; writing %s after the load", path, cache);
    } else {
        LC_WARN(MOD, "%s: rebuilding the scene cache: %s", path, e.msg);
        unlink(cache);
    }
    if ((rc = lc_scene_load_file(path, out, err)) != 0)
        return rc;
    t0 = lc_now();
    if (make_dirs(cache_dir) != 0)
        LC_WARN(MOD, "%s: cannot create the cache folder: %s", cache_dir, strerror(errno));
    else if (lc_scene_cache_write(cache, &key, *out, &e) != 0)
        LC_WARN(MOD, "%s: scene cache not written: %s", path, e.msg);
    else
        LC_INFO(MOD, "%s: scene cache written in %.0f ms", path, (lc_now() - t0) * 1e3);
    return 0;
}
