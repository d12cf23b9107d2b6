#!/usr/bin/python3
"""rostest: bad input never crashes tissue_simulator; bad scenes stop it at start-up, naming the key."""
import os
import sys
import threading
import unittest

import rospy
import rostest
from geometry_msgs.msg import PoseStamped
from rosgraph_msgs.msg import Log
from std_srvs.srv import SetBool

from node_probe import run_node, wait_for_subscribers


class BadInputTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node("bad_input_rostest")
        cls.data = rospy.get_param("~data_dir")
        cls.logs = []
        cls.lock = threading.Lock()
        rospy.Subscriber("/rosout_agg", Log, cls.on_log, queue_size=1000)
        rospy.Subscriber("/rosout", Log, cls.on_log, queue_size=1000)
        rospy.wait_for_service("tissue/pause", timeout=60.0)
        cls.pause = rospy.ServiceProxy("tissue/pause", SetBool)
        cls.pub = rospy.Publisher("tool/pose", PoseStamped, queue_size=10)
        wait_for_subscribers(cls.pub)

    @classmethod
    def on_log(cls, msg):
        with cls.lock:
            cls.logs.append(msg.msg)

    def wait_for_log(self, fragment, timeout=10.0):
        deadline = rospy.get_time() + timeout
        while rospy.get_time() < deadline:
            with self.lock:
                if any(fragment in m for m in self.logs):
                    return True
            rospy.sleep(0.1)
        return False

    def assert_alive(self):
        self.assertTrue(self.pause(False).success, "tissue_simulator stopped answering")

    def pose(self, x, y, z, frame="world", qw=1.0):
        msg = PoseStamped()
        msg.header.stamp = rospy.Time.now()
        msg.header.frame_id = frame
        msg.pose.position.x, msg.pose.position.y, msg.pose.position.z = x, y, z
        msg.pose.orientation.w = qw
        return msg

    def test_nan_pose_is_rejected_and_node_survives(self):
        self.pub.publish(self.pose(float("nan"), 0.0, 0.05))
        self.assertTrue(self.wait_for_log("rejected tool pose: NaN/Inf"))
        self.assert_alive()

    def test_absurd_pose_is_rejected(self):
        self.pub.publish(self.pose(1e6, 0.0, 0.0))
        self.assertTrue(self.wait_for_log("farther than"))
        self.pub.publish(self.pose(0.0, 0.0, 0.05, qw=0.0))
        self.assert_alive()

    def test_unknown_frame_is_rejected(self):
        self.pub.publish(self.pose(0.0, 0.0, 0.05, frame="no_such_frame"))
        self.assertTrue(self.wait_for_log("unknown frame 'no_such_frame'"))
        self.assert_alive()

    def test_out_of_range_scene_exits_naming_the_key(self):
        code, out = run_node("tissue_simulator",
                             ["_scene:=" + os.path.join(self.data, "bad_scene_poisson.yaml")])
        self.assertNotEqual(code, 0)
        self.assertIn("material.poisson_ratio", out)

    def test_malformed_yaml_exits_naming_the_line(self):
        code, out = run_node("tissue_simulator",
                             ["_scene:=" + os.path.join(self.data, "bad_scene_syntax.yaml")])
        self.assertNotEqual(code, 0)
        self.assertIn("malformed YAML", out)

    def test_missing_scene_parameter_exits(self):
        code, out = run_node("tissue_simulator", [])
        self.assertNotEqual(code, 0)
        self.assertIn("~scene", out)


if __name__ == "__main__":
    rostest.rosrun("surgical_sim", "bad_input", BadInputTest, sys.argv)
