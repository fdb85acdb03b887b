#!/usr/bin/env bash
# lriplan_sheet.sh BUILD_DIR: the plan sheet and unequal paired arcs. lri-plan --fast on
# plans/patients/asym-od.yaml (a Pentacam export whose inferior half-meridian is the steeper).
# A second reader parses plan.json back and checks every number plan.html shows (each is in an
# element data-key="<json path>") against it, within the page's printed precision; checks the
# unequal family (the half-meridians found asymmetric, the inferior half steeper, every step's
# opposite arc in the ratio, its SIA curve recomputed from its readings in plan.json), the chosen
# family's SIA curve recomputed from curvature's reading of the chosen run's step files
# (PLAN_DIR/run, whose plan.yaml holds the chosen pair with arc_opposite = ratio x arc when the
# unequal pair is chosen), the answer the least residual of the families, and the link to the
# chosen run's report.html; then headless Chromium renders plan.html: no console message, no
# network request, a screenshot. Without Chromium that last part is skipped.
# The sheet a surgeon takes into theatre (lri-plan(1), plan.html), on that run and on a second:
# plans/patients/wtr-od.yaml (its main incision simulated) with an id, a date of birth and a
# surgeon added, --view superior, on the base eye with a healed wound at 3 months and
# SOURCE_DATE_EPOCH set: the patient block (the operative eye in large type, the plan's date),
# the wound's state in words, the main incision's SIA and the pre-operative astigmatism without
# and with it (recomputed by double-angle vectors from plan.json), both residuals with the
# target's kind in bold and the flip of axis said exactly when the residual lies > 45 deg from
# the pre-operative axis, the precision (0.01 D, 1 deg), the arcs' end points clockwise (the
# clock times advance by the arc) in the table and in the Mendez-ring marking, the view; and
# Chromium's own text boxes of the eye drawing's labels: no two meet.
set -uo pipefail
B=$(cd "$1" && pwd)
cd "$(dirname "$0")/.."
PY=/usr/bin/python3
tmp=$(mktemp -d /tmp/kt-lriplan-sheet.XXXXXX)
trap 'rm -rf "$tmp"' EXIT
out=$tmp/plan
if ! "$B/lri-plan" --fast -q plans/patients/asym-od.yaml -o "$out" > "$tmp/summary" 2> "$tmp/err"; then
    echo "FAILED: lri-plan: $(cat "$tmp/err")"; exit 1
fi
cat "$tmp/summary"
# The second run: a simulated main incision, the identification, --view superior, healed at 3 months.
out2=$tmp/plan2
sed 's/^name: wtr-od$/name: wtr-od\nid: H-0042\ndate_of_birth: 1956-02-29\nsurgeon: "Dr A. Example"/' \
    plans/patients/wtr-od.yaml > "$tmp/wtr-od.yaml"
{ cat plans/eye.yaml; printf '\nwound: {state: healed, months: 3 months}\n'; } > "$tmp/eye-healed.yaml"
if ! SOURCE_DATE_EPOCH=1700000000 "$B/lri-plan" --fast -q --view superior --base "$tmp/eye-healed.yaml" \
        "$tmp/wtr-od.yaml" -o "$out2" > "$tmp/summary2" 2> "$tmp/err"; then
    echo "FAILED: lri-plan (healed, superior): $(cat "$tmp/err")"; exit 1
fi
if "$B/lri-plan" --fast -q --view nasal "$tmp/wtr-od.yaml" -o "$tmp/never" > /dev/null 2> "$tmp/err"; then
    echo "FAILED: --view nasal accepted"; exit 1
elif ! grep -q "expected temporal, superior or examiner" "$tmp/err"; then echo "FAILED: --view nasal: $(cat "$tmp/err")"; exit 1
fi
"$B/curvature" -q --no-png --no-vtk --no-report "$out/run" -o "$out/rc" > /dev/null 2> "$tmp/err" ||
    { echo "FAILED: curvature on the chosen run: $(cat "$tmp/err")"; exit 1; }
