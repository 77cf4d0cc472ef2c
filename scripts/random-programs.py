#!/usr/bin/env python3
"""Writes seeded random programs of the kinds a shop runs, each a little
different, for a stress run of `fairpath smooth` checked by
scripts/independent-check.py (which reads them with LinuxCNC's `rs274`).

Kinds (one per program, in turn):
  raster   3D finishing raster over a random smooth surface: zigzag or
           one-way (rapids back), random step-over, segment length and
           rounding, optional micro jogs before the step-overs;
  pocket   offset rectangles with R-word corner arcs at a few depths, in
           G17, G18 or G19, mm or inch;
  spiral   an Archimedean spiral of chords, or helical G2/G3 turns;
  walk     a random walk of lines: sharp corners, near-reversals, tiny,
           zero-length and collinear moves;
  mixed    G91 step-overs, feed changes inside a run, comments, N numbers
           and block-delete lines between the moves;
  circles  circles sampled as chords and rounded to 3 or 4 decimals
           (CAM noise), with tangent lead-in lines;
  engrave  engraving and V-carving, mm or inch: glyphs 1 to 20 mm across,
           closed outlines of straight and bulged edges or single-line
           strokes with sharp corners that run back over themselves, in
           chords of 0.01 to 0.3 mm; on some glyphs V-carve corner spikes
           (out along the bisector and up to Z0 at each sharp corner, and
           back), ramped entries; each glyph plunged from a clearance
           height and left by a rapid. Not in the default rotation.

Usage: scripts/random-programs.py OUTDIR [COUNT] [SEED] [KINDS]
COUNT defaults to 30 and SEED to 1; KINDS, a comma-separated list of the
kinds above, defaults to the first six (raster to circles), which the
programs take in turn. The same arguments write the same files.
"""
import math
import os
import random
import sys

OUT = sys.argv[1]
COUNT = int(sys.argv[2]) if len(sys.argv) > 2 else 30
SEED = int(sys.argv[3]) if len(sys.argv) > 3 else 1
os.makedirs(OUT, exist_ok=True)


def num(v, places):
    s = ("%." + str(places) + "f") % v
    s = s.rstrip("0").rstrip(".")
    return "0" if s in ("-0", "") else s


def write(name, lines):
    with open(os.path.join(OUT, name), "w") as fh:
        fh.write("\n".join(lines) + "\nM2\n")


def surface(rng):
    terms = [
        (rng.uniform(0.2, 3.0), rng.uniform(0.02, 0.3), rng.uniform(0.02, 0.3), rng.uniform(0, 6.3))
        for _ in range(rng.randint(1, 4))
    ]
    return lambda x, y: sum(a * math.sin(fx * x + fy * y + p) for a, fx, fy, p in terms)


