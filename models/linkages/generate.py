#!/usr/bin/env python3
"""Writes the planar linkages of this folder as SDFormat 1.7 (run from this folder).

Every mechanism moves in the vertical x-z plane of its model frame (gravity -z); its
revolute joints turn about -y, so that a positive joint angle turns x towards z
(counter-clockwise seen from -y, the viewer's side). Each link's frame sits on its proximal
joint with x along the link, as drawn at q = 0; bars are boxes of 0.02 m square section.
"""
import math

import scene_writer

W = 0.02  # m, bar section

# Colours of the links as drawn (the viewer reads <material>: diffuse, else ambient).
COLOURS = dict(crank=(0.8, 0.2, 0.2), coupler=(0.2, 0.5, 0.9), rocker=(0.2, 0.7, 0.3),
               rod=(0.2, 0.5, 0.9), slider=(0.9, 0.7, 0.1), arm=(0.8, 0.3, 0.1),
               delta_rod=(0.6, 0.6, 0.65), platform=(0.2, 0.4, 0.8))


def material(colour):
    rgb = " ".join(f"{c:g}" for c in colour)
    return f"<material><ambient>{rgb} 1</ambient><diffuse>{rgb} 1</diffuse></material>"


def bar_inertial(mass, length):
    i_axial = mass * (W * W + W * W) / 12.0
    i_bend = mass * (length * length + W * W) / 12.0
    return f"""      <inertial>
        <pose>{length / 2:.17g} 0 0 0 0 0</pose>
        <mass>{mass:.17g}</mass>
        <inertia><ixx>{i_axial:.17g}</ixx><iyy>{i_bend:.17g}</iyy><izz>{i_bend:.17g}</izz>
          <ixy>0</ixy><ixz>0</ixz><iyz>0</iyz></inertia>
      </inertial>"""


def bar_visual(length, colour):
    return f"""      <visual name="bar">
        <pose>{length / 2:.17g} 0 0 0 0 0</pose>
        <geometry><box><size>{length:.17g} {W} {W}</size></box></geometry>
        {material(colour)}
      </visual>"""


def link(name, x, z, angle, mass, length, colour=None):
    # pitch -angle turns the link's x axis to (cos angle, 0, sin angle)
    return f"""    <link name="{name}">
      <pose>{x:.17g} 0 {z:.17g} 0 {-angle:.17g} 0</pose>
{bar_inertial(mass, length)}
{bar_visual(length, colour or COLOURS[name])}
    </link>"""


def joint(name, kind, parent, child, pose="0 0 0 0 0 0", axis="0 -1 0"):
    return f"""    <joint name="{name}" type="{kind}">
      <parent>{parent}</parent>
      <child>{child}</child>
      <pose>{pose}</pose>
      <axis><xyz>{axis}</xyz></axis>
    </joint>"""


def circle_intersection(p, r_p, q, r_q, side=1):
    """The intersection of circles (p, r_p) and (q, r_q) left of p -> q (x-z plane), or right
    of it with side -1."""
    dx, dz = q[0] - p[0], q[1] - p[1]
    d = math.hypot(dx, dz)
    a = (r_p * r_p - r_q * r_q + d * d) / (2 * d)
    h = math.sqrt(r_p * r_p - a * a)
    mx, mz = p[0] + a * dx / d, p[1] + a * dz / d
    return (mx - side * h * dz / d, mz + side * h * dx / d)