CHROME=$(command -v chromium || true)
if [ -n "$CHROME" ]; then
    timeout 120 "$CHROME" --headless --no-sandbox --disable-gpu --disable-quic --hide-scrollbars --no-first-run \
        --disable-background-networking --disable-component-update --disable-sync \
        --host-resolver-rules="MAP * ~NOTFOUND" --user-data-dir="$(mktemp -d "$tmp/profile.XXXXXX")" \
        --enable-logging=stderr --v=0 --log-net-log="$tmp/netlog.json" \
        --window-size=1280,2600 --screenshot="$tmp/page.png" "file://$out/plan.html" 2> "$tmp/chrome.stderr" > /dev/null || true
    # Chromium's text boxes of the eye drawing's labels: a copy of each sheet with a script that
    # writes every label's getBBox() into the page, read back from --dump-dom (the copy without
    # the sheet's policy that forbids scripts).
    for o in "$out" "$out2"; do
        sed -e '/http-equiv="Content-Security-Policy"/d' -e 's|</body>|<script>const s=document.querySelector("svg[aria-label=\\"the plan on the eye\\"]");const r=[];for(const t of s.querySelectorAll("text")){const b=t.getBBox();r.push([t.textContent,b.x,b.y,b.width,b.height]);}const p=document.createElement("pre");p.id="bbox";p.textContent=JSON.stringify(r);document.body.appendChild(p);</script></body>|' \
            "$o/plan.html" > "$o/bbox.html"
        timeout 120 "$CHROME" --headless --no-sandbox --disable-gpu --disable-quic --no-first-run \
            --disable-background-networking --disable-component-update --disable-sync \
            --host-resolver-rules="MAP * ~NOTFOUND" --user-data-dir="$(mktemp -d "$tmp/profile.XXXXXX")" \
            --dump-dom "file://$o/bbox.html" > "$o/bbox.dom" 2> /dev/null || true
    done
fi
$PY - "$out" "$tmp" "$CHROME" "$out2" <<'PY'
import json, math, os, re, sys
from html.parser import HTMLParser
out, tmp, chrome, out2 = sys.argv[1:5]
fails = []
def check(cond, what):
    print(("ok   " if cond else "FAIL ") + what)
    if not cond: fails.append(what)
d = json.load(open(f"{out}/plan.json"))
html = open(f"{out}/plan.html").read()
def lookup(path):
    v = d
    for part in path.split("."):
        v = v[int(part)] if isinstance(v, list) else v[part]
    return v
# Every number of the page against plan.json.
spans = re.findall(r'<span data-key="([^"]+)">([^<]*)</span>', html)
bad = []
for key, text in spans:
    try:
        want = lookup(key)
    except (KeyError, IndexError, ValueError):
        bad.append(f"{key}: not in plan.json"); continue
    if isinstance(want, str):
        if text != want: bad.append(f"{key}: page '{text}', json '{want}'")
        continue
    dec = len(text.split(".")[1]) if "." in text else 0
    tol = 0.5 * 10 ** -dec + 1e-9
    # the page rounds the value plan.json rounds to its own precision: allow both roundings
    jdec = len(repr(float(want)).split(".")[1]) if "." in repr(float(want)) else 0
    tol += 0.5 * 10 ** -jdec
    diff = abs(float(text) - float(want))
    if key.endswith("axis_deg"): diff = min(diff, abs(diff - 180))  # 0 and 180 are one axis
    if key.startswith("plan.arcs.") and key.endswith("_deg"): diff = min(diff, abs(diff - 360))  # 360 is 0 on the gauge
    if not diff <= tol: bad.append(f"{key}: page {text}, json {want}")
check(len(spans) >= 40, f"plan.html holds {len(spans)} numbers tied to plan.json")
check(not bad, f"every one of them agrees with plan.json ({bad[:3]})")
keys = {k for k, _ in spans}
for k in ("plan.arcs.0.from_deg", "plan.arcs.0.to_clock", "plan.arcs.1.chord_mm", "plan.blade_um", "plan.post_op_keratometric_D",
          "plan.post_op_total_D", "pre_op.with_main_incision.total_D", "provenance.mesh_hash", "fit.anterior.rms_um", "halves.ratio"):
    check(k in keys, f"the page shows {k}")
check(html.count("<svg") >= 3, "the eye and the two curves are drawn (inline SVG)")
check("<script" not in html and "http://" not in html.replace("http://www.w3.org/2000/svg", ""), "no script, no external reference")
# Unequal pairs.
h = d["halves"]
check(h["astig_opposite_D"] > h["astig_at_axis_D"] and abs(h["steeper_half_deg"] - (d["patient"]["anterior"]["steep_axis_deg"] + 180)) < 0.1,
      f"the inferior half is the steeper ({h['astig_opposite_D']:.2f} against {h['astig_at_axis_D']:.2f} D)")
