#!/usr/bin/env bash
# Fetches the real-data corpus that docs/EVALUATION.md "Density normalization" renders with
# defaults: scans and reconstructions from CGAL's demo data (Debian package
# libcgal-demo), a molecular-dynamics trajectory from votca-tutorials, the
# Hipparcos star catalogue of kstars-data, a terrain from matplotlib's sample
# data and a protein structure from pymol-data (each package downloaded with
# apt-get, never installed) into build/real-data/.
#   thiophene.dump      LAMMPS dump, 9,000 atoms x 100 frames (id type xs ys zs,
#                       periodic box): 9,000 trajectories, 891,000 segments
#   stars.csv           124,608 Hipparcos/Tycho stars: x,y,z in parsecs (sun at
#                       the origin, equatorial axes: x toward RA 0, z toward
#                       the north pole; distance 1000/parallax, parallaxes
#                       below 1 mas clamped to 1000 pc, stars without one
#                       skipped), magnitude (visual; larger = fainter), bv
#   building.ply        100,000 points of a building with segment_index
#   ball.ply             31,374 points with segment_index
#   b9_training.ply      22,300 airborne LIDAR points with RGB and a class label
#   radar.xyz            20,950 points, no attribute
#   bunny.ply            Stanford bunny, 37,706 vertices, 75,408 triangles
#   elephant.ply         44,460 vertices, 88,928 triangles
#   armadillo.ply        26,002 vertices, 52,000 triangles
#   terrain.ply          a digital elevation model (matplotlib's
#                       jacksboro_fault_dem: 403 x 344 samples 3 arc-seconds
#                       apart, 236-1076 m, around Jacksboro, Tennessee) as a
#                       height field: 138,632 vertices, 275,772 triangles; x
#                       east and y north in metres from the centre, z the
#                       height x 5 (a vertical exaggeration), attribute
#                       elevation (metres, as measured)
#   protein.csv          5,684 atoms of a protein crystal structure (PDB 1TII,
#                       E. coli heat-labile enterotoxin IIb, 7 chains and 215
#                       waters; pymol-data): x,y,z in angstroms, bfactor (the
#                       atom's temperature factor: how much it moves), occupancy
# The meshes come as OFF, which Lucent does not read; they are rewritten as
# ASCII PLY here (triangles only, which these files are).
# With --lammps, also the simulations of scripts/lammps_corpus.sh into
# DIR/lammps/ (installs LAMMPS with apt-get; about ten minutes on one core).
# usage: scripts/real_data.sh [--lammps] [DIR]   prints DIR; exits 1 when a package cannot be fetched
set -euo pipefail
lammps=0
if [ "${1:-}" = "--lammps" ]; then
    lammps=1
    shift
fi
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

# Fetches Debian package $1 into a fresh folder and unpacks it there; prints the folder.
unpack() {
    t=$(mktemp -d)
    (cd "$t" && apt-get download "$1" >/dev/null 2>&1) || {
        echo "real_data.sh: apt-get download $1 failed (no Debian mirror?)" >&2
        rm -rf "$t"
        exit 1
    }
    dpkg-deb -x "$t/$1"_*.deb "$t/x"
    echo "$t"
}

if [ ! -s "$DIR/thiophene.dump" ]; then
    T=$(unpack votca-tutorials)
    cp "$T/x/usr/share/votca/xtp-tutorials/LAMMPS/Thiophene/MD_FILES/traj.dump" "$DIR/thiophene.dump"
    rm -rf "$T"
fi

