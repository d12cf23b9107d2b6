#!/usr/bin/python3
"""rostest: launch/scene.launch starts exactly the nodes a runtime scene needs (~expected_nodes,
a space-separated list), and with ~bag replays it in lockstep: one tissue step per pose set,
each trocar its own contact model and motor efforts within its limits, and a second replay after
tissue/reset bit-identical to the first."""
import subprocess
import threading
import unittest

import rosbag
import rosnode
import rospy
import rostest
from sensor_msgs.msg import JointState
from std_srvs.srv import Empty
from surgical_sim.msg import ContactModel, TissueStats

# Effort limits of urdf/active_trocar.urdf by joint suffix [N m] or [N].
EFFORT_LIMIT = {"pitch": 6.0, "yaw": 6.0, "spin": 0.2, "insertion": 5.0, "grip": 0.3}


def running_nodes():
    """Nodes registered with the master, without the master's /rosout and this test node."""
    me = rospy.get_name()
    return sorted(n for n in rosnode.get_node_names() if n not in ("/rosout", me))


class SceneLaunch(unittest.TestCase):
    def setUp(self):
        self.cond = threading.Condition()
        self.steps = []
        self.models = {}   # trocar -> {stamp ns: (in_contact, force)}
        self.efforts = {}  # trocar -> [JointState]
        self.trocars = rospy.get_param("~trocars", "").split()
        rospy.Subscriber("tissue/stats", TissueStats, self.on_stats, queue_size=1000)
        for t in self.trocars:
            self.models[t] = {}
            self.efforts[t] = []
            rospy.Subscriber("/%s/tissue/contact_model" % t, ContactModel, self.on_model, t,
                             queue_size=1000)
            rospy.Subscriber("/%s/trocar/motor_effort" % t, JointState, self.on_effort, t,
                             queue_size=1000)

    def on_stats(self, msg):
        with self.cond:
            self.steps.append(msg)

    def on_model(self, msg, trocar):
        with self.cond:
            self.models[trocar][msg.header.stamp.to_nsec()] = (
                msg.in_contact, (msg.force.x, msg.force.y, msg.force.z))

    def on_effort(self, msg, trocar):
        with self.cond:
            self.efforts[trocar].append(msg)

    def wait_for_nodes(self, expected, timeout=60.0):
        deadline = rospy.get_time() + timeout
        while rospy.get_time() < deadline and running_nodes() != expected:
            rospy.sleep(0.5)
        return running_nodes()

    def replay(self, bag, sets):
        out = subprocess.run(["rosrun", "surgical_sim", "lockstep_play", bag, "--delay", "1",
                              "--ack-timeout", "60"], capture_output=True, text=True, timeout=900)
        self.assertEqual(out.returncode, 0, out.stdout + out.stderr)
        # The last steps' stats and contact models travel on their own topics: wait for them.
        deadline = rospy.get_time() + 30.0
        while rospy.get_time() < deadline:
            with self.cond:
                if len(self.steps) >= sets and all(len(m) >= sets for m in self.models.values()):
                    break
            rospy.sleep(0.1)
        with self.cond:
            steps, models = list(self.steps), {t: dict(m) for t, m in self.models.items()}
            self.steps.clear()
            for m in self.models.values():
                m.clear()
        return steps, models

    def test_scene(self):
        expected = sorted(rospy.get_param("~expected_nodes").split())
        self.assertEqual(self.wait_for_nodes(expected), expected)
        bag = rospy.get_param("~bag", "")
        if not bag:
            return
        sets = {m.header.stamp.to_nsec() for _, m, _ in rosbag.Bag(bag).read_messages()}
        steps, first = self.replay(bag, len(sets))
        # One step per pose set (steps_per_pose 1): N sets -> N steps, none failed.
        self.assertEqual(len(steps), len(sets))
        self.assertEqual(sorted(s.pose_set_stamp.to_nsec() for s in steps), sorted(sets))
        self.assertTrue(all(s.status in ("ok", "contact_limited") for s in steps),
                        {s.status for s in steps})
        for t in self.trocars:
            # Each trocar its own contact model: it touched, on its own topic, at every set.
            self.assertEqual(len(first[t]), len(sets), t)
            self.assertTrue(any(c for c, _ in first[t].values()), t + " never touched the organ")
            # Its motor efforts: some non-zero, every one within the URDF's effort limit.
            with self.cond:
                efforts = list(self.efforts[t])
            self.assertTrue(efforts, t)
            peak = 0.0
            for msg in efforts:
                for name, effort in zip(msg.name, msg.effort):
                    limit = EFFORT_LIMIT[name[len(t) + 1:]]
                    self.assertLessEqual(abs(effort), limit + 1e-9, "%s %s" % (t, name))
                    peak = max(peak, abs(effort))
            self.assertGreater(peak, 0.0, t)
        # A second replay after reset is bit-identical (tissue side: poses are set per stamp).
        rospy.ServiceProxy("tissue/reset", Empty)()
        steps2, second = self.replay(bag, len(sets))
        self.assertEqual(len(steps2), len(sets))
        self.assertEqual([s.energy for s in steps2], [s.energy for s in steps])
        for t in self.trocars:
            self.assertEqual(second[t], first[t], t)


if __name__ == "__main__":
    rospy.init_node("scene_launch_test")
    rostest.rosrun("surgical_sim", "scene_launch", SceneLaunch)