check(0.2 <= h["ratio"] < 0.9, f"asymmetric: ratio {h['ratio']:.3f}")
fams = {c["incisions"]: c for c in d["candidates"]}
check(set(fams) == {"paired", "unequal"}, f"families run: {sorted(fams)}")
u = fams.get("unequal")
def vec(m, a): return (m * math.cos(2 * math.radians(a)), m * math.sin(2 * math.radians(a)))
def sia_worst(curve, readings):
    v0 = vec(*readings[0])
    return max(abs(math.hypot(vec(*r)[0] - v0[0], vec(*r)[1] - v0[1]) - q["sia_D"]) for q, r in zip(curve, readings))
if u:
    check(abs(u["ratio"] - h["ratio"]) < 1e-4 and abs(u["meridian_deg"] - h["steeper_half_deg"]) < 0.1, "the unequal family's ratio and centre")
    check(all(abs(p["arc_opposite_deg"] - u["ratio"] * p["arc_deg"]) < 0.01 for p in u["curve"]), "every step's opposite arc in the ratio")
    w = sia_worst(u["curve"], [(q["keratometric_D"], q["keratometric_axis_deg"]) for q in u["curve"]])
    check(w < 2e-4, f"the unequal SIA curve recomputed from its readings (worst {w:.1e} D)")
    check(u["curve"][-1]["sia_D"] > u["curve"][1]["sia_D"] > 0, "the SIA grows with the arc")
p = d["plan"]
c = fams[p["incisions"]]
rows = [l.rstrip("\n").split("\t") for l in open(f"{out}/rc/curvature.tsv")]
hd = rows[0]
w = sia_worst(c["curve"], [(float(r[hd.index("cyl_D")]), float(r[hd.index("axis_steep_deg")])) for r in rows[1:]])
check(len(rows) - 1 == p["run_step"] + 1 and w < 2e-4,
      f"the chosen ({p['incisions']}) SIA curve recomputed from curvature's reading of run/ (worst {w:.1e} D)")
plan = open(f"{out}/run/plan.yaml").read()
arc = float(re.search(r"\n    arc: ([0-9.eE+-]+) deg", plan).group(1))
check(abs(arc - p["arc_deg"]) < 1e-9, f"run/plan.yaml cuts the chosen arc, {arc:g} deg")
if p["incisions"] == "unequal":
    opp = float(re.search(r"arc_opposite: ([0-9.eE+-]+) deg", plan).group(1))
    check(abs(opp - u["ratio"] * arc) < 0.01, f"run/plan.yaml: arc_opposite {opp:.3f} = ratio x arc {arc:g}")
best = min(c["best_residual_D"] for c in d["candidates"])
check(p["predicted_residual_D"] <= best + 0.01 + 1e-9, f"the answer ({p['incisions']}) is the least residual of the families")
if p["incisions"] == "unequal":
    check(len(p["arcs"]) == 2 and abs(p["arcs"][1]["arc_deg"] - u["ratio"] * p["arcs"][0]["arc_deg"]) < 0.11, "the chosen pair's two arcs")
rep = d["provenance"]["report"]
check(rep != "" and os.path.getsize(f"{out}/{rep}") > 10000 and f'href="{rep}"' in html, f"plan.html links the chosen run's report ({rep})")
# Chromium.
if not chrome:
    print("SKIP the Chromium render: chromium missing (bash scripts/setup.sh --test)")
else:
    err = open(f"{tmp}/chrome.stderr", errors="replace").read()
    console = [l for l in err.splitlines() if ":CONSOLE" in l]
    check(os.path.exists(f"{tmp}/page.png") and os.path.getsize(f"{tmp}/page.png") > 10000, "Chromium rendered plan.html")
    check(not console, f"no console message ({console[:1]})")
    try:
        nl = json.load(open(f"{tmp}/netlog.json"))
        et = {v: k for k, v in nl["constants"]["logEventTypes"].items()}
        reqs = sorted({e["params"].get("url", "") for e in nl["events"] if et.get(e["type"]) == "URL_REQUEST_START_JOB"
                       and not e["params"].get("url", "").startswith(("file:", "data:"))
                       and "file://" in e["params"].get("network_isolation_key", "")})
        check(not reqs, f"no request leaves the page ({reqs[:2]})")
    except (OSError, ValueError) as ex:
        check(False, f"the net log: {ex}")
