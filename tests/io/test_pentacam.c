/* test_pentacam.c: the Pentacam map reader: cells land at their grid coordinates in either
 * separator and decimal style, missing cells (empty or -1) stay missing, and files that are
 * not Pentacam maps, of another grid, truncated or with bad cells are refused at file:line:col. */
#define _POSIX_C_SOURCE 200809L
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "kt_test.h"
#include "pentacam.h"
#include "pentacam_synth.h"

static char dir[64];

static void path_of(char *buf, size_t n, const char *name) { snprintf(buf, n, "%s/%s", dir, name); }

static void test_read(void)
{
    synth_surface s = {7.55, 7.80, 95, -0.2, 0.05, -0.03, 0};
    const char sep[2] = {';', ','};
    for (int k = 0; k < 2; k++) {
        char p[128];
        path_of(p, sizeof p, "front.csv");
        CHECK(synth_write(p, &s, NULL, sep[k], sep[k] == ';', 0, 6.5) == 0, "write");
        kt_pentacam_map m;
        kt_err e = {0};
        int rc = kt_pentacam_read(p, KT_PENTACAM_ELEVATION, &m, &e);
        CHECK(rc == KT_OK, "read (sep '%c'): %s", sep[k], e.msg);
        if (rc != KT_OK) continue;
        int missing_ok = 1, value_ok = 1, nvalid = 0;
        for (int j = 0; j < 141; j++)
            for (int i = 0; i < 141; i++) {
                double v = m.v[j * 141 + i], want = synth_sag(&s, kt_pentacam_coord(i), kt_pentacam_coord(j));
                if (synth_missing(i, j, 6.5)) missing_ok &= isnan(v) != 0;
                else {
                    nvalid++;
                    value_ok &= fabs(v - want) < 1e-9;
                }
            }
        CHECK(missing_ok, "every missing cell (empty or -1) read as missing");
        CHECK(value_ok, "every cell at its (x, y)");
        CHECK(m.nvalid == nvalid, "measured cells %d vs %d", m.nvalid, nvalid);
        kt_pentacam_free(&m);
    }
    /* Pachymetry in um is read in mm. */
    char p[128];
    path_of(p, sizeof p, "pachy.csv");
    double t[3] = {0.54, 0.004, 0.0001};
    CHECK(synth_write(p, NULL, t, ';', 0, 0, 7) == 0, "write");
    kt_pentacam_map m;
    kt_err e = {0};
    CHECK(kt_pentacam_read(p, KT_PENTACAM_PACHYMETRY, &m, &e) == KT_OK, "pachymetry: %s", e.msg);
    CHECK_NEAR(m.v[70 * 141 + 70], 0.54, 1e-12, "central pachymetry in mm");
    kt_pentacam_free(&m);
}

/* Bad files: each one's message names its position and expectation. */
static void test_bad(void)
{
    char good[128], p[128];
    path_of(good, sizeof good, "good.csv");
    synth_surface s = {7.55, 7.80, 95, -0.2, 0, 0, 0};
    CHECK(synth_write(good, &s, NULL, ';', 0, 0, 6.5) == 0, "write");
    FILE *f = fopen(good, "r");
    char *text = calloc(1, 1 << 21);
    size_t n = f ? fread(text, 1, (1 << 21) - 1, f) : 0;
    if (f) fclose(f);
    /* The line starts. */
    int nl = 0;
    static size_t ls[200];
    ls[nl++] = 0;
    for (size_t i = 0; i < n; i++)
        if (text[i] == '\n' && nl < 200) ls[nl++] = i + 1;
    struct { const char *name; int kind; const char *want; } cases[] = {
        {"truncated", 0, ":144:1: expected 141 rows of the grid, the file ends after 140"},
        {"grid0.2", 0, ":3:2: expected the Pentacam grid's 141 x coordinates (-7.0 to 7.0 mm, 0.1 mm steps), found 71"},
        {"shifted", 0, ":3:2: expected x coordinate -7.0 mm"},
        {"scene", 0, ": expected a Pentacam map export: no row of the grid's 141 x coordinates"},
        {"shortrow", 0, ":4:"},
        {"um", 0, ":4:"},
        {"word", 0, ":5:"},
        {"pachy", 1, ":4:"},
    };
    for (size_t c = 0; c < sizeof cases / sizeof cases[0]; c++) {
        path_of(p, sizeof p, "bad.csv");
        f = fopen(p, "w");
        if (!f) break;
        const char *name = cases[c].name;
        if (!strcmp(name, "truncated")) fwrite(text, 1, ls[nl - 2], f); /* the last row cut */
        else if (!strcmp(name, "grid0.2")) {
            fwrite(text, 1, ls[2], f);
            for (int i = 0; i < 71; i++) fprintf(f, ";%.1f", -7 + 0.2 * i);
            fputc('\n', f);
        } else if (!strcmp(name, "shifted")) {
            fwrite(text, 1, ls[2], f);
            for (int i = 0; i < 141; i++) fprintf(f, ";%.2f", -6.95 + 0.1 * i);
            fputc('\n', f);
            fwrite(text + ls[3], 1, n - ls[3], f);
        } else if (!strcmp(name, "scene")) {
            fputs("name: eye\nmodel: eye\neye: {steep_axis: 90 deg}\n", f);
        } else if (!strcmp(name, "shortrow")) {
            fwrite(text, 1, ls[3], f);
            fputs("7.0;0.1;0.2\n", f);
            fwrite(text + ls[4], 1, n - ls[4], f);
        } else if (!strcmp(name, "um")) {
            fwrite(text, 1, ls[3], f);
            fputs("7.0", f);
            for (int i = 0; i < 141; i++) fputs(";120.5", f);
            fputc('\n', f);
            fwrite(text + ls[4], 1, n - ls[4], f);
        } else if (!strcmp(name, "word")) {
            fwrite(text, 1, ls[4], f);
            fputs("6.9", f);
            for (int i = 0; i < 141; i++) fputs(i == 70 ? ";abc" : ";", f);
            fputc('\n', f);
            fwrite(text + ls[5], 1, n - ls[5], f);
        } else { /* an elevation map read as pachymetry: values below 100 um */
            fwrite(text, 1, ls[3], f);
            fputs("7.0", f);
            for (int i = 0; i < 141; i++) fputs(";3.5", f);
            fputc('\n', f);
            fwrite(text + ls[4], 1, n - ls[4], f);
        }
        fclose(f);
        kt_pentacam_map m;
        kt_err e = {0};
        int rc = kt_pentacam_read(p, cases[c].kind, &m, &e);
        CHECK(rc == KT_EINPUT, "%s accepted", name);
        CHECK(strstr(e.msg, cases[c].want) != NULL, "%s: '%s' lacks '%s'", name, e.msg, cases[c].want);
        CHECK(m.v == NULL, "%s: nothing left to free", name);
    }
    free(text);
}

int main(void)
{
    snprintf(dir, sizeof dir, "/tmp/kt-pentacam-XXXXXX");
    if (!mkdtemp(dir)) return 1;
    test_read();
    test_bad();
    char cmd[128];
    snprintf(cmd, sizeof cmd, "rm -rf %s", dir);
    if (system(cmd) != 0) return 1;
    return kt_test_done("test_pentacam");
}
