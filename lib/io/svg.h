/* svg.h: a small inline-SVG writer for the HTML report: shapes in pixel coordinates, text
 * escaped for XML, and a plot frame that maps data to pixels with "nice" ticks. Styling is by
 * class names; the page's CSS gives the colours. Writes to a stream; errors show in ferror(f). */
#ifndef KT_SVG_H
#define KT_SVG_H

#include <stdio.h>

/* Text with & < > " ' escaped. */
void kt_svg_escape(FILE *f, const char *s);

/* <svg> with a viewBox of w x h px, scaled to its container; label: the accessible name. */
void kt_svg_begin(FILE *f, double w, double h, const char *label);
void kt_svg_end(FILE *f);

void kt_svg_line(FILE *f, double x0, double y0, double x1, double y1, const char *cls);
void kt_svg_circle(FILE *f, double cx, double cy, double r, const char *cls);
/* Points xy[2n]: a polyline, or a polygon when closed. */
void kt_svg_poly(FILE *f, const double *xy, int n, int closed, const char *cls);
/* The arc of the circle (cx, cy, r) from angle a0 to a1 (deg, counter-clockwise on screen,
 * 0 to the right: the TABO convention of a frontal view). */
void kt_svg_arc(FILE *f, double cx, double cy, double r, double a0, double a1, const char *cls);
/* A line from (x0, y0) with an arrow head of length head px at (x1, y1). */
void kt_svg_arrow(FILE *f, double x0, double y0, double x1, double y1, double head, const char *cls);
/* Text at (x, y); anchor "start", "middle" or "end"; printf-style, escaped. */
void kt_svg_text(FILE *f, double x, double y, const char *anchor, const char *cls, const char *fmt, ...)
    __attribute__((format(printf, 6, 7)));

/* A plot: the pixel box (x, y, w, h) showing data x in [x0, x1] and y in [y0, y1]. */
typedef struct kt_svg_plot {
    double x, y, w, h;
    double x0, x1, y0, y1;
} kt_svg_plot;

double kt_svg_px(const kt_svg_plot *p, double x);
double kt_svg_py(const kt_svg_plot *p, double y);

/* A tick step of 1, 2 or 5 times a power of ten giving about n ticks over range. */
double kt_svg_nice_step(double range, int n);

/* Widen [*lo, *hi] to multiples of the nice step for about n ticks (a zero range gets +-1). */
void kt_svg_nice_range(double *lo, double *hi, int n);

/* Grid, ticks with labels (printf formats xfmt, yfmt) and axis titles. */
void kt_svg_axes(FILE *f, const kt_svg_plot *p, const char *xfmt, const char *yfmt, const char *xtitle,
                 const char *ytitle);

/* A data series as a polyline with a dot at each point (cls names the colour); points with a
 * NaN or infinite coordinate are left out. */
void kt_svg_series(FILE *f, const kt_svg_plot *p, const double *x, const double *y, int n, const char *cls);

#endif