# ---- The sheet for theatre, on both runs.
class Page(HTMLParser):
    """The page's text by element: every data-key's text, the opeye block, <b> texts, pre#bbox."""
    def __init__(self):
        super().__init__(); self.stack = []; self.keys = {}; self.bold = []; self.opeye = ""; self.bbox = ""; self.text = []
        self.cls = []
    def handle_starttag(self, tag, attrs):
        a = dict(attrs); self.stack.append((tag, a))
    def handle_endtag(self, tag):
        while self.stack and self.stack.pop()[0] != tag: pass
    def handle_data(self, data):
        self.text.append(data)
        for tag, a in self.stack:
            if "data-key" in a: self.keys[a["data-key"]] = self.keys.get(a["data-key"], "") + data
            if tag == "b": self.bold.append(data)
            if a.get("class") == "opeye": self.opeye += data
            if a.get("id") == "bbox": self.bbox += data
def parse(path):
    pg = Page(); pg.feed(open(path, encoding="utf-8").read()); pg.all = " ".join("".join(pg.text).split()); return pg
def dvec(m, a): return (m * math.cos(2 * math.radians(a)), m * math.sin(2 * math.radians(a)))
def dsum(*vs): return (sum(v[0] for v in vs), sum(v[1] for v in vs))
def close(u, v, tol): return math.hypot(u[0] - v[0], u[1] - v[1]) <= tol
def minutes(c): h, m = map(int, c.split(":")); return (h % 12) * 60 + m
def gap(a, b): d = abs(a - b) % 180; return min(d, 180 - d)
def klass(a):
    a %= 180
    return "with-the-rule" if 60 <= a <= 120 else "against-the-rule" if a <= 30 or a >= 150 else "oblique"
