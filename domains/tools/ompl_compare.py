#!/usr/bin/env python3
"""Runs OMPL's RRT-Connect on the arm queries lamp planned, and prints both side by side.

    cargo run --release -p lamp-world --example arm_queries -- /tmp/queries.json
    python3 domains/tools/ompl_compare.py /tmp/queries.json [--runs 3] [--timeout 10]

The example writes each scene (the robot's URDF and base pose, the self-collision pairs lamp
checks, the planning group's joints, the obstacles as primitives at their world poses) with 20
queries and lamp's results over 5 seeds. Here the same scene is loaded into pybullet (DIRECT
mode) and every query is planned by OMPL's RRTConnect, `--runs` times, with a validity checker
that asks pybullet for contacts, and the path simplified by `PathSimplifier.simplifyMax`.

Both sides check edges at lamp's resolution (`MotionConfig::default()`: 0.01 rad for angles,
5 mm for lengths). OMPL subdivides an edge by its space's distance: here the state space is the
group's joints each divided by its resolution, and OMPL checks a state every 1 unit of Euclidean
distance, so no joint moves more than its resolution between checked states (OMPL checks at
least as many states per edge as lamp, more on edges that move many joints). Its range is
lamp's step, 0.5 rad. Path lengths are measured in lamp's metric (its joint weights, continuous
joints the short way round) and given as a ratio to the straight joint distance.

Before planning, the pybullet checker's verdicts are compared with lamp's on the sampled states
the example wrote, and both are timed per check.

Prints one Markdown table. Exits 2 on bad input.
"""

import argparse
import json
import math
import os
import statistics
import sys
import time

from bullet_quiet import quiet_stdout


with quiet_stdout():
    import pybullet as p

from ompl import base as ob
from ompl import geometric as og
from ompl import util as ou


CONTACT_TOLERANCE = 0.002


def wrap(angle):
    return math.atan2(math.sin(angle), math.cos(angle))


class Checker:
    """One scene in pybullet: the robot on its base, the obstacles, and lamp's self pairs."""

    def __init__(self, scene):
        self.client = p.connect(p.DIRECT)
        base = scene["base"]
        with quiet_stdout():
            self.robot = p.loadURDF(scene["urdf"], base["position"], base["orientation"],
                                    useFixedBase=True, flags=p.URDF_USE_SELF_COLLISION,
                                    physicsClientId=self.client)
        links = {p.getBodyInfo(self.robot, physicsClientId=self.client)[0].decode(): -1}
        joints = {}
        for j in range(p.getNumJoints(self.robot, physicsClientId=self.client)):
            info = p.getJointInfo(self.robot, j, physicsClientId=self.client)
            links[info[12].decode()] = j
            joints[info[1].decode()] = j
        self.indices = [joints[j["name"]] for j in scene["joints"]]
        for name, value in scene["other_joints"].items():
            p.resetJointState(self.robot, joints[name], value, physicsClientId=self.client)
        # Only the link pairs lamp checks: pybullet's own rule (every pair but parent and
        # child) would also check pairs the robot's description says to ignore.
        checked = {frozenset((links[a], links[b])) for a, b in scene["self_collision_pairs"]}
        ids = sorted(links.values())
        for i, a in enumerate(ids):
            for b in ids[i + 1:]:
                p.setCollisionFilterPair(self.robot, self.robot, a, b,
                                         int(frozenset((a, b)) in checked),
                                         physicsClientId=self.client)
        for obstacle in scene["obstacles"]:
            kind = obstacle["shape"]
            if kind == "box":
                shape = dict(shapeType=p.GEOM_BOX, halfExtents=obstacle["half_extents"])
            elif kind == "cylinder":
                shape = dict(shapeType=p.GEOM_CYLINDER, radius=obstacle["radius"],
                             height=obstacle["length"])
            else:
                shape = dict(shapeType=p.GEOM_SPHERE, radius=obstacle["radius"])
            collision = p.createCollisionShape(physicsClientId=self.client, **shape)
            p.createMultiBody(baseMass=0, baseCollisionShapeIndex=collision,
                              basePosition=obstacle["pose"]["position"],
                              baseOrientation=obstacle["pose"]["orientation"],
                              physicsClientId=self.client)
        # lamp's scenes count touching as a collision. Bullet's contacts between its primitives
        # (cylinders above all) report up to about 2 mm of depth where parry's exact distance
        # finds the shapes apart: without this tolerance the start of every Café query, which
        # lamp finds clear, is in collision (the agreement table shows what is left).
        self.limit = scene["margin"] - CONTACT_TOLERANCE
        self.checks = 0

    def valid(self, q):
        self.checks += 1
        for index, value in zip(self.indices, q):
            p.resetJointState(self.robot, index, value, physicsClientId=self.client)
        p.performCollisionDetection(physicsClientId=self.client)
        for contact in p.getContactPoints(bodyA=self.robot, physicsClientId=self.client):
            if contact[8] <= self.limit:
                return False
        return True


