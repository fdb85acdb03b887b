#!/usr/bin/env bash
# report_readers.sh BUILD_DIR: what issue 25 found misread, checked by second readers (python's
# HTML parser, yaml, csv, json) on the synthetic run of `test_curv --make-run` (an exact torus
# whose cylinder falls 1.69 -> 0.33 D @ 90 in 3 steps, cut at 5 deg of arc a step by the demo
# plan) and on a real augsolve run of the paper's beam:
#  - report.html: the headline says on target / under / over-correction (a target of 0.5 D makes
#    the same run an over-correction); the step plot's legend names both meridians and their
#    angles; the difference legend labels 0 and symmetric values; the eye drawing has S I N T
#    and OD (OS with --eye OS), a 5 mm bar and no mesh details; a relative-scale row and a
#    strip with every step's map; run.yaml's provenance shown with the run's mesh hash;
#  - the text summary's arc column; --step N and --arc DEG report that step under its own number
#    and arc; --mesh with step-0000.vtk step-0003.vtk labels step 3 (it said "step 1, arc 5");
#    a bad --arc is exit 2 with no output;
#  - run.yaml of a real run: the edits' mesh hash, named once (at the top level, not again in
#    the provenance block); the scene's FNV-1a and text, its materials, the tool versions,
#    steps.tsv's largest factor and residual;
#  - curvature --compare: the two runs' last rows of curvature.tsv in its table.
set -euo pipefail
B=$(cd "$1" && pwd)
cd "$(dirname "$0")/.."
PY=/usr/bin/python3
$PY -c 'import yaml' 2>/dev/null || { echo "SKIP: python3-yaml missing"; exit 77; }
tmp=$(mktemp -d /tmp/kt_readers_XXXXXX)
trap 'rm -rf "$tmp"' EXIT
run=$tmp/run
P=plans/lri-paired-60.yaml
"$B/test_curv" --make-run "$run" > /dev/null
"$B/curvature" -q --plan $P "$run" > "$tmp/all.txt"
"$B/curvature" -q --plan $P --step 2 -o "$tmp/s2" "$run" > "$tmp/s2.txt"
"$B/curvature" -q --plan $P --json --arc 15 -o "$tmp/a15" "$run" > "$tmp/a15.json"
"$B/curvature" -q --plan $P --no-png --json -o "$tmp/m" --mesh "$run/eye.msh" "$run/step-0000.vtk" "$run/step-0003.vtk" > "$tmp/m.json"
"$B/curvature" -q --plan $P --no-png --no-vtk -o "$tmp/m" --mesh "$run/eye.msh" "$run/step-0000.vtk" "$run/step-0003.vtk" > "$tmp/m.txt"
rc=0; "$B/curvature" -q --plan $P --arc 7 -o "$tmp/a7" "$run" > /dev/null 2> "$tmp/a7.err" || rc=$?
[ $rc = 2 ] && [ ! -e "$tmp/a7" ] && grep -q "^curvature: --arc 7: expected the arc of a step, 0 to 15 deg in steps of 5" "$tmp/a7.err" \
    || { echo "FAIL: --arc 7: exit $rc, $(cat "$tmp/a7.err")"; exit 1; }
sed -e 's/magnitude: 1.5 D/magnitude: 0.5 D/' -e "s|^scene: *\([^ ]*\)|scene: $PWD/plans/\1|" $P > "$tmp/over.yaml"
grep -q "magnitude: 0.5 D" "$tmp/over.yaml"
"$B/curvature" -q --plan "$tmp/over.yaml" --eye OS --no-png --no-vtk -o "$tmp/over" "$run" > "$tmp/over.txt"
"$B/curvature" --compare "$run" "$tmp/s2" -o "$tmp/cmp"

# A real run: the paper's beam, cut and solved by the planned method.
"$B/mesh-prep" -q plans/bench/beam-64.yaml -o "$tmp/beam.msh" > /dev/null
"$B/cutplan" -q plans/bench/cut-beam-64.yaml "$tmp/beam.msh" -o "$tmp/beam.edits"
"$B/augsolve" -q "$tmp/beam.msh" "$tmp/beam.edits" -o "$tmp/beam"
# The synthetic run with a provenance block (the beam's: tools, scene, materials, solver figures).
sed -n '/^provenance:/,$p' "$tmp/beam/run.yaml" >> "$run/run.yaml"
"$B/curvature" -q --plan $P --no-png --no-vtk -o "$tmp/prov" "$run" > /dev/null

$PY - "$tmp" "$run" "$B" <<'PYEOF'
import csv, json, re, subprocess, sys
from html.parser import HTMLParser
import yaml

