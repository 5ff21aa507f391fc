"""Parametric total knee replacement: femoral component + fixed-bearing insert.

Coordinates (DESIGN.md section 3): x medial-lateral, y anterior-posterior (+y
anterior), z axial (+z proximal), mm.  The geometry is symmetric in x, so the
same mesh serves left and right knees.  See doc/geometry.md for the
description, the chosen values and their sources.

Tibial insert
    Plan: rounded rectangle width x depth, corner radius r_corner, centred at
    the origin.  Bottom z = 0 (tibia_inferior).  Top (tibia_contact):
    z = min(t_min + plateau, dish_medial, dish_lateral): a flat plateau into
    which two toroidal dishes are cut.  A dish is the lower surface of a torus
    whose axis is parallel to x at height t_min + R_ts above the dish bottom
    (x = +-x_c, y = y_dish, z = t_min), tube radius R_tf: its sagittal radius
    is R_ts and its frontal radius R_tf at the bottom.  Conformity =
    femoral radius / tibial radius.

Femoral component
    A sweep of a frontal (x, eta) section along a sagittal (y, z) reference
    curve Q(s) (the J-curve of the condyle apex line), eta = inset along the
    outward normal n(s):  X(x, s, eta) = (x, Q(s) - eta n(s)).
    J-curve, anterior to posterior: straight anterior flange (length
    L_flange), anterior arc R_a, distal arc R_d, posterior arc R_p, all
    tangent-continuous; theta = angle from the -z direction towards -y
    (posterior), i.e. the flexion angle at which that point is lowest.
    Frontal section of a condyle (u = |x| - x_c): outer profile eta = delta(u)
    = circular arc of radius R_f (frontal radius) with rounded edges (fillet
    radius r_edge up to slope angle alpha_edge at |u| = w_condyle);
    fixation side eta = t_fem (flat in x, like the bone cuts; thickness
    t_fem at the condyle apex, t_fem - delta_edge at the edges).  Anterior of
    theta_notch the two condyles are joined by a bridge (eta in
    [delta_edge, t_fem]): the anterior flange; posterior of it the
    intercondylar notch is open.
    Position: the lowest points of the condyles (theta = 0, u = 0) lie at
    (+-x_c, y_dish, t_min + gap), i.e. exactly above the dish bottoms with
    the initial gap `gap` (0 deg flexion).
"""
import math

import numpy as np

from blockmesh import Body, graded, grid1d, size_near, write_msh

DEG = math.pi / 180.0

VARIANTS = {
    # A: moderately conforming multi-radius design
    "a": dict(
        width=70.0,
        depth=47.0,
        r_corner=14.0,
        t_min=9.0,
        plateau=8.0,
        x_c=22.0,
        y_dish=-2.0,
        R_ts=55.0,
        R_tf=27.0,
        R_d=44.0,
        R_p=21.0,
        R_a=25.0,
        th_fa=-75.0,
        th_0=-20.0,
        th_1=25.0,
        th_2=110.0,
        th_notch=-55.0,
        L_flange=20.0,
        R_f=25.0,
        w_condyle=11.5,
        r_edge=4.0,
        alpha_edge=40.0,
        t_fem=8.0,
        gap=1e-3,
    ),
    # B: flatter, less conforming insert; single-radius-like femur
    "b": dict(
        width=72.0,
        depth=48.0,
        r_corner=10.0,
        t_min=8.0,
        plateau=6.0,
        x_c=21.0,
        y_dish=-1.0,
        R_ts=100.0,
        R_tf=40.0,
        R_d=36.0,
        R_p=24.0,
        R_a=22.0,
        th_fa=-75.0,
        th_0=-15.0,
        th_1=10.0,
        th_2=115.0,
        th_notch=-55.0,
        L_flange=20.0,
        R_f=22.0,
        w_condyle=10.5,
        r_edge=4.0,
        alpha_edge=40.0,
        t_fem=7.8,
        gap=1e-3,
    ),
}

