#!/usr/bin/env python3
"""Layout checks (docs/architecture.md): include directions between folders, and docs that name
only files that exist.

  check_layout.py [SOURCE_DIR]          both checks; exit 1 and one line per finding when one fails
  check_layout.py --rules               print the allowed include directions (docs/architecture.md)

Include rule: a file in folder A may include a file in folder B only when B is in A's allowed list.
The most specific folder wins (core/app/ is not core/). Rules are read from top to bottom.
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
    ("ecat/", ["core/", "hal/", "ecat/"]),
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

SOURCE_FOLDERS = ("core/", "hal/", "ecat/", "fsm/", "drivers/")
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

    findings = include_findings(files, read) + doc_findings(files, read, exists)
    for f in findings:
        print(f)
    print(f"check_layout: {len(findings)} findings over {len(files)} files")
    return 1 if findings else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