tmp, run, B = sys.argv[1:4]
fails = []
def check(cond, what):
    print(('ok   ' if cond else 'FAIL ') + what)
    if not cond: fails.append(what)

class Page(HTMLParser):
    """Text by element id, every <text> of the SVGs, the <img> alts by enclosing id."""
    def __init__(self, path):
        super().__init__()
        self.ids, self.stack, self.svgtext, self.imgs, self.rows = {}, [], [], [], {}
        self.cur_text = None
        self.feed(open(path, encoding='utf-8').read())
    def handle_starttag(self, tag, a):
        a = dict(a)
        if tag in ('img', 'br', 'meta', 'polyline', 'line', 'circle', 'path', 'polygon', 'rect'):
            if tag == 'img': self.imgs.append((a.get('alt', ''), [i for _, i in self.stack if i]))
            return
        self.stack.append((tag, a.get('id')))
        if tag == 'text': self.cur_text = ''
    def handle_endtag(self, tag):
        while self.stack:
            t, _ = self.stack.pop()
            if t == tag: break
        if tag == 'text' and self.cur_text is not None:
            self.svgtext.append(self.cur_text.strip()); self.cur_text = None
    def handle_data(self, d):
        if self.cur_text is not None: self.cur_text += d
        for _, i in self.stack:
            if i: self.ids[i] = self.ids.get(i, '') + d

# --- the report of the whole run
p = Page(run + '/report.html')
check(p.ids.get('verdict', '').startswith('On target'), 'headline: %s' % p.ids.get('verdict', '')[:60])
check('flattening of the incised meridian (90\u00b0)' in p.svgtext and 'steepening of the orthogonal one (0\u00b0)' in p.svgtext,
      'step plot legend names both meridians')
check(not any(t.startswith('steepening at') for t in p.svgtext), 'no "steepening at 90" legend')
lab = p.ids.get('diff-legend', '').split()
check('0' in lab and all(('-' + v[1:]) in lab for v in lab if v.startswith('+')) and len(lab) % 2 == 1,
      'difference legend: 0 and symmetric values (%s)' % ' '.join(lab))
check(all(re.fullmatch(r'[+-]?\d+(\.\d)?', v) for v in lab), 'difference legend values are round (one decimal)')
for t in ('S', 'I', 'N', 'T', 'OD', '5 mm'):
    check(t in p.svgtext, 'eye drawing shows %r' % t)
check(p.svgtext.index('N') > 0 and not any('refined mesh' in t for t in p.svgtext), 'no mesh details on the drawing')
strip = [a for a, ids in p.imgs if 'strip' in ids]
check(strip == ['axial power map, step %d' % i for i in range(4)], 'strip: every step\'s map (%d)' % len(strip))
rel = [a for a, ids in p.imgs if 'relative' in ids]
check(len(rel) == 2, 'relative-scale row: 2 maps')
check('<script' not in open(run + '/report.html').read().lower(), 'no script')

# --- the text summary's arc column, --step, --arc, --mesh labels
def table(path):
    rows = [l.split() for l in open(path) if re.match(r'^\s+\d+\s', l)]
    return [(int(r[0]), r[1]) for r in rows]
hdr = [l for l in open(tmp + '/all.txt') if l.strip().startswith('step')][0].split()
check(hdr[:2] == ['step', 'arc'], 'summary header: %s' % hdr[:3])
check(table(tmp + '/all.txt') == [(0, '0.0'), (1, '5.0'), (2, '10.0'), (3, '15.0')], 'arc column 0, 5, 10, 15')
check(table(tmp + '/s2.txt') == [(0, '0.0'), (2, '10.0')], '--step 2: step 2 at 10 deg')
a15 = json.load(open(tmp + '/a15.json'))
check([(s['step'], s['arc_deg']) for s in a15['steps']] == [(0, 0), (3, 15)], '--arc 15: step 3 (JSON)')
m = json.load(open(tmp + '/m.json'))
check([(s['step'], s['arc_deg']) for s in m['steps']] == [(0, 0), (3, 15)], '--mesh step-0000 step-0003: step 3, arc 15 (JSON)')
check(table(tmp + '/m.txt') == [(0, '0.0'), (3, '15.0')], '--mesh: the summary says step 3, arc 15')
rows = list(csv.DictReader(open(tmp + '/m/curvature.tsv'), delimiter='\t'))
check([r['step'] for r in rows] == ['0', '3'] and rows[1]['arc_deg'] == '15.0000', 'curvature.tsv: step 3, arc_deg 15')
full = list(csv.DictReader(open(run + '/curvature.tsv'), delimiter='\t'))
check(rows[1]['sia_D'] == full[3]['sia_D'], '--mesh step 3 has step 3\'s SIA')