# Mesh resolutions.  h_*: target in-plane cell sizes (mm) in the contact zone
# and away from it; nz / nk: cell layers through tibia / femur thickness.
RESOLUTIONS = {
    "coarse": dict(
        ht=3.2, ht_far=5.0, nz=4, hz_top=1.6, hf_x=2.6, hf_x_far=4.0, hf_s=2.8, hf_s_far=6.0, nk=2
    ),
    "medium": dict(
        ht=1.35, ht_far=3.0, nz=8, hz_top=0.6, hf_x=1.3, hf_x_far=2.5, hf_s=1.3, hf_s_far=4.0, nk=3
    ),
    "fine": dict(
        ht=0.85, ht_far=2.0, nz=11, hz_top=0.35, hf_x=0.9, hf_x_far=1.8, hf_s=0.9, hf_s_far=3.0, nk=4
    ),
}


# per-variant adjustments so that both variants hit the same vertex-count brackets
RESOLUTION_OVERRIDES = {("b", "coarse"): dict(ht=3.45), ("b", "fine"): dict(ht=0.88)}


def resolution(variant, res):
    r = dict(RESOLUTIONS[res])
    r.update(RESOLUTION_OVERRIDES.get((variant, res), {}))
    return r


class Geometry:
    def __init__(self, variant, params=None):
        """variant: a key of VARIANTS, or any name with its params (the
        same keys; tkr_ps.py's variant C)."""
        self.variant = variant
        p = dict(VARIANTS[variant] if params is None else params)
        self.p = p
        for k, v in p.items():
            setattr(self, k, v)
        # ---------------- tibia
        self.A = self.width / 2
        self.B = self.depth / 2
        self.H = self.t_min + self.plateau
        self.z_axis = self.t_min + self.R_ts
        # ---------------- femur frontal profile
        Rf, re, ae, w = self.R_f, self.r_edge, self.alpha_edge * DEG, self.w_condyle
        self.u1 = (w - re * math.sin(ae)) / (1 - re / Rf)
        b1 = math.asin(self.u1 / Rf)
        self.fil_u = (Rf - re) * math.sin(b1)
        self.fil_eta = Rf - (Rf - re) * math.cos(b1)
        self.delta_edge = self.fil_eta - re * math.cos(ae)
        assert self.delta_edge < self.t_fem - 4.0, "femoral shell too thin at the edges"
        # ---------------- femur J-curve
        self.th = {k: getattr(self, k) * DEG for k in ("th_fa", "th_0", "th_1", "th_2", "th_notch")}
        zc = self.t_min + self.gap
        self.C_d = np.array([self.y_dish, zc + self.R_d])
        self.C_a = self.C_d + (self.R_d - self.R_a) * e(self.th["th_0"])
        self.C_p = self.C_d + (self.R_d - self.R_p) * e(self.th["th_1"])
        Q_fa = self.C_a + self.R_a * e(self.th["th_fa"])
        t_fa = np.array([math.cos(self.th["th_fa"]), -math.sin(self.th["th_fa"])])  # up the flange
        self.F_top = Q_fa + self.L_flange * t_fa
        # arc-length breakpoints
        S1 = self.L_flange
        S2 = S1 + self.R_a * (self.th["th_0"] - self.th["th_fa"])
        S3 = S2 + self.R_d * (self.th["th_1"] - self.th["th_0"])
        S4 = S3 + self.R_p * (self.th["th_2"] - self.th["th_1"])
        self.S = (0.0, S1, S2, S3, S4)
        self.s_notch = S1 + self.R_a * (self.th["th_notch"] - self.th["th_fa"])
        assert S1 < self.s_notch < S2
        self.x_out = self.x_c + self.w_condyle
        self.x_in = self.x_c - self.w_condyle

    # ---------------------------------------------------------------- femur
    def delta(self, x):
        """Frontal inset of the outer surface (>= 0) as a function of x."""
        x = np.asarray(x, float)
        u = np.abs(np.abs(x) - self.x_c)
        out = np.where(
            u <= self.u1,
            self.R_f - np.sqrt(np.maximum(self.R_f**2 - u**2, 0)),
            self.fil_eta - np.sqrt(np.maximum(self.r_edge**2 - (u - self.fil_u) ** 2, 0)),
        )
        return np.where(np.abs(x) < self.x_in, self.delta_edge, out)

    def curve(self, s):
        """Q(s), n(s) (outward unit normal), curvature kappa(s) for arrays s."""
        s = np.asarray(s, float)
        S0, S1, S2, S3, S4 = self.S
        Q = np.zeros(s.shape + (2,))
        n = np.zeros(s.shape + (2,))
        k = np.zeros(s.shape)
        th_fa, th_0, th_1 = self.th["th_fa"], self.th["th_0"], self.th["th_1"]
        # flange: from F_top (s = 0) down to Q_fa (s = S1)
        m = s < S1
        nfa = e(th_fa)
        tdown = -np.array([math.cos(th_fa), -math.sin(th_fa)])
        Q[m] = self.F_top + s[m, None] * tdown
        n[m] = nfa
        for lo, hi, C, R, th_lo in (
            (S1, S2, self.C_a, self.R_a, th_fa),
            (S2, S3, self.C_d, self.R_d, th_0),
            (S3, S4 + 1e-9, self.C_p, self.R_p, th_1),
        ):
            m = (s >= lo) & (s < hi) if hi < S4 else (s >= lo)
            theta = th_lo + (s[m] - lo) / R
            ee = np.stack([-np.sin(theta), -np.cos(theta)], axis=-1)
            Q[m] = C + R * ee
            n[m] = ee
            k[m] = 1.0 / R
        return Q, n, k

    def s_of_theta(self, theta_deg):
        t = theta_deg * DEG
        S0, S1, S2, S3, S4 = self.S
        if t <= self.th["th_0"]:
            return S1 + self.R_a * (t - self.th["th_fa"])
        if t <= self.th["th_1"]:
            return S2 + self.R_d * (t - self.th["th_0"])
        return S3 + self.R_p * (t - self.th["th_1"])

    def femur_point(self, x, s, w):
        """Map (x, s, w in [0,1]) -> 3D, w = 0 articular, w = 1 fixation."""
        x, s, w = np.broadcast_arrays(np.asarray(x, float), np.asarray(s, float), np.asarray(w, float))
        Q, n, _ = self.curve(s)
        d = self.delta(x)
        eta = d + w * (self.t_fem - d)
        P = np.empty(x.shape + (3,))
        P[..., 0] = x
        P[..., 1:] = Q - eta[..., None] * n
        return P

    def femur_volume_analytic(self):
        """Exact volume by Gauss quadrature of the sweep:
        V = int_x int_s int_eta (1 - kappa eta) d eta ds dx."""
        g, wg = np.polynomial.legendre.leggauss(24)
        S0, S1, S2, S3, S4 = self.S
        kap = [(S0, S1, 0.0), (S1, S2, 1 / self.R_a), (S2, S3, 1 / self.R_d), (S3, S4, 1 / self.R_p)]

        def int_x(a, b, f):
            xs = 0.5 * (a + b) + 0.5 * (b - a) * g
            return 0.5 * (b - a) * np.sum(wg * f(xs))

        t = self.t_fem
        V = 0.0
        xc, u1, w = self.x_c, self.u1, self.w_condyle
        pieces_condyle = [(xc - w, xc - u1), (xc - u1, xc), (xc, xc + u1), (xc + u1, xc + w)]
        for lo, hi, k in kap:
            L = hi - lo

            def f(xs):
                return L * (t - self.delta(xs)) - k * L * (t**2 - self.delta(xs) ** 2) / 2

            for a, b in pieces_condyle:
                V += 2 * int_x(a, b, f)
        # bridge, s in [0, s_notch]
        for lo, hi, k in kap:
            lo2, hi2 = lo, min(hi, self.s_notch)
            if hi2 <= lo2:
                continue
            L = hi2 - lo2
            d = self.delta_edge
            V += 2 * self.x_in * (L * (t - d) - k * L * (t**2 - d**2) / 2)
        return V

    # ---------------------------------------------------------------- tibia
    def dish(self, x, y, side):
        """Torus lower surface height of one dish (inf outside the torus)."""
        u = np.asarray(x, float) - side * self.x_c
        v = np.asarray(y, float) - self.y_dish
        inside = np.abs(u) <= self.R_tf
        rho = (self.R_ts - self.R_tf) + np.sqrt(np.maximum(self.R_tf**2 - u**2, 0))
        inside &= np.abs(v) < rho
        z = self.z_axis - np.sqrt(np.maximum(rho**2 - v**2, 0))
        return np.where(inside, z, np.inf)

    def tibia_top(self, x, y):
        return np.minimum(self.H, np.minimum(self.dish(x, y, +1), self.dish(x, y, -1)))

    def outline_sd(self, P):
        """Signed distance to the rounded-rectangle outline (negative inside)."""
        r = self.r_corner
        q = np.abs(P) - np.array([self.A - r, self.B - r])
        out = np.linalg.norm(np.maximum(q, 0), axis=-1) + np.minimum(np.max(q, axis=-1), 0)
        return out - r

    def outline_ray(self, P):
        """Points where rays from the origin through P hit the outline."""
        P = np.asarray(P, float)
        lo = np.zeros(P.shape[:-1])
        hi = np.full(P.shape[:-1], 10.0)
        for _ in range(80):
            mid = 0.5 * (lo + hi)
            inside = self.outline_sd(P * mid[..., None]) < 0
            lo = np.where(inside, mid, lo)
            hi = np.where(inside, hi, mid)
        return P * (0.5 * (lo + hi))[..., None]

    # ------------------------------------------------------------- gap check
    def femur_lower_surface(self, xs, ys, flexion_deg=0.0):
        """Height of the femur articular surface above (x, y) after a rigid
        flexion rotation about the distal-arc centre (inf where there is no
        femur above).  Used for the clearance check only."""
        phi = flexion_deg * DEG
        s = np.linspace(0, self.S[4], 6000)
        out = np.full(np.broadcast(xs, ys).shape, np.inf)
        xs_b, ys_b = np.broadcast_arrays(np.asarray(xs, float), np.asarray(ys, float))
        for xv in np.unique(xs_b):
            if abs(xv) > self.x_out:
                continue
            sel = xs_b == xv
            ss = s if abs(xv) >= self.x_in else s[s <= self.s_notch]
            P = self.femur_point(np.full_like(ss, xv), ss, np.zeros_like(ss))[:, 1:]
            # rotate about C_d by +phi about +x (theta -> theta - phi)
            c, sn = math.cos(phi), math.sin(phi)
            d = P - self.C_d
            P = self.C_d + np.stack([c * d[:, 0] - sn * d[:, 1], sn * d[:, 0] + c * d[:, 1]], axis=-1)
            _, n, _ = self.curve(ss)
            nz = sn * n[:, 0] + c * n[:, 1]
            low = nz < 0  # facing down
            if not np.any(low):
                continue
            Py = P[low, 0]
            Pz = P[low, 1]
            order = np.argsort(Py)
            zq = np.interp(ys_b[sel], Py[order], Pz[order], left=np.inf, right=np.inf)
            out[sel] = zq
        return out


