#!/usr/bin/env python3
"""CTest: toolchain/generate_robot_description.py refuses, with URDF:LINE and the reason, every URDF
it cannot represent exactly (exit status 1, nothing written), and accepts the robot's URDF.

Each mutant is the robot's URDF (core/robot/rescue_robot.urdf) with one change: a tilted elbow axis
(0.34 -0.94 0, which the generator once rounded to -y with exit status 0), a non-unit axis, a link
without <inertial>, lower > upper, a kinematic loop, an unknown joint type, a rotated joint origin,
a joint without an acceleration limit, a jerk limit that is not a positive finite number (zero,
negative, not a number, infinite; the jerk limit itself is optional), collision geometry that is not
one unrotated box with positive sizes (a cylinder, a mesh, a rotated box, two <collision>, a flat box)
or a box turned by a continuous joint that is not its link's own. The message must name the joint (or link) and the line of
the element at fault.
Usage: test_...py SOURCE_DIR WORK_DIR
"""
import os
import subprocess
import sys

src = os.path.abspath(sys.argv[1])
work = os.path.abspath(sys.argv[2])
os.makedirs(work, exist_ok=True)
generator = os.path.join(src, "toolchain", "generate_robot_description.py")
with open(os.path.join(src, "core", "robot", "rescue_robot.urdf"), encoding="utf-8") as f:
    robot = f.read()
failures = []

ELBOW = '<origin xyz="0.0 0.0 -0.3" rpy="0 0 0"/><axis xyz="0 -1 0"/>'
ELBOW_LIMIT = '<limit lower="0.00" upper="2.50" effort="80.0" velocity="2.0"'
FOREARM_INERTIAL = ('<link name="l_forearm_link">\n    <inertial><origin xyz="0.0 0.0 -0.14" rpy="0 0 0"/><mass value="4.0"/>\n'
                    '      <inertia ixx="0.0327" ixy="0" ixz="0" iyy="0.0327" iyz="0" izz="0.0054"/></inertial>')


def generate(name, text):
    urdf = os.path.join(work, name + ".urdf")
    out = os.path.join(work, name + ".hpp")
    with open(urdf, "w", encoding="utf-8") as f:
        f.write(text)
    if os.path.exists(out):
        os.remove(out)
    p = subprocess.run([sys.executable, generator, urdf, out], capture_output=True, text=True)
    return urdf, out, p


def line_of(text, needle):
    at = text.index(needle)
    return text.count("\n", 0, at) + 1


def refused(name, old, new, names, needle, why):
    """Applies old -> new (first occurrence), expects exit 1 and `URDF:LINE: ...` naming `names`."""
    if old not in robot:
        print(f"FAIL: {name}: the mutation no longer applies to the URDF")
        failures.append(name)
        return
    text = robot.replace(old, new, 1)
    urdf, out, p = generate(name, text)
    expected = f"{urdf}:{line_of(text, needle)}: "
    message = p.stderr.strip()
    ok = (p.returncode == 1 and message.startswith(expected) and all(n in message for n in names)
          and why in message and not os.path.exists(out))
    print("%s: %s (exit %d): %s" % ("PASS" if ok else "FAIL", name, p.returncode, message))
    if not ok:
        print(f"  expected exit 1, '{expected}...' naming {names} and saying '{why}', no output file")
        failures.append(name)


# The robot itself: accepted.
_, out, p = generate("robot", robot)
ok = p.returncode == 0 and os.path.exists(out) and p.stderr == ""
print("%s: the robot's URDF is accepted (exit %d) %s" % ("PASS" if ok else "FAIL", p.returncode, p.stderr))
if not ok:
    failures.append("robot")

refused("tilted_axis", ELBOW, ELBOW.replace("0 -1 0", "0.34 -0.94 0"), ["joint l_elbow"],
        '<axis xyz="0.34 -0.94 0"/>', "not a unit vector")
# A unit vector that is tilted: refused as tilted, not rounded.
refused("tilted_unit_axis", ELBOW, ELBOW.replace("0 -1 0", "0.6 -0.8 0"), ["joint l_elbow"],
        '<axis xyz="0.6 -0.8 0"/>', "not exactly along +-x, +-y or +-z")
refused("non_unit_axis", ELBOW, ELBOW.replace("0 -1 0", "0 -2 0"), ["joint l_elbow"],
        '<axis xyz="0 -2 0"/>', "not a unit vector")
refused("missing_inertial", FOREARM_INERTIAL, '<link name="l_forearm_link">',
        ["link l_forearm_link", "l_elbow"], '<link name="l_forearm_link">', "no <inertial>")
refused("lower_above_upper", ELBOW_LIMIT, ELBOW_LIMIT.replace('lower="0.00"', 'lower="2.60"'), ["joint l_elbow"],
        '<limit lower="2.60"', "lower limit 2.6 is above upper limit 2.5")
