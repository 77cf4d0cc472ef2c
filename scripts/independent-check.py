#!/usr/bin/env python3
"""An independent check of what `fairpath smooth` writes, through LinuxCNC.

Both programs are read by LinuxCNC's own interpreter (`rs274 -g`, Debian's
linuxcnc-uspace), not by fairpath's reader, and measured here with nothing
of fairpath's code (plain Python, no fairpath verifier):

* tolerance: every point of the written feed path lies within TOLERANCE
  of the original feed path (3D). The distance to the original is
  measured at the written path's vertices (arcs flattened within 0.05 um,
  as the original's are; that is added); the distance to a fixed set is
  1-Lipschitz, so inside a piece from a to b it is at most
  (d(a) + d(b) + |ab|) / 2, and a piece whose bound exceeds the limit is
  halved until it passes or is shorter than TOLERANCE/40 (then it is
  bounded by its larger end plus half its length). The largest distance
  measured is reported. rs274 prints 4 decimals in the program's units,
  which misplaces the centre of a small arc by much of its radius, so it
  reads copies of both programs with every coordinate word scaled by
  1000 (or 100 or 10, the largest it accepts: an inexact arc of the
  original may pass LinuxCNC's radius check only at a smaller factor),
  and the rounding of two printed points (half a unit of the last decimal
  on each axis, both programs) is added to the limit.
* run ends and rapids: the written program's rapids go to the same
  points as the original's, in the same order, and each run (the feed
  moves between two rapids) starts and ends where the original's did.
* with --continuity, the joints of the exact curves: the program is also
  written as JSON (-f json) and the joints between its consecutive feed
  pieces are classed here (end derivatives of the lines and rational
  B-splines by the Cox-de Boor recursion, the thresholds the README
  states); the check fails if fewer joints are G2 than fairpath's summary
  claims C2, or more have gaps, with the thresholds doubled for both
  (rounding of the written control points may move a joint across a
  threshold).

Prints one line per case and, with --markdown, writes a table (date,
commit, command). Exit status 1 if a case fails.

Usage: scripts/independent-check.py [--tolerance 0.05mm] [--methods auto,...]
          [--formats arcs,g1] [--continuity] [--generated] [--max-kb N]
          [--markdown FILE] [PROGRAM or DIRECTORY...]
(--generated adds the programs scripts/check-programs.py writes. A bare
--tolerance number is in mm here, also for inch programs, and is passed
to fairpath with its unit.)
Needs `rs274` (apt-get install linuxcnc-uspace) and a release build
(cargo build --release -p fairpath-cli; FAIRPATH_BIN for another).
"""
import argparse
import datetime
import math
import os
import re
import shutil
import subprocess
import sys
import tempfile

BIN = os.environ.get("FAIRPATH_BIN", "target/release/fairpath")
ARC_SAGITTA_MM = 5e-5
SCALES = (1000.0, 100.0, 10.0)
CALL = re.compile(r"^\s*\d+\s+N\S*\s+([A-Z_0-9]+)\((.*)\)\s*$")
COORD = re.compile(r"([XYZIJKRxyzijkr])(\s*)([+-]?(?:\d+\.?\d*|\.\d+))")


def scaled_copy(path, factor, tmp):
    """A copy of `path` with every coordinate word (X Y Z I J K R) outside
    comments multiplied by `factor`, or None where the program computes
    its words (parameters, expressions, o-words: not scaled)."""
    text = open(path, encoding="latin-1").read()
    if re.search(r"[#\[]|^\s*[oO]\d", text, re.M):
        return None

    def scale_code(code):
        def one(m):
            v = ("%.12f" % (float(m.group(3)) * factor)).rstrip("0").rstrip(".") or "0"
            return m.group(1) + m.group(2) + v
        return COORD.sub(one, code)

    out = []
    for line in text.splitlines():
        parts = re.split(r"(\([^)]*\)|;.*$)", line)
        out.append("".join(p if p.startswith(("(", ";")) else scale_code(p) for p in parts))
    dst = os.path.join(tmp, "scaled-" + os.path.basename(path))
    with open(dst, "w", encoding="latin-1") as f:
        f.write("\n".join(out) + "\n")
    return dst


