#!/usr/bin/env python3
"""Where `fairpath smooth` spends its time in a program, part by part.

The program is cut before each line with its own G0 (where a rapid ends
every run, so each part's runs are the program's own) into standalone
programs: the lines before the first motion line, the modal state in force
at the cut (plane, units, distance mode, feed), the part, and M2. Each part
is smoothed by each method; the table gives wall seconds per part and
method, the part's lines and feed runs, and its share of the whole.

  scripts/part-times.py PROGRAM [--tolerance 0.05mm] [--methods none,auto]
                        [--top 10] [--markdown FILE]

Each part starts with a rapid to where the program was at the cut (the
axes the program had set, in absolute mode), then its own lines: only
rapids differ from the program (never smoothed), so the feed runs, and
what each method does with them, are the program's. (A part cut from an
incremental stretch, G91, starts from the origin instead.)
FAIRPATH_BIN names the binary (default: target/release/fairpath).
"""

import argparse
import os
import re
import subprocess
import sys
import tempfile
import time

MODAL = {
    "plane": re.compile(r"\bG\s*(17|18|19)(?![.\d])", re.I),
    "units": re.compile(r"\bG\s*(20|21)(?![.\d])", re.I),
    "distance": re.compile(r"\bG\s*(90|91)(?![.\d])", re.I),
}
FEED = re.compile(r"\bF\s*([-+]?[\d.]+)", re.I)
RAPID = re.compile(r"\bG\s*0*0(?![.\d])", re.I)
MOTION = re.compile(r"\b[XYZ]\s*[-+]?[\d.]", re.I)
AXIS = re.compile(r"\b([XYZ])\s*([-+]?[\d.]+)", re.I)


def code(line):
    """The line without its comments."""
    return re.sub(r"\(.*?\)|;.*", "", line)


def split(lines):
    """(header, parts): each part a list of lines, with the modal words in
    force before it and the position (`at_X`, `at_Y`, `at_Z`) where the
    program was."""
    first_motion = next((i for i, l in enumerate(lines) if MOTION.search(code(l))), len(lines))
    header = [l for l in lines[:first_motion] if not RAPID.search(code(l))]
    parts, cur, state, before = [], [], {}, {}
    for line in lines[first_motion:]:
        c = code(line)
        if RAPID.search(c) and cur:
            parts.append((before, cur))
            cur = []
        if not cur:
            before = dict(state)
        cur.append(line)
        for axis, value in AXIS.findall(c):
            if state.get("distance", "G90") == "G90":
                state["at_" + axis.upper()] = value
        for k, rx in MODAL.items():
            m = rx.findall(c)
            if m:
                state[k] = "G" + m[-1]
        f = FEED.findall(c)
        if f:
            state["feed"] = "F" + f[-1]
    if cur:
        parts.append((before, cur))
    return header, parts


def preamble(state):
    """The lines that put a standalone part where the program was: the
    modal words, the position as one rapid, the feed on a line of its
    own (no motion)."""
    modal = " ".join(state[m] for m in ("units", "plane", "distance") if m in state)
    pre = [modal] if modal else []
    at = " ".join(a + state["at_" + a] for a in "XYZ" if "at_" + a in state)
    if at and state.get("distance", "G90") == "G90":
        pre.append("G0 " + at)
    if "feed" in state:
        pre.append(state["feed"])
    return pre


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("program")
    ap.add_argument("--tolerance", default="0.05mm")
    ap.add_argument("--methods", default="none,bspline-corner,bspline-fit,auto")
    ap.add_argument("--top", type=int, default=10)
    ap.add_argument("--markdown")
    a = ap.parse_args()
    binary = os.environ.get("FAIRPATH_BIN", "target/release/fairpath")
    methods = a.methods.split(",")
    lines = open(a.program, errors="replace").read().splitlines()
    header, parts = split(lines)
    rows = []
    with tempfile.TemporaryDirectory() as d:
        for k, (state, part) in enumerate(parts, 1):
            path = os.path.join(d, f"part{k}.ngc")
            pre = preamble(state)
            with open(path, "w") as f:
                f.write("\n".join(header + pre + part + ["M2"]) + "\n")
            row = {"part": k, "first": None, "lines": len(part), "runs": "", "secs": {}}
            for m in methods:
                t0 = time.monotonic()
                r = subprocess.run(
                    [binary, "smooth", path, "-t", a.tolerance, "-m", m,
                     "-o", os.path.join(d, "out.ngc")],
                    capture_output=True, text=True)
                dt = time.monotonic() - t0
                if r.returncode != 0:
                    row["secs"][m] = None
                    continue
                row["secs"][m] = dt
                runs = re.search(r"moves in:\s+(\d+) feed moves in (\d+) runs", r.stdout)
                if runs:
                    row["runs"] = f"{runs.group(2)} ({runs.group(1)} moves)"
            rows.append(row)
    # Line numbers of each part in the program.
    at = next((i for i, l in enumerate(lines) if MOTION.search(code(l))), 0) + 1
    for row in rows:
        row["first"] = at
        at += row["lines"]
    total = {m: sum(r["secs"][m] or 0.0 for r in rows) for m in methods}
    key = methods[-1]
    rows.sort(key=lambda r: -(r["secs"][key] or 0.0))
    out = []
    out.append(f"`{os.path.basename(a.program)}` at {a.tolerance}: {len(rows)} parts "
               f"(cut before each line with its own G0), the {min(a.top, len(rows))} "
               f"slowest by `{key}`; wall s per part, then its share of the parts' sum.")
    out.append("")
    out.append("| part | lines | runs | " + " | ".join(methods) + f" | share of `{key}` |")
    out.append("|---" * (4 + len(methods)) + "|")
    for row in rows[: a.top]:
        cells = ["fails" if row["secs"][m] is None else f"{row['secs'][m]:.2f}" for m in methods]
        share = (row["secs"][key] or 0.0) / total[key] if total[key] > 0 else 0.0
        out.append(f"| {row['part']} (line {row['first']}) | {row['lines']} | {row['runs']} | "
                   + " | ".join(cells) + f" | {share:.1%} |")
    out.append("| all parts | " + str(sum(r["lines"] for r in rows)) + " | | "
               + " | ".join(f"{total[m]:.2f}" for m in methods) + " | |")
    text = "\n".join(out) + "\n"
    print(text)
    if a.markdown:
        with open(a.markdown, "a") as f:
            f.write(text + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
