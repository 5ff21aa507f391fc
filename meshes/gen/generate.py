#!/usr/bin/env python3
"""Generate the project's meshes, check them and write meshes/volumes.csv.

Usage (normally through scripts/generate-meshes):
    generate.py [--skip-fine] [--no-check] [NAME_SUBSTRING ...]

Without names every mesh is generated; with names only the meshes whose file
name contains one of them.  volumes.csv is rewritten for every mesh file that
exists afterwards.  Needs the gmsh Python module (Debian: python3-gmsh) and
numpy (python3-numpy); the patch test meshes use the gmsh command line.
"""
import os
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
MESHES = os.path.dirname(HERE)
sys.path.insert(0, HERE)

import blockmesh  # noqa: E402
import check_msh  # noqa: E402
import unstructured  # noqa: E402
import verification  # noqa: E402

PATCH = dict(L=20.0, H_t=10.0, H_f=6.0)
PATCH_RES = {"coarse": dict(n_t=4, n_f=5, nz_t=3, nz_f=2), "fine": dict(n_t=12, n_f=17, nz_t=6, nz_f=4)}


def make_patch(res, path):
    args = ["gmsh", "-3", "-v", "2", os.path.join(MESHES, "verification", "patch.geo"), "-o", path]
    for k, v in PATCH_RES[res].items():
        args += ["-setnumber", k, str(v)]
    subprocess.run(args, check=True)


def patch_volumes():
    L, H_t, H_f = PATCH["L"], PATCH["H_t"], PATCH["H_f"]
    return {"femur": L * L * H_f, "tibia": L * L * H_t}


def targets():
    """Ordered list of (relative file, maker, cad-volume function, is_fine)."""
    out = []
    for res in ("coarse", "fine"):
        out.append(
            (
                "verification/patch-%s.msh" % res,
                (lambda path, r=res: make_patch(r, path)),
                patch_volumes,
                False,
            )
        )
    for res in ("coarse", "medium", "fine"):
        out.append(
            (
                "verification/sphere-%s.msh" % res,
                (lambda path, r=res: _write(path, verification.make_sphere(r)[0])),
                (lambda r=res: verification.make_sphere_volumes()),
                res == "fine",
            )
        )
    for res in ("coarse", "medium", "fine"):
        out.append(
            (
                "verification/cylinder-%s.msh" % res,
                (lambda path, r=res: _write(path, verification.make_cylinder(r)[0])),
                (lambda r=res: verification.make_cylinder_volumes()),
                res == "fine",
            )
        )
    for name in ("patch", "sphere"):
        out.append(
            (
                "verification/%s-unstructured.msh" % name,
                (lambda path, n=name: unstructured.write(n, path)),
                (lambda n=name: unstructured.volumes(n)),
                False,
            )
        )
    try:
        import tkr
    except ImportError:
        tkr = None
    if tkr is not None:
        for variant in tkr.VARIANTS:
            for res in ("coarse", "medium", "fine"):
                out.append(
                    (
                        "tkr/tkr-%s-%s.msh" % (variant, res),
                        (lambda path, v=variant, r=res: _write_tkr(v, r, path)),
                        (lambda v=variant: tkr.cad_volumes(v)),
                        res == "fine",
                    )
                )
        out.append(
            ("tkr/tkr-a-implant.msh", unstructured.make_implant, (lambda: tkr.cad_volumes("a")), False)
        )
        # variant C (posterior-stabilised, tkr_ps.py): scripts/mesh-implant on
        # its STEP files (a child process: it prints its face tables), which
        # also writes tkr-c-report.txt and tkr-c-coarse.prm
        out.append(("tkr/tkr-c-coarse.msh", make_tkr_c, tkr_c_volumes, False))
    return out


MADE_TKR = {}


def make_tkr_c(path):
    assert path == os.path.join(MESHES, "tkr", "tkr-c-coarse.msh")
    subprocess.run(
        [sys.executable, os.path.join(HERE, "tkr_ps.py"), "mesh"], check=True, stdout=subprocess.DEVNULL
    )


def tkr_c_volumes():
    import tkr_ps

    return tkr_ps.cad_volumes(tkr_ps.Geometry())


def _write_tkr(variant, res, path):
    import tkr

    bodies = tkr.make_mesh(variant, res)
    blockmesh.write_msh(path, bodies, "tkr-%s-%s" % (variant, res))
    MADE_TKR.setdefault(variant, []).append(("tkr-%s-%s" % (variant, res), bodies))


