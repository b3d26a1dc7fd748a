/* Camera paths for movies: a turntable about the view-up axis (the up vector
 * never changes, so the view never crosses a pole), a tilt about the view's
 * right axis, and keyframe interpolation with slerp of the orientation and a
 * log-linear distance (a zoom at a constant rate). The Python client
 * (clients/python/lucent/camera.py) computes the same cameras. */
#ifndef LC_CAMERA_PATH_H
#define LC_CAMERA_PATH_H

#include "lc_params.h"

#ifdef __cplusplus
extern "C" {
#endif

/* start turned by `degrees` about the axis through its focal point along its
 * view-up made orthogonal to the view direction (which becomes out's up). */
void lc_camera_turn(const lc_camera *start, double degrees, lc_camera *out);
/* start tilted by `degrees` about its right axis (position and up turn). */
void lc_camera_tilt(const lc_camera *start, double degrees, lc_camera *out);
/* The camera a fraction t in [0, 1] of the way from a to b: focal point and
 * view angle linear, orientation (right, up, back frame) by slerp, distance to
 * the focal point and parallel scale log-linear. Projection type from a. */
void lc_camera_interpolate(const lc_camera *a, const lc_camera *b, double t, lc_camera *out);
/* Frame i of n through keys[0..count-1] (count >= 2, n >= 2), evenly spaced in
 * time: each keyframe segment gets the same share, frames 0 and n-1 are the
 * first and last keyframes. */
void lc_camera_path(const lc_camera *keys, int count, int i, int n, lc_camera *out);

/* A movie's camera path: kind 0 = turntable of `degrees` about start's
 * view-up, 1 = orbit (the turntable after a tilt of `elevation` degrees),
 * 2 = keyframes (start unused); the values of protocol/movie.h's lc_movie_path. */
typedef struct lc_camera_path_desc {
    int kind;
    double degrees, elevation;
    const lc_camera *keys;
    int key_count;
    int frames;
} lc_camera_path_desc;
/* Frame i of the path. Turntables put frame i at i / frames of the turn, so a
 * whole turn loops without a repeated frame. */
void lc_camera_path_frame(const lc_camera_path_desc *d, const lc_camera *start, int i, lc_camera *out);

#ifdef __cplusplus
}
#endif
#endif