def four_bar(name="four_bar", a=0.1, b=0.35, c=0.3, d=0.4, theta2=math.pi / 2, side=1):
    # Ground d, crank a, coupler b, rocker c (m); the default is a Grashof crank-rocker
    # (a the shortest), drawn with the crank at theta2 and the coupler's far pin on `side`.
    A = (a * math.cos(theta2), a * math.sin(theta2))
    B = circle_intersection(A, b, (d, 0.0), c, side)
    theta3 = math.atan2(B[1] - A[1], B[0] - A[0])
    theta4 = math.atan2(B[1], B[0] - d)
    body = "\n".join([
        link("crank", 0.0, 0.0, theta2, 0.5, a),
        link("coupler", A[0], A[1], theta3, 1.0, b),
        link("rocker", d, 0.0, theta4, 0.8, c),
        joint("crank_joint", "revolute", "world", "crank"),
        joint("rocker_joint", "revolute", "world", "rocker"),
        joint("coupler_joint", "revolute", "crank", "coupler"),
        # closes the loop: its child, the rocker, already hangs from the world
        joint("loop_joint", "revolute", "coupler", "rocker", pose=f"{c:.17g} 0 0 0 0 0"),
    ])
    return model(name, body)


def slider_crank():
    r, l = 0.1, 0.3
    theta = math.pi / 2
    A = (r * math.cos(theta), r * math.sin(theta))
    xB = r * math.cos(theta) + math.sqrt(l * l - (r * math.sin(theta)) ** 2)
    phi = math.atan2(0.0 - A[1], xB - A[0])
    body = "\n".join([
        link("crank", 0.0, 0.0, theta, 0.5, r),
        link("rod", A[0], A[1], phi, 1.0, l),
        f"""    <link name="slider">
      <pose>{xB:.17g} 0 0 0 0 0</pose>
      <inertial><mass>2</mass>
        <inertia><ixx>0.001</ixx><iyy>0.001</iyy><izz>0.001</izz>
          <ixy>0</ixy><ixz>0</ixz><iyz>0</iyz></inertia></inertial>
      <visual name="block"><geometry><box><size>0.08 0.05 0.05</size></box></geometry>
        {material(COLOURS["slider"])}</visual>
    </link>""",
        joint("crank_joint", "revolute", "world", "crank"),
        joint("slider_joint", "prismatic", "world", "slider", axis="1 0 0"),
        joint("rod_joint", "revolute", "crank", "rod"),
        # closes the loop: the slider already hangs from the world
        joint("pin_joint", "revolute", "rod", "slider"),
    ])
    return model("slider_crank", body)


# The Delta robot: three arms on motors about horizontal axes (tangents of the base circle),
# each closed on the platform by a parallelogram of two rods. In the tree each rod hangs from
# its arm by a universal joint (two revolutes through a small knuckle: its spin is not a
# degree of freedom, as in the real machine the ball joints leave it idle) and the platform
# hangs from rod 1a by three revolutes (a spherical wrist, far from its gimbal singularity in
# the workspace); the other five rods close on the platform through ball joints, the cut
# joints (parent the platform, so that the tree reaches the platform through the wrist).
# z is up, the base at z = 0, every link frame aligned with the model frame as drawn.
DELTA = dict(base_r=0.2, platform_r=0.05, arm=0.25, rod=0.5, half_width=0.03, z0=-0.45)


def delta_ik(p, **dims):
    """The motor angles (rad, arm below the horizontal positive) that put the platform's
    centre at p = (x, y, z); the elbow-out branch."""
    d = dict(DELTA, **dims)
    angles = []
    for i in range(3):
        g = 2 * math.pi * i / 3
        u = (math.cos(g), math.sin(g), 0.0)
        t = (-math.sin(g), math.cos(g), 0.0)
        dx = [p[k] + (d["platform_r"] - d["base_r"]) * u[k] for k in range(3)]
        a = sum(dx[k] * u[k] for k in range(3))
        b = sum(dx[k] * t[k] for k in range(3))
        c = dx[2]
        k_ = (a * a + b * b + c * c + d["arm"] ** 2 - d["rod"] ** 2) / (2 * d["arm"])
        # a cos(theta) - c sin(theta) = k_
        base = math.atan2(-c, a)
        spread = math.acos(k_ / math.hypot(a, c))
        angles.append(base - spread if math.cos(base - spread) > math.cos(base + spread)
                      else base + spread)
    return angles


def v3(v):
    return " ".join(f"{x:.17g}" for x in v)


