#!/usr/bin/env bash
# Seeds fuzz/corpus/<target>/ with small valid inputs of each format: files of the repository
# and of ../shared/data, and a coloured two-cube union written by the csgkit binary in every
# format it writes. Usage: fuzz/seed.sh [path/to/csgkit] (default: target/release/csgkit).
set -euo pipefail
cd "$(dirname "$0")"
csgkit="${1:-../target/release/csgkit}"
data=../../shared/data
scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT

seed() { # seed TARGET FILE...
    mkdir -p "corpus/$1"
    local target=$1
    shift
    for f in "$@"; do [ -f "$f" ] && cp "$f" "corpus/$target/$(basename "$f")"; done
    return 0
}

cat > "$scratch/scene.json" <<'JSON'
{"difference": [
  {"cube": {"size": 2, "center": true}, "material": "stone"},
  {"union": [
    {"cylinder": {"r": 0.5, "h": 3, "segments": 8, "center": true},
     "transform": [[1, 0, 0, 0.2], [0, 1, 0, 0], [0, 0, 1, 0]]},
    {"sphere": {"r": 0.7, "segments": 6}}]},
  {"intersection": [{"cube": {"size": [1, 2, 3]}}, {"mesh": "missing.obj"}]}
]}
JSON
cat > "$scratch/model.csg" <<'CSG'
group() {
  difference() {
    color([1, 0, 0, 1]) cube(size = [2, 2, 2], center = true);
    multmatrix([[1, 0, 0, 0.5], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]) {
      sphere($fn = 8, $fa = 12, $fs = 2, r = 1);
    }
    cylinder($fn = 6, $fa = 12, $fs = 2, h = 3, r1 = 0.5, r2 = 0.25, center = true);
  }
  linear_extrude(height = 1, center = false, convexity = 1, twist = 30, slices = 2, scale = [1, 1]) {
    polygon(points = [[0, 0], [1, 0], [0, 1]], paths = [[0, 1, 2]], convexity = 1);
    circle($fn = 5, $fa = 12, $fs = 2, r = 0.3);
    square(size = [0.5, 0.5], center = false);
  }
  rotate_extrude(angle = 360, convexity = 2, $fn = 6) { translate([2, 0, 0]) circle(r = 0.5, $fn = 4); }
  polyhedron(points = [[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], faces = [[0, 1, 2], [0, 3, 1], [0, 2, 3], [1, 3, 2]], convexity = 1);
  union() { intersection() { cube(size = 1); sphere(r = 2); } }
}
CSG
printf '0 0 0 1 1 1\n0.5 0.5 0.5 2 2 2\n# a comment\n-1 -1 -1 0 0 0\n' > "$scratch/boxes.txt"
printf '0 0 0 1 1 1\n' > "$scratch/one_box.txt"
printf 'ply\nformat ascii 1.0\nelement vertex 4\nproperty double x\nproperty double y\nproperty double z\nelement face 2\nproperty list uchar int vertex_indices\nproperty uchar red\nproperty uchar green\nproperty uchar blue\nend_header\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1 255 0 0\n4 0 1 3 2 0 255 0\n' > "$scratch/ascii.ply"

seed read_scene_json "$scratch/scene.json"
seed read_openscad_csg "$scratch/model.csg"
seed read_boxes_text "$scratch/boxes.txt" "$scratch/one_box.txt"
seed read_vox "$data/voxels/chr_knight.vox" "$data/voxels/chr_mayor.vox"
seed read_obj ../crates/csgkit/tests/data/cube.obj "$data/meshes/joined_tetrahedra.obj" \
    "$data/meshes/Cray_right.obj"
seed read_off "$data"/meshes/cgal_*.off
seed read_ply "$scratch/ascii.ply"
seed read_stl "$data/meshes/shared.stl" "$data/meshes/soup.stl"
mkdir -p corpus/read_ply corpus/read_3mf corpus/read_gltf corpus/read_glb corpus/boolean_solids

if [ -x "$csgkit" ]; then
    # Two cubes with materials and colours, united: polygons, triangles, attributes.
    cat > "$scratch/pair.json" <<'JSON'
{"union": [{"cube": {"size": 1}, "material": "red"},
           {"cube": {"size": 1}, "material": "blue",
            "transform": [[1, 0, 0, 0.5], [0, 1, 0, 0.5], [0, 0, 1, 0]]}]}
JSON
    "$csgkit" csg "$scratch/pair.json" -o "$scratch/pair.obj" --polygons
    for target in obj ply off stl 3mf gltf glb; do
        "$csgkit" csg "$scratch/pair.json" -o "$scratch/pair.$target" --polygons
        seed "read_$target" "$scratch/pair.$target"
    done
else
    echo "seed.sh: no csgkit binary at $csgkit; only file seeds written" >&2
fi
echo "seeded: $(for d in corpus/*; do printf '%s=%s ' "${d#corpus/}" "$(ls "$d" | wc -l)"; done)"