def raster(rng):
    z = surface(rng)
    w, h = rng.uniform(10, 60), rng.uniform(5, 30)
    step = rng.uniform(0.2, 2.0)
    seg = rng.uniform(0.05, 1.0)
    places = rng.choice([3, 4, 5])
    zigzag = rng.random() < 0.7
    jogs = rng.random() < 0.4
    feed = rng.choice([600, 1500, 3000, 6000])
    out = ["G21 G90 G17", "G64 P%s" % num(rng.choice([0.01, 0.05, 0.1]), 3), "M3 S12000",
           "G0 Z10", "G0 X0 Y0", "G1 Z%s F%d" % (num(z(0, 0), places), feed // 3)]
    y, forward = 0.0, True
    n = max(2, int(w / seg))
    while y <= h:
        xs = [w * i / n for i in range(n + 1)]
        if not forward:
            xs.reverse()
        for i, x in enumerate(xs):
            out.append("G1 X%s Y%s Z%s%s" % (num(x, places), num(y, places), num(z(x, y), places),
                                           " F%d" % feed if i == 0 else ""))
        if jogs:
            x = xs[-1] + (1e-3 if forward else -1e-3) * rng.choice([1, -1])
            out.append("G1 X%s Y%s Z%s" % (num(x, places), num(y, places), num(z(x, y), places)))
        y += step
        if zigzag:
            forward = not forward
        else:
            out += ["G0 Z10", "G0 X0 Y%s" % num(y, places)]
            out.append("G1 Z%s F%d" % (num(z(0, y), places), feed // 3))
    out.append("G0 Z10")
    write_name = "raster"
    return write_name, out


def pocket(rng):
    inch = rng.random() < 0.4
    u = 25.4 if inch else 1.0
    plane = rng.choice(["G17", "G18", "G19"])
    axes = {"G17": ("X", "Y", "Z"), "G18": ("Z", "X", "Y"), "G19": ("Y", "Z", "X")}[plane]
    a, b, c = axes
    places = 4 if inch else 3
    out = ["%s %s G90" % ("G20" if inch else "G21", plane), "M3 S9000", "G0 %s%s" % (c, num(5 / u, places))]
    cx, cy = rng.uniform(-20, 20) / u, rng.uniform(-20, 20) / u
    for depth in [-(k + 1) * rng.uniform(0.2, 1.5) / u for k in range(rng.randint(1, 3))]:
        hw, hh = rng.uniform(5, 25) / u, rng.uniform(5, 25) / u
        r = rng.uniform(0.3, 3.0) / u
        out += ["G0 %s%s %s%s" % (a, num(cx - hw + r, places), b, num(cy - hh, places)),
                "G1 %s%s F%d" % (c, num(depth, places), rng.choice([100, 300, 800]))]
        for k in range(rng.randint(1, 5)):
            x0, y0, x1, y1 = cx - hw, cy - hh, cx + hw, cy + hh
            if x1 - x0 < 3 * r or y1 - y0 < 3 * r:
                break
            d = rng.choice(["G2", "G3"]) if rng.random() < 0.2 else "G3"
            if d == "G3":
                out += [
                    "G1 %s%s %s%s" % (a, num(x0 + r, places), b, num(y0, places)),
                    "G1 %s%s" % (a, num(x1 - r, places)),
                    "G3 %s%s %s%s R%s" % (a, num(x1, places), b, num(y0 + r, places), num(r, places)),
                    "G1 %s%s" % (b, num(y1 - r, places)),
                    "G3 %s%s %s%s R%s" % (a, num(x1 - r, places), b, num(y1, places), num(r, places)),
                    "G1 %s%s" % (a, num(x0 + r, places)),
                    "G3 %s%s %s%s R%s" % (a, num(x0, places), b, num(y1 - r, places), num(r, places)),
                    "G1 %s%s" % (b, num(y0 + r, places)),
                    "G3 %s%s %s%s R%s" % (a, num(x0 + r, places), b, num(y0, places), num(r, places)),
                ]
            else:
                out += [
                    "G1 %s%s %s%s" % (a, num(x0, places), b, num(y0 + r, places)),
                    "G1 %s%s" % (b, num(y1 - r, places)),
                    "G2 %s%s %s%s R%s" % (a, num(x0 + r, places), b, num(y1, places), num(r, places)),
                    "G1 %s%s" % (a, num(x1 - r, places)),
                    "G2 %s%s %s%s R%s" % (a, num(x1, places), b, num(y1 - r, places), num(r, places)),
                    "G1 %s%s" % (b, num(y0 + r, places)),
                    "G2 %s%s %s%s R%s" % (a, num(x1 - r, places), b, num(y0, places), num(r, places)),
                    "G1 %s%s" % (a, num(x0 + r, places)),
                    "G2 %s%s %s%s R%s" % (a, num(x0, places), b, num(y0 + r, places), num(r, places)),
                ]
            hw, hh = hw - rng.uniform(0.5, 3) / u, hh - rng.uniform(0.5, 3) / u
        out.append("G0 %s%s" % (c, num(5 / u, places)))
    return "pocket", out


def spiral(rng):
    out = ["G21 G90 G17", "G0 Z5", "G0 X0 Y0", "G1 Z-1 F300"]
    if rng.random() < 0.5:
        turns, pitch = rng.uniform(2, 8), rng.uniform(0.3, 3)
        per_turn = rng.randint(12, 400)
        places = rng.choice([3, 4])
        for i in range(1, int(turns * per_turn) + 1):
            t = 2 * math.pi * i / per_turn
            r = pitch * t / (2 * math.pi)
            out.append("G1 X%s Y%s F%d" % (num(r * math.cos(t), places), num(r * math.sin(t), places), 1200))
    else:
        r = rng.uniform(0.5, 10)
        out.append("G1 X%s Y0 F600" % num(r, 4))
        z = -1.0
        for _ in range(rng.randint(1, 6)):
            z -= rng.uniform(0.1, 1.0)
            d = rng.choice(["G2", "G3"])
            out.append("%s X%s Y0 Z%s I%s J0" % (d, num(r, 4), num(z, 4), num(-r, 4)))
        out.append("G1 X0 Y0")
    out.append("G0 Z5")
    return "spiral", out


def walk(rng):
    out = ["G21 G90 G17", "G0 Z5", "G0 X0 Y0 Z0", "G1 F%d" % rng.choice([200, 1000, 5000])]
    x = y = z = 0.0
    heading = 0.0
    places = rng.choice([3, 4, 5])
    for _ in range(rng.randint(20, 400)):
        kind = rng.random()
        if kind < 0.1:
            heading += math.pi + rng.uniform(-0.3, 0.3)  # near-reversal
        elif kind < 0.3:
            heading += rng.uniform(-2.0, 2.0)
        else:
            heading += rng.uniform(-0.2, 0.2)
        length = rng.choice([rng.uniform(0.001, 0.05), rng.uniform(0.05, 2), rng.uniform(2, 20)])
        if rng.random() < 0.03:
            length = 0.0
        x += length * math.cos(heading)
        y += length * math.sin(heading)
        if rng.random() < 0.2:
            z += rng.uniform(-0.3, 0.3)
        out.append("X%s Y%s Z%s" % (num(x, places), num(y, places), num(z, places)))
    out.append("G0 Z5")
    return "walk", out


def mixed(rng):
    out = ["(mixed: G91 step-overs, feeds, comments)", "G21 G90 G17 G94", "G0 Z3", "G0 X0 Y0",
           "N10 G1 Z-0.5 F200"]
    n = 20
    for row in range(rng.randint(2, 6)):
        out.append("G90")
        for i in range(rng.randint(5, 40)):
            xx = (i * rng.uniform(0.2, 1.5)) * (1 if row % 2 == 0 else -1)
            line = "G1 X%s" % num(xx, 3)
            if rng.random() < 0.3:
                line += " Z%s" % num(-0.5 + rng.uniform(-0.1, 0.1), 3)
            if rng.random() < 0.1:
                line += " F%d" % rng.choice([150, 200, 400])
            if rng.random() < 0.1:
                line = "N%d %s" % (n, line)
                n += 10
            if rng.random() < 0.08:
                line += " (note %d)" % i
            out.append(line)
            if rng.random() < 0.05:
                out.append("/G1 Z%s" % num(rng.uniform(-0.6, -0.4), 3))
            if rng.random() < 0.05:
                out.append("(comment between moves)")
        out += ["G91", "G1 Y%s" % num(rng.uniform(0.2, 2.0), 3)]
    out += ["G90", "G0 Z3"]
    return "mixed", out


def circles(rng):
    out = ["G21 G90 G17", "G0 Z5"]
    for _ in range(rng.randint(1, 4)):
        cx, cy, r = rng.uniform(-30, 30), rng.uniform(-30, 30), rng.uniform(0.5, 15)
        n = rng.randint(8, 720)
        places = rng.choice([3, 4])
        out += ["G0 X%s Y%s" % (num(cx + r, places), num(cy - 3, places)), "G1 Z-0.2 F300",
                "G1 X%s Y%s F1500" % (num(cx + r, places), num(cy, places))]
        for i in range(1, n + 1):
            t = 2 * math.pi * i / n
            out.append("G1 X%s Y%s" % (num(cx + r * math.cos(t), places), num(cy + r * math.sin(t), places)))
        out += ["G1 X%s Y%s" % (num(cx + r, places), num(cy + 3, places)), "G0 Z5"]
    return "circles", out


def engrave(rng):
    inch = rng.random() < 0.4
    u = 25.4 if inch else 1.0
    places = rng.choice([4, 5]) if inch else rng.choice([3, 4])
    depth = rng.uniform(0.05, 1.5)
    clear = rng.choice([0.25, 1.0, 5.0])
    out = ["%s G90 G17" % ("G20" if inch else "G21"), "G64 P%s" % num(rng.choice([0.005, 0.01, 0.05]) / u, places),
           "F%s" % num(rng.choice([100, 300, 800, 2000]) / u, 2), "M3 S18000", "(engraving)",
           "G0 Z%s" % num(clear / u, places)]
    chord = rng.uniform(0.01, 0.3)

    def p(x, y, z=None):
        w = "X%s Y%s" % (num(x / u, places), num(y / u, places))
        return w + ("" if z is None else " Z%s" % num(z / u, places))

    def edge(a, b):
        # Chords from a to b (b included): straight, or bulged to an arc.
        bulge = 0.0 if rng.random() < 0.5 else rng.uniform(-0.3, 0.3)
        (xa, ya), (xb, yb) = a, b
        n = max(1, int(math.hypot(xb - xa, yb - ya) / chord))
        pts = []
        for i in range(1, n + 1):
            t = i / n
            h = 4 * bulge * t * (1 - t) * math.hypot(xb - xa, yb - ya)
            nx, ny = -(yb - ya), xb - xa
            nn = math.hypot(nx, ny) or 1.0
            pts.append((xa + t * (xb - xa) + h * nx / nn, ya + t * (yb - ya) + h * ny / nn))
        return pts

    ox = 0.0
    for _ in range(rng.randint(2, 6)):
        size = rng.uniform(1.0, 20.0)
        cx, cy = ox + size, rng.uniform(-5, 5)
        ox += 2.5 * size
        corners = []
        if rng.random() < 0.5:
            # A glyph outline: a closed polygon of straight and bulged edges.
            k = rng.randint(3, 8)
            vs = []
            for i in range(k):
                t = 2 * math.pi * (i + rng.uniform(-0.3, 0.3)) / k
                r = 0.5 * size * rng.uniform(0.4, 1.0)
                vs.append((cx + r * math.cos(t), cy + r * math.sin(t)))
            pts = [vs[0]]
            for i in range(k):
                pts += edge(vs[i], vs[(i + 1) % k])
                corners.append(len(pts) - 1)
            corners.pop()
        else:
            # A single-line stroke with sharp corners, running back over itself.
            pts = [(cx, cy)]
            heading = rng.uniform(0, 2 * math.pi)
            for _ in range(rng.randint(3, 12)):
                if rng.random() < 0.25:
                    heading += math.pi  # back along the stroke
                else:
                    heading += rng.choice([-1, 1]) * rng.uniform(0.5, 2.6)
                length = rng.uniform(0.2, size)
                x0, y0 = pts[-1]
                pts += edge((x0, y0), (x0 + length * math.cos(heading), y0 + length * math.sin(heading)))
                corners.append(len(pts) - 1)
            corners.pop()
        spikes = rng.random() < 0.6
        x0, y0 = pts[0]
        out.append("G0 " + p(x0, y0))
        if rng.random() < 0.4 and len(pts) > 3:
            # A ramped entry: down to depth along the first chords.
            out.append("G1 Z0")
            k = min(len(pts) - 1, rng.randint(2, 6))
            for j in range(1, k + 1):
                out.append("G1 " + p(*pts[j], z=-depth * j / k))
            start = k + 1
        else:
            out.append("G1 Z%s" % num(-depth / u, places))
            start = 1
        for j in range(start, len(pts)):
            x, y = pts[j]
            out.append("G1 " + p(x, y, z=-depth if rng.random() < 0.3 else None))
            if spikes and j in corners and j + 1 < len(pts):
                # A V-carve corner spike (90-degree bit): out along the
                # corner's bisector as far as it is deep, up to Z0, and back.
                (xa, ya), (xb, yb) = pts[j - 1], pts[j + 1]
                da, db = math.hypot(x - xa, y - ya) or 1.0, math.hypot(xb - x, yb - y) or 1.0
                bx, by = (x - xa) / da - (xb - x) / db, (y - ya) / da - (yb - y) / db
                nb = math.hypot(bx, by)
                if nb > 0.5:
                    out.append("G1 " + p(x + depth * bx / nb, y + depth * by / nb, z=0.0))
                    out.append("G1 " + p(x, y, z=-depth))
        out.append("G0 Z%s" % num(clear / u, places))
    return "engrave", out


ALL_KINDS = {f.__name__: f for f in [raster, pocket, spiral, walk, mixed, circles, engrave]}
KINDS = [raster, pocket, spiral, walk, mixed, circles]
if len(sys.argv) > 4:
    try:
        KINDS = [ALL_KINDS[k] for k in sys.argv[4].split(",")]
    except KeyError as e:
        sys.exit("unknown kind %s (kinds: %s)" % (e, ", ".join(ALL_KINDS)))
for i in range(COUNT):
    rng = random.Random(SEED * 1000003 + i)
    name, lines = KINDS[i % len(KINDS)](rng)
    write("r%03d_%s.ngc" % (i, name), lines)
