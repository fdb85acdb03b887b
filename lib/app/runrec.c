/* runrec.c: run.yaml's provenance block (runrec.h). */
#define _XOPEN_SOURCE 700
#include <cholmod.h>
#include <inttypes.h>
#include <math.h>
#include <metis.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "runrec.h"
#include "tsv.h"

int kt_runrec_file_hash(const char *path, uint64_t *hash, long *nbytes, kt_err *e)
{
    FILE *f = fopen(path, "rb");
    if (!f) return kt_fail(e, KT_EINPUT, "%s: cannot read", path);
    uint64_t h = 14695981039346656037ULL; /* FNV-1a 64 offset basis */
    long n = 0;
    int c;
    while ((c = getc(f)) != EOF) {
        h = (h ^ (unsigned char)c) * 1099511628211ULL;
        n++;
    }
    int bad = ferror(f);
    fclose(f);
    if (bad) return kt_fail(e, KT_EINPUT, "%s: read error", path);
    *hash = h, *nbytes = n;
    return KT_OK;
}

/* The solver's figures from steps.tsv: the largest nnz_L and rel_residual, the summed time. */
typedef struct tsv_figs {
    int rows;
    double nnz_L, residual, t_ms;
} tsv_figs;

static int read_steps_tsv(const char *run_dir, tsv_figs *t, kt_err *e)
{
    char path[4096];
    memset(t, 0, sizeof *t);
    t->nnz_L = t->residual = t->t_ms = NAN;
    if ((size_t)snprintf(path, sizeof path, "%s/steps.tsv", run_dir) >= sizeof path || access(path, F_OK) != 0)
        return KT_OK;
    kt_tsv in;
    if (kt_tsv_open(&in, path, e)) return e->code;
    static const char *const NAME[3] = {"nnz_L", "rel_residual", "t_total_ms"};
    int col[3];
    double v[3] = {0, 0, 0};
    int seen[3] = {0, 0, 0};
    for (int j = 0; j < 3; j++) col[j] = kt_tsv_find(&in, NAME[j]);
    while (!e->code && kt_tsv_next(&in) > 0) {
        t->rows++;
        for (int j = 0; j < 3 && !e->code; j++) {
            double x;
            if (col[j] < 0 || kt_tsv_num(&in, col[j], KT_TSV_NAN | KT_TSV_INF, &x) || !isfinite(x))
                continue; /* NaN: not measured */
            v[j] = j == 2 ? v[j] + x : seen[j] ? fmax(v[j], x) : x;
            seen[j] = 1;
        }
    }
    kt_tsv_close(&in);
    if (seen[0]) t->nnz_L = v[0];
    if (seen[1]) t->residual = v[1];
    if (seen[2]) t->t_ms = v[2];
    return e->code;
}

static void num(FILE *f, const char *key, double v, const char *fmt)
{
    fprintf(f, "  %s: ", key);
    if (isfinite(v)) fprintf(f, fmt, v);
    else fputs("null", f);
    fputc('\n', f);
}

