#!/usr/bin/env python3
"""Writes this world's model folders (run from this folder): irb1600/ (the IRB 1600 of
models/irb1600/irb1600.urdf as an SDFormat 1.8 model, its base welded to the world) and
box/ (a 0.1 m cube of 1 kg). world.sdf, written by hand, includes them.

`generate.py --push DIR` writes the same two into DIR with collision geometry for contact
(../irb1600_push: the robot's tool a 4 cm sphere at the TCP, the box its own cube).

The URDF's frames carry over unchanged: each joint's pose is its <origin> relative to the
parent link, each link's pose is its joint's frame (relative_to the joint), so the link
frames, inertials and visuals are the URDF's, and the joints keep their names and order.
"""
import xml.etree.ElementTree as ET

URDF = "../../irb1600/irb1600.urdf"


def pose(origin, relative_to=None):
    xyz = origin.get("xyz", "0 0 0") if origin is not None else "0 0 0"
    rpy = origin.get("rpy", "0 0 0") if origin is not None else "0 0 0"
    attribute = f' relative_to="{relative_to}"' if relative_to else ""
    return f"<pose{attribute}>{xyz} {rpy}</pose>"


def geometry(element):
    shape = element.find("geometry")[0]
    if shape.tag == "box":
        return f"<box><size>{shape.get('size')}</size></box>"
    if shape.tag == "cylinder":
        return (f"<cylinder><radius>{shape.get('radius')}</radius>"
                f"<length>{shape.get('length')}</length></cylinder>")
    raise ValueError(f"no SDFormat shape for {shape.tag}")


def link(element, joint_of, tool_radius=None):
    name = element.get("name")
    lines = [f'    <link name="{name}">']
    if name in joint_of:
        lines.append(f"      {pose(None, joint_of[name])}")
    inertial = element.find("inertial")
    if inertial is None:
        # SDFormat's default inertial is 1 kg; the URDF's link (the base, the TCP) has none.
        lines.append("      <inertial><mass>0</mass><inertia><ixx>0</ixx><iyy>0</iyy><izz>0</izz>"
                     "</inertia></inertial>")
    else:
        i = inertial.find("inertia")
        lines += [
            "      <inertial>",
            f"        {pose(inertial.find('origin'))}",
            f"        <mass>{inertial.find('mass').get('value')}</mass>",
            "        <inertia>" + "".join(
                f"<{k}>{i.get(k)}</{k}>" for k in ("ixx", "ixy", "ixz", "iyy", "iyz", "izz")) +
            "</inertia>",
            "      </inertial>",
        ]
    for k, visual in enumerate(element.findall("visual")):
        lines += [
            f'      <visual name="visual{k}">',
            f"        {pose(visual.find('origin'))}",
            f"        <geometry>{geometry(visual)}</geometry>",
            "        <material><diffuse>0.93 0.45 0.1 1</diffuse></material>",
            "      </visual>",
        ]
    if tool_radius is not None and name == "link6":
        # The tool: a sphere centred on the TCP (tcp_joint's origin in link6's frame).
        lines += ['      <collision name="tool">', "        <pose>0.065 0 0 0 0 0</pose>",
                  f"        <geometry><sphere><radius>{tool_radius:g}</radius></sphere></geometry>",
                  "      </collision>"]
    lines.append("    </link>")
    return lines


def joint(element):
    name, kind = element.get("name"), element.get("type")
    parent = element.find("parent").get("link")
    lines = [f'    <joint name="{name}" type="{kind}">',
             f"      {pose(element.find('origin'), parent)}",
             f"      <parent>{parent}</parent>",
             f"      <child>{element.find('child').get('link')}</child>"]
    if kind != "fixed":
        limit = element.find("limit")
        lines += [
            "      <axis>",
            f"        <xyz>{element.find('axis').get('xyz')}</xyz>",
            f"        <limit><lower>{limit.get('lower')}</lower><upper>{limit.get('upper')}</upper>"
            f"<effort>{limit.get('effort')}</effort><velocity>{limit.get('velocity')}</velocity>"
            "</limit>",
            "      </axis>",
        ]
    lines.append("    </joint>")
    return lines


def config(name, description):
    return f"""<?xml version="1.0"?>
<model>
  <name>{name}</name>
  <version>1.0</version>
  <sdf version="1.8">model.sdf</sdf>
  <description>{description}</description>
</model>
"""


def write(path, text):
    with open(path, "w") as out:
        out.write(text)


def irb1600(folder="irb1600", tool_radius=None):
    robot = ET.parse(URDF).getroot()
    joints = robot.findall("joint")
    joint_of = {j.find("child").get("link"): j.get("name") for j in joints}
    lines = ['<?xml version="1.0"?>',
             "<!-- Written by ../generate.py from models/irb1600/irb1600.urdf; do not edit. -->",
             '<sdf version="1.8">', '  <model name="irb1600">']
    for element in robot.findall("link"):
        lines += link(element, joint_of, tool_radius)
    lines += ['    <joint name="base_weld" type="fixed">', "      <parent>world</parent>",
              "      <child>base_link</child>", "    </joint>"]
    for element in joints:
        lines += joint(element)
    lines += ["  </model>", "</sdf>", ""]
    write(f"{folder}/model.sdf", "\n".join(lines))
    write(f"{folder}/model.config", config("irb1600", "ABB IRB 1600, base welded to the world"))


def box(folder="box", collide=False):
    mass, edge = 1.0, 0.1
    moment = mass * 2 * edge * edge / 12
    collision = (f"""
      <collision name="cube">
        <geometry><box><size>{edge:g} {edge:g} {edge:g}</size></box></geometry>
      </collision>""" if collide else "")
    write(f"{folder}/model.sdf", f"""<?xml version="1.0"?>
<!-- Written by ../generate.py; do not edit. A {edge:g} m cube of {mass:g} kg, no joint: a free body. -->
<sdf version="1.8">
  <model name="box">
    <link name="link">
      <inertial>
        <mass>{mass:g}</mass>
        <inertia><ixx>{moment:.17g}</ixx><iyy>{moment:.17g}</iyy><izz>{moment:.17g}</izz></inertia>
      </inertial>
      <visual name="visual">
        <geometry><box><size>{edge:g} {edge:g} {edge:g}</size></box></geometry>
        <material><diffuse>0.2 0.5 0.9 1</diffuse></material>
      </visual>{collision}
    </link>
  </model>
</sdf>
""")
    write(f"{folder}/model.config", config("box", "a 0.1 m cube of 1 kg"))


if __name__ == "__main__":
    import os
    import sys
    if sys.argv[1:2] == ["--push"]:
        out = sys.argv[2]
        os.makedirs(f"{out}/irb1600", exist_ok=True)
        os.makedirs(f"{out}/box", exist_ok=True)
        irb1600(f"{out}/irb1600", tool_radius=0.04)
        box(f"{out}/box", collide=True)
    else:
        os.makedirs("irb1600", exist_ok=True)
        os.makedirs("box", exist_ok=True)
        irb1600()
        box()
