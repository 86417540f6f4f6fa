"""Record simulated cube-stacking demonstrations as plain ROS 2 bags.

    python3 domains/cubes/record.py --count 100 --seed 1 --out domains/cubes/build/bags

A YuMi-like arm (the left arm of domains/robots/yumi.urdf) picks one of one to three cubes lying
on a table and sets it down on the table or on top of another cube, scripted with pybullet's
kinematics (its forward kinematics and Jacobians drive a damped least-squares IK:
calculateInverseKinematics misses this arm's top-down poses by centimetres). Each demonstration is
one MCAP file of standard ROS 2 messages only, as a robot's logger would record it at 50 Hz:

- /tf_static: world -> table, world -> yumi_body (the arm's root link, where it is bolted);
- /tf: world -> cube_N for every cube in the scene, as a motion-capture system reports them (off by
  up to 1.5 mm per axis and 1 degree, and now and then missed: the sample then lacks that cube);
- /joint_states: the arm's joints and both finger joints by their URDF names. The fingers close on
  a grasped cube and open again on release; nothing else says what the gripper holds.

Nothing here uses lamp: it is what a user's own simulation script looks like.
"""

import argparse
import contextlib
import math
import os
import sys

import numpy as np
from mcap_ros2.writer import Writer


@contextlib.contextmanager
def quiet():
    """Silences what pybullet prints on the C streams (its URDF importer warns of every link
    without inertia)."""
    sys.stdout.flush()
    sys.stderr.flush()
    saved = [os.dup(1), os.dup(2)]
    null = os.open(os.devnull, os.O_WRONLY)
    os.dup2(null, 1)
    os.dup2(null, 2)
    try:
        yield
    finally:
        os.dup2(saved[0], 1)
        os.dup2(saved[1], 2)
        for fd in saved + [null]:
            os.close(fd)


# pybullet prints its build time on stdout when it loads.
with quiet():
    import pybullet as p  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
URDF = os.path.join(HERE, "..", "robots", "yumi.urdf")

RATE_HZ = 50.0
MOUNT = (-0.46, 0.0, -0.08)
TABLE_AT = (0.17, 0.0, 0.0)  # the table's frame is the centre of its top face
TABLE_SIZE = (1.2, 1.2, 0.05)
CUBE = 0.04  # side length; a cube's frame is the centre of its bottom face
# Where cubes are laid out: where the arm reaches a top grasp at every yaw.
LAYOUT_X = (-0.38, -0.08)
LAYOUT_Y = (-0.20, 0.10)
MIN_SPACING = 0.09  # between cube centres, so open fingers fit between neighbours

ARM_JOINTS = [
    "yumi_joint_1_l", "yumi_joint_2_l", "yumi_joint_7_l", "yumi_joint_3_l",
    "yumi_joint_4_l", "yumi_joint_5_l", "yumi_joint_6_l",
]
FINGER_JOINTS = ["gripper_l_joint", "gripper_l_joint_m"]
HOME = [0.0, math.radians(-130), math.radians(-135), math.radians(30), 0.0, math.radians(40), 0.0]
# Each finger's pad is 2 mm + its joint value from the gripper's centre plane: open, the pads are
# 48 mm apart, 4 mm clear of a 40 mm cube on either side; closed on a cube, 40 mm apart.
FINGER_OPEN = 0.022
FINGER_CLOSED = (CUBE / 2) - 0.002
# A top grasp holds the cube with its bottom face 13.8 cm along the gripper's approach axis: the
# fingertips (13.37 cm) end 4.3 mm above the bottom, so they clear whatever the cube is set on.
GRASP_DEPTH = 0.138
APPROACH = 0.10  # straight descents and lifts
CLEARANCE = 0.001  # a cube is let go of this far above what holds it up

LINEAR_SPEED = 0.10  # m/s, peak of a straight move
JOINT_SPEED = 0.8  # rad/s, peak of a joint move
GRIP_TIME = 0.5  # s for the fingers to close or open

NOISE_POSITION = 0.0015
NOISE_ANGLE = math.radians(1.0)
DROP_CHANCE = 0.03

TF_MSG = """\
geometry_msgs/TransformStamped[] transforms
================================================================================
MSG: geometry_msgs/TransformStamped
std_msgs/Header header
string child_frame_id
Transform transform
================================================================================
MSG: std_msgs/Header
builtin_interfaces/Time stamp
string frame_id
================================================================================
MSG: builtin_interfaces/Time
int32 sec
uint32 nanosec
================================================================================
MSG: geometry_msgs/Transform
Vector3 translation
Quaternion rotation
================================================================================
MSG: geometry_msgs/Vector3
float64 x
float64 y
float64 z
================================================================================
MSG: geometry_msgs/Quaternion
float64 x 0
float64 y 0
float64 z 0
float64 w 1
"""

