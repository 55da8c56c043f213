#!/usr/bin/env python3
"""Layout checks (docs/architecture.md): include directions between folders, and docs that name
only files that exist.

  check_layout.py [SOURCE_DIR]          both checks; exit 1 and one line per finding when one fails
  check_layout.py --rules               print the allowed include directions (docs/architecture.md)

Include rule: a file in folder A may include a file in folder B only when B is in A's allowed list.
The most specific folder wins (core/app/ is not core/). Rules are read from top to bottom.

Floor rule: inside core/, core/app/, ecat/, hal/, fsm/, drivers/ and drivers/sim/ the folders are floors,
listed bottom first (FLOORS); a file includes only its own folder and the floors below it, never one above.

Knot rule: no two folders anywhere include each other, directly or through any path of includes
(a cycle in the folder graph), whatever the other rules allow.

Ports rule: the tasks' period loops (TASK_LOOPS) reach the shared state only through their ports
(docs/architecture.md "How a task reaches shared state"): no call of the runner's shared_links() or run_control(),
no use of the segment (g_run.segment).
"""
import os
import re
import subprocess
import sys

# (folder, folders it may include). The first folder that is a prefix of a file's path applies.
RULES = [
    ("core/app/", ["core/", "hal/", "ecat/", "fsm/", "drivers/"]),   # the program: everything
    ("core/kinematics/", ["core/base/", "core/containers/", "core/robot/", "core/kinematics/"]),
    ("core/", ["core/"]),                                              # foundation: nothing outside core/
    ("hal/", ["core/", "hal/"]),
    ("ecat/", ["core/", "hal/", "fsm/engine/", "ecat/"]),               # the fsm engine runs ecat's machines
    ("fsm/", ["core/", "fsm/"]),
    ("drivers/sim/", ["core/", "hal/", "ecat/", "fsm/", "drivers/"]),
    ("drivers/", ["core/", "hal/", "ecat/", "fsm/", "drivers/"]),
    ("tests/", None),                                                  # tests may include anything
]
# Never allowed, whatever the rule above says (more specific than a folder's list).
FORBIDDEN = [
    ("core/", "core/app/", "the foundation never includes the program"),
    ("hal/", "core/app/", "the machine layer never includes the program"),
    ("ecat/", "core/app/", "the protocol never includes the program"),
    ("ecat/", "core/robot/", "ecat/ speaks in slaves; the robot's joints are mapped in drivers/joint/"),
    ("fsm/", "core/app/", "state machines never include the program"),
    ("drivers/", "core/app/", "drivers never include the program"),
]
FORBIDDEN_EXCEPT_SIM = ("drivers/", "drivers/sim/", "master-side drivers never include the simulator")

# Floors inside a folder, bottom first: a folder includes only itself and the floors listed before it.
# docs/architecture.md draws them; a new folder must be given its floor here.
FLOORS = {
    "core/": ["base", "containers", "concurrency", "memory", "timing", "robot", "kinematics", "app"],
    "core/app/": ["config", "links", "shm", "operator_protocol", "tasks", "sim", "runtime", "bench", "cli"],
    "ecat/": ["codec", "link", "capture", "sii", "mailbox", "dc", "master"],
    "hal/": ["time", "files", "proc", "rt", "shm", "net"],
    "fsm/": ["engine", "machines"],
    "drivers/": ["cia402", "joint", "sim"],
    "drivers/sim/": ["coe", "devices", "esc", "segment"],
}

SOURCE_FOLDERS = ("core/", "hal/", "ecat/", "fsm/", "drivers/")

# The tasks' period loops, and what in them would reach TaskLinks around the tasks' ports.
TASK_LOOPS = ("core/app/runtime/task_loops.cpp", "core/app/runtime/task_loops.hpp")
AROUND_PORTS = re.compile(r"(?<![\w.>:])(?:shared_links|run_control)\(\)|\bg_run\.segment\b")


