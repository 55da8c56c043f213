#!/usr/bin/env python3
"""Issue 22 closing figures (not run in CI; root; run it under `flock /tmp/rescue-serial.lock`):
online recovery of `rescue-motion run --nic raw:` against `rescue-motion sim --iface` over a veth
pair between two network namespaces, the faults typed into the simulator's fault console.

Cases (each in a run of its own):
  power     each of the 21 drives switched off for OFF_MS and on again, in turn
  branches  each branch cut at its first drive for OFF_MS and restored, in turn
  random    fixed-seed random schedules of SECONDS s of overlapping faults: cuts, restores,
            power-offs, power-ons of drives and SAFE-OP drops (`safe-op DRIVE 0x001A`), at most
            3 faults at once, every fault cleared at the end

Per case it prints: faults injected, losses reported, false losses (a joint reported lost or not
operational while no fault held it), missed losses (a joint a fault held for 100 ms or more, never
reported), recoveries (joints reported `recovered`), slow (every recovery that took longer than a
hold-off would explain: NORMAL_S after the joint returned, plus what was left then of the hold-off
of a `recovery failed` line the master printed before the return; a failure after the return
explains nothing: a returned, healthy drive must not fail), stuck (a joint that became reachable
again and was not recovered within STUCK_S by the end of the run), and the time from each restore (power-on, restore, or the drop) to
the `recovered` line of each returned joint: median and max. Times are the campaign's monotonic
clock at the command and at the run's log line (line-buffered): a few ms of logging latency included.

usage: toolchain/veth-recovery-campaign.py BINARY [--cases power,branches,random] [--seeds 1,2,3,4,5]
                                           [--seconds 60] [--off-ms 500] [--prefix rcv]
  docs/master.md figures: flock /tmp/rescue-serial.lock toolchain/veth-recovery-campaign.py build/release/rescue-motion
Exit status: 0 when every case had 0 false, 0 missed, 0 slow and 0 stuck, 1 otherwise, 2 on a set-up error.
"""
import argparse
import os
import queue
import random
import re
import shutil
import statistics
import subprocess
import sys
import tempfile
import threading
import time

# The robot (core/robot/robot.hpp kSlaves): name -> upstream slave name (None: the master).
SLAVES = [
    ("junction_a", None), ("junction_b", "junction_a"),
    ("r_shoulder_pitch", "junction_b"), ("r_shoulder_roll", "r_shoulder_pitch"), ("r_shoulder_yaw", "r_shoulder_roll"),
    ("r_elbow", "r_shoulder_yaw"), ("r_wrist_yaw", "r_elbow"), ("r_wrist_pitch", "r_wrist_yaw"), ("r_hand", "r_wrist_pitch"),
    ("l_leg", "junction_b"), ("r_leg", "l_leg"), ("l_track", "r_leg"), ("r_track", "l_track"),
    ("waist_yaw", "junction_a"), ("neck_pan", "waist_yaw"), ("neck_tilt", "neck_pan"),
    ("l_shoulder_pitch", "junction_a"), ("l_shoulder_roll", "l_shoulder_pitch"), ("l_shoulder_yaw", "l_shoulder_roll"),
    ("l_elbow", "l_shoulder_yaw"), ("l_wrist_yaw", "l_elbow"), ("l_wrist_pitch", "l_wrist_yaw"), ("l_hand", "l_wrist_pitch"),
]
UPSTREAM = dict(SLAVES)
DRIVES = [n for n, _ in SLAVES if not n.startswith("junction")]
BRANCH_HEADS = ["r_shoulder_pitch", "l_leg", "waist_yaw", "l_shoulder_pitch"]
MISS_MIN_S = 0.1  # a fault held this long must be reported
STUCK_S = 5.0
NORMAL_S = 0.5  # a returned drive is back in OP within this (median 73-83 ms over veth), no hold-off
LINE = re.compile(r"link (lost|not operational|recovered): ([a-z_,]+)")
FAILED = re.compile(r"recovery failed: ([a-z_,]+) \(in (\w+), attempt (\d+) in a row\), trying again from the start in (\d+) ms")


def path_to_master(name):
    while name is not None:
        yield name
        name = UPSTREAM[name]


