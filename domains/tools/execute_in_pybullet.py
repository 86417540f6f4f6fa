#!/usr/bin/env python3
"""Executes a solution as a robot would, in pybullet with physics on, and checks where things end up.

    python3 domains/tools/execute_in_pybullet.py SOLUTION.mcap [--json REPORT.json]

SOLUTION.mcap is the `trajectory.mcap` that `lampc solve` writes. Only what a ROS 2 robot would be
sent is executed (docs/formats.md, "Channels for controllers"):
- `/lamp/joint_trajectory`: the arm's and torso's joints follow it under pybullet's position
  control, each joint's force within its URDF effort;
- `/lamp/base_trajectory`: a mobile base or a free-flying gripper is pulled along the commanded
  poses by a stiff constraint (a base controller that tracks its command);
- `/lamp/gripper_command`: a gripper with finger joints closes its fingers at their URDF speed
  and squeezes with 20 N each (the object is held by friction alone), and opens them to the
  commanded position at a release; a gripper without finger joints (a magnet) takes an object
  only if it touches it when switched on (within 2 mm: 1 mm of reach and the 1 mm gap
  above its support at which lamp's world rests an object, which it falls here).
Everything else comes from the file too: the robot's URDF (`/robot_description`), the objects'
shapes (`/lamp/scene`) and their start poses (`/lamp/world`'s first step). An object of a type the
robot ever holds is a dynamic body (uniform density 600 kg/m³, friction 0.8); every other object
(tables, the box, markers) is fixed where it starts. docs/solving.md, "Executing a solution in
physics", says why each modelling choice was made and what it found.

While the solution runs, each dynamic object is compared with its pose on `/lamp/world` ten times
a second: the first time it leaves it (by 5 mm or 3°, or 1 cm while held) is reported, and so is
the first time a held object presses on another body with more than 10 N. After the last command
and two seconds of settling, every dynamic object's pose is compared with its pose at the
solution's last step: further than 5 mm or turned more than 3°, it did not come to rest where the
solver put it.

Prints the events, one line per dynamic object and a verdict; exits 0 when every object ends
within the tolerance, 1 when one does not, 2 on bad input.
"""

import argparse
import json
import math
import sys
import tempfile
from bisect import bisect_right
from pathlib import Path

from mcap.reader import make_reader
from mcap_ros2.decoder import DecoderFactory


from bullet_quiet import quiet_stdout


with quiet_stdout():
    import pybullet as p


# 240 Hz, pybullet's default, let a Jenga block held in the Fetch's fingers pass through its
# neighbours' contacts; at 960 Hz a 6-block tower stands within 5 mm of the solution's poses.
SIM_HZ = 960
ARM_GAIN = 0.3
SETTLE_SECONDS = 2.0
DENSITY = 600.0
FRICTION = 0.8
POSITION_TOLERANCE = 0.005
ANGLE_TOLERANCE = math.radians(3.0)
SLIP_DISTANCE = 0.01
# A magnet's reach, 1 mm, plus the 1 mm above its support at which lamp's world
# rests an object (docs/world.md) and which it falls here.
MAGNET_REACH = 0.002
PRESS_FORCE = 10.0
LINK_MASS = 0.2
PAD_PATCH = 0.01
BASE_MASS = 10.0
MOUNT_FORCE = 1e5
FINGER_STIFFNESS = 2000.0
FINGER_DAMPING = 50.0
SQUEEZE = 0.01
LINK_INERTIA = 1e-3


def seconds(stamp):
    return stamp.sec + stamp.nanosec * 1e-9


