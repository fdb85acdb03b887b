#!/usr/bin/env bash
# plan-png.sh [BUILD_DIR] [OUT.png]: docs/plan.png, the README's picture of plan.html, from
# today's run: lri-plan --fast on plans/patients/asym-od.yaml, the top of its plan.html as
# headless Chromium renders it at 1280 x 1020, the answer (scripts/plan_answer.py) written into
# the PNG's tEXt chunk "Description" and printed: README.md's alt text for the picture must
# carry the same words (tests/readme_plan.sh checks both against a fresh run).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=$(cd "${1:-$root/build}" && pwd)
out=${2:-$root/docs/plan.png}
chrome=$(command -v chromium || true)
[ -n "$chrome" ] || { echo "plan-png.sh: chromium missing (bash scripts/setup.sh --test)" >&2; exit 1; }
tmp=$(mktemp -d /tmp/kt-plan-png.XXXXXX)
trap 'rm -rf "$tmp"' EXIT
cd "$root"
"$build/lri-plan" --fast -q plans/patients/asym-od.yaml -o "$tmp/plan" > "$tmp/summary"
timeout 120 "$chrome" --headless --no-sandbox --disable-gpu --hide-scrollbars --no-first-run \
    --disable-background-networking --disable-component-update --disable-sync \
    --host-resolver-rules="MAP * ~NOTFOUND" --user-data-dir="$tmp/profile" \
    --window-size=1280,1020 --screenshot="$tmp/page.png" "file://$tmp/plan/plan.html" > /dev/null 2>&1 || true
[ -s "$tmp/page.png" ] || { echo "plan-png.sh: Chromium wrote no screenshot" >&2; exit 1; }
/usr/bin/python3 - "$tmp/page.png" "$tmp/plan/plan.json" "$tmp/out.png" <<'PY'
import json, struct, sys, zlib
sys.path.insert(0, "scripts")
from plan_answer import answer
src, plan, dst = sys.argv[1:4]
text = answer(json.load(open(plan)))
data = open(src, "rb").read()
body = b"Description\0" + text.encode("latin-1")
chunk = struct.pack(">I4s", len(body), b"tEXt") + body + struct.pack(">I", zlib.crc32(b"tEXt" + body) & 0xffffffff)
end = data.rindex(b"IEND") - 4  # before the IEND chunk's length field
open(dst, "wb").write(data[:end] + chunk + data[end:])
print(text)
PY
mv -f "$tmp/out.png" "$out"
echo "plan-png.sh: wrote $out; README.md's alt text for it must carry the line above" >&2
