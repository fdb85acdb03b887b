#!/usr/bin/python3
"""fit.py OUTCOMES RUNS OUT: identify the healing parameters on the training arms and validate
them leave-one-study-out (plans/studies/calibrate/README.md).

Inputs
  OUTCOMES  share/outcomes/lri-outcomes.tsv: the declared training set (role "train"), the
            clinical spreads (role "spread") and the rest (not used here).
  RUNS      the study's runs table (summarize.sh): one row per arm, model eye (sub: WTR, ATR or
            "-") and grid value of the bridge stiffness: columns arm, sub, age_y, log_k (natural
            log of k in MPa/mm), pred_D (the arm's measure predicted by the model at that k),
            dpred_dlogk_D (its derivative, from the run's `heal` derivative), tissue_sd_D (the
            first-order band's sd of pred_D from the tissue quantities alone).
Outputs (into OUT)
  identified.tsv   the identified values, their posterior sd and correlation, provenance
  arms.tsv         every training arm: measured, fitted (all arms) and left-one-study-out
                   prediction with its 90% band for the arm's mean and for one eye
  spread.tsv       the non-tissue term: each spread row's coefficient of variation
  report.md        the same as text

The model. An arm's eyes have mean age a; the healed wound's bridge stiffness is
    log k(a) = theta0 - theta1 (a - 60 y) / 10 y                       (lib/fem/wound.c)
(theta0: log k at 60 y; theta1: the fall of log k per decade of age). For a given arm, every
model quantity depends on theta only through k(a), so the runs give each arm's prediction as a
function of one variable, log k, at a few grid points with its derivative: a cubic Hermite
interpolant in log k through those values and slopes (extrapolation is refused) is the arm's
surrogate. A mixed-orientation arm is the mean of its WTR and ATR model eyes.

The fit. Log-ratio residuals r_i = log p_i(theta) - log m_i with variance
s_i^2 = cv_i^2 / n_i + tau^2: cv_i / sqrt(n_i) the measurement's standard error of the log
mean (a study that reports no SD or n gets the training set's imputed ones, flagged), tau the
between-study discrepancy (the model's and the studies' differences: estimated, by maximising
the marginal likelihood on a grid). Priors: theta0 ~ N(log k_prior, 2^2) (weak), theta1 ~
N(theta1_prior, sd_prior^2) from the mechanism (README.md: keratocyte density's fall with age).
Gauss-Newton on the posterior's negative log; the Laplace posterior's covariance is the inverse
of J^T W J + P at the optimum. Every step is printed.
"""
import csv
import math
import sys

import numpy as np

Z90 = 1.6448536269514722


def read_tsv(path):
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f, delimiter="\t"))
    if not rows:
        sys.exit(f"{path}: no rows")
    return rows


def num(row, key, path, line):
    v = row.get(key, "")
    try:
        x = float(v)
    except ValueError:
        sys.exit(f"{path}:{line}: expected a number in column {key}, found '{v}'")
    if not math.isfinite(x):
        sys.exit(f"{path}:{line}: expected a finite number in column {key}, found '{v}'")
    return x


class Curve:
    """An arm's model eye: pred(log k) through grid values and slopes (cubic Hermite)."""

    def __init__(self, pts):
        pts = sorted(pts)
        self.x = np.array([p[0] for p in pts])
        self.y = np.array([p[1] for p in pts])
        self.d = np.array([p[2] for p in pts])
        self.sd = np.array([p[3] for p in pts])
        if len(self.x) < 2 or np.any(np.diff(self.x) <= 0):
            raise ValueError("an arm needs at least two distinct grid values of log k")

    def __call__(self, x):
        if not (self.x[0] - 1e-12 <= x <= self.x[-1] + 1e-12):
            raise ValueError(f"log k {x:.4f} outside the grid [{self.x[0]:.4f}, {self.x[-1]:.4f}]")
        i = min(max(np.searchsorted(self.x, x) - 1, 0), len(self.x) - 2)
        h = self.x[i + 1] - self.x[i]
        t = (x - self.x[i]) / h
        h00, h10 = 2 * t**3 - 3 * t**2 + 1, t**3 - 2 * t**2 + t
        h01, h11 = -2 * t**3 + 3 * t**2, t**3 - t**2
        y = h00 * self.y[i] + h10 * h * self.d[i] + h01 * self.y[i + 1] + h11 * h * self.d[i + 1]
        dh00, dh10 = (6 * t**2 - 6 * t) / h, 3 * t**2 - 4 * t + 1
        dh01, dh11 = (-6 * t**2 + 6 * t) / h, 3 * t**2 - 2 * t
        dy = dh00 * self.y[i] + dh10 * self.d[i] + dh01 * self.y[i + 1] + dh11 * self.d[i + 1]
        sd = (1 - t) * self.sd[i] + t * self.sd[i + 1]
        return y, dy, sd