JOINT_STATE_MSG = """\
std_msgs/Header header
string[] name
float64[] position
float64[] velocity
float64[] effort
================================================================================
MSG: std_msgs/Header
builtin_interfaces/Time stamp
string frame_id
================================================================================
MSG: builtin_interfaces/Time
int32 sec
uint32 nanosec
"""


class Failed(Exception):
    """A layout or motion the arm cannot do; the demonstration is redrawn."""


def yaw_quat(yaw):
    return p.getQuaternionFromEuler((0.0, 0.0, yaw))


def down_quat(yaw):
    """The gripper pointing straight down (approach axis -z), its fingers opening along yaw."""
    return p.getQuaternionFromEuler((math.pi, 0.0, yaw))


def wrap(angle):
    return (angle + math.pi) % (2 * math.pi) - math.pi


def smooth(u):
    """Rest-to-rest time scaling."""
    return u * u * (3.0 - 2.0 * u)


class Scene:
    def __init__(self):
        self.client = p.connect(p.DIRECT)
        with quiet():
            self.robot = p.loadURDF(URDF, basePosition=MOUNT, useFixedBase=True)
        self.joint_index = {}
        self.links = {}
        for j in range(p.getNumJoints(self.robot)):
            info = p.getJointInfo(self.robot, j)
            self.joint_index[info[1].decode()] = j
            self.links[info[12].decode()] = j
        self.arm = [self.joint_index[name] for name in ARM_JOINTS]
        self.fingers = [self.joint_index[name] for name in FINGER_JOINTS]
        self.gripper = self.links["gripper_l_base"]
        self.finger_links = {self.links["gripper_l_finger_r"], self.links["gripper_l_finger_l"]}
        movable = self.arm + self.fingers
        self.lower = [p.getJointInfo(self.robot, j)[8] for j in movable]
        self.upper = [p.getJointInfo(self.robot, j)[9] for j in movable]
        half = [s / 2 for s in TABLE_SIZE]
        table_shape = p.createCollisionShape(p.GEOM_BOX, halfExtents=half)
        self.table = p.createMultiBody(
            0, table_shape, basePosition=(TABLE_AT[0], TABLE_AT[1], TABLE_AT[2] - half[2])
        )
        # Link pairs two or more joints apart along the chain (the fingers hang off one link).
        chain = [-1] + self.arm + [self.gripper]
        self.link_pairs = [
            (a, b) for i, a in enumerate(chain) for b in chain[i + 2 :] + self.fingers
            if b not in chain[i : i + 2] and not (a == self.gripper and b in self.fingers)
        ]
        self.cube_shape = p.createCollisionShape(p.GEOM_BOX, halfExtents=[CUBE / 2] * 3)
        self.cubes = []

    def set_cubes(self, poses):
        for body in self.cubes:
            p.removeBody(body)
        self.cubes = [p.createMultiBody(0, self.cube_shape) for _ in poses]
        for body, pose in zip(self.cubes, poses):
            self.place_cube(body, pose)

    def place_cube(self, body, frame):
        """Puts a cube's frame (the centre of its bottom face) at a world pose."""
        position, orientation = frame
        centre, _ = p.multiplyTransforms(position, orientation, (0, 0, CUBE / 2), (0, 0, 0, 1))
        p.resetBasePositionAndOrientation(body, centre, orientation)

    def set_arm(self, arm, fingers):
        for j, value in zip(self.arm, arm):
            p.resetJointState(self.robot, j, value)
        for j in self.fingers:
            p.resetJointState(self.robot, j, fingers)

    def gripper_pose(self):
        state = p.getLinkState(self.robot, self.gripper, computeForwardKinematics=True)
        return state[4], state[5]

    def ik(self, position, orientation, seed):
        """Arm joints putting the gripper at the pose, by damped least squares from a seed (the
        previous sample's solution, so the arm follows a line without jumping between branches)."""
        fingers = p.getJointState(self.robot, self.fingers[0])[0]
        target = np.array(p.getMatrixFromQuaternion(orientation)).reshape(3, 3)
        arm = np.array(seed, dtype=float)
        lower, upper = np.array(self.lower[:7]), np.array(self.upper[:7])
        for _ in range(300):
            self.set_arm(arm, fingers)
            reached, turned = self.gripper_pose()
            current = np.array(p.getMatrixFromQuaternion(turned)).reshape(3, 3)
            linear = np.subtract(position, reached)
            # The turn taking the current orientation to the target, as a rotation vector.
            delta = target @ current.T
            angle = math.acos(max(-1.0, min(1.0, (np.trace(delta) - 1) / 2)))
            axis = np.array(
                [delta[2, 1] - delta[1, 2], delta[0, 2] - delta[2, 0], delta[1, 0] - delta[0, 1]]
            )
            angular = axis * (angle / (2 * math.sin(angle))) if angle > 1e-9 else axis / 2
            if np.linalg.norm(linear) < 1e-5 and angle < 1e-4:
                return list(arm)
            q = list(arm) + [fingers, fingers]
            zeros = [0.0] * len(q)
            jl, ja = p.calculateJacobian(self.robot, self.gripper, (0, 0, 0), q, zeros, zeros)
            jacobian = np.vstack([np.array(jl)[:, :7], np.array(ja)[:, :7]])
            error = np.concatenate([linear, angular])
            step = jacobian.T @ np.linalg.solve(jacobian @ jacobian.T + 1e-4 * np.eye(6), error)
            scale = min(1.0, 0.2 / max(1e-12, np.abs(step).max()))
            arm = np.clip(arm + scale * step, lower, upper)
        raise Failed("no IK solution")

    def reach(self, pose, seed, rng):
        """A configuration at the pose touching nothing: IK from the seed, else from random seeds
        (the arm is redundant, and IK from one seed may fold the wrist into the forearm)."""
        seeds = [seed] + [rng.uniform(self.lower[:7], self.upper[:7]) for _ in range(30)]
        for start in seeds:
            try:
                arm = self.ik(pose[0], pose[1], start)
            except Failed:
                continue
            self.set_arm(arm, p.getJointState(self.robot, self.fingers[0])[0])
            # The cubes are checked along the motion, where the held one is carried.
            if not self.self_collides() and not p.getClosestPoints(self.robot, self.table, 0.0):
                return arm
        raise Failed("no collision-free IK solution")

    def self_collides(self):
        return any(
            p.getClosestPoints(self.robot, self.robot, 0.0, linkIndexA=a, linkIndexB=b)
            for a, b in self.link_pairs
        )

    def collides(self, held):
        """Whether the arm or a cube touches anything it should not: the held cube may touch the
        fingers, and links next to each other in the chain touch where they are joined."""
        bodies = [self.table] + self.cubes
        for body in bodies:
            for point in p.getClosestPoints(self.robot, body, 0.0):
                link = point[3]
                if body == held and (link in self.finger_links or link == self.gripper):
                    continue
                return True
        if self.self_collides():
            return True
        for i, a in enumerate(self.cubes):
            for b in bodies[: 1 + i]:
                if p.getClosestPoints(a, b, -1e-4):
                    return True
        return False


