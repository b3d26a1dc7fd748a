/* The elements of a scene by its primitive type: one per point, the lines'
 * equal-arc-length segments (elements_lines.c), the surfaces' patches
 * (elements.c). Above both builders, so that neither calls back up. */
#include <stdlib.h>

#include "elements.h"

/* ---- points: one element per point, no adjacency. FOO §4 treats points as
 * independent elements; there is no surface to smooth over, and a kNN graph
 * over millions of points would cost more than it buys. */
static int build_points(const lc_element_geometry *s, lc_elements *e, lc_error *err)
{
    int rc = lc_elements_alloc(e, s->vertex_count, s->vertex_count, s->name, err);
    if (rc)
        return rc;
    for (uint32_t v = 0; v < s->vertex_count; v++) {
        float w = 1.0f;
        lc_elements_set_vertex(e, v, 1, &v, &w, v);
    }
    e->adjacency = malloc(sizeof(uint32_t));
    if (!e->adjacency)
        return lc_err(err, LC_ERR_NOMEM, "%s: cannot allocate element adjacency", s->name);
    e->adjacency_count = 0;
    return LC_OK;
}

int lc_elements_build(const lc_element_geometry *s, const lc_elements_desc *desc, lc_elements *e, lc_error *err)
{
    if (!s || !e)
        return lc_err(err, LC_ERR_INVALID, "elements: NULL geometry");
    lc_elements_free(e);
    int rc;
    switch (s->type) {
    case LC_PRIM_POINTS: rc = build_points(s, e, err); break;
    case LC_PRIM_LINES:
        rc = lc_elements_build_lines(s, e, desc && desc->line_budget ? desc->line_budget : lc_elements_default_count(s),
                                     err);
        break;
    case LC_PRIM_TRIANGLES: {
        uint32_t want = desc && desc->patch_count ? desc->patch_count : lc_elements_default_count(s);
        rc =
            lc_elements_build_patches(s, e, want ? want : 1, desc ? desc->patch_sampling : LC_PATCH_SAMPLING_AUTO, err);
        break;
    }
    default: rc = lc_err(err, LC_ERR_INVALID, "%s: unknown primitive type", s->name);
    }
    if (rc)
        lc_elements_free(e);
    return rc;
}
