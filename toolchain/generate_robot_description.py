#!/usr/bin/env python3
"""Generates the firmware's constexpr robot description from the URDF.

    generate_robot_description.py URDF OUTPUT_HPP

The build runs it (core/kinematics/CMakeLists.txt, add_custom_command) whenever the URDF or this
script changes; the firmware parses nothing at run time. Standard library only.

It refuses (exit status 1, one line `URDF:LINE: what: why`) whatever the model cannot represent
exactly, rather than rounding it:
  - one tree rooted at base_link, every link reached once (a link with two parents is a loop);
  - joint origins without rotation (rpy 0) and axes exactly along +-x, +-y or +-z of the parent
    link (a tilted or non-unit axis is refused, never rounded);
  - revolute, continuous or fixed joints only; revolute limits with lower <= upper;
  - every link a moving joint carries, and base_link, has an <inertial> with a mass (massless frames
    only behind fixed joints), its frame not rotated;
  - every moving joint's <limit> has velocity, effort and acceleration (rad/s^2, an attribute this
    model adds to URDF's <limit>; urdfdom and kdl_parser ignore it), all positive;
  - an optional jerk (rad/s^3, also this model's attribute) where the drive has a jerk limit: positive
    and finite if given; no jerk attribute means none (0 in the table).
  - at most one <collision> per link, one <box> with positive sizes, not rotated (self-collision
    avoidance computes exact box distances); a box turned by a continuous joint is written as its
    envelope over the whole turn (a cylinder), so only the link the continuous joint moves may have one.
The limits are written as the URDF gives them; core/kinematics/kinematic_model.hpp checks at
compile time that they equal core/robot/robot.hpp's kJoints (one source of truth).
"""
import sys
import xml.etree.ElementTree as ET
import xml.parsers.expat

AXES = {(1.0, 0.0, 0.0): (0, 1.0), (-1.0, 0.0, 0.0): (0, -1.0), (0.0, 1.0, 0.0): (1, 1.0),
        (0.0, -1.0, 0.0): (1, -1.0), (0.0, 0.0, 1.0): (2, 1.0), (0.0, 0.0, -1.0): (2, -1.0)}


class ModelError(Exception):
    def __init__(self, line, message):
        super().__init__(message)
        self.line = line


LINES = {}  # element -> line in the URDF where it starts


def read_with_lines(path):
    """The URDF's element tree, each element's line in LINES (ElementTree keeps none)."""
    builder = ET.TreeBuilder()
    parser = xml.parsers.expat.ParserCreate()

    def start(tag, attrs):
        LINES[builder.start(tag, attrs)] = parser.CurrentLineNumber

    parser.StartElementHandler = start
    parser.EndElementHandler = builder.end
    try:
        with open(path, "rb") as f:
            parser.ParseFile(f)
    except xml.parsers.expat.ExpatError as e:
        raise ModelError(e.lineno, f"not well-formed XML: {xml.parsers.expat.ErrorString(e.code)}") from e
    return builder.close()


def fail(element, message):
    raise ModelError(LINES.get(element, 0), message)


def floats(element, attribute, default, count, what):
    text = element.get(attribute, default) if element is not None else default
    try:
        values = [float(v) for v in (text or "").split()]
    except ValueError:
        values = []
    if len(values) != count:
        fail(element, f"{what}: expected {count} numbers in {attribute}, got '{text}'")
    return values


def number(element, attribute, what, positive=False):
    text = element.get(attribute)
    if text is None:
        fail(element, f"{what}: no {attribute}")
    try:
        value = float(text)
    except ValueError:
        fail(element, f"{what}: {attribute} '{text}' is not a number")
    if value != value or value in (float("inf"), float("-inf")) or (positive and value <= 0.0):
        fail(element, f"{what}: {attribute} {text} must be a finite{' positive' if positive else ''} number")
    return value