def grasp_yaw(cube_yaw, preferred):
    """The gripper's yaw for a top grasp: a face-aligned one nearest the preferred yaw."""
    options = [cube_yaw + k * math.pi / 2 for k in range(4)]
    return min(options, key=lambda y: abs(wrap(y - preferred)))


def demonstration(scene, rng):
    """One scripted pick and place: the samples [(time ns, arm, fingers, cube frames)] and how many
    of them there are up to the first that shows the cube let go of."""
    count = int(rng.integers(1, 4))
    frames = []
    while len(frames) < count:
        x, y = rng.uniform(*LAYOUT_X), rng.uniform(*LAYOUT_Y)
        if all(math.hypot(x - f[0][0], y - f[0][1]) >= MIN_SPACING for f in frames):
            frames.append(((x, y, CLEARANCE), yaw_quat(rng.uniform(-math.pi, math.pi))))
    scene.set_cubes(frames)
    scene.set_arm(HOME, FINGER_OPEN)
    if scene.collides(None):
        raise Failed("start in collision")

    moved = int(rng.integers(count))
    others = [i for i in range(count) if i != moved]
    onto = int(rng.choice(others)) if others and rng.uniform() < 0.7 else None

    cube_pos, cube_quat = frames[moved]
    cube_yaw = p.getEulerFromQuaternion(cube_quat)[2]
    g_yaw = grasp_yaw(cube_yaw, rng.uniform(-0.5, 0.5))
    grasp = ((cube_pos[0], cube_pos[1], cube_pos[2] + GRASP_DEPTH), down_quat(g_yaw))

    if onto is None:
        while True:
            x, y = rng.uniform(*LAYOUT_X), rng.uniform(*LAYOUT_Y)
            if all(
                math.hypot(x - frames[i][0][0], y - frames[i][0][1]) >= MIN_SPACING for i in others
            ) and math.hypot(x - cube_pos[0], y - cube_pos[1]) >= 0.05:
                break
        place_yaw = g_yaw + rng.uniform(-math.pi / 4, math.pi / 4)
        support_top = 0.0
    else:
        (bx, by, bz), b_quat = frames[onto]
        # A stacked cube is set square on the one below, as a careful demonstrator does: a few
        # millimetres and degrees off.
        x, y = bx + rng.uniform(-0.002, 0.002), by + rng.uniform(-0.002, 0.002)
        b_yaw = p.getEulerFromQuaternion(b_quat)[2] + rng.uniform(-math.radians(2), math.radians(2))
        place_yaw = grasp_yaw(b_yaw + wrap(g_yaw - cube_yaw), g_yaw)
        support_top = bz + CUBE
    place = ((x, y, support_top + CLEARANCE + GRASP_DEPTH), down_quat(place_yaw))

    def above(pose, height):
        return ((pose[0][0], pose[0][1], pose[0][2] + height), pose[1])

    pre_grasp = above(grasp, APPROACH)
    pre_place = above(place, APPROACH)
    current = [list(f) for f in frames]
    samples = []
    state = {"arm": list(HOME), "fingers": FINGER_OPEN, "held": False, "offset": None, "t": 0.0}

    def record(time, arm, fingers):
        scene.set_arm(arm, fingers)
        if state["held"]:
            g_pos, g_quat = scene.gripper_pose()
            offset = state["offset"]
            current[moved] = list(p.multiplyTransforms(g_pos, g_quat, offset[0], offset[1]))
            scene.place_cube(scene.cubes[moved], current[moved])
        # The fingers touch the moved cube from when they close on it until they have let go.
        touching = state["held"] or fingers < FINGER_OPEN
        if scene.collides(scene.cubes[moved] if touching else None):
            raise Failed("collision during the motion")
        cubes = [(tuple(c[0]), tuple(c[1])) for c in current]
        samples.append((round(time * 1e9), list(arm), fingers, cubes))

    def segment(duration, at):
        """Samples a motion at the recording rate: `at(u, arm)` is the configuration a fraction u of
        the way through, from the previous sample's arm. The motion's end starts the next one, so
        the arm never jumps between samples."""
        start = state["t"]
        end = start + duration
        k = len(samples)
        while k / RATE_HZ < end - 1e-9:
            u = smooth((k / RATE_HZ - start) / duration)
            state["arm"], state["fingers"] = at(u, state["arm"])
            record(k / RATE_HZ, state["arm"], state["fingers"])
            k += 1
        state["arm"], state["fingers"] = at(1.0, state["arm"])
        state["t"] = end

    def joint_move(goal):
        start = list(state["arm"])
        delta = max(abs(a - b) for a, b in zip(start, goal))
        fingers = state["fingers"]
        segment(
            max(0.6, 1.5 * delta / JOINT_SPEED),
            lambda u, _arm: ([a + u * (b - a) for a, b in zip(start, goal)], fingers),
        )

    def line(a, b):
        # Each sample's IK starts from the previous sample's solution, so the arm follows the line
        # without jumping between IK branches.
        distance = float(np.linalg.norm(np.subtract(b[0], a[0])))
        fingers = state["fingers"]

        def at(u, arm):
            position = tuple(pa + u * (pb - pa) for pa, pb in zip(a[0], b[0]))
            return scene.ik(position, b[1], arm), fingers

        segment(max(0.4, 1.5 * distance / LINEAR_SPEED), at)

    def fingers_to(goal):
        start = state["fingers"]
        segment(GRIP_TIME, lambda u, arm: (arm, start + u * (goal - start)))

    joint_move(scene.reach(pre_grasp, HOME, rng))
    line(pre_grasp, grasp)
    fingers_to(FINGER_CLOSED)
    scene.set_arm(state["arm"], state["fingers"])
    g_pos, g_quat = scene.gripper_pose()
    inv_pos, inv_quat = p.invertTransform(g_pos, g_quat)
    state["offset"] = p.multiplyTransforms(inv_pos, inv_quat, current[moved][0], current[moved][1])
    state["held"] = True
    line(grasp, pre_grasp)
    joint_move(scene.reach(pre_place, state["arm"], rng))
    line(pre_place, place)
    fingers_to(FINGER_OPEN)
    # Let go of: the cube settles square onto what holds it up. The next sample is the first to
    # show it, and a cut demonstration keeps at most the samples up to that one.
    state["held"] = False
    pos, quat = current[moved]
    yaw = p.getEulerFromQuaternion(quat)[2]
    current[moved] = [(pos[0], pos[1], support_top + CLEARANCE), yaw_quat(yaw)]
    scene.place_cube(scene.cubes[moved], current[moved])
    release = len(samples) + 1
    line(place, pre_place)
    joint_move(list(HOME))
    # The last sample is the first at or after the end of the motion, at rest.
    record(len(samples) / RATE_HZ, state["arm"], state["fingers"])
    return samples, release


