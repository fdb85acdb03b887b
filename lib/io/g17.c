/* g17.c: "%.17g" without printf (g17.h). */
#include "g17.h"

#include <stdint.h>
#include <stdio.h>
#include <string.h>

typedef unsigned __int128 u128;

static const uint64_t P10_16 = 10000000000000000ull, P10_17 = 100000000000000000ull;

/* 10^k for k = 0..38 (10^38 < 2^127), high and low 64 bits. */
static const uint64_t P10[39][2] = {
    {0x0000000000000000ull, 0x0000000000000001ull},
    {0x0000000000000000ull, 0x000000000000000aull},
    {0x0000000000000000ull, 0x0000000000000064ull},
    {0x0000000000000000ull, 0x00000000000003e8ull},
    {0x0000000000000000ull, 0x0000000000002710ull},
    {0x0000000000000000ull, 0x00000000000186a0ull},
    {0x0000000000000000ull, 0x00000000000f4240ull},
    {0x0000000000000000ull, 0x0000000000989680ull},
    {0x0000000000000000ull, 0x0000000005f5e100ull},
    {0x0000000000000000ull, 0x000000003b9aca00ull},
    {0x0000000000000000ull, 0x00000002540be400ull},
    {0x0000000000000000ull, 0x000000174876e800ull},
    {0x0000000000000000ull, 0x000000e8d4a51000ull},
    {0x0000000000000000ull, 0x000009184e72a000ull},
    {0x0000000000000000ull, 0x00005af3107a4000ull},
    {0x0000000000000000ull, 0x00038d7ea4c68000ull},
    {0x0000000000000000ull, 0x002386f26fc10000ull},
    {0x0000000000000000ull, 0x016345785d8a0000ull},
    {0x0000000000000000ull, 0x0de0b6b3a7640000ull},
    {0x0000000000000000ull, 0x8ac7230489e80000ull},
    {0x0000000000000005ull, 0x6bc75e2d63100000ull},
    {0x0000000000000036ull, 0x35c9adc5dea00000ull},
    {0x000000000000021eull, 0x19e0c9bab2400000ull},
    {0x000000000000152dull, 0x02c7e14af6800000ull},
    {0x000000000000d3c2ull, 0x1bcecceda1000000ull},
    {0x0000000000084595ull, 0x161401484a000000ull},
    {0x000000000052b7d2ull, 0xdcc80cd2e4000000ull},
    {0x00000000033b2e3cull, 0x9fd0803ce8000000ull},
    {0x00000000204fce5eull, 0x3e25026110000000ull},
    {0x00000001431e0faeull, 0x6d7217caa0000000ull},
    {0x0000000c9f2c9cd0ull, 0x4674edea40000000ull},
    {0x0000007e37be2022ull, 0xc0914b2680000000ull},
    {0x000004ee2d6d415bull, 0x85acef8100000000ull},
    {0x0000314dc6448d93ull, 0x38c15b0a00000000ull},
    {0x0001ed09bead87c0ull, 0x378d8e6400000000ull},
    {0x0013426172c74d82ull, 0x2b878fe800000000ull},
    {0x00c097ce7bc90715ull, 0xb34b9f1000000000ull},
    {0x0785ee10d5da46d9ull, 0x00f436a000000000ull},
    {0x4b3b4ca85a86c47aull, 0x098a224000000000ull},
};

/* p (3 limbs, least significant first) >> s, for 0 <= s < 192, into q. */
static void shr3(const uint64_t p[3], int s, uint64_t q[3])
{
    int w = s / 64, b = s % 64;
    for (int i = 0; i < 3; i++) {
        uint64_t lo = i + w < 3 ? p[i + w] : 0, hi = i + w + 1 < 3 ? p[i + w + 1] : 0;
        q[i] = b ? (lo >> b) | (hi << (64 - b)) : lo;
    }
}

/* Bit i of p, and whether any bit below i is set. */
static int bit3(const uint64_t p[3], int i)
{
    return (int)((p[i / 64] >> (i % 64)) & 1);
}

static int below3(const uint64_t p[3], int i)
{
    for (int j = 0; j < i / 64; j++)
        if (p[j]) return 1;
    return i % 64 && (p[i / 64] & ((1ull << (i % 64)) - 1));
}

/* The 17 correctly rounded significant digits of x > 0, x = mant * 2^e2, as an integer
 * q in [1e16, 1e17) with x ~ q * 10^(d10 - 16); 0 when x lies outside the exact range. */