# --- over-correction and a left eye
o = Page(tmp + '/over/report.html')
check(o.ids.get('verdict', '').startswith('Over-correction') and 'correction index 2.7' in o.ids['verdict'],
      'target 0.5 D: %s' % o.ids.get('verdict', '')[:70])
check('OS' in o.svgtext and 'OD' not in o.svgtext, '--eye OS draws a left eye')
check(any(l.startswith('verdict: Over-correction') for l in open(tmp + '/over.txt')), 'text summary verdict')

# --- run.yaml's provenance of a real run
ry = yaml.safe_load(open(tmp + '/beam/run.yaml'))
pv = ry['provenance']
ed = dict(l.split(None, 1) for l in open(tmp + '/beam.edits') if l.startswith(('hash ', 'scene ')))
check(ry['mesh_hash'] == ed['hash'].strip(), 'run.yaml mesh_hash = the edits header hash %s' % ry['mesh_hash'])
check(not {'mesh_hash', 'mesh_nodes', 'mesh_tets'} & set(pv) and ry['mesh_nodes'] > 0 and ry['mesh_tets'] > 0,
      'run.yaml names the mesh once, at its top level (not again in provenance)')
scene = open('plans/bench/beam-64.yaml', 'rb').read()
h = 0xcbf29ce484222325
for b in scene: h = ((h ^ b) * 0x100000001b3) & 0xffffffffffffffff
check(pv['scene_fnv1a'] == '%016x' % h, 'scene_fnv1a is the FNV-1a of the scene file')
check(pv['scene_text'] == scene.decode(), 'scene_text is the scene file')
check(pv['materials'] == {'body': {'model': 'isotropic', 'E_MPa': 1, 'nu': 0.3}}, 'materials as solved: %s' % pv['materials'])
ver = subprocess.run([B + '/augsolve', '--version'], capture_output=True, text=True).stdout.split()[-1]
check(pv['keratome'] == ver and re.fullmatch(r'\d+\.\d+\.\d+', pv['cholmod']) and re.fullmatch(r'\d+\.\d+\.\d+', pv['metis']),
      'tool versions: keratome %s, CHOLMOD %s, METIS %s' % (pv['keratome'], pv['cholmod'], pv['metis']))
st = list(csv.DictReader(open(tmp + '/beam/steps.tsv'), delimiter='\t'))
check(pv['solver']['factor_nnz_max'] == max(int(float(r['nnz_L'])) for r in st), 'factor_nnz_max = max nnz_L of steps.tsv')
res = max(float(r['rel_residual']) for r in st if r['rel_residual'] not in ('-', 'NaN', 'nan'))
check(abs(pv['solver']['rel_residual_max'] - res) <= 1e-3 * res and res < 1e-8, 'rel_residual_max %.3e' % res)
check(ry['steps'] == len(st) - 1 and ry['ordering'] == 'metis', 'run.yaml keeps its other keys')

# --- the report shows the provenance, with the run's own mesh hash (run.yaml's top level)
q = Page(tmp + '/prov/report.html')
pt = q.ids.get('provenance', '')
sy = yaml.safe_load(open(run + '/run.yaml'))
check(sy['mesh_hash'] + ': the mesh read here' in pt and ry['mesh_hash'] not in pt,
      'report shows the run\'s mesh hash %s, not the provenance donor\'s' % sy['mesh_hash'])
check('CHOLMOD ' + pv['cholmod'] in pt and 'body: model isotropic, E_MPa 1' in pt and 'factor_nnz_max' in pt,
      'report shows tools, materials and solver figures')

# --- the comparison page
c = Page(tmp + '/cmp/compare.html')
html = open(tmp + '/cmp/compare.html').read()
check('<script' not in html.lower() and "default-src 'none'" in html, 'compare.html: no script, CSP')
last_a, last_b = full[-1], list(csv.DictReader(open(tmp + '/s2/curvature.tsv'), delimiter='\t'))[-1]
fin = c.ids.get('final', '')
check(('%.3f' % float(last_a['sia_D'])) in fin and ('%.3f' % float(last_b['sia_D'])) in fin, 'compare: both runs\' SIA')
check(('%+.3f' % (float(last_b['sia_D']) - float(last_a['sia_D']))) in fin, 'compare: their difference')
check(len([t for t in c.svgtext if t.startswith(('A: ', 'B: '))]) == 6, 'compare: three plots of both runs')
sys.exit(1 if fails else 0)
PYEOF
echo "report_readers: all checks passed"
