/* axialmap.c: axial power maps in the style of a corneal topographer, written as PNG by libpng. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <png.h>
#include <stdlib.h>
#include <string.h>

#include "axialmap.h"


/* ---------------------------------------------------------------- colour scale */

int kt_topo_scale_load(const char *path, kt_topo_scale *s, kt_err *e)
{
    memset(s, 0, sizeof *s);
    FILE *f = fopen(path, "r");
    if (!f) return kt_fail(e, KT_EINPUT, "%s: cannot open the colour scale", path);
    char line[512];
    int ln = 0, rc = KT_OK;
    while (rc == KT_OK && fgets(line, sizeof line, f)) {
        ln++;
        char *p = line + strspn(line, " \t");
        if (*p == '#' || *p == '\n' || *p == '\0' || strncmp(p, "lo_D", 4) == 0) continue;
        double lo, hi;
        int r, g, b, used = 0;
        if (sscanf(p, "%lf %lf %d %d %d %n", &lo, &hi, &r, &g, &b, &used) != 5 || p[used] != '\0')
            rc = kt_fail(e, KT_EINPUT, "%s:%d: expected \"lo_D hi_D r g b\"", path, ln);
        else if (!(hi > lo) || r < 0 || r > 255 || g < 0 || g > 255 || b < 0 || b > 255)
            rc = kt_fail(e, KT_EINPUT, "%s:%d: expected lo < hi and colours 0..255", path, ln);
        else if (s->n > 0 && fabs(lo - s->hi[s->n - 1]) > 1e-9)
            rc = kt_fail(e, KT_EINPUT, "%s:%d: bin starts at %g, expected %g (contiguous bins)",
                         path, ln, lo, s->hi[s->n - 1]);
        else if (s->n == KT_TOPO_MAXBIN)
            rc = kt_fail(e, KT_EINPUT, "%s:%d: more than %d bins", path, ln, KT_TOPO_MAXBIN);
        else {
            s->lo[s->n] = lo, s->hi[s->n] = hi;
            s->rgb[s->n][0] = (unsigned char)r, s->rgb[s->n][1] = (unsigned char)g,
            s->rgb[s->n][2] = (unsigned char)b;
            s->n++;
        }
    }
    fclose(f);
    if (rc == KT_OK && s->n == 0) rc = kt_fail(e, KT_EINPUT, "%s: no colour bins", path);
    return rc;
}

int kt_topo_scale_bin(const kt_topo_scale *s, double power)
{
    if (isnan(power)) return -1;
    int i = 0;
    while (i < s->n - 1 && power >= s->hi[i]) i++;
    return i;
}

int kt_topo_scale_auto(const kt_topo_scale *like, double lo, double hi, kt_topo_scale *s, kt_err *e)
{
    static const double W[] = {0.25, 0.5, 1, 1.5, 3};
    memset(s, 0, sizeof *s);
    if (!isfinite(lo) || !isfinite(hi) || hi < lo || like->n < 1)
        return kt_fail(e, KT_ERUN, "relative colour scale: no finite power range (%g to %g D)", lo, hi);
    double w = W[4], a = 0;
    int n = 0;
    for (int k = 0; k < 5; k++) {
        w = W[k], a = floor(lo / w) * w;
        n = (int)ceil((hi - a) / w - 1e-9);
        if (n < 1) n = 1;
        if (n <= 24) break;
    }
    if (n > KT_TOPO_MAXBIN) return kt_fail(e, KT_ERUN, "relative colour scale: range %g to %g D too wide", lo, hi);
    s->n = n;
    for (int i = 0; i < n; i++) {
        int j = n > 1 ? (int)lround((double)i * (like->n - 1) / (n - 1)) : like->n / 2;
        s->lo[i] = a + i * w, s->hi[i] = a + (i + 1) * w;
        memcpy(s->rgb[i], like->rgb[j], 3);
    }
    return KT_OK;
}

/* ---------------------------------------------------------------- bitmap font 5x7 */

typedef struct glyph {
    char c;
    const char *row[7];
} glyph;

#define DEGREE_CHAR '\x01'