def rs274(path):
    """[`rs274_at`] of a copy scaled by the largest of SCALES that rs274
    reads, or of `path` itself where the program has words that are not
    plain numbers or no copy is read (an arc whose end radius differs from
    its start radius within LinuxCNC's absolute limit differs by the
    factor times as much in the copy, and may pass it)."""
    with tempfile.TemporaryDirectory() as tmp:
        for factor in SCALES:
            copy = scaled_copy(path, factor, tmp)
            if not copy:
                break
            try:
                return rs274_at(copy, factor)
            except ValueError:
                pass
    return rs274_at(path, 1.0)


def rs274_at(path, factor):
    """Motion of `path` as rs274 sees it: a list of (kind, points) in mm,
    kind 'rapid' or 'feed', points the move flattened (end included), and
    the largest rounding of a printed coordinate (mm).

    `path` holds coordinates `factor` times the program's: rs274 prints 4
    decimals in the program's units, which misplaces the centre of a small
    arc by much of its radius, so it reads a copy scaled up, and the points
    are scaled back."""
    r = subprocess.run(["rs274", "-g", path], capture_output=True, text=True, timeout=600)
    moves = []
    # rs274 starts at the origin: a first feed move starts there.
    pos = (0.0, 0.0, 0.0)
    scale = 1.0 / factor
    plane = "XY"
    for line in r.stdout.splitlines():
        m = CALL.match(line)
        if not m:
            continue
        name, args = m.group(1), m.group(2)
        if name == "USE_LENGTH_UNITS":
            scale = (25.4 if "INCH" in args else 1.0) / factor
        elif name == "SELECT_PLANE":
            plane = {"CANON_PLANE_XY": "XY", "CANON_PLANE_XZ": "XZ", "CANON_PLANE_YZ": "YZ"}.get(
                args.strip(), plane)
        elif name in ("STRAIGHT_TRAVERSE", "STRAIGHT_FEED"):
            v = [float(x) * scale for x in args.split(",")[:3]]
            end = tuple(v)
            kind = "rapid" if name == "STRAIGHT_TRAVERSE" else "feed"
            moves.append((kind, [pos, end]))
            pos = end
        elif name == "ARC_FEED":
            a = [float(x) for x in args.split(",")]
            e1, e2, c1, c2, rot, ax = [x * scale for x in a[:4]] + [int(a[4]), a[5] * scale]
            moves.append(("feed", arc_points(pos, plane, (e1, e2), (c1, c2), rot, ax)))
            pos = moves[-1][1][-1]
        elif name.startswith("NURBS") or name == "SPLINE_FEED":
            raise ValueError(f"{path}: {name} is not checked here")
    # A program without M2 or % at its end is read to its end all the same.
    if r.returncode != 0 and "File ended with no percent sign or program end" not in r.stderr:
        raise ValueError(f"{os.path.basename(path)}: rs274 failed: "
                         f"{r.stderr.strip().splitlines()[-1:]}")
    return moves, 0.5e-4 * 25.4 / factor


def axes(plane):
    """Indices (first, second, axis) of rs274's ARC_FEED for a plane."""
    return {"XY": (0, 1, 2), "XZ": (2, 0, 1), "YZ": (1, 2, 0)}[plane]


