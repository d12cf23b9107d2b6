#!/usr/bin/python3
"""rostest: grasp-and-pull bag -> tissue_simulator (lockstep, multi-body scene (b)) ->
tissue/wrench, tissue/surface (each organ in its colour)."""
import sys
import threading
import unittest

import rosbag
import rospy
import rostest
from std_msgs.msg import Bool
from std_srvs.srv import Empty
from visualization_msgs.msg import Marker

from node_probe import subscribe_by_stamp, wait_for_subscribers
from palpation_rostest import Collector

FAR_COLOUR = (0.6, 0.35, 0.3)  # bodies[1].colour of config/scenes/connective_two_organs.yaml
PULL_POSES = 50                # poses up to the end of the pull (make_connective_bag.py)
HOLD_POSES = 40                # poses held far away at the end


def read_bag(path):
    with rosbag.Bag(path) as bag:
        return [(topic, msg) for topic, msg, _ in bag.read_messages()]


class ConnectiveTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node("connective_rostest")
        cls.messages = read_bag(rospy.get_param("~bag"))
        rospy.wait_for_service("tissue/reset", timeout=60.0)
        cls.reset = rospy.ServiceProxy("tissue/reset", Empty)
        cls.grasp_pub = rospy.Publisher("tool/grasp", Bool, queue_size=10)
        cls.lock = threading.Condition()
        cls.surfaces = {}
        subscribe_by_stamp("tissue/surface", Marker, cls.lock, cls.surfaces,
                           lambda m: (list(m.points), list(m.colors)))
        cls.collector = Collector()
        wait_for_subscribers(cls.grasp_pub)

    def surface(self, stamp):
        key = stamp.to_nsec()
        with self.lock:
            ok = self.lock.wait_for(lambda: key in self.surfaces, timeout=10.0)
        self.assertTrue(ok, "no tissue/surface stamped %s" % stamp)
        return self.surfaces[key]

    def replay(self):
        """Runs the bag from the rest state; returns (forces, pose stamps)."""
        self.reset()
        self.collector.clear()
        with self.lock:
            self.surfaces.clear()
        forces, stamps = [], []
        for topic, msg in self.messages:
            if topic == "tool/grasp":
                self.grasp_pub.publish(msg)
                rospy.sleep(0.3)  # delivered before the next pose (separate topics)
                continue
            force, _ = self.collector.send(msg)
            forces.append((force.x, force.y, force.z))
            stamps.append(msg.header.stamp)
        return forces, stamps

    def test_grasp_pull_drags_the_far_organ_and_replays_bit_identically(self):
        forces, stamps = self.replay()
        rest_points, colours = self.surface(stamps[0])
        pulled_points, _ = self.surface(stamps[PULL_POSES - 1])
        far = [i for i, c in enumerate(colours)
               if max(abs(c.r - FAR_COLOUR[0]), abs(c.g - FAR_COLOUR[1]),
                      abs(c.b - FAR_COLOUR[2])) < 1e-3]
        self.assertGreater(len(far), 100, "far organ's triangles not found by colour")
        moved = max(abs(pulled_points[i].x - rest_points[i].x) for i in far)
        rospy.loginfo("far organ moved %.3f mm; pull force %.3f N", 1e3 * moved,
                      forces[PULL_POSES - 1][0])
        self.assertGreater(moved, 1e-3, "far organ moved %.2e m" % moved)
        # The grasped tissue pulls the tool back towards the organs (+x).
        self.assertGreater(forces[PULL_POSES - 1][0], 0.1)
        for f in forces[-HOLD_POSES:]:
            self.assertEqual(f, (0.0, 0.0, 0.0), "tool force after the release")
        final_points, _ = self.surface(stamps[-1])

        again, _ = self.replay()
        self.assertEqual(again, forces, "replay after tissue/reset differs")
        replayed_points, _ = self.surface(stamps[-1])
        self.assertEqual([(p.x, p.y, p.z) for p in replayed_points],
                         [(p.x, p.y, p.z) for p in final_points])


if __name__ == "__main__":
    rostest.rosrun("surgical_sim", "connective", ConnectiveTest, sys.argv)
