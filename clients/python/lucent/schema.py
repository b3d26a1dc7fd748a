"""Client-side checks of a render request against the server's field table
(GET /api/v1/schema, the same table `lucent schema` prints), so a typo or an
out-of-range value fails before a round trip, naming the field as the server
would (`params.bandz: unknown field`)."""
import math

SECTIONS = ("camera", "params", "importance", "color", "style")


class LucentError(Exception):
    """An error of the client or the server: code (`unknown_field`,
    `out_of_range`, `not_found`, ...), field (dotted path, or None), message
    (the server's text on 4xx/5xx), status (HTTP status, or None)."""

    def __init__(self, code, message, field=None, status=None):
        super().__init__(message)
        self.code = code
        self.field = field
        self.message = message
        self.status = status


def _is_number(v):
    return isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v)


def _check_range(f, v, path):
    lo, hi = f.get("min"), f.get("max")
    below = lo is not None and (v <= lo if f.get("loOpen") else v < lo)
    above = hi is not None and (v >= hi if f.get("hiOpen") else v > hi)
    if below or above:
        left = "(" if f.get("loOpen") else "["
        right = ")" if f.get("hiOpen") else "]"
        span = "%s%s, %s%s" % (left, "-inf" if lo is None else "%g" % lo, "inf" if hi is None else "%g" % hi, right)
        raise LucentError("out_of_range", "%s: %s is outside %s" % (path, v, span), path)


def check_value(f, v, path):
    """Raises LucentError when v is not a valid value of schema field f."""
    t = f["type"]
    if t in ("int", "num"):
        if not _is_number(v) or (t == "int" and float(v) != int(v)):
            raise LucentError("bad_field", "%s: expected %s" % (path, "an integer" if t == "int" else "a number"), path)
        _check_range(f, v, path)
    elif t == "bool":
        if not isinstance(v, bool):
            raise LucentError("bad_field", "%s: expected true or false" % path, path)
    elif t == "str":
        if not isinstance(v, str):
            raise LucentError("bad_field", "%s: expected a string" % path, path)
        if "maxLength" in f and len(v.encode()) > f["maxLength"]:
            raise LucentError("out_of_range", "%s: longer than %d bytes" % (path, f["maxLength"]), path)
    elif t == "enum":
        if v not in f.get("values", []):
            raise LucentError("bad_field", "%s: %r is not one of %s" % (path, v, ", ".join(f.get("values", []))), path)
    elif t in ("vec3", "color", "range"):
        n = 2 if t == "range" else 3
        if not isinstance(v, (list, tuple)) or len(v) != n or not all(_is_number(x) for x in v):
            raise LucentError("bad_field", "%s: expected %d numbers" % (path, n), path)
        if t == "color" and not all(0 <= x <= 1 for x in v):
            raise LucentError("out_of_range", "%s: each component must lie in [0, 1]" % path, path)


class Schema:
    """The server's field table, indexed by section and name."""

    def __init__(self, fields):
        self.fields = fields
        self.by_path = {}
        for f in fields:
            key = f["name"] if f["section"] is None else f["section"] + "." + f["name"]
            self.by_path[key] = f

    def field(self, path):
        return self.by_path.get(path)

    def validate(self, req, top_level_extra=()):
        """Checks a (partial) request dict; raises LucentError naming the first
        bad field. Sections are objects (camera may be None: fit the data)."""
        if not isinstance(req, dict):
            raise LucentError("bad_field", "request: expected an object", "")
        for key, v in req.items():
            if key in SECTIONS:
                if key == "camera" and v is None:
                    continue
                if not isinstance(v, dict):
                    raise LucentError("bad_field", "%s: expected an object" % key, key)
                for name, x in v.items():
                    path = key + "." + name
                    f = self.by_path.get(path)
                    if f is None:
                        raise LucentError("unknown_field", "%s: unknown field" % path, path)
                    check_value(f, x, path)
            elif key in top_level_extra:
                continue
            else:
                f = self.by_path.get(key)
                if f is None or f["section"] is not None:
                    raise LucentError("unknown_field", "%s: unknown field" % key, key)
                check_value(f, v, key)
        w, h = req.get("width"), req.get("height")
        if w is not None and h is not None:
            wf = self.by_path.get("width", {})
            cap = wf.get("maxPixels")
            if cap and w * h > cap:
                raise LucentError("out_of_range", "width: %d x %d pixels exceeds the limit %d" % (w, h, cap), "width")
        return req
