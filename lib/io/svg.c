/* svg.c: inline SVG for the HTML report. */
#include <math.h>
#include <stdarg.h>

#include "svg.h"
#include "util.h"

void kt_svg_escape(FILE *f, const char *s)
{
    for (; *s; s++) {
        switch (*s) {
        case '&': fputs("&amp;", f); break;
        case '<': fputs("&lt;", f); break;
        case '>': fputs("&gt;", f); break;
        case '"': fputs("&quot;", f); break;
        case '\'': fputs("&#39;", f); break;
        default: fputc(*s, f);
        }
    }
}

void kt_svg_begin(FILE *f, double w, double h, const char *label)
{
    fprintf(f, "<svg xmlns=\"http://www.w3.org/2000/svg\" viewBox=\"0 0 %.0f %.0f\" role=\"img\" aria-label=\"", w, h);
    kt_svg_escape(f, label);
    fputs("\">\n", f);
}

void kt_svg_end(FILE *f) { fputs("</svg>\n", f); }

void kt_svg_line(FILE *f, double x0, double y0, double x1, double y1, const char *cls)
{
    fprintf(f, "<line x1=\"%.2f\" y1=\"%.2f\" x2=\"%.2f\" y2=\"%.2f\" class=\"%s\"/>\n", x0, y0, x1, y1, cls);
}

void kt_svg_circle(FILE *f, double cx, double cy, double r, const char *cls)
{
    fprintf(f, "<circle cx=\"%.2f\" cy=\"%.2f\" r=\"%.2f\" class=\"%s\"/>\n", cx, cy, r, cls);
}

void kt_svg_poly(FILE *f, const double *xy, int n, int closed, const char *cls)
{
    fprintf(f, "<%s class=\"%s\" points=\"", closed ? "polygon" : "polyline", cls);
    for (int i = 0; i < n; i++) fprintf(f, "%s%.2f,%.2f", i ? " " : "", xy[2 * i], xy[2 * i + 1]);
    fputs("\"/>\n", f);
}

void kt_svg_arc(FILE *f, double cx, double cy, double r, double a0, double a1, const char *cls)
{
    double t0 = a0 * KT_PI / 180, t1 = a1 * KT_PI / 180;
    int large = fabs(a1 - a0) > 180, sweep = a1 > a0 ? 0 : 1; /* screen y is down: ccw is sweep 0 */
    fprintf(f, "<path class=\"%s\" d=\"M %.2f %.2f A %.2f %.2f 0 %d %d %.2f %.2f\"/>\n", cls, cx + r * cos(t0),
            cy - r * sin(t0), r, r, large, sweep, cx + r * cos(t1), cy - r * sin(t1));
}

void kt_svg_arrow(FILE *f, double x0, double y0, double x1, double y1, double head, const char *cls)
{
    double dx = x1 - x0, dy = y1 - y0, len = hypot(dx, dy);
    fprintf(f, "<g class=\"%s\">", cls);
    if (len < 1e-9) {
        fputs("</g>\n", f);
        return;
    }
    double ux = dx / len, uy = dy / len, hl = fmin(head, 0.5 * len), bx = x1 - hl * ux, by = y1 - hl * uy;
    fprintf(f, "<line x1=\"%.2f\" y1=\"%.2f\" x2=\"%.2f\" y2=\"%.2f\"/>", x0, y0, bx, by);
    fprintf(f, "<polygon points=\"%.2f,%.2f %.2f,%.2f %.2f,%.2f\"/></g>\n", x1, y1, bx - 0.4 * hl * uy,
            by + 0.4 * hl * ux, bx + 0.4 * hl * uy, by - 0.4 * hl * ux);
}

void kt_svg_text(FILE *f, double x, double y, const char *anchor, const char *cls, const char *fmt, ...)
{
    char buf[512];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(buf, sizeof buf, fmt, ap);
    va_end(ap);
    fprintf(f, "<text x=\"%.2f\" y=\"%.2f\" text-anchor=\"%s\" class=\"%s\">", x, y, anchor, cls);
    kt_svg_escape(f, buf);
    fputs("</text>\n", f);
}

