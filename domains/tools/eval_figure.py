"""Draws one figure comparing `lampc eval` results across domains with what the paper reports.

    python3 domains/tools/eval_figure.py --out figure.svg keva/eval.json packing/eval.json
    python3 domains/tools/eval_figure.py --out figure.svg eval40/eval.json eval20/eval.json

Each input is an `eval.json` written by `lampc eval` (format lamp-eval, version 1). Files of one
domain with different demonstration counts are merged; two files giving the same domain and count
are refused (exit 2), as is a file of another format. The figure is a grouped bar chart, one
group per domain: per demonstration count the mean solved fraction over the runs, a whisker of
± one sample standard deviation and ticks at the worst and best run, then the paper's result with
its full training set. The same table, with each count's generalization factor (as `lampc eval`'s
report computes it), is printed to stdout in Markdown. Same inputs give the same
bytes: everything is sorted and numbers have a fixed precision.
"""

import argparse
import json
import math
import sys
from pathlib import Path
from xml.sax.saxutils import escape

# What the paper (LAMP, CoRL 2025) states per domain; it gives no per-count numbers. Every domain
# solves 100 % of its unseen test tasks with the full training set of `demos` demonstrations, and
# `factor` is the most objects in a solved test task ÷ the most in training (Jenga's is on the real
# robot; Dinner's is not stated). Its text also claims effective models from as few as 40
# goal-achieving demonstrations, which is what the 90 % target line checks.
PAPER = {
    "packing": {"demos": 200, "factor": "4×"},
    "cafe": {"demos": 200, "factor": "18×"},
    "dinner": {"demos": 200, "factor": None},
    "jenga": {"demos": 160, "factor": "6×"},
    "keva": {"demos": 160, "factor": "10×"},
}
ORDER = ["packing", "cafe", "dinner", "jenga", "keva"]
NAMES = {"cafe": "Café"}
# The project's own targets, drawn as dashed lines: (fraction, label).
TARGETS = [(0.9, "≥ 90 % at 40"), (0.6, "≥ 60 % at 20")]
# Colour-blind safe (Paul Tol's bright scheme), one per demonstration count in ascending order.
PALETTE = ["#4477aa", "#ee6677", "#228833", "#ccbb44", "#66ccee", "#aa3377", "#bbbbbb"]
INK = "#222222"


class InputError(Exception):
    """An input the figure cannot honestly be drawn from; reported on stderr with exit 2."""


def summarize(path: Path, data: dict, count: int) -> dict | None:
    """Mean, sample std, worst and best solved fraction over the runs of one count.

    Like `lampc eval`'s report, a run's fraction is over the rows it has (all the problems in a
    finished evaluation) and runs without rows are left out, so a partial file still matches it.
    """
    total = len(data["problems"])
    fractions = []
    for run in sorted({row["run"] for row in data["rows"] if row["demos"] == count}):
        rows = [row for row in data["rows"] if row["demos"] == count and row["run"] == run]
        if len(rows) != total:
            print(f"{path}: run {run} at {count} has {len(rows)} of {total} problems", file=sys.stderr)
        fractions.append(sum(1 for row in rows if row["solved"] is True) / len(rows))
    if not fractions:
        print(f"{path}: no rows for {count} demonstrations, left out", file=sys.stderr)
        return None
    mean = sum(fractions) / len(fractions)
    spread = sum((f - mean) ** 2 for f in fractions) / (len(fractions) - 1) if len(fractions) > 1 else 0.0
    # The generalization factor as `lampc eval`'s report computes it: the most objects in a solved
    # test task over the most in a demonstration of the pool.
    solved = [row["objects"] for row in data["rows"] if row["demos"] == count and row["solved"] is True]
    training = data.get("pool", {}).get("max_objects", 0)
    return {"runs": len(fractions), "planned_runs": data["runs"], "mean": mean,
            "std": math.sqrt(spread), "worst": min(fractions), "best": max(fractions),
            "largest_solved": max(solved) if solved else None, "training_objects": training}


