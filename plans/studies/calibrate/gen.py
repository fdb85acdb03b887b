#!/usr/bin/python3
"""gen.py OUTCOMES BASE GRID OUT: the calibration study's inputs from the declared training set.

OUTCOMES  share/outcomes/lri-outcomes.tsv; its rows with role "train" are the arms.
BASE      the base eye scene (plans/eye.yaml).
GRID      the bridge stiffness values, MPa/mm, blank-separated ("0.05 0.13 0.33 0.85 2.2").
OUT       the study folder.

Writes (a file is rewritten only when its content changes, so make reruns only what changed):
  OUT/bases/k<i>.yaml        BASE (less its own wound: section) with `wound: {state: healed, bridge_stiffness: GRID[i],
                             age_rate: 0}`: at a given k, whatever the arm's age (the fit maps
                             theta and the arm's age to k, fit.py)
  OUT/patients/<run>.yaml    one lri-plan patient per model eye the arms need (below)
  OUT/arms.tsv               every arm's model eyes: which run, family, arc and measure
  OUT/study.mk               RUNS (every run x grid point) for the Makefile

An arm becomes one or two model eyes (sub): its orientation, or both WTR and ATR for a mixed
arm (predicted as their mean: the study's share of each is not reported). A model eye is the
default eye (1.50 D of keratometric cylinder; with the rule: steep at 90 deg, against the rule:
180 deg; right eye) at the arm's mean age, incision zone, depth and white-to-white, with its main
incision (temporal clear-corneal) simulated. An against-the-rule pair's temporal arc holds the
main incision (the surgeons put the phaco incision inside it: the model cannot cut an arc through
its tunnel, and lri-plan's clearance rule leaves such a pair out): its arcs are run without the
main incision (run "<arm>-arcs") and the main incision's simulated SIA, from the same eye's
single-arc run with it (run "<arm>-main"), is added as a double-angle vector (summarize.py).
"""
import csv
import os
import re
import sys


def slug(s):
    return re.sub(r"[^a-z0-9]+", "-", s.lower()).strip("-")


def put(path, text):
    """Write text to path unless it already holds it; atomically."""
    try:
        with open(path) as f:
            if f.read() == text:
                return
    except FileNotFoundError:
        pass
    tmp = f"{path}.tmp{os.getpid()}"
    with open(tmp, "w") as f:
        f.write(text)
    os.replace(tmp, path)


def die(path, line, msg):
    sys.exit(f"{path}:{line}: expected {msg}")


def width(main, path, line):
    m = re.search(r"([0-9.]+) mm", main)
    if not m or "temporal" not in main:
        die(path, line, f"a temporal main incision with its width in mm, found '{main}'")
    return float(m.group(1))


def depth(d, path, line):
    if d.endswith(" %"):
        return f"{d}"
    if d.endswith(" um"):
        # A blade set in um (the paralimbal study's 600 um) reaches the model eye's 90% of the
        # pachymetry at the zone or beyond it (580 um at 10 mm on the default eye), and a patient
        # file allows at most 90% (keratome-patient(5), depth): the arm is cut at 90%, the
        # deepest the planner cuts, which is what a 600 um blade does in an eye of 640-700 um.
        return "90 %"
    die(path, line, f"a depth in '%' or 'um', found '{d}'")


def wtw_of(row):
    m = re.search(r"white-to-white ([0-9.]+) mm assumed", row["derived"])
    return float(m.group(1)) if m else 11.7


def patient(name, age, axis, wtw, zone, dep, main_w, incisions, max_arc):
    k_steep, k_flat = 44.02, 42.52
    main = (f"main_incision: {{meridian: temporal, width: {main_w} mm, kind: clear_corneal, sia: simulate}}\n"
            if main_w else "")
    return (f"# {name}: a model eye of the calibration study (plans/studies/calibrate/gen.py)\n"
            f"name: {name}\neye: OD\nage: {age:g}\n"
            f"cornea:\n  keratometry: {{k_steep: {k_steep} D, k_flat: {k_flat} D, steep_axis: {axis} deg}}\n"
            f"  white_to_white: {wtw:g} mm\n"
            f"{main}"
            f"target: {{astigmatism: keratometric, residual: 0.5 D}}\n"
            f"constraints: {{incisions: {incisions}, max_arc: {max_arc:g} deg, zone: {zone:g} mm, "
            f"depth: {dep}, clearance: 15 deg}}\n")