double kt_svg_px(const kt_svg_plot *p, double x) { return p->x + (x - p->x0) / (p->x1 - p->x0) * p->w; }
double kt_svg_py(const kt_svg_plot *p, double y) { return p->y + p->h - (y - p->y0) / (p->y1 - p->y0) * p->h; }

double kt_svg_nice_step(double range, int n)
{
    if (!(range > 0) || n < 1) return 1;
    double raw = range / n, p10 = pow(10, floor(log10(raw))), m = raw / p10;
    return (m < 1.5 ? 1 : m < 3.5 ? 2 : m < 7.5 ? 5 : 10) * p10;
}

void kt_svg_nice_range(double *lo, double *hi, int n)
{
    if (!(*hi > *lo)) *lo -= 1, *hi += 1;
    double s = kt_svg_nice_step(*hi - *lo, n);
    *lo = s * floor(*lo / s + 1e-9);
    *hi = s * ceil(*hi / s - 1e-9);
}

void kt_svg_axes(FILE *f, const kt_svg_plot *p, const char *xfmt, const char *yfmt, const char *xtitle,
                 const char *ytitle)
{
    double sx = kt_svg_nice_step(p->x1 - p->x0, 6), sy = kt_svg_nice_step(p->y1 - p->y0, 5);
    for (double v = sx * ceil(p->x0 / sx - 1e-9); v <= p->x1 + 1e-9 * sx; v += sx) {
        double X = kt_svg_px(p, v);
        kt_svg_line(f, X, p->y, X, p->y + p->h, "grid");
        kt_svg_text(f, X, p->y + p->h + 16, "middle", "tick", xfmt, fabs(v) < 1e-12 * sx ? 0.0 : v);
    }
    for (double v = sy * ceil(p->y0 / sy - 1e-9); v <= p->y1 + 1e-9 * sy; v += sy) {
        double Y = kt_svg_py(p, v);
        kt_svg_line(f, p->x, Y, p->x + p->w, Y, fabs(v) < 1e-9 * sy ? "zero" : "grid");
        kt_svg_text(f, p->x - 6, Y + 4, "end", "tick", yfmt, fabs(v) < 1e-12 * sy ? 0.0 : v);
    }
    fprintf(f, "<rect class=\"frame\" x=\"%.2f\" y=\"%.2f\" width=\"%.2f\" height=\"%.2f\"/>\n", p->x, p->y, p->w, p->h);
    kt_svg_text(f, p->x + p->w / 2, p->y + p->h + 36, "middle", "axtitle", "%s", xtitle);
    fprintf(f, "<text transform=\"translate(%.2f %.2f) rotate(-90)\" text-anchor=\"middle\" class=\"axtitle\">",
            p->x - 48, p->y + p->h / 2);
    kt_svg_escape(f, ytitle);
    fputs("</text>\n", f);
}

void kt_svg_series(FILE *f, const kt_svg_plot *p, const double *x, const double *y, int n, const char *cls)
{
    fprintf(f, "<g class=\"%s\"><polyline points=\"", cls);
    for (int i = 0, k = 0; i < n; i++)
        if (isfinite(x[i]) && isfinite(y[i])) fprintf(f, "%s%.2f,%.2f", k++ ? " " : "", kt_svg_px(p, x[i]), kt_svg_py(p, y[i]));
    fputs("\"/>", f);
    for (int i = 0; i < n; i++)
        if (isfinite(x[i]) && isfinite(y[i]))
            fprintf(f, "<circle cx=\"%.2f\" cy=\"%.2f\" r=\"3\"/>", kt_svg_px(p, x[i]), kt_svg_py(p, y[i]));
    fputs("</g>\n", f);
}