static const glyph font[] = {
    {' ', {"     ", "     ", "     ", "     ", "     ", "     ", "     "}},
    {'0', {" ### ", "#   #", "#  ##", "# # #", "##  #", "#   #", " ### "}},
    {'1', {"  #  ", " ##  ", "  #  ", "  #  ", "  #  ", "  #  ", " ### "}},
    {'2', {" ### ", "#   #", "    #", "   # ", "  #  ", " #   ", "#####"}},
    {'3', {"#####", "   # ", "  #  ", "   # ", "    #", "#   #", " ### "}},
    {'4', {"   # ", "  ## ", " # # ", "#  # ", "#####", "   # ", "   # "}},
    {'5', {"#####", "#    ", "#### ", "    #", "    #", "#   #", " ### "}},
    {'6', {"  ## ", " #   ", "#    ", "#### ", "#   #", "#   #", " ### "}},
    {'7', {"#####", "    #", "   # ", "  #  ", " #   ", " #   ", " #   "}},
    {'8', {" ### ", "#   #", "#   #", " ### ", "#   #", "#   #", " ### "}},
    {'9', {" ### ", "#   #", "#   #", " ####", "    #", "   # ", " ##  "}},
    {'A', {" ### ", "#   #", "#   #", "#####", "#   #", "#   #", "#   #"}},
    {'B', {"#### ", "#   #", "#   #", "#### ", "#   #", "#   #", "#### "}},
    {'C', {" ### ", "#   #", "#    ", "#    ", "#    ", "#   #", " ### "}},
    {'D', {"###  ", "#  # ", "#   #", "#   #", "#   #", "#  # ", "###  "}},
    {'E', {"#####", "#    ", "#    ", "#### ", "#    ", "#    ", "#####"}},
    {'F', {"#####", "#    ", "#    ", "#### ", "#    ", "#    ", "#    "}},
    {'G', {" ### ", "#   #", "#    ", "# ###", "#   #", "#   #", " ####"}},
    {'H', {"#   #", "#   #", "#   #", "#####", "#   #", "#   #", "#   #"}},
    {'I', {" ### ", "  #  ", "  #  ", "  #  ", "  #  ", "  #  ", " ### "}},
    {'J', {"  ###", "   # ", "   # ", "   # ", "   # ", "#  # ", " ##  "}},
    {'K', {"#   #", "#  # ", "# #  ", "##   ", "# #  ", "#  # ", "#   #"}},
    {'L', {"#    ", "#    ", "#    ", "#    ", "#    ", "#    ", "#####"}},
    {'M', {"#   #", "## ##", "# # #", "# # #", "#   #", "#   #", "#   #"}},
    {'N', {"#   #", "#   #", "##  #", "# # #", "#  ##", "#   #", "#   #"}},
    {'O', {" ### ", "#   #", "#   #", "#   #", "#   #", "#   #", " ### "}},
    {'P', {"#### ", "#   #", "#   #", "#### ", "#    ", "#    ", "#    "}},
    {'Q', {" ### ", "#   #", "#   #", "#   #", "# # #", "#  # ", " ## #"}},
    {'R', {"#### ", "#   #", "#   #", "#### ", "# #  ", "#  # ", "#   #"}},
    {'S', {" ####", "#    ", "#    ", " ### ", "    #", "    #", "#### "}},
    {'T', {"#####", "  #  ", "  #  ", "  #  ", "  #  ", "  #  ", "  #  "}},
    {'U', {"#   #", "#   #", "#   #", "#   #", "#   #", "#   #", " ### "}},
    {'V', {"#   #", "#   #", "#   #", "#   #", "#   #", " # # ", "  #  "}},
    {'W', {"#   #", "#   #", "#   #", "# # #", "# # #", "# # #", " # # "}},
    {'X', {"#   #", "#   #", " # # ", "  #  ", " # # ", "#   #", "#   #"}},
    {'Y', {"#   #", "#   #", " # # ", "  #  ", "  #  ", "  #  ", "  #  "}},
    {'Z', {"#####", "    #", "   # ", "  #  ", " #   ", "#    ", "#####"}},
    {'.', {"     ", "     ", "     ", "     ", "     ", " ##  ", " ##  "}},
    {'-', {"     ", "     ", "     ", "#####", "     ", "     ", "     "}},
    {'+', {"     ", "  #  ", "  #  ", "#####", "  #  ", "  #  ", "     "}},
    {'/', {"    #", "    #", "   # ", "  #  ", " #   ", "#    ", "#    "}},
    {'@', {" ### ", "#   #", "# ###", "# # #", "# ###", "#    ", " ####"}},
    {':', {"     ", " ##  ", " ##  ", "     ", " ##  ", " ##  ", "     "}},
    {'(', {"   # ", "  #  ", " #   ", " #   ", " #   ", "  #  ", "   # "}},
    {')', {" #   ", "  #  ", "   # ", "   # ", "   # ", "  #  ", " #   "}},
    {'=', {"     ", "     ", "#####", "     ", "#####", "     ", "     "}},
    {',', {"     ", "     ", "     ", "     ", " ##  ", "  #  ", " #   "}},
    {'%', {"##   ", "##  #", "   # ", "  #  ", " #   ", "#  ##", "   ##"}},
    {DEGREE_CHAR, {" ##  ", "#  # ", "#  # ", " ##  ", "     ", "     ", "     "}},
};

