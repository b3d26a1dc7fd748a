"""protocol/openapi.yaml against itself and the real daemon: the file is a valid
OpenAPI 3 document (when openapi-spec-validator is installed), every route the
daemon serves is in it, and every key the daemon writes in health, dataset,
session and error bodies is a documented property (no silent drift)."""
import os
import sys

from lucent_server import Check, Server, skip

try:
    import yaml
except ImportError:  # pragma: no cover
    skip("python3-yaml is not installed")

binary = sys.argv[1]
check = Check()
here = os.path.dirname(os.path.abspath(__file__))
spec_path = os.path.join(here, "..", "..", "protocol", "openapi.yaml")
with open(spec_path) as f:
    spec = yaml.safe_load(f)

try:
    from openapi_spec_validator import validate
except ImportError:
    print("note: openapi-spec-validator is not installed; structure checked only")
    validate = None
if validate:
    try:
        validate(spec)
        check(True, "openapi.yaml is a valid OpenAPI 3 document")
    except Exception as e:  # the validator's exception types differ between versions
        check(False, "openapi.yaml is a valid OpenAPI 3 document: %s" % str(e)[:800])


def deref(node):
    """Follows $ref and single-entry allOf wrappers to the schema object."""
    while isinstance(node, dict):
        if "$ref" in node:
            target = spec
            for part in node["$ref"].lstrip("#/").split("/"):
                target = target[part]
            node = target
        elif "allOf" in node and len(node["allOf"]) == 1 and "properties" not in node:
            node = node["allOf"][0]
        else:
            break
    return node


def undocumented(value, schema, where):
    """Dotted paths of keys in value that schema does not declare (objects only;
    arrays are checked through their items)."""
    schema = deref(schema)
    out = []
    if isinstance(value, dict) and isinstance(schema, dict) and "properties" in schema:
        props = schema["properties"]
        for k, v in value.items():
            if k not in props:
                out.append(where + k)
            else:
                out += undocumented(v, props[k], where + k + ".")
    elif isinstance(value, list) and isinstance(schema, dict) and "items" in schema:
        for v in value:
            out += undocumented(v, schema["items"], where + "[].")
    return out


def response_schema(path, method, status):
    r = deref(spec["paths"][path][method]["responses"][status])
    return r["content"]["application/json"]["schema"]


paths = spec["paths"]
for p in ("/api/v1/health", "/api/v1/datasets", "/api/v1/datasets/{name}", "/api/v1/render", "/api/v1/sessions",
          "/api/v1/sessions/{id}", "/api/v1/sessions/{id}/render", "/api/v1/ws", "/metrics", "/"):
    check(p in paths, "route %s is documented" % p)
check("get" in paths["/api/v1/sessions/{id}"], "GET /api/v1/sessions/{id} is documented")
check("426" in paths["/api/v1/ws"]["get"]["responses"], "426 on a wrong WebSocket version is documented")
image_headers = deref(spec["components"]["responses"]["Image"])["headers"]
for h in ("X-Lucent-Timings", "Server-Timing", "X-Lucent-Converged", "X-Lucent-Max-Alpha-Change",
          "X-Lucent-Visibility"):
    check(h in image_headers, "image header %s is documented" % h)

with Server(binary, data=("demo:abc", "demo:points"), demo_size=40) as srv:
    st, _, health = srv.json("GET", "/api/v1/health")
    bad = undocumented(health, response_schema("/api/v1/health", "get", "200"), "")
    check(st == 200 and not bad, "every health key is documented %s" % bad)

    st, _, ds = srv.json("GET", "/api/v1/datasets")
    bad = undocumented(ds, response_schema("/api/v1/datasets", "get", "200"), "")
    check(st == 200 and not bad, "every dataset key is documented %s" % bad)
    check(any("view" in d for d in ds["datasets"]), "a dataset with a view was checked")

    st, h, created = srv.json("POST", "/api/v1/sessions", {"dataset": "demo:points", "width": 32, "height": 32})
    bad = undocumented(created, response_schema("/api/v1/sessions", "post", "201"), "")
    check(st == 201 and not bad, "every session-creation key is documented %s" % bad)
    st, _, info = srv.json("GET", h.get("location", "/nowhere"))
    bad = undocumented(info, response_schema("/api/v1/sessions/{id}", "get", "200"), "")
    check(st == 200 and not bad, "every session key is documented %s" % bad)

    st, _, e = srv.json("POST", "/api/v1/render", {"params": {"bandz": 1}})
    bad = undocumented(e, spec["components"]["schemas"]["Error"], "")
    check(st == 400 and not bad, "every error key is documented %s" % bad)
    check(srv.stop() == 0, "daemon exits 0")

check.done()
