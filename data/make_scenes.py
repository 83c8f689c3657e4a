#!/usr/bin/env python3
"""Generate vdbgi's bundled test scenes (standard library only, deterministic).

  make_scenes.py                      writes world.glb, room.obj/.mtl, floor.png here
  make_scenes.py --world SIZE OUT.glb writes a generated world SIZE x SIZE metres
  make_scenes.py --town OUT.glb       writes the town: 200 x 200 m, up to 60 m tall
  make_scenes.py --interior OUT.glb   writes two rooms lit by a window and by lamps
  make_scenes.py --room OUT.glb       writes a 6 x 4 x 3 m room with a window, a red wall
                                      and a 20 cd lamp, and OUT.json: the same scene for
                                      a path tracer (tests/truth/)
  make_scenes.py --two-rooms OUT.glb  writes two closed 4 x 3 x 4 m rooms sharing a 10 cm
                                      wall, a 20 cd lamp in one, none in the other

The outdoor world follows seed 000: orange canyon walls meeting green grass (a
sharp colour seam), a few buildings with an embedded brick texture, trees
instanced by node transforms with vertex-coloured canopies, and a thin
double-sided wall. The room is a closed box with inward faces, red and green
side walls and an externally textured floor.
"""
import json
import math
import os
import random
import struct
import sys
import zlib

# ---- tiny PNG writer -------------------------------------------------------


def png_bytes(width, height, pixel):
    """RGB8 PNG; pixel(x, y) -> (r, g, b) in 0..255, row 0 at the top."""
    raw = bytearray()
    for y in range(height):
        raw.append(0)
        for x in range(width):
            raw.extend(pixel(x, y))

    def chunk(tag, data):
        c = struct.pack(">I", len(data)) + tag + data
        return c + struct.pack(">I", zlib.crc32(tag + data) & 0xFFFFFFFF)

    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0))
            + chunk(b"IDAT", zlib.compress(bytes(raw), 9)) + chunk(b"IEND", b""))


def brick_pixel(x, y):
    row = y // 8
    mortar = (y % 8 == 7) or ((x + (4 if row % 2 else 0)) % 16 == 15)
    return (200, 195, 185) if mortar else (170, 70, 50)


