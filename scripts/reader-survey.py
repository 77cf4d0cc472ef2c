#!/usr/bin/env python3
"""Issue-17 survey: real programs in, nothing lost.

For every reference program under ../shared/paths: does LinuxCNC's rs274
accept it (Debian's 2.9, and master when built: G6.2 is master only), does
`fairpath smooth` read, smooth and write it, does LinuxCNC accept what was
written, and is nothing lost as LinuxCNC sees it:

* feeds: the list of (place, new feed) where the feed in force for feed
  moves changes is the same in the original and the output (place = the
  point where the first move with the new feed starts, to 2e-4 inch:
  rs274 prints 4 decimals; feeds compared in mm/min);
* non-motion calls: every canonical call of the original that is not a
  motion, a feed rate, a comment or the path-control/plane settings fairpath
  writes around its runs (spindle, coolant, tool, dwell, offsets,
  messages, program end ...) appears in the output, in the same order and
  nothing else is added;
* the tolerance: `fairpath check ORIGINAL OUTPUT` passes.

Writes a Markdown report (with the date, the commit and the command).

Usage: scripts/reader-survey.py [--tolerance 0.05] [--markdown docs/reader-survey.md]
       [PROGRAM ...]
Build first: cargo build --release. Needs `rs274` (apt-get install
linuxcnc-uspace); master from ~/lcnc-master or FAIRPATH_LCNC_MASTER.
"""
import argparse
import datetime
import os
import re
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
PATHS = os.path.normpath(os.path.join(ROOT, "..", "shared", "paths"))
BIN = os.path.join(ROOT, "target", "release", "fairpath")
EXTS = (".ngc", ".nc", ".gcode", ".tap", ".txt", ".cnc")
MASTER = os.environ.get(
    "FAIRPATH_LCNC_MASTER", os.path.expanduser("~/lcnc-master/scripts/rip-environment")
)

MOTION = ("STRAIGHT_TRAVERSE", "STRAIGHT_FEED", "ARC_FEED", "NURBS_FEED", "NURBS_G5_FEED",
          "NURBS_G6_FEED", "STRAIGHT_PROBE", "RIGID_TAP")
# Calls fairpath may add or drop around its runs by design (plane and
# path-control words written around a run, comments such as the expansion
# header), or that only echo feeds.
IGNORED = ("SET_FEED_RATE", "SET_MOTION_CONTROL_MODE", "SET_NAIVECAM_TOLERANCE",
           "SELECT_PLANE", "COMMENT", "ON_RESET")


def programs(given):
    if given:
        return given
    out = []
    for d, _, files in os.walk(PATHS):
        for f in files:
            if f.lower().endswith(EXTS):
                out.append(os.path.join(d, f))
    return sorted(out)


def rel(p):
    return os.path.relpath(p, PATHS)


def rs274(path, master=False):
    """(ok, canonical lines or error text)."""
    d, b = os.path.split(os.path.abspath(path))
    if master:
        if not os.path.exists(MASTER):
            return None, "no master build"
        cmd = ["bash", "-c", f'set +u; . "{MASTER}" >/dev/null 2>&1; rs274 -g "$1"', "_", b]
    else:
        cmd = ["rs274", "-g", b]
    try:
        o = subprocess.run(cmd, cwd=d, capture_output=True, text=True, timeout=120,
                           errors="replace")
    except subprocess.TimeoutExpired:
        return False, "timeout"
    if o.returncode != 0:
        last = (o.stdout.strip().splitlines() or [""])[-1]
        return False, (o.stderr.strip() + " " + last).strip()[:160]
    calls = []
    for line in o.stdout.splitlines():
        m = re.match(r"\s*\d+\s+N\S*\s+(\w+)\((.*)\)\s*$", line)
        if m:
            calls.append((m.group(1), m.group(2)))
    return True, calls


def nums(args):
    out = []
    for a in args.split(","):
        try:
            out.append(float(a))
        except ValueError:
            out.append(a.strip())
    return out


def feed_changes(calls):
    """[(start point, feed)] where the feed in force for feed moves changes,
    in mm and mm/min (rs274 prints both in the units in force: a G20/G21
    converts the feed in force, so `F100` before a G21 and `F2540` after it
    are the same feed)."""
    feed, used, pos, out = None, None, (0.0, 0.0, 0.0), []
    plane = (0, 1, 2)
    mm = 1.0
    for name, args in calls:
        if name == "USE_LENGTH_UNITS":
            new = 25.4 if "INCHES" in args else 1.0
            if feed is not None:
                feed = feed * mm / new
            mm = new
        elif name == "SET_FEED_RATE":
            feed = nums(args)[0]
        elif name == "SELECT_PLANE":
            plane = (2, 0, 1) if "XZ" in args else (1, 2, 0) if "YZ" in args else (0, 1, 2)
        elif name in MOTION:
            n = nums(args)
            f = None if feed is None else round(feed * mm, 6)
            if name != "STRAIGHT_TRAVERSE" and f != used:
                out.append((pos, f))
                used = f
            if name in ("STRAIGHT_TRAVERSE", "STRAIGHT_FEED", "STRAIGHT_PROBE"):
                pos = tuple(x * mm for x in n[:3])
            elif name == "ARC_FEED":
                e = [0.0, 0.0, 0.0]
                e[plane[0]], e[plane[1]], e[plane[2]] = n[0], n[1], n[5]
                pos = tuple(x * mm for x in e)
    return out


def same_feeds(a, b):
    if len(a) != len(b):
        return False
    for (p, f), (q, g) in zip(a, b):
        if f != g or any(abs(x - y) > 2e-4 * 25.4 for x, y in zip(p, q)):
            return False
    return True


def non_motion(calls):
    return [(n, a) for n, a in calls if n not in MOTION and n not in IGNORED]


