/* nomo.c: inverse planning from a simulated nomogram (see nomo.h and lri-nomogram(1)). */
#define _GNU_SOURCE /* qsort_r */
#include "nomo.h"

#include "curv.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

enum { C_EYE, C_AGE, C_CYL, C_AXIS, C_INC, C_ARC, C_DEPTH, C_DIAM, C_SIA, C_SIAAX, C_N };
static const char *const col_name[C_N] = {"eye", "age_y", "cyl_pre_D", "axis_deg", "incisions",
                                          "arc_deg", "depth", "diameter_mm", "sia_D", "sia_axis_deg"};

/* Split line (modified in place) at tabs into at most max fields; returns the count and the
 * 1-based column of each field in colno. */
static int split_tabs(char *line, char **f, int *colno, int max)
{
    int n = 0;
    char *p = line;
    while (n < max) {
        f[n] = p;
        colno[n] = (int)(p - line) + 1;
        n++;
        char *t = strchr(p, '\t');
        if (!t) break;
        *t = '\0';
        p = t + 1;
    }
    return n;
}

/* The optional column: the SIA's first-order sd (tables written before issue 21 have none). */
#define C_SIASD_NAME "sia_sd_D"

static int read_header(char *line, int *idx, int *idx_sd, const char *path, kt_err *e)
{
    char *f[256];
    int colno[256];
    int nf = split_tabs(line, f, colno, 256);
    for (int i = 0; i < nf; i++) /* a column named twice: which one is meant? */
        for (int j = 0; j < i; j++)
            if (f[i][0] && strcmp(f[i], f[j]) == 0)
                return kt_fail(e, KT_EINPUT, "%s:1:%d: expected each column once, '%s' is also column %d (at 1:%d)",
                               path, colno[i], f[i], j + 1, colno[j]);
    *idx_sd = -1;
    for (int i = 0; i < nf; i++)
        if (strcmp(f[i], C_SIASD_NAME) == 0) *idx_sd = i;
    for (int c = 0; c < C_N; c++) {
        idx[c] = -1;
        for (int i = 0; i < nf; i++)
            if (strcmp(f[i], col_name[c]) == 0) idx[c] = i;
        if (idx[c] < 0)
            return kt_fail(e, KT_EINPUT, "%s:1:1: expected a header with column %s", path,
                           col_name[c]);
    }
    return KT_OK;
}

static int parse_case(char *line, int lineno, const int *idx, int idx_sd, kt_nomo_case *k, const char *path,
                      kt_err *e)
{
    char *f[256];
    int colno[256];
    int nf = split_tabs(line, f, colno, 256);
    double *num[C_N] = {NULL, &k->age, &k->cyl_pre, &k->axis, NULL, &k->arc, &k->depth,
                        &k->diameter, &k->sia, &k->sia_axis};
    for (int c = 0; c < C_N; c++) {
        int i = idx[c];
        if (i >= nf)
            return kt_fail(e, KT_EINPUT, "%s:%d:%zu: expected column %s", path, lineno,
                           strlen(line) + 1, col_name[c]);
        if (c == C_EYE) {
            if (strlen(f[i]) >= sizeof k->eye || f[i][0] == '\0')
                return kt_fail(e, KT_EINPUT, "%s:%d:%d: expected an eye name of 1-63 characters",
                               path, lineno, colno[i]);
            strcpy(k->eye, f[i]);
        } else if (c == C_INC) {
            if (kt_parse_int(f[i], &k->incisions) || (k->incisions != 1 && k->incisions != 2))
                return kt_fail(e, KT_EINPUT, "%s:%d:%d: expected incisions 1 or 2", path, lineno,
                               colno[i]);
        } else if (kt_parse_double(f[i], num[c]) || !isfinite(*num[c])) {
            return kt_fail(e, KT_EINPUT, "%s:%d:%d: expected a number in column %s", path, lineno,
                           colno[i], col_name[c]);
        }
    }
    k->sia_sd = NAN;
    if (idx_sd >= 0) {
        if (idx_sd >= nf)
            return kt_fail(e, KT_EINPUT, "%s:%d:%zu: expected column %s", path, lineno, strlen(line) + 1, C_SIASD_NAME);
        if (kt_parse_double(f[idx_sd], &k->sia_sd) || !(isnan(k->sia_sd) || (k->sia_sd >= 0 && isfinite(k->sia_sd))))
            return kt_fail(e, KT_EINPUT, "%s:%d:%d: expected a number >= 0 or NaN in column %s", path, lineno,
                           colno[idx_sd], C_SIASD_NAME);
    }
    k->line = lineno;
    if (!(k->arc > 0) || !(k->sia >= 0) || !(k->depth > 0) || !(k->diameter > 0))
        return kt_fail(e, KT_EINPUT, "%s:%d:1: expected arc, depth and diameter > 0 and SIA >= 0",
                       path, lineno);
    return KT_OK;
}

