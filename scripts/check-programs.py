#!/usr/bin/env python3
"""Writes five small programs of the kinds a shop runs, for
scripts/independent-check.py: an inch pocket with R-word corner arcs at
three depths (pocket_inch.ngc), a V-carve engraving of short 3D moves with
out-and-back spurs and retraced strokes (vcarve.ngc), a finishing pass of
XZ arcs with incremental (G91) Y step-overs (finish_xz.ngc), helices, full
circles, a P-word of turns and YZ/XZ arcs (helix_planes.ngc), and a dense
3D raster with micro jogs before each step-over (raster_jogs.ngc).
Seeded: the same files every time.

Usage: scripts/check-programs.py OUTDIR
"""
import math
import os
import random
import sys

OUT = sys.argv[1]
os.makedirs(OUT, exist_ok=True)
random.seed(7)


def write(name, lines):
    with open(os.path.join(OUT, name), "w") as fh:
        fh.write("\n".join(lines) + "\nM2\n")


def f(v):
    """A number as a CAM system writes it: 4 decimals, no trailing zeros."""
    return ("%.4f" % v).rstrip("0").rstrip(".") if abs(v) >= 1e-9 else "0"


def pocket_inch():
    out = ["%", "(pocket, inch)", "G20 G17 G90 G64 P0.001", "S10000 M3", "G0 Z0.1"]
    for depth in (-0.05, -0.1, -0.15):
        out += ["G0 X0.5 Y0.5", "G1 Z%s F20" % f(depth)]
        for k in range(5):
            a = 0.5 - 0.08 * k
            x0, y0, x1, y1, r = 1.0 - a, 1.0 - a, 2.0 + a, 1.6 + a, 0.05
            if x1 - x0 < 3 * r:
                break
            out += [
                "G1 X%s Y%s F40" % (f(x0 + r), f(y0)),
                "G1 X%s" % f(x1 - r),
                "G3 X%s Y%s R%s" % (f(x1), f(y0 + r), f(r)),
                "G1 Y%s" % f(y1 - r),
                "G3 X%s Y%s R%s" % (f(x1 - r), f(y1), f(r)),
                "G1 X%s" % f(x0 + r),
                "G3 X%s Y%s R%s" % (f(x0), f(y1 - r), f(r)),
                "G1 Y%s" % f(y0 + r),
                "G3 X%s Y%s R%s" % (f(x0 + r), f(y0), f(r)),
            ]
        out.append("G0 Z0.1")
    out.append("M5")
    write("pocket_inch.ngc", out)


def vcarve():
    out = ["G21 G90 G17 G64 P0.01", "M3 S18000", "G0 Z2"]
    for _ in range(12):
        x, y = random.uniform(0, 40), random.uniform(0, 20)
        out += ["G0 X%s Y%s" % (f(x), f(y)), "G1 Z0 F300"]
        pts = []
        ang = random.uniform(0, 6.28)
        for i in range(random.randint(30, 80)):
            ang += random.uniform(-0.6, 0.6)
            st = random.uniform(0.02, 0.3)
            x += st * math.cos(ang)
            y += st * math.sin(ang)
            z = -0.2 - 0.15 * math.sin(i * 0.3)
            pts.append((x, y, z))
            out.append("G1 X%s Y%s Z%s F600" % (f(x), f(y), f(z)))
            if random.random() < 0.1:
                # An out-and-back spur to the surface.
                sx, sy = x + 0.03 * math.cos(ang + 1.2), y + 0.03 * math.sin(ang + 1.2)
                out.append("G1 X%s Y%s Z0" % (f(sx), f(sy)))
                out.append("G1 X%s Y%s Z%s" % (f(x), f(y), f(z)))
        # The stroke retraced, a little deeper.
        for (x, y, z) in reversed(pts[:-1]):
            out.append("G1 X%s Y%s Z%s" % (f(x + 0.001), f(y), f(z - 0.01)))
        out.append("G0 Z2")
    write("vcarve.ngc", out)


def finish_xz():
    out = ["G21 G90 G64 P0.02", "G0 Z10", "G0 X0 Y0", "G1 Z0 F500", "G18"]
    x = 0.0
    for p in range(10):
        d = 1 if p % 2 == 0 else -1
        for _ in range(6):
            dx = d * 10.0
            r = random.uniform(30, 200)
            random.uniform(-0.8, 0.8)  # kept: the stream of numbers stays the same
            g = "G2" if random.random() < 0.5 else "G3"
            out.append("%s X%s Z%s R%s F2000" % (g, f(x + dx), f(random.uniform(0, 1.5)), f(r)))
            x += dx
        out += ["G91 G1 Y1.5", "G90"]
    out.append("G17 G0 Z10")
    write("finish_xz.ngc", out)


def helix_planes():
    write("helix_planes.ngc", [
        "G21 G90 G17", "G0 X10 Y0 Z5", "G1 Z0 F400",
        "G2 X10 Y0 Z-1 I-10 J0 F800", "G2 X10 Y0 Z-3 I-10 J0 P2",
        "G3 X-10 Y0 Z-3.5 R10", "G3 X10 Y0 I10 J0", "G1 X12", "G0 Z5",
        "G0 X0 Y0", "G1 Z0 F300", "G19 G2 Y5 Z0 J2.5 K0", "G3 Y10 Z0 R2.5",
        "G17 G1 X5", "G18 G2 X10 Z0 I2.5 K0", "G17", "G0 Z5",
    ])


def raster_jogs():
    out = ["G21 G90 G64 P0.01", "G0 X0 Y0 Z5", "G1 Z0 F1000"]
    for row in range(25):
        y = row * 0.4
        xs = [i * 0.15 for i in range(200)]
        if row % 2:
            xs = xs[::-1]
        for x in xs:
            z = 0.5 * math.sin(x * 0.2) * math.cos(y * 0.3)
            out.append("G1 X%s Y%s Z%s F3000" % (f(x), f(y), f(z)))
        # A 0.01 mm jog on, then the step-over.
        out.append("G1 X%s Y%s" % (f(xs[-1] + (0.01 if row % 2 == 0 else -0.01)), f(y)))
        out.append("G1 Y%s" % f(y + 0.4))
    out.append("G0 Z5")
    write("raster_jogs.ngc", out)


pocket_inch()
vcarve()
finish_xz()
helix_planes()
raster_jogs()