class Fault:
    """What holds each joint down now: cuts and power-offs (by their slave), SAFE-OP drops."""

    def __init__(self):
        self.cut, self.off, self.dropped = set(), set(), set()

    def down(self):
        held = set()
        for d in DRIVES:
            if d in self.dropped or any(s in self.cut or s in self.off for s in path_to_master(d)):
                held.add(d)
        return held


class Run:
    def __init__(self, args, work, sim, name, duration):
        self.args, self.sim, self.name = args, sim, name
        state = os.path.join(work, "state-" + name)
        os.makedirs(state, exist_ok=True)
        self.log = open(os.path.join(work, "run-" + name + ".log"), "w")
        self.proc = subprocess.Popen(["ip", "netns", "exec", args.prefix + "-m", args.binary, "run", "--nic", "raw:ecm0",
                                      "--duration", str(duration), "--state-dir", state],
                                     stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, bufsize=1)
        self.lines = queue.Queue()
        self.events = []  # (time, kind, joints)
        self.reader = threading.Thread(target=self.read, daemon=True)
        self.reader.start()
        self.faults = Fault()
        self.injected = 0
        self.down_since = {}        # joint -> time it went down (by the schedule)
        self.reachable_since = {}   # joint -> time it became reachable again
        self.false_losses = 0
        self.missed = 0
        self.recovery_times = []
        self.stuck = 0
        self.slow = 0
        self.hold_off_until = {}    # joint -> end of the hold-off of its last `recovery failed` line
        self.failed_since_return = {}  # joint -> the states its recovery failed in since it returned
        self.recovered = 0
        self.losses = 0
        self.reported_down = set()  # reported lost/not operational, not yet recovered

    def read(self):
        for line in self.proc.stdout:
            t = time.monotonic()
            self.log.write("%.4f %s" % (t, line))
            self.lines.put((t, line))
        self.lines.put((time.monotonic(), None))

    def wait_for(self, text, timeout):
        end = time.monotonic() + timeout
        while time.monotonic() < end:
            try:
                t, line = self.lines.get(timeout=0.05)
            except queue.Empty:
                continue
            if line is None:
                return False
            self.take(t, line)
            if text in line:
                return True
        return False

    def take(self, t, line):
        f = FAILED.search(line)
        if f:
            for j in f.group(1).split(","):
                if j in self.reachable_since:  # after its return: explains nothing
                    self.failed_since_return.setdefault(j, []).append(f.group(2))
                else:
                    self.hold_off_until[j] = t + int(f.group(4)) / 1000
            return
        m = LINE.search(line)
        if not m:
            return
        kind, joints = m.group(1), set(m.group(2).split(","))
        held = self.faults.down()
        if kind in ("lost", "not operational"):
            self.losses += len(joints)
            for j in joints:
                # False: nothing holds it now, and nothing released it in the last 50 ms.
                if j not in held and t - self.reachable_since.get(j, -1e9) > 0.05:
                    self.false_losses += 1
                    print("  false loss: %s %s at %.3f" % (kind, j, t - self.t0))
            self.reported_down |= joints
        else:
            self.recovered += len(joints)
            for j in joints:
                if j in self.reachable_since:
                    returned = self.reachable_since.pop(j)
                    self.recovery_times.append(t - returned)
                    # What a hold-off running at the return explains, and the normal recovery after it.
                    explained = max(0.0, self.hold_off_until.get(j, 0.0) - returned) + NORMAL_S
                    failures = self.failed_since_return.pop(j, [])
                    if t - returned > explained:
                        self.slow += 1
                        print("  slow: %s recovered %.2f s after it returned at %.3f s (%.2f s explained by a hold-off); "
                              "failed since the return in: %s" % (j, t - returned, returned - self.t0, explained,
                                                                   ", ".join(failures) if failures else "none"))
            self.reported_down -= joints

    def pump(self, until):
        while True:
            left = until - time.monotonic()
            if left <= 0:
                return
            try:
                t, line = self.lines.get(timeout=min(left, 0.05))
            except queue.Empty:
                continue
            if line is not None:
                self.take(t, line)

    def inject(self, command):
        before = self.faults.down()
        verb, slave = command.split()[0], command.split()[1]
        {"cut": self.faults.cut.add, "restore": self.faults.cut.discard, "power-off": self.faults.off.add,
         "power-on": self.faults.off.discard, "safe-op": self.faults.dropped.add}[verb](slave)
        t = time.monotonic()
        self.sim.stdin.write(command + "\n")
        self.sim.stdin.flush()
        self.injected += 1
        after = self.faults.down()
        for j in after - before:
            # A joint that returned and is not recovered yet (or is still reported down) is out of
            # the master's exchange already: nothing new to report for it.
            if j not in self.reachable_since and j not in self.reported_down:
                self.down_since[j] = t
            self.reachable_since.pop(j, None)
            self.failed_since_return.pop(j, None)
        for j in before - after:
            self.release(j, t)
        if verb == "safe-op":
            # The drive stays reachable: the master takes it back (not operational, then recovered).
            self.faults.dropped.discard(slave)
            self.release(slave, t)
            self.down_since[slave] = t - MISS_MIN_S  # must be reported

    def release(self, j, t):
        since = self.down_since.pop(j, None)
        self.reachable_since[j] = t
        if since is not None:
            self.pending_check.append((j, since, t))

    def finish(self):
        # Every returned joint must be recovered within STUCK_S of its return.
        self.pump(time.monotonic() + STUCK_S)
        self.stuck = len(self.reachable_since)
        for j in self.reachable_since:
            print("  stuck: %s not recovered %.1f s after it returned" % (j, time.monotonic() - self.reachable_since[j]))
        self.proc.wait(timeout=120)
        self.reader.join(timeout=5)
        while not self.lines.empty():
            t, line = self.lines.get()
            if line is not None:
                self.take(t, line)
        self.log.close()


