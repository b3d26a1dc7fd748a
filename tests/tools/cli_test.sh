#!/usr/bin/env bash
# Drives the lucent CLI as a user would: renders, requests, bad inputs, info,
# gen round trips and the benchmark table. Usage: cli_test.sh LUCENT SOURCE_DIR
set -u
LUCENT=$1
SRC=$2
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
pass=0
fail=0
ok() { pass=$((pass + 1)); }
bad() { fail=$((fail + 1)); echo "FAIL: $*" >&2; }

# Prints "WIDTH HEIGHT" of a PNG or JPEG file.
image_size() {
  python3 - "$1" <<'PY'
import struct, sys
d = open(sys.argv[1], 'rb').read()
if d[:8] == b'\x89PNG\r\n\x1a\n':
    print(*struct.unpack('>II', d[16:24]))
elif d[:2] == b'\xff\xd8':
    i = 2
    while i < len(d):
        marker, length = d[i + 1], struct.unpack('>H', d[i + 2:i + 4])[0]
        if marker in (0xC0, 0xC1, 0xC2):
            h, w = struct.unpack('>HH', d[i + 5:i + 9]); print(w, h); break
        i += 2 + length
else:
    print('not-an-image')
PY
}

# expect_ok NAME CMD...: exit 0
expect_ok() {
  local name=$1; shift
  if "$@" >"$tmp/out" 2>"$tmp/err"; then ok; else bad "$name: exit $? ($(head -c 400 "$tmp/err"))"; fi
}
# expect_fail NAME PATTERN CMD...: non-zero exit (not a crash) and stderr matching PATTERN
expect_fail() {
  local name=$1 pattern=$2; shift 2
  "$@" >"$tmp/out" 2>"$tmp/err"
  local rc=$?
  if [ $rc -eq 0 ]; then bad "$name: succeeded"; return; fi
  if [ $rc -ge 128 ]; then bad "$name: crashed with signal $((rc - 128))"; return; fi
  if grep -Eq "$pattern" "$tmp/err"; then ok; else bad "$name: stderr does not match /$pattern/: $(head -c 400 "$tmp/err")"; fi
}

# 1. A demo at 512x512 renders in seconds, PNG and JPEG, of exactly that size.
start=$(date +%s%N)
expect_ok "render tornado png" "$LUCENT" render --dataset demo:tornado --size 512x512 --out "$tmp/t.png"
ms=$((($(date +%s%N) - start) / 1000000))
echo "render demo:tornado 512x512: ${ms} ms (process start to exit)"
[ "$(image_size "$tmp/t.png")" = "512 512" ] && ok || bad "tornado png size: $(image_size "$tmp/t.png")"
grep -q "importance" "$tmp/out" && grep -q "total" "$tmp/out" && ok || bad "render prints per-pass timings"
expect_ok "render points jpeg" "$LUCENT" render --dataset "demo:points?count=50000" --size 320x200 --out "$tmp/p.jpg" --quality 80
[ "$(image_size "$tmp/p.jpg")" = "320 200" ] && ok || bad "points jpeg size: $(image_size "$tmp/p.jpg")"

# 2. The full request of the README/issue, and flags overriding it.
cat >"$tmp/req.json" <<'JSON'
{ "dataset": "demo:tornado", "width": 256, "height": 192, "method": "fourier", "format": "png", "quality": 90,
  "camera": { "position": [0.5, -2.5, 0.5], "focalPoint": [0.5, 0.5, 0.5], "viewUp": [0, 0, 1], "viewAngle": 30,
              "parallelProjection": false, "parallelScale": 1 },
  "params": { "q": 60, "r": 500, "lambda": 1, "bands": 5, "smoothing": 15, "smoothingWeight": 0.1,
              "fadeHalfLife": 0.15, "resolutionScale": 0.5, "subset": 1, "depthMargin": 0.02, "estimator": "midpoint" },
  "importance": { "attribute": "curvature", "range": [0, 1], "exponent": 1 },
  "color": { "attribute": "importance", "colormap": "viridis", "range": [0, 1] },
  "style": { "background": [1, 1, 1], "lineWidth": 0.01, "pointSize": 2, "shading": "phong" } }
JSON
expect_ok "render request" "$LUCENT" render --request "$tmp/req.json" --out "$tmp/r.png"
[ "$(image_size "$tmp/r.png")" = "256 192" ] && ok || bad "request size: $(image_size "$tmp/r.png")"
expect_ok "flags override request" "$LUCENT" render --request "$tmp/req.json" --size 64x48 --bands 3 --method direct --out "$tmp/r2.png"
expect_fail "a field where it does not apply (bands with opaque)" "params.bands: applies to method" \
  "$LUCENT" render --request "$tmp/req.json" --size 64x48 --bands 3 --method opaque --out "$tmp/r3.png"
