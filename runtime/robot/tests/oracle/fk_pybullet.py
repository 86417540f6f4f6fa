"""Forward kinematics oracle: world poses of every link of a URDF, computed by pybullet.

Usage: python3 fk_pybullet.py ROBOT.urdf CONFIGURATIONS.json
CONFIGURATIONS.json is a list of {joint name: value}. For each configuration, prints one line per
link: "POSE <index> <link> x y z qx qy qz qw" (the URDF link frame, base fixed at the origin).
pybullet writes its own chatter to stdout too, so only lines starting with POSE are meaningful.
"""
import json
import sys

import pybullet as p

p.connect(p.DIRECT)
body = p.loadURDF(sys.argv[1], useFixedBase=True)
configurations = json.load(open(sys.argv[2]))
joints = {p.getJointInfo(body, i)[1].decode(): i for i in range(p.getNumJoints(body))}
base_name = p.getBodyInfo(body)[0].decode()
for index, configuration in enumerate(configurations):
    for name, value in configuration.items():
        p.resetJointState(body, joints[name], value)
    position, orientation = p.getBasePositionAndOrientation(body)
    print("POSE", index, base_name, *position, *orientation, flush=True)
    for link in range(p.getNumJoints(body)):
        state = p.getLinkState(body, link, computeForwardKinematics=True)
        name = p.getJointInfo(body, link)[12].decode()
        print("POSE", index, name, *state[4], *state[5], flush=True)