refused("loop", '<link name="l_ee"/>',
        '<link name="l_ee"/>\n  <joint name="l_palm_to_torso" type="fixed"><parent link="l_ee"/><child link="torso_link"/></joint>',
        ["joint l_palm_to_torso", "torso_link", "waist_yaw"], '<joint name="l_palm_to_torso"', "loop")
refused("unknown_joint_type", '<joint name="l_elbow" type="revolute">', '<joint name="l_elbow" type="prismatic">',
        ["joint l_elbow", "prismatic"], '<joint name="l_elbow"', "cannot be represented")
refused("rotated_origin", ELBOW, ELBOW.replace('rpy="0 0 0"', 'rpy="0 0.1 0"'), ["joint l_elbow"],
        '<origin xyz="0.0 0.0 -0.3" rpy="0 0.1 0"/>', "rotation")
refused("no_acceleration_limit", ELBOW_LIMIT + ' acceleration="5.0"', ELBOW_LIMIT, ["joint l_elbow"],
        ELBOW_LIMIT + "/>", "no acceleration")
HAND_LIMIT = '<limit lower="0.00" upper="1.50" effort="40.0" velocity="1.0" acceleration="5.0" jerk="50.0"/>'
for mutant, value in (("zero_jerk", "0"), ("negative_jerk", "-50.0"), ("jerk_not_a_number", "fast"),
                      ("infinite_jerk", "inf")):
    refused(mutant, HAND_LIMIT, HAND_LIMIT.replace('jerk="50.0"', f'jerk="{value}"'), ["joint l_hand"],
            HAND_LIMIT.replace('jerk="50.0"', f'jerk="{value}"'), "jerk")
# Collision geometry: one unrotated box with positive sizes per link; a box a continuous joint turns
# only on that joint's own link (the model checks its envelope over the turn).
FOREARM_COLLISION = ('<collision><origin xyz="0.0 0.0 -0.14" rpy="0 0 0"/><geometry><box size="0.09 0.09 0.3"/>'
                     '</geometry></collision>')
refused("collision_cylinder", FOREARM_COLLISION,
        FOREARM_COLLISION.replace('<box size="0.09 0.09 0.3"/>', '<cylinder radius="0.045" length="0.3"/>'),
        ["link l_forearm_link", "cylinder"], '<cylinder radius="0.045"', "cannot be represented")
refused("collision_mesh", FOREARM_COLLISION,
        FOREARM_COLLISION.replace('<box size="0.09 0.09 0.3"/>', '<mesh filename="forearm.stl"/>'),
        ["link l_forearm_link", "mesh"], '<mesh filename="forearm.stl"/>', "cannot be represented")
refused("collision_rotated", FOREARM_COLLISION, FOREARM_COLLISION.replace('rpy="0 0 0"', 'rpy="0 0 0.3"'),
        ["link l_forearm_link"], '<collision><origin xyz="0.0 0.0 -0.14" rpy="0 0 0.3"/>', "rotated collision box")
refused("collision_twice", FOREARM_COLLISION, FOREARM_COLLISION + "\n    <!-- second -->" + FOREARM_COLLISION,
        ["link l_forearm_link"], "<!-- second -->", "a second <collision>")
refused("collision_flat_box", FOREARM_COLLISION, FOREARM_COLLISION.replace("0.09 0.09 0.3", "0.09 0 0.3"),
        ["link l_forearm_link"], '<box size="0.09 0 0.3"/>', "must be positive")
refused("collision_turned_by_ancestor", '<link name="l_ee"/>',
        '<link name="l_ee"/>\n  <joint name="l_mudguard_fixed" type="fixed"><parent link="l_track_link"/>'
        '<child link="l_mudguard"/></joint>\n  <link name="l_mudguard">\n    <collision><origin xyz="0 0 0.2" rpy="0 0 0"/>'
        '<geometry><box size="0.2 0.2 0.02"/></geometry></collision></link>',
        ["link l_mudguard", "continuous joint l_track"], '<collision><origin xyz="0 0 0.2"', "envelope")
# No jerk attribute: accepted (no jerk limit, 0 in the table).
_, out, p = generate("no_jerk", robot.replace(' jerk="50.0"', ""))
ok = p.returncode == 0 and os.path.exists(out) and "jerk" in open(out, encoding="utf-8").read()
print("%s: a URDF without jerk limits is accepted (exit %d) %s" % ("PASS" if ok else "FAIL", p.returncode, p.stderr))
if not ok:
    failures.append("no_jerk")

if failures:
    print("FAILED: " + ", ".join(failures))
    sys.exit(1)
print("all passed")
