#!/usr/bin/env python3
"""Check a two-body gmsh mesh against the conventions of DESIGN.md section 3.

Pure Python (no gmsh, no numpy), so that it runs anywhere.  For each file:
  * format is ASCII msh 4.1;
  * the physical groups femur, tibia (dim 3) and femur_contact, femur_fixation,
    tibia_contact, tibia_inferior (dim 2) exist (by name);
  * every saved 3D element is a linear hexahedron (gmsh type 5), every saved 2D
    element a linear quadrangle (type 3), nothing else is saved;
  * no hexahedron is inverted: the Jacobian determinant at each of the 8 corners
    (gmsh type-5 node order) is positive;
  * the two bodies share no node;
  * every tagged quadrangle is a boundary face of a hexahedron of the right body;
and it reports hexahedron and vertex counts per body and the meshed volumes
(exact trilinear volume of every hexahedron).

Usage: check_msh.py [--quiet] FILE.msh ...
Exit code 0 only if every file passes.
"""
import sys

GROUPS3 = ("femur", "tibia")
GROUPS2 = {
    "femur_contact": "femur",
    "femur_fixation": "femur",
    "tibia_contact": "tibia",
    "tibia_inferior": "tibia",
}

# Three edge neighbours of every corner of a gmsh hexahedron, right-handed.
CORNER_NEIGHBOURS = ((1, 3, 4), (2, 0, 5), (3, 1, 6), (0, 2, 7), (7, 5, 0), (4, 6, 1), (5, 7, 2), (6, 4, 3))
# The six faces of a gmsh hexahedron.
HEX_FACES = ((0, 3, 2, 1), (0, 1, 5, 4), (0, 4, 7, 3), (1, 2, 6, 5), (2, 3, 7, 6), (4, 5, 6, 7))
ELEMENT_NAMES = {
    1: "line",
    2: "triangle",
    3: "quadrangle",
    4: "tetrahedron",
    5: "hexahedron",
    6: "prism",
    7: "pyramid",
    15: "point",
}


class MeshError(Exception):
    pass


def read_msh(path):
    """Return (physical names {(dim, tag): name}, entity physical tags
    {(dim, tag): [ptags]}, nodes {tag: (x, y, z)}, element blocks
    [(dim, entity, type, [(tag, [nodes])])])."""
    with open(path, "r") as f:
        lines = f.read().split("\n")
    pos = 0

    def nxt():
        nonlocal pos
        while pos < len(lines) and not lines[pos].strip():
            pos += 1
        if pos >= len(lines):
            raise MeshError("unexpected end of file")
        line = lines[pos]
        pos += 1
        return line

    names, ent_phys, nodes, blocks = {}, {}, {}, []
    version = None
    while pos < len(lines):
        line = lines[pos].strip()
        pos += 1
        if not line:
            continue
        if line == "$MeshFormat":
            v, ftype, _ = nxt().split()
            version = v
            if v != "4.1":
                raise MeshError("msh version %s, expected 4.1" % v)
            if ftype != "0":
                raise MeshError("binary msh file, expected ASCII")
        elif line == "$PhysicalNames":
            for _ in range(int(nxt())):
                s = nxt().split(None, 2)
                names[(int(s[0]), int(s[1]))] = s[2].strip().strip('"')
        elif line == "$Entities":
            counts = [int(c) for c in nxt().split()]
            for dim in range(4):
                for _ in range(counts[dim]):
                    s = nxt().split()
                    tag = int(s[0])
                    k = 4 if dim == 0 else 7
                    nph = int(s[k])
                    ent_phys[(dim, tag)] = [int(t) for t in s[k + 1 : k + 1 + nph]]
        elif line == "$Nodes":
            nb, _, _, _ = [int(c) for c in nxt().split()]
            for _ in range(nb):
                _, _, parametric, n = [int(c) for c in nxt().split()]
                if parametric:
                    raise MeshError("parametric node coordinates not supported")
                tags = [int(nxt()) for _ in range(n)]
                for t in tags:
                    x, y, z = nxt().split()[:3]
                    nodes[t] = (float(x), float(y), float(z))
        elif line == "$Elements":
            nb, _, _, _ = [int(c) for c in nxt().split()]
            for _ in range(nb):
                dim, ent, etype, n = [int(c) for c in nxt().split()]
                els = []
                for _ in range(n):
                    s = [int(c) for c in nxt().split()]
                    els.append((s[0], s[1:]))
                blocks.append((dim, ent, etype, els))
        elif line.startswith("$") and not line.startswith("$End"):
            # skip unknown section
            end = "$End" + line[1:]
            while pos < len(lines) and lines[pos].strip() != end:
                pos += 1
    if version is None:
        raise MeshError("no $MeshFormat section")
    return names, ent_phys, nodes, blocks


