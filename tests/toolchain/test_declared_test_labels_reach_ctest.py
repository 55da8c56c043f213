#!/usr/bin/env python3
"""Every label a test declares in rescue_add_test (tests/**/CMakeLists.txt) reaches CTest, with the
properties it implies: `serial` -> RUN_SERIAL (and `ctest -L serial`, the load stage, runs it),
`netns` -> RESOURCE_LOCK netns. A test declared `LABELS netns serial` once reached CTest as `netns`
only (gtest_discover_tests flattened the list), so three end-to-end tests ran in parallel in the debug
stage and never in the load stage.
Usage: test_declared_test_labels_reach_ctest.py SOURCE_DIR BINARY_DIR. Tests not built are skipped."""
import json
import os
import re
import subprocess
import sys

SKIP = 77


def declared(source_dir):
    labels = {}
    for root, _, files in os.walk(os.path.join(source_dir, "tests")):
        if "CMakeLists.txt" not in files:
            continue
        with open(os.path.join(root, "CMakeLists.txt"), encoding="utf-8") as f:
            text = f.read()
        for m in re.finditer(r"rescue_add_test\(\s*(\w+)([^)]*)\)", text):
            rest = m.group(2).split()
            labels[m.group(1)] = set(rest[rest.index("LABELS") + 1:]) if "LABELS" in rest else set()
    return labels


def main():
    source_dir, binary_dir = sys.argv[1], sys.argv[2]
    wanted = declared(source_dir)
    shown = subprocess.run(["ctest", "--test-dir", binary_dir, "--show-only=json-v1"], check=True,
                           capture_output=True, text=True).stdout
    checked = 0
    problems = []
    for test in json.loads(shown)["tests"]:
        command = test.get("command") or []
        name = os.path.basename(command[0]) if command else ""
        if name not in wanted:
            continue
        props = {p["name"]: p["value"] for p in test.get("properties", [])}
        got = set(props.get("LABELS", []))
        want = wanted[name]
        checked += 1
        if got != want:
            problems.append(f"{test['name']} ({name}): labels {sorted(got)}, declared {sorted(want)}")
        if "serial" in want and props.get("RUN_SERIAL") is not True:
            problems.append(f"{test['name']} ({name}): declared serial but not RUN_SERIAL")
        if "netns" in want and "netns" not in props.get("RESOURCE_LOCK", []):
            problems.append(f"{test['name']} ({name}): declared netns but no RESOURCE_LOCK netns")
    if checked == 0:
        print("no declared test is built: nothing to check")
        return SKIP
    for p in problems:
        print(p)
    print(f"{checked} discovered tests checked, {len(problems)} problems")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
