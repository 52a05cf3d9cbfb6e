#!/usr/bin/python3
"""Writes a big game-like level as a scene TOML, for scaling the bake (issue 16).

    /usr/bin/python3 bench/make_level.py --triangles 1000000 -o build/level_1m.toml

A grid of rooms (default 10 x 10) joined by doorways, each lit by one ceiling panel (an area
light of 30..120 W: ~100 lights), with a planar mirror on a wall, a mirror ball or a glossy
metal ring, a glass ball, and `sets` instanced furniture groups (a table with a glass vase and
a glossy metal bowl, four chairs). Two knobs set the size: `sets` (groups per room; the rooms
grow to hold them) and `segments` (the tessellation of every curved shape). `--triangles N`
picks both (sets ~ sqrt(N / 100k), then the segments whose total is nearest N) and prints the
count the loader will make, exactly (`lightbake info FILE` agrees). Standard library only;
the same arguments always write the same file.
"""

import argparse
import math
import sys

ROOM_HEIGHT = 3.0    # m, floor to ceiling
WALL = 0.2           # m, wall thickness
DOOR_WIDTH = 1.0     # m
DOOR_HEIGHT = 2.1    # m
SET_SPACING = 2.4    # m, the square a furniture set needs (table 1.2 x 0.8 m plus chairs)
PANEL = (1.2, 0.6)   # m, ceiling panel light
PANEL_POWERS = [30, 45, 60, 75, 90, 105, 120]  # W, cycled over the rooms
# The glass vase: an open profile (radius, height) in m, bottom centre to rim, walls 4 mm.
VASE_PROFILE = [(0.0, 0.0), (0.05, 0.0), (0.07, 0.05), (0.065, 0.14), (0.035, 0.21),
                (0.04, 0.25)]
VASE_THICKNESS = 0.004


# Triangles the loader makes for each shape (bake/io/shapes.cpp: two per grid cell, minus the
# cells collapsed onto a pole or the axis).
def tris_box():
    return 12


def tris_quad():
    return 2


def tris_sphere(rings, segments):
    return 2 * segments * (rings - 1)


def tris_torus(rings, segments):
    return 2 * rings * segments


def tris_cylinder(segments):
    return 4 * segments  # wall 2s, each cap disc s


def tris_vase(segments):
    # the thick profile is one loop of 2P points: 2P - 1 bands of 2s, the two on the axis s
    return 2 * segments * (2 * len(VASE_PROFILE) - 1) - 2 * segments