static void materials(FILE *f, const kt_scene *sc)
{
    fputs("  materials:                 # as read from the scene (MPa), region by region\n", f);
    for (int i = 0; i < sc->nmat; i++) {
        const kt_region_mat *m = sc->mat + i;
        if (m->fibre && m->gt_profile[0] > 0)
            fprintf(f, "    %s: {model: fibre, E_inplane_MPa: %.6g, E_inplane_2_MPa: %.6g, "
                       "G_transverse_MPa: %.6g, nu: %.6g, G_transverse_profile_MPa: [%.6g, %.6g, %.6g]}\n",
                    m->region, m->E1, m->E2, m->Gt, m->nu, m->gt_profile[0], m->gt_profile[1], m->gt_profile[2]);
        else if (m->fibre)
            fprintf(f, "    %s: {model: fibre, E_inplane_MPa: %.6g, E_inplane_2_MPa: %.6g, "
                       "G_transverse_MPa: %.6g, nu: %.6g}\n", m->region, m->E1, m->E2, m->Gt, m->nu);
        else
            fprintf(f, "    %s: {model: isotropic, E_MPa: %.6g, nu: %.6g}\n", m->region, m->E, m->nu);
    }
    if (sc->nmat == 0) fputs("    {}\n", f);
    fputs("  pressures:\n", f);
    for (int i = 0; i < sc->npressure; i++)
        fprintf(f, "    - {surface: %s, p_kPa: %.6g}\n", sc->pressure[i].surface, 1000 * sc->pressure[i].p);
    if (sc->npressure == 0) fputs("    []\n", f);
    static const char *const REF[] = {"loaded", "unloaded", "prestressed"};
    fprintf(f, "  reference: %s\n", sc->reference >= 0 && sc->reference <= 2 ? REF[sc->reference] : "unknown");
    const kt_wound_scene *w = &sc->wound; /* keratome-scene(5), WOUND: k is what was solved */
    fprintf(f, "  wound: {state: %s, k_MPa_per_mm: %.6g, bridge_stiffness_MPa_per_mm: %.6g, age_rate_per_y: %.6g, "
               "age_y: %.6g, months: ", w->state == KT_WOUND_HEALED ? "healed" : "immediate", kt_scene_wound_k(sc),
            w->bridge_stiffness, w->age_rate, kt_scene_wound_age(sc));
    if (isfinite(w->months)) fprintf(f, "%.6g", w->months);
    else fputs("null", f);
    fprintf(f, ", heal_time_months: %.6g}\n", w->heal_time);
}

/* The scene file itself as a literal block (content indented 4: indicator 2 under a key at 2). */
static void scene_text(FILE *f, const char *path)
{
    FILE *in = fopen(path, "r");
    if (!in) {
        fputs("  scene_text: null\n", f);
        return;
    }
    fputs("  scene_text: |2\n", f);
    int c, bol = 1;
    while ((c = getc(in)) != EOF) {
        if (bol && c != '\n') fputs("    ", f);
        fputc(c, f);
        bol = c == '\n';
    }
    if (!bol) fputc('\n', f);
    fclose(in);
}

int kt_runrec_write(FILE *f, const char *run_dir, const kt_scene *sc, kt_err *e)
{
    uint64_t sh = 0;
    long sn = 0;
    kt_err e2 = {0};
    int have_scene = kt_runrec_file_hash(sc->path, &sh, &sn, &e2) == KT_OK;
    tsv_figs t;
    if (read_steps_tsv(run_dir, &t, e)) return e->code;
    fputs("provenance:                  # what was solved, by what (augsolve(1), RUN FOLDER)\n", f);
    fprintf(f, "  keratome: \"%s\"\n  cholmod: \"%d.%d.%d\"\n  metis: \"%d.%d.%d\"\n", KT_VERSION,
            CHOLMOD_MAIN_VERSION, CHOLMOD_SUB_VERSION, CHOLMOD_SUBSUB_VERSION, METIS_VER_MAJOR,
            METIS_VER_MINOR, METIS_VER_SUBMINOR);
#ifdef __VERSION__
    fprintf(f, "  compiler: \"%s\"\n", __VERSION__);
#endif
    if (have_scene) fprintf(f, "  scene_fnv1a: \"%016" PRIx64 "\"  # of the file's %ld bytes\n", sh, sn);
    else fputs("  scene_fnv1a: null\n", f);
    materials(f, sc);
    fprintf(f, "  solver:                    # from steps.tsv (%d rows)\n", t.rows);
    fprintf(f, "  ");
    num(f, "factor_nnz_max", t.nnz_L, "%.0f");
    fprintf(f, "  ");
    num(f, "rel_residual_max", t.residual, "%.3e");
    fprintf(f, "  ");
    num(f, "t_total_s", t.t_ms / 1000, "%.3f");
    scene_text(f, sc->path);
    if (ferror(f)) return kt_fail(e, KT_ERUN, "run.yaml: write error");
    return KT_OK;
}