if [ ! -s "$DIR/stars.csv" ]; then
    T=$(unpack kstars-data)
    # Fixed-width rows: RA hhmmss.ss (columns 1-9), Dec +-ddmmss.s (11-19),
    # parallax in mas (39-45), visual magnitude (46-51), B-V (52-56).
    awk 'BEGIN { print "x,y,z,magnitude,bv"; d2r = atan2(1, 0) / 90 }
         /^#/ || length($0) < 56 { next }
         { ra = substr($0, 1, 9); de = substr($0, 11, 9); plx = substr($0, 39, 7) + 0
           if (plx <= 0) next
           a = 15 * (substr(ra, 1, 2) + substr(ra, 3, 2) / 60 + substr(ra, 5) / 3600) * d2r
           s = substr(de, 1, 1) == "-" ? -1 : 1
           d = s * (substr(de, 2, 2) + substr(de, 4, 2) / 60 + substr(de, 6) / 3600) * d2r
           r = plx < 1 ? 1000 : 1000 / plx
           printf "%.4f,%.4f,%.4f,%.2f,%.2f\n", r * cos(d) * cos(a), r * cos(d) * sin(a), r * sin(d),
                  substr($0, 46, 6) + 0, substr($0, 52, 5) + 0 }' \
        "$T/x/usr/share/kstars/stars.dat" > "$DIR/stars.csv"
    rm -rf "$T"
fi

if [ ! -s "$DIR/terrain.ply" ]; then
    T=$(unpack python-matplotlib-data)
    python3 - "$T/x/usr/share/matplotlib/mpl-data/sample_data/jacksboro_fault_dem.npz" "$DIR/terrain.ply.part" <<'PY'
import math, struct, sys, zipfile
z = zipfile.ZipFile(sys.argv[1])
def npy(name):  # (header, raw data) of a little-endian .npy member
    b = z.read(name)
    n = struct.unpack("<H", b[8:10])[0]
    return b[10:10 + n].decode(), b[10 + n:]
def scalar(name):
    return struct.unpack("<d", npy(name)[1])[0]
head, raw = npy("elevation.npy")
assert "'<i2'" in head and "(344, 403)" in head, head
rows, cols = 344, 403
h = struct.unpack("<%dh" % (rows * cols), raw)
x0, x1, y0, y1 = scalar("xmin.npy"), scalar("xmax.npy"), scalar("ymin.npy"), scalar("ymax.npy")
lat_c = math.radians((y0 + y1) / 2)
mx = 111320.0 * math.cos(lat_c)  # metres per degree of longitude there
my = 110574.0                    # and of latitude
with open(sys.argv[2], "w") as f:
    f.write("ply\nformat ascii 1.0\nelement vertex %d\nproperty float x\nproperty float y\n" % (rows * cols))
    f.write("property float z\nproperty float elevation\nelement face %d\n" % (2 * (rows - 1) * (cols - 1)))
    f.write("property list uchar int vertex_indices\nend_header\n")
    for r in range(rows):  # rows run from the north (ymin) to the south (ymax)
        lat = y0 + (y1 - y0) * r / (rows - 1)
        for c in range(cols):
            lon = x0 + (x1 - x0) * c / (cols - 1)
            e = h[r * cols + c]
            f.write("%.1f %.1f %.1f %d\n" % ((lon - (x0 + x1) / 2) * mx, (lat - (y0 + y1) / 2) * my, 5.0 * e, e))
    for r in range(rows - 1):
        for c in range(cols - 1):
            a = r * cols + c
            f.write("3 %d %d %d\n3 %d %d %d\n" % (a, a + cols, a + 1, a + 1, a + cols, a + cols + 1))
PY
    mv "$DIR/terrain.ply.part" "$DIR/terrain.ply"
    rm -rf "$T"
fi

if [ ! -s "$DIR/protein.csv" ]; then
    T=$(unpack pymol-data)
    # PDB ATOM/HETATM records: x, y, z in columns 31-54, occupancy 55-60, B 61-66.
    awk 'BEGIN { print "x,y,z,bfactor,occupancy" }
         /^(ATOM  |HETATM)/ { printf "%.3f,%.3f,%.3f,%.2f,%.2f\n", substr($0, 31, 8), substr($0, 39, 8),
                                     substr($0, 47, 8), substr($0, 61, 6), substr($0, 55, 6) }' \
        "$T/x/usr/share/pymol/data/demo/1tii.pdb" > "$DIR/protein.csv"
    rm -rf "$T"
fi

if [ "$lammps" = 1 ]; then
    "$ROOT/scripts/lammps_corpus.sh" "$DIR/lammps" >/dev/null
fi
echo "$DIR"
