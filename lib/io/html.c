/* html.c: the frame of a self-contained HTML page. */
#include "html.h"
#include "b64.h"
#include "svg.h"

void kt_html_text(FILE *f, const char *s) { kt_svg_escape(f, s); }

const char kt_html_css[] =
    /* the page */
    "body{font-family:'DejaVu Sans',Helvetica,Arial,sans-serif;color:#1d232a;background:#f4f5f7;margin:0}\n"
    "main{max-width:1180px;margin:0 auto;padding:18px 26px 40px}\n"
    "header{background:#18324a;color:#fff;padding:18px 26px}\n"
    "header h1{margin:0;font-size:24px;font-weight:600}header p{margin:4px 0 0;color:#c9d6e3;font-size:14px}\n"
    "h2{font-size:18px;margin:28px 0 8px;border-bottom:2px solid #d5dae0;padding-bottom:4px}\n"
    ".cards{display:flex;flex-wrap:wrap;gap:12px;margin-top:16px}\n"
    ".card{background:#fff;border-radius:8px;padding:10px 14px;box-shadow:0 1px 3px rgba(0,0,0,.12);min-width:150px}\n"
    ".card b{display:block;font-size:20px}.card>span{font-size:12px;color:#5b6670}\n"
    ".row{display:flex;flex-wrap:wrap;gap:16px}\n"
    "figure{background:#fff;margin:0;padding:10px 12px;border-radius:8px;box-shadow:0 1px 3px rgba(0,0,0,.12);flex:1 1 420px}\n"
    "figure img,figure svg{width:100%;height:auto;display:block}\n"
    "figcaption{font-size:13px;color:#3d4750;margin-top:6px;line-height:1.4}\n"
    "table{border-collapse:collapse;font-size:13px;background:#fff;margin-bottom:10px}"
    "td,th{padding:4px 10px;border-bottom:1px solid #e2e6ea;text-align:left}\n"
    "th{background:#eef1f4}td.n{text-align:right;font-variant-numeric:tabular-nums}\n"
    "pre{background:#fff;padding:8px;font-size:12px;overflow:auto;border-radius:6px}\n"
    ".note{font-size:13px;color:#3d4750}\n"
    ".verdict{font-size:16px;font-weight:600;margin:14px 0 0;padding:10px 14px;border-radius:8px;background:#fff;"
    "border-left:6px solid #c0392b}.verdict.ok{border-left-color:#27ae60}\n"
    ".strip{display:flex;flex-wrap:wrap;gap:8px}.strip figure{flex:0 1 210px;padding:6px}\n"
    /* drawings: text, axes */
    "svg text{font-family:'DejaVu Sans',Helvetica,Arial,sans-serif;fill:#1d232a}\n"
    ".tick{font-size:11px}.axtitle{font-size:12px}.lbl{font-size:12px}.small{font-size:10px;fill:#5b6670}\n"
    ".clock{font-size:13px;font-weight:600;fill:#18324a}.nsti{font-size:15px;font-weight:700;fill:#18324a}\n"
    ".grid{stroke:#e4e7eb;stroke-width:1}.zero{stroke:#8a939b;stroke-width:1}.frame{fill:none;stroke:#8a939b}\n"
    ".bar{stroke:#1d232a;stroke-width:3}\n"
    /* the eye */
    ".sclera{fill:#fbfaf6;stroke:none}.cornea{fill:#e8f1f8;stroke:#7f97ad;stroke-width:2}\n"
    ".merid{stroke:#b8c3cc;stroke-width:1}.ring{fill:none;stroke:#6b7a88;stroke-width:1.2;stroke-dasharray:5 4}\n"
    ".oz{fill:none;stroke:#3a7d44;stroke-width:1.2;stroke-dasharray:2 3}.kzone{fill:none;stroke:#8a939b;stroke-dasharray:2 2}\n"
    ".inc{fill:none;stroke:#c0392b;stroke-width:8;stroke-linecap:round}\n"
    ".main{fill:none;stroke:#1f6fb4;stroke-width:10;stroke-linecap:butt}\n"
    ".end{fill:#fff;stroke:#c0392b;stroke-width:2}\n"
    ".halo{paint-order:stroke;stroke:#fff;stroke-width:3px;stroke-linejoin:round}.leader{stroke:#c0392b;stroke-width:1}\n"
    ".eyebig{font-size:24px;font-weight:700;fill:#18324a}\n"
    ".steep{stroke:#e67e22;stroke-width:2.5;stroke-dasharray:10 5}.incm{stroke:#c0392b;stroke-width:1.2;stroke-dasharray:3 3}\n"
    /* series, the chosen point, the target, bands */
    ".s1 polyline{fill:none;stroke:#1f6fb4;stroke-width:2.2}.s1 circle{fill:#1f6fb4}\n"
    ".s2 polyline{fill:none;stroke:#d35400;stroke-width:2.2}.s2 circle{fill:#d35400}\n"
    ".s3 polyline{fill:none;stroke:#8e44ad;stroke-width:2.2;stroke-dasharray:6 3}.s3 circle{fill:#8e44ad}\n"
    ".s4 polyline{fill:none;stroke:#2c3e50;stroke-width:2.2}.s4 circle{fill:#2c3e50}\n"
    ".s5 polyline{fill:none;stroke:#16a085;stroke-width:2.2;stroke-dasharray:6 3}.s5 circle{fill:#16a085}\n"
    ".chosen{fill:none;stroke:#c0392b;stroke-width:3}.target{stroke:#27ae60;stroke-width:1.5;stroke-dasharray:6 4}\n"
    ".band{fill:#2c3e50;fill-opacity:.14;stroke:none}.torn{fill:#c0392b;fill-opacity:.75}\n"
    /* astigmatism vectors, the meridional section */
    ".v-pre line{stroke:#7f8c8d;stroke-width:3}.v-pre polygon{fill:#7f8c8d}\n"
    ".v-post line{stroke:#2c3e50;stroke-width:3}.v-post polygon{fill:#2c3e50}\n"
    ".v-tia line{stroke:#27ae60;stroke-width:3;stroke-dasharray:7 4}.v-tia polygon{fill:#27ae60}\n"
    ".v-sia line{stroke:#c0392b;stroke-width:3}.v-sia polygon{fill:#c0392b}\n"
    ".v-dv line{stroke:#e67e22;stroke-width:2;stroke-dasharray:3 3}.v-dv polygon{fill:#e67e22}\n"
    ".polar{fill:none;stroke:#dfe3e7}.sec-ref{fill:none;stroke:#c5ccd3;stroke-width:.5}\n"
    ".sec-def{fill:#f3d9b1;stroke:#9a7b4f;stroke-width:.35}.sec-axis{stroke:#5b6670;stroke-width:1}\n";

void kt_html_begin(FILE *f, const char *title)
{
    fputs("<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n"
          "<meta http-equiv=\"Content-Security-Policy\" content=\"default-src 'none'; "
          "img-src data:; style-src 'unsafe-inline'\">\n"
          "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n<title>", f);
    kt_svg_escape(f, title);
    fprintf(f, "</title>\n<style>\n%s</style>\n</head>\n<body>\n", kt_html_css);
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
