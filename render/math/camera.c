/* Camera matrices, depth range and fitting (ParaView conventions). */
#include "camera.h"

#include <math.h>
#include <string.h>

static double dot3(const double a[3], const double b[3]) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
static void cross3(const double a[3], const double b[3], double o[3])
{
    o[0] = a[1] * b[2] - a[2] * b[1];
    o[1] = a[2] * b[0] - a[0] * b[2];
    o[2] = a[0] * b[1] - a[1] * b[0];
}
static double norm3(double v[3])
{
    double l = sqrt(dot3(v, v));
    if (l > 0)
        v[0] /= l, v[1] /= l, v[2] /= l;
    return l;
}

static void bounds_sphere(const double b[6], double c[3], double *radius)
{
    double r2 = 0;
    for (int i = 0; i < 3; i++) {
        c[i] = 0.5 * (b[i] + b[i + 3]);
        double h = 0.5 * (b[i + 3] - b[i]);
        r2 += h * h;
    }
    *radius = sqrt(r2) > 0 ? sqrt(r2) : 0.5;
}

void lc_camera_fit(lc_camera *cam, const double bounds[6], const double *direction, const double *up)
{
    double dir[3] = {0, 0, -1}, vup[3] = {0, 1, 0};
    if (direction)
        memcpy(dir, direction, sizeof dir);
    if (up)
        memcpy(vup, up, sizeof vup);
    if (norm3(dir) == 0)
        dir[0] = 0, dir[1] = 0, dir[2] = -1;
    /* Make up orthogonal to the direction; pick another axis if parallel. */
    double side[3];
    cross3(dir, vup, side);
    if (norm3(side) < 1e-9) {
        double alt[3] = {fabs(dir[0]) < 0.9 ? 1.0 : 0.0, fabs(dir[0]) < 0.9 ? 0.0 : 1.0, 0};
        cross3(dir, alt, side);
        norm3(side);
    }
    cross3(side, dir, vup);
    norm3(vup);

    double c[3], radius;
    bounds_sphere(bounds, c, &radius);
    if (!(cam->view_angle > 0 && cam->view_angle < 180))
        cam->view_angle = 30;
    double dist = radius / sin(cam->view_angle * M_PI / 360.0);
    for (int i = 0; i < 3; i++) {
        cam->focal_point[i] = c[i];
        cam->position[i] = c[i] - dir[i] * dist;
        cam->view_up[i] = vup[i];
    }
    cam->parallel_scale = radius;
}

int lc_camera_validate(const lc_camera *cam)
{
    double dir[3], side[3];
    for (int i = 0; i < 3; i++) {
        if (!isfinite(cam->position[i]) || !isfinite(cam->focal_point[i]) || !isfinite(cam->view_up[i]))
            return -1;
        dir[i] = cam->focal_point[i] - cam->position[i];
    }
    if (norm3(dir) == 0)
        return -1;
    double up[3] = {cam->view_up[0], cam->view_up[1], cam->view_up[2]};
    if (norm3(up) == 0)
        return -1;
    cross3(dir, up, side);
    if (sqrt(dot3(side, side)) < 1e-6)
        return -1;
    if (!(cam->view_angle > 0 && cam->view_angle < 180))
        return -1;
    if (cam->parallel_projection && !(cam->parallel_scale > 0 && isfinite(cam->parallel_scale)))
        return -1;
    return 0;
}

/* Column-major store helper: m[col*4 + row]. */
#define M(m, r, c) (m)[(c)*4 + (r)]

static void mat_mul(const float a[16], const float b[16], float o[16])
{
    float t[16];
    for (int r = 0; r < 4; r++)
        for (int c = 0; c < 4; c++) {
            float s = 0;
            for (int k = 0; k < 4; k++)
                s += M(a, r, k) * M(b, k, c);
            M(t, r, c) = s;
        }
    memcpy(o, t, sizeof t);
}