def e(theta):
    return np.array([-math.sin(theta), -math.cos(theta)])


# ---------------------------------------------------------------------------
# meshes
# ---------------------------------------------------------------------------
def tibia_body(g, r):
    body = Body("tibia")
    # inner rectangle: its corners lie 3 mm inside the outline's corner arcs
    # (on the diagonal), so the ring is 3 mm thick at the corners
    rc = g.r_corner * (1 - 1 / math.sqrt(2)) + 3.0
    a, b = g.A - rc, g.B - rc
    n_ring = max(1, int(math.ceil(rc / (1.5 * r["ht"]))))
    xsz = size_near([-g.x_c, g.x_c], r["ht"], r["ht_far"], 9.0, 0.3)
    ysz = size_near([g.y_dish], r["ht"], r["ht_far"], 12.0, 0.3)
    x = grid1d([-a, -g.x_c, 0.0, g.x_c, a], xsz)
    y = grid1d([-b, g.y_dish, b], ysz)
    nz = r["nz"]
    s_ring = np.linspace(0.0, 1.0, n_ring + 1)

    def column(P):
        h = g.tibia_top(P[..., 0], P[..., 1])
        sig = 1.0 - graded(nz, 1.0, r["hz_top"] / g.t_min)[::-1]
        Z = h[..., None] * sig
        XY = np.broadcast_to(P[..., None, :], P.shape[:-1] + (nz + 1, 2))
        return np.concatenate([XY, Z[..., None]], axis=-1)

    faces = {"kmin": "tibia_inferior", "kmax": "tibia_contact"}
    P = np.stack(np.meshgrid(x, y, indexing="ij"), axis=-1)
    body.add(column(P), faces)
    # ring blocks: (t, along) plan arrays
    for edge in (
        np.stack([np.full_like(y, a), y], -1),
        np.stack([np.full_like(y, -a), y], -1),
        np.stack([x, np.full_like(x, b)], -1),
        np.stack([x, np.full_like(x, -b)], -1),
    ):
        out = g.outline_ray(edge)
        P = edge[None] + s_ring[:, None, None] * (out - edge)[None]
        body.add(column(P), faces)
    return body


