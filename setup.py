"""The build behind pyproject.toml: CMake builds the `stepstone_python` target and the
module it makes is installed as the extension `stepstone`.

STEPSTONE_BUILD_DIR names a CMake build tree to use (configured if empty, else only
built); without it a Release tree is made under setuptools' temporary folder, without
tests or benchmarks. Everything the build needs comes from scripts/setup-deps."""
import os
import pathlib
import shutil
import subprocess
import sys

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

HERE = pathlib.Path(__file__).resolve().parent


class CMakeExtension(Extension):
    def __init__(self, name):
        super().__init__(name, sources=[])


class CMakeBuild(build_ext):
    def build_extension(self, ext):
        build = pathlib.Path(os.environ.get("STEPSTONE_BUILD_DIR") or pathlib.Path(self.build_temp) / "cmake")
        if not (build / "CMakeCache.txt").exists():
            subprocess.check_call([
                "cmake", "-S", str(HERE), "-B", str(build), "-G", "Ninja", "-DCMAKE_BUILD_TYPE=Release",
                "-DSTEPSTONE_BUILD_TESTS=OFF", "-DSTEPSTONE_BENCH=OFF", "-DSTEPSTONE_MPI=OFF",
                f"-DPython3_EXECUTABLE={sys.executable}"])
        subprocess.check_call(["cmake", "--build", str(build), "--target", "stepstone_python",
                               "-j", str(os.cpu_count() or 2)])
        built = sorted((build / "python").glob("stepstone*.so"))
        if not built:
            raise RuntimeError(f"{build}/python holds no stepstone module after the build")
        target = pathlib.Path(self.get_ext_fullpath(ext.name))
        target.parent.mkdir(parents=True, exist_ok=True)
        shutil.copyfile(built[0], target)


setup(ext_modules=[CMakeExtension("stepstone")], cmdclass={"build_ext": CMakeBuild})
