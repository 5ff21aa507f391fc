# SPDX-License-Identifier: LGPL-2.1-or-later
"""tkr-wear's mesh generators and mesh tools (doc/geometry.md).

Every module is also a script run by its path (`python3
meshes/gen/rounded.py ...`, scripts/mesh-implant, scripts/generate-meshes,
the tests in tests/scripts/) or with this directory on sys.path, so the
modules import one another by their plain names (`import blockmesh`).
Importing the package puts this directory on sys.path, so that those
imports also resolve for `import gen.surface_tags` (with meshes/ on the
path).  The unit tests are in tests/ (README.md, "Python").

Modules: blockmesh, cadlike, check_msh, contact_layer, femur_shell,
flexion_axis, generate, gmsh_hexes, images, insert_sweep, mesh_implant,
rounded, scanlike, surface_tags, tkr, tkr_ps, tkr_variant, unstructured,
verification.
"""
import os
import sys

_HERE = os.path.dirname(os.path.abspath(__file__))
if _HERE not in sys.path:
    sys.path.insert(0, _HERE)