class Space:
    """The group's joints in units of their checking resolution, for OMPL."""

    def __init__(self, scene):
        self.joints = scene["joints"]
        resolution = scene["resolution"]
        self.scale = [resolution["linear"] if j["kind"] == "linear" else resolution["angular"]
                      for j in self.joints]
        n = len(self.joints)
        self.space = ob.RealVectorStateSpace(n)
        bounds = ob.RealVectorBounds(n)
        for i, (joint, scale) in enumerate(zip(self.joints, self.scale)):
            low, high = joint["lower"], joint["upper"]
            if joint["kind"] == "wrapped" or not (math.isfinite(low) and math.isfinite(high)):
                low, high = -math.pi, math.pi
            bounds.setLow(i, low / scale)
            bounds.setHigh(i, high / scale)
        self.space.setBounds(bounds)

    def to_ompl(self, q):
        return [(wrap(v) if j["kind"] == "wrapped" else v) / s
                for v, j, s in zip(q, self.joints, self.scale)]

    def from_ompl(self, state):
        return [state[i] * s for i, s in enumerate(self.scale)]

    def distance(self, a, b):
        """lamp's metric: weighted Euclidean, continuous joints the short way round."""
        total = 0.0
        for x, y, joint in zip(a, b, self.joints):
            d = wrap(y - x) if joint["kind"] == "wrapped" else y - x
            total += joint["weight"] * d * d
        return math.sqrt(total)

    def length(self, path):
        return sum(self.distance(a, b) for a, b in zip(path, path[1:]))


def plan(scene, space, checker, query, timeout):
    """One RRTConnect run and its simplification: success, ms, raw and simplified length,
    checks in all and to find the path."""
    si = ob.SpaceInformation(space.space)
    si.setStateValidityChecker(lambda state: checker.valid(space.from_ompl(state)))
    # One unit of the scaled space is one resolution step of every joint.
    si.setStateValidityCheckingResolution(1.0 / space.space.getMaximumExtent())
    si.setup()
    start, goal = si.allocState(), si.allocState()
    for i, (a, b) in enumerate(zip(space.to_ompl(query["start"]), space.to_ompl(query["goal"]))):
        start[i], goal[i] = a, b
    problem = ob.ProblemDefinition(si)
    problem.setStartAndGoalStates(start, goal)
    planner = og.RRTConnect(si)
    planner.setRange(scene["step"] / scene["resolution"]["angular"])
    planner.setProblemDefinition(problem)
    planner.setup()
    checker.checks = 0
    began = time.perf_counter()
    planner.solve(timeout)
    if not problem.hasExactSolution():
        return dict(success=False, ms=(time.perf_counter() - began) * 1e3)
    path = problem.getSolutionPath()
    search_checks = checker.checks
    raw = [space.from_ompl(path.getState(i)) for i in range(path.getStateCount())]
    og.PathSimplifier(si).simplifyMax(path)
    ms = (time.perf_counter() - began) * 1e3
    simplified = [space.from_ompl(path.getState(i)) for i in range(path.getStateCount())]
    return dict(success=True, ms=ms, raw_length=space.length(raw),
                length=space.length(simplified), checks=checker.checks,
                search_checks=search_checks)


def p90(values):
    values = sorted(values)
    return values[round(0.9 * (len(values) - 1))]


def row(name, planner, runs):
    solved = [(q, r) for q, r in runs if r["success"]]
    times = [r["ms"] for _, r in runs]
    raw = statistics.median(r["raw_length"] / q["straight"] for q, r in solved)
    simplified = statistics.median(r["length"] / q["straight"] for q, r in solved)
    checks = statistics.median(r["checks"] for _, r in solved)
    search = statistics.median(r["search_checks"] for _, r in solved)
    return (f"| {name} | {planner} | {len(solved)}/{len(runs)} | "
            f"{statistics.median(times):,.1f} / {p90(times):,.1f} ms | "
            f"{raw:.2f} / {simplified:.2f} | {checks:,.0f} ({search:,.0f}) |")


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("queries", help="the JSON file the arm_queries example wrote")
    parser.add_argument("--runs", type=int, default=3, help="OMPL runs per query (3)")
    parser.add_argument("--timeout", type=float, default=10.0,
                        help="seconds per OMPL run, lamp's own limit (10)")
    args = parser.parse_args()
    try:
        with open(args.queries) as stream:
            scenes = json.load(stream)["scenes"]
    except (OSError, ValueError, KeyError) as error:
        print(f"cannot read {args.queries}: {error}", file=sys.stderr)
        return 2
    ou.setLogLevel(ou.LOG_ERROR)
    ou.RNG.setSeed(1)
    table, checks = [], []
    for scene in scenes:
        checker = Checker(scene)
        space = Space(scene)
        states, lamp_valid = scene["check_states"], scene["check_valid"]
        began = time.perf_counter()
        verdicts = [checker.valid(q) for q in states]
        pybullet_us = (time.perf_counter() - began) * 1e6 / len(states)
        agree = sum(a == b for a, b in zip(verdicts, lamp_valid))
        checks.append(f"| {scene['name']} | {scene['check_us']['planner']:.1f} µs "
                      f"({scene['check_us']['whole_robot']:.1f} µs whole robot) | "
                      f"{pybullet_us:.1f} µs | {agree} of {len(states)} "
                      f"({sum(lamp_valid)} valid for lamp, {sum(verdicts)} for pybullet) |")
        lamp_runs = [(q, r) for q in scene["queries"] for r in q["lamp"]]
        table.append(row(scene["name"], "lamp", lamp_runs))
        ompl_runs = [(q, plan(scene, space, checker, q, args.timeout))
                     for q in scene["queries"] for _ in range(args.runs)]
        table.append(row(scene["name"], "OMPL RRTConnect", ompl_runs))
        p.disconnect(checker.client)
    print("| scene | planner | success | median / p90 time | length raw / simplified "
          "| checks (to find a path) |")
    print("|---|---|---|---|---|---|")
    print("\n".join(table))
    print()
    print("| scene | one check, lamp | one check, pybullet | same verdict |")
    print("|---|---|---|---|")
    print("\n".join(checks))
    return 0


if __name__ == "__main__":
    code = main()
    sys.stdout.flush()
    # The OMPL bindings report leaked objects at interpreter exit; nothing is left to clean.
    os._exit(code)