def main(argv):
    if len(argv) != 5:
        sys.exit("usage: gen.py OUTCOMES BASE GRID OUT")
    outcomes, base, grid_s, out = argv[1:]
    grid = [float(x) for x in grid_s.split()]
    if len(grid) < 2 or any(not (k > 0) for k in grid) or sorted(grid) != grid:
        sys.exit(f"gen.py: GRID: expected two or more increasing positive stiffnesses, got '{grid_s}'")
    with open(base) as f:
        base_text = f.read()
    # the base's own wound section (plans/eye.yaml carries the identified one) is replaced
    base_text = re.sub(r"^wound:.*\n(?:[ \t#].*\n|\n)*", "", base_text, flags=re.M)
    for d in ("bases", "patients"):
        os.makedirs(f"{out}/{d}", exist_ok=True)
    for i, k in enumerate(grid):
        put(f"{out}/bases/k{i}.yaml",
            f"# the study's base scene at grid point {i} (gen.py): {os.path.abspath(base)} with a healed wound\n"
            + base_text.rstrip("\n")
            + f"\nwound: {{state: healed, bridge_stiffness: {k!r} MPa/mm, age_rate: 0 /y}}\n")
    runs, arms = {}, []
    with open(outcomes, newline="") as f:
        rows = list(csv.DictReader(f, delimiter="\t"))
    for line, r in enumerate(rows, start=2):
        if r["role"] != "train":
            continue
        age, arc, zone = float(r["age_mean_y"]), float(r["arc_deg"]), float(r["zone_mm"])
        main_w = width(r["main_incision"], outcomes, line)
        dep = depth(r["depth"], outcomes, line)
        wtw = wtw_of(r)
        if r["incisions"] not in ("single", "paired"):
            die(outcomes, line, f"incisions single or paired for a training arm, found '{r['incisions']}'")
        measure = "reduction" if r["measure"].startswith("reduction") else "along"
        subs = ["WTR", "ATR"] if r["orientation"] == "mixed" else [r["orientation"]]
        for sub in subs:
            axis = 90 if sub == "WTR" else 180
            eye = slug(f"{r['study']} {sub} z{zone:g} a{age:g} w{wtw:g} d{dep} m{main_w:g}")
            if sub == "WTR":
                runs[eye] = patient(eye, age, axis, wtw, zone, dep, main_w, "either", arc)
                arms.append((f"{r['study']} | {r['arm']}", sub, age, eye, "", r["incisions"], arc, measure, axis))
                continue
            # against the rule: the single arc with the main incision (nasal: the clearance rule
            # puts it on the half away from the incision), the pair without it
            runs[f"{eye}-main"] = patient(f"{eye}-main", age, axis, wtw, zone, dep, main_w, "single", 10)
            if r["incisions"] == "single":
                arms.append((f"{r['study']} | {r['arm']}", sub, age, f"{eye}-main", "", "single", arc, measure, axis))
            else:
                runs[f"{eye}-arcs"] = patient(f"{eye}-arcs", age, axis, wtw, zone, dep, 0, "paired", arc)
                arms.append((f"{r['study']} | {r['arm']}", sub, age, f"{eye}-arcs", f"{eye}-main", "paired", arc,
                             measure, axis))
    # each run's max_arc: the longest arc any arm reads from it
    longest = {run: 10.0 for run in runs}   # lri-plan's shortest max_arc: a main run's tunnel alone
    for a in arms:
        longest[a[3]] = max(longest[a[3]], a[6])
    fams = {}
    for a in arms:
        fams.setdefault(a[3], set()).add(a[5])
    for run, text in runs.items():
        text = re.sub(r"max_arc: [0-9.]+ deg", f"max_arc: {longest[run]:g} deg", text)
        if fams.get(run) and len(fams[run]) == 1:   # one family's arms only: run that family alone
            text = text.replace("incisions: either", f"incisions: {min(fams[run])}")
        put(f"{out}/patients/{run}.yaml", text)
    put(f"{out}/arms.tsv",
        "arm\tsub\tage_y\trun\tmain_run\tfamily\tarc_deg\tmeasure\tsteep_axis_deg\n"
        + "".join("\t".join(str(x) for x in a) + "\n" for a in arms))
    targets = [f"$(OUT)/runs/{run}/k{i}.json" for run in sorted(runs) for i in range(len(grid))]
    put(f"{out}/study.mk", "# made by gen.py\nRUNS := " + " ".join(targets) + "\n")
    print(f"gen.py: {len(arms)} model eyes of {len({a[0] for a in arms})} arms, {len(runs)} runs x "
          f"{len(grid)} grid points = {len(targets)} lri-plan runs", file=sys.stderr)


if __name__ == "__main__":
    main(sys.argv)
