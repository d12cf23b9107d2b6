#!/usr/bin/python3
"""rostest: bad input never crashes tissue_simulator; bad scenes stop it at start-up, naming the key."""
import os
import sys
import tempfile
import threading
import unittest

import rospy
import rostest
from geometry_msgs.msg import PoseStamped
from rosgraph_msgs.msg import Log
from std_srvs.srv import SetBool

from node_probe import pose_stamped, run_node, wait_for_subscribers


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
        return pose_stamped(x, y, z, frame, qw)

    def test_nan_pose_is_rejected_and_node_survives(self):
        self.pub.publish(self.pose(float("nan"), 0.0, 0.05))
        self.assertTrue(self.wait_for_log("rejected tool pose: NaN/Inf position"))
        self.assert_alive()

    def test_absurd_pose_and_zero_quaternion_get_their_own_warnings(self):
        self.pub.publish(self.pose(1e6, 0.0, 0.0))
        self.assertTrue(self.wait_for_log("rejected tool pose: farther than 5 m"))
        self.pub.publish(self.pose(0.0, 0.0, 0.05, qw=0.0))
        self.assertTrue(self.wait_for_log("rejected tool pose: zero or non-finite quaternion"))
        self.assert_alive()

    def test_unknown_frame_is_rejected(self):
        self.pub.publish(self.pose(0.0, 0.0, 0.05, frame="no_such_frame"))
        self.assertTrue(self.wait_for_log("rejected tool pose in unknown frame 'no_such_frame'"))
        self.assert_alive()

    def test_bad_parameters_exit_naming_the_parameter(self):
        scene = "_scene:=" + rospy.get_param("~scene")
        for args, message in ((["_realtime:=1"], "~realtime must be true or false"),
                              (["_steps_per_pose:=2.5"], "~steps_per_pose must be an integer"),
                              (["_steps_per_pose:=0"], "~steps_per_pose = 0 is out of range"),
                              (["_surface_rate:=0"], "~surface_rate = 0 Hz is out of range"),
                              (["_max_tool_distance:=far"], "~max_tool_distance must be a number"),
                              (["_force_arrow_scale:=0"],
                               "~force_arrow_scale = 0 m/N is out of range"),
                              (["_tissue_frame:=7"], "~tissue_frame must be a non-empty string")):
            code, out = run_node("tissue_simulator", [scene] + args)
            self.assertNotEqual(code, 0, "%s accepted" % args)
            self.assertIn(message, out)

    def test_tool_with_an_empty_pose_topic_exits_naming_it(self):
        with open(rospy.get_param("~scene")) as f:
            text = f.read()
        self.assertIn("pose_topic: tool/pose", text)
        with tempfile.NamedTemporaryFile("w", suffix=".yaml") as scene:
            scene.write(text.replace("pose_topic: tool/pose", 'pose_topic: ""'))
            scene.flush()
            code, out = run_node("tissue_simulator", ["_scene:=" + scene.name])
        self.assertNotEqual(code, 0)
        self.assertIn("pose_topic", out)

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
