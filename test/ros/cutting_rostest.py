#!/usr/bin/python3
"""rostest: cutting bag -> cutting_tool -> tissue_simulator (lockstep) -> tissue/stats.pieces."""
import copy
import sys
import threading
import unittest

import rosbag
import rospy
import rostest
from geometry_msgs.msg import Point, PoseStamped
from std_msgs.msg import Bool
from std_srvs.srv import Empty
from surgical_sim.msg import BladeSweep, TissueStats
from surgical_sim.srv import SetBlade

from node_probe import (messages_received, subscribe_by_stamp, wait_for_connection,
                        wait_for_messages_received, wait_for_subscribers)


class Replayer:
    """Publishes the bag's messages in time order, one pose at a time, waiting for its stats."""

    def __init__(self):
        self.lock = threading.Condition()
        self.stats = {}
        self.sweeps = 0
        self.pose_pub = rospy.Publisher("tool/pose", PoseStamped, queue_size=1000)
        self.activate_pub = rospy.Publisher("cutting/activate", Bool, queue_size=10, latch=True)
        subscribe_by_stamp("tissue/stats", TissueStats, self.lock, self.stats)
        rospy.Subscriber("cutting/blade_sweep", BladeSweep, self.on_sweep, queue_size=1000)
        wait_for_subscribers((self.pose_pub, 2), self.activate_pub)

    def on_sweep(self, _):
        with self.lock:
            self.sweeps += 1
            self.lock.notify_all()

    def replay(self, messages, dz, settle_poses=3):
        """Replays (topic, msg) with every pose raised by dz [m]; returns the last stats.
        While the blade is active, waits for the sweep of each pose before the next pose, so
        every sweep is applied at the step of the next pose (tissue_simulator has received it
        before that pose is sent: a deterministic replay, also on a loaded machine). The replay
        ends by holding the last pose for settle_poses more steps, so the returned stats
        include the last sweep."""
        with self.lock:
            self.stats.clear()
            self.sweeps = 0
        last = None
        active, poses_while_active, expected = False, 0, 0
        received = messages_received("/tissue_simulator", "/cutting/blade_sweep")
        for topic, msg in messages:
            if topic == "cutting/activate":
                self.activate_pub.publish(msg)
                active, poses_while_active = msg.data, 0
                rospy.sleep(0.3)  # let cutting_tool see it before the next pose
                continue
            pose = PoseStamped()
            pose.header = msg.header
            pose.pose = msg.pose
            pose.pose.position.z = msg.pose.position.z + dz
            key = pose.header.stamp.to_nsec()
            self.pose_pub.publish(pose)
            with self.lock:
                ok = self.lock.wait_for(lambda: key in self.stats, timeout=20.0)
                if not ok:
                    raise AssertionError("no tissue/stats for pose stamped %s" % pose.header.stamp)
                last = self.stats[key]
                if active:
                    poses_while_active += 1
                    expected += 1 if poses_while_active > 1 else 0
                    if not self.lock.wait_for(lambda: self.sweeps >= expected, timeout=10.0):
                        raise AssertionError("no cutting/blade_sweep for pose stamped %s" %
                                             pose.header.stamp)
            # The sweep also reaches tissue_simulator before the next pose.
            wait_for_messages_received("/tissue_simulator", "/cutting/blade_sweep",
                                       received + expected)
            pose.pose.position.z -= dz
        if last is None:
            return None
        held = PoseStamped()
        held.header = copy.deepcopy(pose.header)
        held.pose = copy.deepcopy(pose.pose)
        held.pose.position.z += dz
        for k in range(settle_poses):
            held.header.stamp += rospy.Duration(0.01)
            key = held.header.stamp.to_nsec()
            self.pose_pub.publish(held)
            with self.lock:
                if not self.lock.wait_for(lambda: key in self.stats, timeout=20.0):
                    raise AssertionError("no tissue/stats for the held pose %d" % k)
                last = self.stats[key]
        return last


class CuttingTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node("cutting_rostest")
        with rosbag.Bag(rospy.get_param("~bag")) as bag:
            cls.messages = [(topic, msg) for topic, msg, _ in bag.read_messages(
                topics=["tool/pose", "cutting/activate"])]
        rospy.wait_for_service("tissue/reset", timeout=60.0)
        rospy.wait_for_service("cutting/set_blade", timeout=60.0)
        cls.reset = rospy.ServiceProxy("tissue/reset", Empty)
        cls.set_blade = rospy.ServiceProxy("cutting/set_blade", SetBlade)
        wait_for_connection("/cutting_tool", "/cutting/blade_sweep", "/tissue_simulator")
        cls.replayer = Replayer()

    def test_1_bag_cuts_the_organ_through(self):
        self.reset()
        stats = self.replayer.replay(self.messages, 0.0)
        self.assertGreater(self.replayer.sweeps, 50)
        self.assertEqual(stats.pieces, 2)
        self.assertIn("cutting", stats.components)
        self.assertIn(stats.status, ("ok", "not_converged"))

    def test_2_shallow_replay_leaves_one_piece(self):
        self.reset()
        stats = self.replayer.replay(self.messages, 0.035)  # blade tip 1 mm below the mid-plane
        self.assertGreater(self.replayer.sweeps, 50)
        self.assertEqual(stats.pieces, 1)
        self.assertIn("cutting", stats.components)

    def test_3_set_blade_rejects_a_single_point(self):
        res = self.set_blade(points=[Point(0, 0, 0)])
        self.assertFalse(res.success)
        self.assertIn("points has 1 points; a blade polyline needs at least 2", res.message)
        res = self.set_blade(points=[Point(0, 0, 0), Point(0, 0, -0.07)])
        self.assertTrue(res.success, res.message)


if __name__ == "__main__":
    rostest.rosrun("surgical_sim", "cutting", CuttingTest, sys.argv)
