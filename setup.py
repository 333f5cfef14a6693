"""Build step for posekit's one optional compiled module, ``posekit.tf2._accel``.

Everything else (metadata, dependencies, package data) is in pyproject.toml. The extension is
``optional``: where no C compiler or Python headers exist, the build skips it and the package
installs pure Python, whose results are bit-identical (posekit.tf2.path selects at import).
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
        )
    ]
)
