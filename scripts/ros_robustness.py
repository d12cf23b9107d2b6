#!/usr/bin/python3
"""ROS-side robustness campaign: real-time tool fuzz, service abuse and soak.
Each part starts its own master (roscore on a free port) and the nodes it needs with roslaunch,
writes CSVs into --out and prints one line of counts per outcome. Needs the workspace sourced
(source <workspace>/devel/setup.bash); scripts/robustness and scripts/soak do that.

  ros_robustness.py realtime [--sequences N] [--seconds S] [--rate HZ] [--seed S] [--out DIR]
                             [--max-force N]
  ros_robustness.py services [--seconds S] [--seed S] [--out DIR]
  ros_robustness.py soak [--duration S] [--seed S] [--out DIR]

Outcomes: non_finite = a NaN/Inf in tissue/stats (energy, residual, step_time) or tissue/wrench;
over_bound = |tissue force| above the tool's bound (--max-force, else the scene's
tools[].max_force when present);
limited_but_ok = force at or above max_force with status "ok"; crashes = a node process that
died (roslaunch "process has died") or vanished; hung = a service call still unanswered
--timeout seconds after the part ended. Exit status 0 when no crash, non-finite value,
over-bound force, limited-but-ok step or hung call was seen.
"""
import argparse
import csv
import math
import os
import random
import signal
import socket
import subprocess
import sys
import threading
import time
import xmlrpc.client

import yaml

HERE = os.path.dirname(os.path.abspath(__file__))
# The package root: the checkout (scripts/..), or share/surgical_sim when installed in
# lib/surgical_sim.
PKG_CANDIDATES = (os.path.dirname(HERE), os.path.join(HERE, "..", "..", "share", "surgical_sim"))
PKG = next((p for p in PKG_CANDIDATES if os.path.isdir(os.path.join(p, "config"))),
           PKG_CANDIDATES[0])
PALPATION = os.path.join(PKG, "config", "scenes", "palpation.yaml")
CUTTING = os.path.join(PKG, "config", "scenes", "cutting.yaml")
NAN = float("nan")
INF = float("inf")


def log(msg):
    sys.stderr.write("[ros_robustness] %s\n" % msg)
    sys.stderr.flush()


def finite(*values):
    return all(math.isfinite(v) for v in values)


# ------------------------------------------------------------------------------------------
# Master and launch files
# ------------------------------------------------------------------------------------------
class RosGraph:
    """A private roscore on a free port plus roslaunch processes; every process group is ended
    on close(). Output of each launch goes to <out>/<name>.log."""

    def __init__(self, out):
        self.out = out
        sock = socket.socket()
        sock.bind(("localhost", 0))
        self.port = sock.getsockname()[1]
        sock.close()
        self.uri = "http://localhost:%d" % self.port
        os.environ["ROS_MASTER_URI"] = self.uri
        os.environ["ROS_HOME"] = os.path.join(out, "ros_home")
        self.procs = []
        self.launch_logs = []
        self._spawn(["roscore", "-p", str(self.port)], "roscore")
        master = xmlrpc.client.ServerProxy(self.uri)
        deadline = time.time() + 30
        while True:
            try:
                master.getSystemState("/ros_robustness")
                break
            except (OSError, xmlrpc.client.Fault):
                if time.time() > deadline:
                    raise RuntimeError("roscore on port %d did not start" % self.port)
                time.sleep(0.2)

    def _spawn(self, cmd, name):
        path = os.path.join(self.out, name + ".log")
        f = open(path, "w")
        proc = subprocess.Popen(cmd, stdout=f, stderr=subprocess.STDOUT, start_new_session=True)
        self.procs.append((proc, f))
        return path

    def launch(self, launch_file, **args):
        cmd = ["roslaunch", "-p", str(self.port), "surgical_sim", launch_file]
        cmd += ["%s:=%s" % kv for kv in args.items()]
        self.launch_logs.append(self._spawn(cmd, launch_file.replace(".launch", "")))

    def run(self, cmd, name):
        self._spawn(cmd, name)

    def node_pid(self, node, timeout=60.0):
        """PID of a running node (by its name), waiting for it to register."""
        master = xmlrpc.client.ServerProxy(self.uri)
        deadline = time.time() + timeout
        while time.time() < deadline:
            try:
                code, _, api = master.lookupNode("/ros_robustness", node)
                if code == 1:
                    code, _, pid = xmlrpc.client.ServerProxy(api).getPid("/ros_robustness")
                    if code == 1:
                        return pid
            except OSError:
                pass
            time.sleep(0.2)
        raise RuntimeError("node %s did not come up (see %s)" % (node, self.out))

    def crashes(self):
        """Lines of the launch logs that report a node process that died."""
        lines = []
        for path in self.launch_logs:
            with open(path, errors="replace") as f:
                lines += [l.strip() for l in f if "has died" in l]
        return lines

    def close(self):
        for proc, _ in reversed(self.procs):
            if proc.poll() is None:
                os.killpg(proc.pid, signal.SIGINT)
        for proc, f in reversed(self.procs):
            try:
                proc.wait(timeout=20)
            except subprocess.TimeoutExpired:
                os.killpg(proc.pid, signal.SIGKILL)
                proc.wait()
            f.close()