def det3(a, b, c):
    return (
        a[0] * (b[1] * c[2] - b[2] * c[1])
        - a[1] * (b[0] * c[2] - b[2] * c[0])
        + a[2] * (b[0] * c[1] - b[1] * c[0])
    )


def sub(p, q):
    return (p[0] - q[0], p[1] - q[1], p[2] - q[2])


def hex_volume(x):
    """Exact volume of a trilinear hexahedron (2x2x2 Gauss is exact)."""
    g = 0.5 / 3**0.5
    vol = 0.0
    for a in (0.5 - g, 0.5 + g):
        for b in (0.5 - g, 0.5 + g):
            for c in (0.5 - g, 0.5 + g):
                # reference coords (a,b,c) in [0,1]^3, gmsh ordering
                # x(a,b,c) = sum N_i x_i
                dxa = [0.0, 0.0, 0.0]
                dxb = [0.0, 0.0, 0.0]
                dxc = [0.0, 0.0, 0.0]
                # shape functions: node (i,j,k) -> index
                for idx, (i, j, k) in enumerate(
                    ((0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0), (0, 0, 1), (1, 0, 1), (1, 1, 1), (0, 1, 1))
                ):
                    fa = a if i else 1 - a
                    fb = b if j else 1 - b
                    fc = c if k else 1 - c
                    sa = 1 if i else -1
                    sb = 1 if j else -1
                    sc = 1 if k else -1
                    for d in range(3):
                        dxa[d] += sa * fb * fc * x[idx][d]
                        dxb[d] += fa * sb * fc * x[idx][d]
                        dxc[d] += fa * fb * sc * x[idx][d]
                vol += det3(dxa, dxb, dxc) / 8.0
    return vol


