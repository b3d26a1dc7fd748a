"""Camera helpers on plain dicts with the render request's camera keys
(position, focalPoint, viewUp, viewAngle, parallelProjection, parallelScale):
fit to bounds as the server does (ParaView's ResetCamera), turntables about the
view-up axis, keyframe interpolation (slerp of the orientation, log-linear
zoom), and the web page's URL state (#dataset=...&position=...)."""
import math
from urllib.parse import unquote_plus

DEFAULT_CAMERA = {"position": [0.0, 0.0, 0.0], "focalPoint": [0.0, 0.0, 0.0], "viewUp": [0.0, 1.0, 0.0],
                  "viewAngle": 30.0, "parallelProjection": False, "parallelScale": 1.0}
CAMERA_KEYS = tuple(DEFAULT_CAMERA)


def _sub(a, b):
    return [a[0] - b[0], a[1] - b[1], a[2] - b[2]]


def _add(a, b):
    return [a[0] + b[0], a[1] + b[1], a[2] + b[2]]


def _scale(a, s):
    return [a[0] * s, a[1] * s, a[2] * s]


def _dot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def _cross(a, b):
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]


def _norm(a):
    n = math.sqrt(_dot(a, a))
    return [a[0] / n, a[1] / n, a[2] / n] if n > 0 else [0.0, 0.0, 0.0]


def rotate(v, axis, angle):
    """v rotated by angle (radians) about the unit axis (Rodrigues)."""
    c, s = math.cos(angle), math.sin(angle)
    k = _norm(axis)
    return _add(_add(_scale(v, c), _scale(_cross(k, v), s)), _scale(k, _dot(k, v) * (1 - c)))


def flat_bounds(bounds):
    """[xmin, ymin, zmin, xmax, ymax, zmax] from that or [[mins], [maxs]]."""
    if len(bounds) == 2:
        return list(bounds[0]) + list(bounds[1])
    return list(bounds)


def fit(bounds, direction=(0, 0, -1), up=(0, 1, 0), view_angle=30.0, camera=None):
    """Looks along direction (camera -> focal point) at the bounding sphere of
    bounds so that it fills the view, as the server's fit (lc_camera_fit) and
    ParaView's ResetCamera do. `bounds` is a dataset's "bounds" from
    Client.datasets(); pass its "view" direction/up to match the server's fit."""
    b = flat_bounds(bounds)
    d = _norm(list(direction))
    if d == [0.0, 0.0, 0.0]:
        d = [0.0, 0.0, -1.0]
    side = _cross(d, list(up))
    if math.sqrt(_dot(side, side)) < 1e-9:
        side = _norm(_cross(d, [1.0, 0.0, 0.0] if abs(d[0]) < 0.9 else [0.0, 1.0, 0.0]))
    vup = _norm(_cross(side, d))
    center = [0.5 * (b[0] + b[3]), 0.5 * (b[1] + b[4]), 0.5 * (b[2] + b[5])]
    r = math.sqrt(sum((0.5 * (b[i + 3] - b[i])) ** 2 for i in range(3))) or 0.5
    cam = dict(DEFAULT_CAMERA)
    if camera:
        cam.update(camera)
    if not 0 < cam["viewAngle"] < 180:
        cam["viewAngle"] = view_angle
    dist = r / math.sin(math.radians(cam["viewAngle"]) / 2)
    cam.update(focalPoint=center, position=_sub(center, _scale(d, dist)), viewUp=vup, parallelScale=r)
    return cam


def turntable(camera, n, degrees=360.0, endpoint=False):
    """n cameras turning about the axis through the focal point along the
    camera's view-up: the up vector never changes, so the view never crosses a
    pole. With endpoint=False (the default) the last camera stops one step
    short of `degrees`, so a 360-degree loop repeats without a doubled frame."""
    if n < 1:
        raise ValueError("turntable: n must be at least 1")
    up = _norm(camera["viewUp"])
    fp = list(camera["focalPoint"])
    off = _sub(camera["position"], fp)
    # Make the up vector orthogonal to the view so that it stays the image's up.
    d = _norm(_scale(off, -1))
    up = _norm(_cross(_cross(d, up), d))
    step = math.radians(degrees) / (n - 1 if endpoint and n > 1 else n)
    out = []
    for i in range(n):
        c = dict(camera)
        c["position"] = _add(fp, rotate(off, up, i * step))
        c["focalPoint"] = fp
        c["viewUp"] = up
        out.append(c)
    return out