def read_solution(path):
    """The solution's header, steps, scene, URDF, static frames and controller commands."""
    out = {"world": [], "joint": [], "base": [], "gripper": [], "tf_static": []}
    topics = ["/lamp/world", "/robot_description", "/tf_static",
              "/lamp/joint_trajectory", "/lamp/base_trajectory", "/lamp/gripper_command"]
    with open(path, "rb") as stream:
        reader = make_reader(stream, decoder_factories=[DecoderFactory()])
        out["header"] = next((r.metadata for r in reader.iter_metadata() if r.name == "lamp"), None)
        if out["header"] is None:
            raise ValueError("not a lamp solution (no `lamp` metadata record)")
        if len(out["header"]["robots"].split("\n")) != 1:
            raise ValueError("only solutions with one robot are executed")
        for _, channel, message, decoded in reader.iter_decoded_messages(topics=topics):
            time = message.log_time * 1e-9
            topic = channel.topic
            if topic == "/lamp/world":
                out["world"].append((time, decoded))
            elif topic == "/robot_description":
                out["urdf"] = decoded.data
            elif topic == "/tf_static":
                out["tf_static"].extend(decoded.transforms)
            elif topic == "/lamp/joint_trajectory":
                out["joint"].append((time, decoded))
            elif topic == "/lamp/base_trajectory":
                out["base"].append((time, decoded))
            elif topic == "/lamp/gripper_command":
                out["gripper"].append((time, decoded.position))
        for _, channel, message in reader.iter_messages(topics=["/lamp/scene"]):
            out["scene"] = json.loads(message.data)
    if not out["world"] or "urdf" not in out or "scene" not in out:
        raise ValueError("not a lamp solution (no /lamp/world, /robot_description or /lamp/scene)")
    return out


class Timeline:
    """A coordinate's commanded position over time: linear between a trajectory's points, held
    at its last point until the next trajectory."""

    def __init__(self):
        self.times = []
        self.values = []

    def add(self, time, value):
        self.times.append(time)
        self.values.append(value)

    def at(self, time):
        i = bisect_right(self.times, time)
        if i == 0:
            return self.values[0]
        if i == len(self.times):
            return self.values[-1]
        t0, t1 = self.times[i - 1], self.times[i]
        v0, v1 = self.values[i - 1], self.values[i]
        if t1 <= t0:
            return v1
        return v0 + (v1 - v0) * (time - t0) / (t1 - t0)


def timelines(trajectories):
    lines = {}
    for start, message in trajectories:
        for point in message.points:
            time = start + seconds(point.time_from_start)
            for name, value in zip(message.joint_names, point.positions):
                lines.setdefault(name, Timeline()).add(time, value)
    return lines


def quaternion_from_rotation_vector(rx, ry, rz):
    angle = math.sqrt(rx * rx + ry * ry + rz * rz)
    if angle < 1e-12:
        return (0.0, 0.0, 0.0, 1.0)
    s = math.sin(angle / 2) / angle
    return (rx * s, ry * s, rz * s, math.cos(angle / 2))


def mount_pose(coordinates):
    """The root link's pose for the mount's coordinates (docs/robots.md, "Mounts")."""
    if set(coordinates) == {"base_x", "base_y", "base_yaw"}:
        yaw = coordinates["base_yaw"]
        return (coordinates["base_x"], coordinates["base_y"], 0.0), p.getQuaternionFromEuler((0, 0, yaw))
    position = (coordinates["base_x"], coordinates["base_y"], coordinates["base_z"])
    rotation = quaternion_from_rotation_vector(
        coordinates["base_rx"], coordinates["base_ry"], coordinates["base_rz"])
    return position, rotation