def arc_points(start, plane, end12, center, rot, axis_end):
    """rs274's ARC_FEED from `start` as points (start included) at most
    ARC_SAGITTA_MM from the arc: `rot` turns counterclockwise (negative:
    clockwise) in the plane's (first, second) axes, a full turn where the
    ends meet; the radius and the axis coordinate change linearly with the
    angle (a spiral where the printed ends are not on one circle)."""
    i1, i2, i3 = axes(plane)
    s1, s2, s3 = start[i1], start[i2], start[i3]
    r0 = math.hypot(s1 - center[0], s2 - center[1])
    r1 = math.hypot(end12[0] - center[0], end12[1] - center[1])
    a0 = math.atan2(s2 - center[1], s1 - center[0])
    a1 = math.atan2(end12[1] - center[1], end12[0] - center[0])
    if rot > 0:
        sweep = a1 - a0
        while sweep <= 1e-12:
            sweep += 2 * math.pi
        sweep += 2 * math.pi * (rot - 1)
    else:
        sweep = a1 - a0
        while sweep >= -1e-12:
            sweep -= 2 * math.pi
        sweep -= 2 * math.pi * (-rot - 1)
    r = max(r0, r1, 1e-12)
    step = 2 * math.acos(max(-1.0, 1 - ARC_SAGITTA_MM / r)) if r > ARC_SAGITTA_MM else math.pi
    n = max(1, int(math.ceil(abs(sweep) / step)))
    pts = []
    for k in range(1, n + 1):
        f = k / n
        ang = a0 + sweep * f
        rr = r0 + (r1 - r0) * f
        p = [0.0, 0.0, 0.0]
        p[i1] = center[0] + rr * math.cos(ang)
        p[i2] = center[1] + rr * math.sin(ang)
        p[i3] = s3 + (axis_end - s3) * f
        pts.append(tuple(p))
    pts[-1] = tuple(end12[0] if i == i1 else end12[1] if i == i2 else axis_end for i in range(3))
    return [start] + pts


def runs(moves):
    """Feed runs (lists of points) and rapid end points, in order."""
    out, cur, rapids = [], None, []
    for kind, pts in moves:
        if kind == "rapid":
            if cur:
                out.append(cur)
            cur = None
            rapids.append(pts[-1])
        else:
            if cur is None:
                cur = [pts[0]]
            cur.extend(pts[1:])
    if cur:
        out.append(cur)
    return out, rapids


class Grid:
    """Segments of a polyline set hashed into cubes of side `cell`: each
    segment is registered in the cubes of its points at most `cell / 2`
    apart, so a segment within `cell - cell / 4` of a point (per axis) is
    registered in a cube next to the point's."""

    def __init__(self, polylines, cell):
        self.cell = cell
        self.cells = {}
        self.segs = []
        for pl in polylines:
            for a, b in zip(pl, pl[1:]):
                k = len(self.segs)
                self.segs.append((a, b))
                n = int(math.dist(a, b) / (0.5 * cell)) + 1
                keys = set()
                for j in range(n + 1):
                    f = j / n
                    keys.add(tuple(math.floor((a[i] + (b[i] - a[i]) * f) / cell)
                                   for i in range(3)))
                for key in keys:
                    self.cells.setdefault(key, []).append(k)

    def nearest(self, p):
        """Distance from p to the nearest segment registered next to it: at
        least the distance to the original, equal to it when that is at
        most half the cell."""
        c = [math.floor(p[i] / self.cell) for i in range(3)]
        best = math.inf
        seen = set()
        for dx in (-1, 0, 1):
            for dy in (-1, 0, 1):
                for dz in (-1, 0, 1):
                    for k in self.cells.get((c[0] + dx, c[1] + dy, c[2] + dz), ()):
                        if k in seen:
                            continue
                        seen.add(k)
                        best = min(best, seg_dist(p, *self.segs[k]))
        return best


def seg_dist(p, a, b):
    d = [b[i] - a[i] for i in range(3)]
    w = [p[i] - a[i] for i in range(3)]
    dd = d[0] * d[0] + d[1] * d[1] + d[2] * d[2]
    t = 0.0 if dd == 0 else max(0.0, min(1.0, (w[0] * d[0] + w[1] * d[1] + w[2] * d[2]) / dd))
    return math.dist(p, (a[0] + t * d[0], a[1] + t * d[1], a[2] + t * d[2]))