void lc_camera_view(const lc_camera *cam, const double bounds[6], double aspect, int height_pixels, lc_view *out)
{
    memset(out, 0, sizeof *out);
    double f[3], s[3], u[3], up[3];
    for (int i = 0; i < 3; i++) {
        f[i] = cam->focal_point[i] - cam->position[i];
        up[i] = cam->view_up[i];
        out->eye[i] = cam->position[i];
    }
    double focal_dist = norm3(f);
    if (focal_dist == 0)
        f[2] = -1, focal_dist = 1;
    cross3(f, up, s);
    norm3(s);
    cross3(s, f, u);
    memcpy(out->dir, f, sizeof f);

    float *v = out->view;
    memset(v, 0, 16 * sizeof(float));
    M(v, 0, 0) = (float)s[0], M(v, 0, 1) = (float)s[1], M(v, 0, 2) = (float)s[2];
    M(v, 1, 0) = (float)u[0], M(v, 1, 1) = (float)u[1], M(v, 1, 2) = (float)u[2];
    M(v, 2, 0) = (float)-f[0], M(v, 2, 1) = (float)-f[1], M(v, 2, 2) = (float)-f[2];
    M(v, 0, 3) = (float)-dot3(s, cam->position);
    M(v, 1, 3) = (float)-dot3(u, cam->position);
    M(v, 2, 3) = (float)dot3(f, cam->position);
    M(v, 3, 3) = 1;

    /* View-space depth (distance along f) of the 8 bound corners. */
    double dmin = INFINITY, dmax = -INFINITY;
    for (int i = 0; i < 8; i++) {
        double p[3] = {bounds[(i & 1) ? 3 : 0], bounds[(i & 2) ? 4 : 1], bounds[(i & 4) ? 5 : 2]};
        double rel[3] = {p[0] - cam->position[0], p[1] - cam->position[1], p[2] - cam->position[2]};
        double d = dot3(rel, f);
        dmin = fmin(dmin, d);
        dmax = fmax(dmax, d);
    }
    double extent = dmax - dmin;
    if (!(extent > 0))
        extent = focal_dist > 0 ? focal_dist : 1;
    /* Pad so that geometry widened by ribbons/splats is not clipped. */
    dmin -= 0.01 * extent;
    dmax += 0.01 * extent;
    double znear, zfar;
    if (cam->parallel_projection) {
        znear = dmin, zfar = dmax; /* may be negative: orthographic allows it */
    } else {
        zfar = dmax > 0 ? dmax : focal_dist;
        znear = fmax(dmin, zfar * 1e-4);
    }
    if (!(zfar > znear))
        zfar = znear + extent;
    out->znear = znear, out->zfar = zfar;
    out->depth_min = cam->parallel_projection ? dmin : fmax(dmin, znear);
    out->depth_max = fmax(dmax, out->depth_min + 1e-9 * (1 + fabs(dmax)));

    float *p = out->proj;
    memset(p, 0, 16 * sizeof(float));
    double half_h;
    if (cam->parallel_projection) {
        half_h = cam->parallel_scale;
        double half_w = half_h * aspect;
        M(p, 0, 0) = (float)(1.0 / half_w);
        M(p, 1, 1) = (float)(1.0 / half_h);
        M(p, 2, 2) = (float)(-2.0 / (zfar - znear));
        M(p, 2, 3) = (float)(-(zfar + znear) / (zfar - znear));
        M(p, 3, 3) = 1;
        out->pixel_world = 2.0 * half_h / (height_pixels > 0 ? height_pixels : 1);
    } else {
        double t = tan(cam->view_angle * M_PI / 360.0);
        M(p, 0, 0) = (float)(1.0 / (t * aspect));
        M(p, 1, 1) = (float)(1.0 / t);
        M(p, 2, 2) = (float)(-(zfar + znear) / (zfar - znear));
        M(p, 2, 3) = (float)(-2.0 * zfar * znear / (zfar - znear));
        M(p, 3, 2) = -1;
        out->pixel_world = 2.0 * t * focal_dist / (height_pixels > 0 ? height_pixels : 1);
    }
    mat_mul(out->proj, out->view, out->view_proj);
}