def add(*vs):
    return tuple(sum(v[k] for v in vs) for k in range(3))


def scale(s, v):
    return tuple(s * x for x in v)


def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def unit(v):
    n = math.sqrt(sum(x * x for x in v))
    return tuple(x / n for x in v)


def rod_like(name, origin, vector, mass, radius, colour):
    """A slender bar from `origin` along `vector`: its inertia about its centre in model axes."""
    length = math.sqrt(sum(x * x for x in vector))
    d = unit(vector)
    i0 = mass * length * length / 12.0
    small = mass * W * W / 6.0
    inertia = [[(i0 * ((1.0 if r == c else 0.0) - d[r] * d[c]) + (small if r == c else 0.0))
                for c in range(3)] for r in range(3)]
    centre = scale(0.5, vector)
    # the cylinder's z along the bar: pitch from z towards it, then yaw about z
    pitch = math.atan2(math.hypot(d[0], d[1]), d[2])
    yaw = math.atan2(d[1], d[0])
    return f"""    <link name="{name}">
      <pose>{v3(origin)} 0 0 0</pose>
      <inertial>
        <pose>{v3(centre)} 0 0 0</pose>
        <mass>{mass}</mass>
        <inertia><ixx>{inertia[0][0]:.17g}</ixx><iyy>{inertia[1][1]:.17g}</iyy><izz>{inertia[2][2]:.17g}</izz>
          <ixy>{inertia[0][1]:.17g}</ixy><ixz>{inertia[0][2]:.17g}</ixz><iyz>{inertia[1][2]:.17g}</iyz></inertia>
      </inertial>
      <visual name="bar">
        <pose>{v3(centre)} 0 {pitch:.17g} {yaw:.17g}</pose>
        <geometry><cylinder><radius>{radius}</radius><length>{length:.17g}</length></cylinder></geometry>
        {material(colour)}
      </visual>
    </link>"""


def small_link(name, origin, mass=0.005, inertia=1e-7):
    return f"""    <link name="{name}">
      <pose>{v3(origin)} 0 0 0</pose>
      <inertial><mass>{mass}</mass>
        <inertia><ixx>{inertia}</ixx><iyy>{inertia}</iyy><izz>{inertia}</izz>
          <ixy>0</ixy><ixz>0</ixz><iyz>0</iyz></inertia></inertial>
    </link>"""


def rpy_of_columns(x, y, z):
    """SDFormat's roll, pitch, yaw of the rotation whose columns are x, y, z (model axes)."""
    R = [[x[0], y[0], z[0]], [x[1], y[1], z[1]], [x[2], y[2], z[2]]]
    return (math.atan2(R[2][1], R[2][2]), -math.asin(R[2][0]), math.atan2(R[1][0], R[0][0]))