def summary(run):
    times = sorted(run.recovery_times)
    med = "%.0f" % (statistics.median(times) * 1000) if times else "-"
    mx = "%.0f" % (max(times) * 1000) if times else "-"
    print("%-14s faults %3d, losses reported %3d, false %d, missed %d, recoveries %3d, slow %d, stuck %d, "
          "restore to OP median %s ms, max %s ms (%d returns), exit %s" %
          (run.name, run.injected, run.losses, run.false_losses, run.missed, run.recovered, run.slow, run.stuck, med, mx,
           len(times), run.proc.returncode))
    return run.false_losses == 0 and run.missed == 0 and run.slow == 0 and run.stuck == 0


def start_run(args, work, sim, name, duration):
    run = Run(args, work, sim, name, duration)
    run.pending_check = []
    if not run.wait_for("network in OP", 20):
        print("%s: the run did not reach OP (see %s)" % (name, work))
        run.proc.kill()
        return None
    run.t0 = time.monotonic()
    run.pump(time.monotonic() + 0.5)
    return run


def check_missed(run):
    # A joint held down MISS_MIN_S or more must have been reported (lost or not operational) by the
    # time it returned; the reports are checked against the log afterwards.
    reported = {}
    with open(run.log.name) as f:
        for line in f:
            t = float(line.split(" ", 1)[0])
            m = LINE.search(line)
            if m and m.group(1) != "recovered":
                for j in m.group(2).split(","):
                    reported.setdefault(j, []).append(t)
    for j, since, until in run.pending_check:
        if until - since < MISS_MIN_S:
            continue
        if not any(since - 0.01 <= t <= until + 0.5 for t in reported.get(j, [])):
            run.missed += 1
            print("  missed: %s down %.3f .. %.3f s" % (j, since - run.t0, until - run.t0))


def one_at_a_time(args, work, sim, name, targets, down, up):
    """Each target in turn: `down` it for --off-ms, `up` it again, wait until every joint answers."""
    run = start_run(args, work, sim, name, len(targets) * 4 + 10)
    if run is None:
        return False
    for target in targets:
        run.inject(down + " " + target)
        run.pump(time.monotonic() + args.off_ms / 1000)
        run.inject(up + " " + target)
        end = time.monotonic() + 3
        while time.monotonic() < end and run.reachable_since:
            run.pump(time.monotonic() + 0.05)
        run.pump(time.monotonic() + 0.2)
    run.finish()
    check_missed(run)
    return summary(run)


def case_power(args, work, sim):
    return one_at_a_time(args, work, sim, "power", DRIVES, "power-off", "power-on")


