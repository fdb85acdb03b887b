#!/usr/bin/env bash
# demo.sh [RUN_DIR]: the keratome demo. The default eye (plans/eye.yaml: 1.5 D with-the-rule
# astigmatism) is meshed, cut with paired 60-degree limbal relaxing incisions at the steep
# meridian (plans/lri-paired-60.yaml, 5 degrees of arc a step), solved step by step with
# augsolve's planned method (the whole plan read from cutplan's pipe, one factorization of the
# final cut mesh, every step exact by substitution), and read like a topographer:
#   mesh-prep -> cutplan | augsolve -> curvature
# It prints the pre-operative K, K at every step, flattening, steepening, coupling ratio and SIA
# (curvature), and the per-step solve times (augsolve's steps.tsv); RUN_DIR (default run/demo)
# keeps the mesh, the step VTKs, surface-NNNN.vtk, the axial power maps axial-NNNN.png, the
# teaching page report.html and the ParaView time series steps.pvd.
# It first installs what is missing (scripts/setup.sh) and builds (scripts/build.sh).
# augsolve runs with --uncertainty (issue 21): curvature's summary and report.html show the SIA
# with its 90% band (first order, the scene's uncertain quantities; curvature(1), UNCERTAINTY).
# The mesh and the step files are binary (mesh-prep --binary: binary MSH 4.1; augsolve --binary:
# binary legacy VTK, keratome-vtk(5)): the same values to the bit as ASCII, which ParaView, gmsh,
# meshio and curvature read alike, at a fraction of the bytes and of the time to write and read.
# mesh-prep --chosen-only: its summary's ordering table holds the chosen ordering alone (the
# other rows cost a third of mesh-prep's CPU; the mesh is the same, mesh-prep(1), COST).
# Environment: KT_BUILD, the build folder with the tools (default build); KT_NO_BUILD=1 skips
# set-up and build (for tests that already built); KT_EYE and KT_PLAN, another scene and plan
# (default plans/eye.yaml and plans/lri-paired-60.yaml; a plan whose scene: is that eye).
set -euo pipefail
cd "$(dirname "$0")/.."
B=${KT_BUILD:-build}
RUN=${1:-run/demo}
EYE=${KT_EYE:-plans/eye.yaml}
PLAN=${KT_PLAN:-plans/lri-paired-60.yaml}
if [ -z "${KT_NO_BUILD:-}" ]; then
    bash scripts/setup.sh
    bash scripts/build.sh "$B"
fi
for tool in mesh-prep cutplan augsolve curvature; do
    [ -x "$B/$tool" ] || { echo "demo: $B/$tool not built (bash scripts/build.sh $B)" >&2; exit 2; }
done
mkdir -p "$RUN"
now() { date +%s.%N; }
t0=$(now)
echo "== mesh-prep $EYE"
"$B/mesh-prep" --binary --chosen-only "$EYE" -o "$RUN/eye.msh"
t1=$(now)
echo "== cutplan $PLAN | augsolve --uncertainty"
"$B/cutplan" "$PLAN" "$RUN/eye.msh" -o - | "$B/augsolve" "$RUN/eye.msh" - -o "$RUN" --uncertainty --binary
t2=$(now)
echo "== curvature"
"$B/curvature" "$RUN"
t3=$(now)
echo "== timings"
awk -F'\t' 'NR == 1 { for (i = 1; i <= NF; i++) c[$i] = i; next }
    { printf "step %3d  %7s dofs  m %5s  refinement %s  update+solve %8.1f ms\n", $c["step"],
      $c["n_dofs"], $c["m"], $c["iters"], $c["t_total_ms"]; s += $c["t_total_ms"]; n++ }
    END { if (n) printf "steps: %d, %.1f ms in all, %.1f ms per step\n", n, s, s / n }' "$RUN/steps.tsv"
awk -v a="$t0" -v b="$t1" -v c="$t2" -v d="$t3" 'BEGIN {
    printf "wall clock: mesh-prep %.1f s, cutplan|augsolve %.1f s, curvature %.1f s, total %.1f s\n",
           b - a, c - b, d - c, d - a }'
echo "outputs in $RUN: report.html (open it in a browser), steps.pvd (ParaView), curvature.tsv, meridians.tsv, steps.tsv, uncertainty.tsv, derivatives.tsv, axial-NNNN.png, surface-NNNN.vtk"