def alive(pid):
    try:
        with open("/proc/%d/stat" % pid) as f:
            return f.read().split()[2] != "Z"
    except OSError:
        return False


# ------------------------------------------------------------------------------------------
# Tool motion (same semantics as core::runToolFuzzSequence, in the world frame)
# ------------------------------------------------------------------------------------------
def body_box(mesh, position):
    """(lo, hi) [m] around a generated body mesh (box/beam from its min corner, organ_blob
    around 0) placed at position, rotation-safe: its centre +- its half diagonal."""
    size = mesh.get("size", [0.075, 0.05, 0.024])
    if mesh.get("generator") in ("box", "beam"):
        centre = [mesh.get("origin", [0.0, 0.0, 0.0])[k] + 0.5 * size[k] for k in range(3)]
        radius = 0.5 * math.sqrt(sum(v * v for v in size))
    elif mesh.get("generator") == "organ_blob":
        centre, radius = [0.0, 0.0, 0.0], max(size)
    else:
        raise SystemExit("ros_robustness: mesh generator %r: no bounding box known (box, beam, "
                         "organ_blob)" % mesh.get("generator"))
    return ([position[k] + centre[k] - radius for k in range(3)],
            [position[k] + centre[k] + radius for k in range(3)])


def scene_info(path):
    """(tissue box (lo, hi) in world [m], tool specs) of an organ_blob/box scene or of a
    multi-body scene (the box around all bodies)."""
    with open(path) as f:
        scene = yaml.safe_load(f)
    origin = scene.get("tissue_pose", {}).get("position", [0.0, 0.0, 0.0])
    if "bodies" not in scene:
        semi = scene["mesh"].get("size", [0.075, 0.05, 0.024])
        lo = [origin[k] - semi[k] for k in range(3)]
        hi = [origin[k] + semi[k] for k in range(3)]
        return (lo, hi), scene.get("tools", [])
    boxes = []
    for body in scene["bodies"]:
        position = body.get("pose", {}).get("position", [0.0, 0.0, 0.0])
        boxes.append(body_box(body["mesh"], [origin[k] + position[k] for k in range(3)]))
    lo = [min(b[0][k] for b in boxes) for k in range(3)]
    hi = [max(b[1][k] for b in boxes) for k in range(3)]
    return (lo, hi), scene.get("tools", [])


def random_quaternion(rng):
    while True:
        q = [rng.gauss(0.0, 1.0) for _ in range(4)]
        n = math.sqrt(sum(c * c for c in q))
        if n > 1e-6:
            return [c / n for c in q]


