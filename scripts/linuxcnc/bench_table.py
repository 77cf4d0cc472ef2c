#!/usr/bin/python3
"""bench.sh's log -> markdown table.   usage: bench_table.py BENCH.log

Log lines: "PROGRAM CASE key=value ..." (run-program.sh / play-stream.sh output,
+ planned=S for fairpath-stream: fairpath's own planned time).
A run is failed when it has no cycles or status=failed (a stream with an
underrun, or not every line played, was not played as written).
Ratios: time / time of the same program's scurve-raw and trapezoid-raw rows.
"""
import re
import sys

CASES = {"trapezoid-raw": "raw, trapezoid (P0)", "scurve-raw": "raw, S-curve (P1)",
         "fairpath-gcode": "fairpath G-code, S-curve (P1)",
         "fairpath-arcfit": "fairpath arc-fit G-code, S-curve (P1)",
         "fairpath-stream": "fairpath stream (halstreamer)"}


def main():
    rows = []
    for ln in open(sys.argv[1]):
        parts = ln.split(" ", 2)
        if len(parts) < 3:
            continue
        prog, case, rest = parts
        d = dict(re.findall(r'(\w+)=("[^"]*"|\S+)', rest))
        ok = d.get("cycles", "NA") != "NA" and d.get("status", "ok") != "failed"
        rows.append((prog, case, d, ok))
    base = {}
    for prog, case, d, ok in rows:
        if ok and case in ("scurve-raw", "trapezoid-raw"):
            base[(prog, case)] = float(d["seconds"])

    def ratio(t, prog, case):
        b = base.get((prog, case))
        return "%.3f" % (t / b) if b else "NA"

    print("| program | case | time s | ratio to S-curve raw | ratio to trapezoid raw "
          "| peak acc mm/s^2 (3D) | peak acc (3D, 5 ms avg) | peak jerk mm/s^3 (3D, 5 ms avg) | peak jerk raw mm/s^3 "
          "| max dev mm | fairpath planned s |")
    print("|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
    for prog, case, d, ok in rows:
        label = CASES.get(case, case)
        planned = d.get("planned", "") if case == "fairpath-stream" else ""
        if not ok:
            why = "failed"
            if d.get("underruns") not in (None, "0", "NA"):
                why += " (underruns=%s)" % d["underruns"]
            elif d.get("played") and d.get("lines") and d["played"] != d["lines"]:
                why += " (played %s of %s lines)" % (d["played"], d["lines"])
            print("| %s | %s | %s | | | | | | | | %s |" % (prog, label, why, planned))
            continue
        t = float(d["seconds"])
        print("| %s | %s | %.3f | %s | %s | %s | %s | %s | %s | %s | %s |" % (
            prog, label, t, ratio(t, prog, "scurve-raw"), ratio(t, prog, "trapezoid-raw"),
            d["acc"], d["acc5"], d["jerk5"], d["jerk"], d.get("max_dev", "NA"), planned))


if __name__ == "__main__":
    main()