def femur_body(g, r):
    body = Body("femur")
    xsz = size_near([-g.x_c, g.x_c], r["hf_x"], r["hf_x_far"], 7.0, 0.3)
    xc, u1, w = g.x_c, g.u1, g.w_condyle
    xr = grid1d([xc - w, xc - u1, xc, xc + u1, xc + w], xsz)
    xl = -xr[::-1]
    xm = grid1d([-g.x_in, 0.0, g.x_in], lambda s: r["hf_x_far"])
    s_lo, s_hi = g.s_of_theta(-15.0), g.s_of_theta(70.0)

    def ssz(s):
        d = max(0.0, s_lo - s, s - s_hi)
        return min(r["hf_s_far"], r["hf_s"] + 0.25 * d)

    S = g.S
    # a node at theta = 0 (the initial contact point)
    brk = sorted(set([S[0], S[1], g.s_notch, S[2], g.s_of_theta(0.0), S[3], S[4]]))
    s = grid1d(brk, ssz)
    jn = int(np.argmin(np.abs(s - g.s_notch)))
    assert abs(s[jn] - g.s_notch) < 1e-9
    wk = graded(r["nk"], 1.0, 0.6 / r["nk"]) if r["nk"] > 1 else np.array([0.0, 1.0])

    def block(xv, sv):
        Xg, Sg, Wg = np.meshgrid(xv, sv, wk, indexing="ij")
        return g.femur_point(Xg, Sg, Wg)

    cond = {"kmin": "femur_contact", "kmax": "femur_fixation"}
    body.add(block(xl, s), cond)
    body.add(block(xr, s), cond)
    body.add(block(xm, s[: jn + 1]), {"kmax": "femur_fixation"})
    return body


