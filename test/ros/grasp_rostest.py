#!/usr/bin/python3
"""rostest: press, close the jaws (tool/grasp or the trocar_grip joint), pull up, open."""
import sys
import unittest

import rospy
import rostest
from geometry_msgs.msg import PoseStamped
from sensor_msgs.msg import JointState
from std_msgs.msg import Bool
from std_srvs.srv import Empty

from node_probe import wait_for_subscribers
from palpation_rostest import Collector

TOP_Z = 0.024  # organ top under the tool in `world` [m] (as in scripts/make_bags)


def pose(stamp, z):
    msg = PoseStamped()
    msg.header.stamp = stamp
    msg.header.frame_id = "world"
    msg.pose.position.z = z
    msg.pose.orientation.x = 1.0  # tool z axis pointing down
    return msg


class GraspTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node("grasp_rostest")
        rospy.wait_for_service("tissue/reset", timeout=60.0)
        cls.reset = rospy.ServiceProxy("tissue/reset", Empty)
        cls.grasp_pub = rospy.Publisher("tool/grasp", Bool, queue_size=10)
        cls.joint_pub = rospy.Publisher("joint_states", JointState, queue_size=10)
        cls.collector = Collector()
        wait_for_subscribers(cls.grasp_pub, cls.joint_pub)

    def set_jaws(self, how, closed):
        if how == "bool":
            self.grasp_pub.publish(Bool(data=closed))
        else:
            joints = JointState(name=["trocar_insertion", "trocar_grip"],
                                position=[0.1, 0.0 if closed else 0.5])
            self.joint_pub.publish(joints)
        rospy.sleep(0.3)  # delivered before the next pose (separate topics)

    def move(self, start, z0, z1, steps):
        """Moves the tip from z0 to z1 in `steps` lockstep poses; returns the last force."""
        force = None
        for k in range(1, steps + 1):
            force, _ = self.collector.send(pose(start + rospy.Duration(0.01 * k),
                                                z0 + (z1 - z0) * k / steps))
        return force

    def pull(self, how, closed, stamp_base):
        """Press 4 mm, set the jaws, pull 15 mm up; returns (force after the pull, after opening
        and holding)."""
        self.reset()
        self.collector.clear()
        self.set_jaws(how, False)
        t = rospy.Time(stamp_base)
        self.move(t, TOP_Z + 0.01, TOP_Z - 0.004, 40)
        self.set_jaws(how, closed)
        pulled = self.move(t + rospy.Duration(1.0), TOP_Z - 0.004, TOP_Z + 0.011, 60)
        self.set_jaws(how, False)
        released = self.move(t + rospy.Duration(2.0), TOP_Z + 0.011, TOP_Z + 0.011, 60)
        return pulled, released

    def check(self, how, base):
        open_pulled, _ = self.pull(how, False, base)
        self.assertLess(abs(open_pulled.z), 1e-6, "open jaws above the surface must not pull")
        pulled, released = self.pull(how, True, base + 100)
        # The grasped tissue, stretched 11 mm above its top, pulls the tool down.
        self.assertLess(pulled.z, -0.05, "%s: grasped pull gives f_z = %.4f N" % (how, pulled.z))
        self.assertLess(abs(released.z), 1e-6, "%s: force %.4f N after opening" % (how, released.z))

    def test_tool_grasp_bool(self):
        self.check("bool", 10)

    def test_trocar_grip_joint(self):
        self.check("joint", 1000)


if __name__ == "__main__":
    rostest.rosrun("surgical_sim", "grasp", GraspTest, sys.argv)
