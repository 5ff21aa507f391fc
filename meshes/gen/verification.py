"""Hertz verification meshes: sphere on block and cylinder on block.

Coordinates: the initial contact point is the origin; the block (tibia role)
fills [-W, W] x [-W, W] x [-D, 0] (cylinder: [-Lx/2, Lx/2] in x); the
sphere/cylinder (femur role) touches it from above with the initial gap `gap`
at the origin only.

Sphere body: the part of the ball of radius R centred at (0, 0, R + gap) with
r = sqrt(x^2 + y^2) <= r_side and z <= gap + h_cap: a spherical cap, cut flat at
height h_cap above the contact point (femur_fixation) and trimmed by a vertical
cylinder r = r_side (untagged side wall, 4+ mm high, so that no cell is
degenerate at the cap rim).  femur_contact is the whole spherical surface.

Cylinder body: the same cross-section in the (y, z) plane, extruded over the
slab length Lx in x (axis of the cylinder parallel to x).

Block mesh: 'box in box': a uniform inner box [-c, c]^2 x [-c, 0] of cubes of
size h0 under the contact point, surrounded by five graded blocks (four sides
and the bottom) that coarsen to the outer faces.  The sphere body is an O-grid
in plan (inner square + 4 ring blocks) with columns graded towards the sphere.
"""
import math

import numpy as np

from blockmesh import Body, graded, grid1d, size_near

R = 20.0  # sphere / cylinder radius
H_CAP = 10.0  # height of the flat cut above the contact point
R_SIDE = 12.0  # lateral trim radius (sphere) / half-width (cylinder)
W = 30.0  # block half-width
D = 30.0  # block depth
LX = 10.0  # cylinder slab length in x
GAP = 1e-3  # initial gap at the contact point

RESOLUTIONS = {
    #           h0 at contact, inner box half-width, shell layers, layers in body
    "coarse": dict(h0=0.6, c=3.6, nr=9, nz=6, nrs=6, nx=4),
    "medium": dict(h0=0.4, c=4.0, nr=12, nz=8, nrs=8, nx=6),
    "fine": dict(h0=0.27, c=4.05, nr=15, nz=12, nrs=11, nx=10),
}


def _even_cells(length, h):
    n = int(math.ceil(length / h))
    return n + (n % 2)


def block_box_in_box(body, h0, c, nr, tag_top="tibia_contact", tag_bottom="tibia_inferior"):
    """3D block [-W,W]^2 x [-D,0] with a refined inner box around the origin."""
    n = _even_cells(2 * c, h0)
    m = int(math.ceil(c / h0))
    x = np.linspace(-c, c, n + 1)
    z = np.linspace(-c, 0.0, m + 1)
    s = graded(nr, 1.0, h0 / (W - c))
    X_out = x * (W / c)
    Z_out = -D + (z + c) * (D / c)
    # inner box
    inner = np.stack(np.meshgrid(x, x, z, indexing="ij"), axis=-1)
    body.add(inner, {"kmax": tag_top})
    # side blocks, index order (t, along, z) with t the shell coordinate
    for sign in (+1, -1):
        for axis in (0, 1):
            P_in = np.zeros((n + 1, m + 1, 3))
            P_out = np.zeros((n + 1, m + 1, 3))
            P_in[:, :, axis] = sign * c
            P_out[:, :, axis] = sign * W
            P_in[:, :, 1 - axis] = x[:, None]
            P_out[:, :, 1 - axis] = X_out[:, None]
            P_in[:, :, 2] = z[None, :]
            P_out[:, :, 2] = Z_out[None, :]
            B = P_in[None] + s[:, None, None, None] * (P_out - P_in)[None]
            body.add(B, {"kmax": tag_top})
    # bottom block, index order (x, y, t)
    P_in = np.stack(np.meshgrid(x, x, [-c], indexing="ij"), axis=-1)[:, :, 0]
    P_out = np.stack(np.meshgrid(X_out, X_out, [-D], indexing="ij"), axis=-1)[:, :, 0]
    B = P_in[:, :, None] + s[None, None, :, None] * (P_out - P_in)[:, :, None]
    body.add(B, {"kmax": tag_bottom})
    return body


def sphere_body(h, nz, nr):
    """Spherical cap body over an O-grid plan."""
    body = Body("femur")
    c = 4.0
    n = _even_cells(2 * c, h)
    x = np.linspace(-c, c, n + 1)
    s = graded(nr, 1.0, h / (R_SIDE - c))

    def column(P):
        """P (..., 2) plan points -> (..., nz+1, 3) column nodes."""
        r2 = (P**2).sum(axis=-1)
        zb = GAP + R - np.sqrt(R * R - r2)
        zt = GAP + H_CAP
        sig = graded(nz, 1.0, h / (H_CAP))
        Z = zb[..., None] + (zt - zb)[..., None] * sig
        XY = np.broadcast_to(P[..., None, :], P.shape[:-1] + (nz + 1, 2))
        return np.concatenate([XY, Z[..., None]], axis=-1)

    faces = {"kmin": "femur_contact", "kmax": "femur_fixation"}
    P = np.stack(np.meshgrid(x, x, indexing="ij"), axis=-1)
    body.add(column(P), faces)
    phi = (math.pi / 4) * x / c
    for k in range(4):
        ang = k * math.pi / 2
        rot = np.array([[math.cos(ang), -math.sin(ang)], [math.sin(ang), math.cos(ang)]])
        P_in = np.stack([np.full_like(x, c), x], axis=-1) @ rot.T
        P_out = np.stack([R_SIDE * np.cos(phi), R_SIDE * np.sin(phi)], axis=-1) @ rot.T
        P = P_in[None] + s[:, None, None] * (P_out - P_in)[None]
        body.add(column(P), faces)
    return body


