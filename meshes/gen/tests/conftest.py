# SPDX-License-Identifier: LGPL-2.1-or-later
"""Unit tests of the mesh generators (meshes/gen): python3 -m pytest
meshes/gen/tests (ctest: python/unit).  The modules are imported as the
scripts import them, by their plain names: importing the package `gen`
(meshes/ on the path) puts meshes/gen on sys.path."""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__)))))
import gen  # noqa: E402,F401
