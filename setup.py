"""Build step for posekit's optional compiled modules, ``posekit.tf2._accel`` (the lookup
engine's kernels) and ``posekit.geometry._accel`` (batch quaternion -> matrix).

Everything else (metadata, dependencies, package data) is in pyproject.toml. The extensions
are ``optional``: where no C compiler or Python headers exist, the build skips them and the
package installs pure Python, whose results are bit-identical (each package selects at
import; ``POSEKIT_PURE_PYTHON=1`` forces pure Python).
Floating-point contraction is turned off so the compiler cannot fuse a multiply and an add
into one rounding that Python's arithmetic does not make.
"""

import sys

from setuptools import Extension, setup

_FLAGS = [] if sys.platform == "win32" else ["-O2", "-ffp-contract=off", "-fno-fast-math"]

setup(
    ext_modules=[
        Extension(
            "posekit.tf2._accel",
            sources=["src/posekit/tf2/_accel.c"],
            extra_compile_args=_FLAGS,
            optional=True,
        ),
        Extension(
            "posekit.geometry._accel",
            sources=["src/posekit/geometry/_accel.c"],
            extra_compile_args=_FLAGS,
            optional=True,
        ),
    ]
)
