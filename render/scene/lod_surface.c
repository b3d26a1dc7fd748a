/* Surface levels of detail (lod.h): the mesh simplified by meshoptimizer. */
#include <meshoptimizer.h>
#include <stdlib.h>
#include <string.h>

#include "lod.h"

/* meshoptimizer's error is its estimate of the geometric deviation, but the
 * image changes sooner: shading interpolates the full mesh's normals over the
 * larger triangles, and the opacity optimization follows coverage. Measured
 * on the surface demo, the first level (a third of the triangles) drew SSIM
 * 0.973-0.985 against every triangle when its estimate was under 0.2 px; a
 * level counts as this many times its estimate, so still frames keep every
 * triangle there and interactive frames (1-8 px) simplify. */
#define SURFACE_ERROR_SCALE 8.0

/* Levels simplify the level before (cheaper than starting over each time), at
 * every second step of the ladder (error x 2): a level's error is the sum of
 * the steps that led to it, below twice its own step. The whole mesh is
 * simplified at once: with each patch's border locked, the small patches of
 * a surface (tens of triangles, mostly border) would not simplify at all. A
 * patch may lose its triangles at coarse levels; its element then gets no
 * fragments in those frames (the interactive ones, which reuse opacities). */
int lc_lod_surface_levels(const lc_scene *s, lc_lod *out, int with_indices, lc_error *err)
{
    uint32_t nt = s->triangle_count, nv = s->vertex_count;
    uint64_t cur_count = nt;
    uint32_t *cur = malloc((nt ? nt : 1) * 3 * sizeof(uint32_t)), *next = malloc((nt ? nt : 1) * 3 * sizeof(uint32_t));
    int rc = cur && next ? 0 : -1;
    if (!rc)
        memcpy(cur, s->triangles, (size_t)nt * 3 * sizeof(uint32_t));
    float scale = nv ? meshopt_simplifyScale(s->positions, nv, 3 * sizeof(float)) : 0;
    double sum = 0;
    for (int j = 0; rc == 0 && scale > 0 && j < LC_LOD_LADDER_STEPS && out->count < LC_LOD_MAX_LEVELS; j += 2) {
        double step = lc_lod_threshold(s, j);
        size_t k = meshopt_simplify(next, cur, 3 * (size_t)cur_count, s->positions, nv, 3 * sizeof(float), 0,
                                    (float)(step / scale), 0, NULL);
        if (k == 0 || k / 3 >= cur_count)
            continue; /* nothing gained at this error (or everything would vanish) */
        sum += step;
        cur_count = k / 3;
        uint32_t *t = cur;
        cur = next, next = t;
        if ((double)cur_count > LC_LOD_SHRINK * (double)out->levels[out->count - 1].primitives)
            continue; /* not a level yet: the next step starts from it */
        lc_lod_level *lv = &out->levels[out->count++];
        lv->error = SURFACE_ERROR_SCALE * sum;
        lv->primitives = cur_count;
        if (with_indices) {
            lv->indices = malloc(cur_count * 3 * sizeof(uint32_t));
            if (!lv->indices)
                rc = -1;
            else
                memcpy(lv->indices, cur, cur_count * 3 * sizeof(uint32_t));
        }
    }
    free(cur);
    free(next);
    if (rc)
        return lc_err(err, LC_ERR_NOMEM, "%s: out of memory for the level-of-detail hierarchy", s->name);
    return 0;
}
