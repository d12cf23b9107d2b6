#!/usr/bin/python3
"""rostest: trocar_palpation.bag -> trocar_device -> tool/pose -> tissue_simulator (lockstep) ->
tissue/contact_model -> trocar_device -> trocar/motor_effort. Physics checked on the efforts:

- while the tool indents the organ, the insertion effort pushes the tool back out (< 0: the
  insertion axis points into the patient);
- while the tip presses down, the efforts oppose the joint motion (tau . dq < 0: by virtual work,
  tau . dq = f . dx, the rendered force opposes the indentation);
- every effort is within the device limits (pitch/yaw 6 N m, spin 0.2 N m, insertion 5 N);
- after the release the efforts return to ~0.
"""
import math
import sys
import threading
import unittest

import rosbag
import rospy
import rostest
from sensor_msgs.msg import JointState
from surgical_sim.msg import ContactModel

from node_probe import subscribe_by_stamp, wait_for_subscribers

LIMITS = {"trocar_pitch": 6.0, "trocar_yaw": 6.0, "trocar_spin": 0.2, "trocar_insertion": 5.0,
          "trocar_grip": 0.3}  # [N m] revolute, [N] insertion
TIP_OFFSET = 0.020  # tip depth below the fulcrum at insertion 0 [m] (TrocarGeometry)
EFFORTS_AFTER_MODEL = 3  # motor_effort messages to wait for after each contact model


class Chain:
    """Publishes one joint command at a time; returns the tissue force it produced and the motor
    efforts the trocar renders once the resulting contact model has reached it."""

    def __init__(self):
        self.lock = threading.Condition()
        self.models = {}
        self.efforts = []  # every trocar/motor_effort message, in arrival order
        self.pub = rospy.Publisher("trocar/joint_command", JointState, queue_size=1000)
        subscribe_by_stamp("tissue/contact_model", ContactModel, self.lock, self.models)
        rospy.Subscriber("trocar/motor_effort", JointState, self.on_effort, queue_size=1000)
        wait_for_subscribers(self.pub)

    def on_effort(self, msg):
        with self.lock:
            self.efforts.append(dict(zip(msg.name, msg.effort)))
            self.lock.notify_all()

    def send(self, command):
        key = command.header.stamp.to_nsec()
        self.pub.publish(command)
        with self.lock:
            if not self.lock.wait_for(lambda: key in self.models, timeout=30.0):
                raise AssertionError("no tissue/contact_model for command %s"
                                     % command.header.stamp)
            first = len(self.efforts)
            if not self.lock.wait_for(lambda: len(self.efforts) >= first + EFFORTS_AFTER_MODEL,
                                      timeout=30.0):
                raise AssertionError("trocar/motor_effort stopped")
            return self.models[key], self.efforts[-1]


class TrocarPalpationTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node("trocar_palpation_rostest")
        with rosbag.Bag(rospy.get_param("~bag")) as bag:
            cls.commands = [m for _, m, _ in bag.read_messages(topics=["trocar/joint_command"])]
        cls.chain = Chain()
        cls.samples = []  # (joint positions by name, contact model, efforts by name)
        for command in cls.commands:
            model, effort = cls.chain.send(command)
            cls.samples.append((dict(zip(command.name, command.position)), model, effort))

    @staticmethod
    def force_norm(model):
        f = model.force
        return (f.x ** 2 + f.y ** 2 + f.z ** 2) ** 0.5

    def test_efforts_within_device_limits(self):
        for q, _, effort in self.samples:
            for name, limit in LIMITS.items():
                self.assertLessEqual(abs(effort[name]), limit + 1e-9,
                                     "%s effort %.6g beyond its limit at insertion %.4f m"
                                     % (name, effort[name], q["trocar_insertion"]))

    def test_insertion_effort_pushes_the_tool_out_while_in_contact(self):
        peak = max(self.force_norm(m) for _, m, _ in self.samples)
        self.assertGreater(peak, 0.05, "the tool never indented the organ (peak %.4f N)" % peak)
        in_contact = [s for s in self.samples if self.force_norm(s[1]) > 0.1 * peak]
        self.assertGreater(len(in_contact), 20)
        for q, model, effort in in_contact:
            self.assertLess(effort["trocar_insertion"], 0.0,
                            "insertion effort %.5f N does not push the tool out (tissue force "
                            "%.4f N, insertion %.4f m)"
                            % (effort["trocar_insertion"], self.force_norm(model),
                               q["trocar_insertion"]))
        peak_effort = max(abs(e["trocar_insertion"]) for _, _, e in in_contact)
        # The organ pushes up and the shaft is tilted by ~15-25 deg: the axial part of the tissue
        # force is most of it.
        self.assertGreater(peak_effort, 0.5 * peak)

    @staticmethod
    def tip_drop(q):
        """Height of the fulcrum above the tool tip [m]: the cannula points straight down, so the
        shaft axis has vertical component cos(pitch) cos(yaw) (TrocarKinematics)."""
        depth = q["trocar_insertion"] + TIP_OFFSET
        return depth * math.cos(q["trocar_pitch"]) * math.cos(q["trocar_yaw"])

    def test_efforts_oppose_the_pressing_motion(self):
        peak = max(self.force_norm(m) for _, m, _ in self.samples)
        pressing = 0
        for (q0, _, _), (q1, model, effort) in zip(self.samples, self.samples[1:]):
            dq = {n: q1[n] - q0[n] for n in q1}
            indenting = self.tip_drop(q1) - self.tip_drop(q0) > 1e-6  # tip moves down [m]
            if not indenting or self.force_norm(model) < 0.1 * peak:
                continue
            pressing += 1
            power = sum(effort[n] * dq[n] for n in dq)  # tau . dq = f . dx [J]
            self.assertLess(power, 0.0, "effort does work with the indentation at insertion %.4f m"
                            % q1["trocar_insertion"])
        self.assertGreater(pressing, 5, "no pressing samples in contact")

    def test_efforts_vanish_after_the_release(self):
        for _, model, effort in self.samples[-10:]:
            self.assertFalse(model.in_contact)
            for name in LIMITS:
                self.assertLess(abs(effort[name]), 1e-6, "%s effort %.3g after the release"
                                % (name, effort[name]))


if __name__ == "__main__":
    rostest.rosrun("surgical_sim", "trocar_palpation", TrocarPalpationTest, sys.argv)
