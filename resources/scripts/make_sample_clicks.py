#!/usr/bin/env python3
"""Simulated TotalCalib clicks for a room bundle: what a careful user would click.

    python3 resources/scripts/make_sample_clicks.py resources/sample_room > resources/sample_room/clicks.json

Every polygon corner of the bundle's true geometry is projected into each photo where it is in
frame and not hidden by another polygon; the click lands on the centre of the pixel the corner
falls in (a user clicks pixels, so the error is up to half a pixel per axis). Corners clicked in
fewer than two photos become typed measurements ("xyz"), rounded to 5 mm as a tape measure
reads. Corners shared by several polygons are one named point. Quadrilaterals are marked as
rectangles and lamps carry their names; nothing else of the truth (albedo, lamp strength) is
written. The output is the CLICKS.json of `relume triangulate`.
"""

import json
import math
import os
import sys


def sub(a, b):
    return [a[i] - b[i] for i in range(3)]


def dot(a, b):
    return sum(a[i] * b[i] for i in range(3))


def cross(a, b):
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]


def normal(vs):
    n = [0.0, 0.0, 0.0]
    for i in range(len(vs)):
        a, b = vs[i], vs[(i + 1) % len(vs)]
        n[0] += (a[1] - b[1]) * (a[2] + b[2])
        n[1] += (a[2] - b[2]) * (a[0] + b[0])
        n[2] += (a[0] - b[0]) * (a[1] + b[1])
    L = math.sqrt(dot(n, n))
    return [x / L for x in n]


def hits(origin, target, poly):
    """Does the open segment origin->target cross the convex polygon before reaching target?"""
    vs = poly["vertices"]
    n = normal(vs)
    d = sub(target, origin)
    den = dot(n, d)
    if abs(den) < 1e-12:
        return False
    t = dot(n, sub(vs[0], origin)) / den
    length = math.sqrt(dot(d, d))
    if t <= 1e-6 or t >= 1 - 0.01 / length:  # within 1 cm of the corner: its own surfaces
        return False
    p = [origin[i] + t * d[i] for i in range(3)]
    for i in range(len(vs)):
        a, b = vs[i], vs[(i + 1) % len(vs)]
        if dot(cross(sub(b, a), sub(p, a)), n) < -1e-9:
            return False
    return True


def project(photo, X):
    R, t, K = photo["R"], photo["t"], photo["K"]
    c = [sum(R[r][k] * X[k] for k in range(3)) + t[r] for r in range(3)]
    if c[2] <= 1e-6:
        return None
    return [K[0][0] * c[0] / c[2] + K[0][2], K[1][1] * c[1] / c[2] + K[1][2]]


def centre(photo):
    R, t = photo["R"], photo["t"]
    return [-sum(R[k][r] * t[k] for k in range(3)) for r in range(3)]


def is_rectangle(vs):
    if len(vs) != 4:
        return False
    for i in range(4):
        a, b, c = vs[i - 1], vs[i], vs[(i + 1) % 4]
        u, v = sub(a, b), sub(c, b)
        if abs(dot(u, v)) > 1e-6 * math.sqrt(dot(u, u) * dot(v, v)):
            return False
    return True


def main():
    bundle = sys.argv[1]
    scene = json.load(open(os.path.join(bundle, "scene.json")))
    polys = scene["polygons"]
    photos = scene["photos"]
    def vkey(vs):
        return tuple(sorted(tuple(round(x, 6) for x in v) for v in vs))
    lamp_of = {vkey(l["polygon"]): l["name"] for l in scene.get("lights", [])}
    points, names = {}, {}
    out_polys = []
    for poly in polys:
        if poly.get("kind") == "window":
            continue
        corners = []
        for X in poly["vertices"]:
            key = tuple(round(x, 6) for x in X)
            if key not in names:
                name = "p%d" % len(names)
                names[key] = name
                clicks = {}
                for ph in photos:
                    px = project(ph, X)
                    if px is None:
                        continue
                    if not (1 <= px[0] <= ph["width"] - 1 and 1 <= px[1] <= ph["height"] - 1):
                        continue
                    if any(hits(centre(ph), X, q) for q in polys if q is not poly):
                        continue
                    clicks[ph["name"]] = [math.floor(px[0]) + 0.5, math.floor(px[1]) + 0.5]
                if len(clicks) >= 2:
                    points[name] = clicks
                else:
                    points[name] = {"xyz": [round(x / 0.005) * 0.005 for x in X]}
            corners.append(names[key])
        entry = {"name": poly["name"], "group": poly["group"], "corners": corners}
        if vkey(poly["vertices"]) in lamp_of:
            entry["lamp"] = lamp_of[vkey(poly["vertices"])]
        if is_rectangle(poly["vertices"]):
            entry["rectangle"] = True
        out_polys.append(entry)
    clicked = sum(1 for p in points.values() if "xyz" not in p)
    json.dump({"main": scene.get("main_photo", "main"),
               "note": "simulated clicks: %d points clicked in 2+ photos (pixel centres), %d typed (5 mm)"
                       % (clicked, len(points) - clicked),
               "points": points, "polygons": out_polys}, sys.stdout, indent=1)
    sys.stdout.write("\n")


if __name__ == "__main__":
    main()
