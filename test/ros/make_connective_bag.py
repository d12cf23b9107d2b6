#!/usr/bin/python3
"""Deterministically writes test/data/connective_grasp_pull.bag (the generator is the source of
truth; the bag is committed) for config/scenes/connective_two_organs.yaml: tool-tip poses
(tool/pose, frame `world` = the scene frame, tool z axis along +x, into the near organ's far face
x = 0 at its centre (y, z) = (2, 2) cm) and the jaws (tool/grasp), one pose per 0.01 s (the
scene's dt), stamps from t = 1 s:
  10 poses with the tip 0.5 mm in front of the face (no contact), close the jaws,
  40 poses pulling it 10 mm away along -x (ramped over 20), open the jaws,
  20 poses taking the tool 30 mm further away, then 40 poses holding it there.
Usage: test/ros/make_connective_bag.py [OUTPUT]"""
import math
import os
import sys

import rosbag
import rospy
from geometry_msgs.msg import PoseStamped
from std_msgs.msg import Bool

RADIUS = 0.003        # tool capsule radius of the scene [m]
FACE = (0.0, 0.02, 0.02)
START_X = FACE[0] - RADIUS - 0.0005
PULL = 0.010          # [m] along -x
AWAY = 0.030          # [m] further along -x after release
DT = 0.01             # [s]
T0 = 1.0              # [s]


def pose(stamp, x):
    msg = PoseStamped()
    msg.header.stamp = stamp
    msg.header.frame_id = "world"
    msg.pose.position.x, msg.pose.position.y, msg.pose.position.z = x, FACE[1], FACE[2]
    # Rotation by +90 degrees about y: the tool z axis along +x.
    msg.pose.orientation.y = math.sin(math.pi / 4)
    msg.pose.orientation.w = math.cos(math.pi / 4)
    return msg


def path():
    """(x, jaws-before-this-pose or None) per pose."""
    out = [(START_X, None)] * 10
    out += [(START_X - PULL * min(1.0, (k + 1) / 20.0), True if k == 0 else None)
            for k in range(40)]
    out += [(START_X - PULL - AWAY * (k + 1) / 20.0, False if k == 0 else None)
            for k in range(20)]
    out += [(START_X - PULL - AWAY, None)] * 40
    return out


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    output = sys.argv[1] if len(sys.argv) > 1 else os.path.join(
        here, "..", "data", "connective_grasp_pull.bag")
    with rosbag.Bag(output, "w") as bag:
        for k, (x, jaws) in enumerate(path()):
            stamp = rospy.Time.from_sec(T0 + DT * k)
            if jaws is not None:
                bag.write("tool/grasp", Bool(data=jaws), stamp - rospy.Duration(DT / 2))
            bag.write("tool/pose", pose(stamp, x), stamp)
    print("wrote %s" % output)


if __name__ == "__main__":
    main()