class ToolMotion:
    """Random motion segments: wander within `reach` of the tissue box, press into the body, dive
    through it below its lowest point (speeds up to max_speed, biased low), hold, teleport
    `teleport` m away and back."""

    def __init__(self, rng, box, reach=0.1, max_speed=2.0, teleport=1.0):
        self.rng, self.box, self.reach = rng, box, reach
        self.max_speed, self.teleport = max_speed, teleport
        lo, hi = box
        self.p = [rng.uniform(lo[0], hi[0]), rng.uniform(lo[1], hi[1]),
                  rng.uniform(hi[2], hi[2] + reach)]
        self.q = random_quaternion(rng)
        self.hold = 0
        self.back = None
        self.teleports = 0
        self._segment()

    def _segment(self):
        rng, (lo, hi), r = self.rng, self.box, self.reach
        self.speed = self.max_speed * max(0.005, rng.random() ** 3)  # median max_speed / 8
        self.q = random_quaternion(rng)
        kind = rng.random()
        if kind < 0.3:
            self.target = [rng.uniform(lo[k] - r, hi[k] + r) for k in range(3)]
        elif kind < 0.55:
            self.target = [rng.uniform(lo[k], hi[k]) for k in range(3)]
        elif kind < 0.75:
            self.target = [rng.uniform(lo[0], hi[0]), rng.uniform(lo[1], hi[1]),
                           rng.uniform(lo[2] - r, lo[2])]
        elif kind < 0.9:
            self.target = list(self.p)
            self.hold = rng.randint(1, 50)
        else:
            d = random_quaternion(rng)[:3]
            n = math.sqrt(sum(c * c for c in d)) or 1.0
            self.back = list(self.p)
            self.p = [self.p[k] + self.teleport * d[k] / n for k in range(3)]
            self.target = list(self.p)
            self.hold = rng.randint(1, 20)
            self.teleports += 1

    def advance(self, dt):
        if self.hold > 0:
            self.hold -= 1
            if self.hold == 0 and self.back is not None:
                self.p, self.back = self.back, None
                self._segment()
            return
        d = [self.target[k] - self.p[k] for k in range(3)]
        n = math.sqrt(sum(c * c for c in d))
        step = self.speed * dt
        if n > step:
            self.p = [self.p[k] + d[k] * step / n for k in range(3)]
        else:
            self.p = list(self.target)
            self._segment()


def pose_msg(p, q, frame="world"):
    from geometry_msgs.msg import PoseStamped
    import rospy
    msg = PoseStamped()
    msg.header.stamp = rospy.Time.now()
    msg.header.frame_id = frame
    msg.pose.position.x, msg.pose.position.y, msg.pose.position.z = p
    msg.pose.orientation.w, msg.pose.orientation.x, msg.pose.orientation.y, \
        msg.pose.orientation.z = q
    return msg


def malformed_pose(rng, motion):
    """(kind, PoseStamped) of a pose the node must reject."""
    kind = rng.choice(["nan", "inf", "zero_quaternion", "unknown_frame", "far"])
    p, q, frame = list(motion.p), list(motion.q), "world"
    if kind == "nan":
        p[rng.randrange(3)] = NAN
    elif kind == "inf":
        q[rng.randrange(4)] = INF
    elif kind == "zero_quaternion":
        q = [0.0, 0.0, 0.0, 0.0]
    elif kind == "unknown_frame":
        frame = "no_such_frame_%d" % rng.randrange(1000)
    else:
        p = [1e3 * rng.uniform(1.0, 1e3), 0.0, 0.0]
    return kind, pose_msg(p, q, frame)


class TissueRecorder:
    """Collects tissue/stats and tissue/wrench of the running simulator, paired by stamp."""

    def __init__(self, bound):
        import rospy
        from geometry_msgs.msg import WrenchStamped
        from surgical_sim.msg import TissueStats
        self.bound = bound
        self.lock = threading.Lock()
        self.reset()
        self.subs = [rospy.Subscriber("tissue/stats", TissueStats, self._stats, queue_size=2000),
                     rospy.Subscriber("tissue/wrench", WrenchStamped, self._wrench,
                                      queue_size=2000)]

    def reset(self):
        with getattr(self, "lock", threading.Lock()):
            self.steps = 0
            self.statuses = {}
            self.non_finite = 0
            self.max_force = 0.0
            self.max_step_ms = 0.0
            self.step_ms_sum = 0.0
            self.status_by_stamp = {}
            self.force_by_stamp = {}
            self.over_bound = 0
            self.limited_but_ok = 0

    def _check_pair(self, stamp):
        if stamp not in self.status_by_stamp or stamp not in self.force_by_stamp:
            return
        status, force = self.status_by_stamp.pop(stamp), self.force_by_stamp.pop(stamp)
        if self.bound is not None:
            self.over_bound += force > self.bound * (1 + 1e-6)
            self.limited_but_ok += force >= self.bound * (1 - 1e-6) and status == "ok"

    def _stats(self, msg):
        with self.lock:
            self.steps += 1
            self.statuses[msg.status] = self.statuses.get(msg.status, 0) + 1
            if not finite(msg.energy, msg.residual, msg.step_time):
                self.non_finite += 1
            else:
                self.max_step_ms = max(self.max_step_ms, 1e3 * msg.step_time)
                self.step_ms_sum += 1e3 * msg.step_time
            stamp = msg.header.stamp.to_nsec()
            self.status_by_stamp[stamp] = msg.status
            self._check_pair(stamp)

    def _wrench(self, msg):
        f = msg.wrench.force
        with self.lock:
            if not finite(f.x, f.y, f.z):
                self.non_finite += 1
                return
            norm = math.sqrt(f.x * f.x + f.y * f.y + f.z * f.z)
            self.max_force = max(self.max_force, norm)
            stamp = msg.header.stamp.to_nsec()
            self.force_by_stamp[stamp] = norm
            self._check_pair(stamp)

    def take(self):
        with self.lock:
            row = {"steps": self.steps, "non_finite": self.non_finite,
                   "max_force_N": round(self.max_force, 6), "over_bound": self.over_bound,
                   "limited_but_ok": self.limited_but_ok,
                   "mean_step_ms": round(self.step_ms_sum / max(1, self.steps), 4),
                   "max_step_ms": round(self.max_step_ms, 4)}
            statuses = dict(self.statuses)
        self.reset()
        return row, statuses


