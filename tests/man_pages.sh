#!/usr/bin/env bash
# man_pages.sh BUILD_DIR: the manual's pages are well formed and point at things that exist.
# For every page of man/man1 and man/man5:
#  - man(1) renders it at 80 columns with --warnings=all and prints no warning;
#  - no section is a results log: no .SH BENCHMARK or HISTORY (measured results live in docs/);
#  - every repository path it names (plans/, docs/, tests/, scripts/, share/, lib/, cmd/,
#    meshes/; a * is a glob that must match) exists;
#  - every docs/ link with a quoted section, docs/X.md, "Title", names a heading of that file;
#  - every reference to another page's section, page(N), SECTION (rendered, in capitals), names
#    a section or subsection of that page.
# BUILD_DIR is not used (the pages are source files); it is taken for the pipeline label's call.
set -euo pipefail
cd "$(dirname "$0")/.."
command -v man > /dev/null || { echo "SKIP: man(1) is not installed"; exit 77; }
PY=/usr/bin/python3
[ -x "$PY" ] || { echo "SKIP: no $PY"; exit 77; }
tmp=$(mktemp -d /tmp/kt_manpages_XXXXXX)
trap 'rm -rf "$tmp"' EXIT
fails=0
for page in man/man1/*.1 man/man5/*.5; do
    name=$(basename "$page")
    MANWIDTH=80 man -l --warnings=all "$page" > /dev/null 2> "$tmp/warn" || true
    if [ -s "$tmp/warn" ]; then
        echo "FAIL $page: man --warnings=all: $(tr '\n' ' ' < "$tmp/warn")"; fails=$((fails + 1))
    else
        echo "ok   $page: no warning at 80 columns"
    fi
    if grep -qE '^\.SH .*(BENCHMARK|HISTORY)' "$page"; then
        echo "FAIL $page: a BENCHMARK or HISTORY section"; fails=$((fails + 1))
    fi
    LC_ALL=C MANWIDTH=10000 man -l "$page" 2> /dev/null > "$tmp/${name}.txt"
done
# paths, docs links and section references, from the rendered text (one paragraph a line)
"$PY" - "$tmp" man/man1/*.1 man/man5/*.5 <<'PYEOF' || fails=$((fails + 1))
import glob, os, re, sys
tmp, pages = sys.argv[1], sys.argv[2:]
bad = 0
def titles(page):
    t = []
    for line in open(page, encoding="utf-8"):
        m = re.match(r'\.(SH|SS)\s+(.*)', line)
        if m:
            t.append(re.sub(r'\\f[BIRP]|\\|"', '', m.group(2)).replace('-', '-').upper().strip())
    return t
index = {}
for p in pages:
    stem = os.path.basename(p)
    index[stem[:-2] + "(" + stem[-1] + ")"] = titles(p)
heads = {}
for d in glob.glob("docs/*.md"):
    heads[d] = [re.sub(r'^#+\s*', '', l).strip() for l in open(d, encoding="utf-8") if l.startswith('#')]
PATH = re.compile(r"(?<![\w/.-])((?:plans|docs|tests|scripts|share|lib|cmd|meshes)/[\w.*+/-]*[\w*])")
DOCLINK = re.compile(r'(docs/[\w-]+\.md),\s+"([^"]+)"')
XREF = re.compile(r"\b([a-z][a-z-]*\([15]\)),? ((?:[A-Z][A-Z']*)(?: [A-Z][A-Z']*)*)\b")
for p in pages:
    stem = os.path.basename(p)
    text = open(os.path.join(tmp, stem + ".txt"), encoding="latin-1").read()
    text = re.sub(r'[ \t]+', ' ', text)
    seen = set()
    for m in PATH.finditer(text):
        path = m.group(1).rstrip('.')
        if path in seen: continue
        seen.add(path)
        if not glob.glob(path):
            print(f"FAIL {p}: names {path}, which does not exist"); bad += 1
    for m in DOCLINK.finditer(text):
        doc, title = m.group(1), m.group(2)
        if doc in heads and not any(h.startswith(title) for h in heads[doc]):
            print(f"FAIL {p}: {doc} has no heading \"{title}\""); bad += 1
    for m in XREF.finditer(text):
        ref, sec = m.group(1), m.group(2)
        if ref not in index or len(sec) < 4: continue
        if not any(t.startswith(sec) for t in index[ref]):
            print(f"FAIL {p}: {ref}, {sec}: no such section in that page"); bad += 1
    print(f"ok   {p}: {len(seen)} paths checked" if bad == 0 else f"     {p}: {len(seen)} paths checked")
sys.exit(1 if bad else 0)
PYEOF
exit $((fails > 0))
