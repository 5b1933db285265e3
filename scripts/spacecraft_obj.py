#!/usr/bin/env python3
"""Write examples/data/spacecraft-full.obj: a GEO-like spacecraft for mote's charging benchmarks
(issue 55, item 5): a 2 m cubic bus, two 1.5 m x 4 m solar-panel sheets on yokes along +-y, a
3 m boom along -z and a 1.6 m parabolic dish on the +x face. Made for mote; metres. Usage:
python3 scripts/spacecraft_obj.py > examples/data/spacecraft-full.obj"""
import math

verts, groups = [], []


def vertex(p):
    verts.append(p)
    return len(verts)


def quad_grid(origin, du, dv, nu, nv, faces, flip=False):
    """A planar grid of nu x nv quads (two triangles each) from origin along du, dv."""
    idx = [[vertex(tuple(origin[k] + du[k] * i / nu + dv[k] * j / nv for k in range(3)))
            for j in range(nv + 1)] for i in range(nu + 1)]
    for i in range(nu):
        for j in range(nv):
            a, b, c, d = idx[i][j], idx[i + 1][j], idx[i + 1][j + 1], idx[i][j + 1]
            faces += [(a, c, b), (a, d, c)] if flip else [(a, b, c), (a, c, d)]


def box(lo, hi, n, faces):
    """A closed box from lo to hi, each face an n x n grid, wound outward."""
    sx, sy, sz = (hi[k] - lo[k] for k in range(3))
    x0, y0, z0 = lo
    x1, y1, z1 = hi
    quad_grid((x0, y0, z0), (0, sy, 0), (0, 0, sz), n, n, faces, True)  # -x
    quad_grid((x1, y0, z0), (0, 0, sz), (0, sy, 0), n, n, faces, True)  # +x
    quad_grid((x0, y0, z0), (0, 0, sz), (sx, 0, 0), n, n, faces, True)  # -y
    quad_grid((x0, y1, z0), (sx, 0, 0), (0, 0, sz), n, n, faces, True)  # +y
    quad_grid((x0, y0, z0), (sx, 0, 0), (0, sy, 0), n, n, faces, True)  # -z
    quad_grid((x0, y0, z1), (0, sy, 0), (sx, 0, 0), n, n, faces, True)  # +z


def dish(centre, radius, depth, rings, sectors, faces):
    """A paraboloid sheet opening toward +x: x = centre_x + depth (r / radius)^2."""
    cx, cy, cz = centre
    apex = vertex((cx, cy, cz))
    prev = None
    for i in range(1, rings + 1):
        r = radius * i / rings
        ring = [vertex((cx + depth * (r / radius) ** 2, cy + r * math.cos(2 * math.pi * s / sectors),
                        cz + r * math.sin(2 * math.pi * s / sectors))) for s in range(sectors)]
        for s in range(sectors):
            t = (s + 1) % sectors
            if prev is None:
                faces.append((apex, ring[s], ring[t]))
            else:
                faces += [(prev[s], ring[s], ring[t]), (prev[s], ring[t], prev[t])]
        prev = ring


def group(name, build):
    faces = []
    build(faces)
    groups.append((name, faces))


group("bus", lambda f: box((-1, -1, -1), (1, 1, 1), 4, f))
group("yoke_left", lambda f: box((-0.05, -1.5, -0.05), (0.05, -1, 0.05), 1, f))
group("yoke_right", lambda f: box((-0.05, 1, -0.05), (0.05, 1.5, 0.05), 1, f))
group("panel_left", lambda f: quad_grid((-0.75, -5.5, 0), (1.5, 0, 0), (0, 4, 0), 2, 8, f))
group("panel_right", lambda f: quad_grid((-0.75, 1.5, 0), (1.5, 0, 0), (0, 4, 0), 2, 8, f))
group("boom", lambda f: box((0.45, -0.05, -4), (0.55, 0.05, -1), 1, f))
group("dish", lambda f: dish((1.05, 0, 0.2), 0.8, 0.3, 6, 24, f))

print("# a GEO-like spacecraft for mote's charging benchmarks (issue 55): a 2 m cubic bus, two")
print("# 1.5 m x 4 m solar-panel sheets on yokes along +-y, a 3 m boom along -z and a 1.6 m dish")
print("# on the +x face (made for mote by scripts/spacecraft_obj.py; metres)")
print("o spacecraft")
for v in verts:
    print("v %.6g %.6g %.6g" % v)
for name, faces in groups:
    print("g " + name)
    for a, b, c in faces:
        print("f %d %d %d" % (a, b, c))
