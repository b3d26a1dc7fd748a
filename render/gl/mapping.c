/* A frame's attribute mapping (importance, terms, colour) and level of detail
 * for one dataset: frame.c calls them for its scene, layers.c for each layer. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "colormap.h"
#include "renderer_internal.h"

/* The range an importance attribute maps from when the request gives none:
 * auto: min/max without the outliers, unless that collapses (e.g. a mostly
 * constant attribute); off: min/max. */
static void default_range(const lc_render_params *p, const lc_attribute *a, double out[2])
{
    int robust = p->foo.normalize == LC_NORMALIZE_AUTO && a->auto_hi > a->auto_lo;
    out[0] = robust ? a->auto_lo : a->min;
    out[1] = robust ? a->auto_hi : a->max;
}

/* lc_render_check (frame_check.c) refuses a mapping the scene cannot resolve,
 * naming the field; reaching one here means a caller skipped it. */
static int unchecked(lc_error *err, const char *field)
{
    return lc_err_field(err, LC_ERR_INTERNAL, field, "the mapping was not checked against the scene");
}

/* The weighted terms (docs/ALGORITHM.md "Importance terms"); the first
 * term's attribute also stands in importance_attr, so "g = 1" stays off. */
static int resolve_terms(lc_frame_setup *fs, lc_error *err)
{
    const lc_importance_map *m = &fs->params->importance;
    const lc_scene *s = fs->gs->scene;
    lc_importance_terms *t = &fs->terms;
    double sum = 0, sum_abs = 0;
    for (int i = 0; i < m->term_count && i < LC_MAX_IMPORTANCE_TERMS; i++) {
        const lc_importance_term *in = &m->terms[i];
        if ((t->attr[i] = lc_scene_find_attribute(s, in->attribute)) < 0)
            return unchecked(err, "importance.terms");
        if (in->has_range)
            t->range[i][0] = in->range[0], t->range[i][1] = in->range[1];
        else
            default_range(fs->params, &s->attributes[t->attr[i]], t->range[i]);
        t->weight[i] = in->weight;
        t->invert[i] = in->invert ? 1 : 0;
        sum += in->weight;
        sum_abs += fabs(in->weight);
        t->count = i + 1;
    }
    if (!(sum_abs > 0))
        return unchecked(err, "importance.terms");
    t->norm = 1.0 / sum_abs;
    t->penalty = sum < 0;
    fs->importance_attr = t->attr[0];
    fs->importance_range[0] = t->range[0][0], fs->importance_range[1] = t->range[0][1];
    return 0;
}

int lc_frame_resolve_mapping(lc_frame_setup *fs, lc_error *err)
{
    const lc_render_params *p = fs->params;
    const lc_scene *s = fs->gs->scene;
    const char *imp = p->importance.attribute[0] ? p->importance.attribute : s->default_importance;
    fs->importance_attr = -1;
    fs->importance_range[0] = 0, fs->importance_range[1] = 1;
    memset(&fs->terms, 0, sizeof fs->terms);
    if (p->importance.term_count > 0) {
        int rc = resolve_terms(fs, err);
        if (rc)
            return rc;
    } else if (imp[0]) {
        if ((fs->importance_attr = lc_scene_find_attribute(s, imp)) < 0)
            return unchecked(err, "importance.attribute");
        default_range(p, &s->attributes[fs->importance_attr], fs->importance_range);
        if (p->importance.has_range)
            fs->importance_range[0] = p->importance.range[0], fs->importance_range[1] = p->importance.range[1];
        /* The mapping inverts a range given max first; importance.invert flips
         * the attribute's own direction (smaller matters more for a magnitude). */
        if (p->importance.invert != s->attributes[fs->importance_attr].smaller_matters) {
            double lo = fs->importance_range[0];
            fs->importance_range[0] = fs->importance_range[1], fs->importance_range[1] = lo;
        }
    }
    fs->importance_exponent = p->importance.exponent > 0 ? p->importance.exponent : 1.0;
    fs->terms.curve_count = p->importance.curve.count;
    for (int i = 0; i < p->importance.curve.count; i++)
        fs->terms.curve[i][0] = (float)p->importance.curve.points[i][0],
        fs->terms.curve[i][1] = (float)p->importance.curve.points[i][1];

    const char *col = p->color.attribute[0] ? p->color.attribute : s->default_color;
    if (!col[0])
        col = "importance";
    fs->color_attr = -1;
    fs->color_range[0] = 0, fs->color_range[1] = 1;
    if (strcmp(col, "rgb") == 0) {
        if (!lc_scene_has_rgb(s))
            return unchecked(err, "color.attribute");
        fs->color_mode = 2;
    } else if (strcmp(col, "importance") == 0) {
        fs->color_mode = 1;
    } else {
        if ((fs->color_attr = lc_scene_find_attribute(s, col)) < 0)
            return unchecked(err, "color.attribute");
        fs->color_mode = 0;
        /* The same range as importance: auto drops the outliers, so one
         * extreme value cannot turn the picture one colour. */
        const lc_attribute *a = &s->attributes[fs->color_attr];
        int robust = p->foo.normalize == LC_NORMALIZE_AUTO && a->auto_hi > a->auto_lo;
        fs->color_range[0] = robust ? a->auto_lo : a->min;
        fs->color_range[1] = robust ? a->auto_hi : a->max;
    }
    if (p->color.has_range)
        fs->color_range[0] = p->color.range[0], fs->color_range[1] = p->color.range[1];
    fs->colormap = lc_colormap_find(p->color.colormap[0] ? p->color.colormap : "viridis");
    if (fs->colormap < 0)
        return lc_err_field(err, LC_ERR_INVALID, "color.colormap", "unknown colormap \"%s\"", p->color.colormap);
    return 0;
}

/* The coarsest level whose simplification error stays under lod_pixels
 * output pixels, measured at the nearest depth of the data's bounds, so that
 * it bounds the error of every vertex on screen. */
int lc_frame_pick_level(const lc_frame_setup *fs)
{
    const lc_render_params *p = fs->params;
    const lc_gpu_scene *gs = fs->gs;
    if (gs->level_count <= 1 || !(p->detail.lod_pixels > 0))
        return 0;
    double pixel = fs->view.pixel_world;
    if (!p->camera.parallel_projection) {
        double focal = lc_frame_focal_distance(fs);
        if (!(focal > 0))
            return 0;
        pixel *= fs->view.depth_min / focal;
    }
    double bound = p->detail.lod_pixels * pixel;
    int best = 0;
    for (int i = 1; i < gs->level_count; i++)
        if (gs->levels[i].error <= bound)
            best = i;
    return best;
}