def tool_bound(tools, override):
    """Force bound [N]: --max-force, else the smallest tools[].max_force of the scene, else None."""
    if override:
        return override
    bounds = [t["max_force"] for t in tools if "max_force" in t]
    return min(bounds) if bounds else None


def write_csv(path, rows):
    keys = []
    for r in rows:
        keys += [k for k in r if k not in keys]
    with open(path, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=keys, restval=0)
        w.writeheader()
        w.writerows(rows)
    log("wrote %s" % path)


def print_counts(part, counts):
    print("%-9s " % part + "  ".join("%s=%s" % kv for kv in counts.items()))


# ------------------------------------------------------------------------------------------
# Parts
# ------------------------------------------------------------------------------------------
def publish_fuzz(rng, pub, grasp_pub, motion, seconds, rate, bad_rate, counts):
    """Publishes the motion (and malformed poses, jaw toggles) for `seconds` at `rate` Hz."""
    import rospy
    from std_msgs.msg import Bool
    period = 1.0 / rate
    jaws = False
    end = time.time() + seconds
    next_t = time.time()
    while time.time() < end and not rospy.is_shutdown():
        motion.advance(period)
        pub.publish(pose_msg(motion.p, motion.q))
        counts["poses"] += 1
        if rng.random() < bad_rate:
            kind, msg = malformed_pose(rng, motion)
            pub.publish(msg)
            counts["malformed_" + kind] = counts.get("malformed_" + kind, 0) + 1
        if grasp_pub is not None and rng.random() < 0.01:
            jaws = not jaws
            grasp_pub.publish(Bool(data=jaws))
            counts["grasp_toggles"] += 1
        next_t += period
        time.sleep(max(0.0, next_t - time.time()))


def part_realtime(args):
    graph = RosGraph(args.out)
    try:
        graph.launch("tissue.launch", scene=args.scene, realtime="true")
        pid = graph.node_pid("/tissue_simulator")
        import rospy
        from geometry_msgs.msg import PoseStamped
        from std_msgs.msg import Bool
        from std_srvs.srv import Empty
        rospy.init_node("ros_robustness", anonymous=True, disable_signals=True)
        box, tools = scene_info(args.scene)
        recorder = TissueRecorder(tool_bound(tools, args.max_force))
        pub = rospy.Publisher(tools[0].get("pose_topic", "tool/pose"), PoseStamped, queue_size=100)
        grasp = tools[0].get("grasp")
        grasp_topic = grasp.get("topic", "tool/grasp") if isinstance(grasp, dict) else None
        grasp_pub = rospy.Publisher(grasp_topic, Bool, queue_size=10) if grasp_topic else None
        rospy.wait_for_service("tissue/reset", timeout=60)
        reset = rospy.ServiceProxy("tissue/reset", Empty)
        time.sleep(1.0)
        rows, total = [], {}
        for s in range(args.sequences):
            rng = random.Random(args.seed + s)
            reset()
            recorder.take()
            counts = {"poses": 0, "grasp_toggles": 0}
            motion = ToolMotion(rng, box)
            publish_fuzz(rng, pub, grasp_pub, motion, args.seconds, args.rate, 0.02, counts)
            time.sleep(0.3)
            row, statuses = recorder.take()
            row = dict({"sequence": s, "seed": args.seed + s}, **row)
            row.update(counts)
            row["teleports"] = motion.teleports
            row["node_alive"] = int(alive(pid))
            row.update({"status_" + k: v for k, v in statuses.items()})
            rows.append(row)
            log("sequence %d: %s" % (s, row))
            for k, v in row.items():
                if k in ("sequence", "seed", "node_alive"):
                    continue
                total[k] = max(total.get(k, 0), v) if k.startswith("max_") or k == "mean_step_ms" \
                    else total.get(k, 0) + v
            if not row["node_alive"]:
                break
        crashes = len(graph.crashes()) + (0 if alive(pid) else 1)
        write_csv(os.path.join(args.out, "realtime_tool_fuzz.csv"), rows)
        total["sequences"] = len(rows)
        total["crashes"] = min(crashes, 1) if crashes else 0
        print_counts("realtime", total)
        return 0 if (total["crashes"] == 0 and total.get("non_finite", 0) == 0 and
                     total.get("over_bound", 0) == 0 and total.get("limited_but_ok", 0) == 0) else 1
    finally:
        graph.close()