def make_mesh(variant, res):
    g = Geometry(variant)
    r = resolution(variant, res)
    return {"femur": femur_body(g, r).assemble(), "tibia": tibia_body(g, r).assemble()}


def write_mesh(variant, res, path):
    bodies = make_mesh(variant, res)
    write_msh(path, bodies, "tkr-%s-%s" % (variant, res))


# ---------------------------------------------------------------------------
# CAD (OpenCASCADE through gmsh): exact volumes and STEP/STL export
# ---------------------------------------------------------------------------
def _occ_profile_wire(g, s0, with_bridge, side=None):
    """Closed wire of the frontal section at arc length s0 (OCC point/curve
    tags).  side=+1/-1: one condyle only; with_bridge: full width."""
    import gmsh

    occ = gmsh.model.occ
    Q, n, _ = g.curve(np.array([s0]))
    Q, n = Q[0], n[0]

    def P(x, eta):
        pt = Q - eta * n
        return occ.addPoint(x, pt[0], pt[1])

    def arc_pts(xa, xb, center):  # circle arc on the profile between x = xa and xb
        return (P(xa, float(g.delta(xa))), P(center[0], center[1]), P(xb, float(g.delta(xb))))

    xc, u1, w, Rf = g.x_c, g.u1, g.w_condyle, g.R_f
    curves = []

    def condyle(sign):
        # outer profile of one condyle from its inner edge to its outer edge
        # (in the direction of increasing sign*x)
        cx = sign * xc
        segs = [
            (cx - sign * w, cx - sign * u1, (cx - sign * g.fil_u, g.fil_eta)),
            (cx - sign * u1, cx + sign * u1, (cx, Rf)),
            (cx + sign * u1, cx + sign * w, (cx + sign * g.fil_u, g.fil_eta)),
        ]
        return segs

    t = g.t_fem
    if with_bridge:
        segs = list(reversed([(b, a, c) for (a, b, c) in condyle(-1)])) + condyle(+1)
        # left outer edge -> ... -> right outer edge, with a bridge line in between
        first = None
        last = None
        prev_end = None
        for i, (a, b, c) in enumerate(segs):
            pa, pc, pb = arc_pts(a, b, c)
            if prev_end is not None:
                # connect previous end to this start (bridge or coincident)
                if abs(prev_end[0] - a) > 1e-9:
                    curves.append(occ.addLine(prev_end[1], pa))
                else:
                    occ.remove([(0, pa)])
                    pa = prev_end[1]
            curves.append(occ.addCircleArc(pa, pc, pb))
            if first is None:
                first = pa
            prev_end = (b, pb)
        last = prev_end[1]
        x0, x1 = -g.x_out, g.x_out
    else:
        segs = condyle(side)
        if side < 0:
            segs = list(reversed([(b, a, c) for (a, b, c) in segs]))
        prev_end = None
        first = None
        for a, b, c in segs:
            pa, pc, pb = arc_pts(a, b, c)
            if prev_end is not None:
                occ.remove([(0, pa)])
                pa = prev_end[1]
            curves.append(occ.addCircleArc(pa, pc, pb))
            if first is None:
                first = pa
            prev_end = (b, pb)
        last = prev_end[1]
        x0, x1 = segs[0][0], segs[-1][1]
    p_in1 = P(x1, t)
    p_in0 = P(x0, t)
    curves.append(occ.addLine(last, p_in1))
    curves.append(occ.addLine(p_in1, p_in0))
    curves.append(occ.addLine(p_in0, first))
    loop = occ.addCurveLoop(curves)
    return occ.addPlaneSurface([loop])


