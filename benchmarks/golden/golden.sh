#!/usr/bin/env bash
# Golden outputs through the CLI; prints a sha256 of each (see README.md beside this file).
set -euo pipefail
OUT=$(realpath -m "${1:?usage: golden.sh OUT_DIR}"); rm -rf "$OUT"; mkdir -p "$OUT"; cd "$(dirname "$0")/../.."
S=samples/data; GEOIMG_DATA=geoimg/data
geoimg image $GEOIMG_DATA/mountain.obj -o $OUT/planar.exr --res 129 --s 2 --preview $OUT/planar.png -q
geoimg mesh $OUT/planar.exr -o $OUT/planar_quads.obj -q
geoimg image $S/spot_low_resolution.obj -o $OUT/octa.exr --res 65 -q
geoimg mesh $OUT/octa.exr -o $OUT/octa_quads.obj -q
geoimg image $S/spot_control_mesh.obj -o $OUT/ctrl.exr --res 33 -q
geoimg filter $OUT/planar.exr -o $OUT/planar_f.exr --mean 5 --sharpen 3 --mesh $OUT/planar_f.obj -q
geoimg filter $OUT/planar.exr -o $OUT/planar_m.exr --gaussian 3 --uv-region 0.5 0.5 0.2 --feather 8 -q
geoimg filter $OUT/octa.exr -o $OUT/octa_f.exr --gaussian 2 --lowpass 0.2 -q
geoimg filter $OUT/octa.exr -o $OUT/octa_r.exr --mean 3 --region 0 0 0 0.3 -q
geoimg curvature $OUT/octa.exr -o $OUT/octa_curv -q
geoimg curvature $OUT/planar.exr -o $OUT/planar_curv -q
geoimg morph $OUT/octa.exr $OUT/octa_f.exr --frames 5 -o $OUT/morph.glb --frames-dir $OUT/frames -q
geoimg morph $S/spot_control_mesh.obj $S/spot_low_resolution.obj --res 33 --frames 4 -o $OUT/morph2.glb -q
geoimg render $OUT/octa_quads.obj -o $OUT/render.png -q
geoimg render $OUT/planar.exr -o $OUT/render_planar.png -q
geoimg demo -o $OUT/demo --res 65 -q >/dev/null
python benchmarks/golden/hash.py "$OUT"
