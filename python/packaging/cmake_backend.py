"""The build backend of pyproject.toml: setuptools' own, which runs setup.py (and
so the project's CMake), plus the build tools it needs asked for only when the
system lacks them. On Debian with cmake and pybind11-dev nothing more is needed,
so `pip install --no-build-isolation .` and `python3 -m build --no-isolation`
work offline; with the package index, cmake and pybind11 come from it."""
from __future__ import annotations

import shutil
import subprocess

from setuptools import build_meta as _setuptools
from setuptools.build_meta import *  # noqa: F401,F403  (the hooks this backend does not change)

_PYBIND11_CONFIGS = ("/usr/lib/cmake/pybind11/pybind11Config.cmake",
                     "/usr/share/cmake/pybind11/pybind11Config.cmake",
                     "/usr/local/lib/cmake/pybind11/pybind11Config.cmake",
                     "/usr/local/share/cmake/pybind11/pybind11Config.cmake")


def _cmake_new_enough() -> bool:
    cmake = shutil.which("cmake")
    if cmake is None:
        return False
    try:
        first = subprocess.run([cmake, "--version"], capture_output=True, text=True, check=True).stdout.split()
        major, minor = (int(p) for p in first[2].split(".")[:2])
    except (OSError, subprocess.CalledProcessError, IndexError, ValueError):
        return False
    return (major, minor) >= (3, 22)


def _has_pybind11() -> bool:
    import os
    if any(os.path.exists(p) for p in _PYBIND11_CONFIGS):
        return True
    try:
        import pybind11  # noqa: F401
        return True
    except ImportError:
        return False


def _missing_tools() -> list:
    wanted = []
    if not _cmake_new_enough():
        wanted.append("cmake>=3.22")
    if not _has_pybind11():
        wanted.append("pybind11>=2.6")
    try:
        import numpy  # noqa: F401
    except ImportError:
        wanted.append("numpy")
    return wanted


def get_requires_for_build_wheel(config_settings=None):
    return _setuptools.get_requires_for_build_wheel(config_settings) + _missing_tools()


def get_requires_for_build_editable(config_settings=None):
    return _setuptools.get_requires_for_build_editable(config_settings) + _missing_tools()