def _occ_sweep(g, surf, s0, s1):
    """Sweep a section surface from s0 to s1 (within one segment)."""
    import gmsh

    occ = gmsh.model.occ
    S = g.S
    if s1 <= S[1] + 1e-12:
        Q0, _, _ = g.curve(np.array([s0]))
        Q1, _, _ = g.curve(np.array([s1]))
        d = Q1[0] - Q0[0]
        out = occ.extrude([(2, surf)], 0, d[0], d[1])
    else:
        if s0 >= S[3] - 1e-12:
            C, R = g.C_p, g.R_p
        elif s0 >= S[2] - 1e-12:
            C, R = g.C_d, g.R_d
        else:
            C, R = g.C_a, g.R_a
        dth = (s1 - s0) / R
        out = occ.revolve([(2, surf)], 0, C[0], C[1], 1, 0, 0, -dth)
    return [dt for dt in out if dt[0] == 3]


def build_occ(g, which=("femur", "tibia")):
    """Build the CAD solids in the current gmsh model; return {name: [tags]}."""
    import gmsh

    occ = gmsh.model.occ
    res = {}
    if "femur" in which:
        S = g.S
        segs = [(S[0], S[1]), (S[1], g.s_notch), (g.s_notch, S[2]), (S[2], S[3]), (S[3], S[4])]
        vols = []
        for s0, s1 in segs:
            if s1 <= g.s_notch + 1e-12:
                surf = _occ_profile_wire(g, s0, True)
                vols += _occ_sweep(g, surf, s0, s1)
            else:
                for side in (-1, +1):
                    surf = _occ_profile_wire(g, s0, False, side)
                    vols += _occ_sweep(g, surf, s0, s1)
        occ.synchronize()
        fused, _ = occ.fuse(vols[:1], vols[1:])
        occ.synchronize()
        res["femur"] = [t for d, t in fused if d == 3]
    if "tibia" in which:
        rect = occ.addRectangle(-g.A, -g.B, 0, 2 * g.A, 2 * g.B, roundedRadius=g.r_corner)
        prism = occ.extrude([(2, rect)], 0, 0, g.H)
        prism = [dt for dt in prism if dt[0] == 3]
        tori = [occ_dish(side * g.x_c, g.y_dish, g.z_axis, g.R_ts, g.R_tf) for side in (-1, +1)]
        cut, _ = occ.cut(prism, tori)
        occ.synchronize()
        res["tibia"] = [t for d, t in cut if d == 3]
    return res