def run(cmd):
    return subprocess.run(cmd, capture_output=True, text=True, errors="replace")


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--tolerance", default="0.05")
    ap.add_argument("--markdown")
    ap.add_argument("programs", nargs="*")
    args = ap.parse_args()
    rows = []
    tmp = tempfile.mkdtemp()
    for p in programs(args.programs):
        r = {"program": rel(p)}
        ok29, c29 = rs274(p)
        okm, cm = (None, None) if ok29 else rs274(p, master=True)
        r["rs274"] = "2.9" if ok29 else ("master" if okm else "rejects")
        ref = c29 if ok29 else (cm if okm else None)
        out = os.path.join(tmp, "out" + os.path.splitext(p)[1])
        if os.path.exists(out):
            os.remove(out)
        o = run([BIN, "smooth", p, "-o", out, "--tolerance", args.tolerance + "mm"])
        if o.returncode != 0:
            err = [l for l in o.stderr.splitlines() if l.strip()]
            r["fairpath"] = "rejects"
            r["message"] = (err[-1] if err else "?").replace(PATHS + "/", "")[:200]
            rows.append(r)
            print(f'{r["program"]}: {r["rs274"]}, fairpath rejects: {r["message"]}',
                  file=sys.stderr)
            continue
        r["fairpath"] = "writes"
        chk = run([BIN, "check", p, out, "--tolerance", args.tolerance + "mm"])
        r["check"] = "pass" if chk.returncode == 0 else "FAIL"
        if ref is not None:
            okw, cw = rs274(out, master=(r["rs274"] == "master"))
            if not okw:
                r["output_rs274"] = "rejects: " + str(cw)[:120]
            else:
                r["output_rs274"] = "reads"
                r["feeds"] = "same" if same_feeds(feed_changes(ref), feed_changes(cw)) else "DIFFER"
                r["non_motion"] = "same" if non_motion(ref) == non_motion(cw) else "DIFFER"
        rows.append(r)
        print(f'{r["program"]}: {r["rs274"]}, writes, check {r["check"]}, '
              f'output {r.get("output_rs274", "-")}, feeds {r.get("feeds", "-")}, '
              f'non-motion {r.get("non_motion", "-")}', file=sys.stderr)
    report(rows, args)


def report(rows, args):
    acc = [r for r in rows if r["rs274"] != "rejects"]
    acc_w = [r for r in acc if r["fairpath"] == "writes"]
    rej = [r for r in rows if r["rs274"] == "rejects"]
    rej_w = [r for r in rej if r["fairpath"] == "writes"]
    written = [r for r in rows if r["fairpath"] == "writes"]
    commit = run(["git", "-C", ROOT, "rev-parse", "--short", "HEAD"]).stdout.strip()
    L = []
    L.append("# Reader survey: real programs in, nothing lost (issue 17)\n")
    L.append(f"Generated by `scripts/reader-survey.py --tolerance {args.tolerance}` on "
             f"{datetime.date.today()} at commit {commit}. Every reference program "
             f"under `../shared/paths` ({len(rows)}) is smoothed with the defaults "
             "(`fairpath smooth P -o OUT`) and both files are run through LinuxCNC's "
             "`rs274 -g` (2.9; master for the G6.2 programs 2.9 refuses).\n")
    L.append("| | programs |\n|---|---|")
    L.append(f"| accepted by rs274 (2.9 or master) | {len(acc)} |")
    L.append(f"| ... read, smoothed and written by fairpath | {len(acc_w)} |")
    L.append(f"| rejected by rs274 | {len(rej)} |")
    L.append(f"| ... written by fairpath anyway (other dialects) | {len(rej_w)} |")
    L.append(f"| written, `fairpath check` passes | "
             f"{sum(r.get('check') == 'pass' for r in written)} of {len(written)} |")
    both = [r for r in written if "output_rs274" in r]
    L.append(f"| written and rs274 reads the output | "
             f"{sum(r['output_rs274'] == 'reads' for r in both)} of {len(both)} |")
    L.append(f"| same feed changes at the same places (rs274's view) | "
             f"{sum(r.get('feeds') == 'same' for r in both)} of {len(both)} |")
    L.append(f"| same non-motion calls in the same order (rs274's view) | "
             f"{sum(r.get('non_motion') == 'same' for r in both)} of {len(both)} |")
    L.append("")
    bad = [r for r in acc if r["fairpath"] != "writes"]
    L.append("## Accepted by rs274, refused by fairpath\n")
    if bad:
        L.append("| program | rs274 | fairpath's message |\n|---|---|---|")
        for r in bad:
            L.append(f"| {r['program']} | {r['rs274']} | {r['message']} |")
    else:
        L.append("None.")
    L.append("")
    odd = [r for r in both if r["output_rs274"] != "reads" or r.get("feeds") != "same"
           or r.get("non_motion") != "same" or r.get("check") != "pass"]
    L.append("## Written with a difference\n")
    if odd:
        L.append("| program | check | rs274 of output | feeds | non-motion |\n|---|---|---|---|---|")
        for r in odd:
            L.append(f"| {r['program']} | {r.get('check')} | {r['output_rs274']} | "
                     f"{r.get('feeds', '-')} | {r.get('non_motion', '-')} |")
    else:
        L.append("None.")
    L.append("")
    L.append("## Refused by both (fairpath's message)\n")
    L.append("| program | message |\n|---|---|")
    for r in rej:
        if r["fairpath"] != "writes":
            L.append(f"| {r['program']} | {r['message']} |")
    text = "\n".join(L) + "\n"
    if args.markdown:
        with open(args.markdown, "w") as f:
            f.write(text)
    else:
        print(text)


if __name__ == "__main__":
    main()
