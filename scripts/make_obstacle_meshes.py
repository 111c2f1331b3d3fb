#!/usr/bin/env python3
"""Writes the demonstration scenes' obstacle meshes (issue 17), as closed, outward-oriented
triangle surfaces in OBJ, in their own frames (the configs place them):

  configs/meshes/hoop.obj  an NBA rim: a torus about the z axis through the origin, inner
                           diameter 0.4572 m (18 in), tube radius 0.008 m, so its ring (the tube's
                           centre line) has radius 0.2366 m; 64 segments around the ring, 12 around
                           the tube. Vertices lie on the true torus; the innermost chords sit
                           (R - r)(1 - cos(pi / 64)) = 0.28 mm inside the 0.2286 m inner radius.
  configs/meshes/bin.obj   an open-top bin: a solid box with a box-shaped cavity open at the
                           top, centred on the z axis, standing on z = 0. Inner size
                           2 x INNER_HALF_X by 2 x INNER_HALF_Y, walls WALL thick, floor FLOOR
                           thick, HEIGHT tall (the defaults below; see configs/demos/bunny_bin.yaml
                           for how they were chosen).

Each triangle is oriented by an outward hint (a direction that leaves the solid there), so both
surfaces are closed and consistently oriented; tests/mesh/test_obstacle_meshes.cpp checks that.

    python3 scripts/make_obstacle_meshes.py            # rewrites both files
"""
import math
import os
import sys

HOOP_INNER_RADIUS = 0.4572 / 2  # m
HOOP_TUBE_RADIUS = 0.008        # m
HOOP_RING_SEGMENTS = 64
HOOP_TUBE_SEGMENTS = 12

BIN_INNER_HALF_X = 2.0  # m
BIN_INNER_HALF_Y = 6.25  # m
BIN_HEIGHT = 1.5        # m, outer
BIN_WALL = 0.05         # m
BIN_FLOOR = 0.05        # m


def sub(a, b):
    return [a[i] - b[i] for i in range(3)]


def cross(a, b):
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]


def dot(a, b):
    return sum(a[i] * b[i] for i in range(3))


class Surface:
    def __init__(self):
        self.vertices = []
        self.faces = []

    def vertex(self, p):
        self.vertices.append(p)
        return len(self.vertices) - 1

    def triangle(self, a, b, c, outward):
        """Adds (a, b, c), flipped if its normal does not point along `outward`."""
        va, vb, vc = (self.vertices[i] for i in (a, b, c))
        n = cross(sub(vb, va), sub(vc, va))
        self.faces.append((a, b, c) if dot(n, outward) > 0 else (a, c, b))

    def quad(self, a, b, c, d, outward):
        """A planar quad a-b-c-d (in order around it) as two triangles."""
        self.triangle(a, b, c, outward)
        self.triangle(a, c, d, outward)

    def write(self, path, header):
        tmp = path + ".tmp"
        with open(tmp, "w") as out:
            for line in header:
                out.write("# " + line + "\n")
            for p in self.vertices:
                out.write("v %.9g %.9g %.9g\n" % tuple(p))
            for f in self.faces:
                out.write("f %d %d %d\n" % (f[0] + 1, f[1] + 1, f[2] + 1))
        os.replace(tmp, path)  # atomic


def hoop():
    s = Surface()
    R = HOOP_INNER_RADIUS + HOOP_TUBE_RADIUS
    r = HOOP_TUBE_RADIUS
    n, m = HOOP_RING_SEGMENTS, HOOP_TUBE_SEGMENTS
    index = {}
    for i in range(n):
        u = 2 * math.pi * i / n
        for j in range(m):
            v = 2 * math.pi * j / m
            index[i, j] = s.vertex([(R + r * math.cos(v)) * math.cos(u),
                                    (R + r * math.cos(v)) * math.sin(u), r * math.sin(v)])
    for i in range(n):
        for j in range(m):
            a, b = index[i, j], index[(i + 1) % n, j]
            c, d = index[(i + 1) % n, (j + 1) % m], index[i, (j + 1) % m]
            # Outward: from the tube's centre line towards the quad.
            um = 2 * math.pi * (i + 0.5) / n
            vm = 2 * math.pi * (j + 0.5) / m
            hint = [math.cos(vm) * math.cos(um), math.cos(vm) * math.sin(um), math.sin(vm)]
            s.quad(a, b, c, d, hint)
    return s


def bin_mesh():
    s = Surface()
    ax, ay = BIN_INNER_HALF_X, BIN_INNER_HALF_Y
    bx, by = ax + BIN_WALL, ay + BIN_WALL
    H, f = BIN_HEIGHT, BIN_FLOOR
    corners = [(-1, -1), (1, -1), (1, 1), (-1, 1)]
    bottom = [s.vertex([sx * bx, sy * by, 0.0]) for sx, sy in corners]
    top_out = [s.vertex([sx * bx, sy * by, H]) for sx, sy in corners]
    top_in = [s.vertex([sx * ax, sy * ay, H]) for sx, sy in corners]
    floor = [s.vertex([sx * ax, sy * ay, f]) for sx, sy in corners]
    s.quad(*bottom, [0, 0, -1])                  # underside
    s.quad(*floor, [0, 0, 1])                    # the cavity's floor, facing up into it
    for k in range(4):
        k1 = (k + 1) % 4
        mid = [0.5 * (corners[k][0] + corners[k1][0]), 0.5 * (corners[k][1] + corners[k1][1]), 0.0]
        s.quad(bottom[k], bottom[k1], top_out[k1], top_out[k], mid)          # outer wall
        s.quad(floor[k], floor[k1], top_in[k1], top_in[k], [-x for x in mid])  # inner wall, into the cavity
        s.quad(top_out[k], top_out[k1], top_in[k1], top_in[k], [0, 0, 1])   # the rim's top
    return s


def main():
    root = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "configs", "meshes")
    hoop().write(os.path.join(root, "hoop.obj"), [
        "An NBA rim (scripts/make_obstacle_meshes.py): torus about z through the origin, inner",
        "diameter 0.4572 m, tube radius 0.008 m (ring radius 0.2366 m); closed, outward."])
    bin_mesh().write(os.path.join(root, "bin.obj"), [
        "An open-top bin (scripts/make_obstacle_meshes.py): cavity %g x %g m, %g m tall outside,"
        % (2 * BIN_INNER_HALF_X, 2 * BIN_INNER_HALF_Y, BIN_HEIGHT),
        "walls %g m and floor %g m thick, centred on z, standing on z = 0; closed, outward."
        % (BIN_WALL, BIN_FLOOR)])
    return 0


if __name__ == "__main__":
    sys.exit(main())
