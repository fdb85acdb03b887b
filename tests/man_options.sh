#!/usr/bin/env bash
# man_options.sh BUILD_DIR: for every tool, the options its --help lists and the options the
# OPTIONS section of its man page (man/man1/TOOL.1, as man(1) renders it) lists are the same
# set: an option added to a tool without its page, or a page documenting an option the tool no
# longer has, fails. Options are the -x / --name tokens of the option column: in --help the
# lines indented at most 8 blanks that start with '-', up to the first run of two blanks; in the
# page the tags of OPTIONS (the lines indented 7 columns that start with '-').
set -euo pipefail
B=$(cd "$1" && pwd)
cd "$(dirname "$0")/.."
command -v man > /dev/null || { echo "SKIP: man(1) is not installed"; exit 77; }
tmp=$(mktemp -d /tmp/kt_manopt_XXXXXX)
trap 'rm -rf "$tmp"' EXIT
tokens() { { grep -oE '(^|[ ,/])--?[A-Za-z][A-Za-z0-9-]*' || true; } | sed 's/^[ ,/]//' | sort -u; }
fails=0
for tool in mesh-prep cutplan augsolve curvature lri-plan lri-nomogram; do
    page=man/man1/$tool.1
    rc=0
    "$B/$tool" --help > "$tmp/help" 2> "$tmp/err" || rc=$?
    if [ $rc -ne 0 ] || [ ! -s "$tmp/help" ]; then
        echo "FAIL $tool --help: exit $rc, $(wc -l < "$tmp/help") lines"; fails=$((fails + 1)); continue
    fi
    awk 'match($0, /^ +-/) && RLENGTH <= 9 { sub(/^ +/, ""); split($0, a, /  +/); print a[1] }' "$tmp/help" |
        tokens > "$tmp/h"
    LC_ALL=C MANWIDTH=250 man -l "$page" 2> /dev/null |
        awk '/^[A-Z]/ { sec = $0 } sec == "OPTIONS" && /^       -/ { sub(/^ +/, ""); split($0, a, /  +/); print a[1] }' |
        tokens > "$tmp/p"
    if [ ! -s "$tmp/h" ] || [ ! -s "$tmp/p" ]; then
        echo "FAIL $tool: no options read ($(wc -l < "$tmp/h") from --help, $(wc -l < "$tmp/p") from $page)"
        fails=$((fails + 1)); continue
    fi
    only_help=$(comm -23 "$tmp/h" "$tmp/p" | tr '\n' ' ')
    only_page=$(comm -13 "$tmp/h" "$tmp/p" | tr '\n' ' ')
    if [ -z "$only_help" ] && [ -z "$only_page" ]; then
        echo "ok   $tool: $(wc -l < "$tmp/h") options in --help and in $page"
    else
        [ -z "$only_help" ] || echo "FAIL $tool: in --help, not in $page OPTIONS: $only_help"
        [ -z "$only_page" ] || echo "FAIL $tool: in $page OPTIONS, not in --help: $only_page"
        fails=$((fails + 1))
    fi
done
exit $((fails > 0))