/* The same simulated eye: every defining column of an eye equal (kt_nomo_read). */
static int same_eye(const kt_nomo_case *a, const kt_nomo_case *b)
{
    return strcmp(a->eye, b->eye) == 0 && a->age == b->age && a->cyl_pre == b->cyl_pre && a->axis == b->axis;
}

/* Cases ordered by all their defining columns: the eye's, then incisions, arc, depth, diameter
 * (0: the same case), then by line. */
static int key_order(const kt_nomo_case *a, const kt_nomo_case *b)
{
    int s = strcmp(a->eye, b->eye);
    if (s) return s;
    double d[7] = {a->age - b->age, a->cyl_pre - b->cyl_pre, a->axis - b->axis, a->incisions - b->incisions,
                   a->arc - b->arc, a->depth - b->depth, a->diameter - b->diameter};
    for (int i = 0; i < 7; i++)
        if (d[i] != 0) return d[i] < 0 ? -1 : 1;
    return 0;
}

static int cmp_case(const void *pa, const void *pb, void *ctx)
{
    const kt_nomo_case *c = ctx, *a = &c[*(const int *)pa], *b = &c[*(const int *)pb];
    int k = key_order(a, b);
    return k ? k : (a->line > b->line) - (a->line < b->line);
}

/* Each case once: the later line of a repeated case is refused, naming the earlier. */
static int check_unique(const kt_nomo *t, const char *path, kt_err *e)
{
    int *ix = kt_calloc((size_t)t->n, sizeof *ix, e);
    if (!ix) return e->code;
    for (int i = 0; i < t->n; i++) ix[i] = i;
    qsort_r(ix, (size_t)t->n, sizeof *ix, cmp_case, t->c);
    for (int i = 1; i < t->n && !e->code; i++) {
        const kt_nomo_case *a = &t->c[ix[i - 1]], *b = &t->c[ix[i]]; /* a->line < b->line when equal */
        if (key_order(a, b) == 0)
            kt_fail(e, KT_EINPUT, "%s:%d:1: expected each case once: this row repeats line %d (eye %s, age %g y, "
                    "cylinder %g D @ %g deg, %d incision%s of %g deg, depth %g, diameter %g mm)", path, b->line, a->line,
                    a->eye, a->age, a->cyl_pre, a->axis, a->incisions, a->incisions == 1 ? "" : "s", a->arc, a->depth,
                    a->diameter);
    }
    free(ix);
    return e->code;
}

int kt_nomo_read(kt_nomo *t, const char *path, kt_err *e)
{
    memset(t, 0, sizeof *t);
    FILE *in = fopen(path, "r");
    if (!in) return kt_fail(e, KT_EINPUT, "%s: cannot open the nomogram table: %s", path, strerror(errno));
    struct stat st;
    if (fstat(fileno(in), &st) == 0 && S_ISDIR(st.st_mode)) {
        fclose(in);
        return kt_fail(e, KT_EINPUT, "%s: cannot read the nomogram table: is a directory", path);
    }
    char *line = NULL;
    size_t cap = 0;
    long len;
    int idx[C_N], idx_sd = -1, lineno = 0, rc = KT_OK, cap_c = 0;
    while ((len = kt_line_read(in, &line, &cap, KT_NOMO_MAX_LINE, e)) >= 0) {
        lineno++;
        while (len > 0 && (line[len - 1] == '\n' || line[len - 1] == '\r')) line[--len] = '\0';
        if (lineno == 1) {
            char *h = strncmp(line, "\xef\xbb\xbf", 3) == 0 ? line + 3 : line; /* UTF-8 BOM */
            if ((rc = read_header(h, idx, &idx_sd, path, e))) break;
            continue;
        }
        if (len == 0) continue;
        if (t->n == KT_NOMO_MAX_CASES) {
            rc = kt_fail(e, KT_EINPUT, "%s:%d:1: expected at most %d cases", path, lineno,
                         KT_NOMO_MAX_CASES);
            break;
        }
        if (t->n == cap_c) {
            int nc = cap_c ? 2 * cap_c : 64;
            kt_nomo_case *p = kt_realloc(t->c, (size_t)nc, sizeof *p, e);
            if (!p) { rc = KT_ERUN; break; }
            t->c = p;
            cap_c = nc;
        }
        if ((rc = parse_case(line, lineno, idx, idx_sd, &t->c[t->n], path, e))) break;
        t->n++;
    }
    if (rc == KT_OK && len == -4) rc = e->code;
    if (rc == KT_OK && len == -2)
        rc = kt_fail(e, KT_EINPUT, "%s:%d: expected text, found a NUL byte", path, lineno + 1);
    if (rc == KT_OK && len == -3)
        rc = kt_fail(e, KT_EINPUT, "%s:%d: expected a line of at most %d bytes", path, lineno + 1,
                     KT_NOMO_MAX_LINE);
    if (rc == KT_OK && ferror(in))
        rc = kt_fail(e, KT_EINPUT, "%s: read error: %s", path, strerror(errno));
    free(line);
    fclose(in);
    if (rc == KT_OK && lineno == 0) rc = kt_fail(e, KT_EINPUT, "%s:1:1: expected a header, found an empty file", path);
    if (rc == KT_OK && t->n == 0) rc = kt_fail(e, KT_EINPUT, "%s:2:1: expected a case", path);
    if (rc == KT_OK) rc = check_unique(t, path, e);
    if (rc) kt_nomo_free(t);
    return rc;
}

