/* Time markers (docs/ALGORITHM.md §26, time.markers): under a time window, a
 * splat at each line's position at t1, where the line leaves the window (or
 * at its last vertex when it ends inside it), in the line's colour. They are
 * drawn opaque over the finished image, after P6 (or the exact method's
 * blend) and before the readback: a marker says where a particle is now, so
 * it must stay visible over the transparent lines rather than take part in
 * the optimization, where it would fade behind important lines. */
#include <stdio.h>

#include "renderer_internal.h"

/* Splat radius in the view's pixels (docs/GUIDE.md: 3 px). */
#define MARKER_RADIUS_PX 3.0f

int lc_markers_draw(lc_renderer *r, const lc_frame_setup *fs, lc_error *err)
{
    const lc_render_params *p = fs->params;
    const lc_scene *s = fs->gs->scene;
    if (!p->time.markers || !p->time.has_window || s->type != LC_PRIM_LINES || fs->layer_count > 0 || !fs->pull_lines)
        return 0;
    int attr = lc_scene_time_attribute(s, p->time.attribute);
    if (attr < 0) /* filter.c refused the window already */
        return lc_err_field(err, LC_ERR_INVALID, "time.attribute", "%s has no time attribute", s->name);
    if (!r->marker_program) {
        static const char *const vs[] = {"common.glsl", "geometry.vert.glsl", NULL};
        static const char *const fsrc[] = {"common.glsl", "fragment_common.glsl", "opaque.frag.glsl", NULL};
        char defines[160];
        snprintf(defines, sizeof defines,
                 "#define PRIM %d\n#define BANDS 1\n#define PULL_PRIMITIVES 1\n#define MARKERS 1\n",
                 (int)LC_PRIM_LINES);
        r->marker_program = lc_renderer_build_program(defines, vs, fsrc, NULL, "time markers", err);
        if (!r->marker_program)
            return LC_ERR_GL;
    }
    GLuint prog = r->marker_program;
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, r->output.fbo);
    glDisable(GL_DEPTH_TEST);
    glDisable(GL_BLEND);
    glDisable(GL_CULL_FACE);
    lc_renderer_bind_geometry(r, prog, fs, fs->width, fs->height, 1);
    glProgramUniform1i(prog, glGetUniformLocation(prog, "u_marker_attr"), attr);
    glProgramUniform1f(prog, glGetUniformLocation(prog, "u_marker_t1"), (float)p->time.window[1]);
    /* In the view's pixels: a moving frame drawn at a fraction of the view's size draws them smaller. */
    double scale = p->detail.pixel_scale > 0 && p->detail.pixel_scale < 1 ? p->detail.pixel_scale : 1.0;
    float radius = (float)(MARKER_RADIUS_PX * scale);
    glProgramUniform1f(prog, glGetUniformLocation(prog, "u_point_radius_px"), radius > 1.0f ? radius : 1.0f);
    glProgramUniform1i(prog, glGetUniformLocation(prog, "u_context_depth"), 0); /* over everything */
    lc_frame_setup every = *fs; /* a marker for every line, also where a moving frame thinned them */
    every.kept_line_indices[0] = every.kept_line_indices[1] = 0;
    lc_renderer_draw_geometry(&every, 1);
    glMemoryBarrier(GL_FRAMEBUFFER_BARRIER_BIT);
    return 0;
}
