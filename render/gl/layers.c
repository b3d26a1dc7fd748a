/* Layers: several datasets in one frame (docs/ALGORITHM.md "Layers"). Each
 * geometry pass draws every visible layer into the same targets, so the
 * layers share one G(d) and one tau(d); a layer's element ids start after
 * those of the layers before it, and P3 smooths each layer over its own
 * adjacency only. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "renderer_internal.h"

static const lc_frame_setup *layer_setup(const lc_frame_setup *fs, const lc_layer_setup *l, lc_frame_setup *tmp);

int lc_frame_layer_count(const lc_frame_setup *fs) { return fs->layer_count > 0 ? fs->layer_count : 1; }

const lc_frame_setup *lc_frame_layer(const lc_frame_setup *fs, int i, lc_frame_setup *tmp)
{
    if (fs->layer_count <= 0)
        return fs;
    const lc_layer_setup *l = &fs->layers[i];
    if (!l->visible || l->context)
        return NULL;
    return layer_setup(fs, l, tmp);
}

lc_layer_setup *lc_frame_layer_setup(lc_frame_setup *fs, int i)
{
    /* The set-ups are the frame's own (render() allocates them); fs holds them const for the passes that only read. */
    return (lc_layer_setup *)&fs->layers[i];
}

const lc_frame_setup *lc_frame_context_layer(const lc_frame_setup *fs, int i, lc_frame_setup *tmp)
{
    if (fs->layer_count <= 0 || !fs->layers[i].visible || !fs->layers[i].context)
        return NULL;
    return layer_setup(fs, &fs->layers[i], tmp);
}

int lc_frame_has_context(const lc_frame_setup *fs)
{
    for (int i = 0; i < fs->layer_count; i++)
        if (fs->layers[i].visible && fs->layers[i].context)
            return 1;
    return 0;
}

/* fs with layer l's scene, mapping, level and element offset in *tmp. */
static const lc_frame_setup *layer_setup(const lc_frame_setup *fs, const lc_layer_setup *l, lc_frame_setup *tmp)
{
    *tmp = *fs;
    tmp->gs = l->gs;
    tmp->params = &l->params;
    tmp->importance_attr = l->importance_attr;
    tmp->color_mode = l->color_mode;
    tmp->color_attr = l->color_attr;
    tmp->colormap = l->colormap;
    tmp->importance_range[0] = l->importance_range[0], tmp->importance_range[1] = l->importance_range[1];
    tmp->color_range[0] = l->color_range[0], tmp->color_range[1] = l->color_range[1];
    tmp->importance_exponent = l->importance_exponent;
    tmp->terms = l->terms;
    tmp->line_half_width = l->line_half_width;
    tmp->level = l->level;
    tmp->element_offset = l->element_offset;
    tmp->filtered = l->filtered;
    tmp->filter_mask = l->filter_mask;
    tmp->pull_lines = l->pull_lines;
    tmp->line_mask = l->line_mask;
    tmp->line_mask_buffer = l->line_mask_buffer;
    tmp->colormap_texture = l->colormap_texture;
    tmp->eq_slot = (int)(l - fs->layers);
    /* The programs the caller picks next draw this layer: pulled segments
     * where its time window hides single ones (lc_renderer_geometry_program). */
    fs->renderer->pull_lines = l->pull_lines;
    /* Per-dataset aids that a layered frame does not offer (lc_render_layers refuses them). */
    tmp->point_stride = 1;
    tmp->kept_points = 0;
    return tmp;
}

void lc_layers_bounds(const lc_gpu_scene *const *scenes, int n, double out[6])
{
    for (int k = 0; k < 3; k++)
        out[k] = INFINITY, out[k + 3] = -INFINITY;
    for (int i = 0; i < n; i++) {
        const double *b = scenes[i]->scene->bounds;
        for (int k = 0; k < 3; k++) {
            out[k] = b[k] < out[k] ? b[k] : out[k];
            out[k + 3] = b[k + 3] > out[k + 3] ? b[k + 3] : out[k + 3];
        }
    }
}