def sphere_volume():
    a2 = R_SIDE**2
    return math.pi * a2 * H_CAP - (math.pi * R * a2 - 2 * math.pi / 3 * (R**3 - (R * R - a2) ** 1.5))


def make_sphere(res):
    p = RESOLUTIONS[res]
    tib = block_box_in_box(Body("tibia"), p["h0"], p["c"], p["nr"])
    fem = sphere_body(p["h0"], p["nz"], p["nrs"])
    return {"femur": fem.assemble(), "tibia": tib.assemble()}, {
        "femur": sphere_volume(),
        "tibia": (2 * W) ** 2 * D,
    }


# ---------------------------------------------------------------- cylinder
def _extrude_x(P2, xs):
    """P2 (..., 2) (y, z) points -> (len(xs), ..., 3)."""
    out = np.empty((len(xs),) + P2.shape[:-1] + (3,))
    out[..., 0] = xs.reshape((-1,) + (1,) * (P2.ndim - 1))
    out[..., 1] = P2[..., 0]
    out[..., 2] = P2[..., 1]
    return out


def cylinder_block(h0, c, nr, nx):
    body = Body("tibia")
    xs = np.linspace(-LX / 2, LX / 2, nx + 1)
    n = _even_cells(2 * c, h0)
    m = int(math.ceil(c / h0))
    y = np.linspace(-c, c, n + 1)
    z = np.linspace(-c, 0.0, m + 1)
    s = graded(nr, 1.0, h0 / (W - c))
    Y_out = y * (W / c)
    Z_out = -D + (z + c) * (D / c)
    body.add(_extrude_x(np.stack(np.meshgrid(y, z, indexing="ij"), axis=-1), xs), {"kmax": "tibia_contact"})
    for sign in (+1, -1):
        P_in = np.stack(np.meshgrid([sign * c], z, indexing="ij"), axis=-1)[0]
        P_out = np.stack(np.meshgrid([sign * W], Z_out, indexing="ij"), axis=-1)[0]
        P = P_in[None] + s[:, None, None] * (P_out - P_in)[None]  # (t, k, 2)
        body.add(_extrude_x(P, xs), {"kmax": "tibia_contact"})
    P_in = np.stack(np.meshgrid(y, [-c], indexing="ij"), axis=-1)[:, 0]
    P_out = np.stack(np.meshgrid(Y_out, [-D], indexing="ij"), axis=-1)[:, 0]
    P = P_in[:, None] + s[None, :, None] * (P_out - P_in)[:, None]  # (j, t, 2)
    body.add(_extrude_x(P, xs), {"kmax": "tibia_inferior"})
    return body


def cylinder_body(h, nz, nx):
    body = Body("femur")
    xs = np.linspace(-LX / 2, LX / 2, nx + 1)
    y = grid1d([-R_SIDE, 0.0, R_SIDE], size_near([0.0], h, 2.5 * h + 0.5, 3.0, 0.35))
    zb = GAP + R - np.sqrt(R * R - y**2)
    zt = GAP + H_CAP
    sig = graded(nz, 1.0, h / H_CAP)
    Z = zb[:, None] + (zt - zb)[:, None] * sig[None, :]
    P = np.stack([np.broadcast_to(y[:, None], Z.shape), Z], axis=-1)
    body.add(_extrude_x(P, xs), {"kmin": "femur_contact", "kmax": "femur_fixation"})
    return body


def cylinder_volume():
    ys = R_SIDE
    area = (
        2 * ys * H_CAP
        - 2 * ys * R
        + 2 * (ys * math.sqrt(R * R - ys * ys) / 2 + R * R / 2 * math.asin(ys / R))
    )
    return area * LX


def make_cylinder(res):
    p = RESOLUTIONS[res]
    tib = cylinder_block(p["h0"], p["c"], p["nr"], p["nx"])
    fem = cylinder_body(p["h0"], p["nz"], p["nx"])
    return {"femur": fem.assemble(), "tibia": tib.assemble()}, {
        "femur": cylinder_volume(),
        "tibia": 2 * W * D * LX,
    }


def make_sphere_volumes():
    return {"femur": sphere_volume(), "tibia": (2 * W) ** 2 * D}


def make_cylinder_volumes():
    return {"femur": cylinder_volume(), "tibia": 2 * W * D * LX}