def delta(ball_wrist=False):
    """ball_wrist: the platform hangs from rod 1a by one ball joint `wrist` in the tree (a
    quaternion joint, server/kinematics/ball_joint.h; the server refuses closed loops with a
    ball joint in the tree, tests/server/loops/ball_joint_test.cc) instead of the three
    revolutes; its frame's x is -normal, y the arm's tangent, z along the rod."""
    d = DELTA
    p = (0.0, 0.0, d["z0"])
    thetas = delta_ik(p)
    links, joints, balls = [], [], []
    links.append(f"""    <link name="platform">
      <pose>{v3(p)} 0 0 0</pose>
      <inertial><mass>0.2</mass>
        <inertia><ixx>1.5e-4</ixx><iyy>1.5e-4</iyy><izz>2.5e-4</izz>
          <ixy>0</ixy><ixz>0</ixz><iyz>0</iyz></inertia></inertial>
      <visual name="disc"><geometry><cylinder><radius>{d["platform_r"]}</radius><length>0.01</length></cylinder></geometry>
        {material(COLOURS["platform"])}</visual>
    </link>""")
    for i in range(3):
        g = 2 * math.pi * i / 3
        u = (math.cos(g), math.sin(g), 0.0)
        t = (-math.sin(g), math.cos(g), 0.0)
        th = thetas[i]
        b = scale(d["base_r"], u)
        arm = add(scale(d["arm"] * math.cos(th), u), (0.0, 0.0, -d["arm"] * math.sin(th)))
        e = add(b, arm)
        n = i + 1
        links.append(rod_like(f"arm{n}", b, arm, 0.3, 0.012, COLOURS["arm"]))
        joints.append(joint(f"motor{n}", "revolute", "world", f"arm{n}", axis=v3(t)))
        for s, side in ((1, "a"), (-1, "b")):
            top = add(e, scale(s * d["half_width"], t))
            bottom = add(p, scale(d["platform_r"], u), scale(s * d["half_width"], t))
            r = add(bottom, scale(-1.0, top))
            normal = unit(cross(r, t))
            rod = f"rod{n}{side}"
            links.append(small_link(f"knuckle{n}{side}", top))
            links.append(rod_like(rod, top, r, 0.1, 0.006, COLOURS["delta_rod"]))
            joints.append(joint(f"elbow{n}{side}_1", "revolute", f"arm{n}", f"knuckle{n}{side}",
                                axis=v3(t)))
            joints.append(joint(f"elbow{n}{side}_2", "revolute", f"knuckle{n}{side}", rod,
                                axis=v3(normal)))
            if (n, side) == (1, "a") and ball_wrist:
                rpy = rpy_of_columns(scale(-1.0, normal), t, unit(r))
                joints.append(f"""    <joint name="wrist" type="ball">
      <parent>{rod}</parent>
      <child>platform</child>
      <pose>{v3(add(bottom, scale(-1.0, p)))} {v3(rpy)}</pose>
    </joint>""")
            elif (n, side) == (1, "a"):  # the wrist: the tree's way to the platform
                links.append(small_link("wrist1", bottom))
                links.append(small_link("wrist2", bottom))
                joints.append(joint("wrist_1", "revolute", rod, "wrist1", axis=v3(normal)))
                joints.append(joint("wrist_2", "revolute", "wrist1", "wrist2", axis=v3(t)))
                joints.append(joint("wrist_3", "revolute", "wrist2", "platform",
                                    pose=f"{v3(add(bottom, scale(-1.0, p)))} 0 0 0",
                                    axis=v3(unit(r))))
            else:  # closes a loop: the rod already hangs from its arm
                balls.append(f"""    <joint name="ball{n}{side}" type="ball">
      <parent>platform</parent>
      <child>{rod}</child>
      <pose>{v3(r)} 0 0 0</pose>
    </joint>""")
    # The tool point: the platform's centre, a massless link on a fixed joint (the server's TCP
    # and the viewer's probe "tcp").
    links.append(f"""    <link name="tcp">
      <pose>{v3(p)} 0 0 0</pose>
      <inertial><mass>0</mass>
        <inertia><ixx>0</ixx><iyy>0</iyy><izz>0</izz><ixy>0</ixy><ixz>0</ixz><iyz>0</iyz></inertia></inertial>
    </link>""")
    balls.append("""    <joint name="tcp_joint" type="fixed">
      <parent>platform</parent>
      <child>tcp</child>
    </joint>""")
    return model("delta_ball" if ball_wrist else "delta", "\n".join(links + joints + balls))


