#!/usr/bin/env python3
"""Times Fast Downward's lazy_greedy([hff], preferred=[hff]) (translate included) on the files the
criterion benchmark `first_plan` uses, so that a ratio can be reported.

Usage: python3 benches/fast_downward.py [--runs N]
Needs the `up-fast-downward` pip package (it ships the driver and a `downward` binary).
"""

import argparse
import importlib.util
import os
import statistics
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
FIXTURES = os.path.join(HERE, "..", "tests", "fixtures")
TASKS = [
    ("cafe-18", "cafe-domain.pddl", "cafe-18.pddl"),
    ("cafe-learned-18", "cafe-learned-domain.pddl", "cafe-learned-18.pddl"),
    ("packing-4", "packing-domain.pddl", "packing-4.pddl"),
]


def driver():
    spec = importlib.util.find_spec("up_fast_downward")
    if spec is None:
        sys.exit("up-fast-downward is not installed: pip install up-fast-downward")
    return os.path.join(os.path.dirname(spec.origin), "downward", "fast-downward.py")


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=10)
    runs = parser.parse_args().runs
    script = driver()
    for label, domain, problem in TASKS:
        times = []
        search_times = []
        with tempfile.TemporaryDirectory() as scratch:
            for _ in range(runs):
                start = time.perf_counter()
                result = subprocess.run(
                    [sys.executable, script, "--plan-file", os.path.join(scratch, "sas_plan"),
                     os.path.join(FIXTURES, domain), os.path.join(FIXTURES, problem),
                     "--evaluator", "hff=ff()", "--search", "lazy_greedy([hff], preferred=[hff])"],
                    cwd=scratch, capture_output=True, text=True)
                times.append(time.perf_counter() - start)
                if result.returncode != 0:
                    sys.exit(f"{label}: Fast Downward failed\n{result.stdout}\n{result.stderr}")
                for line in result.stdout.splitlines():
                    if "] Search time:" in line:
                        search_times.append(float(line.split("Search time:")[1].strip().rstrip("s")))
        print(f"{label}: median {statistics.median(times) * 1000:.1f} ms, "
              f"min {min(times) * 1000:.1f} ms over {runs} runs (driver + translate + search); "
              f"search alone median {statistics.median(search_times) * 1000:.1f} ms")


if __name__ == "__main__":
    main()
