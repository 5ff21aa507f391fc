#!/usr/bin/env python3
"""PNG images of a TKR mesh (gmsh OpenGL rendering; run under xvfb-run when
there is no display).  One mesh per process (gmsh 4.8 crashes when its
graphics are initialised twice).

Usage: images.py OUTDIR MESH.msh [VIEW ...]   (views: iso side tibia femur)"""
import os
import sys

import gmsh

VIEWS = {
    # name: (rotation x, y, z in degrees, what to show)
    "iso": ((-65.0, 0.0, -145.0), ("femur", "tibia")),
    "side": ((-90.0, 0.0, -90.0), ("femur", "tibia")),
    "tibia": ((-40.0, 0.0, -160.0), ("tibia",)),
    "femur": ((-130.0, 0.0, -150.0), ("femur",)),
}


def render(msh, outdir, views=VIEWS):
    base = os.path.splitext(os.path.basename(msh))[0]
    out = []
    gmsh.initialize(["gmsh", "-v", "0"])
    try:
        gmsh.open(msh)
        phys = {gmsh.model.getPhysicalName(d, t): (d, t) for d, t in gmsh.model.getPhysicalGroups()}
        ents = {
            name: [(d, e) for e in gmsh.model.getEntitiesForPhysicalGroup(d, t)]
            for name, (d, t) in phys.items()
        }
        gmsh.fltk.initialize()
        opts = {
            "General.GraphicsWidth": 1000,
            "General.GraphicsHeight": 750,
            "General.Trackball": 0,
            "General.SmallAxes": 1,
            "General.Axes": 0,
            "Mesh.SurfaceEdges": 0,
            "Mesh.SurfaceFaces": 0,
            "Mesh.VolumeEdges": 1,
            "Mesh.VolumeFaces": 1,
            "Mesh.Light": 1,
            "Mesh.ColorCarousel": 2,
            "General.Orthographic": 1,
        }
        for k, v in opts.items():
            gmsh.option.setNumber(k, v)
        gmsh.option.setColor("General.Background", 255, 255, 255)
        gmsh.option.setColor("General.Foreground", 0, 0, 0)
        gmsh.option.setColor("General.Text", 0, 0, 0)
        for vname, ((rx, ry, rz), show) in views.items():
            gmsh.model.setVisibility(gmsh.model.getEntities(), 0, recursive=False)
            for body in show:
                gmsh.model.setVisibility(ents[body], 1, recursive=False)
            gmsh.option.setNumber("General.RotationX", rx)
            gmsh.option.setNumber("General.RotationY", ry)
            gmsh.option.setNumber("General.RotationZ", rz)
            gmsh.option.setNumber("General.ScaleX", 1.0)
            gmsh.option.setNumber("General.ScaleY", 1.0)
            gmsh.option.setNumber("General.ScaleZ", 1.0)
            gmsh.option.setNumber("General.TranslationX", 0.0)
            gmsh.option.setNumber("General.TranslationY", 0.0)
            gmsh.graphics.draw()
            path = os.path.join(outdir, "%s-%s.png" % (base, vname))
            gmsh.write(path)
            out.append(path)
    finally:
        gmsh.finalize()
    return out


if __name__ == "__main__":
    outdir, msh = sys.argv[1], sys.argv[2]
    names = sys.argv[3:] or list(VIEWS)
    for p in render(msh, outdir, {k: VIEWS[k] for k in names}):
        print("wrote", p)
