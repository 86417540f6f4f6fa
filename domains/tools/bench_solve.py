"""Times `lampc solve` on a spec's problems: wall time and peak memory per solve.

    python3 domains/tools/bench_solve.py domains/cafe/cafe.lamp cafe8_01 cafe18_01
    python3 domains/tools/bench_solve.py domains/packing/packing.lamp --all --limit 0.5
    python3 domains/tools/bench_solve.py domains/dinner/dinner.lamp --all --markdown

The spec must be built (`lampc build`). Each problem is solved once, in its own process, with
the release binary (`target/release/lampc`, built first if missing); solutions go to a scratch
folder that is removed afterwards. The table lists per problem whether it was solved, the wall
time, the peak resident memory of the process, and the counts from its summary; for a failed
solve, where its plans ended and the cause met most there (from the failure report, `failure.json`
beside the solution folder). `--markdown` prints the table as Markdown (`docs/benchmarks.md`
is made of such tables). With `--limit
SECONDS` the exit code is 1 when any solve failed or took longer: the speed targets of the
issues are checked this way, on a quiet machine, never in the test suite.
"""

import argparse
import json
import os
import re
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
LAMPC = ROOT / "target" / "release" / "lampc"


def problems_of(spec: Path) -> list[str]:
    text = spec.read_text(encoding="utf-8")
    return re.findall(r"^problem\s+([A-Za-z_][A-Za-z0-9_-]*)\s*\{", text, flags=re.MULTILINE)


def solve(spec: Path, problem: str, out: Path, timeout: float | None) -> dict:
    command = [str(LAMPC), "solve", str(spec), "--problem", problem, "--out", str(out)]
    if timeout:
        command += ["--timeout", str(timeout)]
    started = time.monotonic()
    child = subprocess.Popen(command, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    _, status, usage = os.wait4(child.pid, 0)
    seconds = time.monotonic() - started
    stderr = child.stderr.read().decode("utf-8", "replace") if child.stderr else ""
    child.stderr.close()
    row = {
        "problem": problem,
        "exit": os.waitstatus_to_exitcode(status),
        "seconds": seconds,
        # ru_maxrss is in kilobytes on Linux.
        "peak_mb": usage.ru_maxrss / 1024,
        "error": stderr.strip().splitlines()[-1] if stderr.strip() else "",
    }
    report = out.with_name(out.name + ".failed") / "failure.json"
    if report.exists():
        row["stopped"] = stopped_at(json.loads(report.read_text(encoding="utf-8")))
    summary = out / "summary.json"
    if summary.exists():
        data = json.loads(summary.read_text(encoding="utf-8"))
        row.update(
            success=data.get("success", False),
            steps=len(data.get("plan", [])),
            candidates=data.get("candidates"),
            plans=data.get("plans_tried"),
        )
    return row


def stopped_at(report: dict) -> str:
    """Where a failed solve's plans ended and the cause met most there, from its failure report."""
    deciding = (report.get("refinement") or {}).get("report", {}).get("deciding", [])
    if not deciding:
        return report.get("code", "")
    ended = deciding[0]
    causes = [c for c in ended.get("causes", []) if c.get("cause") != "no_candidate"]
    steps = ", ".join(str(step) for step in ended.get("steps", []))
    where = f"step {steps} {ended.get('action', '')}"
    if not causes:
        return where
    top = causes[0]
    if top["cause"] == "collision":
        what = f"{top['moving']} touches {top['other']}"
    else:
        what = top["cause"].replace("_", " ")
    return f"{where}: {what}"


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("spec", type=Path)
    parser.add_argument("problems", nargs="*", help="problem names (default with --all: every one)")
    parser.add_argument("--all", action="store_true", help="every problem of the spec")
    parser.add_argument("--limit", type=float, help="seconds a solve may take (exit 1 above it)")
    parser.add_argument("--timeout", type=float, help="lampc's --timeout per solve")
    parser.add_argument("--markdown", action="store_true", help="print a Markdown table")
    args = parser.parse_args()
    problems = problems_of(args.spec) if args.all else args.problems
    if not problems:
        parser.error("name problems or pass --all")
    if not LAMPC.exists():
        subprocess.run(["cargo", "build", "--release", "-p", "lampc"], cwd=ROOT, check=True)
    failed = False
    if args.markdown:
        print("| problem | result | seconds | peak MB | steps | candidates | plans | where it stopped |")
        print("| --- | --- | ---: | ---: | ---: | ---: | ---: | --- |")
    else:
        print(f"{'problem':<16} {'result':<8} {'seconds':>8} {'peak MB':>8} {'steps':>6} {'cands':>6} {'plans':>5}")
    with tempfile.TemporaryDirectory() as scratch:
        for problem in problems:
            row = solve(args.spec, problem, Path(scratch) / problem, args.timeout)
            solved = row["exit"] == 0 and row.get("success", False)
            slow = args.limit is not None and row["seconds"] > args.limit
            failed |= not solved or slow
            result = "solved" if solved else f"exit {row['exit']}"
            if args.markdown:
                stopped = row.get("stopped", row["error"]) if not solved else ""
                print(
                    f"| `{problem}` | {result} | {row['seconds']:.1f} | {row['peak_mb']:.0f} | "
                    f"{row.get('steps', '')} | {row.get('candidates', '')} | {row.get('plans', '')} | "
                    f"{stopped.replace('|', '/')} |"
                )
                continue
            print(
                f"{problem:<16} {result:<8} {row['seconds']:>8.2f} {row['peak_mb']:>8.0f} "
                f"{row.get('steps', ''):>6} {row.get('candidates', ''):>6} {row.get('plans', ''):>5}"
                + ("  (over the limit)" if slow else "")
                + (f"  {row.get('stopped', row['error'])}" if not solved else "")
            )
    return 1 if failed and args.limit is not None else 0


if __name__ == "__main__":
    sys.exit(main())