def check(original, written, tol):
    """(largest deviation measured mm, limit mm, list of problems)."""
    om, orr = rs274(original)
    try:
        wm, wr = rs274(written)
    except ValueError as e:
        return math.inf, tol, [f"LinuxCNC does not read the written program ({e})"]
    oruns, orap = runs(om)
    wruns, wrap = runs(wm)
    problems = []
    rounding = math.sqrt(3) * (orr + wr)
    if len(orap) != len(wrap) or any(math.dist(a, b) > rounding for a, b in zip(orap, wrap)):
        problems.append(f"rapids differ ({len(orap)} against {len(wrap)})")
    if len(oruns) != len(wruns):
        problems.append(f"{len(wruns)} runs written, {len(oruns)} in the original")
    for i, (a, b) in enumerate(zip(oruns, wruns)):
        if math.dist(a[0], b[0]) > rounding or math.dist(a[-1], b[-1]) > rounding:
            problems.append(f"run {i + 1}: ends moved")
            break
    h = tol / 40.0
    grid = Grid(oruns, max(tol * 2.0, 1e-3))
    limit = tol + rounding
    worst = 0.0  # the largest distance measured at a point
    where = None
    fail = None  # (bound, run, point) of a piece not proven within the limit
    for i, run in enumerate(wruns):
        da = grid.nearest(run[0])
        for a, b in zip(run, run[1:]):
            db = grid.nearest(b)
            # Split while the Lipschitz bound (da + db + |ab|) / 2 of the
            # distance inside [a, b] exceeds the limit; a piece shorter
            # than h is bounded by its larger end plus half its length.
            todo = [(a, b, da, db)]
            while todo:
                p, q, dp, dq = todo.pop()
                for d, x in ((dp, p), (dq, q)):
                    if d > worst:
                        worst, where = d, (i + 1, x)
                length = math.dist(p, q)
                if (dp + dq + length) / 2 <= limit - ARC_SAGITTA_MM:
                    continue
                if length <= h:
                    e = max(dp, dq) + 0.5 * length + ARC_SAGITTA_MM
                    if e > limit and (fail is None or e > fail[0]):
                        fail = (e, i + 1, p)
                    continue
                m = tuple(0.5 * (p[k] + q[k]) for k in range(3))
                dm = grid.nearest(m)
                todo.append((p, m, dp, dm))
                todo.append((m, q, dm, dq))
            da = db
    bound = worst
    if fail is not None:
        e, run_no, x = fail
        problems.append(f"deviation up to {e:.6f} mm > {limit:.6f} mm at run {run_no}, "
                        f"({x[0]:.4f}, {x[1]:.4f}, {x[2]:.4f}) mm")
    return bound, limit, problems


PROGRAM_EXT = (".ngc", ".nc", ".gcode", ".tap")


def programs(given, max_kb):
    """The files given, and the G-code files under the directories given
    (up to `max_kb`), sorted by name."""
    out = []
    for g in given:
        if os.path.isdir(g):
            for root, _, files in os.walk(g):
                for name in files:
                    path = os.path.join(root, name)
                    if name.lower().endswith(PROGRAM_EXT) and \
                            os.path.getsize(path) <= max_kb * 1024:
                        out.append(path)
        else:
            out.append(g)
    return sorted(out, key=lambda p: (os.path.basename(p), p))


# --- Continuity of the exact curves (--continuity) -----------------------


def basis(knots, i, p, t, last):
    """N_{i,p}(t) by the Cox-de Boor recursion; at the domain's end `last`
    the last non-empty span is closed on the right."""
    if p == 0:
        a, b = knots[i], knots[i + 1]
        return 1.0 if (a <= t < b) or (t == last and a < b == last) else 0.0
    out = 0.0
    d1 = knots[i + p] - knots[i]
    d2 = knots[i + p + 1] - knots[i + 1]
    if d1 > 0:
        out += (t - knots[i]) / d1 * basis(knots, i, p - 1, t, last)
    if d2 > 0:
        out += (knots[i + p + 1] - t) / d2 * basis(knots, i + 1, p - 1, t, last)
    return out