def port_findings(files, read):
    findings = []
    for path in files:
        if path not in TASK_LOOPS:
            continue
        for n, line in enumerate(read(path).splitlines(), 1):
            code = line.split("//", 1)[0]
            m = AROUND_PORTS.search(code)
            if m:
                findings.append(f"{path}:{n}: {m.group(0)} reaches the shared state around the task's ports "
                                "(TaskPorts::task_loop, the task's own ports)")
    return findings
INCLUDE = re.compile(r'^\s*#\s*include\s+"([^"]+)"', re.M)


def rule_for(path):
    for folder, allowed in RULES:
        if path.startswith(folder):
            return folder, allowed
    return None, None


def include_findings(files, read):
    findings = []
    for path in files:
        if not path.endswith((".hpp", ".cpp", ".h")):
            continue
        folder, allowed = rule_for(path)
        if folder is None or allowed is None:
            continue
        for n, line in enumerate(read(path).splitlines(), 1):
            m = INCLUDE.match(line)
            if not m:
                continue
            target = m.group(1)
            if not target.startswith(SOURCE_FOLDERS):
                continue  # a system or third-party header (Eigen, gtest), or a generated one
            why = None
            for src, dst, reason in FORBIDDEN:
                if path.startswith(src) and not path.startswith("core/app/") and target.startswith(dst):
                    why = reason
                    break
            src, dst, reason = FORBIDDEN_EXCEPT_SIM
            if why is None and path.startswith(src) and not path.startswith("drivers/sim/") and target.startswith(dst):
                why = reason
            if why is None and not any(target.startswith(a) for a in allowed):
                why = f"{folder} may include only {', '.join(allowed)}"
            if why:
                findings.append(f"{path}:{n}: includes {target}: {why}")
    return findings


def floor_of(path, base):
    """(index, name) of the floor of `base` that holds `path`, or None when path is not inside one."""
    if not path.startswith(base):
        return None
    rest = path[len(base):]
    if "/" not in rest:
        return None  # a file directly in base/ (e.g. a CMakeLists.txt)
    name = rest.split("/", 1)[0]
    floors = FLOORS[base]
    return (floors.index(name), name) if name in floors else (None, name)


def floor_findings(files, read):
    findings = []
    for path in files:
        if not path.endswith((".hpp", ".cpp", ".h")):
            continue
        for n, line in enumerate(read(path).splitlines(), 1):
            m = INCLUDE.match(line)
            if not m:
                continue
            target = m.group(1)
            for base, floors in FLOORS.items():
                src, dst = floor_of(path, base), floor_of(target, base)
                if src is None or dst is None or src[1] == dst[1]:
                    continue
                if src[0] is None:
                    findings.append(f"{path}:{n}: folder {base}{src[1]}/ has no floor: add it to FLOORS in {os.path.basename(__file__)}")
                elif dst[0] is None or dst[0] > src[0]:
                    findings.append(f"{path}:{n}: includes {target}: {base}{dst[1]}/ is above {base}{src[1]}/ "
                                    f"(floors of {base}, bottom first: {' < '.join(floors)})")
    return findings


def knot_findings(files, read):
    """Folders that reach each other through includes (strongly connected components of the folder graph)."""
    edges = {}
    example = {}
    for path in files:
        if not path.endswith((".hpp", ".cpp", ".h")) or not path.startswith(SOURCE_FOLDERS):
            continue
        a = os.path.dirname(path)
        for n, line in enumerate(read(path).splitlines(), 1):
            m = INCLUDE.match(line)
            if not m or not m.group(1).startswith(SOURCE_FOLDERS):
                continue
            b = os.path.dirname(m.group(1))
            if a != b:
                edges.setdefault(a, set()).add(b)
                example.setdefault((a, b), f"{path}:{n}")
    # Tarjan's algorithm, iterative (no recursion limit on a deep graph).
    index, low, on_stack, stack, knots, counter = {}, {}, set(), [], [], [0]
    for start in sorted(edges):
        if start in index:
            continue
        work = [(start, iter(sorted(edges.get(start, ()))))]
        index[start] = low[start] = counter[0]; counter[0] += 1
        stack.append(start); on_stack.add(start)
        while work:
            node, it = work[-1]
            nxt = next(it, None)
            if nxt is not None:
                if nxt not in index:
                    index[nxt] = low[nxt] = counter[0]; counter[0] += 1
                    stack.append(nxt); on_stack.add(nxt)
                    work.append((nxt, iter(sorted(edges.get(nxt, ())))))
                elif nxt in on_stack:
                    low[node] = min(low[node], index[nxt])
                continue
            work.pop()
            if work:
                low[work[-1][0]] = min(low[work[-1][0]], low[node])
            if low[node] == index[node]:
                comp = []
                while True:
                    w = stack.pop(); on_stack.discard(w); comp.append(w)
                    if w == node:
                        break
                if len(comp) > 1:
                    knots.append(sorted(comp))
    findings = []
    for comp in knots:
        inside = [f"{example[(a, b)]} ({a}/ -> {b}/)" for a in comp for b in sorted(edges.get(a, ())) if b in comp]
        findings.append(f"knot: folders {', '.join(c + '/' for c in comp)} include each other: {'; '.join(inside)}")
    return findings


