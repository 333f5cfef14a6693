"""Run one rclpy script twice: under the real ROS 2 Jazzy rclpy and under posekit.rclpy.

:func:`run_both` executes ``source`` (written against the real API: ``import rclpy``,
``from rclpy.node import Node``, ``from std_msgs.msg import String``...) in the reference
venv (:mod:`_support.ros2`) and in this interpreter with a prelude that makes those imports
resolve to posekit (``rclpy`` -> ``posekit.rclpy``, ``<pkg>.msg`` / ``<pkg>.srv`` /
``<pkg>.action`` -> ``posekit.msgs.<pkg>``). Tests compare what the two print.
"""

from __future__ import annotations

import os
import subprocess
import sys
import textwrap

from _support.ros2 import run_ros2_script

PRELUDE = """\
import importlib, pkgutil, sys, types
import posekit.rclpy as _rclpy
import posekit.msgs as _msgs
sys.modules["rclpy"] = _rclpy
for _info in pkgutil.iter_modules(_rclpy.__path__):
    sys.modules["rclpy." + _info.name] = importlib.import_module("posekit.rclpy." + _info.name)
for _info in pkgutil.iter_modules(_msgs.__path__):
    if _info.name.startswith("_") or _info.name in ("cdr", "errors", "registry", "image",
                                                     "introspection"):
        continue
    _mod = importlib.import_module("posekit.msgs." + _info.name)
    _pkg = types.ModuleType(_info.name)
    sys.modules[_info.name] = _pkg
    for _kind in ("msg", "srv", "action"):
        setattr(_pkg, _kind, _mod)
        sys.modules[_info.name + "." + _kind] = _mod
"""


def run_posekit_script(source: str, timeout: float = 60.0) -> subprocess.CompletedProcess[str]:
    """Run ``source`` under posekit.rclpy (in-process transport) to completion."""
    env = {k: v for k, v in os.environ.items()
           if not k.startswith(("ROS_", "RMW_", "POSEKIT_", "ZENOH_"))}
    env["PYTHONUNBUFFERED"] = "1"
    # compiled as "<string>", as ``python -c`` names it: same file name and line numbers
    code = PRELUDE + f"exec(compile({textwrap.dedent(source)!r}, '<string>', 'exec'))\n"
    return subprocess.run(
        [sys.executable, "-c", code], env=env, capture_output=True, text=True,
        timeout=timeout, stdin=subprocess.DEVNULL,
    )


def run_both(source: str, domain_id: int, timeout: float = 60.0) -> tuple[str, str]:
    """stdout of ``source`` under the real rclpy and under posekit (each must exit 0)."""
    ref = run_ros2_script(source, domain_id=domain_id, timeout=timeout)
    assert ref.returncode == 0, f"reference rclpy failed:\n{ref.stderr[-3000:]}"
    ours = run_posekit_script(source, timeout=timeout)
    assert ours.returncode == 0, f"posekit failed:\n{ours.stderr[-3000:]}"
    return ref.stdout, ours.stdout
