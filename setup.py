"""pip's way in (pyproject.toml): the package sodaevo from python/sodaevo, its
extension and the `sodaevo` command built by the project's CMake, never by
setuptools' compiler, so a pip install runs the very build `cmake` runs
(flags, -ffp-contract=off, the same bits). The CMake build folder is
build-pip-<python ABI>/ in the clone, beside build/ at the same depth, so that
ccache (base_dir: paths relative to the build folder) reuses a developer build's
objects."""
from __future__ import annotations

import os
import re
import shutil
import subprocess
import sys
import sysconfig
from pathlib import Path

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

ROOT = Path(__file__).resolve().parent


def project_version() -> str:
    """The version in CMakeLists.txt's project() line: one version for both."""
    text = (ROOT / "CMakeLists.txt").read_text(encoding="utf-8")
    found = re.search(r"project\(sodaevo\s+VERSION\s+([0-9][0-9.]*)", text)
    if not found:
        raise RuntimeError("CMakeLists.txt: no `project(sodaevo VERSION x.y.z` line")
    return found.group(1)


class CMakeBuild(build_ext):
    """Configures and builds sodaevo_python and sodaevo with CMake, then copies the
    extension and the command into the package."""

    def build_extension(self, ext: Extension) -> None:
        tag = sysconfig.get_config_var("SOABI") or f"py{sys.version_info[0]}{sys.version_info[1]}"
        build_dir = ROOT / f"build-pip-{tag}"
        configure = ["cmake", "-S", str(ROOT), "-B", str(build_dir), "-DCMAKE_BUILD_TYPE=Release",
                     f"-DPython_EXECUTABLE={sys.executable}", "-DSODAEVO_BUILD_TESTS=OFF", "-DSODAEVO_PYTHON=ON"]
        if shutil.which("ninja"):
            configure += ["-G", "Ninja"]
        try:  # pybind11 from the package index (plain `pip install .`); Debian's is found by CMake itself
            import pybind11
            configure.append(f"-Dpybind11_DIR={pybind11.get_cmake_dir()}")
        except ImportError:
            pass
        configure += os.environ.get("SODAEVO_CMAKE_ARGS", "").split()
        jobs = os.environ.get("CMAKE_BUILD_PARALLEL_LEVEL", str(os.cpu_count() or 1))
        self.announce(" ".join(configure), level=2)
        subprocess.run(configure, check=True)
        subprocess.run(["cmake", "--build", str(build_dir), "--target", "sodaevo_python", "sodaevo", "-j", jobs],
                       check=True)
        built = sorted((build_dir / "python" / "sodaevo").glob("_sodaevo*.so"))
        if not built:
            raise RuntimeError("CMake built no Python module: it needs python3-dev, pybind11 and numpy "
                               f"(see {build_dir}/CMakeCache.txt and docs/python.md)")
        target = Path(self.get_ext_fullpath(ext.name))
        target.parent.mkdir(parents=True, exist_ok=True)
        shutil.copy2(built[0], target)
        command = target.parent / "bin" / "sodaevo"
        command.parent.mkdir(exist_ok=True)
        shutil.copy2(build_dir / "sodaevo", command)


setup(
    version=project_version(),
    packages=["sodaevo"],
    package_dir={"sodaevo": "python/sodaevo"},
    package_data={"sodaevo": ["py.typed", "*.pyi", "bin/sodaevo"]},
    ext_modules=[Extension("sodaevo._sodaevo", sources=[])],
    cmdclass={"build_ext": CMakeBuild},
    zip_safe=False,
)
