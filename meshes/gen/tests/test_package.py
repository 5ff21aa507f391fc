# SPDX-License-Identifier: LGPL-2.1-or-later
"""meshes/gen is one package: every module imports as gen.NAME (which
also checks that none fails to import)."""
import importlib
import os

import pytest

HERE = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
MODULES = sorted(f[:-3] for f in os.listdir(HERE) if f.endswith(".py") and f != "__init__.py")


def test_package_lists_its_modules():
    import gen

    for name in MODULES:
        assert name in gen.__doc__


@pytest.mark.parametrize("name", MODULES)
def test_module_imports_from_package(name):
    module = importlib.import_module("gen." + name)
    assert os.path.dirname(module.__file__) == HERE
