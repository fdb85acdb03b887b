/* html.h: a self-contained HTML page: inline CSS, images as base64 data URIs, no scripts and
 * a Content-Security-Policy that forbids every fetch, so the page opens offline (USB stick)
 * and a browser refuses anything that would reach the network. */
#ifndef KT_HTML_H
#define KT_HTML_H

/* The CSS every keratome page starts with (report.html, compare.html, plan.html): the body,
 * the centred main column, the header band, the section titles and the cards; a page appends
 * its own rules to it (string concatenation). */
#define KT_HTML_CSS_PAGE \
    "body{font-family:'DejaVu Sans',Helvetica,Arial,sans-serif;color:#1d232a;background:#f4f5f7;margin:0}\n" \
    "main{max-width:1180px;margin:0 auto;padding:18px 26px 40px}\n" \
    "header{background:#18324a;color:#fff;padding:18px 26px}\n" \
    "header h1{margin:0;font-size:24px;font-weight:600}header p{margin:4px 0 0;color:#c9d6e3;font-size:14px}\n" \
    "h2{font-size:18px;margin:28px 0 8px;border-bottom:2px solid #d5dae0;padding-bottom:4px}\n" \
    ".cards{display:flex;flex-wrap:wrap;gap:12px;margin-top:16px}\n" \
    ".card{background:#fff;border-radius:8px;padding:10px 14px;box-shadow:0 1px 3px rgba(0,0,0,.12);min-width:150px}\n"

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
