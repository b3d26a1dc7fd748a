"""The render request schema has one source, protocol/request_table.c (the field table)
(printed by `lucent schema`). The page's table is generated from it at build time
(BUILD/generated/web/js/schema_fields.js, protocol/gen/schema_js.c); this checks that
the page as built reads exactly that table (web/js/schema.js's FIELDS and
REQUEST_TOP_FIELDS, read through node, are `lucent schema`'s fields in its order),
and the hand-written copies against it: the OpenAPI description
(protocol/openapi.yaml): names, aliases, types, ranges and enum values; and the
settings panel (web/js/ui.js): every control edits a field that exists, sliders stay
inside its range, selects offer exactly its values.
Usage: check_schema.py LUCENT SOURCE_DIR GENERATED_WEB_DIR"""
import json
import os
import subprocess
import sys

lucent, src, generated = sys.argv[1], sys.argv[2], sys.argv[3]
failures = []


def fail(msg):
    failures.append(msg)
    print("FAIL:", msg, file=sys.stderr)


schema = json.loads(subprocess.check_output([lucent, "schema"], text=True))
key = lambda f: (f["section"], f["name"])
c_fields = {key(f): f for f in schema}

# Node resolves the page's generated modules in the build tree (tests/browser/web-generated.mjs).
node = ["node", "--import", os.path.join(src, "tests", "browser", "web-generated.mjs"), "--input-type=module", "-e"]
node_env = dict(os.environ, LUCENT_WEB_GENERATED=generated)

# ---- the page's schema (web/js/schema.js over the generated schema_fields.js) is `lucent schema`
js = ("import('%s').then((m) => console.log(JSON.stringify([...m.FIELDS, ...m.REQUEST_TOP_FIELDS])))"
      % os.path.join(src, "web", "js", "schema.js"))
web = json.loads(subprocess.check_output(node + [js], text=True, env=node_env))
order = {key(f): i for i, f in enumerate(schema)}
web.sort(key=lambda f: order.get(key(f), len(order)))
if web != schema:
    for c, w in zip(schema, web):
        if c != w:
            fail("the page's schema differs from `lucent schema` at %s: %r vs %r (rebuild?)" % (
                ".".join(x for x in key(c) if x), w, c))
            break
    else:
        fail("the page's schema has %d fields, `lucent schema` %d" % (len(web), len(schema)))

# ---- web/js/ui.js: the controls only (labels and slider steps are the panel's own)
js = ("import('%s').then((m) => console.log(JSON.stringify(m.GROUPS.flatMap((g) => g.controls))))"
      % os.path.join(src, "web", "js", "ui.js"))
by_path = {".".join(x for x in k if x): f for k, f in c_fields.items()}
for ctl in json.loads(subprocess.check_output(node + [js], text=True, env=node_env)):
    if ctl["path"] in ("interactiveQuality", "interactiveScale"):
        continue  # WebSocket session settings (protocol/messages.c), not render request fields
    f = by_path.get(ctl["path"])
    where = "web/js/ui.js control %s" % ctl["path"]
    if not f:
        fail("%s: no such field in the C table" % where)
        continue
    if ctl["kind"] == "range":
        if "min" in f and ctl["min"] < f["min"] or "max" in f and ctl["max"] > f["max"]:
            fail("%s: slider [%r, %r] outside the field's [%r, %r]" % (where, ctl["min"], ctl["max"], f.get("min"), f.get("max")))
    elif ctl["kind"] == "select" and ctl.get("options"):
        offered = [o[0] if isinstance(o, list) else o for o in ctl["options"]]
        if ctl["path"] == "method":
            offered.append("surface-layers")  # one-shot renders only: the panel's sessions cannot stream it
        if f.get("type") == "enum" and sorted(offered) != sorted(f["values"]):
            fail("%s: offers %r, the field takes %r" % (where, offered, f["values"]))

# ---- protocol/openapi.yaml (python3-yaml)
try:
    import yaml
except ImportError:
    fail("python3-yaml is not installed (scripts/setup.sh --test installs it)")
    yaml = None
if yaml:
    with open(os.path.join(src, "protocol", "openapi.yaml")) as f:
        spec = yaml.safe_load(f)
    comps = spec["components"]["schemas"]

    def resolve(node):
        while isinstance(node, dict) and "$ref" in node:
            node = comps[node["$ref"].split("/")[-1]]
        return node

    req = comps["RenderRequest"]["properties"]
    for k, c in c_fields.items():
        section, name = k
        props = req if section is None else resolve(req.get(section, {})).get("properties", {})
        node = resolve(props.get(name))
        where = "openapi RenderRequest %s" % ".".join(x for x in k if x)
        if node is None:
            fail("%s: missing" % where)
            continue
        if c["type"] in ("int", "num"):
            want_type = "integer" if c["type"] == "int" else "number"
            if node.get("type") != want_type:
                fail("%s: type %r, expected %r" % (where, node.get("type"), want_type))
            if name == "version":
                if node.get("enum") != [1]:
                    fail("%s: expected enum [1]" % where)
                continue
            for prop, oprop in (("min", "minimum"), ("max", "maximum")):
                if prop in c and (oprop not in node or abs(float(node[oprop]) - c[prop]) > 1e-9 * max(1, abs(c[prop]))):
                    fail("%s: %s %r, expected %r" % (where, oprop, node.get(oprop), c[prop]))
            for prop, oprop in (("loOpen", "exclusiveMinimum"), ("hiOpen", "exclusiveMaximum")):
                if bool(c.get(prop)) != bool(node.get(oprop)):
                    fail("%s: %s %r, expected %r" % (where, oprop, node.get(oprop), bool(c.get(prop))))
        elif c["type"] == "enum":
            values = [v for v in c["values"] if not (name == "format" and v == "jpg")]
            got = [v for v in node.get("enum", []) if v != "jpg"]
            if got != values:
                fail("%s: enum %r, expected %r (same order)" % (where, got, values))
        elif c["type"] == "str" and "maxLength" in node and node["maxLength"] != c["maxLength"]:
            fail("%s: maxLength %r, expected %r" % (where, node["maxLength"], c["maxLength"]))

checked = len(c_fields)
print("%d passed, %d failed" % (checked - len(failures) if len(failures) < checked else 0, len(failures)))
sys.exit(1 if failures else 0)
