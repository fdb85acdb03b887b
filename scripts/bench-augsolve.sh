#!/usr/bin/env bash
# bench-augsolve.sh [BUILD_DIR] [--eye] [--steps N]: per-step time of augsolve's augmented
# method against a full refactorization and Jacobi-PCG on the same steps, as ratios.
#
# Model: the paper's 5 x 5 x 1024 beam (25,600 nodes; plans/bench/beam-1024.yaml) under the advancing
# planar cut of plans/bench/cut-beam-1024.yaml (5 nodes split per step, pulled apart at the free end);
# with --eye also the eye of plans/eye.yaml under plans/lri-paired-60.yaml.
# Each method is one augsolve run over the same edits (--no-vtk); the augmented and PCG runs
# also carry --verify, whose fresh factorization is not part of the timed columns.
# Columns: step, m (appended variables), refinement steps, largest closure (columns of L) of an
# appended column, nnz(L + W + S), ms per step of each method, refactor/augmented and
# pcg/augmented time ratios, and each method's max relative difference from a fresh factor.
# Timings are wall clock: on a shared machine read them as magnitudes (see uptime, printed).
set -euo pipefail
cd "$(dirname "$0")/.."
B=build
EYE=0
STEPS=0
while [ $# -gt 0 ]; do
    case $1 in
    --eye) EYE=1 ;;
    --steps) STEPS=$2; shift ;;
    *) B=$1 ;;
    esac
    shift
done
W=$(mktemp -d /tmp/bench-augsolve.XXXXXX)
trap 'rm -rf "$W"' EXIT
export OPENBLAS_NUM_THREADS=${OPENBLAS_NUM_THREADS:-1}
# The 1024 beam has cond(K) ~ 3e12 (paper, section 4.2): two direct solves already differ by
# ~1e-6. The augmented method runs at its default backward-error bound; PCG stops at a relative
# residual of 1e-4; the verify columns show what each answer is worth.
AUG_OPTS=${AUG_OPTS:-}
PCG_OPTS=${PCG_OPTS:---tol 1e-4 --maxit 100000}

limit() { # keep step 0..STEPS of an edits stream
    if [ "$STEPS" -gt 0 ]; then
        awk -v n="$STEPS" '/^step /{ s = $2 } s <= n' "$1"
    else
        cat "$1"
    fi
}

run_model() { # run_model NAME SCENE PLAN
    local name=$1 scene=$2 plan=$3
    echo "== $name: $(uptime | sed 's/.*load/load/')" >&2
    "$B/mesh-prep" "$scene" -o "$W/$name.msh" -q >"$W/$name.prep"
    "$B/cutplan" "$plan" "$W/$name.msh" -o "$W/$name.full.edits" -q
    limit "$W/$name.full.edits" >"$W/$name.edits"
    for m in augmented refactor pcg-jacobi; do
        local opts=""
        case $m in
        augmented) opts="$AUG_OPTS --verify --verify-tol 1" ;;
        pcg-jacobi) opts="$PCG_OPTS --verify --verify-tol 1" ;;
        esac
        echo "   $m $opts" >&2
        # shellcheck disable=SC2086
        "$B/augsolve" "$W/$name.msh" "$W/$name.edits" -o "$W/$name-$m" --method "$m" --no-vtk -q $opts
    done
    echo "# $name: $(grep -m1 '^dofs' "$W/$name.prep" | sed 's/  */ /g'); augmented: $AUG_OPTS; pcg: $PCG_OPTS"
    paste "$W/$name-augmented/steps.tsv" "$W/$name-refactor/steps.tsv" "$W/$name-pcg-jacobi/steps.tsv" |
        awk -F'\t' '
        # augmented columns 1..15, refactor 16..30, pcg 31..45 (steps.tsv order)
        NR == 1 { printf "%5s %6s %5s %8s %10s %10s %10s %10s %9s %9s %10s %10s\n", "step", "m",
                  "iters", "closure", "nnz(L)", "aug_ms", "refac_ms", "pcg_ms", "refac/aug",
                  "pcg/aug", "aug_diff", "pcg_diff"; next }
        { ra = $26 / $11; rp = $41 / $11
          printf "%5d %6d %5d %8d %10.3g %10.2f %10.1f %10.1f %9.1f %9.1f %10.2e %10.2e\n", $1, $3,
                 $5, $6, $14, $11, $26, $41, ra, rp, $13, $43
          if (NR > 2) { sa += $11; sr += $26; sp += $41; n++
                        if (ra < minr || n == 1) minr = ra; if (rp < minp || n == 1) minp = rp } }
        END { if (n) printf "# steps 1..%d: mean ms aug %.2f, refactor %.1f, pcg %.1f; ratio of means refactor/aug %.1f, pcg/aug %.1f; worst step refactor/aug %.1f, pcg/aug %.1f\n", n, sa / n, sr / n, sp / n, sr / sa, sp / sa, minr, minp }'
}

run_model beam-1024 plans/bench/beam-1024.yaml plans/bench/cut-beam-1024.yaml
if [ "$EYE" = 1 ]; then
    run_model eye plans/eye.yaml plans/lri-paired-60.yaml
fi
