/* The renderer's refusals, without GL (frame_check.h says who calls it). Each
 * names the request field to change, and says how. */
#include <stdio.h>
#include <string.h>

#include "cluster.h"
#include "frame_check.h"
#include "renderer.h" /* lc_pass_plan_tiles */

/* What a layered frame leaves out, each refused naming its field. */
static int check_layered(const lc_scene *const *scenes, const lc_layer_params *layers, int n, const lc_render_params *p,
                         lc_error *err)
{
    if (n < 1 || n > LC_MAX_LAYERS)
        return lc_err_field(err, LC_ERR_INVALID, "layers", "%d layers; 1 to %d are allowed", n, LC_MAX_LAYERS);
    if (p->method == LC_METHOD_OPAQUE || p->method == LC_METHOD_WBOIT || p->method == LC_METHOD_KANZLER)
        return lc_err_field(err, LC_ERR_INVALID, "method",
                            "layers render with fourier, exact, direct, weighted-average or binning, not %s",
                            lc_method_name(p->method));
    if (p->filter_count > 0)
        return lc_err_field(err, LC_ERR_INVALID, "filter",
                            "a layered frame's filters are its layers': layers[i].filter");
    if (p->time.has_window)
        return lc_err_field(err, LC_ERR_INVALID, "time.window",
                            "a layered frame's time windows are its layers': layers[i].time");
    if (p->clusters.count > 0)
        return lc_err_field(err, LC_ERR_INVALID, "lines.clusters",
                            "a layered frame's clusters are its layers': layers[i].lines");
    if (p->color.equalize)
        return lc_err_field(err, LC_ERR_INVALID, "color.equalize",
                            "a layered frame's equalization is its layers': layers[i].color.equalize");
    if (p->foo.guard_band > 0)
        return lc_err_field(err, LC_ERR_INVALID, "params.guardBand", "not with layers");
    uint64_t elements = 0;
    for (int i = 0; i < n; i++) {
        if (layers[i].role == LC_LAYER_CONTEXT && scenes[i]->type == LC_PRIM_POINTS) {
            char field[32];
            snprintf(field, sizeof field, "layers[%d].role", i);
            return lc_err_field(err, LC_ERR_INVALID, field, "a context layer is lines or a surface; %s is points",
                                scenes[i]->name);
        }
        elements += scenes[i]->elements.count;
    }
    if (elements > (1u << 24)) /* the elements of all layers share the renderer's buffers */
        return lc_err_field(err, LC_ERR_INVALID, "layers", "the layers hold %llu elements, more than %u",
                            (unsigned long long)elements, 1u << 24);
    return 0;
}

/* Attribute names of the importance and colour mapping (prefix: "" or "layers[i]."). */
static int check_mapping(const lc_scene *s, const lc_importance_map *imp, const lc_color_map *col, const char *prefix,
                         lc_error *err)
{
    char field[64];
    double sum_abs = 0;
    for (int i = 0; i < imp->term_count && i < LC_MAX_IMPORTANCE_TERMS; i++) {
        snprintf(field, sizeof field, "%simportance.terms[%d].attribute", prefix, i);
        if (lc_scene_find_attribute(s, imp->terms[i].attribute) < 0)
            return lc_err_field(err, LC_ERR_INVALID, field, "%s has no attribute \"%s\"", s->name,
                                imp->terms[i].attribute);
        sum_abs += imp->terms[i].weight < 0 ? -imp->terms[i].weight : imp->terms[i].weight;
    }
    if (imp->term_count > 0 && !(sum_abs > 0)) {
        snprintf(field, sizeof field, "%simportance.terms", prefix);
        return lc_err_field(err, LC_ERR_INVALID, field, "every weight is 0");
    }
    const char *a = imp->attribute[0] ? imp->attribute : s->default_importance;
    if (imp->term_count == 0 && a[0] && lc_scene_find_attribute(s, a) < 0) {
        snprintf(field, sizeof field, "%simportance.attribute", prefix);
        return lc_err_field(err, LC_ERR_INVALID, field, "%s has no attribute \"%s\"", s->name, a);
    }
    const char *c = col->attribute[0] ? col->attribute : s->default_color;
    snprintf(field, sizeof field, "%scolor.attribute", prefix);
    if (strcmp(c, "rgb") == 0 && !lc_scene_has_rgb(s))
        return lc_err_field(err, LC_ERR_INVALID, field, "%s has no per-vertex RGB", s->name);
    if (c[0] && strcmp(c, "rgb") != 0 && strcmp(c, "importance") != 0 && lc_scene_find_attribute(s, c) < 0)
        return lc_err_field(err, LC_ERR_INVALID, field, "%s has no attribute \"%s\"", s->name, c);
    return 0;
}