def orbit(camera, n, degrees=360.0, elevation=0.0):
    """A turntable after tilting the view by `elevation` degrees about its
    right axis (the up vector tilts with it)."""
    fp = list(camera["focalPoint"])
    off = _sub(camera["position"], fp)
    right = _norm(_cross(_scale(off, -1), camera["viewUp"]))
    a = math.radians(elevation)
    c = dict(camera, position=_add(fp, rotate(off, right, a)), viewUp=rotate(list(camera["viewUp"]), right, a))
    return turntable(c, n, degrees)


# ---- orientation as quaternions (w, x, y, z) of the camera frame (right, up, -dir)

def _frame(cam):
    d = _norm(_sub(cam["focalPoint"], cam["position"]))
    right = _norm(_cross(d, cam["viewUp"]))
    up = _cross(right, d)
    return right, up, _scale(d, -1)


def _quat(cols):
    (m00, m10, m20), (m01, m11, m21), (m02, m12, m22) = cols
    tr = m00 + m11 + m22
    if tr > 0:
        s = math.sqrt(tr + 1.0) * 2
        q = (0.25 * s, (m21 - m12) / s, (m02 - m20) / s, (m10 - m01) / s)
    elif m00 > m11 and m00 > m22:
        s = math.sqrt(1.0 + m00 - m11 - m22) * 2
        q = ((m21 - m12) / s, 0.25 * s, (m01 + m10) / s, (m02 + m20) / s)
    elif m11 > m22:
        s = math.sqrt(1.0 + m11 - m00 - m22) * 2
        q = ((m02 - m20) / s, (m01 + m10) / s, 0.25 * s, (m12 + m21) / s)
    else:
        s = math.sqrt(1.0 + m22 - m00 - m11) * 2
        q = ((m10 - m01) / s, (m02 + m20) / s, (m12 + m21) / s, 0.25 * s)
    n = math.sqrt(sum(x * x for x in q))
    return tuple(x / n for x in q)


def _rot(q, v):
    w, x, y, z = q
    u = [x, y, z]
    t = _scale(_cross(u, v), 2)
    return _add(_add(v, _scale(t, w)), _cross(u, t))


def slerp(q0, q1, t):
    dot = sum(a * b for a, b in zip(q0, q1))
    if dot < 0:
        q1, dot = tuple(-x for x in q1), -dot
    if dot > 0.9995:
        q = tuple(a + t * (b - a) for a, b in zip(q0, q1))
    else:
        th = math.acos(dot)
        s0, s1 = math.sin((1 - t) * th) / math.sin(th), math.sin(t * th) / math.sin(th)
        q = tuple(s0 * a + s1 * b for a, b in zip(q0, q1))
    n = math.sqrt(sum(x * x for x in q))
    return tuple(x / n for x in q)


def interpolate(a, b, t):
    """The camera a fraction t of the way from a to b: focal point linear,
    orientation by slerp, distance and parallel scale log-linear (so a zoom
    runs at a constant rate), view angle linear. The same rule as the server's
    movie paths (server/daemon/movie_path.c)."""
    qa, qb = _quat(_frame(a)), _quat(_frame(b))
    q = slerp(qa, qb, t)
    fa, fb = a["focalPoint"], b["focalPoint"]
    fp = [fa[i] + t * (fb[i] - fa[i]) for i in range(3)]
    da = math.sqrt(_dot(_sub(a["position"], fa), _sub(a["position"], fa)))
    db = math.sqrt(_dot(_sub(b["position"], fb), _sub(b["position"], fb)))
    dist = math.exp((1 - t) * math.log(da) + t * math.log(db))
    back = _rot(q, [0.0, 0.0, 1.0])
    c = dict(a)
    c["focalPoint"] = fp
    c["position"] = _add(fp, _scale(back, dist))
    c["viewUp"] = _rot(q, [0.0, 1.0, 0.0])
    va, vb = a.get("viewAngle", 30.0), b.get("viewAngle", 30.0)
    c["viewAngle"] = va + t * (vb - va)
    sa, sb = a.get("parallelScale", 1.0), b.get("parallelScale", 1.0)
    c["parallelScale"] = math.exp((1 - t) * math.log(sa) + t * math.log(sb))
    return c


