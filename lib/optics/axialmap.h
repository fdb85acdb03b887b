/* axialmap.h: corneal-topographer style axial power maps as PNG (libpng): an absolute dioptric
 * colour scale with its legend, axis marks in degrees around the rim (TABO: 0 at the
 * examiner's right, counter-clockwise, seen from the front), a title, and the text drawn with
 * a small built-in bitmap font. The map knows nothing of fits: it samples a callback. */
#ifndef KT_TOPO_H
#define KT_TOPO_H

#include "util.h"

#define KT_TOPO_MAXBIN 64

/* An absolute colour scale: bins [lo, hi) in D, contiguous and increasing; a value below the
 * first bin takes the first colour, above the last the last (as topographers clamp). */
typedef struct kt_topo_scale {
    int n;
    double lo[KT_TOPO_MAXBIN], hi[KT_TOPO_MAXBIN];
    unsigned char rgb[KT_TOPO_MAXBIN][3];
} kt_topo_scale;

/* Read a scale TSV ("lo_D hi_D r g b" per line, '#' comments, an optional header line).
 * Malformed lines, gaps or overlaps between bins are KT_EINPUT naming file:line. */
int kt_topo_scale_load(const char *path, kt_topo_scale *s, kt_err *e);

/* The bin of a power value (clamped to the scale; NaN gives -1). */
int kt_topo_scale_bin(const kt_topo_scale *s, double power);

/* The legend's labels: val[k] (D) at pos[k] bins from the bottom of the legend (an edge at an
 * integer, a bin centre at +0.5); at most max. A diverging scale (a bin straddling 0, as the
 * difference scale) labels the centres of every other bin so that 0 and its symmetric round
 * values (+-0.5, +-1.0, ...) show; an absolute scale every other edge. Returns the count. */
int kt_topo_legend_labels(const kt_topo_scale *s, double *val, double *pos, int max);
/* A label as the legend prints it: "0", one decimal when exact ("42.0", "+0.5"), else two;
 * signed_ adds the sign (difference scales). */
void kt_topo_legend_text(double v, int signed_, char *buf, size_t size);

/* A relative ("auto") scale: bins of a width from 0.25, 0.5, 1, 1.5, 3 D (the smallest giving at
 * most 24 bins) aligned to multiples of it, covering [lo, hi] D, coloured by sampling the
 * colours of `like` evenly from its first to its last bin (cool flat, warm steep). */
int kt_topo_scale_auto(const kt_topo_scale *like, double lo, double hi, kt_topo_scale *s, kt_err *e);

typedef struct kt_topo_image {
    int w, h;
    unsigned char *rgb;   /* w*h*3, row-major from the top */
} kt_topo_image;

/* What to draw: the disk of radius `radius` mm around (cx, cy) mm in the eye frame (x right,
 * y up), the keratometry zone as a circle of diameter zone (mm, 0: none), two title lines
 * (upper case letters, digits and . - + / @ : ( ) = , % and the UTF-8 degree sign). */
typedef struct kt_topo_map {
    double cx, cy, radius, zone;
    char title[2][96];
} kt_topo_map;

/* Power (D) at (x, y) mm; NaN where unknown (drawn grey). */
typedef double (*kt_topo_power_fn)(const void *ctx, double x, double y);

/* Pixel geometry of a rendered map, for readers of the image (tests, overlays). */
typedef struct kt_topo_layout {
    int w, h;             /* image size */
    int cx, cy, rad;      /* map disk centre and radius, px */
    int leg_x, leg_w;     /* legend swatches: left edge and width, px */
    int leg_y, leg_h;     /* top of the legend (the highest bin) and height of one bin, px */
} kt_topo_layout;

void kt_topo_layout_of(const kt_topo_scale *s, kt_topo_layout *L);

int kt_topo_render(const kt_topo_scale *s, const kt_topo_map *m, kt_topo_power_fn power,
                   const void *ctx, kt_topo_image *img, kt_err *e);
void kt_topo_image_free(kt_topo_image *img);

/* The 8-bit RGB PNG file of an image in memory: *buf (the caller frees it) of *len bytes. */
int kt_topo_png_bytes(const kt_topo_image *img, unsigned char **buf, size_t *len, kt_err *e);

/* Write an 8-bit RGB PNG atomically (temporary beside the target, renamed on success). */
int kt_topo_write_png(const char *path, const kt_topo_image *img, kt_err *e);

#endif
