#!/usr/bin/env python3
"""Proves check_layout.py fails on a wrong-way include (between top folders, between floors inside
core/, core/app/, ecat/, hal/, fsm/, drivers/ and drivers/sim/, a folder with no floor, a knot of
folders), on a task loop reaching the shared state around its ports, and on a doc naming a missing
file, and passes on a tree that keeps the rules. Run by CTest (test_layout_check_rejects_wrong_way_includes)."""
import atexit
import os
import shutil
import subprocess
import sys
import tempfile

CHECK = os.path.join(os.path.dirname(os.path.abspath(__file__)), "check_layout.py")


def tree(files):
    root = tempfile.mkdtemp(prefix="layout-")
    atexit.register(shutil.rmtree, root, True)  # removed when the test ends, pass or fail
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
    "core/app/cli/main.cpp": '#include "drivers/sim/segment/segment.hpp"\n#include "core/app/runtime/firmware.hpp"\n',
    "core/app/config/command_line.hpp": '#include "core/base/result.hpp"\n',
    "core/app/links/task_links.hpp": '#include "core/app/config/command_line.hpp"\n',
    "core/app/tasks/joint_manager.hpp": '#include "core/app/links/task_links.hpp"\n',
    "core/app/runtime/firmware.hpp": '#include "core/app/tasks/joint_manager.hpp"\n',
    "core/containers/fixed_vector.hpp": '#include "core/base/result.hpp"\n',
    "ecat/codec/frame.hpp": '#include "core/base/result.hpp"\n',
    "ecat/link/datagram_link.hpp": '#include "ecat/codec/frame.hpp"\n',
    "ecat/sii/sii_reader.hpp": '#include "ecat/link/datagram_link.hpp"\n',
    "ecat/mailbox/mailbox_client.hpp": '#include "ecat/link/datagram_link.hpp"\n',
    "core/app/runtime/task_loops.cpp": "void run_manager() noexcept { task(g_run.tasks.ports->task_loop(k)); }\n"
                                       "// not shared_links() in a comment\n",
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
        ("core/robot/bad.hpp", '#include "core/app/config/command_line.hpp"\n', "never includes the program"),
        ("drivers/joint/bad.hpp", '#include "drivers/sim/segment/segment.hpp"\n', "never include the simulator"),
        ("hal/net/bad.hpp", '#include "ecat/master/master.hpp"\n', "hal/ may include only"),
        ("docs/bad.md", "Read `ecat/master/gone.hpp`.\n", "does not exist"),
        # Floors: each tree's upper folder included from a lower one.
        ("core/app/config/bad.hpp", '#include "core/app/cli/main.cpp"\n', "core/app/cli/ is above core/app/config/"),
        ("core/app/links/bad.hpp", '#include "core/app/tasks/joint_manager.hpp"\n', "core/app/tasks/ is above core/app/links/"),
        ("core/app/tasks/bad.hpp", '#include "core/app/runtime/firmware.hpp"\n', "core/app/runtime/ is above core/app/tasks/"),
        ("ecat/link/bad.hpp", '#include "ecat/master/master.hpp"\n', "ecat/master/ is above ecat/link/"),
        ("ecat/sii/bad.hpp", '#include "ecat/mailbox/mailbox_client.hpp"\n', "ecat/mailbox/ is above ecat/sii/"),
        ("core/base/bad.hpp", '#include "core/containers/fixed_vector.hpp"\n', "core/containers/ is above core/base/"),
        ("hal/time/bad.hpp", '#include "hal/net/nic.hpp"\n', "hal/net/ is above hal/time/"),
        ("drivers/sim/esc/bad.hpp", '#include "drivers/sim/segment/segment.hpp"\n', "drivers/sim/segment/ is above drivers/sim/esc/"),
        ("core/app/newroom/x.hpp", '#include "core/app/config/command_line.hpp"\n', "core/app/newroom/ has no floor"),
        # A knot: a floor and a folder inside it reaching each other (no floor rule sees it).
        ("core/app/tasks/rc/rc.hpp", '#include "core/app/tasks/joint_manager.hpp"\n'
                                      '// and core/app/tasks/joint_manager.hpp includes it back (below)\n',
         "knot: folders core/app/tasks/, core/app/tasks/rc/"),
        # Ports: a task loop reaching TaskLinks around its ports.
        ("core/app/runtime/task_loops.cpp", "void f() { shared_links().joint_status.write(s); }\n", "shared_links() reaches the shared state"),
        ("core/app/runtime/task_loops.cpp", "void f() { run_control().stop.load(); }\n", "run_control() reaches the shared state"),
    ]
    for path, text, expected in wrong:
        files = dict(GOOD)
        files[path] = text
        if path == "core/app/tasks/rc/rc.hpp":
            files["core/app/tasks/joint_manager.hpp"] += '#include "core/app/tasks/rc/rc.hpp"\n'
        status, out = run(tree(files))
        if status != 1 or expected not in out:
            failures.append(f"{path} with {text.strip()!r}: exit {status}, expected a finding '{expected}':\n{out}")
    for f in failures:
        print("FAIL:", f)
    print(f"{len(wrong) + 1 - len(failures)} passed, {len(failures)} failed")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
