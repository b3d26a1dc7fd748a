/* The levels of detail of a scene by its primitive type: the lines'
 * simplification hierarchy (lod.c) or the simplified surface (lod_surface.c).
 * Above both, so that neither calls back up. */
#include <stdlib.h>
#include <string.h>

#include "lod.h"

/* Copies levels built before (a scene cache's, scene.h lod). */
static int copy_levels(const lc_scene *s, lc_lod *out, int with_indices, lc_error *err)
{
    *out = *s->lod;
    for (int i = 0; i < out->count; i++) {
        const uint32_t *from = s->lod->levels[i].indices;
        out->levels[i].indices = NULL;
        if (!with_indices || !from)
            continue;
        size_t n = out->levels[i].primitives * (s->type == LC_PRIM_LINES ? 2 : 3);
        if (!(out->levels[i].indices = malloc(n ? n * sizeof *from : 1))) {
            lc_lod_free(out);
            return lc_err(err, LC_ERR_NOMEM, "%s: cannot copy the levels of detail", s->name);
        }
        memcpy(out->levels[i].indices, from, n * sizeof *from);
    }
    return 0;
}

static int build(const lc_scene *s, lc_lod *out, int with_indices, lc_error *err)
{
    memset(out, 0, sizeof *out);
    if (s->lod)
        return copy_levels(s, out, with_indices, err);
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