# The palletising arm (spatial, z up, the model frame on the floor at the turret's axis): a
# four-axis machine whose tool flange stays level through two parallelograms in series, as on
# the palletisers of ABB (IRB 460, 660) or KUKA (KR QUANTEC PA). Axis 1 turns the turret about
# z; axis 2 tilts the lower arm forward (+y turns z towards x); axis 3 tips the upper arm down
# (+y); axis 6 turns the tool about the vertical. Parallelogram 1: the rear rod, hinged on the
# turret at h1 behind the shoulder, is as long as the lower arm and parallel to it, so the
# elbow plate (turning on the lower arm at the elbow) keeps the turret's orientation;
# parallelogram 2: the upper rod, hinged on the plate at h2 above the elbow, is as long as the
# upper arm, so the wrist flange keeps the plate's orientation: level. Every link frame is
# aligned with the model frame as drawn, its origin on its proximal joint.
PALLETISER = dict(shoulder=(0.25, 0.0, 0.6), lower=1.0, lower_tilt=0.2, upper=1.1,
                  upper_dip=0.1, h1=(-0.25, 0.0, 0.0), h2=(0.0, 0.0, 0.25), drop=0.2,
                  tool=0.15)


def palletiser_points():
    d = PALLETISER
    s = d["shoulder"]
    lower = (d["lower"] * math.sin(d["lower_tilt"]), 0.0, d["lower"] * math.cos(d["lower_tilt"]))
    upper = (d["upper"] * math.cos(d["upper_dip"]), 0.0, -d["upper"] * math.sin(d["upper_dip"]))
    e = add(s, lower)
    w = add(e, upper)
    f = add(w, (0.0, 0.0, -d["drop"]))
    return dict(S=s, E=e, W=w, F=f, T=add(f, (0.0, 0.0, -d["tool"])), lower=lower,
                upper=upper)


def box_visual(name, a, b, width, colour):
    """A box of square section `width` from a to b (link frame coordinates) in the x-z plane."""
    v = add(b, scale(-1.0, a))
    length = math.sqrt(sum(x * x for x in v))
    pitch = math.atan2(-v[2], v[0])  # turns the box's x towards v (about +y)
    return f"""      <visual name="{name}">
        <pose>{v3(add(a, scale(0.5, v)))} 0 {pitch:.17g} 0</pose>
        <geometry><box><size>{length:.17g} {width} {width}</size></box></geometry>
        {material(colour)}
      </visual>"""


def lumped_link(name, origin, mass, centre, radius, visuals):
    """A link of `mass` at `centre` (link frame) with the inertia of a solid ball of `radius`."""
    i = 0.4 * mass * radius * radius
    return f"""    <link name="{name}">
      <pose>{v3(origin)} 0 0 0</pose>
      <inertial><pose>{v3(centre)} 0 0 0</pose><mass>{mass}</mass>
        <inertia><ixx>{i:.17g}</ixx><iyy>{i:.17g}</iyy><izz>{i:.17g}</izz>
          <ixy>0</ixy><ixz>0</ixz><iyz>0</iyz></inertia></inertial>
{visuals}
    </link>"""