/* color.equalize of one mapping (prefix: "" or "layers[i]."; a layer's with
 * fourier or direct, untiled: exact_ok and tiles say which frame it is in). */
static int check_equalize(const lc_scene *s, const lc_color_map *col, lc_method m, const char *prefix, int exact_ok,
                          int tiles, lc_error *err)
{
    if (!col->equalize)
        return 0;
    char field[48];
    snprintf(field, sizeof field, "%scolor.equalize", prefix);
    if (m != LC_METHOD_FOURIER && m != LC_METHOD_DIRECT && !(exact_ok && m == LC_METHOD_EXACT))
        return lc_err_field(err, LC_ERR_INVALID, field,
                            "equalized colour needs method \"fourier\", \"direct\"%s, not \"%s\"",
                            exact_ok ? " or \"exact\"" : " (a layer's)", lc_method_name(m));
    if (!exact_ok && tiles)
        return lc_err_field(err, LC_ERR_INVALID, field,
                            "a layer's equalized colour is measured on one untiled frame: "
                            "render at most 4096x4096");
    const char *c = col->attribute[0] ? col->attribute : s->default_color;
    if (strcmp(c, "rgb") == 0)
        return lc_err_field(err, LC_ERR_INVALID, field, "per-vertex RGB colour has no colormap to equalize");
    snprintf(field, sizeof field, "%scolor.fixed", prefix);
    if (col->fixed_count > 0 && col->curve.count > 0)
        return lc_err_field(err, LC_ERR_INVALID, field, "fixed ranges cannot be combined with color.curve");
    return 0;
}

/* Hard filters and the time window of one dataset (prefix: "" or "layers[i]."). */
static int check_filters(const lc_scene *s, const lc_filter *filters, int count, const lc_time_window *t,
                         const char *prefix, lc_error *err)
{
    char field[64];
    for (int i = 0; i < count; i++) {
        const lc_filter *f = &filters[i];
        snprintf(field, sizeof field, "%sfilter[%d].attribute", prefix, i);
        if (lc_scene_find_attribute(s, f->attribute) < 0)
            return lc_err_field(err, LC_ERR_INVALID, field, "%s has no attribute \"%s\"", s->name, f->attribute);
        snprintf(field, sizeof field, "%sfilter[%d].over", prefix, i);
        if (s->type == LC_PRIM_TRIANGLES)
            return lc_err_field(err, LC_ERR_INVALID, field, "%s is a surface: only lines and points can be filtered",
                                s->name);
        if (s->type == LC_PRIM_POINTS && f->over != LC_FILTER_VERTEX)
            return lc_err_field(err, LC_ERR_INVALID, field, "%s has points, not lines: use \"vertex\"", s->name);
        if (s->type == LC_PRIM_LINES && f->over == LC_FILTER_VERTEX)
            return lc_err_field(err, LC_ERR_INVALID, field,
                                "%s has lines: filter them by min, max, mean, first, last or change", s->name);
        if (s->type == LC_PRIM_LINES && !s->line_offsets)
            return lc_err_field(err, LC_ERR_INVALID, field, "%s keeps no line offsets", s->name);
    }
    if (!t->has_window)
        return 0;
    snprintf(field, sizeof field, "%stime.window", prefix);
    if (!(t->window[0] <= t->window[1]))
        return lc_err_field(err, LC_ERR_INVALID, field, "t0 %g is after t1 %g", t->window[0], t->window[1]);
    if (s->type == LC_PRIM_TRIANGLES)
        return lc_err_field(err, LC_ERR_INVALID, field, "%s is a surface: time windows apply to lines and points",
                            s->name);
    if (s->type == LC_PRIM_LINES && !s->line_offsets)
        return lc_err_field(err, LC_ERR_INVALID, field, "%s keeps no line offsets", s->name);
    if (count >= LC_MAX_FILTERS)
        return lc_err_field(err, LC_ERR_INVALID, field, "at most %d filters with a time window", LC_MAX_FILTERS - 1);
    if (lc_scene_time_attribute(s, t->attribute) >= 0)
        return 0;
    snprintf(field, sizeof field, "%stime.attribute", prefix);
    if (t->attribute[0])
        return lc_err_field(err, LC_ERR_INVALID, field, "%s has no attribute \"%s\"", s->name, t->attribute);
    return lc_err_field(err, LC_ERR_INVALID, field,
                        "%s has no time: no attribute time, t, frame or timestep (name one in %stime.attribute)",
                        s->name, prefix);
}