def case_branches(args, work, sim):
    return one_at_a_time(args, work, sim, "branches", BRANCH_HEADS, "cut", "restore")


def schedule(seed, seconds):
    """Fixed-seed overlapping faults: (time offset in s, command)."""
    rng = random.Random(seed)
    t, out, cut, off = 0.5, [], set(), set()
    while t < seconds - 2:
        active = len(cut) + len(off)
        choices = []
        if active < 3:
            choices += ["cut", "power-off", "safe-op"]
        if cut:
            choices += ["restore"] * 2
        if off:
            choices += ["power-on"] * 2
        verb = rng.choice(choices)
        if verb == "cut":
            s = rng.choice([d for d in DRIVES if d not in cut])
            cut.add(s)
        elif verb == "power-off":
            s = rng.choice([d for d in DRIVES if d not in off])
            off.add(s)
        elif verb == "restore":
            s = rng.choice(sorted(cut))
            cut.discard(s)
        elif verb == "power-on":
            s = rng.choice(sorted(off))
            off.discard(s)
        else:
            s = rng.choice(DRIVES)
            verb = "safe-op"
        out.append((t, verb + " " + s + (" 0x001A" if verb == "safe-op" else "")))
        t += rng.uniform(0.15, 2.0)
    for s in sorted(cut):
        out.append((t, "restore " + s))
    for s in sorted(off):
        out.append((t, "power-on " + s))
    return out, t


def case_random(args, work, sim, seed):
    plan, last = schedule(seed, args.seconds)
    run = start_run(args, work, sim, "seed %d" % seed, int(last) + 15)
    if run is None:
        return False
    start = time.monotonic()
    for at, command in plan:
        run.pump(start + at)
        drive = command.split()[1]
        if command.startswith("safe-op") and (drive in run.faults.down() or drive in run.reachable_since or
                                              drive in run.reported_down):
            continue  # not in OP now: the simulator would refuse the drop
        run.inject(command)
    run.finish()
    check_missed(run)
    return summary(run)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("binary")
    ap.add_argument("--cases", default="power,branches,random")
    ap.add_argument("--seeds", default="1,2,3,4,5")
    ap.add_argument("--seconds", type=float, default=60)
    ap.add_argument("--off-ms", type=float, default=500)
    ap.add_argument("--prefix", default="rcv")
    args = ap.parse_args()
    args.binary = os.path.abspath(args.binary)
    m, s = args.prefix + "-m", args.prefix + "-s"
    work = tempfile.mkdtemp(prefix="recovery-campaign-")
    sh = lambda *c: subprocess.run(c, check=True)
    sim = None
    try:
        sh("ip", "netns", "add", m)
        sh("ip", "netns", "add", s)
        sh("ip", "link", "add", "name", "ecm0", "netns", m, "type", "veth", "peer", "name", "ecs0", "netns", s)
        sh("ip", "-n", m, "link", "set", "ecm0", "up")
        sh("ip", "-n", s, "link", "set", "ecs0", "up")
        sim_log = open(os.path.join(work, "sim.log"), "w")
        rt = ["chrt", "-f", "70"] if os.geteuid() == 0 and shutil.which("chrt") else []
        sim = subprocess.Popen(["ip", "netns", "exec", s] + rt + [args.binary, "sim", "--iface", "ecs0"], stdin=subprocess.PIPE,
                               stdout=sim_log, stderr=subprocess.STDOUT, text=True)
        time.sleep(1.5)
        ok = True
        cases = args.cases.split(",")
        if "power" in cases:
            ok = case_power(args, work, sim) and ok
        if "branches" in cases:
            ok = case_branches(args, work, sim) and ok
        if "random" in cases:
            for seed in [int(x) for x in args.seeds.split(",") if x]:
                ok = case_random(args, work, sim, seed) and ok
        print("logs: %s" % work)
        return 0 if ok else 1
    except subprocess.CalledProcessError as e:
        print("set-up failed: %s" % e)
        return 2
    finally:
        if sim is not None:
            sim.terminate()
            sim.wait(timeout=10)
        subprocess.run(["ip", "netns", "del", m], stderr=subprocess.DEVNULL)
        subprocess.run(["ip", "netns", "del", s], stderr=subprocess.DEVNULL)


if __name__ == "__main__":
    sys.exit(main())
