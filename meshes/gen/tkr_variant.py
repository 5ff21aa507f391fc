#!/usr/bin/env python3
# SPDX-License-Identifier: LGPL-2.1-or-later
"""One design variant of the parametric TKR (meshes/gen/tkr.py), e.g. for a
study that varies the insert's conformity (doc/studies.md, "Design
variants").

usage: tkr_variant.py --variant a|b [--resolution coarse|medium|fine]
                      [--set NAME=VALUE ...] (--print | -o OUT.msh [--prm OUT.prm])

  --variant      the design the variant starts from (VARIANTS of tkr.py)
  --resolution   the mesh resolution (default coarse)
  --set N=V      change parameter N (a key of VARIANTS, e.g. R_ts, the
                 insert's sagittal radius, R_tf its frontal radius, mm)
  --print        print the parameters (after --set) as N=V lines, and exit
  -o OUT.msh     write the hexahedral mesh, checked by check_msh.py (groups,
                 no inverted or degenerate cell)
  --prm OUT.prm  also write a parameter-file fragment: Mesh/File = OUT.msh
                 and Gait/Flexion axis point = the centre of the femur's
                 distal arc (as for the bundled meshes)

Any error is one line on stderr and exit code 1.
"""
import argparse
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)


def reexec_with_system_python(error):
    """numpy or gmsh missing under this python3 (a pyenv or venv first in
    PATH): run again under Debian's /usr/bin/python3."""
    system = "/usr/bin/python3"
    if (
        os.access(system, os.X_OK)
        and not os.environ.get("TKR_GEN_REEXEC")
        and os.path.realpath(sys.executable) != os.path.realpath(system)
    ):
        os.environ["TKR_GEN_REEXEC"] = "1"
        os.execv(system, [system, os.path.abspath(__file__)] + sys.argv[1:])
    fail("needs python3-numpy (%s)" % error)


def fail(message):
    sys.stderr.write("tkr_variant: error: %s\n" % message)
    sys.exit(1)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--variant", required=True)
    ap.add_argument("--resolution", default="coarse")
    ap.add_argument("--set", action="append", default=[], metavar="NAME=VALUE")
    ap.add_argument("--print", action="store_true")
    ap.add_argument("-o", "--output")
    ap.add_argument("--prm")
    args = ap.parse_args()
    try:
        import numpy  # noqa: F401
        import tkr
        import check_msh
        from blockmesh import write_msh
    except ImportError as e:
        reexec_with_system_python(e)

    if args.variant not in tkr.VARIANTS:
        fail("unknown variant <%s> (%s)" % (args.variant, ", ".join(tkr.VARIANTS)))
    if args.resolution not in tkr.RESOLUTIONS:
        fail("unknown resolution <%s> (%s)" % (args.resolution, ", ".join(tkr.RESOLUTIONS)))
    params = dict(tkr.VARIANTS[args.variant])
    for item in args.set:
        name, _, value = item.partition("=")
        name = name.strip()
        if name not in params:
            fail("--set %s: no parameter <%s> (%s)" % (item, name, ", ".join(sorted(params))))
        try:
            params[name] = float(value)
        except ValueError:
            fail("--set %s: <%s> is not a number" % (item, value))
    if args.print:
        for name in sorted(params):
            print("%s=%.12g" % (name, params[name]))
        return
    if not args.output:
        fail("give -o OUT.msh or --print")

    try:
        g = tkr.Geometry(args.variant, params)
        r = tkr.resolution(args.variant, args.resolution)
        bodies = {"femur": tkr.femur_body(g, r).assemble(), "tibia": tkr.tibia_body(g, r).assemble()}
        write_msh(args.output, bodies, "tkr-%s-variant" % args.variant)
        result = check_msh.check(args.output, quiet=True)
    except Exception as e:  # the geometry cannot be built or meshed
        fail("the variant cannot be meshed: %s" % e)
    if result["errors"]:
        fail("the mesh of the variant is not valid: %s" % "; ".join(result["errors"]))
    if args.prm:
        with open(args.prm, "w") as f:
            f.write(
                "# tkr_variant.py --variant %s --resolution %s %s\n"
                % (args.variant, args.resolution, " ".join("--set " + s for s in args.set))
            )
            f.write("subsection Mesh\n  set File = %s\nend\n" % os.path.abspath(args.output))
            f.write(
                "subsection Gait\n  set Flexion axis point = 0, %.12g, %.12g\nend\n" % (g.C_d[0], g.C_d[1])
            )
    print(
        "tkr_variant: %s: %d hexahedra, smallest corner quality %.3f"
        % (args.output, result["hexahedra"], result["min_corner_quality"])
    )


if __name__ == "__main__":
    main()
