/* html.h: a self-contained HTML page: inline CSS, images as base64 data URIs, no scripts and
 * a Content-Security-Policy that forbids every fetch, so the page opens offline (USB stick)
 * and a browser refuses anything that would reach the network. */
#ifndef KT_HTML_H
#define KT_HTML_H

#include <stddef.h>
#include <stdio.h>

/* The one style sheet of every keratome page (plan.html, report.html, compare.html): the page
 * (body, main column, header band, section titles, cards, figures, tables) and the drawings'
 * classes (the eye: .sclera .cornea .merid .ring .oz .kzone .inc .main .end .steep; plots:
 * .tick .axtitle .lbl .grid .zero .frame, series .s1-.s5, .chosen .target .band; vectors .v-*;
 * the section .sec-*), in one place so the pages look alike. */
extern const char kt_html_css[];

/* <!DOCTYPE html> ... <body>: the title (escaped) and the style sheet kt_html_css. */
void kt_html_begin(FILE *f, const char *title);
void kt_html_end(FILE *f);

/* Escaped text (the SVG writer's escaping). */
void kt_html_text(FILE *f, const char *s);

/* <img> of the bytes of an image of the given MIME type as a data URI; alt is escaped.
 * 0, or -1 on a write error. */
int kt_html_img(FILE *f, const char *mime, const unsigned char *data, size_t n, const char *alt,
                const char *cls);

#endif
