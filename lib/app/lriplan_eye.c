/* lriplan_eye.c: plan.html's drawing of the eye (lriplan_eye.h). */
#include "lriplan_eye.h"

#include <math.h>
#include <stdarg.h>
#include <string.h>

#include "svg.h"

#define DEG (3.14159265358979323846 / 180)
#define W 520.0   /* the square drawing, px */
#define C 260.0   /* its centre */
#define R_EYE 185.0 /* the white-to-white circle, px */

const char *kt_lri_view_name(int view)
{
    return view == KT_LRI_VIEW_SUPERIOR ? "superior" : view == KT_LRI_VIEW_EXAMINER ? "examiner" : "temporal";
}

const char *kt_lri_view_words(int view)
{
    return view == KT_LRI_VIEW_SUPERIOR   ? "the surgeon seated superior (at the patient's head): superior at the bottom"
           : view == KT_LRI_VIEW_EXAMINER ? "the examiner facing the patient: superior at the top"
                                          : "the surgeon seated temporal: the temporal limbus at the bottom";
}

double kt_lri_view_turn(int view, int eye)
{
    if (view == KT_LRI_VIEW_EXAMINER) return 0;
    if (view == KT_LRI_VIEW_SUPERIOR) return 180;
    return eye == KT_EYE_OS ? 270 : 90; /* temporal: 180 deg in OD, 0 deg in OS, put at 270 */
}

/* DejaVu Sans advance widths, em (rounded up): digits 0.636, space 0.318, '.' ':' 0.337,
 * '(' ')' 0.39, capitals up to 0.78, lower case up to 0.61 (m 0.974), the degree sign 0.5. */
static double advance(const unsigned char *s, int *len)
{
    *len = 1;
    if (*s >= 0xC0) { /* a UTF-8 sequence: the degree sign and its like */
        while ((s[*len] & 0xC0) == 0x80) ++*len;
        return 0.5;
    }
    if (*s >= '0' && *s <= '9') return 0.64;
    if (*s == ' ') return 0.32;
    if (*s == '.' || *s == ':' || *s == ',') return 0.34;
    if (*s == '(' || *s == ')' || *s == '-') return 0.4;
    if (*s == 'm' || *s == 'w') return 0.98;
    if (*s == 'M' || *s == 'W') return 1.0;
    if (*s >= 'A' && *s <= 'Z') return 0.78;
    return 0.62;
}

kt_lri_box kt_lri_text_box(const char *s, double fs, int bold, double x, double y, char anchor)
{
    double w = 0;
    for (const unsigned char *c = (const unsigned char *)s; *c;) {
        int len;
        w += advance(c, &len);
        c += len;
    }
    w *= fs * (bold ? 1.12 : 1.0);
    double x0 = anchor == 'm' ? x - w / 2 : anchor == 'e' ? x - w : x;
    kt_lri_box b = {x0 - 1, y - 0.95 * fs, x0 + w + 1, y + 0.25 * fs}; /* ascent 0.93, descent 0.24 */
    return b;
}

int kt_lri_box_meet(const kt_lri_box *a, const kt_lri_box *b)
{
    return a->x0 < b->x1 && b->x0 < a->x1 && a->y0 < b->y1 && b->y0 < a->y1;
}

/* A label's class: its font size and weight (lib/io/html.c's CSS). */
typedef struct style {
    const char *cls;
    double fs;
    int bold;
} style;
static const style TICK = {"tick", 11, 0}, CLOCK = {"clock", 13, 1}, NSTI = {"nsti", 15, 1}, LBL = {"lbl halo", 12, 0},
                   SMALL = {"small", 10, 0}, BIG = {"eyebig", 24, 1};

static int free_at(const kt_lri_labels *lab, const kt_lri_box *b)
{
    if (b->x0 < 0 || b->y0 < 0 || b->x1 > W || b->y1 > W) return 0;
    for (int i = 0; i < lab->n; i++)
        if (kt_lri_box_meet(&lab->b[i], b)) return 0;
    return 1;
}

static void emit(FILE *f, kt_lri_labels *lab, const style *st, double x, double y, char anchor, const char *s)
{
    if (lab->n < KT_LRI_MAXLABEL) {
        lab->b[lab->n] = kt_lri_text_box(s, st->fs, st->bold, x, y, anchor);
        snprintf(lab->text[lab->n], sizeof lab->text[0], "%s", s);
        lab->n++;
    }
    kt_svg_text(f, x, y, anchor == 'm' ? "middle" : anchor == 'e' ? "end" : "start", st->cls, "%s", s);
}

/* Where a label centred on the screen direction `ang` (deg) goes: the first radius of rad[]
 * (then the next, then turned by 4 deg steps either way) where its box meets no other; its
 * baseline in (*x, *y) (the first candidate when there is no room: the tests say so). */
static void spot(const kt_lri_labels *lab, const style *st, const double *rad, int nrad, double ang, const char *s,
                 double *x, double *y)
{
    for (int j = 0; j < 45; j++) {
        double a = ang + 4 * ((j + 1) / 2) * (j % 2 ? 1 : -1);
        for (int i = 0; i < nrad; i++) {
            *x = C + rad[i] * cos(a * DEG), *y = C - rad[i] * sin(a * DEG) + 0.35 * st->fs;
            kt_lri_box b = kt_lri_text_box(s, st->fs, st->bold, *x, *y, 'm');
            if (free_at(lab, &b)) return;
        }
    }
    *x = C + rad[0] * cos(ang * DEG), *y = C - rad[0] * sin(ang * DEG) + 0.35 * st->fs;
}