static const glyph *find_glyph(char c)
{
    if (c >= 'a' && c <= 'z') c = (char)(c - 'a' + 'A');
    for (size_t i = 0; i < sizeof font / sizeof font[0]; i++)
        if (font[i].c == c) return &font[i];
    return &font[0]; /* unknown: a blank */
}

static void put_pixel(kt_topo_image *img, int x, int y, const unsigned char *rgb)
{
    if (x < 0 || y < 0 || x >= img->w || y >= img->h) return;
    memcpy(img->rgb + 3 * ((size_t)y * img->w + x), rgb, 3);
}

/* Decode the next character; the UTF-8 degree sign (C2 B0) becomes DEGREE_CHAR. */
static char next_char(const char **s)
{
    const unsigned char *p = (const unsigned char *)*s;
    if (p[0] == 0xC2 && p[1] == 0xB0) {
        *s += 2;
        return DEGREE_CHAR;
    }
    (*s)++;
    return (char)p[0];
}

static int text_width(const char *s, int scale)
{
    int n = 0;
    while (*s) next_char(&s), n++;
    return n > 0 ? (6 * n - 1) * scale : 0;
}

/* Text with its top-left corner at (x, y); each font pixel a scale x scale square. */
static void draw_text(kt_topo_image *img, int x, int y, int scale, const unsigned char *rgb,
                      const char *s)
{
    while (*s) {
        const glyph *g = find_glyph(next_char(&s));
        for (int r = 0; r < 7; r++)
            for (int c = 0; c < 5; c++) {
                if (g->row[r][c] != '#') continue;
                for (int dy = 0; dy < scale; dy++)
                    for (int dx = 0; dx < scale; dx++)
                        put_pixel(img, x + c * scale + dx, y + r * scale + dy, rgb);
            }
        x += 6 * scale;
    }
}

/* ---------------------------------------------------------------- map */

static const unsigned char BLACK[3] = {0, 0, 0}, GREY[3] = {160, 160, 160};

enum { FONT = 2, TITLE_Y = 8, LINE_H = 22 };

void kt_topo_layout_of(const kt_topo_scale *s, kt_topo_layout *L)
{
    L->w = 720, L->h = 580;
    L->cx = 290, L->cy = 320, L->rad = 220;
    L->leg_x = 590, L->leg_w = 34;
    L->leg_h = s->n > 0 ? 440 / s->n : 16;
    if (L->leg_h > 24) L->leg_h = 24;
    L->leg_y = L->cy - (L->leg_h * s->n) / 2;
}

static void draw_line(kt_topo_image *img, double x0, double y0, double x1, double y1,
                      const unsigned char *rgb)
{
    int n = (int)ceil(fmax(fabs(x1 - x0), fabs(y1 - y0))) + 1;
    for (int i = 0; i <= n; i++) {
        double t = (double)i / n;
        put_pixel(img, (int)lround(x0 + t * (x1 - x0)), (int)lround(y0 + t * (y1 - y0)), rgb);
    }
}

static void draw_circle(kt_topo_image *img, int cx, int cy, double r, int dashed,
                        const unsigned char *rgb)
{
    int n = (int)(2 * KT_PI * r) + 8;
    for (int i = 0; i < n; i++) {
        if (dashed && (i / 6) % 2) continue;
        double t = 2 * KT_PI * i / n;
        put_pixel(img, (int)lround(cx + r * cos(t)), (int)lround(cy - r * sin(t)), rgb);
    }
}

