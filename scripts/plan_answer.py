#!/usr/bin/env python3
"""plan_answer.py PLAN.json [PNG]: the answer of an lri-plan run as one line, the words that
README.md's picture of plan.html (docs/plan.png) carries in its alt text and in the PNG's tEXt
chunk "Description" (scripts/plan-png.sh writes both; tests/readme_plan.sh checks them).
With PNG: the Description the PNG holds instead (empty when none)."""
import json
import struct
import sys


def answer(plan):
    p = plan["plan"]
    kind, arcs = p["incisions"], p.get("arcs", [])
    if not arcs:
        what = "no arc"
    elif kind == "single":
        what = f"a single arc, {arcs[0]['arc_deg']:g} deg"
    elif kind == "paired":
        what = f"paired arcs, 2 x {arcs[0]['arc_deg']:g} deg"
    else:
        what = f"unequal arcs, {arcs[0]['arc_deg']:g} + {arcs[1]['arc_deg']:g} deg"
    return f"lri-plan --fast: {what}, predicted residual {p['predicted_residual_D']:.3f} D"


def png_description(path):
    with open(path, "rb") as f:
        data = f.read()
    if data[:8] != b"\x89PNG\r\n\x1a\n":
        raise ValueError(f"{path}: not a PNG")
    at = 8
    while at + 8 <= len(data):
        n, kind = struct.unpack(">I4s", data[at:at + 8])
        body = data[at + 8:at + 8 + n]
        if kind == b"tEXt" and body.startswith(b"Description\0"):
            return body[len(b"Description\0"):].decode("latin-1")
        at += 12 + n
    return ""


if __name__ == "__main__":
    if len(sys.argv) == 3:
        print(png_description(sys.argv[2]))
    else:
        print(answer(json.load(open(sys.argv[1]))))
