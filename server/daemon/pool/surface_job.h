/* A render worker's frame of method "surface-layers": the request's surface
 * object turned into the renderer's terms (render/gl/surface_render.h), the
 * statistics into the frame info that the response headers report. */
#ifndef LC_SERVER_SURFACE_JOB_H
#define LC_SERVER_SURFACE_JOB_H

#include <stdint.h>

#include "field.h"
#include "renderer.h"
#include "request.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Renders the surface s of field with p's size, camera and background into
 * rgba (p's width x height, top row first) on the calling worker's GL context. Errors name the
 * request field. */
int lc_surface_job_render(const lc_field *field, const lc_surface_request *s, const lc_render_params *p,
                          uint8_t *rgba, lc_frame_info *info, lc_error *err);

#ifdef __cplusplus
}
#endif
#endif