/* Ticks every 10 deg, labels every 30 deg, around the rim. */
static void draw_axis_marks(kt_topo_image *img, const kt_topo_layout *L)
{
    char buf[16];
    for (int t = 0; t < 360; t += 10) {
        double c = cos(t * KT_PI / 180), s = sin(t * KT_PI / 180);
        int len = t % 30 == 0 ? 10 : 5;
        draw_line(img, L->cx + L->rad * c, L->cy - L->rad * s, L->cx + (L->rad + len) * c,
                  L->cy - (L->rad + len) * s, BLACK);
        if (t % 30) continue;
        snprintf(buf, sizeof buf, "%d\xC2\xB0", t);
        int tw = text_width(buf, FONT), th = 7 * FONT;
        double rr = L->rad + 14 + 0.5 * (fabs(c) * tw + fabs(s) * th);
        draw_text(img, (int)lround(L->cx + rr * c - tw / 2.0), (int)lround(L->cy - rr * s - th / 2.0),
                  FONT, BLACK, buf);
    }
}

int kt_topo_legend_labels(const kt_topo_scale *s, double *val, double *pos, int max)
{
    int z = -1, n = 0;
    for (int i = 0; i < s->n; i++)
        if (s->lo[i] < 0 && s->hi[i] > 0) z = i;
    if (z >= 0) { /* a diverging scale: the centres of every other bin, 0's bin among them */
        for (int i = z % 2; i < s->n && n < max; i += 2, n++) {
            double c = 0.5 * (s->lo[i] + s->hi[i]);
            val[n] = i == z ? 0 : c, pos[n] = i + 0.5;
        }
        return n;
    }
    for (int i = 0; i <= s->n && n < max; i++) { /* every other boundary from the bottom, and the top */
        if (i % 2 && i != s->n) continue;
        if (i == s->n - 1 && s->n % 2) continue; /* would overlap the top label */
        val[n] = i < s->n ? s->lo[i] : s->hi[s->n - 1], pos[n] = i, n++;
    }
    return n;
}

void kt_topo_legend_text(double v, int signed_, char *buf, size_t size)
{
    double r1 = round(v * 10) / 10;
    if (v == 0) snprintf(buf, size, "0");
    else if (fabs(v - r1) < 1e-9) snprintf(buf, size, signed_ ? "%+.1f" : "%.1f", v);
    else snprintf(buf, size, signed_ ? "%+.2f" : "%.2f", v);
}

/* Swatches from the highest bin at the top; labels in D where kt_topo_legend_labels says. */
static void draw_legend(kt_topo_image *img, const kt_topo_scale *s, const kt_topo_layout *L)
{
    char buf[32];
    double val[KT_TOPO_MAXBIN + 1], pos[KT_TOPO_MAXBIN + 1];
    for (int i = 0; i < s->n; i++) {
        int y0 = L->leg_y + (s->n - 1 - i) * L->leg_h;
        for (int y = y0; y < y0 + L->leg_h; y++)
            for (int x = L->leg_x; x < L->leg_x + L->leg_w; x++) put_pixel(img, x, y, s->rgb[i]);
    }
    int nl = kt_topo_legend_labels(s, val, pos, KT_TOPO_MAXBIN + 1), diverging = s->n > 0 && s->lo[0] < 0;
    for (int k = 0; k < nl; k++) {
        int y = (int)lround(L->leg_y + (s->n - pos[k]) * L->leg_h);
        draw_line(img, L->leg_x + L->leg_w, y, L->leg_x + L->leg_w + 4, y, BLACK);
        kt_topo_legend_text(val[k], diverging, buf, sizeof buf);
        draw_text(img, L->leg_x + L->leg_w + 7, y - 7 * FONT / 2, FONT, BLACK, buf);
    }
    draw_text(img, L->leg_x + L->leg_w / 2 - 5 * FONT / 2, L->leg_y - 10 * FONT, FONT, BLACK, "D");
}