def checker_pixel(x, y):
    return (230, 225, 210) if ((x // 8) + (y // 8)) % 2 == 0 else (60, 60, 70)


# ---- mesh building ----------------------------------------------------------


class Mesh:
    def __init__(self):
        self.pos, self.uv, self.col, self.idx = [], [], [], []

    def vert(self, p, uv=(0.0, 0.0), col=(1.0, 1.0, 1.0)):
        self.pos.append(tuple(float(c) for c in p))
        self.uv.append(uv)
        self.col.append(col)
        return len(self.pos) - 1

    def quad(self, a, b, c, d, uvs=None, col=(1.0, 1.0, 1.0)):
        """Counter-clockwise a b c d seen from the front."""
        uvs = uvs or [(0, 0), (1, 0), (1, 1), (0, 1)]
        i = [self.vert(p, uv, col) for p, uv in zip((a, b, c, d), uvs)]
        self.idx += [i[0], i[1], i[2], i[0], i[2], i[3]]

    def tri(self, a, b, c, col=(1.0, 1.0, 1.0)):
        self.idx += [self.vert(a, col=col), self.vert(b, col=col), self.vert(c, col=col)]

    def box(self, lo, hi, inward=False, uv_scale=None):
        x0, y0, z0 = lo
        x1, y1, z1 = hi
        faces = [
            ((x0, y0, z1), (x1, y0, z1), (x1, y1, z1), (x0, y1, z1)),  # +z
            ((x1, y0, z0), (x0, y0, z0), (x0, y1, z0), (x1, y1, z0)),  # -z
            ((x1, y0, z1), (x1, y0, z0), (x1, y1, z0), (x1, y1, z1)),  # +x
            ((x0, y0, z0), (x0, y0, z1), (x0, y1, z1), (x0, y1, z0)),  # -x
            ((x0, y1, z1), (x1, y1, z1), (x1, y1, z0), (x0, y1, z0)),  # +y
            ((x0, y0, z0), (x1, y0, z0), (x1, y0, z1), (x0, y0, z1)),  # -y
        ]
        for f in faces:
            if inward:
                f = f[::-1]
            uvs = None
            if uv_scale:
                w = math.dist(f[0], f[1]) / uv_scale
                h = math.dist(f[1], f[2]) / uv_scale
                uvs = [(0, 0), (w, 0), (w, h), (0, h)]
            self.quad(*f, uvs=uvs)


def terrain_height(x, z, size):
    return 0.35 * math.sin(0.21 * x) * math.cos(0.17 * z) + 0.2 * math.sin(0.05 * (x + 2 * z))


def build_world(size, seed):
    rnd = random.Random(seed)
    half = size / 2.0
    meshes = {}  # name -> (Mesh, material)

    # Ground: a low-poly heightfield in 2 m cells, green grass.
    ground = Mesh()
    cells = int(size // 2)
    step = size / cells
    for i in range(cells):
        for j in range(cells):
            x0, z0 = -half + i * step, -half + j * step
            x1, z1 = x0 + step, z0 + step
            p = [(x, terrain_height(x, z, size), z) for x, z in ((x0, z1), (x1, z1), (x1, z0), (x0, z0))]
            ground.quad(*p)
    meshes["ground"] = (ground, "grass")

    # Canyon walls: closed orange prisms with jagged tops, along both x edges.
    rock = Mesh()
    for side in (-1, 1):
        inner = side * (half - 10.0)
        outer = side * (half - 2.0)
        zs = [-half + 4.0 + k * 4.0 for k in range(int((size - 8.0) // 4.0) + 1)]
        for z0, z1 in zip(zs, zs[1:]):
            h0 = 9.0 + 4.0 * rnd.random()
            lo = (min(inner, outer), -0.5, z0)
            hi = (max(inner, outer), h0, z1)
            rock.box(lo, hi)
    meshes["rock"] = (rock, "rock")

    # Buildings: brick-textured boxes with flat red roofs.
    walls, roofs = Mesh(), Mesh()
    n_buildings = max(3, int(size * size / 1200))
    placed = []
    for _ in range(n_buildings * 20):
        if len(placed) == n_buildings:
            break
        w, d, h = rnd.uniform(4, 8), rnd.uniform(4, 8), rnd.uniform(3, 7)
        x = rnd.uniform(-half + 14, half - 14 - w)
        z = rnd.uniform(-half + 6, half - 6 - d)
        if any(abs(x - px) < 10 and abs(z - pz) < 10 for px, pz in placed):
            continue
        placed.append((x, z))
        walls.box((x, -0.5, z), (x + w, h, z + d), uv_scale=2.0)
        roofs.box((x - 0.3, h, z - 0.3), (x + w + 0.3, h + 0.3, z + d + 0.3))
    meshes["walls"] = (walls, "brick")
    meshes["roofs"] = (roofs, "roof")

    # A thin wall: one double-sided quad, thinner than any probe spacing.
    thin = Mesh()
    tx = 0.0 if size < 100 else half * 0.3
    thin.quad((tx - 4.0, -0.2, 3.0), (tx + 4.0, -0.2, 3.0), (tx + 4.0, 3.0, 3.0), (tx - 4.0, 3.0, 3.0))
    meshes["thin_wall"] = (thin, "thin")

    # Tree: trunk + canopy; canopy vertex colours vary so COLOR_0 matters.
    tree = Mesh()
    tree.box((-0.25, -0.3, -0.25), (0.25, 2.2, 0.25))
    trunk_tris = len(tree.idx) // 3
    top, r = 5.5, 1.8
    ring = [(r * math.cos(a), 2.6, r * math.sin(a)) for a in [k * 2 * math.pi / 7 for k in range(7)]]
    for k in range(7):
        a, b = ring[k], ring[(k + 1) % 7]
        shade = 0.55 + 0.45 * (k / 6.0)
        tree.tri(a, (0.0, top, 0.0), b, col=(0.2 * shade, 0.6 * shade, 0.15 * shade))
        tree.tri(b, (0.0, 1.9, 0.0), a, col=(0.1, 0.35, 0.08))
    trees = []
    n_trees = max(4, int(size * size / 500))
    for _ in range(n_trees):
        x = rnd.uniform(-half + 12, half - 12)
        z = rnd.uniform(-half + 4, half - 4)
        if any(x > px - 1 and x < px + 9 and z > pz - 1 and z < pz + 9 for px, pz in placed):
            continue
        trees.append((x, terrain_height(x, z, size), z, rnd.uniform(0.8, 1.3)))
    return meshes, tree, trunk_tris, trees


# ---- glTF 2.0 binary writer ---------------------------------------------------


class GlbWriter:
    def __init__(self):
        self.bin = bytearray()
        self.g = {"asset": {"version": "2.0", "generator": "vdbgi make_scenes.py"},
                  "buffers": [], "bufferViews": [], "accessors": [], "meshes": [],
                  "materials": [], "nodes": [], "scenes": [{"nodes": []}], "scene": 0}

    def view(self, data, target=None):
        while len(self.bin) % 4:
            self.bin.append(0)
        v = {"buffer": 0, "byteOffset": len(self.bin), "byteLength": len(data)}
        if target:
            v["target"] = target
        self.bin.extend(data)
        self.g["bufferViews"].append(v)
        return len(self.g["bufferViews"]) - 1

    def accessor(self, values, kind, comp=5126):
        n = {"VEC2": 2, "VEC3": 3, "SCALAR": 1}[kind]
        flat = [c for v in values for c in (v if n > 1 else (v,))]
        fmt = "<%d%s" % (len(flat), "f" if comp == 5126 else "I")
        target = 34963 if comp == 5125 else 34962
        a = {"bufferView": self.view(struct.pack(fmt, *flat), target), "componentType": comp,
             "count": len(values), "type": kind}
        if kind == "VEC3" and comp == 5126:
            a["min"] = [min(v[k] for v in values) for k in range(3)]
            a["max"] = [max(v[k] for v in values) for k in range(3)]
        self.g["accessors"].append(a)
        return len(self.g["accessors"]) - 1

    def material(self, name, color, texture=None, double_sided=False):
        m = {"name": name, "pbrMetallicRoughness": {"baseColorFactor": list(color) + [1.0],
                                                   "metallicFactor": 0.0, "roughnessFactor": 1.0}}
        if texture is not None:
            m["pbrMetallicRoughness"]["baseColorTexture"] = {"index": texture}
        if double_sided:
            m["doubleSided"] = True
        self.g["materials"].append(m)
        return len(self.g["materials"]) - 1

    def texture(self, png):
        g = self.g
        g.setdefault("images", []).append({"bufferView": self.view(png), "mimeType": "image/png"})
        g.setdefault("samplers", []).append({"magFilter": 9729, "minFilter": 9729})
        g.setdefault("textures", []).append({"source": len(g["images"]) - 1, "sampler": len(g["samplers"]) - 1})
        return len(g["textures"]) - 1

    def mesh(self, name, m, material, uv=False, colors=False):
        attrs = {"POSITION": self.accessor(m.pos, "VEC3")}
        if uv:
            attrs["TEXCOORD_0"] = self.accessor([(u, 1.0 - v) for u, v in m.uv], "VEC2")
        if colors:
            attrs["COLOR_0"] = self.accessor(m.col, "VEC3")
        prim = {"attributes": attrs, "indices": self.accessor(m.idx, "SCALAR", 5125), "material": material}
        self.g["meshes"].append({"name": name, "primitives": [prim]})
        return len(self.g["meshes"]) - 1

    def node(self, name, mesh, translation=None, scale=None, children=None, root=True):
        n = {"name": name}
        if mesh is not None:
            n["mesh"] = mesh
        if translation:
            n["translation"] = list(translation)
        if scale:
            n["scale"] = [scale] * 3
        if children:
            n["children"] = children
        self.g["nodes"].append(n)
        idx = len(self.g["nodes"]) - 1
        if root:
            self.g["scenes"][0]["nodes"].append(idx)
        return idx

    def light(self, name, kind, color, intensity, at, towards=None, spot=None, range_=None):
        """A KHR_lights_punctual light on a node of its own at `at`, shining along
        `towards` (glTF lights shine down their node's -z)."""
        g = self.g
        g.setdefault("extensionsUsed", ["KHR_lights_punctual"])
        lights = g.setdefault("extensions", {}).setdefault("KHR_lights_punctual", {"lights": []})["lights"]
        light = {"name": name, "type": kind, "color": list(color), "intensity": intensity}
        if spot:
            light["spot"] = {"innerConeAngle": spot[0], "outerConeAngle": spot[1]}
        if range_:
            light["range"] = range_
        lights.append(light)
        idx = self.node(name, None, translation=at)
        node = g["nodes"][idx]
        node["extensions"] = {"KHR_lights_punctual": {"light": len(lights) - 1}}
        if towards:
            node["rotation"] = rotation_onto((0.0, 0.0, -1.0), towards)
        return idx

    def write(self, path):
        while len(self.bin) % 4:
            self.bin.append(0)
        self.g["buffers"] = [{"byteLength": len(self.bin)}]
        js = json.dumps(self.g, separators=(",", ":")).encode()
        js += b" " * ((4 - len(js) % 4) % 4)
        body = struct.pack("<II", len(js), 0x4E4F534A) + js + struct.pack("<II", len(self.bin), 0x004E4942) + bytes(self.bin)
        with open(path + ".tmp", "wb") as f:
            f.write(struct.pack("<III", 0x46546C67, 2, 12 + len(body)) + body)
        os.replace(path + ".tmp", path)


def write_world(path, size, seed=7):
    meshes, tree, trunk_tris, trees = build_world(size, seed)
    w = GlbWriter()
    brick = w.texture(png_bytes(32, 32, brick_pixel))
    mats = {"grass": w.material("grass", (0.22, 0.50, 0.16)),
            "rock": w.material("orange rock", (0.80, 0.38, 0.12)),
            "brick": w.material("brick", (1.0, 1.0, 1.0), texture=brick),
            "roof": w.material("roof", (0.55, 0.12, 0.10)),
            "thin": w.material("thin wall", (0.20, 0.30, 0.75), double_sided=True),
            "tree": w.material("tree", (0.45, 0.30, 0.18))}
    for name, (m, mat) in meshes.items():
        if m.idx:
            w.node(name, w.mesh(name, m, mats[mat], uv=(mat == "brick")))
    tree_mesh = w.mesh("tree", tree, mats["tree"], colors=True)
    kids = [w.node("tree%d" % i, tree_mesh, translation=(x, y, z), scale=s, root=False)
            for i, (x, y, z, s) in enumerate(trees)]
    # Trees hang under a parent with its own offset: transforms must compose.
    w.node("forest", None, translation=(0.0, 0.0, 0.0), children=kids)
    w.write(path)


def write_room(directory):
    """Closed room 6 x 3 x 5 m (inward faces), a table, textured floor (external file)."""
    parts = []  # (material, Mesh)
    x0, x1, y0, y1, z0, z1 = -3.0, 3.0, 0.0, 3.0, -2.5, 2.5
    def face(mat, quad, inward, uv=False):
        """Add quad facing along inward (flipped if its winding points the other way)."""
        a, b, c = quad[0], quad[1], quad[2]
        e1 = [b[k] - a[k] for k in range(3)]
        e2 = [c[k] - a[k] for k in range(3)]
        n = (e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0])
        if sum(n[k] * inward[k] for k in range(3)) < 0:
            quad = quad[::-1]
        m = Mesh()
        uvs = [(p[0] / 2.0, p[2] / 2.0) for p in quad] if uv else None
        m.quad(*quad, uvs=uvs)
        parts.append((mat, m, uv))
    face("floor", ((x0, y0, z1), (x1, y0, z1), (x1, y0, z0), (x0, y0, z0)), (0, 1, 0), uv=True)
    face("white", ((x0, y1, z1), (x1, y1, z1), (x1, y1, z0), (x0, y1, z0)), (0, -1, 0))
    face("red", ((x0, y0, z0), (x0, y0, z1), (x0, y1, z1), (x0, y1, z0)), (1, 0, 0))
    face("green", ((x1, y0, z1), (x1, y0, z0), (x1, y1, z0), (x1, y1, z1)), (-1, 0, 0))
    face("white", ((x1, y0, z0), (x0, y0, z0), (x0, y1, z0), (x1, y1, z0)), (0, 0, 1))
    face("white", ((x0, y0, z1), (x1, y0, z1), (x1, y1, z1), (x0, y1, z1)), (0, 0, -1))
    table = Mesh()
    table.box((-0.8, 0.0, -0.5), (0.8, 0.8, 0.5))
    parts.append(("wood", table, False))
    lines = ["# vdbgi test room: closed, faces point inwards; generated by make_scenes.py",
             "mtllib room.mtl"]
    base = 1
    for k, (mat, m, uv) in enumerate(parts):
        lines.append("o part%d" % k)
        for p in m.pos:
            lines.append("v %.4f %.4f %.4f" % p)
        if uv:
            for t in m.uv:
                lines.append("vt %.4f %.4f" % t)
        lines.append("usemtl %s" % mat)
        for t in range(0, len(m.idx), 3):
            a, b, c = (m.idx[t + i] + base for i in range(3))
            if uv:
                lines.append("f %d/%d %d/%d %d/%d" % (a, a, b, b, c, c))
            else:
                lines.append("f %d %d %d" % (a, b, c))
        base += len(m.pos)
    # vt indices share numbering with v only because every textured part comes first.
    assert parts[0][2] and not any(p[2] for p in parts[1:])
    with open(os.path.join(directory, "room.obj"), "w") as f:
        f.write("\n".join(lines) + "\n")
    mtl = ["# materials of room.obj", "newmtl floor", "Kd 1.0 1.0 1.0", "map_Kd floor.png",
           "newmtl white", "Kd 0.75 0.75 0.75", "newmtl red", "Kd 0.70 0.10 0.08",
           "newmtl green", "Kd 0.12 0.60 0.10", "newmtl wood", "Kd 0.50 0.33 0.18"]
    with open(os.path.join(directory, "room.mtl"), "w") as f:
        f.write("\n".join(mtl) + "\n")
    with open(os.path.join(directory, "floor.png"), "wb") as f:
        f.write(png_bytes(32, 32, checker_pixel))


# ---- the town: seed 000's 200 x 60 x 200 m case ------------------------------


def town_ground(x, z):
    """Flat for z < 10, then a slope rising to 8 m at the far edge (z = 100)."""
    return 0.0 if z < 10.0 else 8.0 * (z - 10.0) / 90.0


def facing_quad(m, q, normal):
    """Quad q, wound so that its front faces along normal."""
    e1 = [q[1][k] - q[0][k] for k in range(3)]
    e2 = [q[2][k] - q[0][k] for k in range(3)]
    n = (e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0])
    m.quad(*(q if sum(n[k] * normal[k] for k in range(3)) > 0 else q[::-1]))


def facade(m, a, b, y0, storeys, t, out):
    """A wall of thickness t from a to b (x, z), its outer face along the unit
    vector out (x, z), with one window a storey every 3 m: outer and inner faces
    and the window reveals. Storeys 3 m tall."""
    ax, az = a
    length = math.hypot(b[0] - ax, b[1] - az)
    ux, uz = (b[0] - ax) / length, (b[1] - az) / length
    nx, nz = out
    bays = max(1, int(length // 3.0))
    bay = length / bays

    def pt(s, y, depth):
        return (ax + ux * s - nx * depth, y, az + uz * s - nz * depth)

    def panel(s0, s1, y0_, y1_):
        facing_quad(m, [pt(s0, y0_, 0), pt(s1, y0_, 0), pt(s1, y1_, 0), pt(s0, y1_, 0)], (nx, 0, nz))
        facing_quad(m, [pt(s0, y0_, t), pt(s1, y0_, t), pt(s1, y1_, t), pt(s0, y1_, t)], (-nx, 0, -nz))

    for k in range(storeys):
        base = y0 + 3.0 * k
        sill, head = base + 1.0, base + 2.4
        panel(0.0, length, base, sill)
        panel(0.0, length, head, base + 3.0)
        for i in range(bays):
            s0, s1 = i * bay, (i + 1) * bay
            w0, w1 = s0 + 0.35 * bay, s1 - 0.35 * bay
            panel(s0, w0, sill, head)
            panel(w1, s1, sill, head)
            # The opening's four sides, facing into it.
            for s_, d in ((w0, 1.0), (w1, -1.0)):
                q = [pt(s_, sill, 0), pt(s_, sill, t), pt(s_, head, t), pt(s_, head, 0)]
                facing_quad(m, q, (ux * d, 0, uz * d))
            for y_, d in ((sill, 1.0), (head, -1.0)):
                q = [pt(w0, y_, 0), pt(w1, y_, 0), pt(w1, y_, t), pt(w0, y_, t)]
                facing_quad(m, q, (0, d, 0))


def town_building(walls, floors, roofs, x0, z0, w, d, storeys, y0):
    """A hollow building: windowed walls 0.3 m thick, a floor slab every storey
    (both faces), one partition wall across the middle (rooms behind the windows),
    and a flat roof."""
    t = 0.3
    x1, z1 = x0 + w, z0 + d
    for a, b, out in (((x0, z1), (x1, z1), (0, 1)), ((x1, z1), (x1, z0), (1, 0)),
                      ((x1, z0), (x0, z0), (0, -1)), ((x0, z0), (x0, z1), (-1, 0))):
        facade(walls, a, b, y0, storeys, t, out)
    top = y0 + 3.0 * storeys
    for k in range(storeys + 1):
        y = y0 + 3.0 * k
        lo, hi = (x0 + t, y - 0.2, z0 + t), (x1 - t, y, z1 - t)
        (roofs if k == storeys else floors).box(lo, hi)
    roofs.box((x0 - 0.2, top, z0 - 0.2), (x1 + 0.2, top + 0.4, z1 + 0.2))
    xm = x0 + w / 2.0
    for k in range(storeys):
        floors.quad((xm, y0 + 3.0 * k, z0 + t), (xm, y0 + 3.0 * k, z1 - t),
                    (xm, y0 + 3.0 * k + 2.8, z1 - t), (xm, y0 + 3.0 * k + 2.8, z0 + t))
        floors.quad((xm, y0 + 3.0 * k, z1 - t), (xm, y0 + 3.0 * k, z0 + t),
                    (xm, y0 + 3.0 * k + 2.8, z0 + t), (xm, y0 + 3.0 * k + 2.8, z1 - t))


def build_town(seed=11):
    """200 x 200 m, up to 60 m tall: city blocks of multi-storey buildings with
    windows and rooms, a paved plaza, an arcade to walk under along the plaza's
    north side, a footbridge between two towers, and a slope to the north."""
    rnd = random.Random(seed)
    meshes = {}
    ground, plaza = Mesh(), Mesh()
    step = 4.0
    for i in range(50):
        for j in range(50):
            x0, z0 = -100.0 + i * step, -100.0 + j * step
            x1, z1 = x0 + step, z0 + step
            p = [(x, town_ground(x, z), z) for x, z in ((x0, z1), (x1, z1), (x1, z0), (x0, z0))]
            (plaza if abs(x0 + 2) < 20 and abs(z0 + 2) < 20 else ground).quad(*p)
    meshes["ground"] = (ground, "grass")
    meshes["plaza"] = (plaza, "stone")
    walls, floors, roofs = Mesh(), Mesh(), Mesh()
    # Blocks of 36 m with 12 m streets; the centre block is the plaza.
    for bi in range(-2, 3):
        for bj in range(-2, 3):
            if bi == 0 and bj == 0:
                continue
            cx, cz = bi * 40.0, bj * 40.0
            y0 = town_ground(cx, cz + 14.0)
            for (ox, oz) in ((-14.0, -14.0), (2.0, -14.0), (-14.0, 2.0), (2.0, 2.0)):
                if rnd.random() < 0.25:
                    continue
                w, d = rnd.uniform(8.0, 12.0), rnd.uniform(8.0, 12.0)
                tall = rnd.random() < 0.15
                storeys = rnd.randint(12, 17) if tall else rnd.randint(2, 6)
                town_building(walls, floors, roofs, cx + ox, cz + oz, w, d, storeys, y0)
    meshes["walls"] = (walls, "plaster")
    meshes["floors"] = (floors, "concrete")
    meshes["roofs"] = (roofs, "roof")
    # Arcade: a roof on columns along the plaza's north edge.
    arcade = Mesh()
    arcade.box((-18.0, 4.0, 18.0), (18.0, 4.6, 22.0))
    for k in range(7):
        x = -18.0 + 6.0 * k
        arcade.box((x - 0.3, 0.0, 21.4), (x + 0.3, 4.0, 22.0))
    # Footbridge: 10 m up, from block (-1, 0) to block (1, 0), over the plaza.
    arcade.box((-26.0, 10.0, -1.5), (26.0, 10.5, 1.5))
    arcade.box((-26.0, 10.5, -1.5), (26.0, 11.5, -1.3))
    arcade.box((-26.0, 10.5, 1.3), (26.0, 11.5, 1.5))
    meshes["arcade"] = (arcade, "stone")
    return meshes


def write_town(path):
    meshes = build_town()
    w = GlbWriter()
    mats = {"grass": w.material("grass", (0.22, 0.50, 0.16)),
            "stone": w.material("stone", (0.60, 0.57, 0.52)),
            "plaster": w.material("plaster", (0.85, 0.72, 0.55)),
            "concrete": w.material("concrete", (0.50, 0.50, 0.50)),
            "roof": w.material("roof", (0.55, 0.12, 0.10))}
    for name, (m, mat) in meshes.items():
        if m.idx:
            w.node(name, w.mesh(name, m, mats[mat]))
    w.write(path)


def rotation_onto(a, b):
    """The unit quaternion (x, y, z, w) that turns unit a onto direction b."""
    n = math.sqrt(sum(c * c for c in b))
    b = [c / n for c in b]
    d = sum(a[k] * b[k] for k in range(3))
    axis = (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])
    if d < -0.999999:  # opposite: half a turn about any axis across a
        return [1.0, 0.0, 0.0, 0.0] if abs(a[0]) < 0.9 else [0.0, 1.0, 0.0, 0.0]
    q = [axis[0], axis[1], axis[2], 1.0 + d]
    n = math.sqrt(sum(c * c for c in q))
    return [c / n for c in q]


def wall(m, pt, s0, s1, h, hole, normal):
    """A wall pt(s, y) over s in [s0, s1], y in [0, h], facing normal, with an
    opening hole = (sa, sb, ya, yb) (or None): the quads around it."""
    if hole is None:
        facing_quad(m, [pt(s0, 0), pt(s1, 0), pt(s1, h), pt(s0, h)], normal)
        return
    sa, sb, ya, yb = hole
    for q in ([pt(s0, 0), pt(sa, 0), pt(sa, h), pt(s0, h)], [pt(sb, 0), pt(s1, 0), pt(s1, h), pt(sb, h)],
              [pt(sa, 0), pt(sb, 0), pt(sb, ya), pt(sa, ya)], [pt(sa, yb), pt(sb, yb), pt(sb, h), pt(sa, h)]):
        if abs(q[1][0] - q[0][0]) + abs(q[1][2] - q[0][2]) > 1e-9 and abs(q[2][1] - q[1][1]) > 1e-9:
            facing_quad(m, q, normal)


def write_interior(path):
    """Two 6 x 3 x 6 m rooms side by side (x 0..6 and 6..12), closed shells of
    inward faces: room A has a window in its south wall (z = 0) where the sun and
    the sky come in, and a reading spot; room B, through a doorway in the wall
    between them, is lit by a ceiling lamp only, and by what bounces in from A:
    light that reaches it after two and three bounces."""
    h = 3.0
    shell, inner, floor_, sofa = Mesh(), Mesh(), Mesh(), Mesh()
    floor_.quad((0, 0, 6), (12, 0, 6), (12, 0, 0), (0, 0, 0))        # up
    shell.quad((0, h, 0), (12, h, 0), (12, h, 6), (0, h, 6))           # ceiling, down
    wall(shell, lambda s, y: (s, y, 0.0), 0.0, 12.0, h, (1.5, 4.5, 0.9, 2.4), (0, 0, 1))  # south
    wall(shell, lambda s, y: (s, y, 6.0), 0.0, 12.0, h, None, (0, 0, -1))                # north
    wall(shell, lambda s, y: (0.0, y, s), 0.0, 6.0, h, None, (1, 0, 0))                  # west
    wall(shell, lambda s, y: (12.0, y, s), 0.0, 6.0, h, None, (-1, 0, 0))                # east
    door = (2.5, 3.5, 0.0, 2.2)
    wall(inner, lambda s, y: (6.0, y, s), 0.0, 6.0, h, door, (-1, 0, 0))   # A's side
    wall(inner, lambda s, y: (6.0, y, s), 0.0, 6.0, h, door, (1, 0, 0))    # B's side
    sofa.box((8.0, 0.0, 4.6), (11.0, 0.8, 5.6))
    sofa.box((1.0, 0.0, 4.0), (3.0, 0.9, 5.5))
    w = GlbWriter()
    w.node("shell", w.mesh("shell", shell, w.material("plaster", (0.80, 0.78, 0.74))))
    w.node("partition", w.mesh("partition", inner, w.material("red plaster", (0.75, 0.25, 0.20))))
    w.node("floor", w.mesh("floor", floor_, w.material("wood", (0.55, 0.38, 0.22))))
    w.node("furniture", w.mesh("furniture", sofa, w.material("blue", (0.15, 0.25, 0.60))))
    # The sun (lux / pi is the estimator's sun colour) through the window, a lamp in B, a spot in A.
    w.light("sun", "directional", (1.0, 0.95, 0.85), 15.0, (3.0, 5.0, -3.0), towards=(0.25, -0.55, 1.0))
    w.light("ceiling lamp", "point", (1.0, 0.85, 0.6), 15.0, (9.0, 2.4, 3.0), range_=12.0)
    w.light("reading spot", "spot", (0.9, 0.95, 1.0), 25.0, (2.0, 2.9, 4.7), towards=(0.0, -1.0, 0.0),
            spot=(0.35, 0.7))
    w.write(path)


def write_room_truth(path):
    """A 6 x 4 x 3 m room (x 0..6, z 0..4), a shell of inward faces with a 2 x 1.2 m
    window in its south wall (z = 0), a red west wall, a 20 cd point lamp; and,
    beside the .glb, a .json of the same triangles, albedos and lamp for a path
    tracer to build the scene from (so both read one geometry)."""
    h = 3.0
    walls, red, floor_ = Mesh(), Mesh(), Mesh()
    floor_.quad((0, 0, 4), (6, 0, 4), (6, 0, 0), (0, 0, 0))                                  # up
    walls.quad((0, h, 0), (6, h, 0), (6, h, 4), (0, h, 4))                                   # ceiling
    wall(walls, lambda s, y: (s, y, 0.0), 0.0, 6.0, h, (2.0, 4.0, 1.0, 2.2), (0, 0, 1))    # south
    wall(walls, lambda s, y: (s, y, 4.0), 0.0, 6.0, h, None, (0, 0, -1))                   # north
    wall(walls, lambda s, y: (6.0, y, s), 0.0, 4.0, h, None, (-1, 0, 0))                   # east
    wall(red, lambda s, y: (0.0, y, s), 0.0, 4.0, h, None, (1, 0, 0))                      # west
    parts = [("walls", walls, (0.8, 0.8, 0.8)), ("red wall", red, (0.7, 0.15, 0.1)),
             ("floor", floor_, (0.5, 0.4, 0.3))]
    lamp = {"position": [3.5, 2.6, 2.5], "color": [1.0, 1.0, 1.0], "intensity": 20.0}
    w = GlbWriter()
    for name, m, albedo in parts:
        w.node(name, w.mesh(name, m, w.material(name, albedo)))
    w.light("lamp", "point", lamp["color"], lamp["intensity"], lamp["position"])
    w.write(path)
    truth = {"meshes": [{"name": n, "albedo": a, "positions": m.pos, "indices": m.idx}
                        for n, m, a in parts], "lamps": [lamp]}
    base = path[:-4] if path.endswith(".glb") else path
    with open(base + ".json.tmp", "w") as f:
        json.dump(truth, f)
    os.replace(base + ".json.tmp", base + ".json")


def write_two_rooms(path):
    """Two closed rooms, x 0..4 (lit: a 20 cd lamp) and x 4.1..8.1 (dark), 3 m
    high and 4 m deep, each a shell of inward faces: the 10 cm between them is
    the wall a probe grid must not see through (issue 46)."""
    h, d = 3.0, 4.0
    lit, dark = Mesh(), Mesh()
    for m, x0, x1 in ((lit, 0.0, 4.0), (dark, 4.1, 8.1)):
        m.quad((x0, 0, d), (x1, 0, d), (x1, 0, 0), (x0, 0, 0))                               # floor, up
        m.quad((x0, h, 0), (x1, h, 0), (x1, h, d), (x0, h, d))                               # ceiling
        wall(m, lambda s, y: (s, y, 0.0), x0, x1, h, None, (0, 0, 1))
        wall(m, lambda s, y: (s, y, d), x0, x1, h, None, (0, 0, -1))
        wall(m, lambda s, y, x=x0: (x, y, s), 0.0, d, h, None, (1, 0, 0))
        wall(m, lambda s, y, x=x1: (x, y, s), 0.0, d, h, None, (-1, 0, 0))
    w = GlbWriter()
    w.node("lit room", w.mesh("lit room", lit, w.material("plaster", (0.8, 0.8, 0.8))))
    w.node("dark room", w.mesh("dark room", dark, w.material("plaster", (0.8, 0.8, 0.8))))
    w.light("lamp", "point", (1.0, 1.0, 1.0), 20.0, (2.0, 2.2, 2.0))
    w.write(path)


def main(argv):
    if len(argv) == 3 and argv[0] == "--world":
        write_world(argv[2], float(argv[1]), seed=int(float(argv[1])))
        return 0
    if len(argv) == 2 and argv[0] == "--town":
        write_town(argv[1])
        return 0
    if len(argv) == 2 and argv[0] == "--interior":
        write_interior(argv[1])
        return 0
    if len(argv) == 2 and argv[0] == "--room":
        write_room_truth(argv[1])
        return 0
    if len(argv) == 2 and argv[0] == "--two-rooms":
        write_two_rooms(argv[1])
        return 0
    if argv:
        sys.stderr.write(__doc__)
        return 2
    here = os.path.dirname(os.path.abspath(__file__))
    write_world(os.path.join(here, "world.glb"), 48.0)
    write_room(here)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
