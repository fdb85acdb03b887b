/* g17.h: doubles as printf("%.17g") prints them, fast: the text of ASCII VTK and MSH files.
 *
 * 17 significant digits, correctly rounded (ties to even), give every double back bit for bit
 * through strtod. The common magnitudes (1e-22 to 1e17, which hold coordinates in mm,
 * displacements, moduli and derivatives) are converted exactly in 192-bit integer arithmetic;
 * the rest (and NaN, infinities, subnormals) go through snprintf. The text is byte for byte the C library's
 * (tests/io/test_g17.c compares them on millions of values). */
#ifndef KT_G17_H
#define KT_G17_H

#include <stddef.h>

/* Longest text kt_g17 writes, with its terminating NUL ("-1.2345678901234567e-308"). */
#define KT_G17_MAX 32

/* Write x as "%.17g" into buf (at least KT_G17_MAX bytes), NUL-terminated; returns its length. */
int kt_g17(double x, char *buf);

/* Write v as "%d" into buf (at least 12 bytes), NUL-terminated; returns its length. */
int kt_itoa(int v, char *buf);

#endif