int kt_topo_render(const kt_topo_scale *s, const kt_topo_map *m, kt_topo_power_fn power,
                   const void *ctx, kt_topo_image *img, kt_err *e)
{
    memset(img, 0, sizeof *img);
    if (s->n < 1) return kt_fail(e, KT_EINPUT, "axial map: empty colour scale");
    kt_topo_layout L;
    kt_topo_layout_of(s, &L);
    img->w = L.w, img->h = L.h;
    img->rgb = kt_calloc((size_t)L.w * L.h * 3, 1, e);
    if (!img->rgb) return e->code;
    memset(img->rgb, 255, (size_t)L.w * L.h * 3);
    double px_per_mm = L.rad / m->radius;
    for (int py = L.cy - L.rad; py <= L.cy + L.rad; py++)
        for (int px = L.cx - L.rad; px <= L.cx + L.rad; px++) {
            double dx = px + 0.5 - L.cx, dy = L.cy - (py + 0.5); /* screen y down, eye y up */
            if (dx * dx + dy * dy > (double)L.rad * L.rad) continue;
            double p = power(ctx, m->cx + dx / px_per_mm, m->cy + dy / px_per_mm);
            int b = kt_topo_scale_bin(s, p);
            put_pixel(img, px, py, b < 0 ? GREY : s->rgb[b]);
        }
    draw_circle(img, L.cx, L.cy, L.rad, 0, BLACK);
    if (m->zone > 0) draw_circle(img, L.cx, L.cy, 0.5 * m->zone * px_per_mm, 1, BLACK);
    draw_line(img, L.cx - 4, L.cy, L.cx + 4, L.cy, BLACK); /* the apex, on the map's axis */
    draw_line(img, L.cx, L.cy - 4, L.cx, L.cy + 4, BLACK);
    draw_axis_marks(img, &L);
    draw_legend(img, s, &L);
    for (int i = 0; i < 2; i++) draw_text(img, 10, TITLE_Y + i * LINE_H, FONT, BLACK, m->title[i]);
    return KT_OK;
}

void kt_topo_image_free(kt_topo_image *img)
{
    free(img->rgb);
    memset(img, 0, sizeof *img);
}

/* ---------------------------------------------------------------- PNG */

static void png_error_fn(png_structp png, png_const_charp msg)
{
    kt_err *e = png_get_error_ptr(png);
    kt_fail(e, KT_ERUN, "libpng: %s", msg);
    png_longjmp(png, 1);
}

static void png_warn_fn(png_structp png, png_const_charp msg) { (void)png, (void)msg; }

/* The libpng part, apart so that setjmp's caller has no locals to clobber. */
static int png_encode(FILE *f, const kt_topo_image *img, kt_err *e)
{
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, e, png_error_fn, png_warn_fn);
    if (!png) return kt_fail(e, KT_ERUN, "libpng: cannot create a writer");
    png_infop info = png_create_info_struct(png);
    if (!info) {
        png_destroy_write_struct(&png, NULL);
        return kt_fail(e, KT_ERUN, "libpng: cannot create the image header");
    }
    if (setjmp(png_jmpbuf(png))) {
        png_destroy_write_struct(&png, &info);
        return e->code ? e->code : kt_fail(e, KT_ERUN, "libpng: write failed");
    }
    png_init_io(png, f);
    png_set_IHDR(png, info, (png_uint_32)img->w, (png_uint_32)img->h, 8, PNG_COLOR_TYPE_RGB,
                 PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    png_write_info(png, info);
    for (int y = 0; y < img->h; y++) png_write_row(png, img->rgb + (size_t)y * img->w * 3);
    png_write_end(png, NULL);
    png_destroy_write_struct(&png, &info);
    return KT_OK;
}

int kt_topo_png_bytes(const kt_topo_image *img, unsigned char **buf, size_t *len, kt_err *e)
{
    char *mem = NULL;
    size_t n = 0;
    *buf = NULL, *len = 0;
    FILE *f = open_memstream(&mem, &n);
    if (!f) return kt_fail(e, KT_ERUN, "PNG in memory: cannot open a memory stream");
    int rc = png_encode(f, img, e);
    if (fclose(f) != 0 && rc == KT_OK) rc = kt_fail(e, KT_ERUN, "PNG in memory: out of memory");
    if (rc != KT_OK) {
        free(mem);
        return rc;
    }
    *buf = (unsigned char *)mem, *len = n;
    return KT_OK;
}

int kt_topo_write_png(const char *path, const kt_topo_image *img, kt_err *e)
{
    kt_out o;
    if (kt_out_open(&o, path, e) != KT_OK) return e->code;
    if (png_encode(o.f, img, e) != KT_OK) {
        kt_out_abort(&o);
        return e->code;
    }
    return kt_out_commit(&o, e);
}