class Arm:
    def __init__(self, key, row, curves):
        self.key = key
        self.study = row["study"]
        self.name = row["arm"]
        self.age = float(row["age_mean_y"])
        self.mean = float(row["mean_D"])
        self.sd = float(row["sd_D"]) if row["sd_D"] else float("nan")
        self.n = float(row["eyes"]) if row["eyes"] else float("nan")
        self.curves = curves          # one (WTR or ATR) or two (mixed: their mean)

    def pred(self, theta):
        """Predicted measure, d/dtheta (2,), tissue sd, log k."""
        lk = theta[0] - theta[1] * (self.age - 60) / 10
        vals = [c(lk) for c in self.curves]
        y = sum(v[0] for v in vals) / len(vals)
        dy = sum(v[1] for v in vals) / len(vals)
        sd = sum(v[2] for v in vals) / len(vals)
        return y, np.array([dy, -dy * (self.age - 60) / 10]), sd, lk


def load(outcomes, runs):
    rows = read_tsv(outcomes)
    train = {}
    spread = []
    for i, r in enumerate(rows, start=2):
        if r["role"] == "train":
            train[f'{r["study"]} | {r["arm"]}'] = (i, r)
        elif r["role"] == "spread":
            spread.append((num(r, "mean_D", outcomes, i), num(r, "sd_D", outcomes, i), r))
    pts = {}
    for i, r in enumerate(read_tsv(runs), start=2):
        key = r["arm"]
        if key not in train:
            sys.exit(f"{runs}:{i}: arm '{key}' is not a training arm of {outcomes}")
        pts.setdefault((key, r["sub"]), []).append(
            (num(r, "log_k", runs, i), num(r, "pred_D", runs, i), num(r, "dpred_dlogk_D", runs, i),
             num(r, "tissue_sd_D", runs, i)))
    arms = []
    for key, (line, r) in train.items():
        subs = ["WTR", "ATR"] if r["orientation"] == "mixed" else [r["orientation"]]
        curves = []
        for s in subs:
            if (key, s) not in pts:
                sys.exit(f"{runs}: no runs for arm '{key}' ({s}), needed by {outcomes}:{line}")
            curves.append(Curve(pts[(key, s)]))
        arms.append(Arm(key, r, curves))
    return arms, spread


def impute(arms, spread):
    """Each arm's cv and n: its own when reported, else the spread rows' pooled cv and the
    training arms' median n (flagged)."""
    cvs = [s / m for m, s, _ in spread if m > 0]
    cv_pool = math.sqrt(sum(c * c for c in cvs) / len(cvs))
    ns = [a.n for a in arms if math.isfinite(a.n)]
    n_default = float(np.median(ns)) if ns else 20.0
    for a in arms:
        a.cv = a.sd / a.mean if math.isfinite(a.sd) and a.mean > 0 else cv_pool
        a.cv_imputed = not math.isfinite(a.sd)
        a.neff = a.n if math.isfinite(a.n) else n_default
        a.n_imputed = not math.isfinite(a.n)
    return cv_pool, cvs