[ "$(image_size "$tmp/r2.png")" = "64 48" ] && ok || bad "override size: $(image_size "$tmp/r2.png")"
for m in fourier opaque direct wboit kanzler; do
  expect_ok "method $m" "$LUCENT" render --dataset demo:abc --size 96x96 --method "$m" --out "$tmp/m_$m.png"
done

# 3. Bad requests and flags: clear message, non-zero exit.
printf '{"width": 256,' >"$tmp/trunc.json"
expect_fail "truncated request" "trunc.json" "$LUCENT" render --request "$tmp/trunc.json" --out "$tmp/x.png"
printf '{"params": {"bandz": 3}}' >"$tmp/unknown.json"
expect_fail "unknown field" "params.bandz" "$LUCENT" render --request "$tmp/unknown.json" --out "$tmp/x.png"
printf '{"params": {"bands": 9}}' >"$tmp/range.json"
expect_fail "bands out of range" "params.bands" "$LUCENT" render --request "$tmp/range.json" --out "$tmp/x.png"
printf '{"width": "wide"}' >"$tmp/type.json"
expect_fail "wrong type" "width" "$LUCENT" render --request "$tmp/type.json" --out "$tmp/x.png"
expect_fail "missing request file" "nope.json" "$LUCENT" render --request "$tmp/nope.json" --out "$tmp/x.png"
expect_fail "bad size flag" "size" "$LUCENT" render --size 12xq --out "$tmp/x.png"
expect_fail "bad bands flag" "bands" "$LUCENT" render --bands 0 --out "$tmp/x.png"
expect_fail "unknown attribute" "nosuch" "$LUCENT" render --dataset demo:abc --importance nosuch --size 64x64 --out "$tmp/x.png"
expect_fail "unknown demo" "nosuchdemo" "$LUCENT" render --dataset demo:nosuchdemo --out "$tmp/x.png"
expect_fail "bad output extension" "png" "$LUCENT" render --dataset demo:abc --size 32x32 --out "$tmp/x.bmp"

# 4. Bad dataset files: the error names the file and the reason.
printf 'ply\nformat ascii 1.0\nelement vertex 4000000000\nproperty float x\nproperty float y\nproperty float z\nend_header\n0 0 0\n' >"$tmp/huge.ply"
expect_fail "hostile PLY" "huge.ply.*(exceeds|vertex)" "$LUCENT" render --input "$tmp/huge.ply" --out "$tmp/x.png"
printf 'ply\nformat binary_little_endian 1.0\nelement vertex 10\nproperty float x\nproperty float y\nproperty float z\nend_header\n\x00\x00' >"$tmp/short.ply"
expect_fail "truncated PLY" "short.ply" "$LUCENT" info "$tmp/short.ply"
printf 'v 0 0 0\nv 1 0 0\nl 1 7\n' >"$tmp/badidx.obj"
expect_fail "OBJ index out of range" "badidx.obj.*line 3" "$LUCENT" info "$tmp/badidx.obj"
printf 'garbage\n' >"$tmp/garbage.xyzw"
expect_fail "unknown extension" "garbage.xyzw.*expected .*\\.tck.*\\.binlines" "$LUCENT" info "$tmp/garbage.xyzw"
printf 'x,y\n1,2\n' >"$tmp/flat.csv"
expect_fail "CSV without z" "flat.csv: line 1: no position columns" "$LUCENT" info "$tmp/flat.csv"

# 5. info, and gen round trips through both formats.
expect_ok "info demo" "$LUCENT" info demo:tornado
grep -q "elements" "$tmp/out" && grep -q "curvature" "$tmp/out" && ok || bad "info lists elements and attributes"
grep -Eq "^loaded in +[0-9.]+ ms" "$tmp/out" && grep -Eq "^memory +[0-9.]+ MB in the scene's arrays, peak RSS [0-9.]+ MB" "$tmp/out" &&
  ok || bad "info reports load time and memory: $(tail -2 "$tmp/out")"
expect_ok "info tck" "$LUCENT" info "$SRC/tests/data/loaders/tck/valid/lines_f64be.tck"
grep -q "lines       2" "$tmp/out" && ok || bad "info on a .tck: $(head -5 "$tmp/out")"
# Vector fields: a demo field and a grid file are described, a bad grid names its line.
expect_ok "info field demo" "$LUCENT" info demo:double-gyre-flow
grep -q "^type        vector field (time-dependent" "$tmp/out" && grep -q "^time        \[0, 20\]" "$tmp/out" &&
  ok || bad "info on a demo field: $(head -6 "$tmp/out")"