class Object:
    """One `/lamp/scene` entity as a pybullet body."""

    def __init__(self, body, centre):
        self.body, self.centre = body, centre

    def pose(self):
        """The object's own frame's pose: pybullet reports its centre of mass's."""
        position, orientation = p.getBasePositionAndOrientation(self.body)
        return p.multiplyTransforms(position, orientation, [-c for c in self.centre], [0, 0, 0, 1])

    @staticmethod
    def add(entity, pose, dynamic):
        """A pybullet body for one `/lamp/scene` entity at its world pose: one compound shape, its
        centre of mass the volume-weighted centre of its parts."""
        kinds, frames = [], []
        for cube in entity["cubes"]:
            s = cube["size"]
            kinds.append(dict(shapeType=p.GEOM_BOX, halfExtents=[s["x"] / 2, s["y"] / 2, s["z"] / 2]))
            frames.append(cube["pose"])
        for cylinder in entity["cylinders"]:
            s = cylinder["size"]
            kinds.append(dict(shapeType=p.GEOM_CYLINDER, radius=s["x"] / 2, height=s["z"]))
            frames.append(cylinder["pose"])
        for sphere in entity["spheres"]:
            kinds.append(dict(shapeType=p.GEOM_SPHERE, radius=sphere["size"]["x"] / 2))
            frames.append(sphere["pose"])
        for triangles in entity["triangles"]:
            vertices = [[q["x"], q["y"], q["z"]] for q in triangles["points"]]
            kinds.append(dict(shapeType=p.GEOM_MESH, vertices=vertices,
                              indices=list(range(len(vertices)))))
            frames.append(triangles["pose"])
        if not kinds:
            return None
        positions = [[f["position"][k] for k in "xyz"] for f in frames]
        orientations = [[f["orientation"][k] for k in "xyzw"] for f in frames]
        shapes = [p.createCollisionShape(collisionFramePosition=position,
                                         collisionFrameOrientation=orientation, **kind)
                  for kind, position, orientation in zip(kinds, positions, orientations)]
        if len(shapes) == 1:
            shape = shapes[0]
        elif any(k["shapeType"] == p.GEOM_MESH for k in kinds):
            raise ValueError(f"`{entity['id']}` joins a mesh to other shapes, which this check "
                             f"does not build")
        else:
            shape = p.createCollisionShapeArray(
                shapeTypes=[k["shapeType"] for k in kinds],
                halfExtents=[k.get("halfExtents", [0, 0, 0]) for k in kinds],
                radii=[k.get("radius", 0) for k in kinds],
                lengths=[k.get("height", 0) for k in kinds],
                collisionFramePositions=positions,
                collisionFrameOrientations=orientations)
        mass, centre = 0.0, [0.0, 0.0, 0.0]
        if dynamic:
            volumes = list(shape_volume(entity))
            mass = DENSITY * sum(volumes)
            centre = [sum(v * q[i] for v, q in zip(volumes, positions)) / sum(volumes)
                      for i in range(3)]
        body = p.createMultiBody(baseMass=mass, baseCollisionShapeIndex=shape,
                                 baseInertialFramePosition=centre,
                                 basePosition=pose[0], baseOrientation=pose[1])
        p.changeDynamics(body, -1, lateralFriction=FRICTION, spinningFriction=0.001,
                         rollingFriction=0.0001, frictionAnchor=True)
        return Object(body, centre)


def shape_volume(entity):
    for cube in entity["cubes"]:
        s = cube["size"]
        yield s["x"] * s["y"] * s["z"]
    for cylinder in entity["cylinders"]:
        s = cylinder["size"]
        yield math.pi * (s["x"] / 2) ** 2 * s["z"]
    for sphere in entity["spheres"]:
        yield 4 / 3 * math.pi * (sphere["size"]["x"] / 2) ** 3
    for triangles in entity["triangles"]:
        xs = [[q[k] for k in "xyz"] for q in triangles["points"]]
        lo = [min(v[i] for v in xs) for i in range(3)]
        hi = [max(v[i] for v in xs) for i in range(3)]
        yield (hi[0] - lo[0]) * (hi[1] - lo[1]) * (hi[2] - lo[2])


def pose_error(a, b):
    """Distance and rotation angle between two (position, quaternion) poses."""
    distance = math.dist(a[0], b[0])
    dot = abs(sum(x * y for x, y in zip(a[1], b[1])))
    return distance, 2 * math.acos(min(1.0, dot))


def step_poses(step, bodies):
    return {name: ((pose.position.x, pose.position.y, pose.position.z),
                   (pose.orientation.x, pose.orientation.y, pose.orientation.z, pose.orientation.w))
            for name, pose in zip(bodies, step.body_poses)}


