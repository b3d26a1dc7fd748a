#!/bin/sh
# Fetches the real point clouds and meshes that docs/EVALUATION.md §7 renders
# with the density normalization: scans and reconstructions from CGAL's demo
# data (Debian package libcgal-demo, downloaded with apt-get, not installed)
# into build/real-data/. Debian 12 ships no large real line data (see
# bench_peers_data.sh); these are the real point sets and meshes it has.
#   building.ply        100,000 points of a building with segment_index
#   ball.ply             31,374 points with segment_index
#   b9_training.ply      22,300 airborne LIDAR points with RGB and a class label
#   radar.xyz            20,950 points, no attribute
#   bunny.ply            Stanford bunny, 37,706 vertices, 75,408 triangles
#   elephant.ply         44,460 vertices, 88,928 triangles
#   armadillo.ply        26,002 vertices, 52,000 triangles
# The meshes come as OFF, which Lucent does not read; they are rewritten as
# ASCII PLY here (triangles only, which these files are).
# usage: scripts/real_data.sh [DIR]   prints DIR; exits 1 when the package cannot be fetched
set -eu
ROOT=$(cd "$(dirname "$0")/.." && pwd)
DIR=${1:-$ROOT/build/real-data}
FILES="points_3/building.ply points_3/ball.ply points_3/b9_training.ply points_3/radar.xyz"
MESHES="bunny00:bunny refined_elephant:elephant armadillo:armadillo"
mkdir -p "$DIR"
missing=0
for f in $FILES; do [ -s "$DIR/$(basename "$f")" ] || missing=1; done
for m in $MESHES; do [ -s "$DIR/${m#*:}.ply" ] || missing=1; done
if [ "$missing" = 1 ]; then
    TMP=$(mktemp -d)
    trap 'rm -rf "$TMP"' EXIT
    (cd "$TMP" && apt-get download libcgal-demo >/dev/null 2>&1) || {
        echo "real_data.sh: apt-get download libcgal-demo failed (no Debian mirror?)" >&2
        exit 1
    }
    dpkg-deb -x "$TMP"/libcgal-demo_*.deb "$TMP/x"
    members=""
    for f in $FILES; do members="$members data/$f"; done
    for m in $MESHES; do members="$members data/meshes/${m%%:*}.off"; done
    # shellcheck disable=SC2086 # a word list by design
    tar -xzf "$TMP/x/usr/share/doc/libcgal-dev/data.tar.gz" -C "$TMP" $members
    for f in $FILES; do cp "$TMP/data/$f" "$DIR/"; done
    for m in $MESHES; do
        awk 'BEGIN { state = 0 }
             /^[ \t]*(#|$)/ { next }
             state == 0 { if ($1 != "OFF") { print "not OFF" > "/dev/stderr"; exit 1 } state = 1; next }
             state == 1 { nv = $1; nf = $2
                          printf "ply\nformat ascii 1.0\nelement vertex %d\nproperty float x\nproperty float y\n", nv
                          printf "property float z\nelement face %d\nproperty list uchar int vertex_indices\nend_header\n", nf
                          state = 2; next }
             state == 2 { print $1, $2, $3; if (++v == nv) state = 3; next }
             state == 3 { if ($1 != 3) { print "not a triangle" > "/dev/stderr"; exit 1 } print $1, $2, $3, $4 }' \
            "$TMP/data/meshes/${m%%:*}.off" > "$DIR/${m#*:}.ply"
    done
fi
echo "$DIR"
