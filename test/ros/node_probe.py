"""Shared by the rostests: start-up rejection probes (a node run once, outside the launch),
waiting for the nodes under test to subscribe, and collecting their replies by stamp."""
import signal
import subprocess
import time
import uuid
import xmlrpc.client

import rosgraph
import rospy
from geometry_msgs.msg import PoseStamped


def wait_for_subscribers(*publishers, timeout=30.0):
    """Waits at most `timeout` s until every publisher has its subscribers: each argument is a
    rospy.Publisher (at least one subscriber) or a (publisher, count) pair."""
    wanted = [p if isinstance(p, tuple) else (p, 1) for p in publishers]
    deadline = rospy.get_time() + timeout
    while rospy.get_time() < deadline and any(
            pub.get_num_connections() < count for pub, count in wanted):
        rospy.sleep(0.05)


def wait_for_connection(node, topic, peer, timeout=30.0):
    """Waits at most `timeout` s until node's publisher of `topic` is connected to `peer` (node
    names and topic fully qualified), from node's bus information: messages published before
    that connection exists are lost. Raises AssertionError naming the three on time-out."""
    uri = rosgraph.Master(rospy.get_name()).lookupNode(node)
    proxy = xmlrpc.client.ServerProxy(uri)
    deadline = time.time() + timeout
    while time.time() < deadline:
        _, _, connections = proxy.getBusInfo(rospy.get_name())
        if any(c[1] == peer and c[2] == "o" and c[4] == topic for c in connections):
            return
        time.sleep(0.05)
    raise AssertionError("%s's %s never connected to %s within %.0f s" % (node, topic, peer,
                                                                         timeout))


def messages_received(node, topic):
    """Messages of `topic` that node's subscription has received so far (all publishers), from
    its bus statistics (roscpp: [connection, bytes, messages, drops, ...] per publisher)."""
    uri = rosgraph.Master(rospy.get_name()).lookupNode(node)
    _, subscriptions = xmlrpc.client.ServerProxy(uri).getBusStats(rospy.get_name())[:2]
    return sum(c[2] for name, connections in subscriptions if name == topic for c in connections)


def wait_for_messages_received(node, topic, count, timeout=20.0):
    """Waits at most `timeout` s until node has received `count` messages of `topic`; raises
    AssertionError naming them on time-out."""
    deadline = time.time() + timeout
    while messages_received(node, topic) < count:
        if time.time() > deadline:
            raise AssertionError("%s received %d of %d messages of %s within %.0f s" % (
                node, messages_received(node, topic), count, topic, timeout))
        time.sleep(0.002)


def subscribe_by_stamp(topic, msg_type, lock, store, value=lambda msg: msg):
    """Subscribes to `topic`: each message's value(msg) goes to store[header stamp in ns] under
    the threading.Condition `lock`, whose waiters are then woken."""
    def callback(msg):
        with lock:
            store[msg.header.stamp.to_nsec()] = value(msg)
            lock.notify_all()
    return rospy.Subscriber(topic, msg_type, callback, queue_size=1000)


def run_node(node_type, extra_args, timeout=60):
    """Runs a second `node_type` of surgical_sim under a fresh node name (so no private parameter
    is left over from an earlier probe) with `extra_args` (e.g. private params `_name:=value`);
    returns (exit code, combined output)."""
    name = "probe_%s_%s" % (node_type, uuid.uuid4().hex[:8])
    cmd = ["rosrun", "surgical_sim", node_type, "__name:=" + name] + extra_args
    proc = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, timeout=timeout,
                          text=True)
    return proc.returncode, proc.stdout


def start_node(node_type, namespace, extra_args):
    """Starts a second `node_type` of surgical_sim in `namespace` (its topics and services under
    /namespace/...) with `extra_args`; returns the subprocess.Popen (output piped)."""
    cmd = ["rosrun", "surgical_sim", node_type, "__ns:=" + namespace,
           "__name:=" + node_type] + extra_args
    return subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)


def sigint_and_wait(proc, timeout=10.0):
    """Sends SIGINT to `proc` and polls for its exit for at most `timeout` s; returns the time it
    took to exit [s], or None (after killing it) if it did not."""
    start = time.monotonic()
    proc.send_signal(signal.SIGINT)
    try:
        proc.wait(timeout)
    except subprocess.TimeoutExpired:
        proc.kill()
        proc.wait()
        return None
    return time.monotonic() - start


def pose_stamped(x, y, z, frame="world", qw=1.0):
    """geometry_msgs/PoseStamped at (x, y, z) [m] in `frame`, quaternion (qw, 0, 0, 0), stamped now."""
    msg = PoseStamped()
    msg.header.stamp = rospy.Time.now()
    msg.header.frame_id = frame
    msg.pose.position.x, msg.pose.position.y, msg.pose.position.z = x, y, z
    msg.pose.orientation.w = qw
    return msg