def load(paths: list[Path]) -> dict[tuple[str, int], dict]:
    """The summaries per (domain, count), refusing a wrong format or a (domain, count) given twice."""
    results: dict[tuple[str, int], dict] = {}
    sources: dict[tuple[str, int], Path] = {}
    for path in paths:
        try:
            data = json.loads(path.read_text(encoding="utf-8"))
        except (OSError, ValueError) as error:
            raise InputError(f"{path}: cannot read it as JSON ({error})") from error
        if not isinstance(data, dict) or (data.get("format"), data.get("version")) != ("lamp-eval", 1):
            found = f"{data.get('format')!r} version {data.get('version')!r}" if isinstance(data, dict) else "no object"
            raise InputError(f"{path}: not a lamp-eval version 1 file (found {found})")
        try:
            domain, counts = str(data["domain"]), sorted(set(data["counts"]))
        except (KeyError, TypeError) as error:
            raise InputError(f"{path}: no domain or counts ({error})") from error
        for count in counts:
            key = (domain, count)
            if key in sources:
                raise InputError(f"{domain} at {count} demonstrations is in both {sources[key]} and {path}")
            sources[key] = path
            summary = summarize(path, data, count)
            if summary is not None:
                results[key] = summary
    return results


def domain_order(domains: set[str]) -> list[str]:
    """The paper's domains in the project's usual order, then any others alphabetically."""
    return [d for d in ORDER if d in domains] + sorted(domains - set(ORDER))


def display(domain: str) -> str:
    return NAMES.get(domain, domain[:1].upper() + domain[1:])


def pct(fraction: float, decimals: int) -> str:
    return f"{fraction * 100:.{decimals}f} %"


def paper_text(domain: str) -> str:
    if domain not in PAPER:
        return "—"
    entry = PAPER[domain]
    factor = f"; generalization {entry['factor']}" if entry["factor"] else ""
    return f"100 % ({entry['demos']} demonstrations{factor})"


def factor_text(summary: dict) -> str:
    """`30× (30 ÷ 1)`, or a dash when nothing was solved or no demonstration shows an object."""
    test, training = summary["largest_solved"], summary["training_objects"]
    if test is None or not training:
        return "—"
    factor = test / training
    shown = f"{factor:.0f}" if factor == round(factor) else f"{factor:.1f}"
    return f"{shown}× ({test} ÷ {training})"


def markdown(results: dict[tuple[str, int], dict]) -> str:
    """The Markdown table, one row per (domain, count); the paper's figure once per domain."""
    lines = ["| domain | demonstrations | runs | solved (mean ± std) | worst | best | generalization | paper |",
             "| --- | ---: | ---: | --- | ---: | ---: | --- | --- |"]
    for domain in domain_order({d for d, _ in results}):
        for index, count in enumerate(sorted(c for d, c in results if d == domain)):
            s = results[(domain, count)]
            paper = paper_text(domain) if index == 0 or domain not in PAPER else ""
            lines.append(f"| {display(domain)} | {count} | {s['runs']} | {pct(s['mean'], 1)} ± {pct(s['std'], 1)} "
                         f"| {pct(s['worst'], 0)} | {pct(s['best'], 0)} | {factor_text(s)} | {paper} |")
    return "\n".join(lines) + "\n"


def num(value: float) -> str:
    """Coordinates with one decimal, so that the bytes do not depend on float noise."""
    text = f"{value:.1f}"
    return "0" if text == "-0.0" else text.removesuffix(".0")


def text(x: float, y: float, size: float, anchor: str, content: str, weight: str = "normal") -> str:
    return (f'<text x="{num(x)}" y="{num(y)}" font-family="sans-serif" font-size="{num(size)}" '
            f'font-weight="{weight}" text-anchor="{anchor}" fill="{INK}">{escape(content)}</text>')


def line(x1: float, y1: float, x2: float, y2: float, stroke: str, width: float, dash: str = "") -> str:
    extra = f' stroke-dasharray="{dash}"' if dash else ""
    return (f'<line x1="{num(x1)}" y1="{num(y1)}" x2="{num(x2)}" y2="{num(y2)}" '
            f'stroke="{stroke}" stroke-width="{num(width)}"{extra}/>')


def rect(x: float, y: float, w: float, h: float, fill: str, stroke: str = "none") -> str:
    return (f'<rect x="{num(x)}" y="{num(y)}" width="{num(w)}" height="{num(h)}" '
            f'fill="{fill}" stroke="{stroke}"/>')


def title_of(results: dict[tuple[str, int], dict]) -> str:
    counts = sorted({c for _, c in results})
    spoken = ", ".join(map(str, counts[:-1])) + (" and " if len(counts) > 1 else "") + str(counts[-1])
    planned = {s["planned_runs"] for s in results.values()}
    # A runs count only says something when every file used the same one.
    runs = f" ({planned.pop()} runs each)" if len(planned) == 1 else ""
    return f"Solved test problems: lamp at {spoken} demonstrations{runs} beside the paper's full training"


