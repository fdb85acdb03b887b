/* b64.c: base64 encoding (RFC 4648 section 4). */
#include "b64.h"

static const char ALPHA[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";

size_t kt_b64_len(size_t n) { return 4 * ((n + 2) / 3); }

/* One group of up to 3 bytes (k of them) as 4 characters. */
static void group(const unsigned char *in, size_t k, char *out)
{
    unsigned v = (unsigned)in[0] << 16 | (k > 1 ? (unsigned)in[1] << 8 : 0) | (k > 2 ? in[2] : 0);
    out[0] = ALPHA[v >> 18 & 63];
    out[1] = ALPHA[v >> 12 & 63];
    out[2] = k > 1 ? ALPHA[v >> 6 & 63] : '=';
    out[3] = k > 2 ? ALPHA[v & 63] : '=';
}

size_t kt_b64_encode(const unsigned char *in, size_t n, char *out)
{
    size_t o = 0;
    for (size_t i = 0; i < n; i += 3, o += 4) group(in + i, n - i < 3 ? n - i : 3, out + o);
    out[o] = '\0';
    return o;
}

int kt_b64_write(FILE *f, const unsigned char *in, size_t n)
{
    char buf[4 * 256];
    size_t fill = 0;
    for (size_t i = 0; i < n; i += 3) {
        group(in + i, n - i < 3 ? n - i : 3, buf + fill);
        fill += 4;
        if (fill == sizeof buf || i + 3 >= n) {
            if (fwrite(buf, 1, fill, f) != fill) return -1;
            fill = 0;
        }
    }
    return 0;
}