class Robot:
    """The solution's robot in pybullet: its URDF on its mount, the arm under position control."""

    def __init__(self, solution, coordinates, initial):
        self.mount = [c for c in coordinates if c.startswith("base_")]
        with tempfile.NamedTemporaryFile("w", suffix=".urdf", delete=False) as urdf:
            urdf.write(solution["urdf"])
        with quiet_stdout():
            self.body = p.loadURDF(urdf.name, useFixedBase=not self.mount)
        Path(urdf.name).unlink()
        self.joints = {}
        for j in range(p.getNumJoints(self.body)):
            info = p.getJointInfo(self.body, j)
            if info[2] != p.JOINT_FIXED:
                self.joints[info[1].decode()] = (j, info)
        self.arm = timelines(solution["joint"])
        self.base = timelines(solution["base"])
        self.initial = initial
        # The trajectories name every joint but the fingers, which the gripper command drives.
        self.fingers = [n for n in self.joints if n not in self.arm] if self.arm else []
        if self.mount:
            position, orientation = mount_pose({c: initial[c] for c in self.mount})
        else:
            root = p.getBodyInfo(self.body)[0].decode()
            fixed = next((t for t in solution["tf_static"] if t.child_frame_id == root), None)
            if fixed is None:
                raise ValueError(f"no /tf_static transform places the root link `{root}`")
            tr, rot = fixed.transform.translation, fixed.transform.rotation
            position, orientation = (tr.x, tr.y, tr.z), (rot.x, rot.y, rot.z, rot.w)
        p.resetBasePositionAndOrientation(self.body, position, orientation)
        for name, (index, _) in self.joints.items():
            p.resetJointState(self.body, index, initial.get(name, 0.0))
        for link in range(-1, p.getNumJoints(self.body)):
            # A pad touches over an area: pybullet's one point per pad needs rolling and spinning
            # friction to resist the turn a patch resists.
            p.changeDynamics(self.body, link, lateralFriction=FRICTION, frictionAnchor=True,
                             rollingFriction=PAD_PATCH, spinningFriction=PAD_PATCH)
            if link >= 0:
                # A URDF without inertial data gets bullet's 1 kg and 1 kg·m² per link, far
                # heavier to turn than an arm's links; a light link stands for a controller that
                # compensates gravity. A fixed mount's root keeps mass 0, which fixes it.
                p.changeDynamics(self.body, link, mass=LINK_MASS,
                                 localInertiaDiagonal=[LINK_INERTIA] * 3)
        if self.mount:
            # A moving mount is driven by a stiff constraint, not set: its links then move with
            # a velocity, and what the fingers hold is carried by friction.
            p.changeDynamics(self.body, -1, mass=BASE_MASS)
            self.drive = p.createConstraint(self.body, -1, -1, -1, p.JOINT_FIXED, [0, 0, 0],
                                            [0, 0, 0], position, childFrameOrientation=orientation)

    def command(self, time):
        """Sends the arm and the mount where their trajectories are at `time`."""
        if self.mount:
            position, orientation = mount_pose(
                {c: self.base[c].at(time) if c in self.base else self.initial[c]
                 for c in self.mount})
            p.changeConstraint(self.drive, jointChildPivot=position,
                               jointChildFrameOrientation=orientation, maxForce=MOUNT_FORCE)
        for name, line in self.arm.items():
            index, info = self.joints[name]
            p.setJointMotorControl2(self.body, index, p.POSITION_CONTROL,
                                    targetPosition=line.at(time), force=info[10] or 100.0,
                                    positionGain=ARM_GAIN)


