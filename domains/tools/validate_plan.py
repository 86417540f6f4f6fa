#!/usr/bin/env python3
"""Validates a solution's plan against the model's PDDL with an independent validator.

    python3 domains/tools/validate_plan.py DOMAIN PROBLEM SOLUTION_DIR

DOMAIN and PROBLEM are the build's `model/domain.pddl` and `model/problems/NAME.pddl`;
SOLUTION_DIR is the folder `lampc solve` wrote (`plan.txt`, `summary.json`).

`plan.txt` is split at its `; replan after step N: ...` lines into segments (docs/solving.md). Each
segment is checked with unified-planning's sequential `PlanValidator` (pip `unified-planning`):
the first from the problem's initial state, each later one from the state the segment before
ends in, less the replan's `deleted` atoms, plus its `added` ones (from `summary.json`). Every
segment must be applicable from its start; the last must reach the problem's goal (when the solve
relaxed the goal, the last segment is checked for applicability only, and the output says so).
A replan's `added` atoms must be false and its `deleted` ones true where the segment before ends,
or the report disagrees with the domain about what was predicted.

Prints one line per segment and exits 0 when all are valid, 1 when one is not, 2 on bad input.
"""

import itertools
import json
import sys
from pathlib import Path

from unified_planning.engines import ValidationResultStatus
from unified_planning.io import PDDLReader
from unified_planning.plans import SequentialPlan
from unified_planning.shortcuts import PlanValidator, get_environment


def segments(plan_text):
    """The plan's steps split at its replan comments: (lines, after_step of the mark or None)."""
    parts = [([], None)]
    count = 0
    for line in plan_text.splitlines():
        line = line.strip()
        if not line:
            continue
        if line.startswith(";"):
            if line.startswith("; replan after step "):
                after = int(line[len("; replan after step ") :].split(":", 1)[0])
                if after != count:
                    raise ValueError(f"the mark `{line}` stands after step {count}")
                parts.append(([], after))
            continue
        parts[-1][0].append(line)
        count += 1
    return parts


def atom_text(fluent, objects):
    return "(" + " ".join([fluent.name] + [o.name for o in objects]) + ")"


def ground_atoms(problem):
    """Every ground atom of the problem's boolean fluents, by its `(name a b)` text."""
    atoms = {}
    for fluent in problem.fluents:
        domains = [list(problem.objects(p.type)) for p in fluent.signature]
        for objects in itertools.product(*domains):
            atoms[atom_text(fluent, objects)] = fluent(*objects)
    return atoms


def true_atoms(state, atoms):
    return {text for text, expression in atoms.items() if state.get_value(expression).bool_constant_value()}


def main(argv):
    if len(argv) != 4:
        print(__doc__.strip().splitlines()[2].strip(), file=sys.stderr)
        return 2
    domain, problem_file, solution = argv[1], argv[2], Path(argv[3])
    get_environment().credits_stream = None
    problem = PDDLReader().parse_problem(domain, problem_file)
    plan_text = (solution / "plan.txt").read_text()
    summary = json.loads((solution / "summary.json").read_text())
    parts = segments(plan_text)
    replans = summary["replan_points"]
    marks = [after for _, after in parts[1:]]
    if marks != [replan["after_step"] for replan in replans]:
        print(f"plan.txt marks replans after steps {marks}, summary.json after "
              f"{[r['after_step'] for r in replans]}", file=sys.stderr)
        return 2
    atoms = ground_atoms(problem)
    relaxed = bool(summary.get("relaxed_goal"))
    start = None  # the problem's own initial state
    for index, (lines, after) in enumerate(parts):
        last = index == len(parts) - 1
        segment = problem.clone()
        if start is not None:
            for text, expression in atoms.items():
                segment.set_initial_value(expression, text in start)
        if not last or relaxed:
            segment.clear_goals()
        plan = PDDLReader().parse_plan_string(segment, "\n".join(lines))
        assert isinstance(plan, SequentialPlan)
        with PlanValidator(name="sequential_plan_validator") as validator:
            result = validator.validate(segment, plan)
        first = 1 if after is None else after + 1
        what = "reaches the goal" if last and not relaxed else "is applicable"
        where = "the initial state" if after is None else f"the state of the replan after step {after}"
        if result.status != ValidationResultStatus.VALID:
            reason = "; ".join(message.message for message in result.log_messages or [])
            print(f"segment {index + 1} (steps {first}-{first + len(lines) - 1}) from {where}: INVALID: {reason}")
            return 1
        print(f"segment {index + 1} (steps {first}-{first + len(lines) - 1}) from {where}: valid, {what}")
        if last:
            break
        end = true_atoms(result.trace[-1], atoms)
        replan = replans[index]
        wrong = [a for a in replan["added"] if a in end] + [a for a in replan["deleted"] if a not in end]
        if wrong:
            print(f"replan after step {replan['after_step']}: the domain predicts otherwise for {' '.join(wrong)}")
            return 1
        start = (end - set(replan["deleted"])) | set(replan["added"])
    if relaxed:
        print(f"the goal was relaxed ({', '.join(summary['relaxed_goal'])}): the last segment was checked for applicability only")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
