#!/usr/bin/env python3
"""Proves check_layout.py fails on a wrong-way include and on a doc naming a missing file, and
passes on a tree that keeps the rules. Run by CTest (test_layout_check_rejects_wrong_way_includes)."""
import os
import subprocess
import sys
import tempfile

CHECK = os.path.join(os.path.dirname(os.path.abspath(__file__)), "check_layout.py")


def tree(files):
    root = tempfile.mkdtemp(prefix="layout-")
    for path, text in files.items():
        full = os.path.join(root, path)
        os.makedirs(os.path.dirname(full), exist_ok=True)
        with open(full, "w") as fh:
            fh.write(text)
    return root


def run(root):
    p = subprocess.run([sys.executable, CHECK, root], capture_output=True, text=True)
    return p.returncode, p.stdout


GOOD = {
    "core/base/result.hpp": "#pragma once\n",
    "core/robot/robot.hpp": '#include "core/base/result.hpp"\n',
    "hal/net/nic.hpp": '#include "core/base/result.hpp"\n',
    "ecat/master/master.hpp": '#include "hal/net/nic.hpp"\n#include <Eigen/Dense>\n',
    "drivers/joint/joint_bus.hpp": '#include "ecat/master/master.hpp"\n#include "core/robot/robot.hpp"\n',
    "drivers/sim/segment/segment.hpp": '#include "drivers/joint/joint_bus.hpp"\n',
    "core/app/cli/main.cpp": '#include "drivers/sim/segment/segment.hpp"\n',
    "docs/architecture.md": "See `ecat/master/master.hpp`, `core/app/cli/main` and `drivers/sim/`.\n",
}


def main():
    failures = []
    status, out = run(tree(GOOD))
    if status != 0:
        failures.append(f"a tree that keeps the rules failed:\n{out}")
    wrong = [
        ("ecat/master/bad.hpp", '#include "drivers/joint/joint_bus.hpp"\n', "ecat/ may include only"),
        ("ecat/master/bad.hpp", '#include "core/robot/robot.hpp"\n', "ecat/ speaks in slaves"),
        ("core/robot/bad.hpp", '#include "hal/net/nic.hpp"\n', "core/ may include only core/"),
        ("core/robot/bad.hpp", '#include "core/app/cli/cli.hpp"\n', "never includes the program"),
        ("drivers/joint/bad.hpp", '#include "drivers/sim/segment/segment.hpp"\n', "never include the simulator"),
        ("hal/net/bad.hpp", '#include "ecat/master/master.hpp"\n', "hal/ may include only"),
        ("docs/bad.md", "Read `ecat/master/gone.hpp`.\n", "does not exist"),
    ]
    for path, text, expected in wrong:
        files = dict(GOOD)
        files[path] = text
        status, out = run(tree(files))
        if status != 1 or expected not in out:
            failures.append(f"{path} with {text.strip()!r}: exit {status}, expected a finding '{expected}':\n{out}")
    for f in failures:
        print("FAIL:", f)
    print(f"{len(wrong) + 1 - len(failures)} passed, {len(failures)} failed")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