static int digits17(uint64_t mant, int e2, uint64_t *q, int *d10)
{
    /* x = mant * 2^e2 < 10^17 (so the scale 10^k, k = 16 - d10, has k >= 0) and k <= 38:
     * mant * 10^k < 2^180 and the shift s = -e2 < 192: 10^-22 <= x < 10^17. */
    if (e2 > 4 || e2 < -190) return 0;
    int bits = 64 - __builtin_clzll(mant) + e2; /* 2^(bits-1) <= x < 2^bits */
    int k = 16 - (int)((bits - 1) * 0.30102999566398120); /* an estimate, corrected below */
    for (int tries = 0; tries < 4; tries++) {
        if (k < 0 || k > 38) return 0;
        u128 lo = (u128)mant * P10[k][1], hi = (u128)mant * P10[k][0];
        u128 mid = (lo >> 64) + (uint64_t)hi;
        uint64_t p[3] = {(uint64_t)lo, (uint64_t)mid, (uint64_t)(hi >> 64) + (uint64_t)(mid >> 64)};
        uint64_t ip[3];
        int s = -e2, up = 0;
        if (s > 0) {
            shr3(p, s, ip);
            up = bit3(p, s - 1) && (below3(p, s - 1) || (ip[0] & 1)); /* to nearest, ties to even */
        } else { /* x = mant * 2^e2 with e2 <= 4 and mant * 10^k < 2^57 * 10 here */
            if (p[1] || p[2] || (p[0] >> 59)) { k--; continue; }
            ip[0] = p[0] << -s, ip[1] = ip[2] = 0;
        }
        if (ip[1] || ip[2] || ip[0] >= P10_17) { k--; continue; }
        if (ip[0] < P10_16) { k++; continue; }
        uint64_t v = ip[0] + (uint64_t)up;
        int d = 16 - k;
        if (v == P10_17) v = P10_16, d++;
        *q = v, *d10 = d;
        return 1;
    }
    return 0;
}

int kt_g17(double x, char *buf)
{
    uint64_t b;
    memcpy(&b, &x, 8);
    int neg = (int)(b >> 63), be = (int)((b >> 52) & 0x7ff);
    uint64_t frac = b & ((1ull << 52) - 1);
    char *o = buf;
    if (be == 0 && frac == 0) {
        if (neg) *o++ = '-';
        *o++ = '0';
        *o = '\0';
        return (int)(o - buf);
    }
    uint64_t q;
    int d10;
    if (be == 0 || be == 0x7ff || !digits17(frac | (1ull << 52), be - 1075, &q, &d10))
        return snprintf(buf, KT_G17_MAX, "%.17g", x);
    char dg[17];
    for (int i = 16; i >= 0; i--) dg[i] = (char)('0' + q % 10), q /= 10;
    int nd = 17;
    while (nd > 1 && dg[nd - 1] == '0') nd--;
    if (neg) *o++ = '-';
    if (d10 < -4 || d10 >= 17) { /* d.ddde-XX */
        *o++ = dg[0];
        if (nd > 1) {
            *o++ = '.';
            memcpy(o, dg + 1, (size_t)nd - 1);
            o += nd - 1;
        }
        int ex = d10 < 0 ? -d10 : d10;
        *o++ = 'e';
        *o++ = d10 < 0 ? '-' : '+';
        if (ex >= 100) *o++ = (char)('0' + ex / 100);
        *o++ = (char)('0' + ex / 10 % 10);
        *o++ = (char)('0' + ex % 10);
    } else if (d10 >= 0) { /* ddd.ddd */
        memcpy(o, dg, (size_t)d10 + 1);
        o += d10 + 1;
        if (nd > d10 + 1) {
            *o++ = '.';
            memcpy(o, dg + d10 + 1, (size_t)(nd - d10 - 1));
            o += nd - d10 - 1;
        }
    } else { /* 0.000ddd */
        *o++ = '0';
        *o++ = '.';
        for (int i = 0; i < -d10 - 1; i++) *o++ = '0';
        memcpy(o, dg, (size_t)nd);
        o += nd;
    }
    *o = '\0';
    return (int)(o - buf);
}

int kt_itoa(int v, char *buf)
{
    char t[12];
    int n = 0;
    unsigned u = v < 0 ? 0u - (unsigned)v : (unsigned)v;
    do t[n++] = (char)('0' + u % 10), u /= 10;
    while (u);
    char *o = buf;
    if (v < 0) *o++ = '-';
    while (n) *o++ = t[--n];
    *o = '\0';
    return (int)(o - buf);
}