def shape_segments(segments):
    """Segments of each curved shape for the knob `segments` (the largest shapes get it,
    the thin legs a quarter)."""
    return dict(ball=segments, ball_rings=max(2, segments // 2), ring=segments,
                ring_rings=max(3, segments // 4), vase=max(3, segments // 2),
                bowl=max(3, segments // 2), bowl_rings=max(3, segments // 4),
                leg=max(3, segments // 4))


def rooms_walls(nx, nz):
    """Wall boxes of an nx x nz grid: the outer walls whole, each inner wall with a doorway
    (two pieces and a lintel)."""
    outer = 2 * (nx + nz)
    inner = (nx - 1) * nz + (nz - 1) * nx
    return outer + 3 * inner


def count(nx, nz, sets, segments):
    s = shape_segments(segments)
    rooms = nx * nz
    per_set = (tris_box() + 4 * tris_cylinder(s["leg"])        # table
               + 4 * (2 * tris_box() + 4 * tris_cylinder(s["leg"]))  # chairs
               + tris_vase(s["vase"]) + tris_torus(s["bowl_rings"], s["bowl"]))
    per_room = (2 * tris_quad()          # floor, ceiling
                + tris_quad()            # ceiling panel light
                + tris_quad()            # planar mirror
                + tris_sphere(s["ball_rings"], s["ball"])  # glass ball
                + sets * per_set)
    # every other room a mirror ball, the rest a glossy metal ring
    mirror_balls = (rooms + 1) // 2
    curved = (mirror_balls * tris_sphere(s["ball_rings"], s["ball"])
              + (rooms - mirror_balls) * tris_torus(s["ring_rings"], s["ring"]))
    return rooms * per_room + curved + rooms_walls(nx, nz) * tris_box()


def choose(triangles, nx, nz):
    """(sets, segments) whose count is nearest `triangles`."""
    sets = max(1, round(math.sqrt(triangles / 1e5)))
    best = None
    for segments in range(8, 4096):
        n = count(nx, nz, sets, segments)
        if best is None or abs(n - triangles) < abs(best[1] - triangles):
            best = (segments, n)
        if n > triangles:
            break
    return sets, best[0]


def fmt(v):
    return f"{v:.6g}"


def vec(*v):
    return "[" + ", ".join(fmt(x) for x in v) + "]"


def box(name, lo, hi, material):
    return (f'[[objects]]\nname = "{name}"\nshape = "box"\nmin = {vec(*lo)}\nmax = {vec(*hi)}\n'
            f'material = "{material}"\n\n')


def definitions(segments):
    s = shape_segments(segments)
    leg = s["leg"]
    out = []

    def part(owner, text):
        out.append(f"[[define.{owner}]]\n{text}\n")

    part("table", 'name = "top"\nshape = "box"\nmin = [-0.6, 0.71, -0.4]\nmax = [0.6, 0.75, 0.4]\n'
         'material = "wood"')
    for i, (x, z) in enumerate([(-0.55, -0.35), (0.55, -0.35), (-0.55, 0.35), (0.55, 0.35)]):
        part("table", f'name = "leg{i + 1}"\nshape = "cylinder"\nradius = 0.02\nheight = 0.71\n'
             f'segments = {leg}\ntranslate = {vec(x, 0.355, z)}\nmaterial = "steel"')
    part("chair", 'name = "seat"\nshape = "box"\nmin = [-0.225, 0.43, -0.225]\n'
         'max = [0.225, 0.47, 0.225]\nmaterial = "wood"')
    part("chair", 'name = "back"\nshape = "box"\nmin = [-0.225, 0.47, -0.235]\n'
         'max = [0.225, 0.9, -0.205]\nmaterial = "wood"')
    for i, (x, z) in enumerate([(-0.2, -0.2), (0.2, -0.2), (-0.2, 0.2), (0.2, 0.2)]):
        part("chair", f'name = "leg{i + 1}"\nshape = "cylinder"\nradius = 0.012\nheight = 0.43\n'
             f'segments = {leg}\ntranslate = {vec(x, 0.215, z)}\nmaterial = "steel"')
    # A set: the table, a glass vase and a metal bowl on it, a chair on each side facing it.
    part("set", 'name = "table"\ninstance = "table"')
    profile = ", ".join(vec(r, y) for r, y in VASE_PROFILE)
    part("set", f'name = "vase"\nshape = "revolution"\nprofile = [{profile}]\n'
         f'thickness = {VASE_THICKNESS}\nsegments = {s["vase"]}\ntranslate = [-0.3, 0.75, 0]\n'
         'material = "glass"')
    part("set", f'name = "bowl"\nshape = "torus"\nmajor_radius = 0.08\nminor_radius = 0.025\n'
         f'rings = {s["bowl_rings"]}\nsegments = {s["bowl"]}\ntranslate = [0.3, 0.775, 0]\n'
         'material = "gold"')
    for i, (x, z, turn) in enumerate([(0, -0.75, 0), (0, 0.75, 180), (-0.95, 0, 90),
                                      (0.95, 0, 270)]):
        part("set", f'name = "chair{i + 1}"\ninstance = "chair"\ntranslate = {vec(x, 0, z)}\n'
             f'rotate = {vec(0, turn, 0)}')
    return "".join(out)


def level(nx, nz, sets, segments):
    s = shape_segments(segments)
    cols = math.ceil(math.sqrt(sets))
    rows = math.ceil(sets / cols)
    # interior size: the sets' grid plus 1.2 m around it for the ball, ring and doorways
    width = cols * SET_SPACING + 2.4
    depth = rows * SET_SPACING + 2.4
    pitch_x, pitch_z = width + WALL, depth + WALL
    h = ROOM_HEIGHT
    text = [f'description = "Generated level: {nx} x {nz} rooms, {sets} furniture sets a room, '
            f'{segments} segments; {count(nx, nz, sets, segments)} triangles '
            f'(bench/make_level.py)"\n\n']
    text.append("[materials]\n"
                "wall   = { reflectance = 0.7 }\n"
                "floor  = { reflectance = [0.55, 0.45, 0.35] }\n"
                "ceiling = { reflectance = 0.8 }\n"
                "wood   = { reflectance = [0.5, 0.33, 0.2] }\n"
                'steel  = { type = "glossy", reflectance = [0.6, 0.6, 0.62], roughness = 0.35 }\n'
                'gold   = { type = "glossy", reflectance = [0.9, 0.7, 0.35], roughness = 0.2 }\n'
                'mirror = { type = "mirror", reflectance = 0.9 }\n'
                'glass  = { type = "glass", ior = 1.5 }\n')
    for p in PANEL_POWERS:
        text.append(f"panel{p} = {{ reflectance = 0.0, power = {p} }}  # W\n")
    text.append("\n" + definitions(segments))

    # Walls along x = const (between columns i-1 and i) and z = const (rows j-1 and j); x0, z0
    # are the inner faces' corner of room (0, 0).
    def wall_x(i, j):  # the wall on the low-x side of room (i, j) if i < nx, else the far side
        x = i * pitch_x - WALL
        z0, z1 = j * pitch_z - WALL, (j + 1) * pitch_z
        name = f"wall_x{i}_{j}"
        if i == 0 or i == nx:
            return box(name, (x, 0, z0), (x + WALL, h, z1), "wall")
        zm = 0.5 * (z0 + z1)
        d = 0.5 * DOOR_WIDTH
        return (box(name + "a", (x, 0, z0), (x + WALL, h, zm - d), "wall") +
                box(name + "b", (x, 0, zm + d), (x + WALL, h, z1), "wall") +
                box(name + "c", (x, DOOR_HEIGHT, zm - d), (x + WALL, h, zm + d), "wall"))

    def wall_z(i, j):
        z = j * pitch_z - WALL
        x0, x1 = i * pitch_x, (i + 1) * pitch_x - WALL
        name = f"wall_z{i}_{j}"
        if j == 0 or j == nz:
            return box(name, (x0, 0, z), (x1, h, z + WALL), "wall")
        xm = 0.5 * (x0 + x1)
        d = 0.5 * DOOR_WIDTH
        return (box(name + "a", (x0, 0, z), (xm - d, h, z + WALL), "wall") +
                box(name + "b", (xm + d, 0, z), (x1, h, z + WALL), "wall") +
                box(name + "c", (xm - d, DOOR_HEIGHT, z), (xm + d, h, z + WALL), "wall"))

    for j in range(nz):
        for i in range(nx + 1):
            text.append(wall_x(i, j))
    for j in range(nz + 1):
        for i in range(nx):
            text.append(wall_z(i, j))

    for j in range(nz):
        for i in range(nx):
            r = j * nx + i
            x0, z0 = i * pitch_x, j * pitch_z
            cx, cz = x0 + 0.5 * width, z0 + 0.5 * depth
            tag = f"r{i}_{j}"
            # the floor reaches under the low-x and low-z walls: it covers the doorways' sills
            text.append(f'[[objects]]\nname = "{tag}_floor"\nshape = "quad"\n'
                        f'size = {vec(pitch_x, pitch_z)}\n'
                        f'translate = {vec(cx - 0.5 * WALL, 0, cz - 0.5 * WALL)}\n'
                        'material = "floor"\n\n')
            text.append(f'[[objects]]\nname = "{tag}_ceiling"\nshape = "quad"\n'
                        f'size = {vec(width, depth)}\nnormal = [0, -1, 0]\n'
                        f'translate = {vec(cx, h, cz)}\nmaterial = "ceiling"\n\n')
            power = PANEL_POWERS[r % len(PANEL_POWERS)]
            text.append(f'[[objects]]\nname = "{tag}_panel"\nshape = "quad"\n'
                        f'size = {vec(*PANEL)}\nnormal = [0, -1, 0]\n'
                        f'translate = {vec(cx, h - 0.01, cz)}\nmaterial = "panel{power}"\n\n')
            # planar mirror on the low-z wall, off the doorway, facing into the room
            text.append(f'[[objects]]\nname = "{tag}_mirror"\nshape = "quad"\n'
                        f'size = [1.0, 1.4]\nnormal = [0, 0, 1]\n'
                        f'translate = {vec(x0 + 0.9, 1.4, z0 + 0.01)}\nmaterial = "mirror"\n\n')
            # the corners (1.2 m free around the sets) hold the curved objects
            text.append(f'[[objects]]\nname = "{tag}_glass_ball"\nshape = "sphere"\n'
                        f'radius = 0.3\nrings = {s["ball_rings"]}\nsegments = {s["ball"]}\n'
                        f'translate = {vec(x0 + width - 0.6, 0.3, z0 + depth - 0.6)}\n'
                        'material = "glass"\n\n')
            if r % 2 == 0:
                text.append(f'[[objects]]\nname = "{tag}_mirror_ball"\nshape = "sphere"\n'
                            f'radius = 0.35\nrings = {s["ball_rings"]}\nsegments = {s["ball"]}\n'
                            f'translate = {vec(x0 + 0.6, 0.35, z0 + depth - 0.6)}\n'
                            'material = "mirror"\n\n')
            else:
                text.append(f'[[objects]]\nname = "{tag}_ring"\nshape = "torus"\n'
                            f'major_radius = 0.35\nminor_radius = 0.08\n'
                            f'rings = {s["ring_rings"]}\nsegments = {s["ring"]}\n'
                            f'translate = {vec(x0 + 0.6, 0.08, z0 + depth - 0.6)}\n'
                            'material = "gold"\n\n')
            for k in range(sets):
                sx = x0 + 1.2 + (k % cols + 0.5) * SET_SPACING
                sz = z0 + 1.2 + (k // cols + 0.5) * SET_SPACING
                text.append(f'[[objects]]\nname = "{tag}_set{k}"\ninstance = "set"\n'
                            f'translate = {vec(sx, 0, sz)}\nrotate = [0, {(r * 37 + k * 90) % 360}, 0]\n\n')
    # A camera in room (0, 0) looking through the doorways along the diagonal.
    text.append(f'[[cameras]]\nname = "overview"\nposition = {vec(0.4, 1.7, 0.4)}\n'
                f'target = {vec(nx * pitch_x, 0.6, nz * pitch_z)}\nfov = 70\n\n')
    text.append(f'[[cameras]]\nname = "room"\nposition = {vec(0.3, 2.2, depth - 0.3)}\n'
                f'target = {vec(width - 0.5, 0.5, 0.5)}\nfov = 75\n')
    return "".join(text)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--triangles", type=float, help="picks --sets and --segments")
    parser.add_argument("--rooms", default="10x10", help="NXxNZ (default 10x10: 100 lights)")
    parser.add_argument("--sets", type=int, default=1, help="furniture sets a room")
    parser.add_argument("--segments", type=int, default=12, help="tessellation of curved shapes")
    parser.add_argument("-o", "--output", required=True)
    args = parser.parse_args()
    nx, nz = (int(v) for v in args.rooms.lower().split("x"))
    if nx < 1 or nz < 1:
        parser.error("--rooms: at least 1x1")
    sets, segments = args.sets, args.segments
    if args.triangles:
        sets, segments = choose(args.triangles, nx, nz)
    if sets < 1 or segments < 8:
        parser.error("--sets >= 1, --segments >= 8")
    with open(args.output, "w") as f:
        f.write(level(nx, nz, sets, segments))
    print(f"{args.output}: {nx} x {nz} rooms, {nx * nz} lights, {sets} sets a room, "
          f"{segments} segments: {count(nx, nz, sets, segments)} triangles", file=sys.stderr)


if __name__ == "__main__":
    main()