void lc_render_fit_camera(const lc_gpu_scene *const *scenes, int n, lc_camera *cam)
{
    double bounds[6];
    lc_layers_bounds(scenes, n, bounds);
    const lc_scene *s = scenes[0]->scene;
    cam->view_angle = cam->view_angle > 0 ? cam->view_angle : 30;
    lc_camera_fit(cam, bounds, s->has_view ? s->view_direction : NULL, s->has_view ? s->view_up : NULL);
}

/* Prefixes err's field with "layers[i]." so that a mapping error names the layer. */
static int layer_error(lc_error *err, int i, int rc)
{
    if (!err)
        return rc;
    lc_error e = *err;
    int n = snprintf(err->field, sizeof err->field, "layers[%d].", i);
    if (n > 0 && (size_t)n < sizeof err->field)
        memcpy(err->field + n, e.field, strnlen(e.field, sizeof err->field - (size_t)n - 1) + 1),
            err->field[sizeof err->field - 1] = '\0';
    n = snprintf(err->msg, sizeof err->msg, "layers[%d]: ", i);
    if (n > 0 && (size_t)n < sizeof err->msg)
        memcpy(err->msg + n, e.msg, strnlen(e.msg, sizeof err->msg - (size_t)n - 1) + 1),
            err->msg[sizeof err->msg - 1] = '\0';
    return rc;
}

int lc_frame_layers_prepare(lc_frame_setup *fs, const lc_gpu_scene *const *scenes, const lc_layer_params *layers, int n,
                            lc_layer_setup *out, lc_error *err)
{
    uint64_t offset = 0;
    for (int i = 0; i < n; i++) {
        lc_layer_setup *l = &out[i];
        const lc_layer_params *in = &layers[i];
        const lc_scene *s = scenes[i]->scene;
        memset(l, 0, sizeof *l);
        l->gs = scenes[i];
        l->visible = in->visible ? 1 : 0;
        l->context = in->role == LC_LAYER_CONTEXT;
        l->params = *fs->params;
        l->params.importance = in->importance;
        l->params.color = in->color;
        l->params.style.line_width = in->style.line_width;
        l->params.style.min_line_pixels = in->style.min_line_pixels;
        l->params.style.point_size = in->style.point_size;
        l->params.style.shading = in->style.shading;
        l->params.filter_count = in->filter_count;
        memcpy(l->params.filters, in->filters, sizeof l->params.filters);
        l->params.time = in->time;
        l->params.clusters = in->clusters;
        lc_frame_setup tmp = *fs;
        tmp.gs = l->gs;
        tmp.params = &l->params;
        int rc = lc_frame_resolve_mapping(&tmp, err);
        if (rc == 0 && l->visible)
            rc = lc_filter_prepare(fs->renderer, &tmp, err);
        if (rc == 0 && l->visible)
            rc = lc_line_clusters_prepare(fs->renderer, &tmp, err);
        if (rc)
            return layer_error(err, i, rc);
        l->filtered = tmp.filtered;
        l->filter_mask = tmp.filter_mask;
        l->pull_lines = tmp.pull_lines;
        l->line_mask = tmp.line_mask;
        l->line_mask_buffer = tmp.line_mask_buffer;
        l->importance_attr = tmp.importance_attr;
        l->color_mode = tmp.color_mode;
        l->color_attr = tmp.color_attr;
        l->colormap = tmp.colormap;
        memcpy(l->importance_range, tmp.importance_range, sizeof l->importance_range);
        memcpy(l->color_range, tmp.color_range, sizeof l->color_range);
        l->importance_exponent = tmp.importance_exponent;
        l->terms = tmp.terms;
        double diag = 0;
        for (int k = 0; k < 3; k++)
            diag += (s->bounds[k + 3] - s->bounds[k]) * (s->bounds[k + 3] - s->bounds[k]);
        l->line_half_width = 0.5 * (in->style.line_width > 0 ? in->style.line_width : 0.004 * sqrt(diag));
        l->level = lc_frame_pick_level(&tmp);
        l->element_offset = (uint32_t)offset;
        offset += s->elements.count; /* at most 2^24 in all (lc_render_check) */
    }
    fs->renderer->pull_lines = 0; /* lc_frame_layer sets it for each layer drawn */
    fs->layers = out;
    fs->layer_count = n;
    fs->element_total = (uint32_t)offset;
    return 0;
}
