#!/usr/bin/env python3
"""Writes resources/examples/vase.obj (+ vase.mtl): a floor vase 80 cm tall, a surface of
revolution with exact normals, for image-based objects (relume ibr-fan). Run from anywhere:
    python3 resources/scripts/make_example_objects.py
"""
import math
import os

OUT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "examples")
SEGMENTS, RINGS, WALL = 64, 48, 0.012
# Radius (m) against height (m): a foot, a belly, a neck and a flared lip.
PROFILE = [(0.0, 0.10), (0.02, 0.12), (0.18, 0.19), (0.32, 0.20), (0.50, 0.15), (0.64, 0.075), (0.72, 0.07), (0.80, 0.10)]


def radius(z):
    """Smooth (Catmull-Rom) radius through PROFILE, and its derivative dr/dz."""
    pts = PROFILE
    for i in range(len(pts) - 1):
        if pts[i][0] <= z <= pts[i + 1][0]:
            break
    p0 = pts[max(i - 1, 0)][1]
    p1, p2 = pts[i][1], pts[i + 1][1]
    p3 = pts[min(i + 2, len(pts) - 1)][1]
    h = pts[i + 1][0] - pts[i][0]
    t = (z - pts[i][0]) / h
    r = 0.5 * ((2 * p1) + (-p0 + p2) * t + (2 * p0 - 5 * p1 + 4 * p2 - p3) * t * t + (-p0 + 3 * p1 - 3 * p2 + p3) * t ** 3)
    dr = 0.5 * ((-p0 + p2) + 2 * (2 * p0 - 5 * p1 + 4 * p2 - p3) * t + 3 * (-p0 + 3 * p1 - 3 * p2 + p3) * t * t) / h
    return r, dr


def main():
    v, vn, f = [], [], []

    def surface(offset, inward, z_top):
        base = len(v)
        for j in range(RINGS + 1):
            z = z_top * j / RINGS
            r, dr = radius(z)
            r -= offset
            for i in range(SEGMENTS):
                a = 2 * math.pi * i / SEGMENTS
                v.append((r * math.cos(a), r * math.sin(a), z))
                n = (math.cos(a), math.sin(a), -dr)
                l = math.sqrt(n[0] ** 2 + n[1] ** 2 + n[2] ** 2)
                s = -1 if inward else 1
                vn.append((s * n[0] / l, s * n[1] / l, s * n[2] / l))
        for j in range(RINGS):
            for i in range(SEGMENTS):
                a = base + j * SEGMENTS + i
                b = base + j * SEGMENTS + (i + 1) % SEGMENTS
                c, d = a + SEGMENTS, b + SEGMENTS
                f.append((a, b, d, c) if not inward else (a, c, d, b))
        return base

    top = PROFILE[-1][0]
    outer = surface(0.0, False, top)
    inner = surface(WALL, True, top)
    # The lip joins the two top rings; the bottom is a disc facing down.
    lip_n = len(vn)
    vn.append((0.0, 0.0, 1.0))
    vn.append((0.0, 0.0, -1.0))
    for i in range(SEGMENTS):
        o = outer + RINGS * SEGMENTS
        n = inner + RINGS * SEGMENTS
        f.append(((o + i, lip_n), (o + (i + 1) % SEGMENTS, lip_n), (n + (i + 1) % SEGMENTS, lip_n), (n + i, lip_n)))
    centre = len(v)
    v.append((0.0, 0.0, 0.0))
    for i in range(SEGMENTS):
        f.append(((centre, lip_n + 1), (outer + (i + 1) % SEGMENTS, lip_n + 1), (outer + i, lip_n + 1)))
    with open(os.path.join(OUT, "vase.mtl"), "w") as m:
        m.write("# A terracotta glaze (linear diffuse albedo)\nnewmtl terracotta\nKd 0.55 0.22 0.12\n")
    with open(os.path.join(OUT, "vase.obj"), "w") as o:
        o.write("# A floor vase, 80 cm tall, metres, +Z up (resources/scripts/make_example_objects.py)\n")
        o.write("mtllib vase.mtl\nusemtl terracotta\n")
        for p in v:
            o.write("v %.4f %.4f %.4f\n" % p)
        for n in vn:
            o.write("vn %.4f %.4f %.4f\n" % n)
        for face in f:
            if isinstance(face[0], tuple):
                o.write("f " + " ".join("%d//%d" % (a + 1, b + 1) for a, b in face) + "\n")
            else:
                o.write("f " + " ".join("%d//%d" % (a + 1, a + 1) for a in face) + "\n")


if __name__ == "__main__":
    main()
