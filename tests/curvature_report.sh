#!/usr/bin/env bash
# curvature_report.sh BUILD_DIR: what curvature writes for people and scripts, read back by
# second readers: --json (python json) against curvature.tsv; steps.pvd (python xml) naming
# every step VTK in order, each read by meshio; report.html self-contained (CSP, no script, no
# URL, every image a PNG data URI) and its pre-operative map holding the colours of the TSV's K
# along the principal meridians; then the page rendered by headless Chromium: no console
# message, no request leaving the page (net log), and the screenshot showing those colours.
# The Chromium checks are shown to fail on copies of the page with an external image.
# Chromium and PIL come from `scripts/setup.sh --test`; without them the test is skipped (77).
set -euo pipefail
B=$(cd "$1" && pwd)
cd "$(dirname "$0")/.."
PY=/usr/bin/python3
CHROME=$(command -v chromium || true)
if [ -z "$CHROME" ] || ! $PY -c 'import PIL, meshio' 2>/dev/null; then
    echo "SKIP: chromium or python3-pil/meshio missing (bash scripts/setup.sh --test)"
    exit 77
fi
tmp=$(mktemp -d /tmp/kt_report_XXXXXX)
trap 'rm -rf "$tmp"' EXIT
run=$tmp/run
"$B/test_curv" --make-run "$run"
"$B/curvature" -q --json --plan plans/lri-paired-60.yaml "$run" > "$tmp/summary.json"
for f in report.html steps.pvd curvature.tsv; do [ -s "$run/$f" ] || { echo "FAIL: no $f"; exit 1; }; done

# Headless Chromium: a screenshot, the console on stderr, every network request in a net log.
render() { # render PAGE TAG
    rm -rf "$tmp/profile"
    timeout 120 "$CHROME" --headless --no-sandbox --disable-gpu --hide-scrollbars --no-first-run \
        --disable-background-networking --disable-component-update --disable-sync \
        --host-resolver-rules="MAP * ~NOTFOUND" --user-data-dir="$tmp/profile" \
        --enable-logging=stderr --v=0 --log-net-log="$tmp/$2.netlog.json" \
        --window-size=1280,2400 --screenshot="$tmp/$2.png" "file://$1" 2> "$tmp/$2.stderr" > /dev/null || true
}
render "$run/report.html" page
# Controls: the page with an external image trips the net-log check without its CSP, and the
# console check with it (the CSP refuses the image with a console message).
sed -e 's|<main>|<main><img src="http://example.invalid/x.png" alt="x">|' \
    -e '/Content-Security-Policy/d' "$run/report.html" > "$tmp/bad.html"
render "$tmp/bad.html" bad
sed -e 's|<main>|<main><img src="http://example.invalid/x.png" alt="x">|' "$run/report.html" > "$tmp/blocked.html"
render "$tmp/blocked.html" blocked

$PY - "$run" "$tmp" share/colour/axial.tsv <<'PYEOF'
import base64, csv, io, json, math, os, re, sys
import xml.etree.ElementTree as ET
import meshio
from PIL import Image

run, tmp, scale_path = sys.argv[1:4]
fails = []
def check(cond, what):
    print(('ok   ' if cond else 'FAIL ') + what)
    if not cond: fails.append(what)

# --json against the TSV
with open(run + '/curvature.tsv') as f: rows = list(csv.DictReader(f, delimiter='\t'))
js = json.load(open(tmp + '/summary.json'))
check(len(js['steps']) == len(rows) == 4, 'JSON and TSV: 4 steps each')
for r, s in zip(rows, js['steps']):
    for tk, jk in [('k_steep_D', 'k_steep_D'), ('k_flat_D', 'k_flat_D'), ('cyl_D', 'cyl_D'), ('sia_D', 'sia_D'),
                   ('flattening_D', 'flattening_D'), ('total_cyl_D', 'total_cyl_D')]:
        t, j = float(r[tk]), s[jk]
        ok = (math.isnan(t) and j is None) or (j is not None and abs(t - j) <= 1e-4 * max(1, abs(t)))
        if not ok: check(False, 'step %s %s: TSV %s, JSON %s' % (r['step'], tk, r[tk], j))
check(js['incised_deg'] == 90 and abs(js['target']['tia_D'] - 1.5) < 1e-9, 'JSON: plan meridian 90, TIA 1.5 D')
check(js['keratome'] and re.match(r'^\d+\.\d+\.\d+$', js['keratome']), 'JSON: version %s' % js['keratome'])

# steps.pvd: a ParaView collection, every step in order, each readable
root = ET.parse(run + '/steps.pvd').getroot()
ds = root.findall('./Collection/DataSet')
check(root.tag == 'VTKFile' and root.get('type') == 'Collection', 'steps.pvd is a VTK Collection')
check([d.get('file') for d in ds] == ['step-%04d.vtk' % i for i in range(4)], 'steps.pvd names step-0000..0003.vtk')
times = [float(d.get('timestep')) for d in ds]
check(all(b > a for a, b in zip(times, times[1:])), 'steps.pvd timesteps increase: %s' % times)
for d in ds:
    m = meshio.read(os.path.join(run, d.get('file')))
    check('displacement' in m.point_data and len(m.points) > 0, 'meshio reads %s (%d points)' % (d.get('file'), len(m.points)))