def abuse_requests(rng):
    """{service: (srv type, request factory)} of garbage, huge and valid requests."""
    from geometry_msgs.msg import Point
    from std_srvs.srv import Empty, EmptyRequest, SetBool, SetBoolRequest
    from surgical_sim.srv import (SetBlade, SetBladeRequest, SetTarget, SetTargetRequest,
                                  SetTrocarLimits, SetTrocarLimitsRequest, StepTissue,
                                  StepTissueRequest)

    def garbage():
        return rng.choice([NAN, INF, -INF, 1e300, -1e300, 0.0, rng.uniform(-2, 2)])

    def blade():
        n = rng.choice([0, 1, 2, 3, 10000])
        pts = [Point(garbage(), garbage(), garbage()) for _ in range(n)]
        if rng.random() < 0.3:
            pts = [Point(0, 0, 0), Point(0, 0, -0.07)]
        return SetBladeRequest(points=pts)

    def limits():
        return SetTrocarLimitsRequest(pitch_limit_deg=rng.choice([NAN, INF, -1.0, 1e9, 30.0, 70.0]),
                                      yaw_limit_deg=rng.choice([NAN, -INF, -5.0, 1e9, 45.0]))

    def target():
        req = SetTargetRequest()
        req.target.header.frame_id = rng.choice(["", "", "robot_base", "no_such_frame"])
        req.target.point = rng.choice([Point(NAN, 0, 0), Point(10.0, 10.0, 10.0),
                                       Point(1e300, 0, 0), Point(0.0, 0.05, 0.25),
                                       Point(0.02, 0.0, 0.2)])
        req.tolerance = rng.choice([0.0, 0.0, NAN, -1.0, 1e-12, 1e9])
        req.max_iterations = rng.choice([0, 1, 30, 100000, 4294967295])
        return req

    return {
        "tissue/step": (StepTissue, lambda: StepTissueRequest(
            steps=rng.choice([0, 1, 10, 1000, 10000, 10001, 4294967295]))),
        "tissue/pause": (SetBool, lambda: SetBoolRequest(data=rng.random() < 0.7)),
        "tissue/reset": (Empty, EmptyRequest),
        "cutting/set_blade": (SetBlade, blade),
        "trocar/set_limits": (SetTrocarLimits, limits),
        "continuum_robot/set_target": (SetTarget, target),
    }


def classify(resp):
    """"accepted" or "rejected" from a response's success / accepted flag or its status
    (set_target: invalid_target, unknown_frame and invalid_request are refusals)."""
    for flag in ("success", "accepted"):
        if hasattr(resp, flag):
            return "accepted" if getattr(resp, flag) else "rejected"
    status = getattr(resp, "status", "")
    return "rejected" if status.startswith("invalid") or status == "unknown_frame" else "accepted"


def describe(resp):
    for field in ("status", "message"):
        if hasattr(resp, field) and getattr(resp, field):
            return str(getattr(resp, field))[:80]
    return "ok"


