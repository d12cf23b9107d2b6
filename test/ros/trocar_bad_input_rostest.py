#!/usr/bin/python3
"""rostest: bad input never crashes trocar_device; bad parameters stop it at start-up, naming the
parameter or the URDF problem. The node runs on urdf/active_trocar.urdf (robot_description) with its
default pose: fulcrum at (0, 0, 0.2) m, cannula pointing down."""
import math
import os
import sys
import tempfile
import threading
import unittest

import rospkg
import rospy
import rostest
from geometry_msgs.msg import WrenchStamped
from rosgraph_msgs.msg import Log
from sensor_msgs.msg import JointState
from std_srvs.srv import Trigger
from surgical_sim.msg import ContactModel, LoopStats
from surgical_sim.srv import SetTrocarLimits

from node_probe import run_node, wait_for_subscribers

JOINTS = ["trocar_pitch", "trocar_yaw", "trocar_spin", "trocar_insertion", "trocar_grip"]
ENCODER_PITCH = math.radians(0.01)  # pitch encoder step [rad]


class TrocarBadInputTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node("trocar_bad_input_rostest")
        cls.lock = threading.Condition()
        cls.logs = []
        cls.joints = None
        cls.wrenches = []
        rospy.Subscriber("/rosout", Log, cls.on_log, queue_size=1000)
        rospy.Subscriber("/rosout_agg", Log, cls.on_log, queue_size=1000)
        rospy.Subscriber("joint_states", JointState, cls.on_joints, queue_size=10)
        rospy.Subscriber("trocar/rendered_wrench", WrenchStamped, cls.on_wrench, queue_size=100)
        rospy.wait_for_service("trocar/home", timeout=60.0)
        cls.home = rospy.ServiceProxy("trocar/home", Trigger)
        cls.set_limits = rospy.ServiceProxy("trocar/set_limits", SetTrocarLimits)
        cls.command_pub = rospy.Publisher("trocar/joint_command", JointState, queue_size=10)
        cls.model_pub = rospy.Publisher("tissue/contact_model", ContactModel, queue_size=10)
        wait_for_subscribers(cls.command_pub, cls.model_pub)

    @classmethod
    def on_log(cls, msg):
        with cls.lock:
            cls.logs.append(msg.msg)

    @classmethod
    def on_joints(cls, msg):
        with cls.lock:
            cls.joints = dict(zip(msg.name, msg.position))
            cls.lock.notify_all()

    @classmethod
    def on_wrench(cls, msg):
        f = msg.wrench.force
        with cls.lock:
            cls.wrenches.append((f.x, f.y, f.z))
            cls.lock.notify_all()

    def setUp(self):
        self.assertTrue(self.set_limits(45.0, 45.0).success)
        self.assertTrue(self.home().success)

    def wait_for_log(self, fragment, timeout=10.0):
        with self.lock:
            return self.lock.wait_for(lambda: any(fragment in m for m in self.logs), timeout)

    def wait_for_joints(self, predicate, timeout=10.0):
        """Waits until a joint_states message satisfies predicate; returns the last one."""
        with self.lock:
            self.lock.wait_for(lambda: self.joints is not None and predicate(self.joints), timeout)
            return dict(self.joints)

    def next_wrenches(self, count, timeout=10.0):
        with self.lock:
            first = len(self.wrenches)
            self.lock.wait_for(lambda: len(self.wrenches) >= first + count, timeout)
            return self.wrenches[first:]

    def command(self, names, positions):
        msg = JointState()
        msg.header.stamp = rospy.Time.now()
        msg.name, msg.position = names, positions
        self.command_pub.publish(msg)

    def assert_alive_and_finite(self):
        self.assertTrue(self.home().success, "trocar_device stopped answering")
        joints = self.wait_for_joints(lambda j: True)
        self.assertTrue(all(math.isfinite(v) for v in joints.values()))
        for f in self.next_wrenches(3):
            self.assertTrue(all(math.isfinite(c) for c in f))

    def assert_zero_force(self):
        """The next rendered forces are zero up to round-off of the coupling proxy [N]."""
        for f in self.next_wrenches(3):
            self.assertLess(max(abs(c) for c in f), 1e-9, "rendered force %s is not zero" % (f,))

    def test_nan_command_holds_the_previous_position(self):
        self.command(["trocar_pitch"], [0.3])
        self.wait_for_joints(lambda j: abs(j["trocar_pitch"] - 0.3) < ENCODER_PITCH)
        self.command(["trocar_pitch", "trocar_insertion"], [float("nan"), 0.05])
        joints = self.wait_for_joints(lambda j: abs(j["trocar_insertion"] - 0.05) < 1e-4)
        self.assertAlmostEqual(joints["trocar_pitch"], 0.3, delta=ENCODER_PITCH)
        self.assertTrue(self.wait_for_log("non-finite position for joint 'trocar_pitch'"))
        self.assert_alive_and_finite()

    def test_command_beyond_limits_is_clamped_naming_the_joint(self):
        self.command(["trocar_yaw"], [2.0])
        joints = self.wait_for_joints(lambda j: j["trocar_yaw"] > 0.5)
        self.assertAlmostEqual(joints["trocar_yaw"], math.radians(45.0), delta=ENCODER_PITCH)
        self.assertTrue(self.wait_for_log("joint 'trocar_yaw' command 2 rad is beyond its limits"))
        self.command(["trocar_insertion"], [0.5])
        joints = self.wait_for_joints(lambda j: j["trocar_insertion"] > 0.2)
        self.assertAlmostEqual(joints["trocar_insertion"], 0.30, delta=1e-4)
        self.assert_alive_and_finite()

    def test_unknown_joint_and_malformed_command_are_ignored(self):
        self.command(["elbow"], [1.0])
        self.assertTrue(self.wait_for_log("unknown joint 'elbow'"))
        msg = JointState()
        msg.name = JOINTS
        msg.position = [0.1]
        self.command_pub.publish(msg)
        self.assertTrue(self.wait_for_log("5 names but 1 positions"))
        self.assert_alive_and_finite()

    def test_duplicated_joint_rejects_the_command_naming_it(self):
        self.command(["trocar_pitch"], [0.2])
        self.wait_for_joints(lambda j: abs(j["trocar_pitch"] - 0.2) < ENCODER_PITCH)
        self.command(["trocar_pitch", "trocar_yaw", "trocar_pitch"], [0.4, 0.1, -0.4])
        self.assertTrue(self.wait_for_log(
            "trocar/joint_command ignored: joint 'trocar_pitch' appears more than once"))
        self.command(["trocar_insertion"], [0.05])  # a later valid command still applies
        joints = self.wait_for_joints(lambda j: abs(j["trocar_insertion"] - 0.05) < 1e-4)
        self.assertAlmostEqual(joints["trocar_pitch"], 0.2, delta=ENCODER_PITCH)
        self.assertAlmostEqual(joints["trocar_yaw"], 0.0, delta=ENCODER_PITCH)
        self.assert_alive_and_finite()

    def test_set_limits_validates_and_applies(self):
        reply = self.set_limits(80.0, 10.0)
        self.assertFalse(reply.success)
        self.assertIn("trocar.pitch_limit", reply.message)
        reply = self.set_limits(20.0, float("nan"))
        self.assertFalse(reply.success)
        self.assertIn("trocar.yaw_limit", reply.message)
        self.assertTrue(self.set_limits(20.0, 20.0).success)
        self.command(["trocar_pitch"], [-0.6])
        joints = self.wait_for_joints(lambda j: j["trocar_pitch"] < -0.1)
        self.assertAlmostEqual(joints["trocar_pitch"], -math.radians(20.0), delta=ENCODER_PITCH)
        self.assert_alive_and_finite()

    def contact_model(self, force_z, frame="world"):
        """A tissue pushing the tool up by force_z [N] at the tip of the homed tool."""
        msg = ContactModel()
        msg.header.stamp = rospy.Time.now()
        msg.header.frame_id = frame
        msg.in_contact = True
        msg.point.z = 0.2 - 0.02 - 0.1  # fulcrum height - (tip offset + insertion 0.1 m)
        msg.force.z = force_z
        return msg

    def test_stale_nan_and_wrong_frame_contact_models_give_zero_force(self):
        self.command(["trocar_insertion"], [0.1])
        self.wait_for_joints(lambda j: abs(j["trocar_insertion"] - 0.1) < 1e-4)
        # Fresh model, re-sent well within ~stale_age (0.5 s): the force is rendered.
        stop = threading.Event()

        def stream():
            while not stop.is_set():
                self.model_pub.publish(self.contact_model(1.0))
                rospy.sleep(0.02)

        streamer = threading.Thread(target=stream)
        streamer.start()
        try:
            with self.lock:
                self.lock.wait_for(lambda: any(f[2] > 0.5 for f in self.wrenches[-5:]), 10.0)
            self.assertGreater(self.wrenches[-1][2], 0.5, "fresh contact force not rendered")
        finally:
            stop.set()
            streamer.join()
        # No new model: it goes stale and the force drops to zero (fade_time 0), with a warning.
        self.assertTrue(self.wait_for_log("tissue/contact_model is stale"))
        self.assert_zero_force()
        self.model_pub.publish(self.contact_model(float("nan")))
        self.assertTrue(self.wait_for_log("tissue/contact_model with NaN/Inf ignored"))
        self.model_pub.publish(self.contact_model(1.0, frame="tissue"))
        self.assertTrue(self.wait_for_log("tissue/contact_model in frame 'tissue' ignored"))
        self.assert_zero_force()
        self.assert_alive_and_finite()

    def test_home_retracts_the_tool_and_loop_stats_are_published(self):
        self.command(["trocar_insertion", "trocar_yaw"], [0.12, 0.3])
        self.wait_for_joints(lambda j: abs(j["trocar_insertion"] - 0.12) < 1e-4)
        reply = self.home()
        self.assertTrue(reply.success)
        joints = self.wait_for_joints(lambda j: j["trocar_insertion"] == 0.0)
        self.assertEqual(joints["trocar_insertion"], 0.0)
        self.assertEqual(joints["trocar_yaw"], 0.0)
        stats = rospy.wait_for_message("trocar/loop_stats", LoopStats, timeout=10.0)
        self.assertGreater(stats.ticks, 0)
        self.assertAlmostEqual(stats.nominal_period, 1e-3)
        self.assertTrue(0.0 < stats.period_mean <= stats.period_p99 <= stats.period_max)

    def test_out_of_range_parameters_exit_naming_the_parameter(self):
        for args, name in ((["_pitch_limit_deg:=80"], "~pitch_limit_deg is not a parameter"),
                           (["_rate:=5"], "~rate"),
                           (["_stale_age:=-1"], "~stale_age"),
                           (["_stale_policy:=maybe"], "~stale_policy"),
                           (["_z:=.nan"], "~z"),
                           (["_x:=far"], "~x must be a number"),
                           (["_passivity:=1"], "~passivity must be true or false"),
                           (["_realtime_priority:=2.5"], "~realtime_priority must be an integer"),
                           (["_world_frame:=3"], "~world_frame must be a non-empty string"),
                           (["_joint_prefix:=true"], "~joint_prefix must be a string")):
            code, out = run_node("trocar_device", args)
            self.assertNotEqual(code, 0, "%s accepted" % args)
            self.assertIn(name, out)

    def test_a_namespaced_node_finds_the_global_robot_description(self):
        code, out = run_node("trocar_device", ["__ns:=/left", "_rate:=5"])
        self.assertNotEqual(code, 0)
        self.assertIn("~rate", out)  # read after the URDF
        self.assertNotIn("no trocar URDF", out)

    def test_bad_urdfs_exit_naming_the_problem(self):
        path = os.path.join(rospkg.RosPack().get_path("surgical_sim"), "urdf", "active_trocar.urdf")
        with open(path) as f:
            urdf = f.read()
        placed = urdf.replace("</robot>", '<link name="world"/><joint name="world_to_trocar" '
                              'type="fixed"><parent link="world"/><child link="trocar"/>'
                              '<origin xyz="0 0 0.2" rpy="3.14159 0 0"/></joint></robot>')
        wide = urdf.replace('upper="0.7853981633974483"', 'upper="1.4"', 1)
        with tempfile.TemporaryDirectory() as folder:
            files = {}
            for name, text in (("placed", placed), ("wide", wide)):
                files[name] = os.path.join(folder, name + ".urdf")
                with open(files[name], "w") as f:
                    f.write(text)
            for args, problem in (
                    (["_urdf_file:=/nonexistent/trocar.urdf"],
                     "~urdf_file: cannot read '/nonexistent/trocar.urdf'"),
                    (["_trocar_frame:=trocar_9"], "trocar URDF has no link 'trocar_9'"),
                    (["_joint_prefix:=left_"], "has no link 'left_tool_tip'"),
                    (["_urdf_file:=" + files["wide"]],
                     "joint 'trocar_pitch' <limit upper> = 1.4 rad is out of range"),
                    (["_urdf_file:=" + files["placed"], "_x:=0.1"],
                     "~x is set but the URDF places 'trocar' in 'world'")):
                code, out = run_node("trocar_device", args)
                self.assertNotEqual(code, 0, "%s accepted" % args)
                self.assertIn(problem, out)


if __name__ == "__main__":
    rostest.rosrun("surgical_sim", "trocar_bad_input", TrocarBadInputTest, sys.argv)