class Fingers:
    """A gripper with finger joints, force-controlled: a grasp squeezes, a release opens."""

    def __init__(self, robot):
        self.robot = robot
        self.target = {n: robot.initial.get(n, 0.0) for n in robot.fingers}
        self.setpoint = dict(self.target)
        for name in robot.fingers:
            p.setJointMotorControl2(robot.body, robot.joints[name][0], p.VELOCITY_CONTROL, force=0)

    def command(self, position, time, events):
        # A grasp pulls each finger SQUEEZE past where it meets the object, so that it presses
        # with FINGER_STIFFNESS · SQUEEZE (20 N) and an object pushed off centre is pushed back;
        # a release opens to the command.
        robot = self.robot
        current = p.getJointState(robot.body, robot.joints[robot.fingers[0]][0])[0]
        closing = position < current - 1e-6
        for name in robot.fingers:
            self.target[name] = position - SQUEEZE if closing else position

    def step(self):
        robot = self.robot
        for name in robot.fingers:
            index, info = robot.joints[name]
            q, v = p.getJointState(robot.body, index)[:2]
            lower, upper, effort, speed = info[8], info[9], info[10] or 60.0, info[11] or 0.05
            # The setpoint moves at the finger's speed limit toward its goal, as the gripper's
            # motor would; a PD pulls the finger to it, its force within the URDF effort.
            goal = min(max(self.target[name], lower - SQUEEZE), upper)
            stride = speed / SIM_HZ
            self.setpoint[name] += max(-stride, min(stride, goal - self.setpoint[name]))
            force = FINGER_STIFFNESS * (self.setpoint[name] - q) - FINGER_DAMPING * v
            p.setJointMotorControl2(robot.body, index, p.TORQUE_CONTROL,
                                    force=max(-effort, min(effort, force)))


class Magnet:
    """A gripper without finger joints: on, it holds what it touches; off, it lets go."""

    def __init__(self, robot, objects, dynamic):
        self.robot, self.objects, self.dynamic = robot, objects, dynamic
        self.hold = None

    def command(self, position, time, events):
        if position <= 0.5:
            if self.hold is not None:
                p.removeConstraint(self.hold)
                self.hold = None
            return
        robot = self.robot.body
        touching = [n for n in self.dynamic
                    if p.getClosestPoints(robot, self.objects[n].body, MAGNET_REACH)]
        if not touching:
            nearest = min((c[8] for n in self.dynamic
                           for c in p.getClosestPoints(robot, self.objects[n].body, 1.0)),
                          default=float("inf"))
            events.append(f"{time:.2f} s: the magnet is switched on {nearest * 1000:.1f} mm from "
                          f"the nearest object and holds nothing")
            return
        held = self.objects[touching[0]].body
        # Constraints join centres of mass, which is what pybullet reports for a base.
        gripper = p.invertTransform(*p.getBasePositionAndOrientation(robot))
        relative = p.multiplyTransforms(*gripper, *p.getBasePositionAndOrientation(held))
        self.hold = p.createConstraint(robot, -1, held, -1, p.JOINT_FIXED, [0, 0, 0],
                                       relative[0], [0, 0, 0], relative[1])
        events.append(f"{time:.2f} s: the magnet takes {touching[0]}")

    def step(self):
        pass


class Watch:
    """Follows the dynamic objects against the solution: the first time each leaves its pose,
    and the first time a held object presses on something else."""

    def __init__(self, solution, bodies, objects, dynamic):
        self.world = solution["world"]
        self.times = [t for t, _ in self.world]
        self.bodies, self.objects, self.dynamic = bodies, objects, dynamic
        self.departed, self.pressed = set(), set()

    def check(self, time, events):
        i = max(0, bisect_right(self.times, time) - 1)
        step = self.world[i][1]
        expected = step_poses(step, self.bodies)
        holding = step.robots[0].held[0] if step.robots[0].held else ""
        for name in self.dynamic:
            if name in self.departed:
                continue
            distance, angle = pose_error(expected[name], self.objects[name].pose())
            held = name == holding
            if distance > (SLIP_DISTANCE if held else POSITION_TOLERANCE) or (
                    not held and angle > ANGLE_TOLERANCE):
                self.departed.add(name)
                events.append(f"{time:.2f} s: {name} ({'held' if held else 'not held'}) leaves "
                              f"the solution's pose: {distance * 1000:.1f} mm, "
                              f"{math.degrees(angle):.1f}°")
        if holding:
            for other, body in self.objects.items():
                if other == holding or (holding, other) in self.pressed:
                    continue
                force = sum(c[9] for c in p.getContactPoints(self.objects[holding].body, body.body))
                if force > PRESS_FORCE:
                    self.pressed.add((holding, other))
                    events.append(f"{time:.2f} s: {holding}, held, presses on {other} with "
                                  f"{force:.0f} N")


