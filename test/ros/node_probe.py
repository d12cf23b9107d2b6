"""Shared by the rostests: start-up rejection probes (a node run once, outside the launch) and
waiting for the nodes under test to subscribe."""
import subprocess
import uuid

import rospy


def wait_for_subscribers(*publishers, timeout=30.0):
    """Waits at most `timeout` s until every publisher has its subscribers: each argument is a
    rospy.Publisher (at least one subscriber) or a (publisher, count) pair."""
    wanted = [p if isinstance(p, tuple) else (p, 1) for p in publishers]
    deadline = rospy.get_time() + timeout
    while rospy.get_time() < deadline and any(
            pub.get_num_connections() < count for pub, count in wanted):
        rospy.sleep(0.05)


def run_node(node_type, extra_args, timeout=60):
    """Runs a second `node_type` of surgical_sim under a fresh node name (so no private parameter
    is left over from an earlier probe) with `extra_args` (e.g. private params `_name:=value`);
    returns (exit code, combined output)."""
    name = "probe_%s_%s" % (node_type, uuid.uuid4().hex[:8])
    cmd = ["rosrun", "surgical_sim", node_type, "__name:=" + name] + extra_args
    proc = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, timeout=timeout,
                          text=True)
    return proc.returncode, proc.stdout
