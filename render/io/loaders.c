/* Dataset file dispatcher: picks the reader by extension and finalizes. */
#include "loaders.h"

#include <string.h>
#include <strings.h>
#include <sys/stat.h>

#include "io_util.h"

typedef int (*path_loader)(const char *path, lc_scene **out, lc_error *err);

static const struct {
    const char *ext;
    path_loader load;
} readers[] = {
    {".ply", lc_load_ply},        {".obj", lc_load_obj},           {".vtk", lc_load_vtk},   {".trk", lc_load_trk},
    {".tck", lc_load_tck},        {".binlines", lc_load_binlines}, {".csv", lc_load_csv},   {".tsv", lc_load_csv},
    {".xyz", lc_load_csv},        {".trx", lc_load_trx},           {".nc", lc_load_netcdf}, {".dump", lc_load_dump},
    {".lammpstrj", lc_load_dump},
};

static path_loader reader_for(const char *path)
{
    const char *dot = strrchr(lc_io_basename(path), '.');
    for (size_t i = 0; dot && i < sizeof readers / sizeof *readers; i++)
        if (strcasecmp(dot, readers[i].ext) == 0)
            return readers[i].load;
    return NULL;
}

int lc_scene_is_dataset_file(const char *path) { return reader_for(path) != NULL; }

typedef int (*part_loader)(const char *path, int rank, int size, lc_scene **out, lc_error *err);

/* Formats whose records can be skipped without keeping them: for lines a
 * first pass counts every line's points, the second keeps the process's
 * share; a point cloud's share is a contiguous range of its vertices. A PLY
 * file qualifies only when its header declares no faces or lines. */
static const struct {
    const char *ext;
    part_loader load;
    int (*applies)(const char *path); /* NULL: every file of the extension */
} part_readers[] = {{".trk", lc_load_trk_part, NULL},
                    {".tck", lc_load_tck_part, NULL},
                    {".binlines", lc_load_binlines_part, NULL},
                    {".trx", lc_load_trx_part, NULL},
                    {".nc", lc_load_netcdf_part, NULL},
                    {".csv", lc_load_csv_part, NULL},
                    {".tsv", lc_load_csv_part, NULL},
                    {".xyz", lc_load_csv_part, NULL},
                    {".ply", lc_load_ply_part, lc_ply_file_is_point_cloud},
                    {".vtk", lc_load_vtk_part, lc_vtk_file_has_lines},
                    {".dump", lc_load_dump_part, NULL},
                    {".lammpstrj", lc_load_dump_part, NULL}};

static part_loader part_reader_for(const char *path)
{
    const char *dot = strrchr(lc_io_basename(path), '.');
    for (size_t i = 0; dot && i < sizeof part_readers / sizeof *part_readers; i++)
        if (strcasecmp(dot, part_readers[i].ext) == 0)
            return !part_readers[i].applies || part_readers[i].applies(path) ? part_readers[i].load : NULL;
    return NULL;
}

int lc_scene_can_read_part(const char *path) { return part_reader_for(path) != NULL; }

int lc_scene_read_file_part(const char *path, int rank, int size, lc_scene **out, lc_error *err)
{
    *out = NULL;
    part_loader load = part_reader_for(path);
    if (!load)
        return lc_err(err, LC_ERR_UNSUPPORTED, "%s: this format is read whole (parts: %s)", lc_io_basename(path),
                      LC_PART_EXTENSIONS);
    if (size < 1 || rank < 0 || rank >= size)
        return lc_err(err, LC_ERR_INVALID, "%s: part %d of %d", lc_io_basename(path), rank, size);
    return load(path, rank, size, out, err);
}

int lc_scene_read_file(const char *path, lc_scene **out, lc_error *err)
{
    *out = NULL;
    path_loader load = reader_for(path);
    if (!load)
        return lc_err(err, LC_ERR_UNSUPPORTED, "%s: unknown dataset format (expected %s)", lc_io_basename(path),
                      LC_DATASET_EXTENSIONS);
    int rc = load(path, out, err);
    if (rc == 0)
        lc_io_stem(path, (*out)->name, sizeof(*out)->name);
    return rc;
}

void lc_scene_set_load_limit(uint64_t bytes) { lc_io_set_memory_limit(bytes); }

int lc_scene_load_file(const char *path, lc_scene **out, lc_error *err)
{
    *out = NULL;
    const char *base = lc_io_basename(path);
    lc_scene *s = NULL;
    int rc = lc_scene_read_file(path, &s, err);
    if (rc)
        return rc;
    struct stat st;
    if (stat(path, &st) == 0 && S_ISREG(st.st_mode)) /* what finalize will need, before it allocates */
        rc = lc_io_check_load(base, (uint64_t)st.st_size, s->vertex_count, s->triangle_count * 12ull, "its vertices",
                              err);
    if (!rc)
        rc = lc_cancelled() ? lc_err_cancelled(err, base) : lc_scene_finalize(s, NULL, err);
    if (rc) {
        if (err && strncmp(err->msg, base, strlen(base)) != 0)
            lc_err_prefix(err, "%s", base);
        lc_scene_destroy(s);
        return rc;
    }
    *out = s;
    return 0;
}