/* lines.clusters of one dataset (prefix: "" or "layers[i]."). */
static int check_clusters(const lc_scene *s, const lc_line_cluster_params *c, const char *prefix, lc_error *err)
{
    char field[48];
    snprintf(field, sizeof field, "%slines.clusters", prefix);
    if (c->count > 0 && s->type != LC_PRIM_LINES && prefix[0]) /* one dataset: protocol's scope table refuses lines.* */
        return lc_err_field(err, LC_ERR_INVALID, field, "%s is not lines: clusters group lines", s->name);
    if (c->count <= 0 || s->type != LC_PRIM_LINES)
        return 0;
    if (s->line_count > LC_CLUSTER_MAX_LINES)
        return lc_err_field(err, LC_ERR_UNSUPPORTED, field, "%s has %u lines; clustering is limited to %u lines",
                            s->name, s->line_count, LC_CLUSTER_MAX_LINES);
    if (s->part_of > 0 || s->vertex_base > 0)
        return lc_err_field(err, LC_ERR_UNSUPPORTED, field,
                            "%s is split across processes; clustering needs every line in one process", s->name);
    return 0;
}

/* Method kanzler (docs/ALGORITHM.md §28): its maps are a dataset's lines or
 * points at one resolution; layers are refused with the other methods. */
static int check_kanzler(const lc_scene *s, int tiles, lc_error *err)
{
    if (s->type == LC_PRIM_TRIANGLES)
        return lc_err_field(err, LC_ERR_INVALID, "method",
                            "%s is a surface: method \"kanzler\" applies to lines and points", s->name);
    if (tiles)
        return lc_err_field(err, LC_ERR_INVALID, "width",
                            "method \"kanzler\" blurs its maps over the whole frame: render at most 4096x4096");
    return 0;
}

int lc_render_ground_drawn(const lc_render_params *p, int has_context)
{
    if (p->method != LC_METHOD_FOURIER && p->method != LC_METHOD_DIRECT)
        return 0;
    return p->style.ground == LC_GROUND_ON ||
           (p->style.ground == LC_GROUND_AUTO && p->style.shadow > 0 && !has_context);
}

/* params.progressive (progressive.c): the Fourier method's sums, kept by one
 * renderer frame to frame for one dataset drawn in full; what would draw other
 * primitives, or only some, in a pass is refused naming its field. */
static int check_progressive(const lc_render_params *p, int layered, int tiles, lc_error *err)
{
    const lc_foo_params *foo = &p->foo;
    if (foo->progressive <= 1)
        return 0;
    const char *f = "params.progressive", *why = NULL;
    if (p->method != LC_METHOD_FOURIER)
        why = "batches add into the Fourier method's sums: use method \"fourier\"";
    else if (layered)
        why = "one dataset's batches, not layers";
    else if (tiles)
        why = "the sums are kept for one untiled frame: render at most 4096x4096";
    else if (foo->subset > 1 || foo->auto_subset > 1)
        why = "batches draw every primitive once: not with params.subset or params.autoSubset";
    else if (foo->guard_band > 0)
        why = "not with params.guardBand";
    else if (p->style.antialias > 1)
        why = "a still's jittered samples each draw every primitive: style.antialias 1";
    else if (p->style.shadow > 0 || p->style.ground == LC_GROUND_ON)
        why = "the light's map draws every primitive: no style.shadow or style.ground";
    else if (p->detail.point_stride > 1 || p->detail.line_stride > 1)
        why = "a moving frame's strides draw some primitives: batches are for the still";
    else if (foo->batch < 0 || foo->batch > foo->progressive)
        return lc_err_field(err, LC_ERR_INVALID, f, "batch %d of %d", foo->batch, foo->progressive);
    return why ? lc_err_field(err, LC_ERR_INVALID, f, "%s", why) : 0;
}

/* Ground shadows and smart transparency (docs/ALGORITHM.md §29): whether they
 * have something to work on, and frames they cannot be drawn in. */