def noisy(frame, rng):
    (x, y, z), quat = frame
    dx, dy, dz = rng.uniform(-NOISE_POSITION, NOISE_POSITION, 3)
    while True:
        axis = rng.uniform(-1, 1, 3)
        norm = np.linalg.norm(axis)
        if 1e-6 < norm <= 1:
            break
    angle = rng.uniform(0, NOISE_ANGLE)
    turn = p.getQuaternionFromAxisAngle(list(axis / norm), angle)
    _, turned = p.multiplyTransforms((0, 0, 0), turn, (0, 0, 0), quat)
    return (x + dx, y + dy, z + dz), turned


def stamp(ns):
    return {"sec": ns // 1_000_000_000, "nanosec": ns % 1_000_000_000}


def transform(ns, parent, child, frame):
    (x, y, z), (qx, qy, qz, qw) = frame
    norm = math.sqrt(qx * qx + qy * qy + qz * qz + qw * qw)
    return {
        "header": {"stamp": stamp(ns), "frame_id": parent},
        "child_frame_id": child,
        "transform": {
            "translation": {"x": x, "y": y, "z": z},
            "rotation": {"x": qx / norm, "y": qy / norm, "z": qz / norm, "w": qw / norm},
        },
    }


def write_bag(path, samples, rng):
    with open(path, "wb") as stream:
        writer = Writer(stream)
        tf_schema = writer.register_msgdef("tf2_msgs/msg/TFMessage", TF_MSG)
        js_schema = writer.register_msgdef("sensor_msgs/msg/JointState", JOINT_STATE_MSG)
        first = samples[0][0]
        static = {
            "transforms": [
                transform(first, "world", "table", (TABLE_AT, (0, 0, 0, 1))),
                transform(first, "world", "yumi_body", (MOUNT, (0, 0, 0, 1))),
            ]
        }
        writer.write_message("/tf_static", tf_schema, static, log_time=first, publish_time=first)
        for index, (ns, arm, fingers, cubes) in enumerate(samples):
            transforms = []
            for i, frame in enumerate(cubes):
                measured = noisy(frame, rng)
                # The tracker misses a cube now and then; the sample then has no transform for it.
                if index > 0 and rng.uniform() < DROP_CHANCE:
                    continue
                transforms.append(transform(ns, "world", f"cube_{i + 1}", measured))
            if transforms:
                writer.write_message(
                    "/tf", tf_schema, {"transforms": transforms}, log_time=ns, publish_time=ns
                )
            joints = {
                "header": {"stamp": stamp(ns), "frame_id": ""},
                "name": ARM_JOINTS + FINGER_JOINTS,
                "position": list(arm) + [fingers, fingers],
                "velocity": [],
                "effort": [],
            }
            writer.write_message("/joint_states", js_schema, joints, log_time=ns, publish_time=ns)
        writer.finish()


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--count", type=int, default=100)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--out", required=True)
    parser.add_argument("--cut", type=float, default=0.5, help="share of demonstrations cut short")
    args = parser.parse_args()
    os.makedirs(args.out, exist_ok=True)
    scene = Scene()
    total = 0
    for index in range(args.count):
        # Each demonstration has a stream of its own, so it does not depend on --count.
        rng = np.random.default_rng([args.seed, index])
        cut = rng.uniform() < args.cut
        where = rng.uniform()
        for _attempt in range(50):
            try:
                samples, release = demonstration(scene, rng)
                break
            except Failed:
                continue
        else:
            sys.exit(f"demonstration {index}: no feasible layout in 50 attempts")
        if cut:
            # Cut anywhere from the first sample up to the release, as an interrupted recording.
            samples = samples[: 1 + int(where * release)]
        noise_rng = np.random.default_rng([args.seed, index, 1])
        write_bag(os.path.join(args.out, f"cubes_{index:04d}.mcap"), samples, noise_rng)
        total += len(samples)
    print(f"{args.count} demonstrations, {total} samples at {RATE_HZ:g} Hz, in {args.out}")


if __name__ == "__main__":
    main()
