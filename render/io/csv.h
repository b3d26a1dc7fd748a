/* Point tables: .csv, .tsv and .xyz, one point per row.
 * The separator is the header line's: a comma, else a tab, else runs of blanks.
 * A first row holding a field that is not a number is the header naming the
 * columns (quotes stripped); positions come from x/y/z (any case; ParaView's
 * Points:0/1/2 too), else lon/lat with height from alt/altitude/height/z
 * (0 without one). Without a header the first three columns are x, y, z and
 * the others column_K. Every other column that holds numbers becomes an
 * attribute of its name; a column whose first value is not a number (text) is
 * skipped with a warning. '#' starts a comment line. Rows with a missing or
 * non-finite coordinate are dropped with a warning; an empty attribute field
 * is NaN. */
#ifndef LC_IO_CSV_H
#define LC_IO_CSV_H

#include <stddef.h>

#include "lc_base.h"
#include "scene.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Readers return an un-finalized scene (the caller runs lc_scene_finalize and
 * owns the scene). On error *out is NULL and err names the file, the line and
 * the reason. `name` is used in messages and as the scene name. */
int lc_load_csv_memory(const void *data, size_t size, const char *name, lc_scene **out, lc_error *err);
int lc_load_csv(const char *path, lc_scene **out, lc_error *err);
/* Only process rank's share (of size) of the rows with finite coordinates:
 * the contiguous range lc_scene_shard gives rank (lc_scene_read_file_part).
 * Every row is still parsed and checked. */
int lc_load_csv_part(const char *path, int rank, int size, lc_scene **out, lc_error *err);

#ifdef __cplusplus
}
#endif
#endif
