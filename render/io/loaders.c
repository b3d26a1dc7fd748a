/* Dataset file dispatcher: picks the reader by extension and finalizes. */
#include "loaders.h"

#include <string.h>
#include <strings.h>

#include "io_util.h"

int lc_scene_load_file(const char *path, lc_scene **out, lc_error *err)
{
    *out = NULL;
    const char *base = lc_io_basename(path);
    const char *dot = strrchr(base, '.');
    int rc;
    lc_scene *s = NULL;
    if (dot && strcasecmp(dot, ".ply") == 0)
        rc = lc_load_ply(path, &s, err);
    else if (dot && strcasecmp(dot, ".obj") == 0)
        rc = lc_load_obj(path, &s, err);
    else if (dot && strcasecmp(dot, ".vtk") == 0)
        rc = lc_load_vtk(path, &s, err);
    else if (dot && strcasecmp(dot, ".trk") == 0)
        rc = lc_load_trk(path, &s, err);
    else
        return lc_err(err, LC_ERR_UNSUPPORTED, "%s: unknown dataset format (expected .ply, .obj, .vtk or .trk)", base);
    if (rc)
        return rc;
    lc_io_stem(path, s->name, sizeof s->name);
    rc = lc_scene_finalize(s, NULL, err);
    if (rc) {
        if (err && strncmp(err->msg, base, strlen(base)) != 0)
            lc_err_prefix(err, "%s", base);
        lc_scene_destroy(s);
        return rc;
    }
    *out = s;
    return 0;
}
