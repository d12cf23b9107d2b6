#!/usr/bin/python3
"""rostest: bad parameters stop cutting_tool naming the parameter; a blade given as a YAML string
is used; bad set_blade requests, bad poses and frame changes are refused with specific texts."""
import math
import sys
import threading
import unittest

import rospy
import rostest
from geometry_msgs.msg import Point, PoseStamped
from rosgraph_msgs.msg import Log
from std_msgs.msg import Bool
from surgical_sim.msg import BladeSweep
from surgical_sim.srv import SetBlade

from node_probe import pose_stamped as pose
from node_probe import (run_node, sigint_and_wait, start_node, wait_for_messages_received,
                        wait_for_subscribers)


class CuttingBadInputTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node("cutting_bad_input_rostest")
        cls.lock = threading.Condition()
        cls.logs = []
        rospy.Subscriber("/rosout", Log, cls.on_log, queue_size=1000)
        rospy.Subscriber("/rosout_agg", Log, cls.on_log, queue_size=1000)
        rospy.wait_for_service("cutting/set_blade", timeout=60.0)
        cls.set_blade = rospy.ServiceProxy("cutting/set_blade", SetBlade)
        cls.pose_pub = rospy.Publisher("tool/pose", PoseStamped, queue_size=10)
        cls.activate_pub = rospy.Publisher("cutting/activate", Bool, queue_size=10, latch=True)
        wait_for_subscribers(cls.pose_pub, cls.activate_pub)

    @classmethod
    def on_log(cls, msg):
        with cls.lock:
            cls.logs.append(msg.msg)
            cls.lock.notify_all()

    def wait_for_log(self, fragment, timeout=10.0):
        with self.lock:
            return self.lock.wait_for(lambda: any(fragment in m for m in self.logs), timeout)

    def test_bad_parameters_exit_naming_the_parameter(self):
        for args, message in ((["_blade:=oops"], "~blade must be a list of points [m]"),
                              (["_blade:=[[0,0,0],[0,0"], "~blade must be a list of points"),
                              (["_blade:=[[0,0,0],[0,0,0]]"], "~blade has a total length of 0 m"),
                              (["_blade:=[0,0,0,0,0]"], "~blade has 5 numbers"),
                              (["_max_step:=-1"], "~max_step = -1 m is out of range"),
                              (["_max_tool_distance:=far"], "~max_tool_distance must be a number")):
            code, out = run_node("cutting_tool", args)
            self.assertNotEqual(code, 0, "%s accepted" % args)
            self.assertIn(message, out)

    def test_blade_given_as_a_yaml_string_is_used(self):
        # rosrun stores _blade:="[[0,0,0],[0,0,0.02]]" as a string: a 20 mm blade along z.
        ns = "yaml_blade"
        proc = start_node("cutting_tool", ns, ["_blade:=[[0,0,0],[0,0,0.02]]"])
        try:
            rospy.wait_for_service("/%s/cutting/set_blade" % ns, timeout=60.0)
            sweeps = []
            got = threading.Event()

            def on_sweep(msg):
                sweeps.append(msg)
                got.set()

            sub = rospy.Subscriber("/%s/cutting/blade_sweep" % ns, BladeSweep, on_sweep)
            poses = rospy.Publisher("/%s/tool/pose" % ns, PoseStamped, queue_size=10)
            activate = rospy.Publisher("/%s/cutting/activate" % ns, Bool, queue_size=1, latch=True)
            wait_for_subscribers(poses, activate)
            activate.publish(Bool(True))
            # Received (hence queued) before any pose sent afterwards, on the node's one thread.
            wait_for_messages_received("/%s/cutting_tool" % ns, "/%s/cutting/activate" % ns, 1)
            poses.publish(pose(0.0, 0.0, 0.10))
            rospy.sleep(0.1)
            poses.publish(pose(0.0, 0.0, 0.09))
            self.assertTrue(got.wait(10.0), "no blade sweep")
            sub.unregister()
        finally:
            self.assertIsNotNone(sigint_and_wait(proc))
        sweep = sweeps[0]
        self.assertEqual(len(sweep.start), 2)
        a, b = sweep.end
        self.assertAlmostEqual(a.z, 0.09)
        self.assertAlmostEqual(b.z - a.z, 0.02)  # the blade of the string, not the default (x)
        self.assertAlmostEqual(b.x - a.x, 0.0)

    def test_set_blade_rejects_zero_length_and_too_many_points(self):
        res = self.set_blade(points=[Point(0.01, 0, 0)] * 3)
        self.assertFalse(res.success)
        self.assertIn("points has a total length of 0 m", res.message)
        many = [Point(0.02 * i / 1000.0, 0, 0) for i in range(1001)]
        res = self.set_blade(points=many)
        self.assertFalse(res.success)
        self.assertIn("points has 1001 points", res.message)
        self.assertIn("at most 1000", res.message)
        res = self.set_blade(points=[Point(0, 0, 0), Point(0.02, 0, 0)])
        self.assertTrue(res.success, res.message)

    def test_bad_poses_and_a_frame_change_get_their_own_warnings(self):
        self.pose_pub.publish(pose(float("nan"), 0.0, 0.0))
        self.assertTrue(self.wait_for_log("rejected tool pose: NaN/Inf position"))
        self.pose_pub.publish(pose(0.0, 0.0, 0.0, qw=0.0))
        self.assertTrue(self.wait_for_log("rejected tool pose: zero or non-finite quaternion"))
        self.pose_pub.publish(pose(1e3, 0.0, 0.0))
        self.assertTrue(self.wait_for_log("rejected tool pose: farther than 5 m"))
        self.activate_pub.publish(Bool(True))
        # The first activation this node gets: received (hence queued) before the poses below.
        wait_for_messages_received("/cutting_tool", "/cutting/activate", 1)
        self.pose_pub.publish(pose(0.0, 0.0, 0.1, frame="world"))
        rospy.sleep(0.1)
        self.pose_pub.publish(pose(0.0, 0.0, 0.1, frame="elsewhere"))
        self.assertTrue(self.wait_for_log(
            "tool/pose in frame 'elsewhere' while cutting in frame 'world'"))
        self.activate_pub.publish(Bool(False))


if __name__ == "__main__":
    rostest.rosrun("surgical_sim", "cutting_bad_input", CuttingBadInputTest, sys.argv)
