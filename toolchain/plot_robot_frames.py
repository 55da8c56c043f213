#!/usr/bin/env python3
"""Figure of the rescue robot's joint frames, from the URDF (docs/kinematics.md).

    plot_robot_frames.py URDF OUTPUT_PNG

Draws the kinematic tree in the ready posture (the values of core/kinematics/rescue_motion.cpp
ready_posture()) and at q = 0 side by side: links as lines, each joint's axis as a short arrow
(x red, y green, z blue by the axis it turns about), the palms (l_ee, r_ee) and the support polygon.
Needs matplotlib (Debian: python3-matplotlib); reads the URDF with the build's own generator.
"""
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import generate_robot_description as gen  # noqa: E402

import matplotlib  # noqa: E402
matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

READY = {"l_shoulder_roll": 0.1, "r_shoulder_roll": -0.1, "l_elbow": math.pi / 2, "r_elbow": math.pi / 2,
         "l_hand": 0.2, "r_hand": 0.2}


def matmul(a, b):
    return [[sum(a[i][k] * b[k][j] for k in range(3)) for j in range(3)] for i in range(3)]


def rot(axis, sign, angle):
    c, s = math.cos(angle), sign * math.sin(angle)
    if axis == 0:
        return [[1, 0, 0], [0, c, -s], [0, s, c]]
    if axis == 1:
        return [[c, 0, s], [0, 1, 0], [-s, 0, c]]
    return [[c, -s, 0], [s, c, 0], [0, 0, 1]]


def forward(links, by_child, q):
    poses = {}
    for link in links:
        name = link["name"]
        j = by_child.get(name)
        if j is None:
            poses[name] = ([[1, 0, 0], [0, 1, 0], [0, 0, 1]], [0.0, 0.0, 0.0])
            continue
        R, p = poses[j["parent"]]
        p2 = [p[i] + sum(R[i][k] * j["xyz"][k] for k in range(3)) for i in range(3)]
        R2 = R if j["kind"] == "fixed" else matmul(R, rot(j["axis"], j["sign"], q.get(j["name"], 0.0)))
        poses[name] = (R2, p2)
    return poses


def draw(ax, links, by_child, support, q, title):
    poses = forward(links, by_child, q)
    colours = ["tab:red", "tab:green", "tab:blue"]
    for link in links:
        j = by_child.get(link["name"])
        if j is None:
            continue
        a, b = poses[j["parent"]][1], poses[link["name"]][1]
        ax.plot([a[0], b[0]], [a[1], b[1]], [a[2], b[2]], color="0.35", linewidth=2)
        if j["kind"] == "fixed":
            ax.scatter([b[0]], [b[1]], [b[2]], color="black", s=25)
            ax.text(b[0], b[1], b[2] - 0.06, link["name"], fontsize=7)
            continue
        R = poses[link["name"]][0]
        axis = [j["sign"] * R[i][j["axis"]] * 0.12 for i in range(3)]
        ax.quiver(b[0], b[1], b[2], axis[0], axis[1], axis[2], color=colours[j["axis"]], linewidth=1.5)
        if not j["name"].startswith("r_"):
            ax.text(b[0], b[1], b[2] + 0.02, j["name"], fontsize=6)
    xs = [c[0] for c in support] + [support[0][0]]
    ys = [c[1] for c in support] + [support[0][1]]
    ax.plot(xs, ys, [0.0] * len(xs), color="tab:orange", linewidth=1.5)
    ax.set_title(title, fontsize=10)
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")
    ax.set_zlabel("z (m)")
    ax.set_xlim(-0.6, 0.9)
    ax.set_ylim(-0.75, 0.75)
    ax.set_zlim(0.0, 1.5)
    ax.set_box_aspect((1.5, 1.5, 1.5))  # equal scale on every axis
    ax.view_init(elev=14, azim=-35)


def main(argv):
    if len(argv) != 3:
        print("usage: plot_robot_frames.py URDF OUTPUT_PNG", file=sys.stderr)
        return 2
    links, by_child, support = gen.parse(argv[1])
    fig = plt.figure(figsize=(12, 6))
    draw(fig.add_subplot(1, 2, 1, projection="3d"), links, by_child, support, READY, "ready posture")
    draw(fig.add_subplot(1, 2, 2, projection="3d"), links, by_child, support, {}, "q = 0")
    fig.suptitle("rescue_robot.urdf: joint axes (x red, y green, z blue), palms, support polygon (orange)")
    fig.tight_layout()
    fig.savefig(argv[2], dpi=110)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