def check(path, quiet=False):
    names, ent_phys, nodes, blocks = read_msh(path)
    errors = []
    by_name = {}
    for (dim, tag), name in names.items():
        by_name[name] = (dim, tag)
    for g in GROUPS3:
        if by_name.get(g, (None,))[0] != 3:
            errors.append("missing physical volume '%s'" % g)
    for g in GROUPS2:
        if by_name.get(g, (None,))[0] != 2:
            errors.append("missing physical surface '%s'" % g)
    if errors:
        raise MeshError("; ".join(errors))
    tag_to_name = {(d, t): n for (d, t), n in names.items()}

    hexes = {g: [] for g in GROUPS3}
    quads = {g: [] for g in GROUPS2}
    for dim, ent, etype, els in blocks:
        if dim == 3 and etype != 5:
            errors.append("%d %s elements in 3D entity %d" % (len(els), ELEMENT_NAMES.get(etype, etype), ent))
            continue
        if dim == 2 and etype != 3:
            errors.append("%d %s elements in 2D entity %d" % (len(els), ELEMENT_NAMES.get(etype, etype), ent))
            continue
        if dim < 2:
            errors.append("%d elements of dimension %d saved" % (len(els), dim))
            continue
        groups = [tag_to_name.get((dim, p)) for p in ent_phys.get((dim, ent), [])]
        groups = [g for g in groups if g]
        target = hexes if dim == 3 else quads
        hit = [g for g in groups if g in target]
        if len(hit) != 1:
            errors.append("%dD entity %d belongs to groups %s" % (dim, ent, groups))
            continue
        target[hit[0]].extend(conn for _, conn in els)

    verts = {}
    volume = {}
    inverted = 0
    worst = 1e300
    for g in GROUPS3:
        vs = set()
        vol = 0.0
        for conn in hexes[g]:
            if len(conn) != 8:
                errors.append("hexahedron with %d nodes" % len(conn))
                continue
            vs.update(conn)
            x = [nodes[n] for n in conn]
            for c, (i, j, k) in enumerate(CORNER_NEIGHBOURS):
                e1, e2, e3 = sub(x[i], x[c]), sub(x[j], x[c]), sub(x[k], x[c])
                d = det3(e1, e2, e3)
                norm = (sum(t * t for t in e1) * sum(t * t for t in e2) * sum(t * t for t in e3)) ** 0.5
                q = d / norm if norm > 0 else -1.0
                worst = min(worst, q)
                if d <= 0:
                    inverted += 1
                    break
            vol += hex_volume(x)
        verts[g] = vs
        volume[g] = vol
        if not hexes[g]:
            errors.append("physical volume '%s' has no hexahedra" % g)
    if inverted:
        errors.append("%d inverted hexahedra" % inverted)
    shared = verts["femur"] & verts["tibia"]
    if shared:
        errors.append("femur and tibia share %d nodes" % len(shared))

    # tagged quadrangles must be boundary faces of the right body
    for g in GROUPS3:
        count = {}
        for conn in hexes[g]:
            for f in HEX_FACES:
                key = frozenset(conn[i] for i in f)
                count[key] = count.get(key, 0) + 1
        for s, body in GROUPS2.items():
            if body != g:
                continue
            if not quads[s]:
                errors.append("physical surface '%s' is empty" % s)
            bad = sum(1 for q in quads[s] if count.get(frozenset(q), 0) != 1)
            if bad:
                errors.append("%d quadrangles of '%s' are not boundary faces of '%s'" % (bad, s, g))

    result = {
        "file": path,
        "femur_vertices": len(verts["femur"]),
        "tibia_vertices": len(verts["tibia"]),
        "femur_hexahedra": len(hexes["femur"]),
        "tibia_hexahedra": len(hexes["tibia"]),
        "hexahedra": len(hexes["femur"]) + len(hexes["tibia"]),
        "quads": {s: len(q) for s, q in quads.items()},
        "femur_volume": volume["femur"],
        "tibia_volume": volume["tibia"],
        "min_corner_quality": worst if worst < 1e299 else float("nan"),
        "errors": errors,
    }
    return result


def main(argv):
    quiet = "--quiet" in argv
    files = [a for a in argv if not a.startswith("--")]
    if not files:
        print(__doc__)
        return 2
    ok = True
    for path in files:
        try:
            r = check(path, quiet)
        except (MeshError, OSError, ValueError, KeyError) as e:
            print("FAIL %s: %s" % (path, e))
            ok = False
            continue
        nv = r["femur_vertices"] + r["tibia_vertices"]
        status = "ok  " if not r["errors"] else "FAIL"
        print(
            "%s %s: hex %d (femur %d, tibia %d), vertices femur %d tibia %d, "
            "Q1 DoFs %d, meshed volume femur %.6g tibia %.6g mm^3, "
            "min scaled corner Jacobian %.3f"
            % (
                status,
                path,
                r["hexahedra"],
                r["femur_hexahedra"],
                r["tibia_hexahedra"],
                r["femur_vertices"],
                r["tibia_vertices"],
                3 * nv,
                r["femur_volume"],
                r["tibia_volume"],
                r["min_corner_quality"],
            )
        )
        if not quiet:
            print("     quads: " + ", ".join("%s %d" % kv for kv in sorted(r["quads"].items())))
        for e in r["errors"]:
            print("     error: " + e)
        ok = ok and not r["errors"]
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