void kt_nomo_free(kt_nomo *t)
{
    free(t->c);
    t->c = NULL;
    t->n = 0;
}

/* Whether case k is in the selection (count, depth, diameter). */
static int selected(const kt_nomo_case *k, int n, double depth, double diameter)
{
    return k->incisions == n && fabs(k->depth - depth) < 1e-9 && fabs(k->diameter - diameter) < 1e-9;
}

/* The SIA of eye's selected cases at arc, linear between simulated arcs, 0 at arc 0; NAN beyond
 * the longest. *near gets the simulated case nearest in arc; *sd (when not NULL) the SIA's sd
 * interpolated the same way (NAN when a case used has none). */
static double sia_at_sd(const kt_nomo *t, const kt_nomo_case *eye, int n, double depth, double diameter,
                        double arc, const kt_nomo_case **near, double *sd, const kt_nomo_case **used)
{
    const kt_nomo_case *lo = NULL, *hi = NULL;
    *near = NULL;
    if (sd) *sd = NAN;
    for (int i = 0; i < t->n; i++) {
        const kt_nomo_case *k = &t->c[i];
        if (!same_eye(k, eye) || !selected(k, n, depth, diameter)) continue;
        if (k->arc <= arc && (!lo || k->arc > lo->arc)) lo = k;
        if (k->arc >= arc && (!hi || k->arc < hi->arc)) hi = k;
        if (!*near || fabs(k->arc - arc) < fabs((*near)->arc - arc)) *near = k;
    }
    if (used) used[0] = lo, used[1] = hi;
    if (!hi) return NAN;
    double a0 = lo ? lo->arc : 0, s0 = lo ? lo->sia : 0, d0 = lo ? lo->sia_sd : 0;
    if (hi->arc == a0) {
        if (sd) *sd = hi->sia_sd;
        return hi->sia;
    }
    double w = (arc - a0) / (hi->arc - a0);
    if (sd) *sd = d0 + (hi->sia_sd - d0) * w;
    return s0 + (hi->sia - s0) * w;
}

static double sia_at(const kt_nomo *t, const kt_nomo_case *eye, int n, double depth, double diameter,
                     double arc, const kt_nomo_case **near)
{
    return sia_at_sd(t, eye, n, depth, diameter, arc, near, NULL, NULL);
}

/* Whether case k's eye is nearer cylinder cyl than case o's; between two as near, the first in
 * the order of the defining columns (key_order), so that the answer does not depend on the
 * table's row order. */
static int nearer(const kt_nomo_case *k, const kt_nomo_case *o, double cyl)
{
    double dk = fabs(k->cyl_pre - cyl), dof = fabs(o->cyl_pre - cyl);
    return dk < dof || (dk == dof && key_order(k, o) < 0);
}

/* For each simulated age: the eye of that age whose cylinder is nearest cyl among the
 * selection. Then the ages bracketing age (clamped to the range): eyes lo/hi, weight w of hi. */
