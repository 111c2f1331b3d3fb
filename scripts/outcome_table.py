#!/usr/bin/env python3
"""One outcome table for several demonstrations (issue 17), from `rbaa evaluate` outputs.

    python3 scripts/outcome_table.py hoop=out/ball/demo bin=out/bunny/demo star=out/star/demo \
        [--out=FILE]

Each NAME=DIR is the --out of `rbaa evaluate --config=configs/demos/<demo>.yaml ...`; the table
reads DIR/report.json only (its `outcomes`, the step, how far the stiff baseline strays from its
rigid twin, the rigid twins' agreement and the runs' wall times), so it says nothing an evaluation
did not measure. Per demonstration one row per simulator: the reference, adversarial and soft
control runs' predicate (yes/no) or, for a demonstration without one, its figure in degrees.
Written as Markdown to stdout or --out. A directory without a report.json, or a report without
`outcomes` (not a demonstration), is a one-line error naming it.
"""
import json
import os
import sys

OBJECTS = ("reference", "adversarial", "soft control")


def fail(message):
    print(f"outcome_table: {message}", file=sys.stderr)
    sys.exit(1)


def cell(run):
    """A run's outcome: its predicate, with the figure beside it when the demo has one."""
    if run is None:
        return "not run"
    parts = []
    if run.get("predicate") is not None:
        parts.append("**yes**" if run["predicate"] else "**no**")
    if run.get("figure_deg") is not None and (run.get("predicate") is None or run["figure_deg"] != 0):
        parts.append(f"{run['figure_deg']:.3g} deg")
    return ", ".join(parts) if parts else "-"


def rows_of(name, directory):
    path = os.path.join(directory, "report.json")
    if not os.path.isfile(path):
        fail(f"{name}: no report.json in {directory} (give NAME=DIR, DIR an `rbaa evaluate --out`)")
    try:
        with open(path) as f:
            report = json.load(f)
    except (OSError, ValueError) as e:  # ValueError: bad JSON, or bytes that are not UTF-8
        fail(f"{path}: {e}")
    if not isinstance(report, dict):
        fail(f"{path}: not an `rbaa evaluate` report (a JSON object)")
    outcomes = report.get("outcomes")
    if not isinstance(outcomes, dict) or not outcomes:
        fail(f"{path}: no 'outcomes' (not a demonstration: its config has no 'demonstration' block)")
    runs = {}
    for i, r in enumerate(outcomes.get("runs") or []):
        if not isinstance(r, dict) or "simulator" not in r or "object" not in r:
            fail(f"{path}: outcomes.runs[{i}] has no 'simulator' and 'object' "
                 "(not written by `rbaa evaluate`?)")
        runs[(r["simulator"], r["object"])] = r
    step = report.get("time_step_s")
    strays = report.get("baseline_disagreement")
    twins = (report.get("rigid_vs_rigid") or {}).get("max_com_gap_m")
    times = report.get("timing_s", {})
    what = outcomes.get("predicate", "none")
    if what == "none":
        what = f"figure: {outcomes.get('figure', '-')} ({outcomes.get('figure_against', '')})"
    out = []
    for simulator in ("rigid", "deformable"):
        cells = [cell(runs.get((simulator, o))) for o in OBJECTS]
        wall = sum(t for k, t in times.items() if k.startswith(simulator))
        extra = (f"twins {twins:.2g} m apart" if simulator == "rigid" and twins is not None
                 else f"h = {step:.4g} s, baseline strays {100 * strays:.3g} %"
                 if simulator == "deformable" and step and strays is not None else "")
        out.append(f"| {name} | {what} | {simulator} | " + " | ".join(cells) +
                   f" | {extra} | {wall:.0f} |")
    return out


def main(argv):
    out_file = None
    pairs = []
    for arg in argv:
        if arg.startswith("--out="):
            out_file = arg[len("--out="):]
        elif arg in ("-h", "--help"):
            print(__doc__)
            return 0
        elif "=" in arg and not arg.startswith("-"):
            name, directory = arg.split("=", 1)
            if not name or not directory:
                fail(f"'{arg}' needs a name and a directory (NAME=DIR)")
            pairs.append((name, directory))
        else:
            fail(f"unknown argument '{arg}' (NAME=DIR ... [--out=FILE])")
    if not pairs:
        fail("no demonstrations given (NAME=DIR ...)")
    lines = ["| demo | predicate / figure | simulator | reference | adversarial | soft control | "
             "step and baseline | wall (s) |",
             "|---|---|---|---|---|---|---|---|"]
    for name, directory in pairs:
        lines += rows_of(name, directory)
    text = "\n".join(lines) + "\n"
    if out_file:
        try:
            with open(out_file, "w") as f:
                f.write(text)
        except OSError as e:
            fail(f"--out={out_file}: {e.strerror}")
    else:
        sys.stdout.write(text)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
