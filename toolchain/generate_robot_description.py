#!/usr/bin/env python3
"""Generates the firmware's constexpr robot description from the URDF.

    generate_robot_description.py URDF OUTPUT_HPP

The build runs it (core/kinematics/CMakeLists.txt, add_custom_command) whenever the URDF or this
script changes; the firmware parses nothing at run time. Standard library only.

It refuses (exit status 1, one line saying why) a URDF outside the model's assumptions:
  - one tree rooted at base_link, every link reached once;
  - joint origins without rotation (rpy 0) and axes along +-x, +-y or +-z of the parent link;
  - revolute, continuous or fixed joints only.
The limits are written as the URDF gives them; core/kinematics/kinematic_model.hpp checks at
compile time that they equal core/robot/robot.hpp's kJoints (one source of truth).
"""
import sys
import xml.etree.ElementTree as ET

AXES = {(1, 0, 0): (0, 1.0), (-1, 0, 0): (0, -1.0), (0, 1, 0): (1, 1.0), (0, -1, 0): (1, -1.0),
        (0, 0, 1): (2, 1.0), (0, 0, -1): (2, -1.0)}


class ModelError(Exception):
    pass


def floats(text, count, what):
    values = [float(v) for v in (text or "").split()]
    if len(values) != count:
        raise ModelError(f"{what}: expected {count} numbers, got '{text}'")
    return values


def parse(path):
    """Returns (links, joints, support) in tree order (parents before children)."""
    root = ET.parse(path).getroot()
    if root.tag != "robot":
        raise ModelError("root element is not <robot>")
    links = {}
    for link in root.findall("link"):
        name = link.get("name")
        mass, com, inertia, box = 0.0, [0.0, 0.0, 0.0], [0.0] * 6, None
        inertial = link.find("inertial")
        if inertial is not None:
            mass = float(inertial.find("mass").get("value"))
            origin = inertial.find("origin")
            if origin is not None:
                com = floats(origin.get("xyz", "0 0 0"), 3, f"{name} inertial origin")
                if any(abs(v) > 0 for v in floats(origin.get("rpy", "0 0 0"), 3, name)):
                    raise ModelError(f"{name}: rotated inertial frame")
            i = inertial.find("inertia")
            inertia = [float(i.get(k)) for k in ("ixx", "ixy", "ixz", "iyy", "iyz", "izz")]
        collision = link.find("collision")
        if collision is not None and collision.find("geometry/box") is not None:
            size = floats(collision.find("geometry/box").get("size"), 3, f"{name} box")
            centre = floats(collision.find("origin").get("xyz", "0 0 0"), 3, f"{name} box origin")
            box = (centre, size)
        links[name] = {"name": name, "mass": mass, "com": com, "inertia": inertia, "box": box}
    joints = {}
    for joint in root.findall("joint"):
        name, kind = joint.get("name"), joint.get("type")
        if kind not in ("revolute", "continuous", "fixed"):
            raise ModelError(f"{name}: joint type {kind} is not supported")
        origin = joint.find("origin")
        xyz = floats(origin.get("xyz", "0 0 0"), 3, f"{name} origin") if origin is not None else [0.0] * 3
        rpy = floats(origin.get("rpy", "0 0 0"), 3, f"{name} rpy") if origin is not None else [0.0] * 3
        if any(v != 0.0 for v in rpy):
            raise ModelError(f"{name}: joint origin has a rotation (rpy must be 0 0 0)")
        axis, sign = 0, 1.0
        lower = upper = velocity = effort = 0.0
        if kind != "fixed":
            a = joint.find("axis")
            vec = tuple(int(round(v)) for v in floats(a.get("xyz") if a is not None else "1 0 0", 3, f"{name} axis"))
            if vec not in AXES:
                raise ModelError(f"{name}: axis {vec} is not along +-x, +-y or +-z")
            axis, sign = AXES[vec]
            limit = joint.find("limit")
            if limit is None:
                raise ModelError(f"{name}: no <limit>")
            velocity, effort = float(limit.get("velocity")), float(limit.get("effort"))
            if kind == "revolute":
                lower, upper = float(limit.get("lower")), float(limit.get("upper"))
        joints[name] = {"name": name, "kind": kind, "parent": joint.find("parent").get("link"),
                        "child": joint.find("child").get("link"), "xyz": xyz, "axis": axis, "sign": sign,
                        "lower": lower, "upper": upper, "velocity": velocity, "effort": effort}
    by_child = {}
    for j in joints.values():
        if j["child"] in by_child:
            raise ModelError(f"link {j['child']} has two parents")
        by_child[j["child"]] = j
    if "base_link" not in links or "base_link" in by_child:
        raise ModelError("base_link must exist and be the root")
    ordered, todo = [], ["base_link"]
    while todo:
        name = todo.pop(0)
        ordered.append(name)
        todo.extend(j["child"] for j in joints.values() if j["parent"] == name)
    if len(ordered) != len(links):
        raise ModelError("not every link is reached from base_link")
    support = support_polygon(links, joints, by_child)
    return [links[n] for n in ordered], by_child, support