def fit(arms, prior, tau, quiet=False):
    """MAP by Gauss-Newton; returns theta, covariance, the objective."""
    m0, s0 = np.array(prior[0]), np.array(prior[1])
    P = np.diag(1 / s0**2)
    theta = m0.copy()
    for it in range(50):
        J, r, w = [], [], []
        for a in arms:
            try:
                y, dy, _, _ = a.pred(theta)
            except ValueError as ex:
                raise ValueError(f"{a.key}: {ex}")
            r.append(math.log(y) - math.log(a.mean))
            J.append(dy / y)
            w.append(1 / (a.cv**2 / a.neff + tau**2))
        J, r, W = np.array(J), np.array(r), np.diag(w)
        H = J.T @ W @ J + P
        g = J.T @ W @ r + P @ (theta - m0)
        step = np.linalg.solve(H, -g)
        # a damped step that stays inside every arm's grid
        lam = 1.0
        while lam > 1e-6:
            t = theta + lam * step
            try:
                for a in arms:
                    a.pred(t)
                break
            except ValueError:
                lam /= 2
        theta = theta + lam * step
        if not quiet:
            print(f"  GN {it}: theta = ({theta[0]:.5f}, {theta[1]:.5f}), |step| {np.linalg.norm(lam * step):.2e}",
                  file=sys.stderr)
        if np.linalg.norm(lam * step) < 1e-10:
            break
    else:
        raise RuntimeError("Gauss-Newton did not converge in 50 iterations")
    J, r, w = [], [], []
    for a in arms:
        y, dy, _, _ = a.pred(theta)
        r.append(math.log(y) - math.log(a.mean))
        J.append(dy / y)
        w.append(1 / (a.cv**2 / a.neff + tau**2))
    J, r, W = np.array(J), np.array(r), np.diag(w)
    C = np.linalg.inv(J.T @ W @ J + P)
    # the marginal likelihood (Laplace) of tau: -1/2 (r'Wr + d'Pd + log det(2 pi W^-1) + log det H)
    d = theta - m0
    lml = -0.5 * (r @ W @ r + d @ P @ d - np.sum(np.log(w)) + np.linalg.slogdet(J.T @ W @ J + P)[1]
                  - np.linalg.slogdet(P)[1])
    return theta, C, lml


def fit_tau(arms, prior):
    """tau by the marginal likelihood over a grid (0 .. 1 in log units)."""
    best = None
    for tau in np.linspace(0.0, 1.0, 101):
        try:
            _, _, lml = fit(arms, prior, tau, quiet=True)
        except (ValueError, RuntimeError):
            continue
        if best is None or lml > best[1]:
            best = (tau, lml)
    if best is None:
        raise RuntimeError("no value of tau gives a fit inside the grid")
    return best[0]


def band(a, theta, C, tau, cv_nt):
    """The arm's prediction, the 90% band of its mean (posterior + tau, log-normal) and of one
    eye (adds the tissue band and the non-tissue term)."""
    y, dy, tsd, lk = a.pred(theta)
    if not (y > 0):
        # a measure the model predicts at or below zero (an over-correcting arm's reduction):
        # no log-normal band; the arm counts as not covered
        nan = float("nan")
        return y, nan, nan, nan, nan, lk
    g = dy / y
    v_mean = g @ C @ g + tau**2
    lo, hi = y * math.exp(-Z90 * math.sqrt(v_mean)), y * math.exp(Z90 * math.sqrt(v_mean))
    v_eye = v_mean + (tsd / y) ** 2 + cv_nt**2
    elo, ehi = y * math.exp(-Z90 * math.sqrt(v_eye)), y * math.exp(Z90 * math.sqrt(v_eye))
    return y, lo, hi, elo, ehi, lk


