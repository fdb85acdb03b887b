/* pentacam_synth.h: synthetic Pentacam map exports for the tests (test code only): a biconic
 * surface (radii of the steep and flat meridians, steep axis, one conic constant Q, apex at
 * (ax, ay)) as sagittal heights below its apex plane, or a thickness profile t(r) in um, on the
 * device's 141 x 141 grid, -7 ... 7 mm, with cells marked missing. */
#ifndef KT_PENTACAM_SYNTH_H
#define KT_PENTACAM_SYNTH_H

#include <math.h>
#include <stdio.h>

typedef struct synth_surface {
    double r_steep, r_flat, axis, conic, ax, ay; /* mm, mm, deg, -, mm, mm */
    double coma;                                 /* 1/mm^2: + coma u (u^2 + v^2), u along the axis */
} synth_surface;

/* Sag of the biconic at (x, y); NAN outside its domain. */
static double synth_sag(const synth_surface *s, double x, double y)
{
    double t = s->axis * 3.14159265358979323846 / 180, c = cos(t), sn = sin(t);
    double dx = x - s->ax, dy = y - s->ay, u = c * dx + sn * dy, v = -sn * dx + c * dy;
    double cs = 1 / s->r_steep, cf = 1 / s->r_flat;
    double q1 = cs * u * u + cf * v * v, q2 = cs * cs * u * u + cf * cf * v * v;
    double w = 1 - (1 + s->conic) * q2;
    return w > 0 ? q1 / (1 + sqrt(w)) + s->coma * u * (u * u + v * v) : NAN;
}

/* Which cells are missing: beyond radius r_data from the centre, every 13th cell, a 5-cell
 * patch near (2, 1) mm; marked "-1" or left empty alternately. */
static int synth_missing(int i, int j, double r_data)
{
    double x = -7 + 0.1 * i, y = -7 + 0.1 * j;
    if (hypot(x, y) > r_data) return 1;
    if ((i * 141 + j) % 13 == 0) return 1;
    return fabs(x - 2) < 0.25 && fabs(y - 1) < 0.25;
}

/* Write a map: sep ';' (with decimal commas when comma_decimal) or ','; mirror: x -> -x (the
 * other eye's map of a mirror-symmetric cornea); value(x, y) from the surface (mm) or, when
 * s is NULL, the thickness t0 + t2 r^2 + t4 r^4 (mm) written in um. 0 on success. */
static int synth_write(const char *path, const synth_surface *s, const double *pachy, char sep, int comma_decimal,
                       int mirror, double r_data)
{
    FILE *f = fopen(path, "w");
    if (!f) return -1;
    fprintf(f, "Synthetic test export%cEye%c%s\n", sep, sep, mirror ? "OS" : "OD");
    fprintf(f, "%s [%s]\n", s ? "Elevation" : "Pachymetry", s ? "mm" : "um");
    for (int i = 0; i < 141; i++) fprintf(f, "%c%.1f", sep, -7 + 0.1 * i);
    fputc('\n', f);
    for (int j = 140; j >= 0; j--) {
        double y = -7 + 0.1 * j;
        fprintf(f, "%.1f", y);
        for (int i = 0; i < 141; i++) {
            double x = -7 + 0.1 * i, xs = mirror ? -x : x, v;
            if (s) v = synth_sag(s, xs, y);
            else {
                double r2 = xs * xs + y * y;
                v = 1000 * (pachy[0] + pachy[1] * r2 + pachy[2] * r2 * r2);
            }
            if (synth_missing(i, j, r_data) || isnan(v)) {
                fprintf(f, (i + j) % 2 ? "%c-1" : "%c", sep);
                continue;
            }
            char buf[64];
            snprintf(buf, sizeof buf, "%.10f", v);
            if (comma_decimal)
                for (char *p = buf; *p; p++)
                    if (*p == '.') *p = ',';
            fprintf(f, "%c%s", sep, buf);
        }
        fputc('\n', f);
    }
    return fclose(f) == 0 ? 0 : -1;
}

#endif