# Paths in prose: folder/name.ext for the project's own kinds of file, or a folder path ending in '/'.
DOC_PATH = re.compile(r"(?<![\w/.-])((?:core|hal|ecat|fsm|drivers|tests|toolchain|docs)/[\w./-]*[\w/])")


# Files the build generates (in <build>/generated/, included by these names): docs may name them.
GENERATED = {"core/robot/robot_description.hpp"}


def doc_findings(files, read, exists):
    findings = []
    for path in files:
        if not (path.endswith(".md") and (path.startswith("docs/") or "/" not in path)):
            continue
        for n, line in enumerate(read(path).splitlines(), 1):
            for m in DOC_PATH.finditer(line):
                ref = m.group(1).rstrip(".")
                if "*" in ref or ref.startswith("build/") or ref in GENERATED:
                    continue
                if not exists(ref):
                    findings.append(f"{path}:{n}: names {ref}, which does not exist")
    return findings


def main(argv):
    if "--rules" in argv:
        for folder, allowed in RULES:
            print(f"{folder:18} -> {'anything' if allowed is None else ' '.join(allowed)}")
        for src, dst, reason in FORBIDDEN + [FORBIDDEN_EXCEPT_SIM]:
            print(f"{src:18} -/-> {dst:14} {reason}")
        for base, floors in FLOORS.items():
            print(f"floors of {base:13} {' < '.join(floors)}")
        print("no knots: no two folders include each other through any path")
        print(f"ports: {' '.join(TASK_LOOPS)} never call shared_links() or run_control() nor use g_run.segment")
        return 0
    root = os.path.abspath(argv[1] if len(argv) > 1 else ".")
    try:
        files = subprocess.check_output(["git", "-C", root, "ls-files", "-co", "--exclude-standard"], text=True).split()
    except (OSError, subprocess.CalledProcessError):
        files = [os.path.relpath(os.path.join(d, f), root) for d, _, fs in os.walk(root) for f in fs]
    files = [f for f in files if os.path.isfile(os.path.join(root, f))]

    def read(p):
        with open(os.path.join(root, p), encoding="utf-8", errors="replace") as fh:
            return fh.read()

    def exists(p):
        # A path names a file or folder; a stem names its .hpp/.cpp pair ("core/app/tasks/joint_manager",
        # "hal/rt/rt_setup.hpp/.cpp"); a prefix ending in '_' names a family ("tests/fuzz/fuzz_").
        p = p.replace(".hpp/.cpp", ".hpp")
        full = os.path.join(root, p)
        if any(os.path.exists(full + ext) for ext in ("", ".hpp", ".cpp", ".py", ".sh")):
            return True
        if p.endswith("_"):
            folder, prefix = os.path.split(full)
            return os.path.isdir(folder) and any(n.startswith(prefix) for n in os.listdir(folder))
        return False

    findings = (include_findings(files, read) + floor_findings(files, read) + knot_findings(files, read)
                + port_findings(files, read) + doc_findings(files, read, exists))
    for f in findings:
        print(f)
    print(f"check_layout: {len(findings)} findings over {len(files)} files")
    return 1 if findings else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
