#!/usr/bin/python3
# Copied unchanged from the shared timing rig ../shared/tools/lcnc-master/prep.py
# (so that the project's LinuxCNC scripts stand on their own).
"""Prepare a G-code program for a timing run, and/or extract its reference polyline.

usage: prep.py IN.ngc OUT.ngc REF.csv [--g64 "P0.05 Q0"] [--feed MM_PER_MIN]
       prep.py --ref-only IN.ngc REF.csv

Supports absolute (G90) G0/G1 XYZ programs in G20 or G21 (arcs -> error).
Transformations written to OUT.ngc (the input is never modified):
  * every existing G61/G61.1/G64 (with its P/Q words) is removed and ONE line
    "G64 <args>" is inserted right after the first line that sets G20/G21
    (or at the top); tolerances are given in mm and converted to inches
    for G20 programs ("--g64 G61" or "--g64 G61.1" inserts that mode instead);
  * every F word is replaced by --feed (mm/min, converted for G20 programs),
    so the programmed feed is never the limit (default: 60*VEL*1.001);
  * rapid (G0) moves before the first feed move and after the last feed move
    are commented out; the position reached by the leading rapids is the
    start point, written to stdout as "start=x,y,z" (mm) -> the rig homes
    the machine there, so timing covers the feed moves only.
REF.csv: start point + every feed-move end point, in mm (x,y,z,line).
"""
import re
import sys

WORD = re.compile(r"([A-Z])\s*([-+]?(?:\d+\.?\d*|\.\d+))")


def strip_comments(ln):
    return re.sub(r"\(.*?\)|;.*", "", ln).upper()


def parse(lines):
    """-> list of (lineno, kind('G0'/'G1'/None), xyz_mm or None, words)"""
    scale, motion, pos = 1.0, None, [0.0, 0.0, 0.0]
    out = []
    for i, raw in enumerate(lines):
        ln = strip_comments(raw)
        words = [(m.group(1), float(m.group(2))) for m in WORD.finditer(ln)]
        gs = [v for k, v in words if k == "G"]
        for g in gs:
            if abs(g - 20) < 1e-9:
                scale = 25.4
            elif abs(g - 21) < 1e-9:
                scale = 1.0
            elif abs(g - 91) < 1e-9:
                raise SystemExit("prep.py: G91 (incremental) not supported")
            elif g in (2.0, 3.0):
                motion = "G1"   # an arc is a feed move; its end point is enough here
            elif g in (0.0, 1.0):
                motion = "G%d" % g
        axes = {k: v for k, v in words if k in "XYZ"}
        if axes and motion is None:
            raise SystemExit("prep.py: coordinates without G0/G1 (line %d)" % (i + 1))
        if axes:
            for j, a in enumerate("XYZ"):
                if a in axes:
                    pos[j] = axes[a] * scale
            out.append((i, motion, tuple(pos), scale))
        else:
            out.append((i, None, None, scale))
    return out


def reference(parsed):
    """start point (after leading rapids) and feed-move end points (mm)."""
    moves = [(i, k, p) for i, k, p, _ in parsed if k is not None]
    feeds = [n for n, (_, k, _) in enumerate(moves) if k == "G1"]
    if not feeds:
        raise SystemExit("prep.py: no feed moves")
    first, last = feeds[0], feeds[-1]
    start = moves[first - 1][2] if first > 0 else (0.0, 0.0, 0.0)
    pts = [(start, -1)] + [(p, i + 1) for i, k, p in moves[first:last + 1]]
    drop = [i for i, _, _ in moves[:first]] + [i for i, _, _ in moves[last + 1:]]
    return start, pts, drop


def write_ref(path, pts):
    with open(path, "w") as f:
        f.write("x,y,z,line\n")
        prev = None
        for p, line in pts:
            if p != prev:
                f.write("%.9f,%.9f,%.9f,%d\n" % (p[0], p[1], p[2], line))
            prev = p


def main():
    a = sys.argv[1:]
    if a and a[0] == "--ref-only":
        lines = open(a[1]).read().splitlines()
        start, pts, _ = reference(parse(lines))
        write_ref(a[2], pts)
        print("start=%.6f,%.6f,%.6f" % start)
        return
    g64, feed = "P0.05 Q0", None
    pos_args = []
    while a:
        x = a.pop(0)
        if x == "--g64":
            g64 = a.pop(0)
        elif x == "--feed":
            feed = float(a.pop(0))
        else:
            pos_args.append(x)
    src, dst, ref = pos_args
    lines = open(src).read().splitlines()
    parsed = parse(lines)
    start, pts, drop = reference(parsed)
    write_ref(ref, pts)
    units_line = next((i for i, l in enumerate(lines)
                       if re.search(r"G\s*2[01](?!\d)", strip_comments(l))), None)
    inch = any(s == 25.4 for _, _, _, s in parsed[:units_line + 1]) if units_line is not None else False
    keep = g64.strip().lower() == "keep"   # the program's own path control stays
    # G64/G61 line in program units
    if keep:
        mode = "(prep: path control as programmed)"
    elif g64.strip().upper().startswith("G"):
        mode = g64.strip().upper()
    else:
        def conv(m):
            v = float(m.group(2)) / (25.4 if inch else 1.0)
            return "%s%.6g" % (m.group(1), v)
        mode = "G64 " + re.sub(r"([PQ])\s*([-+]?[\d.]+)", conv, g64.upper())
    out = []
    for i, l in enumerate(lines):
        code = l
        if i in drop:
            code = "(prep: dropped lead-in/out rapid) (" + re.sub(r"[()]", "", l) + ")"
        else:
            # remove existing path-control modes (outside comments is good enough here)
            if not keep:
                code = re.sub(r"(?i)G\s*6(?:4|1(?:\.1)?)(?![\d.])(\s*[PQ]\s*[-+]?[\d.]+)*", "", code)
            if feed is not None:
                f = feed / (25.4 if inch else 1.0)
                code = re.sub(r"(?i)F\s*[-+]?(?:\d+\.?\d*|\.\d+)", "F%.4f" % f, code)
        out.append(code)
        if i == (units_line if units_line is not None else -1):
            out.append(mode + " (prep: path control)")
    if units_line is None:
        out.insert(0, mode + " (prep: path control)")
    with open(dst, "w") as f:
        f.write("\n".join(out) + "\n")
    print("start=%.6f,%.6f,%.6f inch=%d mode=%s" % (start[0], start[1], start[2], int(inch), mode.replace(" ", "_")))


if __name__ == "__main__":
    main()