def basis_d(knots, i, p, t, k, last):
    """k-th derivative of N_{i,p} at t (The NURBS Book, eq. 2.9)."""
    if k == 0:
        return basis(knots, i, p, t, last)
    out = 0.0
    d1 = knots[i + p] - knots[i]
    d2 = knots[i + p + 1] - knots[i + 1]
    if d1 > 0:
        out += p / d1 * basis_d(knots, i, p - 1, t, k - 1, last)
    if d2 > 0:
        out -= p / d2 * basis_d(knots, i + 1, p - 1, t, k - 1, last)
    return out


def nurbs_derivs(piece, t):
    """Point, first and second derivative of a (rational) B-spline piece
    at t, by the quotient rule on homogeneous coordinates (eq. 4.8)."""
    knots, pts, p = piece["knots"], piece["points"], piece["degree"]
    w = piece.get("weights") or [1.0] * len(pts)
    last = max(k for k in knots[p:len(knots) - p])
    a = [[0.0] * 3 for _ in range(3)]
    ww = [0.0] * 3
    for k in range(3):
        for i in range(len(pts)):
            n = basis_d(knots, i, p, t, k, last)
            if n == 0.0:
                continue
            ww[k] += n * w[i]
            for j in range(3):
                a[k][j] += n * w[i] * pts[i][j]
    c0 = [a[0][j] / ww[0] for j in range(3)]
    c1 = [(a[1][j] - c0[j] * ww[1]) / ww[0] for j in range(3)]
    c2 = [(a[2][j] - 2 * c1[j] * ww[1] - c0[j] * ww[2]) / ww[0] for j in range(3)]
    return c0, c1, c2


def ends(piece):
    """(start, end) of a piece, each (point, C', C'')."""
    if piece["type"] == "line":
        p0, p1 = piece["p0"], piece["p1"]
        d = [p1[j] - p0[j] for j in range(3)]
        return (p0, d, [0.0] * 3), (p1, d, [0.0] * 3)
    if piece["type"] == "nurbs":
        k, p = piece["knots"], piece["degree"]
        lo, hi = k[p], k[len(k) - p - 1]
        return nurbs_derivs(piece, lo), nurbs_derivs(piece, hi)
    raise ValueError(f"piece type {piece['type']} is not checked here")


def norm(v):
    return math.sqrt(sum(x * x for x in v))


def curvature_vector(d1, d2):
    """(C'' - (C''.T) T) / |C'|^2, T = C'/|C'|."""
    s = norm(d1)
    t = [x / s for x in d1]
    dot = sum(a * b for a, b in zip(d2, t))
    return [(d2[j] - dot * t[j]) / (s * s) for j in range(3)]


def over(x, y):
    """x / y with IEEE semantics for y = 0 (x > 0: infinity)."""
    return x / y if y != 0.0 else math.inf


def classify(ea, eb, tol, size, slack=1.0):
    """'G2', 'G1', 'G0' or 'gap' for the joint where the piece with ends
    `ea` ([`ends`]) ends and the one with ends `eb` starts, with the thresholds fairpath's README states (gap: a
    millionth of the tolerance; tangent: 1 microradian; curvature
    vectors: 1e-6 relative plus 1e-6 / tolerance), each widened by what
    f64 rounding of coordinates of magnitude `size` allows on pieces of
    their chord lengths (a thousand times `size * 2^-52 / l` for the
    tangent, `/ l^2` for the curvature), every threshold times `slack`."""
    (pa, da1, da2), (pb, db1, db2) = ea[1], eb[0]
    if math.dist(pa, pb) > slack * tol * 1e-6:
        return "gap"
    if norm(da1) == 0 or norm(db1) == 0:
        return "G0"
    eps = 1000 * size * 2.0 ** -52
    l = min(math.dist(ea[0][0], pa), math.dist(pb, eb[1][0]))
    ua = [x / norm(da1) for x in da1]
    ub = [x / norm(db1) for x in db1]
    angle = 2 * math.asin(min(1.0, math.dist(ua, ub) / 2))
    if angle > slack * (1e-6 + over(eps, l)):
        return "G0"
    ka, kb = curvature_vector(da1, da2), curvature_vector(db1, db2)
    allowed = slack * (1e-6 * max(norm(ka), norm(kb)) + 1e-6 / tol + over(eps, l * l))
    return "G2" if math.dist(ka, kb) <= allowed else "G1"