def path(keyframes, n):
    """n cameras through the keyframes, evenly spaced in time (each keyframe
    segment gets the same share)."""
    if len(keyframes) < 2:
        raise ValueError("path: give at least two keyframes")
    if n < 2:
        raise ValueError("path: n must be at least 2")
    segs = len(keyframes) - 1
    out = []
    for i in range(n):
        u = i * segs / (n - 1)
        k = min(int(u), segs - 1)
        out.append(interpolate(keyframes[k], keyframes[k + 1], u - k))
    return out


def from_url(state, aliases=None):
    """Reads the web page's URL state (the part after '#', or a whole link):
    `#dataset=demo:tornado&position=0,0,5&focalPoint=0,0,0&viewUp=0,1,0&q=80`.
    Returns (dataset or None, camera dict or None, request update dict) with
    the flat keys mapped to request sections (camera.*, params.*, ...) through
    the same aliases as GET /api/v1/render (`aliases`: {flat key: (section,
    name)}, from the server's schema by Client.from_url; default: the keys of
    protocol/README.md). Unknown keys raise ValueError."""
    keys = dict(_URL_KEYS)
    keys.update(aliases or {})
    text = state.split("#", 1)[1] if "#" in state else state.split("?", 1)[-1] if "?" in state else state
    dataset, camera, update = None, None, {}
    for part in text.split("&"):
        if not part:
            continue
        k, _, v = part.partition("=")
        k, v = unquote_plus(k), unquote_plus(v)
        if k == "token" or k.startswith("_"):
            continue
        if k == "dataset":
            dataset = v
            continue
        section, name = keys.get(k, (None, None)) if "." not in k else tuple(k.split(".", 1))
        if name is None:
            raise ValueError("%s: unknown key in the link" % k)
        value = _url_value(v)
        if section == "camera":
            camera = camera or {}
            camera[name] = value
        elif section:
            update.setdefault(section, {})[name] = value
        else:
            update[name] = value
    return dataset, camera, update


def _url_value(v):
    if v in ("true", "false"):
        return v == "true"
    parts = v.split(",")
    try:
        nums = [float(p) for p in parts]
    except ValueError:
        return v
    if len(nums) == 1:
        return int(nums[0]) if nums[0].is_integer() and "." not in v and "e" not in v.lower() else nums[0]
    return nums


# The flat aliases of the page's hash and GET /api/v1/render (protocol/README.md).
_URL_KEYS = {k: ("camera", k) for k in CAMERA_KEYS}
_URL_KEYS.update({k: ("params", k) for k in ("q", "r", "lambda", "bands", "smoothing", "smoothingWeight", "fadeHalfLife",
                                             "resolutionScale", "subset", "depthMargin", "estimator", "depthRange",
                                             "normalize", "lod", "directExponent", "kanzlerImportance",
                                             "kanzlerCoverage", "kanzlerVariance", "kanzlerDepth", "kanzlerLambda")})
_URL_KEYS.update({"importance": ("importance", "attribute"), "importanceRange": ("importance", "range"),
                  "importanceExponent": ("importance", "exponent"), "color": ("color", "attribute"),
                  "colormap": ("color", "colormap"), "colorRange": ("color", "range")})
_URL_KEYS.update({k: ("style", k) for k in ("background", "lineWidth", "minLinePixels", "pointSize", "shading")})
_URL_KEYS.update({k: (None, k) for k in ("method", "quality", "interactiveQuality", "interactiveScale")})
