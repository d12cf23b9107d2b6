#!/usr/bin/python3
"""rostest: the palpation checks (palpation_rostest.PalpationTest) on the EFG organ."""
import sys

import rostest

from palpation_rostest import PalpationTest

if __name__ == "__main__":
    rostest.rosrun("surgical_sim", "palpation_efg", PalpationTest, sys.argv)