def collision_box(link, name):
    """(centre, size) of the link's one <collision> box in its frame, None without <collision>.

    Self-collision avoidance (core/kinematics/self_collision.hpp) computes exact distances between
    boxes; what is not one unrotated box with positive sizes is refused, never approximated."""
    collisions = link.findall("collision")
    if not collisions:
        return None
    if len(collisions) > 1:
        fail(collisions[1], f"link {name}: a second <collision> (the model has one collision box per link)")
    collision = collisions[0]
    geometry = collision.find("geometry")
    shapes = list(geometry) if geometry is not None else []
    if len(shapes) != 1 or shapes[0].tag != "box":
        kind = ", ".join(e.tag for e in shapes) or "none"
        fail(shapes[0] if shapes else collision,
             f"link {name}: collision geometry '{kind}' cannot be represented (one <box> per link only)")
    size = floats(shapes[0], "size", None, 3, f"link {name} collision box")
    if any(not (v > 0.0 and v != float("inf")) for v in size):
        fail(shapes[0], f"link {name}: collision box size {' '.join(repr(v) for v in size)} must be positive and finite")
    origin = collision.find("origin")
    centre = floats(origin, "xyz", "0 0 0", 3, f"link {name} collision origin")
    if any(v != 0.0 for v in floats(origin, "rpy", "0 0 0", 3, f"link {name} collision rpy")):
        fail(origin, f"link {name}: rotated collision box (rpy must be 0 0 0: the boxes are aligned with their link)")
    return (centre, size)


