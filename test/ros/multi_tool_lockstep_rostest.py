#!/usr/bin/python3
"""rostest: two tools in lockstep (test/data/two_tools_scene.yaml, steps_per_pose 2). One step
burst per synchronized pose set whatever the order the tools' poses arrive in; each tool its own
contact model; bit-identical replays through scripts/lockstep_play and through a publisher that
changes the order inside each set."""
import os
import sys
import tempfile
import threading
import unittest

import rosbag
import rospy
import rostest
from geometry_msgs.msg import PoseStamped, WrenchStamped
from rosgraph_msgs.msg import Log
from std_srvs.srv import Empty, SetBool
from surgical_sim.msg import ContactModel, TissueStats

from node_probe import run_node, wait_for_subscribers

TOOLS = ("left", "right")
# Tool tip (x, y) [m] and the organ's top height there at rest [m] (palpation organ).
SPOT = {"left": (-0.02, 0.0, 0.0243), "right": (0.025, 0.0, 0.0206)}
SETS = 60
HALF = SETS // 2
BASE = 1.0   # stamp of the first set [s]
DT = 0.01    # [s] between sets
ABOVE, DEPTH = 0.01, 0.006  # [m] start above the surface, press depth


def pose(tool, stamp, depth):
    """Tip of `tool` `depth` [m] below the organ top at its spot, tool z axis pointing down."""
    x, y, top = SPOT[tool]
    msg = PoseStamped()
    msg.header.stamp = stamp
    msg.header.frame_id = "world"
    msg.pose.position.x, msg.pose.position.y, msg.pose.position.z = x, y, top - depth
    msg.pose.orientation.x, msg.pose.orientation.w = 1.0, 0.0
    return msg


def motion():
    """SETS sets of (stamp, {tool: pose}): `left` presses during the first half, `right` stays
    above, then presses during the second half while `left` holds."""
    sets = []
    for k in range(SETS):
        stamp = rospy.Time.from_sec(BASE + DT * k)
        s_left = min(1.0, (k + 1) / HALF)
        s_right = max(0.0, (k + 1 - HALF) / HALF)
        sets.append((stamp, {
            "left": pose("left", stamp, -ABOVE + (ABOVE + DEPTH) * s_left),
            "right": pose("right", stamp, -ABOVE + (ABOVE + DEPTH) * s_right)}))
    return sets


class Recorder:
    """Everything the simulator publishes, keyed by stamp [ns]; burst ends wake waiters."""

    def __init__(self):
        self.cond = threading.Condition()
        self.stats = []
        self.ends = set()
        self.received = 0  # wrench and contact-model messages since the last clear()
        self.logs = []
        self.force = {t: {} for t in TOOLS}
        self.model = {t: {} for t in TOOLS}
        rospy.Subscriber("tissue/stats", TissueStats, self.on_stats, queue_size=1000)
        rospy.Subscriber("/rosout", Log, self.on_log, queue_size=1000)
        for tool in TOOLS:
            rospy.Subscriber(tool + "/tissue/wrench", WrenchStamped, self.keep,
                             (self.force[tool], lambda m: m.wrench.force), queue_size=1000)
            rospy.Subscriber(tool + "/tissue/contact_model", ContactModel, self.keep,
                             (self.model[tool], lambda m: m), queue_size=1000)

    def on_stats(self, msg):
        with self.cond:
            self.stats.append(msg)
            if msg.burst_end:
                self.ends.add(msg.pose_set_stamp.to_nsec())
            self.cond.notify_all()

    def on_log(self, msg):
        with self.cond:
            self.logs.append(msg.msg)
            self.cond.notify_all()

    def keep(self, msg, args):
        store, value = args
        with self.cond:
            store[msg.header.stamp.to_nsec()] = value(msg)
            self.received += 1
            self.cond.notify_all()

    def clear(self):
        with self.cond:
            self.stats, self.ends, self.received = [], set(), 0
            for tool in TOOLS:
                self.force[tool].clear()
                self.model[tool].clear()

    def wait_end(self, stamp, timeout=30.0):
        with self.cond:
            if not self.cond.wait_for(lambda: stamp.to_nsec() in self.ends, timeout):
                raise AssertionError("no end of a step burst for the set stamped %s" % stamp)

    def wait_outputs(self, steps, timeout=30.0):
        """Waits for every tool's wrench and contact model of `steps` steps: they travel on other
        topics than tissue/stats, so a burst's end can arrive before its last step's outputs."""
        with self.cond:
            if not self.cond.wait_for(lambda: self.received >= 2 * len(TOOLS) * steps, timeout):
                raise AssertionError("%d of the outputs of %d steps arrived" % (self.received, steps))

    def wait_log(self, fragment, timeout=30.0):
        with self.cond:
            if not self.cond.wait_for(lambda: any(fragment in m for m in self.logs), timeout):
                raise AssertionError("no log containing '%s'; the last ones: %s" %
                                     (fragment, self.logs[-4:]))

    def history(self):
        """Per set stamp: (left force, right force, left model, right model)."""
        with self.cond:
            return {k: tuple(self.force[t][k] for t in TOOLS) + tuple(
                (m.point, m.force, m.stiffness, m.contacts)
                for m in (self.model[t][k] for t in TOOLS)) for k in self.force["left"]}


class MultiToolLockstepTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node("multi_tool_lockstep_rostest")
        cls.steps_per_pose = rospy.get_param("~steps_per_pose")
        cls.sets = motion()
        cls.rec = Recorder()
        cls.pubs = {t: rospy.Publisher(t + "/tool/pose", PoseStamped, queue_size=1000)
                    for t in TOOLS}
        rospy.wait_for_service("tissue/reset", timeout=120.0)
        cls.reset_srv = rospy.ServiceProxy("tissue/reset", Empty)
        cls.pause = rospy.ServiceProxy("tissue/pause", SetBool)
        wait_for_subscribers(*cls.pubs.values())

    def reset(self):
        self.reset_srv()
        self.rec.clear()

    def publish_sets(self):
        """Publishes every set, `right` first in even sets and `left` first in odd ones, waiting
        for each set's burst; returns the recorder's history."""
        self.reset()
        for k, (stamp, poses) in enumerate(self.sets):
            for tool in (TOOLS if k % 2 else TOOLS[::-1]):
                self.pubs[tool].publish(poses[tool])
            self.rec.wait_end(stamp)
        self.rec.wait_outputs(SETS * self.steps_per_pose)
        return self.rec.history()

    def lockstep_play(self, bag_path):
        """Replays the bag with scripts/lockstep_play; returns the recorder's history."""
        self.reset()
        code, out = run_node("lockstep_play", [bag_path, "--delay", "0.5"], timeout=600)
        self.assertEqual(code, 0, out)
        self.rec.wait_end(self.sets[-1][0])
        self.rec.wait_outputs(SETS * self.steps_per_pose)
        with self.rec.cond:
            self.assertEqual(len(self.rec.stats), SETS * self.steps_per_pose)
        return self.rec.history()

    def test_one_step_burst_per_pose_set_and_a_contact_model_per_tool(self):
        history = self.publish_sets()
        with self.rec.cond:
            stats = list(self.rec.stats)
        # N pose sets of 2 tools -> exactly N x steps_per_pose steps, in bursts stamped per set.
        self.assertEqual(len(stats), SETS * self.steps_per_pose)
        self.assertEqual([s.step for s in stats], list(range(1, len(stats) + 1)))
        for k, (stamp, _) in enumerate(self.sets):
            burst = stats[k * self.steps_per_pose:(k + 1) * self.steps_per_pose]
            self.assertEqual([s.pose_set_stamp for s in burst], [stamp] * self.steps_per_pose)
            self.assertEqual([s.header.stamp for s in burst], [stamp] * self.steps_per_pose)
            self.assertEqual([s.burst_step for s in burst],
                             list(range(1, self.steps_per_pose + 1)))
            self.assertEqual([s.burst_end for s in burst],
                             [False] * (self.steps_per_pose - 1) + [True])
        self.assertAlmostEqual(stats[-1].sim_time, SETS * self.steps_per_pose * 0.01, places=9)
        # Each tool its own contact model: at the end of the first half `left` presses and
        # `right`, still above the organ, feels nothing; at the end both press.
        half = self.sets[HALF - 1][0].to_nsec()
        end = self.sets[-1][0].to_nsec()
        left_half, right_half = history[half][0], history[half][1]
        self.assertGreater(left_half.z, 0.01, "left pressing 6 mm: f_z = %.5f N" % left_half.z)
        self.assertEqual((right_half.x, right_half.y, right_half.z), (0.0, 0.0, 0.0))
        with self.rec.cond:
            for tool in TOOLS:
                model = self.rec.model[tool][end]
                self.assertEqual(model.tool, tool)
                self.assertTrue(model.in_contact, tool)
                self.assertGreater(model.force.z, 0.01, tool)
                # the contact point lies under the tool, not under the other one
                self.assertLess(abs(model.point.x - SPOT[tool][0]), 0.005, tool)
            self.assertFalse(self.rec.model["right"][half].in_contact)
            self.assertTrue(self.rec.model["left"][half].in_contact)

    def test_replays_are_bit_identical(self):
        with tempfile.TemporaryDirectory() as folder:
            path = os.path.join(folder, "two_tools.bag")
            with rosbag.Bag(path, "w") as bag:
                for stamp, poses in self.sets:
                    for tool in TOOLS:
                        bag.write(tool + "/tool/pose", poses[tool], stamp)
            first = self.lockstep_play(path)
            second = self.lockstep_play(path)
        reordered = self.publish_sets()
        self.assertEqual(len(first), SETS)
        self.assertEqual(first, second, "two lockstep_play replays differ")
        self.assertEqual(first, reordered, "the order of the poses inside a set changed the result")

    def test_missing_overrun_and_stale_poses(self):
        self.reset()
        t1, t2, t3 = (rospy.Time.from_sec(50.0 + 0.01 * k) for k in range(3))
        # Only `left` posts (a deep press, then a pose above): no step; the second pose replaces
        # the first (a dropped pose) and the warning names the tool that blocks the set.
        self.pubs["left"].publish(pose("left", t1, 0.006))
        self.pubs["left"].publish(pose("left", t2, -ABOVE))
        self.rec.wait_log("tool left overran")
        self.rec.wait_log("waiting for the first pose of tool(s) right")
        # `right` completes the set: one burst stamped t2 with left's newest pose (above: no force).
        self.pubs["right"].publish(pose("right", t2, -ABOVE))
        self.rec.wait_end(t2)
        # A set not newer than the last one is ignored; the next one steps. The tools' topics are
        # separate connections and the warning is throttled per call site, so `right`'s stale
        # pose goes out only once `left`'s warning arrived (else it may arrive first and hide it).
        self.pubs["left"].publish(pose("left", t1, 0.006))
        self.rec.wait_log("tool left pose stamped 50.000000 s ignored")
        self.pubs["right"].publish(pose("right", t1, 0.006))
        for tool in TOOLS:
            self.pubs[tool].publish(pose(tool, t3, -ABOVE))
        self.rec.wait_end(t3)
        with self.rec.cond:
            stamps = [s.pose_set_stamp for s in self.rec.stats]
            self.assertEqual(stamps, [t2] * self.steps_per_pose + [t3] * self.steps_per_pose)
            self.assertEqual(self.rec.force["left"][t2.to_nsec()].z, 0.0)

    def test_a_set_completed_while_paused_steps_on_resume(self):
        self.reset()
        first, second = self.sets[0][0], self.sets[1][0]
        for tool in TOOLS:
            self.pubs[tool].publish(self.sets[0][1][tool])
        self.rec.wait_end(first)
        self.assertTrue(self.pause(True).success)
        try:
            for tool in TOOLS:
                self.pubs[tool].publish(self.sets[1][1][tool])
            rospy.sleep(1.0)  # delivered while paused (the assertions below hold either way)
            with self.rec.cond:
                self.assertNotIn(second.to_nsec(), self.rec.ends, "stepped while paused")
        finally:
            self.assertTrue(self.pause(False).success)
        self.rec.wait_end(second)
        with self.rec.cond:
            self.assertEqual([s.pose_set_stamp for s in self.rec.stats],
                             [first] * self.steps_per_pose + [second] * self.steps_per_pose)


if __name__ == "__main__":
    rostest.rosrun("surgical_sim", "multi_tool_lockstep", MultiToolLockstepTest, sys.argv)