expect_ok "info field file" "$LUCENT" info "$SRC/tests/data/fields/valid/rectilinear_be.vtk"
grep -q "^grid        rectilinear, 3 x 3 x 2 nodes" "$tmp/out" && grep -q "^magnitude   \[3.16228, 7.87401\]" "$tmp/out" &&
  ok || bad "info on a field file: $(head -6 "$tmp/out")"
expect_fail "bad field file" "not_increasing.vtk: line 7: X_COORDINATES value 2" "$LUCENT" info \
  "$SRC/tests/data/fields/invalid/not_increasing.vtk"
# The curves of a stream surface from a seed line, as a line dataset; bad seeds name seed.points.
expect_ok "gen traced curves" "$LUCENT" gen demo:shear-flow --seed-line "-0.9,-0.5,0;-0.9,0.5,0" --count 16 \
  --length 1 -o "$tmp/sheet.vtk"
expect_ok "info traced curves" "$LUCENT" info "$tmp/sheet.vtk"
grep -q "^lines       16 " "$tmp/out" && grep -q "^  normal_z  *\[1, 1\]" "$tmp/out" &&
  ok || bad "16 curves with the shear plane's normal: $(grep -E '^lines|normal_z' "$tmp/out")"
expect_fail "seed outside" "seed.points: point 0 \(5, 0, 0\) lies outside demo:shear-flow" "$LUCENT" gen \
  demo:shear-flow --seed-line "5,0,0;0,0,0" -o "$tmp/x.vtk"
expect_fail "seed syntax" "seed.points: point 1: expected x,y,z" "$LUCENT" gen demo:abc-flow --seed-line "1,1,1;2,2" \
  -o "$tmp/x.vtk"
expect_fail "no seed" "seed.points: demo:abc-flow is a vector field" "$LUCENT" gen demo:abc-flow -o "$tmp/x.vtk"
expect_fail "seed on lines" "tornado: .*seed-line, --seeding, .*--mesh and --split apply to vector fields only" \
  "$LUCENT" gen tornado --seed-line "0,0,0;1,1,1" -o "$tmp/x.vtk"
# Streamline sets (docs/ALGORITHM.md §22): a rake of 5 in the shear flow gives 5 lines along x from x = -0.5;
# two ways they reach back upstream to x = -0.9.
expect_ok "gen rake" "$LUCENT" gen demo:shear-flow --seeding rake --seeds "-0.5,-0.5,0;-0.5,0.5,0" --count 5 \
  --length 0.4 -o "$tmp/rake.vtk"
expect_ok "info rake" "$LUCENT" info "$tmp/rake.vtk"
grep -q "^lines       5 " "$tmp/out" && grep -q "^bounds *\[-0.5, -0.0" "$tmp/out" &&
  ok || bad "5 rake lines from x = -0.5 to -0.1: $(grep -E '^lines|^bounds' "$tmp/out")"
expect_ok "gen rake both ways" "$LUCENT" gen demo:shear-flow --seeding rake --seeds "-0.5,-0.5,0;-0.5,0.5,0" \
  --count 5 --length 0.4 --direction both -o "$tmp/rake2.vtk"
expect_ok "info rake both ways" "$LUCENT" info "$tmp/rake2.vtk"
grep -q "^lines       5 " "$tmp/out" && grep -q "^bounds *\[-0.90[0-9]*, -0.0" "$tmp/out" &&
  ok || bad "5 two-way lines from x = -0.9 to -0.1 (a step past each half's length): $(grep -E '^lines|^bounds' "$tmp/out")"
expect_ok "gen density" "$LUCENT" gen demo:abc-flow --seeding density --count 20 -o "$tmp/dense.vtk"
grep -q "^density seeding: 20 of [0-9]* candidates kept at separation" "$tmp/out" &&
  ok || bad "density seeding reports its candidates: $(head -3 "$tmp/out")"
expect_ok "render a streamline set" "$LUCENT" render \
  --dataset "streamlines:demo:shear-flow?seeding=rake&seeds=-0.5,-0.5,0;-0.5,0.5,0&count=5&length=0.4" \
  --size 64x64 --out "$tmp/rake.png"
expect_fail "streamline set key" "streamlines.direction: 'up' is not one of forward" "$LUCENT" info \
  "streamlines:demo:shear-flow?direction=up"
expect_fail "rake without ends" "gen: --seeding rake needs --seeds" "$LUCENT" gen demo:abc-flow --seeding rake -o "$tmp/x.vtk"
expect_fail "bad direction" "gen: --direction: 'up' is not forward, backward or both" "$LUCENT" gen demo:abc-flow \
  --seed-line "1,1,1;2,2,2" --direction up -o "$tmp/x.vtk"
