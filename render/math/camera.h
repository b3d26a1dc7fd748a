/* Camera math with ParaView's conventions: view and projection matrices, the
 * view-space depth range of the data bounds, and "reset camera" fitting. */
#ifndef LC_CAMERA_H
#define LC_CAMERA_H

#include "lc_params.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Column-major 4x4 matrices (OpenGL layout). */
typedef struct lc_view {
    float view[16];
    float proj[16];
    float view_proj[16];
    double znear, zfar; /* clip planes (positive distances) */
    double depth_min;   /* view-space depth range of the bounds this frame, */
    double depth_max;   /* clamped to the near plane (docs/ALGORITHM.md) */
    double pixel_world; /* world size of one pixel at the focal distance (for minimum widths) */
    double eye[3];      /* camera position */
    double dir[3];      /* unit view direction */
} lc_view;

/* Sets cam to look at bounds (xmin,ymin,zmin,xmax,ymax,zmax) along the given
 * direction (from camera to focal point; NULL = ParaView's default -Z) with up
 * vector (NULL = +Y), so that the bounding sphere fills the view, as ParaView's
 * ResetCamera does. Keeps view_angle (default 30 if <= 0) and sets
 * parallel_scale to the sphere radius. */
void lc_camera_fit(lc_camera *cam, const double bounds[6], const double *direction, const double *up);
/* Returns 0 if the camera is usable (finite, position != focal point, up not
 * parallel to the view direction, angle in (0,180), scale > 0), else -1. */
int lc_camera_validate(const lc_camera *cam);
/* Computes matrices and depth range for an image of the given aspect. */
void lc_camera_view(const lc_camera *cam, const double bounds[6], double aspect, int height_pixels, lc_view *out);

#ifdef __cplusplus
}
#endif
#endif