def export_cad():
    """STEP/STL of variants A and B (tkr.export_cad) and of the
    posterior-stabilised C (tkr_ps.export_cad, STL faceted by a chordal
    tolerance): the test inputs of scripts/mesh-implant.  In child processes
    because OpenCASCADE prints its STEP statistics on stdout."""
    out = os.path.join(MESHES, "tkr", "cad")
    codes = [
        "import sys; sys.path.insert(0, %r); import tkr; "
        "print('\\n'.join(tkr.export_cad(%r, %r)))" % (HERE, v, out)
        for v in ("a", "b")
    ]
    codes.append(
        "import sys; sys.path.insert(0, %r); import tkr_ps; "
        "print('\\n'.join('%%s %%s' %% fd for fd in tkr_ps.export_cad(%r)))" % (HERE, out)
    )
    os.makedirs(out, exist_ok=True)
    for code in codes:
        r = subprocess.run([sys.executable, "-c", code], check=True, capture_output=True, text=True)
        for line in r.stdout.splitlines():
            if line.startswith("/"):
                f, dev = (line.split(" ") + ["None"])[:2]
                print(
                    "made  %s (%.2f MB)%s"
                    % (
                        os.path.relpath(f, MESHES),
                        os.path.getsize(f) / 1e6,
                        "" if dev == "None" else ", STL chordal deviation %.3f mm" % float(dev),
                    )
                )


def _write(path, bodies):
    blockmesh.write_msh(path, bodies)


def main(argv):
    skip_fine = "--skip-fine" in argv
    no_check = "--no-check" in argv
    names = [a for a in argv if not a.startswith("--")]
    t_all = time.time()
    tg = targets()
    for rel, make, _, fine in tg:
        if names and not any(n in rel for n in names):
            continue
        if fine and skip_fine:
            print("skip  %s (--skip-fine)" % rel)
            continue
        path = os.path.join(MESHES, rel)
        os.makedirs(os.path.dirname(path), exist_ok=True)
        t = time.time()
        make(path)
        print("made  %s in %.1f s (%.1f MB)" % (rel, time.time() - t, os.path.getsize(path) / 1e6))
        sys.stdout.flush()
    if not names or "cad" in names:
        export_cad()
    for variant, made in MADE_TKR.items():
        import tkr

        # the report covers every existing mesh of the variant (the meshes are
        # deterministic, so the ones not regenerated now are rebuilt in memory)
        have = dict(made)
        made = []
        for res in ("coarse", "medium", "fine"):
            name = "tkr-%s-%s" % (variant, res)
            if name in have:
                made.append((name, have[name]))
            elif os.path.exists(os.path.join(MESHES, "tkr", name + ".msh")):
                made.append((name, tkr.make_mesh(variant, res)))
        path = os.path.join(MESHES, "tkr", "tkr-%s-report.txt" % variant)
        with open(path, "w") as f:
            f.write(tkr.geometry_report(variant, made))
        print("wrote %s" % os.path.relpath(path, MESHES))
    if no_check:
        return 0
    rows, ok = [], True
    for rel, _, volfun, _ in tg:
        path = os.path.join(MESHES, rel)
        if not os.path.exists(path):
            continue
        r = check_msh.check(path)
        vols = volfun()
        status = "ok  " if not r["errors"] else "FAIL"
        nv = r["femur_vertices"] + r["tibia_vertices"]
        dev = [100 * (r[b + "_volume"] / vols[b] - 1) for b in ("femur", "tibia")]
        print(
            "%s %-32s hex %7d  vertices femur %6d tibia %6d  Q1 DoFs %7d  "
            "volume error femur %+.2f%% tibia %+.2f%%  min corner J %.2f"
            % (
                status,
                rel,
                r["hexahedra"],
                r["femur_vertices"],
                r["tibia_vertices"],
                3 * nv,
                dev[0],
                dev[1],
                r["min_corner_quality"],
            )
        )
        for e in r["errors"]:
            print("      error: " + e)
        ok = ok and not r["errors"]
        rows.append(
            "%s,%.6f,%.6f,%d,%d,%d"
            % (rel, vols["femur"], vols["tibia"], r["femur_vertices"], r["tibia_vertices"], r["hexahedra"])
        )
    with open(os.path.join(MESHES, "volumes.csv"), "w") as f:
        f.write("file,femur_volume_mm3,tibia_volume_mm3,femur_vertices,tibia_vertices,hexahedra\n")
        f.write("\n".join(rows) + "\n")
    print("wrote meshes/volumes.csv (%d meshes); total %.1f s" % (len(rows), time.time() - t_all))
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
