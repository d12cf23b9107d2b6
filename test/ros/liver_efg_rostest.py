#!/usr/bin/python3
"""rostest: the palpation checks (palpation_rostest.PalpationTest) on the EFG liver, with the bag's
press moved to the liver's top: the tool goes as deep below the liver's top as the bag goes below
the palpation organ's (top z = 24 mm)."""
import copy
import sys
import threading

import rospy
import rostest
from visualization_msgs.msg import Marker

from node_probe import wait_for_connection
from palpation_rostest import PalpationTest

BAG_ORGAN_TOP = 0.024  # [m] top of the palpation organ under the bag's press
AXIS_RADIUS = 0.005  # [m] surface points this close to the press axis give the top


class LiverEfgTest(PalpationTest):
    @classmethod
    def setUpClass(cls):
        super().setUpClass()
        # One step with the tool far above publishes the surface (replays start with a reset).
        # The subscription is connected first: the step publishes it at once, and a message
        # published before the connection exists is lost.
        surfaces = []
        arrived = threading.Event()

        def keep(msg):
            surfaces.append(msg)
            arrived.set()

        subscriber = rospy.Subscriber("tissue/surface", Marker, keep, queue_size=1)
        wait_for_connection("/tissue_simulator", "/tissue/surface", rospy.get_name())
        clear = copy.deepcopy(cls.poses[0])
        clear.pose.position.z = 1.0
        clear.header.stamp += rospy.Duration(2000.0)  # a stamp no replay uses
        cls.collector.send(clear)
        if not arrived.wait(60.0):
            raise AssertionError("no tissue/surface within 60 s of the step with the tool above")
        subscriber.unregister()
        surface = surfaces[-1]
        x0 = cls.poses[0].pose.position.x
        y0 = cls.poses[0].pose.position.y
        top = max(p.z for p in surface.points
                  if (p.x - x0) ** 2 + (p.y - y0) ** 2 <= AXIS_RADIUS ** 2)
        rospy.loginfo("liver top under the press: %.4f m", top)
        for pose in cls.poses:
            pose.pose.position.z += top - BAG_ORGAN_TOP


if __name__ == "__main__":
    rostest.rosrun("surgical_sim", "liver_efg", LiverEfgTest, sys.argv)
