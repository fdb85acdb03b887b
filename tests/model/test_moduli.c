/* test_moduli.c: the rate argument of keratome-scene(5) ("Rate: which moduli a slowly opening
 * wound sees") holds together and is what keratome uses. From the inputs of its table (the
 * in vivo shear modulus and its frequency, the IOP and the cornea's radius and thickness, the
 * loss ratio, the wound's timescale) the test recomputes the membrane prestress, the rate
 * exponent, the wound's frequency, the wound's shear modulus G_w and the alternatives; each
 * printed number must be the recomputed one to its last printed digit. G_w and E_w must be the
 * built-in defaults of the eye's cornea and limbus and the values of plans/eye.yaml, and
 * docs/moduli.md must carry the same table. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "kt_test.h"
#include "scene.h"

#define NROW 32
typedef struct row {
    char sym[32], text[32], unit[16];
    double v; /* in MPa, mm, s, Hz or none */
} row;
typedef struct table {
    int n;
    row r[NROW];
} table;

static double unit_factor(const char *u)
{
    static const struct { const char *u; double f; } U[] = {
        {"kPa", 1e-3}, {"MPa", 1}, {"mmHg", 133.322387415e-6}, {"mm", 1}, {"s", 1}, {"Hz", 1},
        {"-", 1}, {"\\-", 1}};
    for (size_t i = 0; i < sizeof U / sizeof U[0]; i++)
        if (strcmp(u, U[i].u) == 0) return U[i].f;
    return NAN;
}

/* Half a unit in the last printed digit of text (relative to the unit's value). */
static double half_ulp(const char *text)
{
    const char *dot = strchr(text, '.'), *ex = strpbrk(text, "eE");
    int dec = 0;
    if (dot)
        for (const char *c = dot + 1; *c >= '0' && *c <= '9'; c++) dec++;
    int exp10 = ex ? atoi(ex + 1) : 0;
    return 0.5 * pow(10.0, exp10 - dec) * (1 + 1e-9);
}

/* Add the row "sym value unit" (fields already split); 0 on a malformed row. */
static int add_row(table *t, const char *sym, const char *val, const char *unit)
{
    if (t->n >= NROW) return 0;
    row *r = &t->r[t->n];
    char *end;
    double x = strtod(val, &end);
    if (end == val || *end || !isfinite(unit_factor(unit))) return 0;
    snprintf(r->sym, sizeof r->sym, "%s", sym);
    snprintf(r->text, sizeof r->text, "%s", val);
    snprintf(r->unit, sizeof r->unit, "%s", unit);
    r->v = x * unit_factor(unit);
    t->n++;
    return 1;
}

static const row *find(const table *t, const char *sym)
{
    for (int i = 0; i < t->n; i++)
        if (strcmp(t->r[i].sym, sym) == 0) return &t->r[i];
    return NULL;
}

/* The tbl rows after the man page's ".\" rate-table" comment, up to .TE. */
static int read_man(const char *path, table *t)
{
    FILE *f = fopen(path, "r");
    if (!f) return 0;
    char line[512];
    int in = 0, bad = 0;
    while (fgets(line, sizeof line, f)) {
        line[strcspn(line, "\n")] = 0;
        if (strncmp(line, ".\\\" rate-table", 14) == 0) in = 1;
        else if (in && strcmp(line, ".TE") == 0) break;
        else if (in && strchr(line, '\t')) {
            char *f1 = strtok(line, "\t"), *f2 = strtok(NULL, "\t"), *f3 = strtok(NULL, "\t");
            if (!f1 || !f2 || !f3 || !add_row(t, f1, f2, f3)) bad++;
        }
    }
    fclose(f);
    return in && !bad;
}

/* The markdown rows "| sym | value | unit | ... |" of docs/moduli.md's rate table. */
static int read_md(const char *path, table *t)
{
    FILE *f = fopen(path, "r");
    if (!f) return 0;
    char line[512];
    while (fgets(line, sizeof line, f)) {
        char sym[32], val[32], unit[16];
        if (sscanf(line, "| `%31[^`]` | %31[^ |] | %15[^ |] |", sym, val, unit) == 3)
            add_row(t, sym, val, unit);
    }
    fclose(f);
    return t->n > 0;
}