def joints(json_path, tol, slacks):
    """For each of `slacks`, the counts of each class over the joints
    between consecutive feed pieces of the written JSON (a run is the feed
    pieces between rapids; fairpath also ends runs at feed changes, whose
    joints it does not count, so these counts may hold more joints than
    fairpath's). Each piece's ends are evaluated once."""
    import json
    with open(json_path) as f:
        pieces = json.load(f)["pieces"]
    e = [None if p["rapid"] else ends(p) for p in pieces]
    counts = [{"G2": 0, "G1": 0, "G0": 0, "gap": 0} for _ in slacks]
    for ea, eb in zip(e, e[1:]):
        if ea is None or eb is None:
            continue
        size = max(abs(x) for end in ea + eb for x in end[0])
        for c, slack in zip(counts, slacks):
            c[classify(ea, eb, tol, size, slack)] += 1
    return counts


CLAIM_SLACK = 2.0
JOINTS = re.compile(r"joints:\s+(\d+) C2 .*?(\d+) C1 .*?(\d+) C0 .*?(\d+) gaps")


def continuity_check(prog, method, tol_text, tol, tmp, extra=()):
    """fairpath's claim of C2 joints for `prog` and `method` against the
    joints of its exact curves (-f json) classed here: (text, failed)."""
    out = os.path.join(tmp, "out.json")
    r = subprocess.run([BIN, "smooth", prog, "-t", tol_text, "-m", method, "-f", "json",
                        "-o", out, *extra], capture_output=True, text=True)
    if r.returncode != 0:
        return "refused", False
    m = JOINTS.search(r.stdout + r.stderr)
    if not m:
        return "no joints line in the summary", True
    claimed = dict(zip(("G2", "G1", "G0", "gap"), map(int, m.groups())))
    # The curves' own classes and those of their JSON form (rounded control
    # points, evaluated here in another order) may differ at a threshold:
    # a claim is refuted only beyond CLAIM_SLACK times the thresholds.
    found, loose = joints(out, tol, (1.0, CLAIM_SLACK))
    text = (f"claimed {claimed['G2']}/{claimed['G1']}/{claimed['G0']}/{claimed['gap']}, "
            f"found {found['G2']}/{found['G1']}/{found['G0']}/{found['gap']} (G2/G1/G0/gap)")
    failed = loose["G2"] < claimed["G2"] or loose["gap"] > claimed["gap"]
    return text, failed