def figure(results: dict[tuple[str, int], dict]) -> str:
    """The grouped bar chart as SVG text."""
    width, height = 820.0, 440.0
    left, right, top, bottom = 56.0, 730.0, 76.0, 366.0
    counts = sorted({c for _, c in results})
    colour = {count: PALETTE[i % len(PALETTE)] for i, count in enumerate(counts)}
    domains = domain_order({d for d, _ in results})

    def y(fraction: float) -> float:
        return bottom - (bottom - top) * fraction

    out = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{num(width)}" height="{num(height)}" '
           f'viewBox="0 0 {num(width)} {num(height)}">',
           '<pattern id="paper" width="6" height="6" patternUnits="userSpaceOnUse" patternTransform="rotate(45)">'
           + rect(0, 0, 6, 6, "#ffffff") + line(0, 0, 0, 6, "#777777", 2) + "</pattern>",
           rect(0, 0, width, height, "#ffffff"), text(width / 2, 24, 13, "middle", title_of(results), "bold")]
    legend = [(f"{c} demonstrations", colour[c]) for c in counts] + [("paper, full training set", "url(#paper)")]
    x = left
    for label, fill in legend:
        out += [rect(x, 40, 12, 12, fill, INK if fill.startswith("url") else "none"), text(x + 17, 50, 11, "start", label)]
        x += 17 + 6.2 * len(label) + 18
    out.append("<g>")
    for tick in range(0, 101, 20):
        out += [line(left, y(tick / 100), right, y(tick / 100), "#dddddd" if tick else INK, 1),
                text(left - 6, y(tick / 100) + 4, 11, "end", f"{tick} %")]
    out.append("</g>")
    group = (right - left) / max(len(domains), 1)
    for index, domain in enumerate(domains):
        bars = [(c, results[(domain, c)]) for c in counts if (domain, c) in results]
        slots = len(bars) + (domain in PAPER)
        slot = min(group * 0.86 / slots, 60.0)
        bar = slot * 0.7
        start = left + group * index + (group - slot * slots) / 2
        out.append("<g>")
        for position, (count, s) in enumerate(bars):
            centre = start + slot * (position + 0.5)
            out.append(rect(centre - bar / 2, y(s["mean"]), bar, y(0) - y(s["mean"]), colour[count]))
            low, high = max(0.0, s["mean"] - s["std"]), min(1.0, s["mean"] + s["std"])
            if high > low:
                out += [line(centre, y(low), centre, y(high), INK, 1),
                        line(centre - 3, y(low), centre + 3, y(low), INK, 1),
                        line(centre - 3, y(high), centre + 3, y(high), INK, 1)]
            for extreme in (s["worst"], s["best"]):
                out.append(line(centre - bar / 2 - 3, y(extreme), centre - bar / 2 + 4, y(extreme), INK, 2))
            out.append(text(centre, bottom + 15, 10, "middle", str(count)))
        if domain in PAPER:
            centre = start + slot * (slots - 0.5)
            out += [rect(centre - bar / 2, y(1), bar, y(0) - y(1), "url(#paper)", INK)]
            label = f"paper, {PAPER[domain]['demos']}"
            # A narrow slot cannot hold the label on one line without running into its neighbours.
            if 5.5 * len(label) <= slot:
                out.append(text(centre, bottom + 15, 10, "middle", label))
            else:
                out += [text(centre, bottom + 15, 10, "middle", "paper,"),
                        text(centre, bottom + 26, 10, "middle", str(PAPER[domain]["demos"]))]
        out += [text(left + group * (index + 0.5), bottom + 44, 12, "middle", display(domain), "bold"), "</g>"]
    # The targets go over the bars, so that a bar just short of its target stays readable.
    for fraction, label in TARGETS:
        out += [line(left, y(fraction), right, y(fraction), "#555555", 1, "5 4"),
                text(right + 4, y(fraction) + 4, 10, "start", label)]
    out.append(text(left, height - 10, 10, "start",
                    "Bars: mean over runs; whiskers: ± sample standard deviation; side ticks: worst and best run."))
    out.append("</svg>")
    return "\n".join(out) + "\n"


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("inputs", nargs="+", type=Path, help="eval.json files written by `lampc eval`")
    parser.add_argument("--out", type=Path, required=True, help="the SVG file to write")
    args = parser.parse_args()
    try:
        results = load(args.inputs)
    except InputError as error:
        print(f"eval_figure: {error}", file=sys.stderr)
        return 2
    if not results:
        print("eval_figure: no results in the given files", file=sys.stderr)
        return 2
    args.out.write_text(figure(results), encoding="utf-8")
    sys.stdout.write(markdown(results))
    return 0


if __name__ == "__main__":
    sys.exit(main())