static int pick_eyes(const kt_nomo *t, int n, double depth, double diameter, double cyl,
                     double age, const kt_nomo_case **elo, const kt_nomo_case **ehi, double *w)
{
    *elo = *ehi = NULL;
    for (int i = 0; i < t->n; i++) {
        const kt_nomo_case *k = &t->c[i];
        if (!selected(k, n, depth, diameter)) continue;
        const kt_nomo_case **slot = NULL;
        if (k->age <= age && (!*elo || k->age >= (*elo)->age)) slot = elo;
        if (slot && *slot && k->age == (*slot)->age && !nearer(k, *slot, cyl)) slot = NULL;
        if (slot) *slot = k;
        slot = NULL;
        if (k->age >= age && (!*ehi || k->age <= (*ehi)->age)) slot = ehi;
        if (slot && *slot && k->age == (*slot)->age && !nearer(k, *slot, cyl)) slot = NULL;
        if (slot) *slot = k;
    }
    if (!*elo && !*ehi) return 0;
    if (!*elo) *elo = *ehi;
    if (!*ehi) *ehi = *elo;
    *w = (*ehi)->age > (*elo)->age ? (age - (*elo)->age) / ((*ehi)->age - (*elo)->age) : 0;
    return 1;
}

/* The selection's simulated arcs of eye, ascending, into arcs (at most max); returns the count. */
static int eye_arcs(const kt_nomo *t, const kt_nomo_case *eye, int n, double depth, double diameter,
                    double *arcs, int max)
{
    int m = 0;
    for (int i = 0; i < t->n; i++) {
        const kt_nomo_case *k = &t->c[i];
        if (!same_eye(k, eye) || !selected(k, n, depth, diameter)) continue;
        int j = m;
        if (m == max) break;
        while (j > 0 && arcs[j - 1] > k->arc) { arcs[j] = arcs[j - 1]; j--; }
        if (j > 0 && arcs[j - 1] == k->arc) { memmove(arcs + j, arcs + j + 1, (size_t)(m - j) * sizeof *arcs); continue; }
        arcs[j] = k->arc;
        m++;
    }
    return m;
}

/* The double-angle sum of two astigmatisms (magnitude, axis in deg) into *mag, *ax; no axis
 * (0) for a vanishing sum. */
static void astig_add(double m1, double a1, double m2, double a2, double *mag, double *ax)
{
    double p[2], q[2];
    kt_astig_xy((kt_astig){m1, a1}, p);
    kt_astig_xy((kt_astig){m2, a2}, q);
    kt_astig sum = kt_astig_from_xy(p[0] + q[0], p[1] + q[1]);
    *mag = sum.mag;
    *ax = sum.mag > 1e-9 ? sum.axis : 0;
}

double kt_nomo_pre(const kt_nomo_query *q, double *axis)
{
    double mag, ax;
    astig_add(q->k_steep - q->k_flat, q->axis, q->main_sia, q->main_axis, &mag, &ax);
    if (mag <= 1e-9) ax = q->axis;
    *axis = fmod(fmod(ax, 180) + 180, 180);
    return mag;
}

void kt_nomo_ages(const kt_nomo *t, double *lo, double *hi)
{
    *lo = INFINITY, *hi = -INFINITY;
    for (int i = 0; i < t->n; i++) *lo = fmin(*lo, t->c[i].age), *hi = fmax(*hi, t->c[i].age);
}

/* The answer's band (nomo.h): the SIA's sd at the arc, from both ages' eyes, and the residual's. */
static void band(const kt_nomo *t, const kt_nomo_query *q, int n, double depth, double diameter,
                 const kt_nomo_case *elo, const kt_nomo_case *ehi, double w, double cyl, double axis,
                 double sia_axis, kt_nomo_answer *a)
{
    const kt_nomo_case *near;
    double sd_lo, sd_hi;
    (void)q;
    a->sia_sd = a->residual_sd = a->residual_lo90 = a->residual_hi90 = NAN;
    sia_at_sd(t, elo, n, depth, diameter, a->arc, &near, &sd_lo, NULL);
    sia_at_sd(t, ehi, n, depth, diameter, a->arc, &near, &sd_hi, NULL);
    double sd = (1 - w) * sd_lo + w * sd_hi;
    if (!(sd >= 0)) return; /* NAN: the table (or a case used) has no sd */
    a->sia_sd = sd;
    /* d|pre + S| / dS along the SIA's double-angle direction: the cosine between the residual's
     * vector and the SIA's; below KT_NOMO_RES_DIR the residual's direction is round-off, and the
     * residual moves through zero along the pre-operative astigmatism: its cosine with the SIA. */
    double p[2], s[2];
    kt_astig_xy((kt_astig){cyl, axis}, p);
    kt_astig_xy((kt_astig){1, sia_axis}, s);
    double rx = p[0] + a->sia * s[0], ry = p[1] + a->sia * s[1], r = hypot(rx, ry), pn = hypot(p[0], p[1]);
    double d = r > KT_NOMO_RES_DIR ? fabs(rx * s[0] + ry * s[1]) / r : pn > 0 ? fabs(p[0] * s[0] + p[1] * s[1]) / pn : 1;
    a->residual_sd = d * sd;
    a->residual_lo90 = fmax(0, a->residual - KT_NOMO_Z90 * a->residual_sd);
    a->residual_hi90 = a->residual + KT_NOMO_Z90 * a->residual_sd;
}

