/* html.h: a self-contained HTML page: inline CSS, images as base64 data URIs, no scripts and
 * a Content-Security-Policy that forbids every fetch, so the page opens offline (USB stick)
 * and a browser refuses anything that would reach the network. */
#ifndef KT_HTML_H
#define KT_HTML_H

#include <stddef.h>
#include <stdio.h>

/* <!DOCTYPE html> ... <body>: the title (escaped) and the style sheet (verbatim). */
void kt_html_begin(FILE *f, const char *title, const char *css);
void kt_html_end(FILE *f);

/* Escaped text (the SVG writer's escaping). */
void kt_html_text(FILE *f, const char *s);

/* <img> of the bytes of an image of the given MIME type as a data URI; alt is escaped.
 * 0, or -1 on a write error. */
int kt_html_img(FILE *f, const char *mime, const unsigned char *data, size_t n, const char *alt,
                const char *cls);

#endif