# report.html: self-contained
html = open(run + '/report.html').read()
check('<script' not in html.lower(), 'no script')
check("default-src 'none'" in html, 'CSP forbids every fetch')
urls = [u for u in re.findall(r'''(?:src|href)\s*=\s*["']([^"']*)''', html) if not u.startswith('data:')]
urls += re.findall(r'url\(', html)
check(not urls, 'no URL besides data: (%s)' % urls[:3])
imgs = re.findall(r'src="data:image/png;base64,([A-Za-z0-9+/=]+)"', html)
# pre-op and final (absolute), the same on the relative scale, tangential, difference, and
# the strip of the 4 steps' maps
check(len(imgs) == 10 and len(re.findall(r'<img', html)) == 10, '10 maps, all PNG data URIs (%d)' % len(imgs))
pngs = [Image.open(io.BytesIO(base64.b64decode(b, validate=True))).convert('RGB') for b in imgs]
check(all(p.size == (720, 580) for p in pngs), 'maps are 720 x 580 (kt_topo_layout_of)')

# The pre-op map's colours: along the principal meridians of the synthetic torus the axial power
# is the TSV's K (the sections are circles), so the map shows the colour of K's bin there.
bins = []
for line in open(scale_path):
    p = line.split()
    if len(p) == 5 and not line.startswith('#') and p[0] != 'lo_D':
        bins.append((float(p[0]), float(p[1]), tuple(int(v) for v in p[2:])))
def colour(k):
    for lo, hi, rgb in bins:
        if k < hi: return rgb
    return bins[-1][2]
ks, kf = float(rows[0]['k_steep_D']), float(rows[0]['k_flat_D'])
# kt_topo_layout_of: disk centre (290, 320), radius 220 px; legend x 590, width 34, bin height
# min(24, 440 / n), legend top = 320 - n * bin / 2. Checked here on the image itself:
n = len(bins); bh = min(24, 440 // n); legtop = 320 - (bh * n) // 2
pre = pngs[0]
check(pre.getpixel((607, legtop + bh // 2)) == bins[-1][2], 'legend top swatch where the layout puts it')
probe = {'steep (90 deg)': ((290, 320 - 50), colour(ks)), 'flat (0 deg)': ((290 + 50, 320), colour(kf))}
for name, (xy, rgb) in probe.items():
    check(pre.getpixel(xy) == rgb, 'pre-op map, %s meridian: %s = colour of K %s' % (name, pre.getpixel(xy), rgb))

# Chromium: console and network
def browser(tag):
    err = open('%s/%s.stderr' % (tmp, tag), errors='replace').read()
    console = [l for l in err.splitlines() if ':CONSOLE' in l]
    nl = json.load(open('%s/%s.netlog.json' % (tmp, tag)))
    et = {v: k for k, v in nl['constants']['logEventTypes'].items()}
    out = sorted({e['params']['url'] for e in nl['events'] if et.get(e['type']) == 'URL_REQUEST_START_JOB'
                  and 'file://' in e['params'].get('network_isolation_key', '')
                  and not e['params']['url'].startswith(('file:', 'data:'))})
    return console, out
console, out = browser('page')
check(os.path.getsize(tmp + '/page.png') > 10000, 'Chromium rendered a screenshot')
check(not console, 'no console message (%s)' % console[:1])
check(not out, 'no request leaves the page (%s)' % out[:2])
bc, bo = browser('bad')
check(bool(bo), 'control: the external image of the copy shows in the net log (%s)' % bo[:1])
bc, bo = browser('blocked')
check(bool(bc) and not bo, 'control: with the CSP the image is refused, with a console message (%s)' % bc[:1])

# The screenshot: find the pre-op legend's top swatch (its colour is only in legends; the first
# from the top is the pre-op map's), scale the layout, and read the probe pixels on screen.
shot = Image.open(tmp + '/page.png').convert('RGB')
W, H = shot.size
top = bins[-1][2]
px = shot.load()
hit = None
for y in range(H):
    xs = [x for x in range(0, W // 2) if px[x, y] == top]
    if len(xs) > 4: hit = (y, xs); break
check(hit is not None, 'pre-op legend found in the screenshot')
if hit:
    y0, xs = hit
    x0, x1 = xs[0], xs[-1]
    s = (x1 - x0 + 1) / 34.0
    ox, oy = x0 - 590 * s, y0 - legtop * s
    for name, ((ix, iy), rgb) in probe.items():
        got = px[int(round(ox + ix * s)), int(round(oy + iy * s))]
        check(max(abs(a - b) for a, b in zip(got, rgb)) <= 6,
              'screenshot, pre-op map, %s meridian: %s ~ %s (scale %.3f)' % (name, got, rgb, s))
sys.exit(1 if fails else 0)
PYEOF
echo "curvature_report: all checks passed"
