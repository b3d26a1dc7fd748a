/* One frame of a field's integral surface (method "surface-layers";
 * docs/ALGORITHM.md §23): trace, draw in batches into surface layers,
 * composite. The layers' K is bounded by the frame size so that a frame's
 * layer memory stays within LC_SURFACE_LAYER_BUDGET. */
#include "surface_render.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "camera.h"

#define PIXEL_WORD_BYTES 12u /* list head, layer count, output of a pixel (surface_layers.c) */
#define LAYER_BYTES 32u
#define FRAGMENT_BYTES 32u

uint64_t lc_surface_bytes(int width, int height, int max_layers, int *k_used)
{
    uint64_t px = (uint64_t)(width > 0 ? width : 1) * (uint64_t)(height > 0 ? height : 1);
    uint64_t fit = LC_SURFACE_LAYER_BUDGET / (px * LAYER_BYTES);
    int k = max_layers < 1 ? 1 : max_layers;
    if ((uint64_t)k > fit)
        k = fit > 0 ? (int)fit : 1;
    if (k_used)
        *k_used = k;
    return px * ((uint64_t)k * LAYER_BYTES + PIXEL_WORD_BYTES) + LC_SURFACE_POOL_FRAGMENTS * FRAGMENT_BYTES;
}

static double diagonal(const double b[6])
{
    double d = 0;
    for (int a = 0; a < 3; a++)
        d += (b[3 + a] - b[a]) * (b[3 + a] - b[a]);
    return sqrt(d);
}

static int check_params(const lc_surface_params *sp, lc_error *err)
{
    if (sp->particles < 1)
        return lc_err_field(err, LC_ERR_INVALID, "surface.particles", "surface.particles must be >= 1");
    if (!(sp->epsilon >= 0 && isfinite(sp->epsilon)))
        return lc_err_field(err, LC_ERR_INVALID, "surface.epsilon", "surface.epsilon must be finite and >= 0");
    if (!(sp->opacity > 0 && sp->opacity <= 1))
        return lc_err_field(err, LC_ERR_INVALID, "surface.opacity", "surface.opacity must lie in (0, 1]");
    if (sp->max_layers < 1 || sp->max_layers > LC_SURFACE_LAYERS_MAX_K)
        return lc_err_field(err, LC_ERR_INVALID, "surface.maxLayers", "surface.maxLayers must lie in 1..%d",
                            LC_SURFACE_LAYERS_MAX_K);
    if (sp->direction < LC_TRACE_FORWARD || sp->direction > LC_TRACE_BOTH)
        return lc_err_field(err, LC_ERR_INVALID, "surface.direction",
                            "surface.direction must be forward, backward or both");
    if (!(sp->step >= 0 && isfinite(sp->step)) || !(sp->length >= 0 && isfinite(sp->length)))
        return lc_err_field(err, LC_ERR_INVALID, "surface.step", "surface.step and length must be finite and >= 0");
    return 0;
}

struct lc_surface_keep {
    lc_surface_layers *sl;
    lc_surface_layers_desc desc; /* what sl was made for (zeroed padding: compared whole) */
    float rgb[3];
    uint64_t curves_id; /* the curves drawn into sl: the first `drawn` of that sequence */
    uint32_t drawn;
    uint64_t fragments; /* sl's fragment count after the last frame */
};

lc_surface_keep *lc_surface_keep_create(void) { return calloc(1, sizeof(lc_surface_keep)); }

void lc_surface_keep_release(lc_surface_keep *keep)
{
    if (!keep)
        return;
    lc_surface_layers_destroy(keep->sl);
    memset(keep, 0, sizeof *keep);
}

int lc_surface_keep_holds(const lc_surface_keep *keep) { return keep && keep->sl; }

uint64_t lc_surface_keep_id(const lc_surface_keep *keep) { return keep && keep->sl ? keep->curves_id : 0; }

void lc_surface_keep_destroy(lc_surface_keep *keep)
{
    lc_surface_keep_release(keep);
    free(keep);
}

/* Brings k's layers to curves [0, n) of sequence id: kept layers of the same
 * view and sequence take the curves they lack, others start empty. */
static int prepare(lc_surface_keep *k, const lc_surface_layers_desc *d, const float rgb[3], uint64_t id, uint32_t n,
                   lc_surface_info *info, lc_error *err)
{
    if (k->sl && memcmp(&k->desc, d, sizeof *d) == 0 && memcmp(k->rgb, rgb, sizeof k->rgb) == 0) {
        if (k->curves_id == id && k->drawn <= n) {
            info->kept = 1;
            return 0;
        }
        lc_surface_layers_reset(k->sl); /* same view, other curves: empty, not reallocated */
    } else {
        lc_surface_keep_release(k);
        int rc = lc_surface_layers_create(d, &k->sl, err);
        if (rc)
            return rc;
        k->desc = *d;
        memcpy(k->rgb, rgb, sizeof k->rgb);
    }
    k->curves_id = id, k->drawn = 0, k->fragments = 0;
    return 0;
}

/* Draws the curves the layers lack in batches (bounding the fragment pool) and composites. */
static int draw(const lc_surface_layers_desc *d, const lc_trace_curve *curves, uint32_t n, uint64_t id,
                lc_surface_keep *keep, const float rgb[3], uint8_t *rgba, lc_surface_info *info, lc_error *err)
{
    lc_surface_keep local = {0};
    lc_surface_keep *k = keep && id ? keep : &local;
    int rc = prepare(k, d, rgb, id, n, info, err);
    info->drawn_curves = rc ? 0 : n - k->drawn;
    while (!rc && k->drawn < n) {
        uint32_t c = n - k->drawn < LC_SURFACE_BATCH ? n - k->drawn : LC_SURFACE_BATCH;
        rc = lc_surface_layers_add(k->sl, curves + k->drawn, c, rgb, err);
        k->drawn += c;
    }
    if (!rc)
        rc = lc_surface_layers_composite(k->sl, rgba, err);
    if (!rc)
        rc = lc_surface_layers_read(k->sl, NULL, &info->stats, err);
    if (!rc) {
        info->drawn_fragments = info->stats.fragments - k->fragments;
        k->fragments = info->stats.fragments;
    }
    if (rc || k == &local) /* a failed batch leaves the layers unknown */
        lc_surface_keep_release(k);
    return rc;
}