expect_fail "flat box" "seeding.box: axis y" "$LUCENT" gen demo:abc-flow --seeding box \
  --seeds "1,1,1;2,1,2" -o "$tmp/x.vtk"
# The meshed reference: the shear flow's surface from a straight seed line is the plane z = 0.
expect_ok "gen meshed surface" "$LUCENT" gen demo:shear-flow --seed-line "-0.9,-0.5,0;-0.9,0.5,0" --length 1 --mesh \
  -o "$tmp/sheet.obj"
grep -q "^meshed [0-9]* particles: [0-9]* vertices, [1-9][0-9]* triangles" "$tmp/out" &&
  ok || bad "gen --mesh reports its particles and triangles: $(head -2 "$tmp/out")"
expect_ok "info meshed surface" "$LUCENT" info "$tmp/sheet.obj"
grep -q "^type        triangles" "$tmp/out" && grep -q "^bounds .* x \[-0.5, 0.5\] x \[0, 0\]" "$tmp/out" &&
  ok || bad "the mesh is the plane z = 0: $(grep -E '^type|^bounds' "$tmp/out")"
expect_fail "mesh on lines" "tornado: .*--mesh and --split apply to vector fields only" "$LUCENT" gen tornado --mesh \
  -o "$tmp/x.obj"
for demo in surface tornado; do
  for ext in ply obj; do
    expect_ok "gen $demo.$ext" "$LUCENT" gen "$demo" -o "$tmp/$demo.$ext" --count 20
    expect_ok "info $demo.$ext" "$LUCENT" info "$tmp/$demo.$ext"
    expect_ok "render $demo.$ext" "$LUCENT" render --input "$tmp/$demo.$ext" --size 64x64 --out "$tmp/$demo-$ext.png"
  done
done

# 6. The benchmark prints its table (tiny here; `lucent bench` defaults to 1024^2).
expect_ok "bench" "$LUCENT" bench --size 64x64 --frames 1 --warmup 0
rows=$(grep -c '^demo:' "$tmp/out")
[ "$rows" -ge 4 ] && ok || bad "bench printed $rows dataset rows"
grep -q "pipeline MB" "$tmp/out" && ok || bad "bench prints memory"
# --dataset benches that dataset alone (it used to be accepted and ignored), with --elements.
expect_ok "bench --dataset" "$LUCENT" bench --dataset "demo:tornado?count=20" --elements 300 --size 64x64 --frames 1 --warmup 0
rows=$(grep -c '^demo:' "$tmp/out")
[ "$rows" -eq 1 ] && grep -q '^demo:tornado .* 300 ' "$tmp/out" && ok || bad "bench --dataset printed $rows rows: $(grep '^demo:' "$tmp/out")"
# A flag that would go unused is refused, not ignored.
expect_fail "bench --dataset and --datasets" "not both" "$LUCENT" bench --dataset demo:abc --datasets abc --size 16x16
expect_fail "bench --point-stride alone" "interactive frames only" "$LUCENT" bench --point-stride 2 --size 16x16
expect_fail "bench --uniform-points alone" "point-stride N > 1" "$LUCENT" bench --interactive --uniform-points \
  --size 16x16
expect_fail "render --uniform-points alone" "needs --point-stride" "$LUCENT" render --dataset demo:points \
  --uniform-points --size 16x16 --out "$tmp/x.png"
expect_fail "render --point-stride 0" "render: --point-stride: \"0\" is not an integer in \\[1, 1024\\]" "$LUCENT" render --dataset demo:points --point-stride 0 \
  --size 16x16 --out "$tmp/x.png"

# 7. No usable EGL: a clear message naming EGL and what to install; a device that does not exist.
expect_fail "no EGL vendor" "EGL.*install" env __EGL_VENDOR_LIBRARY_FILENAMES=/nonexistent.json \
  "$LUCENT" render --dataset demo:abc --size 32x32 --out "$tmp/x.png"
expect_fail "missing device" "device 7 does not exist" "$LUCENT" render --device 7 --dataset demo:abc --size 32x32 --out "$tmp/x.png"
expect_fail "missing device (env)" "device 7 does not exist" env LUCENT_EGL_DEVICE=7 \
  "$LUCENT" render --dataset demo:abc --size 32x32 --out "$tmp/x.png"

# 8. Usage errors.
expect_fail "unknown command" "unknown command" "$LUCENT" frobnicate
expect_fail "render without --out" "render: --out IMG.png\\|.jpg is required" "$LUCENT" render --dataset demo:abc

echo "$pass passed, $fail failed"
[ "$fail" -eq 0 ]
