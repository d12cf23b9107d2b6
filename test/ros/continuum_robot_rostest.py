#!/usr/bin/python3
"""rostest: continuum_robot_controller services and topics (behaviour, no timing assertions)."""
import math
import sys
import threading
import unittest
import xml.etree.ElementTree as ET

import rospy
import rostest
from geometry_msgs.msg import Point, PointStamped, PoseArray
from std_srvs.srv import Trigger
from surgical_sim.msg import Actuation
from surgical_sim.srv import FollowPath, SetTarget
from tf2_msgs.msg import TFMessage

TIP_REST = (0.4, 0.0, 0.0)  # trunk tip at rest in robot_base [m]
ACTUATORS = 6


def stamped(x, y, z, frame="robot_base"):
    p = PointStamped()
    p.header.frame_id = frame
    p.point = Point(x, y, z)
    return p


class ContinuumRobotTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node("continuum_robot_rostest")
        for name in ("continuum_robot/set_target", "continuum_robot/follow_path",
                     "continuum_robot/reset"):
            rospy.wait_for_service(name, timeout=300.0)  # first run condenses the sections
        cls.set_target = rospy.ServiceProxy("continuum_robot/set_target", SetTarget)
        cls.follow_path = rospy.ServiceProxy("continuum_robot/follow_path", FollowPath)
        cls.reset = rospy.ServiceProxy("continuum_robot/reset", Trigger)
        cls.lock = threading.Lock()
        cls.actuations = []
        cls.shape = None
        rospy.Subscriber("continuum_robot/actuation", Actuation, cls.on_actuation, queue_size=1000)
        rospy.Subscriber("continuum_robot/shape", PoseArray, cls.on_shape, queue_size=10)
        cls.tf_children = set()
        for topic in ("/tf", "/tf_static"):
            rospy.Subscriber(topic, TFMessage, cls.on_tf, queue_size=1000)

    @classmethod
    def on_tf(cls, msg):
        with cls.lock:
            cls.tf_children.update(t.child_frame_id for t in msg.transforms)

    @classmethod
    def on_actuation(cls, msg):
        with cls.lock:
            cls.actuations.append(msg)

    @classmethod
    def on_shape(cls, msg):
        with cls.lock:
            cls.shape = msg

    def setUp(self):
        self.assertTrue(self.reset().success)

    def test_reachable_target_converges_and_shape_follows(self):
        # Pressurized chambers extend and bend the trunk: 10 mm beyond the rest tip, 20 mm aside.
        target = (TIP_REST[0] + 0.01, 0.02, 0.0)
        res = self.set_target(stamped(*target), 1e-4, 50)
        self.assertEqual(res.status, "converged", res.message)
        self.assertLess(res.effector_error, 1e-4)
        self.assertEqual(len(res.actuation), ACTUATORS)
        self.assertTrue(all(0.0 <= a <= 300e3 for a in res.actuation), res.actuation)
        rospy.sleep(0.5)
        with self.lock:
            tip = self.shape.poses[-1].position
            self.assertEqual(self.shape.header.frame_id, "robot_base")
            self.assertEqual(len(self.shape.poses), 17)
        self.assertLess(math.dist((tip.x, tip.y, tip.z), target), 2e-4)

    def test_robot_description_links_are_the_published_frames(self):
        """The generated URDF (make_urdf --robot trunk) has one link per frame on tf: world (the
        root), robot_base (robot_state_publisher), vertebra_1..16 and robot_tip (controller)."""
        links = {link.get("name")
                 for link in ET.fromstring(rospy.get_param("/robot_description")).iter("link")}
        self.assertEqual(len(links), 19)
        self.assertTrue(self.reset().success)  # publishes the shape and its tf
        deadline = rospy.get_time() + 10.0
        while rospy.get_time() < deadline:
            with self.lock:
                if links - {"world"} <= self.tf_children:
                    break
            rospy.sleep(0.1)
        with self.lock:
            self.assertEqual(links - {"world"}, self.tf_children)

    def test_target_in_world_frame_is_resolved_with_tf(self):
        # URDF mount: world -> robot_base is the identity.
        res = self.set_target(stamped(TIP_REST[0] + 0.01, 0.0, 0.02, "world"), 1e-4, 50)
        self.assertEqual(res.status, "converged", res.message)

    def test_unreachable_target_returns_closest_feasible_actuation(self):
        # 30 mm shorter than at rest: pressure can only extend the trunk.
        res = self.set_target(stamped(TIP_REST[0] - 0.03, 0.0, 0.0), 1e-4, 50)
        self.assertEqual(res.status, "unreachable", res.message)
        self.assertEqual(len(res.actuation), ACTUATORS)
        self.assertTrue(all(0.0 <= a <= 300e3 for a in res.actuation), res.actuation)
        self.assertGreater(res.effector_error, 1e-3)
        self.node_is_alive()

    def test_nan_target_unknown_frame_and_bad_tolerance_give_clear_status(self):
        res = self.set_target(stamped(float("nan"), 0.0, 0.0), 1e-4, 50)
        self.assertEqual(res.status, "invalid_target")
        self.assertIn("NaN", res.message)
        res = self.set_target(stamped(0.41, 0.0, 0.0, "no_such_frame"), 1e-4, 50)
        self.assertEqual(res.status, "unknown_frame")
        self.assertIn("no_such_frame", res.message)
        res = self.set_target(stamped(0.41, 0.0, 0.0), -1.0, 50)
        self.assertEqual(res.status, "invalid_request")
        self.node_is_alive()

    def test_follow_path_publishes_actuation_at_the_control_rate(self):
        rate = rospy.get_param("~rate")
        c = (TIP_REST[0] + 0.01, 0.0, 0.0)
        points = [Point(c[0], c[1] + 0.02 * math.cos(a), c[2] + 0.02 * math.sin(a))
                  for a in (2.0 * math.pi * i / 24 for i in range(25))]
        with self.lock:
            del self.actuations[:]
        res = self.follow_path(points, "robot_base", 0.05)
        self.assertTrue(res.accepted, res.message)
        expected = 2.0 * math.pi * 0.02 / 0.05 * rate  # arc length / speed * rate (chords: less)
        self.assertGreater(res.steps, 0.9 * expected)
        self.assertLess(res.steps, 1.1 * expected + 2)
        rospy.sleep(res.duration + 2.0)
        with self.lock:
            received = list(self.actuations)
        # One message per control step: generous bounds, no timing assertion.
        self.assertGreater(len(received), 0.7 * res.steps)
        self.assertLess(len(received), 1.3 * res.steps + 2)
        self.assertEqual(list(received[-1].names),
                         ["lower_a", "lower_b", "lower_c", "upper_a", "upper_b", "upper_c"])
        self.assertEqual(list(received[-1].units), ["Pa"] * ACTUATORS)
        self.assertLess(received[-1].effector_error, 2e-3)
        res = self.follow_path([], "robot_base", 0.05)
        self.assertFalse(res.accepted)

    def node_is_alive(self):
        res = self.set_target(stamped(*TIP_REST), 1e-4, 50)
        self.assertEqual(res.status, "converged", res.message)


if __name__ == "__main__":
    rostest.rosrun("surgical_sim", "continuum_robot", ContinuumRobotTest, sys.argv)