def palletiser():
    d, p = PALLETISER, palletiser_points()
    grey, orange = (0.35, 0.35, 0.4), (0.95, 0.55, 0.1)
    origin = (0.0, 0.0, 0.0)
    turret_visual = f"""      <visual name="column">
        <pose>0 0 0.3 0 0 0</pose>
        <geometry><cylinder><radius>0.3</radius><length>0.6</length></cylinder></geometry>
        {material(grey)}
      </visual>"""
    plate = (box_visual("to_rear_rod", origin, d["h1"], 0.06, grey) + "\n" +
             box_visual("to_upper_rod", origin, d["h2"], 0.06, grey))
    flange = (box_visual("to_upper_rod", origin, d["h2"], 0.06, grey) + "\n" +
              box_visual("drop", origin, (0.0, 0.0, -d["drop"]), 0.08, grey))
    tool = f"""      <visual name="gripper">
        <pose>0 0 {-d["tool"] / 2:.17g} 0 0 0</pose>
        <geometry><box><size>0.4 0.3 {d["tool"]:.17g}</size></box></geometry>
        {material((0.2, 0.2, 0.25))}
      </visual>"""
    links = [
        lumped_link("turret", origin, 60.0, (0.0, 0.0, 0.35), 0.3, turret_visual),
        rod_like("lower_arm", p["S"], p["lower"], 25.0, 0.07, orange),
        rod_like("rear_rod", add(p["S"], d["h1"]), p["lower"], 4.0, 0.025, grey),
        rod_like("upper_arm", p["E"], p["upper"], 18.0, 0.06, orange),
        lumped_link("plate", p["E"], 5.0, (-0.08, 0.0, 0.08), 0.1, plate),
        lumped_link("flange", p["W"], 4.0, (0.0, 0.0, -0.06), 0.08, flange),
        rod_like("upper_rod", add(p["E"], d["h2"]), p["upper"], 3.0, 0.02, grey),
        lumped_link("tool", p["F"], 8.0, (0.0, 0.0, -d["tool"] / 2), 0.15, tool),
        f"""    <link name="tcp">
      <pose>{v3(p["T"])} 0 0 0</pose>
      <inertial><mass>0</mass>
        <inertia><ixx>0</ixx><iyy>0</iyy><izz>0</izz><ixy>0</ixy><ixz>0</ixz><iyz>0</iyz></inertia></inertial>
    </link>""",
    ]
    y, z = "0 1 0", "0 0 1"
    joints = [
        joint("axis1", "revolute", "world", "turret", axis=z),
        joint("axis2", "revolute", "turret", "lower_arm", axis=y),
        joint("rear_rod_joint", "revolute", "turret", "rear_rod", axis=y),
        joint("axis3", "revolute", "lower_arm", "upper_arm", axis=y),
        joint("plate_joint", "revolute", "lower_arm", "plate", axis=y),
        joint("wrist_joint", "revolute", "upper_arm", "flange", axis=y),
        joint("upper_rod_joint", "revolute", "plate", "upper_rod", axis=y),
        joint("axis6", "revolute", "flange", "tool", axis=z),
        """    <joint name="tcp_joint" type="fixed">
      <parent>tool</parent>
      <child>tcp</child>
    </joint>""",
        # close the parallelograms: the plate and the flange already hang from the arms
        joint("rear_loop", "revolute", "rear_rod", "plate", pose=f"{v3(d['h1'])} 0 0 0", axis=y),
        joint("upper_loop", "revolute", "upper_rod", "flange", pose=f"{v3(d['h2'])} 0 0 0",
              axis=y),
    ]
    return model("palletiser", "\n".join(links + joints))


def model(name, body):
    return f"""<?xml version="1.0"?>
<!-- Generated by generate.py: edit that, not this file. -->
<sdf version="1.7">
  <model name="{name}">
{body}
  </model>
</sdf>
"""


if __name__ == "__main__":
    # A parallelogram: opposite bars equal (crank = rocker 0.2 m, coupler = ground 0.4 m),
    # drawn hanging, the crank at -60 degrees; the coupler stays parallel to the ground.
    parallelogram = four_bar("parallelogram", a=0.2, b=0.4, c=0.2, d=0.4, theta2=-math.pi / 3,
                             side=-1)
    for name, text in (("four_bar.sdf", four_bar()), ("slider_crank.sdf", slider_crank()),
                       ("parallelogram.sdf", parallelogram), ("delta.sdf", delta()),
                       ("palletiser.sdf", palletiser())):
        with open(name, "w") as f:
            f.write(text)
    # Each linkage's scene script, from its model (scene_writer.py).
    titles = {"four_bar": "Four-bar linkage (crank-rocker)", "slider_crank": "Slider-crank",
              "parallelogram": "Parallelogram linkage", "delta": "Delta robot",
              "palletiser": "Palletising arm with two parallelograms"}
    for name, title in titles.items():
        with open(f"{name}.sdf") as f:
            text = scene_writer.scene_script(f.read(), title)
        with open(f"{name}.scene", "w") as f:
            f.write(text)
    # The Delta with a ball joint inside the tree, for tests/server/loops/ball_joint_test.cc.
    with open("../../tests/data/delta_ball.sdf", "w") as f:
        f.write(delta(ball_wrist=True))