def tolerance_mm(text):
    m = re.fullmatch(r"([0-9.eE+-]+)\s*(mm|in)?", text)
    v = float(m.group(1))
    return v * 25.4 if m.group(2) == "in" else v


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--tolerance", default="0.05mm")
    ap.add_argument("--methods", default="auto,bspline-corner,lotm,ctm,bspline-fit,fair,arc-fit,none")
    ap.add_argument("--formats", default="arcs,g1")
    ap.add_argument("--markdown")
    ap.add_argument("--continuity", action="store_true",
                    help="also write the exact curves (-f json) and class their joints here")
    ap.add_argument("--max-kb", type=float, default=math.inf,
                    help="in directories, only programs up to this size")
    ap.add_argument("--generated", action="store_true",
                    help="also the programs scripts/check-programs.py writes")
    ap.add_argument("--smooth-args", default="",
                    help="more arguments for every `fairpath smooth` (e.g. '--block-time 0.001')")
    ap.add_argument("programs", nargs="*", help="programs, or directories to search")
    a = ap.parse_args()
    generated = tempfile.mkdtemp()
    if a.generated:
        here = os.path.dirname(os.path.abspath(__file__))
        subprocess.run([sys.executable, os.path.join(here, "check-programs.py"), generated],
                       check=True)
        a.programs.append(generated)
    a.programs = programs(a.programs, a.max_kb)
    if not a.programs:
        ap.error("no programs: give files or directories, or --generated")
    if not set(a.formats.split(",")) <= {"arcs", "g1"}:
        ap.error("--formats: arcs and g1 only (rs274 of Debian's LinuxCNC reads no G6.2, "
                 "and its G5.2 is not measured here)")
    tol = tolerance_mm(a.tolerance)
    # fairpath reads a bare number in the program's units (inches in a G20
    # program); this check reads it in mm, so fairpath is given mm too.
    tol_arg = f"{tol!r}mm"
    rows, failed = [], 0
    with tempfile.TemporaryDirectory() as tmp:
        for prog in a.programs:
            for method in a.methods.split(","):
                for fmt in a.formats.split(","):
                    out = os.path.join(tmp, "out.ngc")
                    r = subprocess.run([BIN, "smooth", prog, "-t", tol_arg, "-m", method,
                                        "-f", fmt, "-o", out, *a.smooth_args.split()],
                                       capture_output=True, text=True)
                    name = os.path.basename(prog)
                    if r.returncode != 0:
                        lines = r.stderr.strip().splitlines() or ["?"]
                        msg = next((x for x in lines if x.startswith("error")), lines[-1])
                        msg = msg.replace(os.path.dirname(prog) + "/", "").replace("|", "/")
                        rows.append((name, method, fmt, "-", "-", "refused: " + msg))
                        print(f"{name:32} {method:15} {fmt:5} refused: {msg}", flush=True)
                        continue
                    try:
                        bound, limit, problems = check(prog, out, tol)
                    except (ValueError, subprocess.TimeoutExpired) as e:
                        rows.append((name, method, fmt, "-", "-", f"not checked: {e}"))
                        print(f"{name:32} {method:15} {fmt:5} not checked: {e}", flush=True)
                        continue
                    verdict = "ok" if not problems else "FAIL: " + "; ".join(problems)
                    failed += bool(problems)
                    rows.append((name, method, fmt, f"{bound:.6f}", f"{limit:.6f}", verdict))
                    print(f"{name:32} {method:15} {fmt:5} {bound:.6f} <= {limit:.6f} {verdict}",
                          flush=True)
                if a.continuity:
                    name = os.path.basename(prog)
                    try:
                        text, bad = continuity_check(prog, method, tol_arg, tol, tmp,
                                                     a.smooth_args.split())
                    except ValueError as e:
                        text, bad = f"not checked: {e}", False
                    except (KeyError, ZeroDivisionError, OverflowError) as e:
                        text, bad = f"checker error: {e!r}", True
                    verdict = ("FAIL: " if bad else "ok: ") + text if text != "refused" else text
                    failed += bad
                    rows.append((name, method, "json", "-", "-", verdict))
                    print(f"{name:32} {method:15} json  {verdict}", flush=True)
    if a.markdown:
        commit = subprocess.run(["git", "rev-parse", "--short", "HEAD"], capture_output=True,
                                text=True).stdout.strip()
        with open(a.markdown, "w") as f:
            f.write("# Independent check of written programs\n\n")
            f.write(f"Generated by `scripts/independent-check.py {' '.join(sys.argv[1:])}` on "
                    f"{datetime.datetime.utcnow():%Y-%m-%d %H:%M} UTC, commit {commit}.\n")
            f.write("Both programs read by LinuxCNC's `rs274 -g`; deviation measured by the "
                    "script alone (see its docstring).\n\n")
            counts = {}
            for r in rows:
                key = r[5].split(":")[0]
                counts[key] = counts.get(key, 0) + 1
            f.write(f"{len(rows)} cases: " + ", ".join(f"{v} {k}" for k, v in sorted(counts.items()))
                    + ". `refused`: fairpath reports the input as unsupported or bad "
                    "(file:line:col); `not checked`: rs274 does not read the original.\n\n")
            f.write("| program | method | format | largest deviation mm | limit mm | result |\n")
            f.write("|---|---|---|---|---|---|\n")
            for r in rows:
                f.write("| " + " | ".join(r) + " |\n")
    shutil.rmtree(generated, ignore_errors=True)
    print(f"{len(rows)} cases, {failed} failed")
    sys.exit(1 if failed else 0)


if __name__ == "__main__":
    main()
