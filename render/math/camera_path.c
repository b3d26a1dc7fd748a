/* Turntables, tilts and keyframe interpolation of cameras (camera_path.h). */
#include "camera_path.h"

#include <math.h>
#include <string.h>

static double dot3(const double a[3], const double b[3]) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
static void cross3(const double a[3], const double b[3], double o[3])
{
    double r[3] = {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
    memcpy(o, r, sizeof r);
}
static double norm3(double v[3])
{
    double l = sqrt(dot3(v, v));
    if (l > 0)
        v[0] /= l, v[1] /= l, v[2] /= l;
    return l;
}

/* v rotated by angle (radians) about the unit axis k (Rodrigues). */
static void rotate(const double v[3], const double k[3], double angle, double out[3])
{
    double c = cos(angle), s = sin(angle), kv[3], d = dot3(k, v);
    cross3(k, v, kv);
    for (int i = 0; i < 3; i++)
        out[i] = v[i] * c + kv[i] * s + k[i] * d * (1 - c);
}

void lc_camera_turn(const lc_camera *start, double degrees, lc_camera *out)
{
    lc_camera c = *start;
    double off[3], d[3], right[3], up[3];
    for (int i = 0; i < 3; i++)
        off[i] = start->position[i] - start->focal_point[i], d[i] = -off[i];
    norm3(d);
    /* (d x up) x d: the up vector without its component along the view. */
    cross3(d, start->view_up, right);
    cross3(right, d, up);
    norm3(up);
    double p[3];
    rotate(off, up, degrees * M_PI / 180.0, p);
    for (int i = 0; i < 3; i++)
        c.position[i] = start->focal_point[i] + p[i], c.view_up[i] = up[i];
    *out = c;
}

void lc_camera_tilt(const lc_camera *start, double degrees, lc_camera *out)
{
    lc_camera c = *start;
    double off[3], d[3], right[3];
    for (int i = 0; i < 3; i++)
        off[i] = start->position[i] - start->focal_point[i], d[i] = -off[i];
    cross3(d, start->view_up, right);
    norm3(right);
    double a = degrees * M_PI / 180.0, p[3];
    rotate(off, right, a, p);
    rotate(start->view_up, right, a, c.view_up);
    for (int i = 0; i < 3; i++)
        c.position[i] = start->focal_point[i] + p[i];
    *out = c;
}

/* Unit quaternion (w, x, y, z) of the rotation whose columns are the camera's
 * right, up and back (-direction) axes. */
static void camera_quat(const lc_camera *cam, double q[4])
{
    double d[3], r[3], u[3];
    for (int i = 0; i < 3; i++)
        d[i] = cam->focal_point[i] - cam->position[i];
    norm3(d);
    cross3(d, cam->view_up, r);
    norm3(r);
    cross3(r, d, u);
    double m00 = r[0], m10 = r[1], m20 = r[2], m01 = u[0], m11 = u[1], m21 = u[2];
    double m02 = -d[0], m12 = -d[1], m22 = -d[2];
    double tr = m00 + m11 + m22, s;
    if (tr > 0) {
        s = sqrt(tr + 1.0) * 2;
        q[0] = 0.25 * s, q[1] = (m21 - m12) / s, q[2] = (m02 - m20) / s, q[3] = (m10 - m01) / s;
    } else if (m00 > m11 && m00 > m22) {
        s = sqrt(1.0 + m00 - m11 - m22) * 2;
        q[0] = (m21 - m12) / s, q[1] = 0.25 * s, q[2] = (m01 + m10) / s, q[3] = (m02 + m20) / s;
    } else if (m11 > m22) {
        s = sqrt(1.0 + m11 - m00 - m22) * 2;
        q[0] = (m02 - m20) / s, q[1] = (m01 + m10) / s, q[2] = 0.25 * s, q[3] = (m12 + m21) / s;
    } else {
        s = sqrt(1.0 + m22 - m00 - m11) * 2;
        q[0] = (m10 - m01) / s, q[1] = (m02 + m20) / s, q[2] = (m12 + m21) / s, q[3] = 0.25 * s;
    }
    double n = sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
    for (int i = 0; i < 4; i++)
        q[i] /= n;
}

static void quat_rotate(const double q[4], const double v[3], double out[3])
{
    double u[3] = {q[1], q[2], q[3]}, t[3], ut[3];
    cross3(u, v, t);
    for (int i = 0; i < 3; i++)
        t[i] *= 2;
    cross3(u, t, ut);
    for (int i = 0; i < 3; i++)
        out[i] = v[i] + q[0] * t[i] + ut[i];
}

static void slerp(const double a[4], const double b0[4], double t, double out[4])
{
    double b[4], d = 0;
    for (int i = 0; i < 4; i++)
        d += a[i] * b0[i];
    for (int i = 0; i < 4; i++)
        b[i] = d < 0 ? -b0[i] : b0[i];
    d = fabs(d);
    double s0 = 1 - t, s1 = t;
    if (d < 0.9995) { /* otherwise linear, then normalized: sin(th) would vanish */
        double th = acos(d);
        s0 = sin((1 - t) * th) / sin(th), s1 = sin(t * th) / sin(th);
    }
    double n = 0;
    for (int i = 0; i < 4; i++)
        out[i] = s0 * a[i] + s1 * b[i], n += out[i] * out[i];
    n = sqrt(n);
    for (int i = 0; i < 4; i++)
        out[i] /= n;
}

static double loglerp(double a, double b, double t)
{
    return a > 0 && b > 0 ? exp((1 - t) * log(a) + t * log(b)) : a + t * (b - a);
}

void lc_camera_interpolate(const lc_camera *a, const lc_camera *b, double t, lc_camera *out)
{
    double qa[4], qb[4], q[4];
    camera_quat(a, qa);
    camera_quat(b, qb);
    slerp(qa, qb, t, q);
    double da[3], db[3];
    for (int i = 0; i < 3; i++)
        da[i] = a->position[i] - a->focal_point[i], db[i] = b->position[i] - b->focal_point[i];
    double dist = loglerp(sqrt(dot3(da, da)), sqrt(dot3(db, db)), t);
    lc_camera c = *a;
    static const double z[3] = {0, 0, 1}, y[3] = {0, 1, 0};
    double back[3];
    quat_rotate(q, z, back);
    quat_rotate(q, y, c.view_up);
    for (int i = 0; i < 3; i++) {
        c.focal_point[i] = a->focal_point[i] + t * (b->focal_point[i] - a->focal_point[i]);
        c.position[i] = c.focal_point[i] + back[i] * dist;
    }
    c.view_angle = a->view_angle + t * (b->view_angle - a->view_angle);
    c.parallel_scale = loglerp(a->parallel_scale, b->parallel_scale, t);
    *out = c;
}

void lc_camera_path(const lc_camera *keys, int count, int i, int n, lc_camera *out)
{
    int segs = count - 1;
    double u = n > 1 ? (double)i * segs / (n - 1) : 0;
    int k = (int)u;
    if (k > segs - 1)
        k = segs - 1;
    if (k < 0)
        k = 0;
    lc_camera_interpolate(&keys[k], &keys[k + 1], u - k, out);
}

void lc_camera_path_frame(const lc_camera_path_desc *d, const lc_camera *start, int i, lc_camera *out)
{
    if (d->kind == 2) {
        lc_camera_path(d->keys, d->key_count, i, d->frames, out);
        return;
    }
    lc_camera s = *start;
    if (d->kind == 1)
        lc_camera_tilt(&s, d->elevation, &s);
    lc_camera_turn(&s, d->frames > 0 ? d->degrees * i / d->frames : 0, out);
}
