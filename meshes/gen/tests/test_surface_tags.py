# SPDX-License-Identifier: LGPL-2.1-or-later
"""surface_tags.tag_pair() on a synthetic pair whose groups follow from the
geometry by hand.

Insert: the box 40 x 30 x 10 mm (x, y, z), z = 0 its base, triangulated on
a 0.5 mm grid.  Femur: a thick cylindrical shell about the axis parallel to
x through (Y0, Z0), outer radius R, inner R - 4 mm, 30 mm long, the polar
angle phi (from straight down towards +y) from -100 to 100 degrees in
1-degree facets.  The shell is invariant under a turn about its axis, so in
every flexion pose (phi turned by -5 ... 60 degrees) the lowered femur
touches the insert's top along the line y = Y0, and

* the flexion axis the tagging estimates is (0, Y0, Z0);
* femur_contact is the outer surface where phi + flexion lies within
  BETA = acos(1 - DISTANCE / R) of straight down for some flexion, i.e.
  phi in (-60 - BETA, 5 + BETA) degrees;
* femur_fixation is the inner surface (facing the bounding box's centre);
  the 30 mm long ends (|n_x| = 1) and the rims at phi = +-100 degrees
  (facing up, in the top 15 % of the height) stay untagged;
* tibia_contact is the insert's top where the cylinder is within DISTANCE
  of it: |y - Y0| < sqrt(R^2 - (R - DISTANCE)^2), |x| < 15 + DISTANCE;
* tibia_inferior is the base, nothing else.

The tagging measures distances to the other body's triangle corners and
centroids (not to its surface) and lowers the femur by its facets'
centroids, so the bands are checked within one facet: 1.5 degrees on the
femur, 0.5 mm on the insert.
"""
import numpy as np
import pytest

import surface_tags as st

Y0, R, THICKNESS, HALF_LENGTH, SPAN = 2.0, 25.0, 4.0, 15.0, 100.0
Z0 = 10.0 + R + 3.0  # 3 mm above the insert: tag_pair lowers the femur itself
DISTANCE = 1.0
BETA = np.degrees(np.arccos(1.0 - DISTANCE / R))


def grid_triangles(X, outward):
    """Two triangles per cell of the point grid X (ni x nj x 3), each turned
    so that its normal points along outward(centroids)."""
    a, b, c, d = X[:-1, :-1], X[1:, :-1], X[1:, 1:], X[:-1, 1:]
    T = np.concatenate([np.stack([a, b, c], -2).reshape(-1, 3, 3), np.stack([a, c, d], -2).reshape(-1, 3, 3)])
    n = np.cross(T[:, 1] - T[:, 0], T[:, 2] - T[:, 0])
    flip = np.einsum("ij,ij->i", n, outward(T.mean(axis=1))) < 0
    T[flip] = T[flip][:, ::-1]
    return T


def constant(v):
    return lambda c: np.broadcast_to(np.asarray(v, float), c.shape)


def box(lo, hi, h):
    """{(axis, side): triangles} of the closed box lo..hi, grids of about h."""
    faces = {}
    for axis in range(3):
        u, v = [k for k in range(3) if k != axis]
        su = np.linspace(lo[u], hi[u], int(round((hi[u] - lo[u]) / h)) + 1)
        sv = np.linspace(lo[v], hi[v], int(round((hi[v] - lo[v]) / h)) + 1)
        for side, value in ((-1, lo[axis]), (1, hi[axis])):
            X = np.zeros((len(su), len(sv), 3))
            X[..., axis] = value
            X[..., u], X[..., v] = np.meshgrid(su, sv, indexing="ij")
            faces[(axis, side)] = grid_triangles(X, constant(np.eye(3)[axis] * side))
    return faces


def shell():
    """{part: triangles} of the femur (outer, inner, two rims, two ends)."""
    phi = np.radians(np.linspace(-SPAN, SPAN, int(2 * SPAN) + 1))
    x = np.linspace(-HALF_LENGTH, HALF_LENGTH, int(2 * HALF_LENGTH) + 1)
    r = np.linspace(R - THICKNESS, R, 4)

    def point(x, r, phi):
        return np.stack([x, Y0 + r * np.sin(phi), Z0 - r * np.cos(phi)], -1)

    def radial(c):
        return np.column_stack([np.zeros(len(c)), c[:, 1] - Y0, c[:, 2] - Z0])

    X, P = np.meshgrid(x, phi, indexing="ij")
    parts = {
        "outer": grid_triangles(point(X, R, P), radial),
        "inner": grid_triangles(point(X, R - THICKNESS, P), lambda c: -radial(c)),
    }
    end = np.radians(SPAN)
    for s in (-1, 1):
        Xr, Rr = np.meshgrid(x, r, indexing="ij")
        parts["rim%+d" % s] = grid_triangles(
            point(Xr, Rr, s * end), constant([0.0, s * np.cos(end), np.sin(end)])
        )
        Rp, Pp = np.meshgrid(r, phi, indexing="ij")
        parts["end%+d" % s] = grid_triangles(
            point(np.full(Rp.shape, s * HALF_LENGTH), Rp, Pp), constant([s, 0, 0])
        )
    return parts


