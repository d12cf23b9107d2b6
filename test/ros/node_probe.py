"""Shared by the rostests that check start-up rejection: runs a node once, outside the launch."""
import subprocess
import uuid


def run_node(node_type, extra_args, timeout=60):
    """Runs a second `node_type` of surgical_sim under a fresh node name (so no private parameter
    is left over from an earlier probe) with `extra_args` (e.g. private params `_name:=value`);
    returns (exit code, combined output)."""
    name = "probe_%s_%s" % (node_type, uuid.uuid4().hex[:8])
    cmd = ["rosrun", "surgical_sim", node_type, "__name:=" + name] + extra_args
    proc = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, timeout=timeout,
                          text=True)
    return proc.returncode, proc.stdout
