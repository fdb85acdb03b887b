#!/usr/bin/env python3
"""make-pentacam.py: writes the synthetic Pentacam export of plans/patients/pentacam-od.yaml
(keratome-patient(5), THE PENTACAM EXPORT): the anterior and posterior elevation maps of a
biconic pair (with-the-rule, 1.75 D, aspheric) and a pachymetry map, on the device's 141 x 141
grid (-7 ... 7 mm, 0.1 mm), ';'-separated with decimal commas, cells beyond the measured
disk and a few scattered ones marked -1 or left empty. Closed-form, so the fit is exact:
  python3 plans/patients/make-pentacam.py plans/patients/pentacam
It also writes {base}-asym-front.csv, the anterior elevation of plans/patients/asym-od.yaml:
the same biconic plus a coma-like term kappa * u * (u^2 + v^2) along the steep meridian u
(kappa = -4e-4 / mm^2, about 10 um at 3 mm), which makes the inferior half of the steep
meridian steeper than the superior half (an asymmetric bow tie)."""
import math
import sys


def sag(x, y, rs, rf, axis, q, ax, ay):
    t = math.radians(axis)
    dx, dy = x - ax, y - ay
    u, v = math.cos(t) * dx + math.sin(t) * dy, -math.sin(t) * dx + math.cos(t) * dy
    q1 = u * u / rs + v * v / rf
    q2 = u * u / rs ** 2 + v * v / rf ** 2
    w = 1 - (1 + q) * q2
    return q1 / (1 + math.sqrt(w)) if w > 0 else None


def write(path, title, value, r_data):
    with open(path, "w") as f:
        f.write(f"Synthetic Pentacam export (keratome);{title}\nEye;OD\n")
        f.write("".join(f";{-7 + 0.1 * i:.1f}".replace(".", ",") for i in range(141)) + "\n")
        for j in range(140, -1, -1):
            y = -7 + 0.1 * j
            row = [f"{y:.1f}".replace(".", ",")]
            for i in range(141):
                x = -7 + 0.1 * i
                v = value(x, y)
                if v is None or math.hypot(x, y) > r_data or (i * 141 + j) % 17 == 0:
                    row.append("-1" if (i + j) % 2 else "")
                else:
                    row.append(f"{v:.6f}".replace(".", ","))
            f.write(";".join(row) + "\n")


base = sys.argv[1] if len(sys.argv) > 1 else "pentacam"
# anterior K 44.75 / 43.00 D @ 92 deg, Q -0.20; posterior -6.20 / -5.85 D @ 88 deg, Q -0.25
ant = (337.5 / 44.75, 337.5 / 43.00, 92.0, -0.20, 0.04, -0.02)
post = (40 / 6.20, 40 / 5.85, 88.0, -0.25, 0.04, -0.02)
write(f"{base}-front.csv", "Elevation front [mm]", lambda x, y: sag(x, y, *ant), 6.5)
write(f"{base}-back.csv", "Elevation back [mm]", lambda x, y: sag(x, y, *post), 6.0)
write(f"{base}-pachy.csv", "Pachymetry [um]",
      lambda x, y: 1000 * (0.545 + 0.0035 * ((x - 0.04) ** 2 + (y + 0.02) ** 2)
                           + 0.00012 * ((x - 0.04) ** 2 + (y + 0.02) ** 2) ** 2), 6.9)


def asym(x, y, kappa=-4e-4):
    z = sag(x, y, *ant)
    if z is None:
        return None
    t = math.radians(ant[2])
    dx, dy = x - ant[4], y - ant[5]
    u = math.cos(t) * dx + math.sin(t) * dy
    return z + kappa * u * (dx * dx + dy * dy)


write(f"{base}-asym-front.csv", "Elevation front [mm]", asym, 6.5)
