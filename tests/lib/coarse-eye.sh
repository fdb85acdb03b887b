#!/usr/bin/env bash
# coarse-eye.sh [--order N] [--floor UM] OZ INCISION CORNEA SCLERA OUT: writes to OUT a coarse
# version of the default eye, plans/eye.yaml, for the pipeline tests: the same scene (geometry,
# materials, loads, ordering) with larger element sizes (mesh.size's optical_zone, incision,
# cornea and sclera, in mm). The incision-floor refinement is dropped unless --floor keeps it
# at UM micrometres; --order sets the element order (default: the scene's). Each field keeps
# the rest of its line (its comment).
# Every change is checked: a field that is not found exactly once in plans/eye.yaml (its layout
# changed) is an error (exit 1, OUT not written), so no test runs on an eye it did not ask for.
# It lives in tests/lib/, outside the tests/*.sh glob, so CMake does not take it for a test.
set -euo pipefail
order= floor=
while [ $# -gt 0 ]; do
    case $1 in
    --order) order=$2; shift 2 ;;
    --floor) floor=$2; shift 2 ;;
    *) break ;;
    esac
done
if [ $# -ne 5 ]; then
    echo "usage: coarse-eye.sh [--order N] [--floor UM] OZ INCISION CORNEA SCLERA OUT" >&2
    exit 2
fi
src=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)/plans/eye.yaml
out=$5
# One field a line: the start of its line in plans/eye.yaml, '|', its new value (empty: the
# line is deleted).
spec="    optical_zone: |$1 mm
    incision: |$2 mm
    cornea: |$3 mm
    sclera: |$4 mm
    incision_floor: |${floor:+$floor um}"
[ -n "$order" ] && spec="$spec
order: |$order"
tmp=$out.part$$
trap 'rm -f "$tmp"' EXIT
awk -v spec="$spec" -v src="$src" '
BEGIN { n = split(spec, f, "\n")
        for (i = 1; i <= n; i++) { k = index(f[i], "|"); pat[i] = substr(f[i], 1, k - 1); val[i] = substr(f[i], k + 1) } }
{
    for (i = 1; i <= n; i++) {
        if (index($0, pat[i]) != 1) continue
        rest = substr($0, length(pat[i]) + 1)
        if (!match(rest, /^[0-9.]+( [a-z]+)?/)) continue
        seen[i]++
        if (val[i] != "") print pat[i] val[i] substr(rest, RLENGTH + 1)
        next
    }
    print
}
END { for (i = 1; i <= n; i++) if (seen[i] != 1) {
          printf "coarse-eye.sh: %s: expected one line \"%sVALUE\", found %d\n", src, pat[i], seen[i] > "/dev/stderr"
          bad = 1 }
      exit bad }' "$src" > "$tmp"
mv -f "$tmp" "$out"
trap - EXIT