def execute(solution):
    header = solution["header"]
    coordinates = header[f"robot.{header['robots']}.coordinates"].split()
    lines = [line.split() for line in header["bodies"].split("\n") if line]
    bodies = [name for name, _ in lines]
    types = dict(lines)
    held_types = {types[h] for _, step in solution["world"] for h in step.robots[0].held if h}
    start = step_poses(solution["world"][0][1], bodies)
    final = step_poses(solution["world"][-1][1], bodies)

    with quiet_stdout():
        p.connect(p.DIRECT)
    p.setGravity(0, 0, -9.81)
    p.setTimeStep(1.0 / SIM_HZ)
    p.setPhysicsEngineParameter(numSolverIterations=100)
    robot = Robot(solution, coordinates, dict(zip(coordinates, solution["world"][0][1].robots[0].positions)))
    objects = {}
    for entity in solution["scene"]["entities"]:
        name = entity["id"]
        body = Object.add(entity, start[name], types[name] in held_types)
        if body is not None:
            objects[name] = body
    dynamic = sorted(n for n in objects if types[n] in held_types)
    gripper = Fingers(robot) if robot.fingers else Magnet(robot, objects, dynamic)
    watch = Watch(solution, bodies, objects, dynamic)

    report = {"objects": {}, "events": []}
    end_time = max([solution["world"][-1][0]] + [t for t, _ in solution["gripper"]])
    commands = list(solution["gripper"])
    for k in range(int(math.ceil((end_time + SETTLE_SECONDS) * SIM_HZ)) + 1):
        time = k / SIM_HZ
        while commands and commands[0][0] <= time:
            gripper.command(commands.pop(0)[1], time, report["events"])
        robot.command(time)
        gripper.step()
        p.stepSimulation()
        if k % (SIM_HZ // 10) == 0:
            watch.check(time, report["events"])

    for name in dynamic:
        distance, angle = pose_error(final[name], objects[name].pose())
        report["objects"][name] = {
            "distance_mm": round(distance * 1000, 2), "angle_deg": round(math.degrees(angle), 2),
            "at_rest": distance <= POSITION_TOLERANCE and angle <= ANGLE_TOLERANCE}
    report["executed"] = all(o["at_rest"] for o in report["objects"].values())
    report["seconds"] = round(end_time, 2)
    p.disconnect()
    return report


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("solution")
    parser.add_argument("--json", help="also write the report as JSON")
    args = parser.parse_args()
    try:
        solution = read_solution(args.solution)
    except (OSError, ValueError) as error:
        print(f"error: {args.solution}: {error}", file=sys.stderr)
        return 2
    try:
        report = execute(solution)
    except ValueError as error:
        print(f"error: {args.solution}: {error}", file=sys.stderr)
        return 2
    for event in report["events"]:
        print(event)
    for name, result in report["objects"].items():
        verdict = "at rest" if result["at_rest"] else "NOT where the solution put it"
        print(f"{name}: {result['distance_mm']} mm, {result['angle_deg']}° from its final pose, {verdict}")
    print("executed" if report["executed"] else "not executed", f"({report['seconds']} s)")
    if args.json:
        Path(args.json).write_text(json.dumps(report, indent=2, sort_keys=True) + "\n")
    return 0 if report["executed"] else 1


if __name__ == "__main__":
    sys.exit(main())