static int check_shadows(const lc_render_params *p, int context, int tiles, int jittered, lc_error *err)
{
    const lc_style *st = &p->style;
    /* Other methods draw none of them: a request that gives them there is
     * refused by the scope table; a session that keeps them from an earlier
     * method's update draws without them until it returns. */
    if (p->method != LC_METHOD_FOURIER && p->method != LC_METHOD_DIRECT)
        return 0;
    int ground = lc_render_ground_drawn(p, context);
    if (st->shadow > 0 && !context && !ground)
        return lc_err_field(err, LC_ERR_INVALID, "style.shadow",
                            "nothing receives the shadow: set style.ground \"auto\" or \"on\", or add a context layer");
    const char *field = st->ground == LC_GROUND_ON ? "style.ground" : "style.shadow";
    /* The shadows shade the context once, for the frame's own view: a tile or
     * a jittered sample that draws its context anew would lose them. */
    if ((ground || st->shadow > 0) && (tiles || jittered))
        return lc_err_field(err, LC_ERR_INVALID, field,
                            "shadows and the ground plane are drawn in one untiled, "
                            "unjittered frame: %s",
                            tiles ? "render at most 4096x4096" : "antialias 1");
    if (ground && p->foo.guard_band > 0) /* the context is drawn for the view, the optimization sees a wider one */
        return lc_err_field(err, LC_ERR_INVALID, field, "not with params.guardBand");
    if (st->smart > 0 && tiles) /* the diffusion would stop at every tile's edge */
        return lc_err_field(err, LC_ERR_INVALID, "style.smartTransparency",
                            "drawn over one untiled image: render at most 4096x4096");
    return 0;
}

int lc_render_check(const lc_scene *const *scenes, const lc_layer_params *layers, int n, const lc_render_params *p,
                    int tile_size, lc_error *err)
{
    if (p->method == LC_METHOD_SURFACE_LAYERS) /* a field's surface: lc_surface_render checks its own */
        return 0;
    int rc = 0, context = 0, nx, ny, tiles = lc_pass_plan_tiles(p, tile_size, &nx, &ny);
    if (layers) {
        if ((rc = check_layered(scenes, layers, n, p, err)) != 0)
            return rc;
        for (int i = 0; i < n; i++) {
            char prefix[40];
            snprintf(prefix, sizeof prefix, "layers[%d].", i);
            if ((rc = check_mapping(scenes[i], &layers[i].importance, &layers[i].color, prefix, err)) != 0 ||
                (rc = check_filters(scenes[i], layers[i].filters, layers[i].filter_count, &layers[i].time, prefix,
                                    err)) != 0 ||
                (rc = check_clusters(scenes[i], &layers[i].clusters, prefix, err)) != 0 ||
                (rc = check_equalize(scenes[i], &layers[i].color, p->method, prefix, 0, tiles, err)) != 0)
                return rc;
            context |= layers[i].visible && layers[i].role == LC_LAYER_CONTEXT;
            if (layers[i].color.equalize && layers[i].role == LC_LAYER_CONTEXT) {
                snprintf(prefix, sizeof prefix, "layers[%d].color.equalize", i);
                return lc_err_field(err, LC_ERR_INVALID, prefix,
                                    "a context layer is drawn opaque before any visibility is measured: equalize "
                                    "transparent layers");
            }
            if (layers[i].time.markers && layers[i].time.has_window) {
                snprintf(prefix, sizeof prefix, "layers[%d].time.markers", i);
                return lc_err_field(err, LC_ERR_INVALID, prefix, "markers are drawn for a frame of one dataset");
            }
        }
    } else {
        const lc_scene *s = scenes[0];
        if ((rc = check_mapping(s, &p->importance, &p->color, "", err)) != 0 ||
            (rc = check_equalize(s, &p->color, p->method, "", 1, tiles, err)) != 0 ||
            (rc = check_filters(s, p->filters, p->filter_count, &p->time, "", err)) != 0 ||
            (rc = check_clusters(s, &p->clusters, "", err)) != 0)
            return rc;
    }
    if (p->method == LC_METHOD_KANZLER && (rc = check_kanzler(scenes[0], tiles, err)) != 0)
        return rc;
    if ((rc = check_progressive(p, layers != NULL, tiles, err)) != 0)
        return rc;
    int jittered = p->method != LC_METHOD_EXACT && p->method != LC_METHOD_OPAQUE && p->style.antialias > 1;
    if (p->foo.guard_band > 0 && p->foo.depth_range == LC_DEPTH_RANGE_PIXEL)
        return lc_err_field(err, LC_ERR_INVALID, "params.guardBand",
                            "the optimization's wider view needs depthRange \"global\", \"moments\" or \"auto\", "
                            "not \"pixel\"");
    return check_shadows(p, context, tiles, jittered, err);
}
