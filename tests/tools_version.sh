#!/usr/bin/env bash
# tools_version.sh BUILD_DIR: every tool answers --version with one line on stdout naming the
# CMake project version (read here from CMakeLists.txt), exit 0; an unknown option is one line
# on stderr, nothing on stdout, exit 2.
set -euo pipefail
B=$(cd "$1" && pwd)
cd "$(dirname "$0")/.."
want=$(sed -n 's/^project(keratome VERSION \([0-9.]*\).*/\1/p' CMakeLists.txt)
[ -n "$want" ] || { echo "FAIL: no project version in CMakeLists.txt"; exit 1; }
tmp=$(mktemp -d /tmp/kt_version_XXXXXX)
trap 'rm -rf "$tmp"' EXIT
fails=0
for tool in mesh-prep cutplan augsolve curvature lri-plan; do
    rc=0
    "$B/$tool" --version > "$tmp/out" 2> "$tmp/err" || rc=$?
    if [ $rc -eq 0 ] && [ "$(cat "$tmp/out")" = "$tool (keratome) $want" ] && [ ! -s "$tmp/err" ]; then
        echo "ok   $tool --version: $(cat "$tmp/out")"
    else
        echo "FAIL $tool --version: exit $rc, stdout '$(cat "$tmp/out")', stderr '$(cat "$tmp/err")'"
        fails=$((fails + 1))
    fi
    rc=0
    "$B/$tool" --no-such-option > "$tmp/out" 2> "$tmp/err" || rc=$?
    if [ $rc -eq 2 ] && [ ! -s "$tmp/out" ] && [ "$(wc -l < "$tmp/err")" -eq 1 ] && grep -q -- "--no-such-option" "$tmp/err"; then
        echo "ok   $tool --no-such-option: $(cat "$tmp/err")"
    else
        echo "FAIL $tool --no-such-option: exit $rc, $(wc -l < "$tmp/err") stderr lines, stdout $(wc -c < "$tmp/out") bytes"
        fails=$((fails + 1))
    fi
done
rc=0
"$B/curvature" > "$tmp/out" 2> "$tmp/err" || rc=$?
if [ $rc -eq 2 ] && [ ! -s "$tmp/out" ] && [ "$(wc -l < "$tmp/err")" -eq 1 ]; then
    echo "ok   curvature without RUN_DIR: $(cat "$tmp/err")"
else
    echo "FAIL curvature without RUN_DIR: exit $rc, $(wc -l < "$tmp/err") stderr lines"; fails=$((fails + 1))
fi
exit $((fails > 0))