def occ_dish(x, y, z, r_sagittal, r_frontal):
    """A dish of the insert as an OpenCASCADE torus of the current model,
    its axis along x through (x, y, z): the sagittal radius r_sagittal, the
    frontal radius r_frontal. Returns its (dim, tag)."""
    import gmsh

    occ = gmsh.model.occ
    t = occ.addTorus(0, 0, 0, r_sagittal - r_frontal, r_frontal)
    occ.rotate([(3, t)], 0, 0, 0, 0, 1, 0, math.pi / 2)  # axis z -> x
    occ.translate([(3, t)], x, y, z)
    return (3, t)


_VOL_CACHE = {}


def cad_volumes(variant):
    """Exact CAD volumes (OpenCASCADE getMass) of femur and tibia."""
    if variant in _VOL_CACHE:
        return _VOL_CACHE[variant]
    import gmsh

    g = Geometry(variant)
    gmsh.initialize(["gmsh", "-v", "0"])
    try:
        gmsh.model.add("cad")
        tags = build_occ(g)
        vols = {k: sum(gmsh.model.occ.getMass(3, t) for t in v) for k, v in tags.items()}
    finally:
        gmsh.finalize()
    va = g.femur_volume_analytic()
    if abs(va / vols["femur"] - 1) > 1e-6:
        raise RuntimeError("femur volume: OCC %.6f vs quadrature %.6f" % (vols["femur"], va))
    _VOL_CACHE[variant] = vols
    return vols


def export_cad(variant, outdir, stl_size=1.5):
    """Write <outdir>/tkr-<v>-femur.step/.stl and tkr-<v>-insert.step/.stl."""
    import os

    import gmsh

    g = Geometry(variant)
    files = []
    for name, fname in (("femur", "femur"), ("tibia", "insert")):
        gmsh.initialize(["gmsh", "-v", "0"])
        try:
            gmsh.model.add(name)
            build_occ(g, (name,))
            base = os.path.join(outdir, "tkr-%s-%s" % (variant, fname))
            gmsh.write(base + ".step")
            gmsh.option.setNumber("Mesh.MeshSizeMax", stl_size)
            gmsh.option.setNumber("Mesh.MeshSizeFromCurvature", 12)
            gmsh.model.mesh.generate(2)
            gmsh.option.setNumber("Mesh.Binary", 1)
            gmsh.write(base + ".stl")
            files += [base + ".step", base + ".stl"]
        finally:
            gmsh.finalize()
    return files


def clearance_report(variant, flexions=(0, 10, 20, 30, 40, 50, 60), step=0.25):
    """Exact-geometry contact check: for each flexion angle (rigid rotation of
    the femur about the distal-arc centre), the femur is lowered until it
    touches; report where it touches and the smallest clearance elsewhere."""
    g = Geometry(variant)
    xs = np.arange(-g.A, g.A + 1e-9, step)
    ys = np.arange(-g.B, g.B + 1e-9, step)
    X, Y = np.meshgrid(xs, ys, indexing="ij")
    inside = g.outline_sd(np.stack([X, Y], -1)) < 0
    Ht = g.tibia_top(X, Y)
    lines = []
    for phi in flexions:
        Zf = g.femur_lower_surface(X, Y, phi)
        gap = np.where(inside, Zf - Ht, np.inf)
        gmin = gap.min()
        gap = gap - gmin
        # the touching points (one per condyle), then clearance away from them
        far = np.ones_like(gap, bool)
        for side in (-1, 1):
            gs = np.where(X * side > 0, gap, np.inf)
            j = np.unravel_index(np.argmin(gs), gs.shape)
            far &= np.hypot(X - X[j], Y - Y[j]) > 12.0
            lines.append(
                "flexion %4.0f deg: condyle %+d touches at x %+6.2f y %+6.2f (dish bottom y %+.1f)"
                % (phi, side, X[j], Y[j], g.y_dish)
            )
        notch = np.abs(X) < g.x_in + 0.01
        plateau = Ht >= g.H - 1e-9
        lines.append(
            "flexion %4.0f deg: gap at touch %.4f mm; min clearance >12 mm from the touch points "
            "%.2f mm; over plateau/eminence %.2f mm; under the notch %.2f mm"
            % (
                phi,
                gmin,
                np.min(np.where(far, gap, np.inf)),
                np.min(np.where(plateau, gap, np.inf)),
                np.min(np.where(notch, gap, np.inf)),
            )
        )
    return lines