/* The printed value of sym equals want to its last printed digit. */
static void check_printed(const table *t, const char *sym, double want)
{
    const row *r = find(t, sym);
    CHECK(r != NULL, "row %s missing", sym);
    if (!r) return;
    double got = r->v / unit_factor(r->unit), w = want / unit_factor(r->unit);
    CHECK(fabs(got - w) <= half_ulp(r->text), "%s printed %s %s, recomputed %.6g", sym, r->text,
          r->unit, w);
}

static double val(const table *t, const char *sym)
{
    const row *r = find(t, sym);
    CHECK(r != NULL, "row %s missing", sym);
    return r ? r->v : NAN;
}

int main(void)
{
    table man = {0}, md = {0};
    CHECK(read_man("man/man5/keratome-scene.5", &man), "keratome-scene(5): no well-formed rate table");
    CHECK(read_md("docs/moduli.md", &md), "docs/moduli.md: no rate table");
    double G = val(&man, "G_oce"), f = val(&man, "f_oce"), p = val(&man, "p");
    double R = val(&man, "R"), th = val(&man, "t"), td = val(&man, "tan_delta");
    double tw = val(&man, "t_w"), Gtor = val(&man, "G_tor");
    double sm = p * R / (2 * th), a = 2 / KT_PI * atan(td), fw = 1 / (2 * KT_PI * tw);
    double Gw = (G - sm) * pow(fw / f, a);
    check_printed(&man, "sigma_m", sm);
    check_printed(&man, "alpha", a);
    check_printed(&man, "f_w", fw);
    check_printed(&man, "G_w", Gw);
    check_printed(&man, "G_1h", (G - sm) * pow(1 / (2 * KT_PI * 3600) / f, a));
    check_printed(&man, "G_1w", (G - sm) * pow(1 / (2 * KT_PI * 7 * 86400) / f, a));
    check_printed(&man, "G_30d", (G - sm) * pow(1 / (2 * KT_PI * 30 * 86400) / f, a));
    check_printed(&man, "G_tor_w", Gtor * pow(fw / 1.0, a));
    CHECK(fabs(tw - 86400) < 1e-9, "t_w %g s: the text says 1 day", tw);
    /* docs/moduli.md: the same rows, printed alike */
    for (int i = 0; i < man.n; i++) {
        const row *r = find(&md, man.r[i].sym);
        CHECK(r && strcmp(r->text, man.r[i].text) == 0 && unit_factor(r->unit) == unit_factor(man.r[i].unit),
              "docs/moduli.md row %s: %s, keratome-scene(5): %s %s", man.r[i].sym, r ? r->text : "missing",
              man.r[i].text, man.r[i].unit);
    }
    /* the defaults: built in (an eye scene without materials) and plans/eye.yaml */
    double Gw_text = val(&man, "G_w"), Ew_text = val(&man, "E_w");
    char dir[] = "/tmp/kt-moduli-XXXXXX", path[64];
    CHECK(mkdtemp(dir) != NULL, "mkdtemp");
    snprintf(path, sizeof path, "%s/eye.yaml", dir);
    FILE *fy = fopen(path, "w");
    CHECK(fy && fputs("model: eye\n", fy) >= 0 && fclose(fy) == 0, "write %s", path);
    const char *scenes[2] = {path, "plans/eye.yaml"};
    for (int k = 0; k < 2; k++) {
        kt_scene s;
        kt_err e = {0};
        CHECK(kt_scene_load(scenes[k], &s, &e) == KT_OK, "%s: %s", scenes[k], e.msg);
        if (e.code) continue;
        int seen = 0;
        for (int i = 0; i < s.nmat; i++) {
            if (strcmp(s.mat[i].region, "cornea") && strcmp(s.mat[i].region, "limbus")) continue;
            seen++;
            CHECK(s.mat[i].fibre, "%s %s: model fibre", scenes[k], s.mat[i].region);
            CHECK(fabs(s.mat[i].Gt - Gw_text) <= 1e-15, "%s %s: G_transverse %.15g MPa, the rate "
                  "argument's G_w %.15g", scenes[k], s.mat[i].region, s.mat[i].Gt, Gw_text);
            CHECK(fabs(s.mat[i].E1 - Ew_text) <= 1e-15 && fabs(s.mat[i].E2 - Ew_text) <= 1e-15,
                  "%s %s: E_inplane %.15g/%.15g MPa, the rate argument's E_w %.15g", scenes[k],
                  s.mat[i].region, s.mat[i].E1, s.mat[i].E2, Ew_text);
        }
        CHECK(seen == 2, "%s: cornea and limbus materials (%d)", scenes[k], seen);
        /* the depth profile is off by default (keratome-scene(5), G_transverse_profile) */
        for (int i = 0; i < s.nmat; i++)
            CHECK(s.mat[i].gt_profile[0] == 0 && kt_gt_profile(&s.mat[i], 0.1) == s.mat[i].Gt,
                  "%s %s: G_transverse_profile is on by default", scenes[k], s.mat[i].region);
    }
    /* G_transverse_profile: on is Petsche 2012's thirds, scaled so the layers in series keep
     * G_transverse: 34.1 / 8.8 / 5.8 kPa at 9.5 kPa, as keratome-scene(5) prints */
    fy = fopen(path, "w");
    CHECK(fy && fputs("model: eye\nmaterials:\n  cornea: {G_transverse_profile: on}\n"
                      "  limbus: {G_transverse_profile: [3 kPa, 2 kPa, 1 kPa]}\n", fy) >= 0 &&
              fclose(fy) == 0, "write %s", path);
    {
        kt_scene s;
        kt_err e = {0};
        CHECK(kt_scene_load(path, &s, &e) == KT_OK, "%s: %s", path, e.msg);
        for (int i = 0; i < s.nmat && !e.code; i++) {
            const kt_region_mat *r = &s.mat[i];
            if (!strcmp(r->region, "sclera")) continue;
            int cornea = !strcmp(r->region, "cornea");
            double g[3] = {cornea ? 7.71e-3 : 3e-3, cornea ? 1.99e-3 : 2e-3, cornea ? 1.31e-3 : 1e-3};
            double depth[3] = {0.1, 0.5, 0.9}, inv = 0;
            for (int k = 0; k < 3; k++) {
                CHECK(fabs(r->gt_profile[k] - g[k]) <= 1e-15, "%s: profile[%d] %g", r->region, k, r->gt_profile[k]);
                inv += 1 / kt_gt_profile(r, depth[k]);
            }
            CHECK(fabs(3 / inv - Gw_text) <= 1e-15, "%s: thirds in series %.15g MPa, not G_transverse",
                  r->region, 3 / inv);
            CHECK(kt_gt_profile(r, NAN) == r->Gt, "%s: no depth (sclera): G_transverse", r->region);
            if (cornea) {
                const double want[3] = {34.1e-3, 8.8e-3, 5.8e-3}; /* as printed, 0.1 kPa */
                for (int k = 0; k < 3; k++)
                    CHECK(fabs(kt_gt_profile(r, depth[k]) - want[k]) <= 0.05e-3, "cornea third %d: %.4g kPa, "
                          "keratome-scene(5) prints %.1f", k, 1e3 * kt_gt_profile(r, depth[k]), 1e3 * want[k]);
            }
        }
    }
    unlink(path);
    rmdir(dir);
    printf("rate argument: sigma_m %.4g kPa, alpha %.4g, f_w %.4g Hz, G_w %.4g kPa (printed %s)\n",
           1e3 * sm, a, fw, 1e3 * Gw, find(&man, "G_w") ? find(&man, "G_w")->text : "-");
    return kt_test_done("test_moduli");
}
