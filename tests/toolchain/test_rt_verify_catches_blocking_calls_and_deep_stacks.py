#!/usr/bin/env python3
"""CTest: toolchain/rt_verify.py fails on a deliberate malloc in a handler path, on an unresolved
function pointer, on recursion and on a stack over budget, and passes the clean fixture.

Compiles tests/toolchain/rt_verify/fixture.cpp with GCC's -fstack-usage -fcallgraph-info=su (as the
`verify` preset does) in variants and runs the checker on each, with the firmware's own deny and
safe-external lists (toolchain/rt-verify.json), so the lists cannot rot unnoticed.
Usage: test_...py SOURCE_DIR WORK_DIR
"""
import json
import os
import shutil
import subprocess
import sys

src = os.path.abspath(sys.argv[1])
work = os.path.abspath(sys.argv[2])
fixture_dir = os.path.join(src, "tests", "toolchain", "rt_verify")
checker = os.path.join(src, "toolchain", "rt_verify.py")
failures = []


def config(indirect=True):
    with open(os.path.join(src, "toolchain", "rt-verify.json"), encoding="utf-8") as f:
        firmware = json.load(f)
    return {
        "stack_limit": {"file": "limits.hpp", "constant": "kFixtureStackBytes"},
        "external_stack_bytes": firmware["external_stack_bytes"],
        "tasks": [{"name": "fixture_handler", "entry": "fixture::cycle", "why": "fixture"}],
        "deny": firmware["deny"], "safe_externals": firmware["safe_externals"],
        "boundaries": [], "allow": [],
        "indirect": [{"name": "g_hook", "file": "fixture", "signature": r"int .*\(int\)", "why": "HookFn"}] if indirect else [],
    }


def run(name, defines, expect_rc, expect_lines, indirect=True, extra=()):
    build = os.path.join(work, name)
    shutil.rmtree(build, ignore_errors=True)
    os.makedirs(build)
    subprocess.run(["g++", "-std=c++17", "-O2", "-fno-exceptions", "-fno-rtti", "-fstack-usage",
                    "-fcallgraph-info=su", "-c", os.path.join(fixture_dir, "fixture.cpp"), "-o",
                    os.path.join(build, "fixture.o")] + ["-D" + d for d in defines], check=True, cwd=build)
    cfg = os.path.join(build, "config.json")
    with open(cfg, "w", encoding="utf-8") as f:
        json.dump(config(indirect), f)
    p = subprocess.run([sys.executable, checker, "--build", build, "--source", fixture_dir, "--config", cfg] + list(extra),
                       capture_output=True, text=True)
    ok = p.returncode == expect_rc and all(any(e in line for line in p.stdout.splitlines()) for e in expect_lines)
    print("%s: %s (exit %d, expected %d)" % ("PASS" if ok else "FAIL", name, p.returncode, expect_rc))
    if not ok:
        print(p.stdout + p.stderr)
        failures.append(name)


run("clean_fixture_passes", [], 0,
    ["fixture_handler_blocking_violations: 0", "rt_verify_result: pass"])
run("deliberate_malloc_fails", ["RT_VERIFY_DELIBERATE_MALLOC"], 1,
    ["fixture_handler_violation: malloc: heap allocation", "    fixture::cycle"])
run("unresolved_function_pointer_fails", [], 1,
    ["fixture_handler_violation: <unresolved indirect call g_hook>"], indirect=False)
run("recursion_fails", ["RT_VERIFY_RECURSION"], 1, ["fixture_handler_recursion: fixture::walk -> fixture::walk"])
run("stack_over_budget_fails", [], 1, ["fixture_handler_stack_violation"], extra=("--stack-limit", "1024"))
print("%d passed, %d failed" % (5 - len(failures), len(failures)))
sys.exit(1 if failures else 0)