def origin_in_base(name, by_child):
    """Position of a link's frame in base_link at q = 0 (no joint origin rotates)."""
    p = [0.0, 0.0, 0.0]
    while name in by_child:
        j = by_child[name]
        p = [p[k] + j["xyz"][k] for k in range(3)]
        name = j["parent"]
    return p


def support_polygon(links, joints, by_child):
    """Footprint rectangle of the two track links' collision boxes at q = 0, counter-clockwise."""
    xs, ys = [], []
    for track in ("l_track_link", "r_track_link"):
        if track not in links or links[track]["box"] is None:
            raise ModelError(f"{track} with a collision box is needed for the support polygon")
        centre, size = links[track]["box"]
        o = origin_in_base(track, by_child)
        xs += [o[0] + centre[0] - size[0] / 2, o[0] + centre[0] + size[0] / 2]
        ys += [o[1] + centre[1] - size[1] / 2, o[1] + centre[1] + size[1] / 2]
    x0, x1, y0, y1 = min(xs), max(xs), min(ys), max(ys)
    return [(x0, y0), (x1, y0), (x1, y1), (x0, y1)]


def num(v):
    return repr(float(v))


def render(links, by_child, support, source):
    index = {l["name"]: i for i, l in enumerate(links)}
    out = ["// GENERATED by toolchain/generate_robot_description.py from " + source + ". Do not edit.",
           "// The robot's kinematic tree (parents before children), masses and the track support polygon.",
           "#pragma once", "", "#include <array>", "#include <cstddef>", "",
           "namespace rescue::robot_description {", "",
           "enum class JointType : unsigned char { fixed, revolute, continuous };", "",
           "struct Link {",
           "  const char* name;",
           "  int parent;             // index into kLinks, -1 for base_link",
           "  const char* joint;      // joint from the parent (its name in core/robot/robot.hpp kJoints, or a fixed joint's name)",
           "  JointType type;",
           "  int axis;               // 0 x, 1 y, 2 z of the parent-side joint frame",
           "  double axis_sign;       // +1 or -1",
           "  double origin[3];       // joint frame in the parent link (no rotation)",
           "  double lower, upper;    // rad (0, 0 for continuous and fixed)",
           "  double velocity, effort;  // rad/s, N m",
           "  double mass;            // kg",
           "  double com[3];          // centre of mass in the link frame",
           "  double inertia[6];      // ixx ixy ixz iyy iyz izz about the com",
           "};", "",
           f"constexpr std::size_t kLinkCount = {len(links)};",
           "// clang-format off",
           "constexpr std::array<Link, kLinkCount> kLinks{{"]
    for l in links:
        j = by_child.get(l["name"])
        parent = index[j["parent"]] if j else -1
        jname = f'"{j["name"]}"' if j else '""'
        kind = j["kind"] if j else "fixed"
        xyz = ", ".join(num(v) for v in (j["xyz"] if j else [0, 0, 0]))
        vals = (j["lower"], j["upper"], j["velocity"], j["effort"]) if j else (0, 0, 0, 0)
        out.append(f'  {{"{l["name"]}", {parent}, {jname}, JointType::{kind}, {j["axis"] if j else 0}, '
                   f'{num(j["sign"] if j else 1)}, {{{xyz}}}, {", ".join(num(v) for v in vals)}, {num(l["mass"])}, '
                   f'{{{", ".join(num(v) for v in l["com"])}}}, {{{", ".join(num(v) for v in l["inertia"])}}}}},')
    out += ["}};", "// clang-format on", "",
            "// Support polygon of the tracks in base_link (x, y), counter-clockwise.",
            f"constexpr std::size_t kSupportCorners = {len(support)};",
            "constexpr double kSupportPolygon[kSupportCorners][2] = {" +
            ", ".join(f"{{{num(x)}, {num(y)}}}" for x, y in support) + "};", "",
            "}  // namespace rescue::robot_description", ""]
    return "\n".join(out)


def main(argv):
    if len(argv) != 3:
        print(__doc__.strip().splitlines()[2].strip(), file=sys.stderr)
        return 2
    try:
        links, by_child, support = parse(argv[1])
    except (ModelError, ET.ParseError, AttributeError, TypeError, ValueError) as e:
        print(f"generate_robot_description: {argv[1]}: {e}", file=sys.stderr)
        return 1
    text = render(links, by_child, support, "core/robot/rescue_robot.urdf")
    try:
        with open(argv[2], encoding="utf-8") as f:
            if f.read() == text:
                return 0  # unchanged: keep the timestamp
    except OSError:
        pass
    with open(argv[2], "w", encoding="utf-8") as f:
        f.write(text)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