def sheet(o, want):
    tag = want["tag"]
    d = json.load(open(f"{o}/plan.json")); pg = parse(f"{o}/plan.html"); t = pg.all
    p = d["patient"]
    check(pg.opeye.strip().startswith(p["eye"]) and ("RIGHT" if p["eye"] == "OD" else "LEFT") in pg.opeye,
          f"{tag}: the operative eye in large type ({pg.opeye.strip()!r})")
    for k in ("id", "date_of_birth", "surgeon"):
        if want.get(k): check(pg.keys.get(f"patient.{k}") == want[k] == p[k], f"{tag}: the patient block shows {k} {want[k]}")
        else: check(f"patient.{k}" not in pg.keys, f"{tag}: no {k} line when the file has none")
    check(pg.keys.get("provenance.date") in want["date"], f"{tag}: the plan's date {pg.keys.get('provenance.date')} (want {want['date']})")
    check(want["wound"] in t, f"{tag}: the wound's state: {want['wound']!r}")
    # the main incision's SIA and the pre-op without and with it, recomputed by double angles
    m, po = d["main_incision"], d["pre_op"]
    sia = dvec(m["sia_keratometric_D"], m["sia_keratometric_axis_deg"])
    bare = dvec(po["without_main_incision"]["keratometric_D"], po["without_main_incision"]["keratometric_axis_deg"])
    withm = dvec(po["with_main_incision"]["keratometric_D"], po["with_main_incision"]["keratometric_axis_deg"])
    # plan.json's axes to 0.1 deg: at 2 D a 0.05 deg rounding moves a double-angle vector 0.0036 D
    check(close(dsum(bare, sia), withm, 0.01), f"{tag}: pre-op with = without + the main incision's SIA (keratometric)")
    if want["simulated"]:
        sim = dvec(m["simulated_sia_keratometric_D"], m["simulated_sia_keratometric_axis_deg"])
        check(m["sia"].startswith("simulated") and close(sim, sia, 0.003) and m["sia_keratometric_D"] > 0.05,
              f"{tag}: the SIA shown is the simulated tunnel's ({m['sia_keratometric_D']:.2f} D @ {m['sia_keratometric_axis_deg']:.0f})")
    else:
        check(close(sia, dvec(m["sia_added_D"], m["sia_axis_deg"]), 0.003), f"{tag}: the SIA shown is the surgeon's vector")
    for k in ("main_incision.sia_keratometric_D", "main_incision.sia_total_D", "pre_op.without_main_incision.keratometric_D",
              "pre_op.with_main_incision.total_D", "plan.post_op_keratometric_D", "plan.post_op_total_D"):
        check(re.fullmatch(r"\d+\.\d\d", pg.keys.get(k, "")) is not None, f"{tag}: {k} shown to 0.01 D ({pg.keys.get(k)})")
    for k in ("main_incision.sia_keratometric_axis_deg", "pre_op.with_main_incision.total_axis_deg", "plan.post_op_total_axis_deg",
              "plan.arcs.0.from_deg", "plan.arcs.0.arc_deg"):
        check(re.fullmatch(r"\d+", pg.keys.get(k, "")) is not None, f"{tag}: {k} shown to 1 deg ({pg.keys.get(k)})")
    # the target's kind in bold, the flip said exactly when the residual turns > 45 deg
    kind = "total corneal" if d["target"]["astigmatism"] == "total_corneal" else "keratometric"
    check(any(kind in b for b in pg.bold), f"{tag}: the target's kind ({kind}) in bold")
    pl = d["plan"]
    for name, res, pre in (("keratometric", "post_op_keratometric", "keratometric"), ("total corneal", "post_op_total", "total")):
        ra, pa = pl[res + "_axis_deg"], po["without_main_incision"][pre + "_axis_deg"]
        said = re.search(rf"over-corrects[^.]*: the {name} residual turns to (the other )?{klass(ra)}", t) is not None
        check(said == (gap(ra, pa) > 45 and pl[res + "_D"] >= 0.005),
              f"{tag}: the {name} residual at {ra:.0f} against {pa:.0f} pre-op: flip {'said' if said else 'not said'}")
    # the arcs clockwise, in the table and in the marking
    for i, q in enumerate(pl["arcs"]):
        dm = (minutes(q["to_clock"]) - minutes(q["from_clock"])) % 720
        check(abs(dm - 2 * q["arc_deg"]) <= 2 and abs((q["from_deg"] - q["arc_deg"] - q["to_deg"] + 180) % 360 - 180) < 0.1,
              f"{tag}: arc {i + 1} marked clockwise, {q['from_clock']} then {q['to_clock']} ({q['arc_deg']:g} deg)")
        mk = re.search(rf"Arc {i + 1}, (\d+)° long: its centre at (\d+)°; mark first (\d+)° \(([\d:]+)\), then (\d+)° \(([\d:]+)\), clockwise", t)
        deg = lambda g, v: abs((int(mk.group(g)) - v + 180) % 360 - 180) <= 0.55  # printed to 1 deg, json to 0.1
        check(mk is not None and deg(3, q["from_deg"]) and deg(5, q["to_deg"]) and deg(2, q["centre_deg"])
              and mk.group(4) == q["from_clock"] and mk.group(6) == q["to_clock"],
              f"{tag}: the Mendez-ring marking of arc {i + 1}: {mk.group(0) if mk else 'missing'}")
    # the view
    check(d["provenance"]["view"] == want["view"] and f"view: {want['view']}" in t and f"--view {want['view']}" in t,
          f"{tag}: the view ({want['view']}) on the sheet and in plan.json")
    # the labels of the eye: Chromium's boxes
    if chrome:
        try:
            dom = parse(f"{o}/bbox.dom"); boxes = json.loads(dom.bbox)
        except (OSError, ValueError) as ex:
            check(False, f"{tag}: Chromium's label boxes: {ex}"); return
        meet = [(a[0], b[0]) for i, a in enumerate(boxes) for b in boxes[i + 1:]
                if a[1] < b[1] + b[3] - 0.5 and b[1] < a[1] + a[3] - 0.5 and a[2] < b[2] + b[4] - 0.5 and b[2] < a[2] + a[4] - 0.5]
        out_ = [a[0] for a in boxes if a[1] < 0 or a[2] < 0 or a[1] + a[3] > 520 or a[2] + a[4] > 520]
        ends = [a[0] for a in boxes if " from " in " " + a[0] or " to " in " " + a[0]]
        check(len(boxes) >= 30 and len(ends) == 2 * len(pl["arcs"]), f"{tag}: Chromium laid out {len(boxes)} labels of the eye, {len(ends)} end points")
        check(not meet and not out_, f"{tag}: no two labels of the eye meet, none outside ({meet[:2]}, {out_[:2]})")
import datetime
now = datetime.datetime.now(datetime.timezone.utc)
today = [(now - datetime.timedelta(days=k)).strftime("%Y-%m-%d") for k in (0, 1)]  # a run across midnight
sheet(out, {"tag": "asym-od", "date": today,
            "wound": "Predicted for the fully healed wound (healed wound, its asymptotic scar; identified on published outcomes, "
                     "validated: see docs/validation.md).",
            "simulated": False, "view": "temporal"})
sheet(out2, {"tag": "wtr-od healed", "id": "H-0042", "date_of_birth": "1956-02-29", "surgeon": "Dr A. Example",
             "date": ["2023-11-14"], "simulated": True, "view": "superior",
             "wound": "Predicted at 3 months after surgery (healed wound; identified on published outcomes, validated: see docs/validation.md)"})
print(f"lriplan_sheet: {0 if fails else 1} passed, {len(fails)} failed")
sys.exit(1 if fails else 0)
PY
