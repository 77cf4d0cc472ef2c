#!/usr/bin/env bash
# Issue 20, item 6: `auto` with `fair` among its candidates. For each
# program (the dense programs of scripts/fair-vs-relaxation.sh, the thesis'
# cases of examples/thesis/, the B-spline programs of
# ../shared/paths/linuxcnc-nurbs/), `fairpath smooth --method auto` at the
# tolerance: what auto chose, planned times of the curves and of the written
# program, computing time; beside the same figures from BASE_BIN (a build
# of the commit before fair was a candidate), when given. Writes
# docs/auto-fair.md.
# Usage: [BASE_BIN=/path/to/old/fairpath [BASE_WHAT="what it is"]
#   [BASE_UNITS=1]] scripts/auto-fair.sh [TOLERANCE]
#   (build first: cargo build --release -p fairpath-cli; BASE_WHAT says
#   what the base build is, by default a build before `fair` was a
#   candidate; BASE_UNITS=1 for a base that reads `0.05mm` as this build
#   does, else it is given a bare number, which builds before units were
#   read took as mm)
set -euo pipefail
cd "$(dirname "$0")/.."
tol=${1:-0.05}
bin=${FAIRPATH_BIN:-target/release/fairpath}
base=${BASE_BIN:-}
P=../shared/paths
out=docs/auto-fair.md
progs=(synthetic/surface-raster.ngc synthetic/helix.ngc synthetic/butterfly-80.ngc
  synthetic/noisy-line.ngc linuxcnc/performance/contour.ngc linuxcnc/performance/LHchips4.ngc
  linuxcnc/performance/Cereal.ngc gcode-rs/makerblock_tinycnc.gcode)
