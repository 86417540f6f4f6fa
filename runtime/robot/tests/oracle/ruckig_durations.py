"""Ruckig's time-optimal duration of rest-to-rest moves, the oracle of ruckig_oracle.rs.

Reads a JSON list of moves from the file named by the first argument, each
{"displacement": [...], "velocity": [...], "acceleration": [...]} with one entry per joint, and
prints one duration in seconds per line. Jerk is unlimited, as lamp's timing does not limit it, so
each joint's profile is the acceleration-limited trapezoid; joints are synchronised in time, so the
duration is that of the slowest joint.
"""
import json
import math
import sys

from ruckig import InputParameter, Result, Ruckig, Trajectory

with open(sys.argv[1]) as stream:
    moves = json.load(stream)
for move in moves:
    dofs = len(move["displacement"])
    request = InputParameter(dofs)
    request.current_position = [0.0] * dofs
    request.current_velocity = [0.0] * dofs
    request.current_acceleration = [0.0] * dofs
    request.target_position = move["displacement"]
    request.target_velocity = [0.0] * dofs
    request.target_acceleration = [0.0] * dofs
    request.max_velocity = move["velocity"]
    request.max_acceleration = move["acceleration"]
    request.max_jerk = [math.inf] * dofs
    trajectory = Trajectory(dofs)
    result = Ruckig(dofs).calculate(request, trajectory)
    if result not in (Result.Working, Result.Finished):
        sys.exit(f"ruckig refused {move}: {result}")
    print(repr(trajectory.duration))