def part_services(args):
    graph = RosGraph(args.out)
    try:
        graph.launch("cutting.launch", realtime="true")
        graph.launch("trocar.launch")
        graph.launch("continuum_robot.launch")
        nodes = ["/tissue_simulator", "/cutting_tool", "/trocar_device",
                 "/continuum_robot_controller"]
        pids = {n: graph.node_pid(n) for n in nodes}
        import rospy
        rospy.init_node("ros_robustness", anonymous=True, disable_signals=True)
        rng = random.Random(args.seed)
        services = abuse_requests(rng)
        for name in services:
            rospy.wait_for_service(name, timeout=60)
        calls, lock, pending = [], threading.Lock(), {}
        end = time.time() + args.seconds

        def hammer(name, srv_type, make):
            proxy = rospy.ServiceProxy(name, srv_type)
            while time.time() < end:
                with lock:
                    req = make()
                key = (name, threading.get_ident())
                t0 = time.time()
                pending[key] = t0
                try:
                    resp = proxy(req)
                    outcome = (classify(resp), describe(resp))
                except (rospy.ServiceException, rospy.ROSException) as e:
                    outcome = ("error", str(e)[:80])
                pending.pop(key, None)
                with lock:
                    calls.append({"service": name, "t": round(t0 - end + args.seconds, 3),
                                  "latency_ms": round(1e3 * (time.time() - t0), 3),
                                  "outcome": outcome[0], "detail": outcome[1],
                                  "request": " ".join(str(req).split())[:160]})

        threads = [threading.Thread(target=hammer, args=(n, t, m), daemon=True)
                   for n, (t, m) in services.items() for _ in range(2)]
        for t in threads:
            t.start()
        deadline = end + args.timeout
        for t in threads:
            t.join(timeout=max(0.0, deadline - time.time()))
        hung = [k[0] for k in pending]
        write_csv(os.path.join(args.out, "service_abuse.csv"), calls)
        summary = []
        for name in services:
            lat = sorted(c["latency_ms"] for c in calls if c["service"] == name)
            outs = [c["outcome"] for c in calls if c["service"] == name]
            row = {"service": name, "calls": len(lat), "accepted": outs.count("accepted"),
                   "rejected": outs.count("rejected"), "errors": outs.count("error"),
                   "hung": hung.count(name),
                   "p50_ms": lat[len(lat) // 2] if lat else 0,
                   "p99_ms": lat[min(len(lat) - 1, int(0.99 * len(lat)))] if lat else 0,
                   "max_ms": lat[-1] if lat else 0}
            summary.append(row)
            log("%s" % row)
        write_csv(os.path.join(args.out, "service_abuse_summary.csv"), summary)
        dead = [n for n, p in pids.items() if not alive(p)]
        crashes = graph.crashes()
        total = {"calls": len(calls), "accepted": sum(r["accepted"] for r in summary),
                 "rejected": sum(r["rejected"] for r in summary),
                 "errors": sum(r["errors"] for r in summary), "hung": len(hung),
                 "max_latency_ms": max((r["max_ms"] for r in summary), default=0),
                 "crashes": len(set(dead)) + (0 if dead else min(1, len(crashes)))}
        for line in crashes:
            log("crash: " + line)
        print_counts("services", total)
        return 0 if total["crashes"] == 0 and total["hung"] == 0 else 1
    finally:
        graph.close()


def rss_kb(pid):
    with open("/proc/%d/status" % pid) as f:
        for line in f:
            if line.startswith("VmRSS:"):
                return int(line.split()[1])
    return 0


def part_soak(args):
    graph = RosGraph(args.out)
    try:
        graph.launch("tissue.launch", scene=args.scene, realtime="true")
        pid = graph.node_pid("/tissue_simulator")
        bag = os.path.join(PKG, "test", "data", "palpation.bag")
        if not os.path.exists(bag):
            subprocess.run(["/usr/bin/python3", os.path.join(HERE, "make_bags")], check=True)
        graph.run(["rosbag", "play", "--loop", "--quiet", bag], "rosbag_play")
        import rospy
        from geometry_msgs.msg import PoseStamped
        rospy.init_node("ros_robustness", anonymous=True, disable_signals=True)
        box, tools = scene_info(args.scene)
        recorder = TissueRecorder(tool_bound(tools, args.max_force))
        pub = rospy.Publisher(tools[0].get("pose_topic", "tool/pose"), PoseStamped, queue_size=100)
        rng = random.Random(args.seed)
        samples, start = [], time.time()
        counts = {"poses": 0, "grasp_toggles": 0}
        # Every 30 s: 20 s of the bag alone, then 10 s of random motion published alongside it.
        while time.time() - start < args.duration and alive(pid):
            t = time.time() - start
            if int(t) % 30 >= 20:
                publish_fuzz(rng, pub, None, ToolMotion(rng, box), min(10.0, args.duration - t),
                             100.0, 0.02, counts)
            else:
                time.sleep(min(10.0 - (t % 10.0), args.duration - t))
            row, statuses = recorder.take()
            sample = {"t_s": round(time.time() - start, 1),
                      "rss_kb": rss_kb(pid) if alive(pid) else 0}
            sample.update(row)
            sample.update({"status_" + k: v for k, v in statuses.items()})
            samples.append(sample)
            log("soak %s" % sample)
        write_csv(os.path.join(args.out, "soak.csv"), samples)
        warm = [s for s in samples if s["t_s"] >= args.warmup and s["steps"] > 0]
        n = max(1, len(warm) // 10)
        total = {"duration_s": round(time.time() - start, 1), "samples": len(samples),
                 "non_finite": sum(s["non_finite"] for s in samples),
                 "steps": sum(s["steps"] for s in samples),
                 "over_bound": sum(s["over_bound"] for s in samples),
                 "limited_but_ok": sum(s["limited_but_ok"] for s in samples),
                 "crashes": (0 if alive(pid) else 1) or min(1, len(graph.crashes()))}
        if len(warm) >= 2:
            total["rss_first_kb"] = warm[0]["rss_kb"]
            total["rss_growth_kb"] = warm[-1]["rss_kb"] - warm[0]["rss_kb"]
            first = sum(s["mean_step_ms"] for s in warm[:n]) / n
            last = sum(s["mean_step_ms"] for s in warm[-n:]) / n
            total["step_ms_first10"] = round(first, 4)
            total["step_ms_last10"] = round(last, 4)
            total["step_ms_drift_pct"] = round(100.0 * (last - first) / first, 2) if first else 0
        plot_soak(samples, args.warmup, os.path.join(args.out, "soak.png"))
        print_counts("soak", total)
        return 0 if total["crashes"] == 0 and total["non_finite"] == 0 else 1
    finally:
        graph.close()


def plot_soak(samples, warmup, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    t = [s["t_s"] for s in samples]
    fig, (a, b) = plt.subplots(2, 1, sharex=True, figsize=(8, 6))
    a.plot(t, [s["rss_kb"] / 1024.0 for s in samples], "o-")
    a.set_ylabel("tissue_simulator RSS [MiB]")
    b.plot(t, [s["mean_step_ms"] for s in samples], "o-", label="mean")
    b.plot(t, [s["max_step_ms"] for s in samples], "x--", label="max")
    b.set_ylabel("step time per 10 s window [ms]")
    b.set_xlabel("wall time [s]")
    b.legend()
    for ax in (a, b):
        ax.axvline(warmup, color="grey", lw=0.8)
        ax.grid(True, alpha=0.3)
    fig.suptitle("soak: palpation scene, realtime, bag loop + random tool motion")
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    log("wrote %s" % path)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("part", choices=["realtime", "services", "soak"])
    parser.add_argument("--out", default=os.path.join(PKG, "report", "robustness"))
    parser.add_argument("--scene", default=PALPATION)
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--max-force", type=float, default=None,
                        help="realtime, soak: force bound [N] (default: the scene's max_force)")
    parser.add_argument("--sequences", type=int, default=5, help="realtime: sequences")
    parser.add_argument("--seconds", type=float, default=10.0,
                        help="realtime: seconds per sequence; services: abuse duration")
    parser.add_argument("--rate", type=float, default=150.0, help="realtime: pose rate [Hz]")
    parser.add_argument("--timeout", type=float, default=30.0,
                        help="services: wait for in-flight calls after the end [s]")
    parser.add_argument("--duration", type=float, default=3600.0, help="soak: seconds")
    parser.add_argument("--warmup", type=float, default=60.0, help="soak: warm-up [s]")
    args = parser.parse_args()
    args.out = os.path.abspath(args.out)
    os.makedirs(args.out, exist_ok=True)
    part = {"realtime": part_realtime, "services": part_services, "soak": part_soak}[args.part]
    sys.exit(part(args))


if __name__ == "__main__":
    main()
