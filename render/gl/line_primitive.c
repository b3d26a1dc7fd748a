/* Lines as one primitive (docs/ALGORITHM.md "Lines as one primitive"): which
 * form a frame's line segments draw in on this device (the rule, the
 * LUCENT_LINE_PRIMITIVE override, the frames where a wide line cannot stand
 * for the ribbon), and the GL line width each pass sets. */
#include <math.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>

#include "renderer_internal.h"

static atomic_int line_override = -1; /* LUCENT_LINE_PRIMITIVE: -1 the rule, 0 ribbons, 1 lines */

static int env_override(void)
{
    const char *e = getenv("LUCENT_LINE_PRIMITIVE"); /* 0 / 1: ribbons / lines (comparisons, tests) */
    return e && (e[0] == '0' || e[0] == '1') ? e[0] - '0' : -1;
}

void lc_line_primitive_configure(lc_renderer *r)
{
    atomic_store(&line_override, env_override());
    GLfloat range[2] = {1, 1};
    glGetFloatv(GL_ALIASED_LINE_WIDTH_RANGE, range);
    r->line_width_max = range[1];
    r->line_path = -1;
}

/* The rule: ribbons on every device. On llvmpipe the line strips cost the
 * geometry front end less (one vertex a line vertex where a ribbon has two,
 * one primitive a segment where it has two), but each shades the fragments
 * of the frame's widest ribbon at its worst angle, and alternated stills of
 * the MD file ranged from 0.6 to 2.5 times the ribbons' time on the shared
 * host; and a wide line ends square to its major axis where a ribbon ends
 * square to the line and is mitred at joins, so the images move further
 * from the ribbons' (SSIM 0.90-0.98 on real data) than the 0.999 that a
 * change of primitive may cost (docs/EVALUATION.md, lines as one primitive). */
static int rule(int override) { return override >= 0 ? override : 0; }

const char *lc_line_path_name(void) { return rule(env_override()) ? "lines" : "ribbons"; }

void lc_renderer_set_line_path(lc_renderer *r, int path) { r->line_path = path < 0 ? -1 : path > 0; }

float lc_renderer_line_width_max(const lc_renderer *r) { return r->line_width_max; }

/* The widest ribbon of the frame in this pass's pixels: its half width at the
 * nearest depth of the data's bounds (geometry.vert.glsl ribbon_frame), the
 * halo band included. 0 when a bound does not exist: some of the bounds lie
 * at or behind the eye, where the projected width grows without limit (and a
 * segment's ends may lie behind it). */
static double widest_half_px(const lc_frame_setup *fs, int h, int out_h)
{
    const lc_render_params *p = fs->params;
    const lc_view *v = &fs->view;
    double pixel = v->pixel_world * (double)out_h / h; /* bind_geometry's u_pixel_world */
    if (!p->camera.parallel_projection) {
        double focal = 0, nearest = INFINITY; /* as lc_frame_focal_distance */
        for (int i = 0; i < 3; i++)
            focal += (p->camera.focal_point[i] - v->eye[i]) * v->dir[i];
        for (int c = 0; c < 8; c++) {
            double d = 0;
            for (int i = 0; i < 3; i++)
                d += (fs->bounds[i + ((c >> i) & 1) * 3] - v->eye[i]) * v->dir[i];
            nearest = d < nearest ? d : nearest;
        }
        if (!(focal > 0) || !(nearest > v->znear))
            return 0;
        pixel *= nearest / focal;
    }
    double min_half = 0.5 * (p->style.min_line_pixels > 0 ? p->style.min_line_pixels : 1.0);
    double half = fs->line_half_width / pixel;
    half = half > min_half ? half : min_half;
    return half + (p->style.halo_width > 0 ? p->style.halo_width : 0.0);
}

/* A wide line that is not antialiased covers its width along the minor axis
 * (x for a steep segment, y for a flat one), which is the perpendicular width
 * times 1/cos of the angle to the major axis, at most sqrt(2). Both decide
 * coverage at pixel centres, so that covers every centre of the ribbon; a
 * quarter pixel each side takes rounding. Every pixel beyond costs a
 * fragment that is shaded only to be discarded. */
double lc_line_primitive_width(const lc_frame_setup *fs, int h, int out_h)
{
    double half = widest_half_px(fs, h, out_h);
    return half > 0 ? 2.0 * (half * sqrt(2.0) + 0.25) : 0.0;
}

int lc_frame_line_primitive(const lc_renderer *r, const lc_frame_setup *fs)
{
    if (fs->gs->scene->type != LC_PRIM_LINES)
        return 0;
    int want = r->line_path >= 0 ? r->line_path : rule(atomic_load(&line_override));
    if (!want)
        return 0;
    double width = lc_line_primitive_width(fs, fs->params->height, fs->params->height);
    return width > 0 && width <= r->line_width_max;
}