def labels_by_part(parts, labels):
    out, start = {}, 0
    for name, T in parts.items():
        out[name] = labels[start : start + len(T)]
        start += len(T)
    return out


def test_synthetic_pair_is_closed():
    """The surfaces are closed (every edge shared by two triangles) and
    outward (positive enclosed volume), as tag_pair() expects."""
    for parts in (shell(), box((-20.0, -15.0, 0.0), (20.0, 15.0, 10.0), 0.5)):
        T = np.concatenate(list(parts.values()))
        _, _, edges, _, _ = st.shared_edges(T)
        assert 2 * len(edges) == 3 * len(T)
        volume = np.einsum("ij,ij->i", T[:, 0], np.cross(T[:, 1], T[:, 2])).sum() / 6
        assert volume > 0


def test_tag_pair_groups_of_shell_on_box():
    femur = shell()
    insert = box((-20.0, -15.0, 0.0), (20.0, 15.0, 10.0), 0.5)
    fem_tris = np.concatenate(list(femur.values()))
    ins_tris = np.concatenate(list(insert.values()))
    fem, ins, point = st.tag_pair(fem_tris, ins_tris, DISTANCE)

    assert point == pytest.approx((0.0, Y0, Z0), abs=1e-6)

    fem = labels_by_part(femur, fem)
    c, _ = st.normals(femur["outer"])
    phi = np.degrees(np.arctan2(c[:, 1] - Y0, Z0 - c[:, 2]))
    contact = fem["outer"] == st.CONTACT
    lo, hi = -60.0 - BETA, 5.0 + BETA
    assert np.all(contact[(phi > lo + 1.5) & (phi < hi - 1.5)])
    assert not np.any(contact[(phi < lo - 1.5) | (phi > hi + 1.5)])
    assert np.all(fem["outer"][~contact] == st.UNTAGGED)
    assert np.all(fem["inner"] == st.OTHER)
    for name in ("rim-1", "rim+1", "end-1", "end+1"):
        assert np.all(fem[name] == st.UNTAGGED), name

    ins = labels_by_part(insert, ins)
    assert np.all(ins[(2, -1)] == st.OTHER)  # the base
    for face in ((0, -1), (0, 1), (1, -1), (1, 1)):  # the walls
        assert np.all(ins[face] == st.UNTAGGED), face
    c, _ = st.normals(insert[(2, 1)])
    half_width = np.sqrt(R**2 - (R - DISTANCE) ** 2)
    dy, dx = np.abs(c[:, 1] - Y0), np.abs(c[:, 0])
    contact = ins[(2, 1)] == st.CONTACT
    assert np.all(contact[(dy < half_width - 0.5) & (dx < HALF_LENGTH)])
    assert not np.any(contact[(dy > half_width + 0.5) | (dx > HALF_LENGTH + DISTANCE)])
    assert np.all(ins[(2, 1)][~contact] == st.UNTAGGED)


def test_convex_femur_has_no_fixation():
    """A solid cylinder (no surface faces its bounding box's centre) gives
    no femur_fixation: tag_pair() refuses it, naming the group."""
    phi = np.radians(np.linspace(-180.0, 180.0, 121))
    x = np.linspace(-HALF_LENGTH, HALF_LENGTH, 31)
    X, P = np.meshgrid(x, phi, indexing="ij")
    side = grid_triangles(
        np.stack([X, Y0 + R * np.sin(P), Z0 - R * np.cos(P)], -1),
        lambda c: np.column_stack([np.zeros(len(c)), c[:, 1] - Y0, c[:, 2] - Z0]),
    )
    insert = np.concatenate(list(box((-20.0, -15.0, 0.0), (20.0, 15.0, 10.0), 1.0).values()))
    with pytest.raises(ValueError, match="femur_fixation"):
        st.tag_pair(side, insert, DISTANCE)


def test_smooth_patches_of_a_box_are_its_faces():
    """patches(): across the box's edges the normals turn by 90 degrees, so
    with a 30-degree feature angle the smooth patches are the six faces."""
    faces = box((0.0, 0.0, 0.0), (4.0, 3.0, 2.0), 0.5)
    T = np.concatenate(list(faces.values()))
    patch = st.patches(T, 30.0, 0.1)
    assert len(np.unique(patch)) == 6
    start = 0
    for t in faces.values():
        assert len(np.unique(patch[start : start + len(t)])) == 1
        start += len(t)
