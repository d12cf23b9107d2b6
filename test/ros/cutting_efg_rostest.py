#!/usr/bin/python3
"""rostest: the cutting checks (cutting_rostest.CuttingTest) on the EFG organ, and the cut's lips
separating in the rendered surface."""
import math
import sys
import threading

import rospy
import rostest
from visualization_msgs.msg import Marker

from cutting_rostest import CuttingTest

CUT_RED = (0.55, 0.08)  # r, g of the cut faces in tissue/surface


def cut_face_gap(marker):
    """(gap [m], cut triangles, all points finite): mean x of the sheet facing -x (the piece at
    larger x) minus mean x of the sheet facing +x; positive when the lips have separated."""
    sums = {1: [0.0, 0], -1: [0.0, 0]}
    finite = all(math.isfinite(c) for p in marker.points for c in (p.x, p.y, p.z))
    for t in range(len(marker.points) // 3):
        col = marker.colors[3 * t]
        if abs(col.r - CUT_RED[0]) > 1e-3 or abs(col.g - CUT_RED[1]) > 1e-3:
            continue
        a, b, c = marker.points[3 * t:3 * t + 3]
        nx = (b.y - a.y) * (c.z - a.z) - (b.z - a.z) * (c.y - a.y)
        side = 1 if nx > 0.0 else -1
        sums[side][0] += (a.x + b.x + c.x) / 3.0
        sums[side][1] += 1
    if sums[1][1] == 0 or sums[-1][1] == 0:
        return 0.0, sums[1][1] + sums[-1][1], finite
    return sums[-1][0] / sums[-1][1] - sums[1][0] / sums[1][1], sums[1][1] + sums[-1][1], finite


class CuttingEfgTest(CuttingTest):
    @classmethod
    def setUpClass(cls):
        super().setUpClass()
        cls.surface_lock = threading.Lock()
        cls.surface = None
        rospy.Subscriber("tissue/surface", Marker, cls.on_surface, queue_size=10)

    @classmethod
    def on_surface(cls, msg):
        with cls.surface_lock:
            cls.surface = msg

    def test_4_lips_of_a_through_cut_separate(self):
        self.reset()
        stats = self.replayer.replay(self.messages, 0.0)
        self.assertEqual(stats.pieces, 2)
        rospy.sleep(0.5)  # the last surface marker
        with self.surface_lock:
            gap, triangles, finite = cut_face_gap(self.surface)
        rospy.loginfo("cut faces: %d triangles, lips %.3f mm apart", triangles, 1e3 * gap)
        self.assertTrue(finite, "tissue/surface has a non-finite point")
        self.assertGreater(triangles, 20, "too few cut faces in tissue/surface")
        self.assertGreater(gap, 1e-4, "the lips did not separate: gap %.6f m" % gap)


if __name__ == "__main__":
    rostest.rosrun("surgical_sim", "cutting_efg", CuttingEfgTest, sys.argv)
