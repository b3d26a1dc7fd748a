/* Surface levels of detail (lod.h): the mesh simplified by meshoptimizer. */
#include <meshoptimizer.h>
#include <stdlib.h>
#include <string.h>

#include "lod.h"

/* meshoptimizer's error is its estimate of the geometric deviation, but the
 * image changes sooner: shading interpolates the full mesh's normals over the
 * larger triangles, and the opacity optimization follows coverage. Measured
 * on the surface demo, a first level drew SSIM 0.973-0.985 against every
 * triangle when its estimate was under 0.2 px; a level counts as this many
 * times its estimate, so still frames keep every triangle there and
 * interactive frames (1-8 px) simplify. With halving levels, the demo's first
 * level (half the triangles) is drawn from 0.5 px at 512x512, SSIM 0.989. */
#define SURFACE_ERROR_SCALE 8.0

/* Each level simplifies the level before to half its triangles (cheaper than
 * starting over each time: the calls cost about twice the first one, where
 * error-bounded steps up a fine ladder each paid for the whole mesh and took a
 * minute for 6 M triangles). Its error is the sum of meshoptimizer's achieved
 * errors along the chain, a bound on its deviation from the full mesh. The
 * whole mesh is simplified at once: with each patch's border locked, the small
 * patches of a surface (tens of triangles, mostly border) would not simplify
 * at all. A patch may lose its triangles at coarse levels; its element then
 * gets no fragments in those frames (the interactive ones, which reuse
 * opacities). */
#define SURFACE_MIN_TRIANGLES 64

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
    while (rc == 0 && scale > 0 && out->count < LC_LOD_MAX_LEVELS && cur_count >= 2 * SURFACE_MIN_TRIANGLES) {
        size_t target = 3 * (size_t)(LC_LOD_SHRINK * (double)cur_count);
        float achieved = 0;
        /* Error cap: the ladder's coarsest step, far beyond any useful level. */
        size_t k = meshopt_simplify(next, cur, 3 * (size_t)cur_count, s->positions, nv, 3 * sizeof(float), target,
                                    (float)(lc_lod_threshold(s, LC_LOD_LADDER_STEPS - 1) / scale), 0, &achieved);
        if (k == 0 || k / 3 >= cur_count)
            break; /* nothing more to gain (or everything would vanish) */
        sum += (double)achieved * scale;
        cur_count = k / 3;
        uint32_t *t = cur;
        cur = next, next = t;
        if ((double)cur_count > LC_LOD_SHRINK * (double)out->levels[out->count - 1].primitives)
            continue; /* not a level yet: the next call starts from it */
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
