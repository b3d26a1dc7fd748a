/* Confinement of --data folders and sidecars (data_paths.h). */
#include "data_paths.h"

#include <errno.h>
#include <ftw.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

/* Whether the resolved path real lies in the resolved folder root. */
static bool inside(const char *root, const char *real)
{
    size_t n = strlen(root);
    if (n == 1 && root[0] == '/')
        return true;
    return strncmp(real, root, n) == 0 && (real[n] == '/' || real[n] == '\0');
}

/* nftw's callback has no user pointer: the walk keeps its state here,
 * thread-local so that the check stays reentrant across threads. */
static _Thread_local struct {
    const char *root;
    char bad[PATH_MAX];
    long entries;
} walk;

enum { WALK_MAX_ENTRIES = 4096 }; /* a TRX folder holds a few dozen files */

static int walk_entry(const char *path, const struct stat *st, int kind, struct FTW *ftw)
{
    (void)st, (void)ftw;
    if (++walk.entries > WALK_MAX_ENTRIES) {
        snprintf(walk.bad, sizeof walk.bad, "%s: more than %d entries", path, WALK_MAX_ENTRIES);
        return 1;
    }
    if (kind != FTW_SL)
        return 0;
    char real[PATH_MAX];
    if (!realpath(path, real) || !inside(walk.root, real)) {
        snprintf(walk.bad, sizeof walk.bad, "%s", path);
        return 1;
    }
    return 0;
}

/* A folder dataset (TRX) is read file by file: every link inside it must stay
 * inside root too, or a folder inside the data folder reaches out. */
static int check_folder(const char *root, const char *path, lc_error *err)
{
    walk.root = root;
    walk.bad[0] = '\0';
    walk.entries = 0;
    int rc = nftw(path, walk_entry, 8, FTW_PHYS);
    if (rc > 0 && walk.entries > WALK_MAX_ENTRIES)
        return lc_err(err, LC_ERR_INVALID, "%s", walk.bad);
    if (rc > 0)
        return lc_err(err, LC_ERR_INVALID, "%s: links outside the data folder (--follow-symlinks allows it)", walk.bad);
    if (rc < 0)
        return lc_err(err, LC_ERR_IO, "%s: cannot list (%s)", path, strerror(errno));
    return 0;
}

int lc_data_path_check(const char *root, const char *path, bool follow, lc_error *err)
{
    struct stat st;
    if (stat(path, &st) != 0)
        return lc_err(err, LC_ERR_IO, "%s: cannot open (%s)", path, strerror(errno));
    if (!S_ISREG(st.st_mode) && !S_ISDIR(st.st_mode))
        return lc_err(err, LC_ERR_INVALID, "%s: not a regular file", path);
    if (follow)
        return 0;
    char real[PATH_MAX];
    if (!realpath(path, real))
        return lc_err(err, LC_ERR_IO, "%s: cannot resolve (%s)", path, strerror(errno));
    if (!inside(root, real))
        return lc_err(err, LC_ERR_INVALID, "%s: links outside the data folder (--follow-symlinks allows it)", path);
    return S_ISDIR(st.st_mode) ? check_folder(root, real, err) : 0;
}

int lc_data_sidecar_check(const char *dataset, const char *side, bool follow, lc_error *err)
{
    struct stat st;
    if (lstat(side, &st) == 0 && S_ISLNK(st.st_mode) && !follow) {
        char folder[PATH_MAX], real[PATH_MAX];
        if (!realpath(dataset, folder))
            return lc_err(err, LC_ERR_IO, "%s: cannot resolve (%s)", dataset, strerror(errno));
        char *slash = strrchr(folder, '/');
        if (slash)
            slash[slash == folder] = '\0'; /* "/a/b" -> "/a", "/b" -> "/" */
        if (!realpath(side, real))
            return lc_err(err, LC_ERR_IO, "%s: cannot resolve (%s)", side, strerror(errno));
        if (!inside(folder, real))
            return lc_err(err, LC_ERR_INVALID,
                          "%s: sidecar links outside its dataset's folder; not read (--follow-symlinks allows it)",
                          side);
    }
    return 0;
}
