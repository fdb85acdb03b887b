#!/usr/bin/python3
"""summarize.py OUT GRID: the runs table fit.py reads, from the study's plan.json files.

For every model eye of OUT/arms.tsv (gen.py) and every grid point i (bridge stiffness GRID[i]):
the arm's measure predicted by the model, its derivative with respect to ln k, and the tissue
band's sd of it, written to OUT/runs.tsv (columns: arm, sub, age_y, log_k, pred_D,
dpred_dlogk_D, tissue_sd_D).

The SIA is read as a double-angle vector (x, y) = |SIA| (cos 2a, sin 2a), a its axis, from a
candidate family's curve at the arm's arc: the change of the eye's keratometric astigmatism from
the pre-operative (intact) eye, a simulated main incision included (lri-plan(1), FILES), with its
derivative per band quantity (dsia). An against-the-rule pair's main incision is added as a vector
from its -main run (gen.py): that run's curve at arc 0 is the main incision's own SIA. The
measures (the training table's `measure` column):
  along      the SIA's component along the correction of the arcs' meridian m: arcs flatten m,
             so their SIA is steep at m + 90: pred = (x, y) . (cos 2(m + 90), sin 2(m + 90))
             (the with-the-wound minus against-the-wound change of Holladay-Cravy-Koch)
  reduction  |A_pre| - |A_pre + SIA|, A_pre the eye's pre-operative keratometric astigmatism
             (1.50 D at m): the reduction of the magnitude of astigmatism
d pred / d ln k is g . dsia[heal] (heal is ln k), g the gradient of pred in (x, y); the tissue sd
is sqrt(sum over the other quantities of (g . dsia[q] sd_q)^2).
"""
import csv
import json
import math
import sys


def vec(mag, axis):
    a = math.radians(2 * axis)
    return (mag * math.cos(a), mag * math.sin(a))


def curve_at(plan, path, family, arc):
    for c in plan["candidates"]:
        if c["incisions"] == family:
            for p in c["curve"]:
                if abs(p["arc_deg"] - arc) < 1e-6:
                    return p, plan
            sys.exit(f"{path}: the {family} curve has no step at {arc:g} deg")
    sys.exit(f"{path}: no {family} candidate (lri-plan left it out?)")


def load(path):
    try:
        with open(path) as f:
            return json.load(f)
    except (OSError, ValueError) as ex:
        sys.exit(f"{path}: {ex}")


def sia_of(p):
    x, y = vec(p["sia_intact_D"], p["sia_intact_axis_deg"])
    return [x, y], {q: d for q, d in p["dsia"].items()}


def main(argv):
    if len(argv) != 3:
        sys.exit("usage: summarize.py OUT GRID")
    out, grid = argv[1], [float(k) for k in argv[2].split()]
    with open(f"{out}/arms.tsv", newline="") as f:
        arms = list(csv.DictReader(f, delimiter="\t"))
    rows = []
    for a in arms:
        m = float(a["steep_axis_deg"])
        for i, k in enumerate(grid):
            path = f"{out}/runs/{a['run']}/k{i}.json"
            plan = load(path)
            p, _ = curve_at(plan, path, a["family"], float(a["arc_deg"]))
            s, ds = sia_of(p)
            if a["main_run"]:
                mpath = f"{out}/runs/{a['main_run']}/k{i}.json"
                mp, _ = curve_at(load(mpath), mpath, "single", 0.0)
                s2, ds2 = sia_of(mp)
                s = [s[0] + s2[0], s[1] + s2[1]]
                ds = {q: [ds[q][0] + ds2[q][0], ds[q][1] + ds2[q][1]] for q in ds}
            if a["measure"] == "along":
                u = vec(1.0, m + 90)
                pred, g = s[0] * u[0] + s[1] * u[1], u
            else:
                pre = vec(1.50, m)
                post = (pre[0] + s[0], pre[1] + s[1])
                n = math.hypot(*post)
                pred, g = 1.50 - n, (-post[0] / n, -post[1] / n)
            sds = {q["name"]: q["sd"] for q in plan["band"]["quantities"]}
            if "heal" not in ds:
                sys.exit(f"{path}: no derivative with respect to heal (the run was not healed, or had no band)")
            dk = g[0] * ds["heal"][0] + g[1] * ds["heal"][1]
            var = sum(((g[0] * d[0] + g[1] * d[1]) * sds[q]) ** 2 for q, d in ds.items() if q != "heal")
            rows.append((a["arm"], a["sub"], a["age_y"], math.log(k), pred, dk, math.sqrt(var)))
    with open(f"{out}/runs.tsv", "w") as f:
        f.write("arm\tsub\tage_y\tlog_k\tpred_D\tdpred_dlogk_D\ttissue_sd_D\n")
        for r in rows:
            f.write("\t".join([r[0], r[1], r[2]] + [f"{x:.9g}" for x in r[3:]]) + "\n")
    print(f"summarize.py: {len(rows)} rows from {len(arms)} model eyes x {len(grid)} grid points", file=sys.stderr)


if __name__ == "__main__":
    main(sys.argv)
