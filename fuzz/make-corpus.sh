#!/usr/bin/env bash
# Writes the seed corpus of every harness into fuzz/corpus/<harness>/ (the
# files are committed; run this again after changing a harness's input
# format). Small valid inputs: the fuzzer mutates from files our readers
# accept, so it reaches the validation behind the parser.
set -euo pipefail
cd "$(dirname "$0")/corpus"
rm -rf scene mesh path_csv artifact path tau voxels spheres labels distfield
mkdir -p scene mesh path_csv artifact path tau voxels spheres labels distfield

# scene.yaml beside s.obj, d.obj, s.off and d.off (the harness writes those;
# the same tetrahedron): the OFF files load in 1-2 ms under ASan, the OBJ
# files in about 80 ms (fuzz_scene.cpp), so one seed names the OBJ files.
printf 'format: ausbau-scene/1\nstatic: s.obj\ndynamic: d.obj\n' > scene/minimal.yaml
printf 'format: ausbau-scene/1\nstatic: s.off\ndynamic: d.off\n' > scene/minimal-off.yaml
printf 'format: ausbau-scene/1\nname: full\nunits: mm\nstatic: [s.off, s.off]\ndynamic: d.off\ndynamic_origin: [0.25, 0.25, 0.25]\nstart: {t: [0, 0, 0], q: [1, 0, 0, 0]}\ngoal: {t: [5, 0, 0], q: [0.7071068, 0.7071068, 0, 0]}\nbounds: {min: [-10, -10, -10], max: [10, 10, 10]}\n' > scene/full.yaml
printf 'format: ausbau-scene/2\nunits: mm\nassembly: {file: s.off, units: cm}\nstatic: [{file: s.off, part: 0, pose: {t: [20, 0, 0], q: [1, 0, 0, 0]}}]\ndynamic: {file: d.off, part: [0]}\n' > scene/assembly.yaml
printf '# a comment\nformat: "ausbau-scene/1"\nstatic:\n  - s.off\ndynamic: d.off\nstart:\n  t: [1e3, -2.5, 0x10]\n' > scene/block.yaml

# Meshes: the first byte picks the extension (fuzz_mesh.cpp): 0 .obj, 1 .stl,
# 2 .ply, 3 .off, 4 .OBJ (capitals), 5 .txt, 6 none.
tetra_obj='v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n'
printf "\x00$tetra_obj" > mesh/tetra.obj
printf '\x00o quad\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvn 0 0 1\nvt 0 0\nf 1/1/1 2/1/1 3/1/1 4/1/1\nf -1 -2 -3\n' > mesh/quad.obj
printf '\x01solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nendloop\nendfacet\nendsolid t\n' > mesh/tri.stl
{ printf '\x01'; printf 'binary stl header%63s' ''; printf '\x01\x00\x00\x00'; head -c 12 /dev/zero;
  printf '\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00'; printf '\x00\x00\x80\x3f\x00\x00\x00\x00\x00\x00\x00\x00';
  printf '\x00\x00\x00\x00\x00\x00\x80\x3f\x00\x00\x00\x00'; printf '\x00\x00'; } > mesh/tri-binary.stl
printf '\x02ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\nelement face 2\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 1 2\n3 0 1 3\n' > mesh/tetra.ply
# A list count no line holds (fuzz_mesh found assimp asking for 15 GB for it).
printf '\x02ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\nelement face 2\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 1 2\n%s3 0 1 3\n' "$(printf '7%.0s' $(seq 40))" > mesh/ply-huge-list-count.ply
# A form feed before end_header (fuzz_mesh: it passed our header check and
# assimp never found the header's end).
printf '\x02ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n\fend_header\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n' > mesh/ply-form-feed-header.ply
printf '\x03OFF\n4 2 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 1 2\n3 0 1 3\n' > mesh/tetra.off
printf "\x04$tetra_obj" > mesh/tetra-capitals.OBJ
printf "\x05$tetra_obj" > mesh/tetra.txt
# OBJ as exporters write it (CRLF, a byte order mark, objects, groups,
# materials, every corner form, relative indices, a free-form section), and
# the face line with NUL bytes and mixed corner forms that corrupted assimp's
# heap (fuzz_mesh; now refused by CheckObjStructure).
printf '\x00\xEF\xBB\xBF# exported\r\nmtllib m.mtl mesh.obj\r\no part\r\ng a b\r\nusemtl steel\r\ns 1\r\nv 0 0 0\r\nv 1.5e+0 0 0\r\nv 0 1. 0 1\r\nv 0 0 1 0.5 0.5 0.5\r\nvt 0 0\r\nvt 1 0 0\r\nvn 0 0 1\r\nf 1 2 3\r\nf 1/1 2/2 4/1\r\nf 1//1 3//1 4//1\r\nf -3/-2/-1 -2/-1/-1 -1/-2/-1\r\nl 1 2\r\np 1\r\ncstype bspline\r\ndeg 3\r\nend\r\n' > mesh/exporter.obj
printf '\x00v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nvt 0 0\nf 1/1/1 2/1\x00\x00\x00 3/1/1\n' > mesh/obj-mixed-corners-nul.obj
# An mtllib naming the file itself (the harness writes mesh.obj): assimp
# parsed the mesh as a material library and crashed on "map_emissive".
printf '\x00mtllib mesh.obj\nmap_emissive x\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n' > mesh/obj-mtllib-itself.obj

printf 'x,y,z,qw,qx,qy,qz\n0,0,0,1,0,0,0\n1.5,2,-3,0.7071067811865476,0,0.7071067811865476,0\n' > path_csv/plain.csv
printf '# written by a tool\r\nqw, qx, qy, qz, x, y, z, extra\r\n1, 0, 0, 0, 1e3, 0, 0, note\r\n' > path_csv/reordered.csv

# Artifact recipes (artifact_recipe.cpp): no bytes = the typical valid file;
# then a dataset left out, free dims from the recipe, another type, a huge
# declared size, and values from the palette (NaN, inf, 1e300, ...).
for h in artifact path tau voxels spheres labels distfield; do
  : > "$h/valid"
  printf '\x01' > "$h/first-absent"
  printf '\x05\x03\x03\x00\x05\x03\x03' > "$h/free-dims"
  printf '\x02\x04' > "$h/other-type"
  printf '\x04\x00\x01' > "$h/huge"
  printf '\x00\x04\x05\x07\x0c\x01\x02\x03\x04\x05\x06\x07\x08' > "$h/values"
done
