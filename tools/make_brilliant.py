"""Writes scenes/meshes/brilliant.obj: a round brilliant-cut gem (run once; committed).

A simplified round brilliant with Tolkowsky's (1919) proportions: table 56 % of the
girdle diameter, crown angle 34.5 deg, pavilion angle 40.75 deg, a girdle 2 % thick.
The crown is cut into 8 kite-and-star triangles per octant between an octagonal
table and a 16-sided girdle; the pavilion into 16 triangles meeting at the culet.
Girdle radius 1, table at the top, culet at the bottom; faces wound outwards.
"""
import math

TABLE = 0.56
CROWN = math.radians(34.5)
PAVILION = math.radians(40.75)
GIRDLE = 0.02

crown_h = (1.0 - TABLE) * math.tan(CROWN)
pav_h = math.tan(PAVILION)
verts = []


def add(x, y, z):
    verts.append((x, y, z))
    return len(verts)  # OBJ indices start at 1


table = [add(TABLE * math.cos(j * math.pi / 4), GIRDLE / 2 + crown_h, TABLE * math.sin(j * math.pi / 4)) for j in range(8)]
upper = [add(math.cos(k * math.pi / 8), GIRDLE / 2, math.sin(k * math.pi / 8)) for k in range(16)]
lower = [add(math.cos(k * math.pi / 8), -GIRDLE / 2, math.sin(k * math.pi / 8)) for k in range(16)]
culet = add(0.0, -GIRDLE / 2 - pav_h, 0.0)
top = add(0.0, GIRDLE / 2 + crown_h, 0.0)

faces = []
for j in range(8):
    t0, t1 = table[j], table[(j + 1) % 8]
    g0, g1, g2 = upper[2 * j], upper[2 * j + 1], upper[(2 * j + 2) % 16]
    faces += [(t0, g0, g1), (t0, g1, t1), (t1, g1, g2), (top, t0, t1)]
for k in range(16):
    a, b = upper[k], upper[(k + 1) % 16]
    c, d = lower[k], lower[(k + 1) % 16]
    faces += [(a, c, d), (a, d, b), (c, culet, d)]


def outward(face):
    """Winds a triangle so that its normal points away from the gem's axis/centre."""
    p = [verts[i - 1] for i in face]
    u = [p[1][i] - p[0][i] for i in range(3)]
    v = [p[2][i] - p[0][i] for i in range(3)]
    n = (u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0])
    c = [sum(q[i] for q in p) / 3 for i in range(3)]
    out = (c[0], c[1] - 0.0, c[2])
    return face if sum(n[i] * out[i] for i in range(3)) > 0 else (face[0], face[2], face[1])


with open("scenes/meshes/brilliant.obj", "w") as f:
    f.write("# Round brilliant (simplified), Tolkowsky proportions; made by tools/make_brilliant.py\n")
    for x, y, z in verts:
        f.write(f"v {x:.6f} {y:.6f} {z:.6f}\n")
    for face in faces:
        f.write("f {} {} {}\n".format(*outward(face)))
print(len(verts), "vertices,", len(faces), "faces; height", GIRDLE + crown_h + pav_h)
