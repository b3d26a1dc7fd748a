/* Defaults and names of the plain-data render parameters. */
#include "lc_params.h"

#include <string.h>

void lc_foo_params_default(lc_foo_params *p)
{
    memset(p, 0, sizeof *p);
    p->q = 60;
    p->r = 500;
    p->lambda = 1;
    p->bands = 5;
    p->smoothing = 15;
    p->smoothing_weight = 0.1;
    p->fade_half_life = 0.15;
    p->resolution_scale = 0.5;
    p->subset = 1;
    p->auto_subset = LC_AUTO_SUBSET_DEFAULT;
    p->progressive = 1; /* one frame */
    p->depth_margin = 0.02;
    p->estimator = LC_ESTIMATOR_MIDPOINT;
    p->depth_range = LC_DEPTH_RANGE_AUTO;
    p->direct_exponent = 2;
    p->alpha_source = LC_ALPHA_IMPORTANCE;
    p->alpha_constant = 0.3;
    p->gamma = 1;
    /* Kanzler's weights: the thesis gives none, these are ours (docs/ALGORITHM.md §28). */
    p->kanzler_importance = 1;
    p->kanzler_coverage = 0.05;
    p->kanzler_variance = 1;
    p->kanzler_depth = 2;
    p->kanzler_lambda = 1;
    p->normalize = LC_NORMALIZE_AUTO;
    p->target_opacity = 1;
}

void lc_style_default(lc_style *s)
{
    memset(s, 0, sizeof *s);
    s->background[0] = s->background[1] = s->background[2] = 1.0;
    s->line_width = 0; /* 0 = derived from the data bounds by the renderer */
    s->min_line_pixels = 1.0;
    s->point_size = 2;
    s->shading = LC_SHADING_PHONG;
    s->silhouette_exponent = 1;
    s->halo_depth = 0.02;
    s->halo_strength = 1;
    s->antialias = 1;
    /* shadow_light 0: the up vector of the dataset's suggested view (shadow.c) */
    s->ground_color[0] = s->ground_color[1] = s->ground_color[2] = 0.8;
    s->ground_offset = 0.02;
    s->smart_iterations = 5; /* OOS §6 */
}

void lc_render_params_default(lc_render_params *p)
{
    memset(p, 0, sizeof *p);
    p->width = 1024;
    p->height = 768;
    p->method = LC_METHOD_FOURIER;
    lc_foo_params_default(&p->foo);
    lc_style_default(&p->style);
    p->detail.lod_pixels = LC_DEFAULT_LOD_PIXELS;
    p->detail.point_stride = 1;
    p->importance.exponent = 1;
    p->camera.view_angle = 30;
    p->camera.view_up[1] = 1;
    p->camera.parallel_scale = 1;
    /* color.attribute "": the dataset's default colour (docs/GUIDE.md "Default attributes") */
    strcpy(p->color.colormap, "viridis");
    p->color.fade_half_life = 0.8; /* DLS §5.3 */
}

void lc_layer_params_default(lc_layer_params *l)
{
    lc_render_params p;
    lc_render_params_default(&p);
    memset(l, 0, sizeof *l);
    l->role = LC_LAYER_TRANSPARENT;
    l->visible = true;
    l->importance = p.importance;
    l->color = p.color;
    l->style = p.style;
}

static const char *method_names[LC_METHOD_COUNT] = {
    "fourier", "exact", "opaque", "direct", "wboit", "surface-layers", "weighted-average", "binning", "kanzler"};

const char *lc_method_name(lc_method m) { return (unsigned)m < LC_METHOD_COUNT ? method_names[m] : "unknown"; }

int lc_method_from_name(const char *name)
{
    for (int i = 0; i < LC_METHOD_COUNT; i++)
        if (name && strcmp(name, method_names[i]) == 0)
            return i;
    return -1;
}

const char *lc_estimator_name(lc_estimator e) { return e == LC_ESTIMATOR_FOO ? "foo" : "midpoint"; }

const char *const lc_colormap_names[] = {LC_COLORMAP_LIST(LC_COLORMAP_NAME_ENTRY) NULL};