def geometry_report(variant, meshes=()):
    """Text report: parameters, derived dimensions, candidate flexion axes,
    exact-geometry clearances over flexion and the discrete initial gaps of
    the given mesh files (bodies dicts)."""
    g = Geometry(variant)
    vols = cad_volumes(variant)
    L = [
        "TKR variant %s: parametric geometry report (generated by meshes/gen/tkr.py; mm)" % variant.upper(),
        "",
    ]
    L.append("parameters:")
    for k, v in VARIANTS[variant].items():
        L.append("  %-12s %g" % (k, v))
    fem = g.femur_point(
        np.linspace(-g.x_out, g.x_out, 5)[:, None], np.linspace(0, g.S[4], 2000)[None, :], 0.0
    ).reshape(-1, 3)
    L += [
        "",
        "derived:",
        "  insert: width %.1f (x), depth %.1f (y), height %.1f (plateau top z = %.1f), "
        "minimum thickness %.1f at the dish bottoms (+-%.1f, %.1f, %.1f)"
        % (2 * g.A, 2 * g.B, g.H, g.H, g.t_min, g.x_c, g.y_dish, g.t_min),
        "  insert conformity: sagittal R_d/R_ts = %.2f (posterior arc R_p/R_ts = %.2f), "
        "frontal R_f/R_tf = %.2f" % (g.R_d / g.R_ts, g.R_p / g.R_ts, g.R_f / g.R_tf),
        "  femoral component: width %.1f, AP extent %.1f (y %.1f..%.1f), height %.1f (z %.1f..%.1f), "
        "condyle width %.1f, notch width %.1f, condyle spacing %.1f"
        % (
            2 * g.x_out,
            fem[:, 1].max() - fem[:, 1].min(),
            fem[:, 1].min(),
            fem[:, 1].max(),
            fem[:, 2].max() - fem[:, 2].min(),
            fem[:, 2].min(),
            fem[:, 2].max(),
            2 * g.w_condyle,
            2 * g.x_in,
            2 * g.x_c,
        ),
        "  femoral shell thickness: %.2f at the condyle apex, %.2f at the condyle edges and on the bridge"
        % (g.t_fem, g.t_fem - g.delta_edge),
        "  J-curve: flange top (y, z) = (%.2f, %.2f); anterior arc R_a centre (%.2f, %.2f); "
        "distal arc R_d centre (%.2f, %.2f); posterior arc R_p centre (%.2f, %.2f)"
        % (g.F_top[0], g.F_top[1], g.C_a[0], g.C_a[1], g.C_d[0], g.C_d[1], g.C_p[0], g.C_p[1]),
        "  candidate flexion axes (parallel to x): through (0, %.3f, %.3f) (distal-arc centre) or "
        "(0, %.3f, %.3f) (posterior-arc centre)" % (g.C_d[0], g.C_d[1], g.C_p[0], g.C_p[1]),
        "  initial position (0 deg flexion): lowest condyle points (+-%.1f, %.1f, %.4f), "
        "i.e. gap %.4g mm above the dish bottoms" % (g.x_c, g.y_dish, g.t_min + g.gap, g.gap),
        "  CAD volumes (OpenCASCADE): femur %.3f mm^3, insert %.3f mm^3 (insert mass %.1f g at 0.935 mg/mm^3)"
        % (vols["femur"], vols["tibia"], vols["tibia"] * 0.935e-3),
        "",
        "exact-geometry contact check (femur rotated about the distal-arc centre, then lowered to touch):",
    ]
    L += ["  " + s for s in clearance_report(variant)]
    if meshes:
        import blockmesh

        L += ["", "discrete initial gap (vertical distance between the meshed articular surfaces):"]
        for name, b in meshes:
            fn, _, fs = b["femur"]
            tn, _, ts = b["tibia"]
            g1 = blockmesh.vertical_gap(tn[np.unique(ts["tibia_contact"])], fn, fs["femur_contact"])
            g2 = -blockmesh.vertical_gap(fn[np.unique(fs["femur_contact"])], tn, ts["tibia_contact"])
            L.append(
                "  %-20s min over tibia_contact nodes %+.4f, over femur_contact nodes %+.4f "
                "(negative = femur node below the faceted insert surface)"
                % (name, np.nanmin(g1), np.nanmin(g2))
            )
    return "\n".join(L) + "\n"
