"""`pip install .`: the pbf Python module, built by the project's CMake.

Debian 12 has no scikit-build-core, so this is setuptools (python3-setuptools)
with a build_ext that configures CMake (tests, benchmarks and viewer off),
builds the _pbf target and puts the extension beside the pure-Python package
python/pbf. Offline, with Debian's packages only (pip's isolated build would
download setuptools; Debian's pip refuses to install outside a venv):

    python3 -m venv --system-site-packages .venv
    .venv/bin/pip install --no-build-isolation .

Environment: CMAKE_BUILD_PARALLEL_LEVEL (compile jobs, default: all cores),
CMAKE_ARGS (extra configure arguments, e.g. "-DPBF_NATIVE=OFF" for a module
that runs on other x86-64 machines; the default is -march=native).
"""

import os
import pathlib
import re
import shlex
import shutil
import subprocess
import sys

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

ROOT = pathlib.Path(__file__).resolve().parent


def project_version():
    text = (ROOT / "CMakeLists.txt").read_text()
    return re.search(r"project\(pbf VERSION ([0-9.]+)", text).group(1)


class CMakeExtension(Extension):
    """An extension CMake builds (no sources for setuptools to compile)."""

    def __init__(self, name, target):
        super().__init__(name, sources=[])
        self.target = target


class CMakeBuild(build_ext):
    def build_extension(self, ext):
        build = pathlib.Path(self.build_temp).resolve() / "cmake"
        build.mkdir(parents=True, exist_ok=True)
        generator = ["-G", "Ninja"] if shutil.which("ninja") else []
        configure = [
            "cmake", "-S", str(ROOT), "-B", str(build), *generator,
            "-DCMAKE_BUILD_TYPE=Release",
            "-DPBF_BUILD_TESTS=OFF", "-DPBF_BUILD_BENCH=OFF", "-DPBF_BUILD_VIEWER=OFF",
            "-DPBF_BUILD_PYTHON=ON",
            # The interpreter pip runs (a venv's python finds the system's
            # headers and numpy through --system-site-packages).
            f"-DPython3_EXECUTABLE={sys.executable}",
            *shlex.split(os.environ.get("CMAKE_ARGS", "")),
        ]
        subprocess.run(configure, check=True)
        jobs = os.environ.get("CMAKE_BUILD_PARALLEL_LEVEL") or str(os.cpu_count() or 1)
        subprocess.run(["cmake", "--build", str(build), "--target", ext.target, "-j", jobs],
                       check=True)
        built = sorted((build / "python" / "pbf").glob("_pbf*.so"))
        if not built:
            raise RuntimeError(f"CMake built no _pbf module in {build / 'python' / 'pbf'}")
        destination = pathlib.Path(self.get_ext_fullpath(ext.name))
        destination.parent.mkdir(parents=True, exist_ok=True)
        shutil.copyfile(built[0], destination)


setup(
    version=project_version(),
    packages=["pbf"],
    package_dir={"": "python"},
    ext_modules=[CMakeExtension("pbf._pbf", target="_pbf")],
    cmdclass={"build_ext": CMakeBuild},
    zip_safe=False,
)