static void answer_one(const kt_nomo *t, const kt_nomo_query *q, int n, double depth,
                       double diameter, kt_nomo_answer *a)
{
    const kt_nomo_case *elo, *ehi, *near;
    double w, axis, cyl = kt_nomo_pre(q, &axis);
    memset(a, 0, sizeof *a);
    if (!pick_eyes(t, n, depth, diameter, cyl, q->age, &elo, &ehi, &w)) return;
    double arcs[512];
    int m = eye_arcs(t, elo, n, depth, diameter, arcs, 512);
    a->incisions = n;
    a->depth = depth;
    a->diameter = diameter;
    a->age_lo = elo->age;
    a->age_hi = ehi->age;
    double prev_arc = 0, prev_sia = 0;
    a->arc = a->arc_lo = a->arc_hi = 0;
    for (int i = 0; i < m; i++) {
        double s = (1 - w) * sia_at(t, elo, n, depth, diameter, arcs[i], &near) +
                   w * sia_at(t, ehi, n, depth, diameter, arcs[i], &near);
        if (isnan(s)) break; /* beyond the longest arc of the other age */
        if (s >= q->target) {
            a->reached = 1;
            a->arc_lo = prev_arc;
            a->arc_hi = arcs[i];
            a->arc = s > prev_sia ? prev_arc + (arcs[i] - prev_arc) * (q->target - prev_sia) / (s - prev_sia)
                                  : arcs[i];
            if (a->arc == arcs[i]) a->arc_lo = arcs[i];
            a->sia = q->target;
            break;
        }
        prev_arc = a->arc = a->arc_lo = a->arc_hi = arcs[i];
        prev_sia = a->sia = s;
    }
    /* the SIA's axis relative to the incised meridian, from the nearest simulated case */
    const kt_nomo_case *used[2][2];
    sia_at_sd(t, ehi, n, depth, diameter, a->arc, &near, NULL, used[1]);
    sia_at_sd(t, elo, n, depth, diameter, a->arc, &near, NULL, used[0]);
    for (int g = 0; g < 2; g++)
        for (int b = 0; b < 2; b++) a->rows[g][b] = used[g][b] ? used[g][b]->line : 0;
    double sia_axis = near ? axis + (near->sia_axis - near->axis) : axis + 90;
    astig_add(cyl, axis, a->sia, sia_axis, &a->residual, &a->residual_axis);
    band(t, q, n, depth, diameter, elo, ehi, w, cyl, axis, sia_axis, a);
}

int kt_nomo_plan(const kt_nomo *t, const kt_nomo_query *q, kt_nomo_answer ans[2], kt_err *e)
{
    if (!(q->k_steep >= q->k_flat) || !(q->k_flat > 0))
        return kt_fail(e, KT_EINPUT, "expected K steep >= K flat > 0 D");
    if (!(q->axis >= 0 && q->axis < 180)) return kt_fail(e, KT_EINPUT, "expected an axis in [0, 180) deg");
    if (!(q->age > 0 && q->age < 150)) return kt_fail(e, KT_EINPUT, "expected an age in years");
    if (!(q->target >= 0)) return kt_fail(e, KT_EINPUT, "expected a target >= 0 D");
    /* depth: the query's or the deepest; diameter: the query's or the most frequent */
    double depth = q->depth, diameter = q->diameter;
    if (!(depth > 0))
        for (int i = 0; i < t->n; i++) depth = fmax(depth, t->c[i].depth);
    if (!(diameter > 0)) {
        int best = 0;
        for (int i = 0; i < t->n; i++) {
            int cnt = 0;
            for (int j = 0; j < t->n; j++) cnt += fabs(t->c[j].diameter - t->c[i].diameter) < 1e-9;
            if (cnt > best) { best = cnt; diameter = t->c[i].diameter; }
        }
    }
    for (int n = 1; n <= 2; n++) answer_one(t, q, n, depth, diameter, &ans[n - 1]);
    if (!ans[0].incisions && !ans[1].incisions)
        return kt_fail(e, KT_EINPUT, "the nomogram has no case at depth %g and diameter %g mm",
                       depth, diameter);
    return KT_OK;
}
