/* The levels of detail of a scene by its primitive type: the lines'
 * simplification hierarchy (lod.c) or the simplified surface (lod_surface.c).
 * Above both, so that neither calls back up. */
#include <string.h>

#include "lod.h"

static int build(const lc_scene *s, lc_lod *out, int with_indices, lc_error *err)
{
    memset(out, 0, sizeof *out);
    out->count = 1;
    out->levels[0].primitives = lc_scene_primitive_count(s);
    if (s->type == LC_PRIM_TRIANGLES)
        return lc_lod_surface_levels(s, out, with_indices, err);
    if (s->type != LC_PRIM_LINES)
        return 0;
    int rc = lc_lod_line_levels(s, out, with_indices, err);
    if (rc)
        lc_lod_free(out);
    return rc;
}

int lc_lod_plan(const lc_scene *s, lc_lod *out, lc_error *err) { return build(s, out, 0, err); }

int lc_lod_build(const lc_scene *s, lc_lod *out, lc_error *err) { return build(s, out, 1, err); }