def parse(path):
    """Returns (links, joints, support) in tree order (parents before children)."""
    root = read_with_lines(path)
    if root.tag != "robot":
        fail(root, "root element is not <robot>")
    links = {}
    for link in root.findall("link"):
        name = link.get("name")
        if name in links:
            fail(link, f"link {name}: defined twice")
        mass, com, inertia, box, has_inertial = 0.0, [0.0, 0.0, 0.0], [0.0] * 6, None, False
        inertial = link.find("inertial")
        if inertial is not None:
            has_inertial = True
            mass_element = inertial.find("mass")
            if mass_element is None:
                fail(inertial, f"link {name}: <inertial> without <mass>")
            mass = number(mass_element, "value", f"link {name} mass")
            if mass < 0.0:
                fail(mass_element, f"link {name}: negative mass {mass}")
            origin = inertial.find("origin")
            if origin is not None:
                com = floats(origin, "xyz", "0 0 0", 3, f"link {name} inertial origin")
                if any(v != 0.0 for v in floats(origin, "rpy", "0 0 0", 3, f"link {name} inertial rpy")):
                    fail(origin, f"link {name}: rotated inertial frame (the model keeps inertias in the link frame)")
            i = inertial.find("inertia")
            if i is None:
                fail(inertial, f"link {name}: <inertial> without <inertia>")
            inertia = [number(i, k, f"link {name} inertia") for k in ("ixx", "ixy", "ixz", "iyy", "iyz", "izz")]
        box = collision_box(link, name)
        links[name] = {"name": name, "mass": mass, "com": com, "inertia": inertia, "box": box,
                       "has_inertial": has_inertial, "element": link,
                       "box_element": link.find("collision") if box is not None else None}
    joints = {}
    for joint in root.findall("joint"):
        name, kind = joint.get("name"), joint.get("type")
        what = f"joint {name}"
        if name in joints:
            fail(joint, f"{what}: defined twice")
        if kind not in ("revolute", "continuous", "fixed"):
            fail(joint, f"{what}: joint type '{kind}' cannot be represented (revolute, continuous or fixed only)")
        parent, child = joint.find("parent"), joint.find("child")
        if parent is None or child is None or parent.get("link") not in links or child.get("link") not in links:
            fail(joint, f"{what}: parent or child is not a link of this robot")
        origin = joint.find("origin")
        xyz = floats(origin, "xyz", "0 0 0", 3, f"{what} origin")
        rpy = floats(origin, "rpy", "0 0 0", 3, f"{what} origin")
        if any(v != 0.0 for v in rpy):
            fail(origin, f"{what}: joint origin has a rotation (rpy must be 0 0 0 in this model)")
        axis, sign = 0, 1.0
        lower = upper = velocity = effort = acceleration = jerk = 0.0
        if kind != "fixed":
            a = joint.find("axis")
            vec = tuple(floats(a, "xyz", "1 0 0", 3, f"{what} axis"))
            norm = sum(v * v for v in vec) ** 0.5
            if abs(norm - 1.0) > 1e-12:
                fail(a if a is not None else joint, f"{what}: axis {' '.join(repr(v) for v in vec)} is not a unit vector "
                     f"(norm {norm:.6g})")
            if vec not in AXES:
                fail(a, f"{what}: axis {' '.join(repr(v) for v in vec)} is not exactly along +-x, +-y or +-z "
                     "(the model cannot represent a tilted axis; it is refused, not rounded)")
            axis, sign = AXES[vec]
            limit = joint.find("limit")
            if limit is None:
                fail(joint, f"{what}: no <limit>")
            velocity = number(limit, "velocity", what, positive=True)
            effort = number(limit, "effort", what, positive=True)
            acceleration = number(limit, "acceleration", what, positive=True)
            if limit.get("jerk") is not None:
                jerk = number(limit, "jerk", what, positive=True)
            if kind == "revolute":
                lower, upper = number(limit, "lower", what), number(limit, "upper", what)
                if lower > upper:
                    fail(limit, f"{what}: lower limit {lower} is above upper limit {upper}")
            if not links[child.get("link")]["has_inertial"]:
                fail(links[child.get("link")]["element"],
                     f"link {child.get('link')}: no <inertial> on a link the moving joint {name} carries")
        joints[name] = {"name": name, "kind": kind, "parent": parent.get("link"), "child": child.get("link"),
                        "xyz": xyz, "axis": axis, "sign": sign, "lower": lower, "upper": upper,
                        "velocity": velocity, "effort": effort, "acceleration": acceleration, "jerk": jerk,
                        "element": joint}
    by_child = {}
    for j in joints.values():
        if j["child"] in by_child:
            fail(j["element"], f"joint {j['name']}: link {j['child']} already has the parent joint "
                 f"{by_child[j['child']]['name']} (a kinematic loop or a second parent: the model is a tree)")
        by_child[j["child"]] = j
    if "base_link" not in links:
        fail(root, "no base_link")
    if "base_link" in by_child:
        fail(by_child["base_link"]["element"], f"joint {by_child['base_link']['name']}: base_link must be the root")
    if not links["base_link"]["has_inertial"]:
        fail(links["base_link"]["element"], "link base_link: no <inertial>")
    ordered, todo = [], ["base_link"]
    while todo:
        name = todo.pop(0)
        ordered.append(name)
        todo.extend(j["child"] for j in joints.values() if j["parent"] == name)
    if len(ordered) != len(links):
        orphan = next(l for l in links.values() if l["name"] not in ordered)
        fail(orphan["element"], f"link {orphan['name']}: not reached from base_link (a loop or a second tree)")
    support = support_polygon(links, joints, by_child)
    for name in ordered:
        collision_envelope(links[name], by_child)
    return [links[n] for n in ordered], by_child, support