static int check_color(const lc_surface_params *sp, lc_error *err)
{
    for (int c = 0; c < 3; c++)
        if (!(sp->color[c] >= 0 && sp->color[c] <= 1))
            return lc_err_field(err, LC_ERR_INVALID, "surface.color", "surface.color components must lie in [0, 1]");
    return 0;
}

int lc_surface_draw(const lc_field *field, const lc_trace_curve *curves, uint32_t n, uint64_t curves_id,
                    lc_surface_keep *keep, const lc_surface_params *sp, const lc_render_params *p,
                    const double fit_box[6], uint8_t *rgba, lc_surface_info *info, lc_camera *camera_out, lc_error *err)
{
    double trace_ms = info->trace_ms;
    memset(info, 0, sizeof *info);
    info->trace_ms = trace_ms;
    int rc = check_params(sp, err);
    if (!rc)
        rc = check_color(sp, err);
    if (rc)
        return rc;
    for (uint32_t i = 0; i < n; i++)
        info->vertices += curves[i].n;
    lc_camera cam = p->camera;
    if (!p->has_camera) { /* fit the box, seen obliquely from above the seed's side */
        const double dir[3] = {-1.0, 1.5, -0.8};
        lc_camera_fit(&cam, fit_box, dir, NULL);
    }
    if (camera_out)
        *camera_out = cam;
    lc_view v;
    lc_camera_view(&cam, fit_box, (double)p->width / p->height, p->height, &v);
    lc_surface_layers_desc d;
    memset(&d, 0, sizeof d); /* compared whole with the kept layers' (padding included) */
    d.width = p->width, d.height = p->height;
    d.epsilon = sp->epsilon * diagonal(field->bounds);
    d.opacity = sp->opacity;
    d.pool_fragments = LC_SURFACE_POOL_FRAGMENTS;
    d.composite = sp->composite;
    lc_surface_bytes(p->width, p->height, sp->max_layers, &info->k);
    /* A pixel's layers live in one storage block: where the driver's block is
     * smaller than the budget (llvmpipe: 128 MiB), fewer layers, not a failure. */
    long long block = lc_surface_layers_block_bytes();
    uint64_t per_layer = (uint64_t)p->width * (uint64_t)p->height * LAYER_BYTES;
    if (block > 0 && (uint64_t)info->k * per_layer > (uint64_t)block) {
        uint64_t fit = (uint64_t)block / per_layer;
        if (fit < 1) {
            int side = (int)sqrt((double)block / LAYER_BYTES);
            return lc_err_field(err, LC_ERR_INVALID, "width",
                                "a %dx%d surface frame needs more than one storage block (%lld MiB) holds even at "
                                "one layer a pixel: render at most about %dx%d pixels",
                                p->width, p->height, (long long)(block >> 20), side, side);
        }
        info->k = (int)fit;
    }
    d.max_layers = info->k;
    memcpy(d.background, p->style.background, sizeof d.background);
    memcpy(d.view, v.view, sizeof d.view);
    memcpy(d.projection, v.proj, sizeof d.projection);
    const float rgb[3] = {(float)sp->color[0], (float)sp->color[1], (float)sp->color[2]};
    double t0 = lc_now();
    rc = draw(&d, curves, n, curves_id, keep, rgb, rgba, info, err);
    info->draw_ms = (lc_now() - t0) * 1000.0;
    return rc;
}

int lc_surface_render(const lc_field *field, const lc_seed *seed_in, const lc_surface_params *sp,
                      const lc_render_params *p, int threads, uint8_t *rgba, lc_surface_info *info,
                      lc_camera *camera_out, lc_error *err)
{
    memset(info, 0, sizeof *info);
    int rc = check_params(sp, err);
    if (!rc)
        rc = check_color(sp, err);
    if (rc)
        return rc;
    lc_seed seed = *seed_in;
    if ((rc = lc_seed_check(&seed, field, err)) != 0) {
        if (err)
            snprintf(err->field, sizeof err->field, "surface.seed");
        return rc;
    }
    lc_trace_curve *curves = calloc((size_t)sp->particles, sizeof *curves);
    if (!curves)
        return lc_err(err, LC_ERR_NOMEM, "out of memory for %d curves", sp->particles);
    double t0 = lc_now();
    lc_trace_desc td = {.step = sp->step,
                        .max_length = sp->length,
                        .direction = (lc_trace_direction)sp->direction,
                        .work = sp->work,
                        .step_units = sp->step_units};
    rc = lc_trace_curves(field, &seed, &td, 0, (uint32_t)sp->particles, threads, curves, err);
    info->trace_ms = (lc_now() - t0) * 1000.0;
    if (rc) {
        free(curves);
        return rc;
    }
    /* Framed and clipped by the field's bounds, as a session's frames are from
     * their first curves on: the one-shot image is a session's last. */
    rc = lc_surface_draw(field, curves, (uint32_t)sp->particles, 0, NULL, sp, p, field->bounds, rgba, info, camera_out,
                         err);
    lc_trace_curves_free(curves, (uint32_t)sp->particles);
    free(curves);
    return rc;
}
