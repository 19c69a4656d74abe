"""Writes a linkage's scene script (the viewer's scene language, viewer/README.md) from its
SDFormat text, as generate.py writes it: every pose relative to the model frame (links) or to
the child link (joints, visuals), axes in the joint frame.

The Device is the spanning tree the reader chooses (shared/model_files/sdf_reading.h: breadth-first
from the world, each link's joints in file order; a joint whose child already has a parent is
cut), its moving joints numbered in that order, which is the server's joint order: a run's
joint values pose the script's joints one for one. Each joint turns (slides) about its axis a:
the script's joints turn about z, so a joint's pre-transform ends with Q (z onto a) and its
post-transform is Q^-1, which leaves each link frame the model's. A link on a fixed joint
draws in the frame it hangs from; the link named tcp is the Device's Tcp. Each visual is a
part (Cube, Cylinder, Sphere) placed in its link's frame, in its <material>'s colour.
Lengths mm, angles degrees (the language's units)."""
import math
import xml.etree.ElementTree as ET

IDENTITY = ((1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0))


def mat_mul(a, b):
    return tuple(tuple(sum(a[i][k] * b[k][j] for k in range(3)) for j in range(3))
                 for i in range(3))


def mat_vec(a, v):
    return tuple(sum(a[i][k] * v[k] for k in range(3)) for i in range(3))


def transpose(a):
    return tuple(tuple(a[j][i] for j in range(3)) for i in range(3))


def compose(x, y):  # (R, p) * (R, p)
    return (mat_mul(x[0], y[0]), tuple(a + b for a, b in zip(mat_vec(x[0], y[1]), x[1])))


def inverse(x):
    rt = transpose(x[0])
    return (rt, tuple(-c for c in mat_vec(rt, x[1])))


def rot_axis(axis, angle):
    x, y, z = axis
    c, s, t = math.cos(angle), math.sin(angle), 1.0 - math.cos(angle)
    return ((t * x * x + c, t * x * y - s * z, t * x * z + s * y),
            (t * x * y + s * z, t * y * y + c, t * y * z - s * x),
            (t * x * z - s * y, t * y * z + s * x, t * z * z + c))


def pose_of(element):
    """The <pose> child of `element` as (R, p): SDFormat's x y z roll pitch yaw."""
    pose = element.find("pose")
    v = [float(x) for x in pose.text.split()] if pose is not None else [0.0] * 6
    roll, pitch, yaw = v[3:6]
    R = mat_mul(rot_axis((0, 0, 1), yaw), mat_mul(rot_axis((0, 1, 0), pitch),
                                                 rot_axis((1, 0, 0), roll)))
    return (R, tuple(v[0:3]))


def z_onto(a):
    """A rotation taking z onto the unit vector a."""
    n = math.sqrt(sum(c * c for c in a))
    a = tuple(c / n for c in a)
    axis = (-a[1], a[0], 0.0)  # z x a
    s = math.hypot(axis[0], axis[1])
    if s < 1e-12:
        return IDENTITY if a[2] > 0 else rot_axis((1, 0, 0), math.pi)
    return rot_axis((axis[0] / s, axis[1] / s, 0.0), math.atan2(s, a[2]))


def euler_zyz(R):
    """Degrees (e1, e2, e3) with R = Rz(e1) Ry(e2) Rz(e3)."""
    e2 = math.atan2(math.hypot(R[0][2], R[1][2]), R[2][2])
    if math.sin(e2) > 1e-9:
        e1 = math.atan2(R[1][2], R[0][2])
        e3 = math.atan2(R[2][1], -R[2][0])
    elif R[2][2] > 0:
        e1, e3 = math.atan2(R[1][0], R[0][0]), 0.0
    else:
        e1, e3 = math.atan2(-R[0][1], -R[0][0]), 0.0
    return tuple(math.degrees(e) for e in (e1, e2, e3))


def number(x):
    text = f"{x:.10f}".rstrip("0").rstrip(".")
    return "0" if text in ("-0", "") else text


def clause(x):
    """A transform clause (shift in mm, ZYZ Euler in degrees) for (R, p) in metres."""
    words = []
    for name, value in zip("xyz", x[1]):
        if abs(value) > 1e-12:
            words.append(f"{name} {number(1000.0 * value)}")
    euler = euler_zyz(x[0])
    if any(abs(e) > 1e-9 for e in euler):
        words.append("euler " + " ".join(number(e) for e in euler))
    return f"({' '.join(words)})" if words else ""


def spanning_tree(joints):
    reached, order, queue = {"world"}, [], ["world"]
    while queue:
        link = queue.pop(0)
        for j in joints:
            if j.find("parent").text != link or j.find("child").text in reached:
                continue
            reached.add(j.find("child").text)
            order.append(j)
            queue.append(j.find("child").text)
    return order


