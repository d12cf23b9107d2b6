#!/usr/bin/python3
"""rostest: bad parameters stop continuum_robot_controller at start-up, naming the parameter."""
import sys
import unittest

import rospy
import rostest

from node_probe import run_node


class ContinuumRobotBadInputTest(unittest.TestCase):
    def test_bad_parameters_exit_naming_the_parameter(self):
        for args, message in ((["_rate:=0"], "~rate = 0 Hz is out of range: must be in (0, 1000] Hz"),
                              (["_rate:=fast"], "~rate must be a number"),
                              (["_tolerance:=2"], "~tolerance = 2 m is out of range"),
                              (["_max_iterations:=5000"], "~max_iterations = 5000 is out of range"),
                              (["_max_iterations:=2.0"], "~max_iterations must be an integer"),
                              (["_step_iterations:=0"], "~step_iterations = 0 is out of range"),
                              (["_base_frame:=1"], "~base_frame must be a non-empty string"),
                              (["_robot:=nope"], "~robot = 'nope'")):
            code, out = run_node("continuum_robot_controller", args)
            self.assertNotEqual(code, 0, "%s accepted" % args)
            self.assertIn(message, out)


if __name__ == "__main__":
    rospy.init_node("continuum_robot_bad_input_rostest")
    rostest.rosrun("surgical_sim", "continuum_robot_bad_input", ContinuumRobotBadInputTest,
                   sys.argv)