static void place(FILE *f, kt_lri_labels *lab, const style *st, const double *rad, int nrad, double ang, const char *s)
{
    double x, y;
    spot(lab, st, rad, nrad, ang, s, &x, &y);
    emit(f, lab, st, x, y, 'm', s);
}

static void frame(FILE *f, const kt_patient *p, double turn, kt_lri_labels *lab)
{
    char s[48];
    int os = p->eye == KT_EYE_OS;
    for (int t = 0; t < 180; t += 30) {
        double a = (t + turn) * DEG;
        kt_svg_line(f, C + 196 * cos(a), C - 196 * sin(a), C - 196 * cos(a), C + 196 * sin(a), "merid");
    }
    for (int t = 0; t < 360; t += 30) { /* TABO degrees inside, clock hours outside */
        double a = (t + turn) * DEG;
        snprintf(s, sizeof s, "%d\xC2\xB0", t);
        emit(f, lab, &TICK, C + 206 * cos(a), C - 206 * sin(a) + 4, 'm', s);
        int h = ((3 - t / 30) % 12 + 12) % 12;
        snprintf(s, sizeof s, "%d", h ? h : 12);
        emit(f, lab, &CLOCK, C + 238 * cos(a), C - 238 * sin(a) + 5, 'm', s);
    }
    emit(f, lab, &BIG, 8, 30, 'l', os ? "OS" : "OD");
    emit(f, lab, &SMALL, 8, 46, 'l', os ? "left eye" : "right eye");
    static const double RS[] = {222, 252};
    const char *nsti[4] = {"S", "I", os ? "T" : "N", os ? "N" : "T"};
    const double at[4] = {90, 270, 0, 180};
    for (int i = 0; i < 4; i++) place(f, lab, &NSTI, RS, 2, at[i] + turn + 15, nsti[i]);
}

static void arcs_svg(FILE *f, const kt_patient *p, const kt_lp_arc *arcs, int narc, double turn, double s,
                     kt_lri_labels *lab)
{
    double r = 0.5 * p->zone * s;
    for (int i = 0; i < narc; i++) /* the arcs first, under their end points and labels */
        kt_svg_arc(f, C, C, r, arcs[i].to + turn, arcs[i].to + turn + arcs[i].arc, "inc");
    const double RL[] = {r - 34, r - 54, r - 74, r - 94, r + 30};
    for (int i = 0; i < narc; i++) {
        const kt_lp_arc *q = &arcs[i];
        for (int k = 0; k < 2; k++) {
            double e = (k ? q->to : q->from) + turn, ex = C + r * cos(e * DEG), ey = C - r * sin(e * DEG), lx, ly;
            char t[48];
            snprintf(t, sizeof t, "%s%s %.0f\xC2\xB0 (%s)", narc > 1 ? (i ? "2 " : "1 ") : "", k ? "to" : "from",
                     kt_lp_deg_mark(k ? q->to : q->from), k ? q->to_clock : q->from_clock);
            spot(lab, &LBL, RL, 5, e, t, &lx, &ly);
            kt_svg_line(f, ex, ey, lx, ly - 0.35 * LBL.fs, "leader");
            kt_svg_circle(f, ex, ey, 4, "end");
            emit(f, lab, &LBL, lx, ly, 'm', t);
        }
    }
}

void kt_lri_eye_svg(FILE *f, const kt_patient *p, const kt_lp_arc *arcs, int narc, int view, kt_lri_labels *lab)
{
    double turn = kt_lri_view_turn(view, p->eye), s = R_EYE / (0.5 * p->wtw); /* px per mm */
    lab->n = 0;
    kt_svg_begin(f, W, W, "the plan on the eye");
    fprintf(f, "<rect class=\"sclera\" x=\"0\" y=\"0\" width=\"%.0f\" height=\"%.0f\"/>\n", W, W);
    kt_svg_circle(f, C, C, R_EYE, "cornea");
    kt_svg_circle(f, C, C, 0.5 * p->zone * s, "ring");
    double ax = (p->ant.axis + turn) * DEG;
    kt_svg_line(f, C + 190 * cos(ax), C - 190 * sin(ax), C - 190 * cos(ax), C + 190 * sin(ax), "steep");
    frame(f, p, turn, lab);
    char v[48];
    snprintf(v, sizeof v, "view: %s", kt_lri_view_name(view));
    emit(f, lab, &SMALL, W - 8, 16, 'e', v);
    kt_svg_line(f, W - 16 - 5 * s, W - 22, W - 16, W - 22, "bar");
    emit(f, lab, &SMALL, W - 16 - 2.5 * s, W - 30, 'm', "5 mm");
    if (p->main_present) {
        /* The main incision at the limbus: its width as an arc just inside white-to-white. */
        double r = 0.5 * p->wtw - 0.3, half = 0.5 * p->main_width / r / DEG, m = p->main_meridian + turn;
        kt_svg_arc(f, C, C, r * s, m - half, m + half, "main");
        char t[48];
        snprintf(t, sizeof t, "main %.1f mm", p->main_width);
        const double RM[] = {(r - 1.0) * s, (r - 1.6) * s, (r - 2.2) * s};
        place(f, lab, &LBL, RM, 3, m, t);
    }
    arcs_svg(f, p, arcs, narc, turn, s, lab);
    kt_svg_line(f, C - 5, C, C + 5, C, "zero");
    kt_svg_line(f, C, C - 5, C, C + 5, "zero");
    kt_svg_end(f);
}
