/* What a --data folder may reach: its entries and their sidecars are served
 * only when they are regular files (or TRX folders) whose real path stays
 * inside the folder, unless --follow-symlinks allows links that leave it.
 * Threading: plain functions on paths; reentrant. */
#ifndef LC_DATA_PATHS_H
#define LC_DATA_PATHS_H

#include <stdbool.h>

#include "lc_base.h"

/* 0 when path (an entry of the folder whose real path is root) may be served:
 * a regular file or a directory, inside root after resolving every link, or
 * anywhere when follow. A directory's own entries (a TRX folder is read file
 * by file) must not link out of root either. Otherwise LC_ERR_INVALID naming path and the reason. */
int lc_data_path_check(const char *root, const char *path, bool follow, lc_error *err);
/* 0 when the sidecar side of dataset may be read: a regular file whose real
 * path is in the dataset's own real folder (or anywhere when follow). */
int lc_data_sidecar_check(const char *dataset, const char *side, bool follow, lc_error *err);

#endif