def collision_envelope(link, by_child):
    """Marks a box its own continuous joint turns: the model checks its envelope over the whole turn.

    A continuous joint (a track) turns at any speed to any angle, faster than any joint the RC task
    moves can get out of the way, so its link is checked as the cylinder its box sweeps about the
    joint's axis (through the link's origin). A box further down, turned by a continuous joint that
    is not its own, would sweep a torus: refused."""
    if link["box"] is None:
        return
    own = by_child.get(link["name"])
    name = link["name"]
    parent = own["parent"] if own else None
    while parent in by_child:
        j = by_child[parent]
        if j["kind"] == "continuous":
            fail(link["box_element"], f"link {name}: its collision box is turned by the continuous joint {j['name']} "
                 "of an ancestor (only the link a continuous joint turns can be modelled, by its envelope)")
        parent = j["parent"]
    if own is None or own["kind"] != "continuous":
        return
    centre, size = link["box"]
    a = own["axis"]
    i, k = (a + 1) % 3, (a + 2) % 3
    radius = ((abs(centre[i]) + size[i] / 2) ** 2 + (abs(centre[k]) + size[k] / 2) ** 2) ** 0.5
    link["envelope"] = (a, radius)


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
            raise ModelError(0, f"{track} with a collision box is needed for the support polygon")
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
           "  double acceleration;    // rad/s^2 (the <limit acceleration> this model adds to URDF)",
           "  double jerk;            // rad/s^3 (the optional <limit jerk> this model adds; 0: none)",
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
        vals = (j["lower"], j["upper"], j["velocity"], j["effort"], j["acceleration"], j["jerk"]) if j else (0,) * 6
        out.append(f'  {{"{l["name"]}", {parent}, {jname}, JointType::{kind}, {j["axis"] if j else 0}, '
                   f'{num(j["sign"] if j else 1)}, {{{xyz}}}, {", ".join(num(v) for v in vals)}, {num(l["mass"])}, '
                   f'{{{", ".join(num(v) for v in l["com"])}}}, {{{", ".join(num(v) for v in l["inertia"])}}}}},')
    out += ["}};", "// clang-format on", "",
            "// Support polygon of the tracks in base_link (x, y), counter-clockwise.",
            f"constexpr std::size_t kSupportCorners = {len(support)};",
            "constexpr double kSupportPolygon[kSupportCorners][2] = {" +
            ", ".join(f"{{{num(x)}, {num(y)}}}" for x, y in support) + "};", ""]
    out += render_collision(links, index)
    out += ["}  // namespace rescue::robot_description", ""]
    return "\n".join(out)


def render_collision(links, index):
    """The links' collision boxes (core/kinematics/self_collision.hpp), parents first."""
    out = ["// Collision shapes: each link's one <collision> box, in the link frame (never rotated). A box",
           "// its own continuous joint turns (a track) is checked as its envelope over the whole turn: the",
           "// cylinder about that joint's axis (through the link's origin) of radius `radius`, centred on the",
           "// axis at centre[axis], half-length half[axis].",
           "struct CollisionShape {",
           "  int link;           // index into kLinks",
           "  double centre[3];   // box centre in the link frame",
           "  double half[3];     // box half sizes",
           "  int envelope_axis;  // -1: the box itself; 0 x, 1 y, 2 z: the cylinder about that link axis",
           "  double radius;      // the cylinder's radius (0 for a box)",
           "  double bound;       // radius of the sphere about the centre that holds the shape (a broad phase)",
           "};", ""]
    shapes = [l for l in links if l["box"] is not None]
    out.append(f"constexpr std::size_t kCollisionShapeCount = {len(shapes)};")
    out.append("// clang-format off")
    out.append("constexpr std::array<CollisionShape, kCollisionShapeCount> kCollisionShapes{{")
    for l in shapes:
        centre, size = l["box"]
        axis, radius = l.get("envelope", (-1, 0.0))
        if axis >= 0:
            centre = [centre[k] if k == axis else 0.0 for k in range(3)]
        if axis >= 0:
            bound = (radius ** 2 + (size[axis] / 2) ** 2) ** 0.5
        else:
            bound = sum((v / 2) ** 2 for v in size) ** 0.5
        out.append(f'  {{{index[l["name"]]}, {{{", ".join(num(v) for v in centre)}}}, '
                   f'{{{", ".join(num(v / 2) for v in size)}}}, {axis}, {num(radius)}, {num(bound)}}},  // {l["name"]}')
    out += ["}};", "// clang-format on", ""]
    return out


def main(argv):
    if len(argv) != 3:
        print(__doc__.strip().splitlines()[2].strip(), file=sys.stderr)
        return 2
    try:
        links, by_child, support = parse(argv[1])
    except ModelError as e:
        print(f"{argv[1]}:{e.line}: {e}", file=sys.stderr)
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
