/* b64.h: base64 (RFC 4648, standard alphabet, '=' padding), for data URIs in the HTML report. */
#ifndef KT_B64_H
#define KT_B64_H

#include <stddef.h>
#include <stdio.h>

/* Length of the encoding of n bytes (without a terminating NUL). */
size_t kt_b64_len(size_t n);

/* Encode n bytes into out (kt_b64_len(n) + 1 chars, NUL-terminated); returns the length. */
size_t kt_b64_encode(const unsigned char *in, size_t n, char *out);

/* Encode n bytes onto a stream; 0 on success, -1 on a write error. */
int kt_b64_write(FILE *f, const unsigned char *in, size_t n);

#endif
