/* html.c: the frame of a self-contained HTML page. */
#include "html.h"
#include "b64.h"
#include "svg.h"

void kt_html_text(FILE *f, const char *s) { kt_svg_escape(f, s); }

void kt_html_begin(FILE *f, const char *title, const char *css)
{
    fputs("<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n"
          "<meta http-equiv=\"Content-Security-Policy\" content=\"default-src 'none'; "
          "img-src data:; style-src 'unsafe-inline'\">\n"
          "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n<title>", f);
    kt_svg_escape(f, title);
    fprintf(f, "</title>\n<style>\n%s</style>\n</head>\n<body>\n", css);
}

void kt_html_end(FILE *f) { fputs("</body>\n</html>\n", f); }

int kt_html_img(FILE *f, const char *mime, const unsigned char *data, size_t n, const char *alt,
                const char *cls)
{
    fprintf(f, "<img class=\"%s\" alt=\"", cls);
    kt_svg_escape(f, alt);
    fprintf(f, "\" src=\"data:%s;base64,", mime);
    int rc = kt_b64_write(f, data, n);
    fputs("\">\n", f);
    return rc || ferror(f) ? -1 : 0;
}