def visual_part(title, visual):
    """(part command, placement of the part's own frame in the visual frame)."""
    geometry = visual.find("geometry")
    box, cylinder, sphere = (geometry.find(k) for k in ("box", "cylinder", "sphere"))
    if box is not None:
        size = [float(x) for x in box.find("size").text.split()]
        mm = " ".join(number(1000.0 * s) for s in size)
        return f"Cube {title} {mm};", (IDENTITY, tuple(-s / 2 for s in size))
    if cylinder is not None:
        r, length = float(cylinder.find("radius").text), float(cylinder.find("length").text)
        return (f"Cylinder {title} dia {number(2000.0 * r)} res 24 len {number(1000.0 * length)};",
                (IDENTITY, (0.0, 0.0, -length / 2)))
    r = float(sphere.find("radius").text)
    return f"Sphere {title} radius {number(1000.0 * r)} res 16;", (IDENTITY, (0.0, 0.0, 0.0))


def colour_of(visual):
    material = visual.find("material")
    colour = material.find("diffuse") if material is not None else None
    return " ".join(number(float(c)) for c in colour.text.split()[:3]) if colour is not None else None


def device_lines(model, tree, X_ML):
    """The Device's joint lines; each link's Device frame number and the frames in the model
    frame (G: Device frame -> pose at q = 0; F: link -> its frame)."""
    fixed_tcp = {f.find("parent").text: f.find("child").text for f in model.findall("joint")
                 if f.get("type") == "fixed" and f.find("child").text.lower() in ("tcp", "tool0")}
    frame = {"world": 0}
    G = {0: (IDENTITY, (0.0, 0.0, 0.0))}
    F = {"world": G[0]}
    lines, previous, moving = [], 0, 0
    for j in tree:
        parent, child = j.find("parent").text, j.find("child").text
        if j.get("type") == "fixed":
            frame[child] = frame[parent]
            F[child] = X_ML[child]
            continue
        X_MJ = compose(X_ML[child], pose_of(j))
        Q = (z_onto([float(c) for c in j.find("axis").find("xyz").text.split()]),
             (0.0, 0.0, 0.0))
        moving += 1
        if frame[parent] != previous:
            lines.append(f"  Extend {frame[parent]}")
        pre = compose(compose(inverse(G[frame[parent]]), X_MJ), Q)
        kind = "prismatic" if j.get("type") == "prismatic" else "revolute"
        words = ["  Joint", str(moving), clause(pre), kind, "z", clause(inverse(Q))]
        lines.append(" ".join(w for w in words if w))
        previous = frame[child] = moving
        G[moving] = F[child] = X_MJ
        if child in fixed_tcp:  # the Tcp sits on the joint just defined
            lines.append(f"  Tcp {clause(compose(inverse(X_MJ), X_ML[fixed_tcp[child]])) or '(x 0)'}")
    return lines, frame, G, F


def scene_script(sdf_text, title):
    model = ET.fromstring(sdf_text).find("model")
    name = model.get("name")
    links = {l.get("name"): l for l in model.findall("link")}
    X_ML = {n: pose_of(l) for n, l in links.items()}
    lines, frame, G, F = device_lines(model, spanning_tree(model.findall("joint")), X_ML)
    out = [f"! {title}",
           "! Generated by models/linkages/generate.py (scene_writer.py) from "
           f"{name}.sdf: edit those, not this file.",
           "! Lengths mm, angles degrees. The Device is the model's spanning tree in the server's",
           "! joint order (the cut joints pose nothing: the tree's values close the loops).",
           f"Device {name}"] + lines + ["  ;", ""]
    by_frame = {}  # Device frame -> [(part, placement, colour)]
    for link_name, link in links.items():
        k = frame[link_name]
        X_GL = compose(inverse(G[k]), F[link_name])
        for visual in link.findall("visual"):
            part = f"{link_name}_{visual.get('name')}"
            command, X_VP = visual_part(part, visual)
            out.append(command)
            by_frame.setdefault(k, []).append(
                (part, compose(compose(X_GL, pose_of(visual)), X_VP), colour_of(visual)))
    out.append("")
    for k, parts in sorted(by_frame.items()):
        device_frame = name if k == 0 else f"{name}#{k}"
        placed = " ".join(f"{part} {clause(x)}".rstrip() for part, x, _ in parts)
        out.append(f"Set {device_frame} add {placed};")
        if parts[0][2] is not None:
            out.append(f"Render {device_frame} color {parts[0][2]};")
        for part, _, colour in parts[1:]:
            if colour is not None and colour != parts[0][2]:
                out.append(f"Render {part} color {colour};")
    return "\n".join(out) + "\n"