files=()
for rel in "${progs[@]}"; do files+=("$P/$rel"); done
files+=(examples/thesis/*.ngc "$P"/linuxcnc-nurbs/G5/*.ngc "$P"/linuxcnc-nurbs/G6/*.ngc)
export BASE_WHAT="${BASE_WHAT:-\`fair\` not a candidate}" BASE_UNITS="${BASE_UNITS:-}"
python3 - "$bin" "$base" "$tol" "$out" "$(git rev-parse --short HEAD)" "${files[@]}" <<'EOF'
import json, os, resource, subprocess, sys, tempfile, time
bin_, base, tol, out, commit = sys.argv[1:6]
files = sys.argv[6:]
tmp = tempfile.mkdtemp()

def run(b, f, method="auto", extra=()):
    """The JSON summary of `f` smoothed by `method`, with the CPU time
    (user + system, s) as "cpu_s", or None when smooth fails."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    # The current build reads a bare tolerance in the program's units: mm
    # said (the base build, older, reads mm and no unit).
    t = tol + "mm" if b == bin_ or os.environ.get("BASE_UNITS") else tol
    o = subprocess.run([b, "smooth", f, "--tolerance", t, "-o", os.path.join(tmp, "x.ngc"),
                        "-m", method, "--json-summary", *extra], capture_output=True, text=True)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if o.returncode != 0:
        return None
    d = json.loads(o.stdout[o.stdout.index("{"):])
    d["cpu_s"] = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return d

def name(f):
    for pre in ("../shared/paths/", "examples/"):
        if f.startswith(pre):
            return f[len(pre):]
    return f

rows, picks, sums = [], 0, [0.0] * 6
for f in files:
    if not os.path.exists(f):
        print(f"{f}: not found", file=sys.stderr)
        continue
    new = run(bin_, f)
    old = run(base, f) if base else None
    if new is None:
        both = " (before too)" if base and old is None else ""
        rows.append(f"| {name(f)} | smooth failed{both} | | | | | | | | | | | |")
        continue
    # auto ranks by the planned time with the feeds overridden to the
    # machine's maximum: the curves' time that way, now and before.
    fast = run(bin_, f, extra=["--override-feed"])
    fast_old = run(base, f, extra=["--override-feed"]) if base else None
    chose = "; ".join(f"{c['sections']} x {c['candidate']}" for c in new["auto_chose"])
    if any(c["candidate"] == "fair" for c in new["auto_chose"]):
        picks += 1
    nf = ", ".join(f"{x['curves']} {x['reason']}" for x in new.get("not_faired", []))
    cells = [name(f), chose, nf, "%.3f" % new["curves_time_s"], "%.3f" % new["written_time_s"],
             "%.3f" % fast["curves_time_s"], "%.2f" % new["time_s"], "%.2f" % new["cpu_s"]]
    if old:
        cells += ["%.3f" % old["curves_time_s"], "%.3f" % old["written_time_s"],
                  "%.3f" % fast_old["curves_time_s"], "%.2f" % old["time_s"], "%.2f" % old["cpu_s"]]
        sums[0] += new["written_time_s"]; sums[1] += old["written_time_s"]
        sums[2] += new["time_s"]; sums[3] += old["time_s"]
        sums[4] += new["cpu_s"]; sums[5] += old["cpu_s"]
    else:
        cells += ["", "", "", "", ""]
    rows.append("| " + " | ".join(cells) + " |")

# Long runs of lines: auto before and after on the large raster (fair is
# not offered on its one run of 138,803 lines), and the two methods alone
# that fit its lines, on it and on the longest runs of the others.
large = f"{os.path.dirname(files[0])}/surface-raster-large.ngc"
long_rows = []
timed = [(large, "none", bin_), (large, "auto", bin_)]
if base:
    timed.append((large, "auto", base))
for f in (large, files[0].replace("synthetic/surface-raster.ngc", "gcode-rs/makerblock_tinycnc.gcode")):
    timed += [(f, "bspline-fit", bin_), (f, "fair", bin_)]
for f, method, b in timed:
    if not os.path.exists(f):
        continue
    d = run(b, f, method)
    if d is None:
        long_rows.append(f"| {name(f)} | {method} | failed | | | | |")
        continue
    who = "before" if b == base and b != bin_ else "this commit"
    long_rows.append(f"| {name(f)} | {method} ({who}) | {d['curves_time_s']:.3f} | {d['written_time_s']:.3f} "
                     f"| {d['time_s']:.2f} | {d['cpu_s']:.2f} |")

load = open("/proc/loadavg").read().split()[0]
with open(out, "w") as o:
    o.write("# `auto` with `fair` as a candidate\n\n")
    o.write(f"Generated by `scripts/auto-fair.sh {tol}` on {time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}, "
            f"commit {commit}, load {load}. `fairpath smooth --method auto --tolerance {tol}` on the\n"
            "default machine: what `auto` chose (sections per candidate), the curves `fair` kept as\n"
            "written (`not faired`), planned times in s of the exact curves and of the written program\n"
            "(arcs) at the programmed feeds and of the curves at the machine's maximum feed (`at V`,\n"
            "`--override-feed`: what `auto` ranks its candidates by), and the computing time of the\n"
            f"first (wall and CPU, s); `before`: the same with {os.environ['BASE_WHAT']} (BASE_BIN"
            + (")" if base else ", not given here)") + ".\n\n")
    o.write("| program | auto chose | not faired | curves s | written s | curves at V s | wall s | CPU s "
            "| before: curves s | before: written s | before: curves at V s | before: wall s | before: CPU s |\n")
    o.write("|---|---|---|---|---|---|---|---|---|---|---|---|---|\n")
    o.write("\n".join(rows) + "\n\n")
    o.write(f"`fair` chosen somewhere on {picks} of {len(rows)} programs.")
    if base:
        o.write(f" Written time, all programs: {sums[0]:.3f} s (before {sums[1]:.3f} s); "
                f"computing time: wall {sums[2]:.2f} s (before {sums[3]:.2f} s), CPU {sums[4]:.2f} s "
                f"(before {sums[5]:.2f} s).")
    o.write("\n\n## Long runs of lines\n\n")
    o.write("`auto` on the large raster (one run of 138,803 lines: `fair` is not offered there), and\n"
            "the two methods that fit lines, alone, on it and on `makerblock_tinycnc.gcode` (two runs\n"
            "of 8,465 lines in all; `auto` offers `fair` on runs and sections of at most 10,000 pieces, `FAIR_MAX_PIECES`).\n\n")
    o.write("| program | method | curves s | written s | wall s | CPU s |\n|---|---|---|---|---|---|\n")
    o.write("\n".join(long_rows) + "\n")
print(open(out).read())
EOF
