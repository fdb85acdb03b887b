#!/usr/bin/env bash
# reproducible.sh BUILD_DIR: the same input gives the same answer, to the last byte, on any
# thread count: the quick look (labels pipeline and reproducible); tests/reproducible/full.sh
# (ctest reproducible_full) is the check at full size, on the demo and `make quick` as the
# README runs them. A coarse version of the default eye (plans/eye.yaml with larger element sizes,
# still order 2 and meshed by the same gmsh calls as the default: the 3D mesher and its options
# do not depend on the sizes) is taken through
#   1. mesh-prep twice, once with OMP_NUM_THREADS=1 OPENBLAS_NUM_THREADS=1 and once with both 2,
#      in different folders: the two .msh files are equal (cmp);
#   2. the demo pipeline (cutplan plans/lri-paired-60.yaml | augsolve | curvature, as
#      scripts/demo.sh runs it) on each of those two meshes, with the same two thread settings:
#      the two curvature.tsv are equal, and the cut did something (SIA > 0 at the last step);
#   3. the nomogram study (plans/studies/nomogram) twice from nothing, each meshing its own eye:
#      once with make (ENGINE=local) and once with ENGINE=parallel, on a reduced spec written
#      here (the coarse eye, paired arcs of 15 and 30 deg: two steps of one run): the two
#      nomogram.tsv are equal.
# This test: 3 min 9 s at load ~12 (33 s of CPU); the full one takes minutes of CPU.
set -euo pipefail
B=$(cd "$1" && pwd)
cd "$(dirname "$0")/.."
ROOT=$PWD
T=$(mktemp -d /tmp/kt-reproducible.XXXXXX)
trap 'rm -rf "$T"' EXIT
# under the sanitizer build, gmsh's own leftovers are not ours to report
printf 'leak:libgmsh.so\n' > "$T/lsan.supp"
export LSAN_OPTIONS="suppressions=$T/lsan.supp:print_suppressions=0"
fail() { echo "reproducible: FAILED: $*" >&2; exit 1; }

bash tests/lib/coarse-eye.sh 0.8 0.4 1.0 2.5 "$T/eye.yaml" && grep -q "^order: 2 " "$T/eye.yaml" ||
    fail "could not coarsen plans/eye.yaml"

# 1. mesh-prep, two thread settings, two folders.
mkdir -p "$T/a" "$T/b"
(cd "$T/a" && OMP_NUM_THREADS=1 OPENBLAS_NUM_THREADS=1 "$B/mesh-prep" -q ../eye.yaml -o eye.msh > prep.txt) ||
    fail "mesh-prep (1 thread)"
(cd "$T/b" && OMP_NUM_THREADS=2 OPENBLAS_NUM_THREADS=2 "$B/mesh-prep" -q "$T/eye.yaml" -o mesh.msh > prep.txt) ||
    fail "mesh-prep (2 threads)"
cmp "$T/a/eye.msh" "$T/b/mesh.msh" || fail "mesh-prep gave two different meshes of one scene"
echo "reproducible: mesh-prep: $(awk '$1 == "mesh" { print $2 }' "$T/a/prep.txt") nodes, the same file twice"

# 2. The demo pipeline on each mesh.
pipeline() { # DIR MESH THREADS
    (cd "$1" && export OMP_NUM_THREADS=$3 OPENBLAS_NUM_THREADS=$3 &&
     "$B/cutplan" -q "$ROOT/plans/lri-paired-60.yaml" "$2" -o - | "$B/augsolve" -q "$2" - -o run &&
     "$B/curvature" -q --no-png run > /dev/null) || fail "the demo pipeline in $1"
}
pipeline "$T/a" eye.msh 1
pipeline "$T/b" mesh.msh 2
cmp "$T/a/run/curvature.tsv" "$T/b/run/curvature.tsv" || fail "two curvature.tsv of one plan on one scene differ"
steps=$(($(wc -l < "$T/a/run/steps.tsv") - 1))
awk -F'\t' -v n0="$steps" 'NR == 1 { for (i = 1; i <= NF; i++) c[$i] = i; next } { n++; s = $c["sia_D"] }
    END { exit !(n == n0 && n >= 5 && s + 0 > 0.1) }' "$T/a/run/curvature.tsv" ||
    fail "curvature.tsv does not hold a row per step ($steps) ending with an SIA above 0.1 D"
echo "reproducible: demo pipeline: the same curvature.tsv twice (SIA $(awk -F'\t' 'NR == 1 {
    for (i = 1; i <= NF; i++) if ($i == "sia_D") k = i } END { print $k }' "$T/a/run/curvature.tsv") D)"

# 3. The nomogram study, locally and through GNU parallel, each from nothing.
spec=$T/study.spec
printf 'base %s\nage_rule 60 0.075\n' "$T/eye.yaml" > "$spec"
printf 'eye default 44.02 42.52 90 540 60 -\nrun full default 2 0.9 10.5 15 30\n' >> "$spec"
printf 'band 1.00 1.50\n' >> "$spec"
mk=(make --no-print-directory -C plans/studies/nomogram KT_BUILD="$B" KEEP_VTK=0 SPEC="$spec")
"${mk[@]}" OUT="$T/local" > "$T/local.log" 2>&1 || { tail -n 20 "$T/local.log" >&2; fail "make (local)"; }
if command -v parallel > /dev/null; then
    "${mk[@]}" OUT="$T/par" ENGINE=parallel > "$T/par.log" 2>&1 ||
        { tail -n 20 "$T/par.log" >&2; fail "make ENGINE=parallel"; }
    [ -s "$T/par/eyes/default.msh" ] || fail "ENGINE=parallel did not mesh its own eye"
    cmp "$T/local/eyes/default.msh" "$T/par/eyes/default.msh" || fail "the two studies' eyes differ"
    cmp "$T/local/nomogram.tsv" "$T/par/nomogram.tsv" || fail "the local and the parallel nomogram.tsv differ"
    [ "$(wc -l < "$T/local/nomogram.tsv")" -eq 3 ] || fail "nomogram.tsv does not hold its two cases"
    echo "reproducible: nomogram study: the same nomogram.tsv locally and with ENGINE=parallel"
else
    echo "reproducible: GNU parallel missing (bash scripts/setup.sh): the study part is skipped" >&2
    exit 77
fi