def main(argv):
    if len(argv) != 5:
        sys.exit("usage: fit.py OUTCOMES RUNS PRIOR OUT   (PRIOR: theta0 sd0 theta1 sd1)")
    outcomes, runs, prior_s, out = argv[1:]
    p = [float(x) for x in prior_s.split()]
    prior = ((p[0], p[2]), (p[1], p[3]))
    arms, spread = load(outcomes, runs)
    cv_pool, cvs = impute(arms, spread)
    tissue_cv = float(np.median([a.pred(np.array(prior[0]))[2] / a.pred(np.array(prior[0]))[0] for a in arms]))
    cv_nt = math.sqrt(max(cv_pool**2 - tissue_cv**2, 0.0))
    print(f"fit.py: {len(arms)} training arms, {len(spread)} spread rows: pooled cv {cv_pool:.3f}, "
          f"tissue cv {tissue_cv:.3f}, non-tissue cv {cv_nt:.3f}", file=sys.stderr)
    tau = fit_tau(arms, prior)
    print(f"fit.py: all arms, tau = {tau:.3f}", file=sys.stderr)
    theta, C, _ = fit(arms, prior, tau)
    studies = sorted({a.study for a in arms})
    loso = {}
    for s in studies:
        keep = [a for a in arms if a.study != s]
        tau_s = fit_tau(keep, prior)
        th_s, C_s, _ = fit(keep, prior, tau_s, quiet=True)
        print(f"fit.py: without {s}: theta = ({th_s[0]:.4f}, {th_s[1]:.4f}), tau {tau_s:.3f}", file=sys.stderr)
        for a in arms:
            if a.study == s:
                loso[a.key] = band(a, th_s, C_s, tau_s, cv_nt) + (th_s,)
    sd = np.sqrt(np.diag(C))
    corr = C[0, 1] / (sd[0] * sd[1])
    with open(f"{out}/identified.tsv", "w") as f:
        f.write("quantity\tmean\tsd\tunit\n")
        f.write(f"log_k60\t{theta[0]:.6f}\t{sd[0]:.6f}\tlog(MPa/mm)\n")
        f.write(f"k60\t{math.exp(theta[0]):.6g}\t{math.exp(theta[0]) * sd[0]:.6g}\tMPa/mm\n")
        f.write(f"age_fall\t{theta[1]:.6f}\t{sd[1]:.6f}\tlog k per decade\n")
        f.write(f"corr\t{corr:.6f}\t\t\n")
        f.write(f"tau\t{tau:.6f}\t\tlog units\n")
        f.write(f"cv_nontissue\t{cv_nt:.6f}\t\t\n")
        f.write(f"cv_pooled\t{cv_pool:.6f}\t\t\n")
        f.write(f"cv_tissue\t{tissue_cv:.6f}\t\t\n")
    with open(f"{out}/arms.tsv", "w") as f:
        f.write("study\tarm\tage_y\tmeasured_D\tcv\tcv_imputed\tn\tn_imputed\tfit_D\tfit_lo90_D\tfit_hi90_D\t"
                "loso_D\tloso_lo90_D\tloso_hi90_D\tloso_eye_lo90_D\tloso_eye_hi90_D\tloso_covers\tloso_eye_covers\t"
                "loso_ratio\n")
        for a in arms:
            y, lo, hi, _, _, _ = band(a, theta, C, tau, cv_nt)
            ly, llo, lhi, elo, ehi, _, _ = loso[a.key]
            f.write(f"{a.study}\t{a.name}\t{a.age:g}\t{a.mean:.3f}\t{a.cv:.3f}\t{int(a.cv_imputed)}\t{a.neff:g}\t"
                    f"{int(a.n_imputed)}\t{y:.4f}\t{lo:.4f}\t{hi:.4f}\t{ly:.4f}\t{llo:.4f}\t{lhi:.4f}\t{elo:.4f}\t"
                    f"{ehi:.4f}\t{int(llo <= a.mean <= lhi)}\t{int(elo <= a.mean <= ehi)}\t{ly / a.mean:.3f}\n")
    with open(f"{out}/spread.tsv", "w") as f:
        f.write("study\tarm\tmean_D\tsd_D\tcv\n")
        for m, s, r in spread:
            f.write(f"{r['study']}\t{r['arm']}\t{m:g}\t{s:g}\t{s / m:.3f}\n")
    print(f"fit.py: k60 = {math.exp(theta[0]):.4g} MPa/mm (log sd {sd[0]:.3f}), age fall {theta[1]:.4f} "
          f"+- {sd[1]:.4f} per decade, corr {corr:.3f}", file=sys.stderr)


if __name__ == "__main__":
    main(sys.argv)
