/* test_g17.c: kt_g17 prints every double byte for byte as the C library's "%.17g" and strtod
 * gives it back bit for bit: random bit patterns over the whole range, random values in each
 * decade of the exact range and at its edges, integers, decimal ties (x * 10^k ending in exactly
 * .5, rounded to even), powers of ten and two, subnormals, zeros, infinities and NaN; kt_itoa
 * against "%d". A failure prints the value. */
#include <float.h>
#include <limits.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "g17.h"
#include "kt_test.h"

static uint64_t rng = 0x9e3779b97f4a7c15ull;
static uint64_t next(void) /* xorshift64* */
{
    rng ^= rng >> 12, rng ^= rng << 25, rng ^= rng >> 27;
    return rng * 2685821657736338717ull;
}

static long bad;
static void one(double x)
{
    char a[KT_G17_MAX], b[64];
    int n = kt_g17(x, a);
    snprintf(b, sizeof b, "%.17g", x);
    int same = strcmp(a, b) == 0 && n == (int)strlen(b);
    if (same && x == x) {
        double y = strtod(a, NULL);
        same = memcmp(&x, &y, 8) == 0;
    }
    if (!same && bad++ < 10) CHECK(0, "%a: kt_g17 '%s', printf '%s'", x, a, b);
    else kt_test_pass += same;
}

int main(void)
{
    for (int i = 0; i < 300000; i++) { /* any bit pattern */
        uint64_t u = next();
        double x;
        memcpy(&x, &u, 8);
        one(x);
    }
    for (int d = -24; d <= 18; d++) /* each decade of the exact range and beyond its edges */
        for (int i = 0; i < 10000; i++) {
            double x = (1 + 9 * ((next() >> 11) * 0x1p-53)) * pow(10, d);
            one(i % 2 ? -x : x);
            one(nextafter(pow(10, d), 0));
            one(pow(10, d));
        }
    for (int i = 0; i < 200000; i++) { /* short decimals, as coordinates often are */
        one((double)(int64_t)(next() % 2000001 - 1000000) / 1000);
        one((double)(int64_t)(next() >> 20));
    }
    for (int k = 1; k <= 6; k++) /* ties: a / 2^(k+1) with x * 10^k ending in .5 */
        for (int i = 0; i < 20000; i++) {
            uint64_t a = ((next() >> 11) | 1) & ((1ull << 53) - 1);
            one(ldexp((double)a, -(k + 1)));
        }
    for (int e = -1074; e <= 1023; e++) one(ldexp(1, e));
    double sp[] = {0.0, -0.0, 1.0, -1.0, 0.1, 1e-6, 9.9999999999999995e-7, 1e16, 1e17, 9.999999999999999e16,
                   DBL_MIN, DBL_MAX, DBL_TRUE_MIN, -DBL_TRUE_MIN, 4.9406564584124654e-324, 0x1p52, 0x1p53,
                   0x1p56, 0x1p57, 1e15 + 0.25, 1e15 + 0.75, 5e-324, INFINITY, -INFINITY, NAN};
    for (size_t i = 0; i < sizeof sp / sizeof sp[0]; i++) one(sp[i]);
    int iv[] = {0, 1, -1, 9, 10, -10, 123456789, INT_MAX, INT_MIN, INT_MIN + 1};
    for (size_t i = 0; i < sizeof iv / sizeof iv[0]; i++) {
        char a[12], b[16];
        int n = kt_itoa(iv[i], a);
        snprintf(b, sizeof b, "%d", iv[i]);
        CHECK(strcmp(a, b) == 0 && n == (int)strlen(b), "kt_itoa(%d) '%s'", iv[i], a);
    }
    for (int i = 0; i < 30000; i++) {
        int v = (int)(uint32_t)next();
        char a[12], b[16];
        kt_itoa(v, a);
        snprintf(b, sizeof b, "%d", v);
        if (strcmp(a, b)) CHECK(0, "kt_itoa(%d) '%s'", v, a);
    }
    CHECK(bad == 0, "%ld values differ from printf", bad);
    return kt_test_done("test_g17");
}
