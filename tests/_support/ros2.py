"""The reference peer: a real ROS 2 Jazzy rclpy (Fast DDS) in its own virtual environment.

``make ros2-ref`` (a prerequisite of ``make test``) creates ``.venv-ros2`` from PyPI's
``ros-jazzy-*`` wheels. :func:`ros2_python` returns its interpreter and builds the venv itself
when a test runs outside ``make`` (so a plain ``pytest`` needs nothing by hand either).
Scripts run there see only real ROS 2 packages; posekit is not importable in that venv.

:func:`ros2_env` gives the environment every reference process uses: loopback-only discovery
(``ROS_AUTOMATIC_DISCOVERY_RANGE=LOCALHOST``), Fast DDS, and a domain id of the caller's
choice so concurrent tests never meet.
"""

from __future__ import annotations

import os
import subprocess
import sys
import textwrap
from pathlib import Path

REPO = Path(__file__).resolve().parents[2]
ROS2_VENV = Path(os.environ.get("POSEKIT_ROS2_VENV", str(REPO / ".venv-ros2")))


def ros2_python() -> Path:
    """The reference venv's python, created with ``make ros2-ref`` if it is missing."""
    python = ROS2_VENV / "bin" / "python"
    if not (ROS2_VENV / ".ros2-installed").exists():
        subprocess.run(
            ["make", "-C", str(REPO), "ros2-ref", f"ROS2_VENV={ROS2_VENV}",
             f"PYTHON={sys.executable}"],
            check=True, timeout=900,
        )
    return python


def ros2_env(domain_id: int, **extra: str) -> dict[str, str]:
    """Environment for a reference ROS 2 process on ``domain_id``, discovery on loopback."""
    env = {k: v for k, v in os.environ.items()
           if not k.startswith(("ROS_", "RMW_", "POSEKIT_", "ZENOH_", "PYTHON"))}
    env.update(
        ROS_DOMAIN_ID=str(domain_id),
        ROS_AUTOMATIC_DISCOVERY_RANGE="LOCALHOST",
        RMW_IMPLEMENTATION="rmw_fastrtps_cpp",
        PYTHONUNBUFFERED="1",
    )
    env.update(extra)
    return env


def run_ros2_script(source: str, domain_id: int, timeout: float = 60.0,
                    **extra_env: str) -> subprocess.CompletedProcess[str]:
    """Run ``source`` under the real rclpy to completion; stdout/stderr captured as text."""
    return subprocess.run(
        [str(ros2_python()), "-c", textwrap.dedent(source)],
        env=ros2_env(domain_id, **extra_env), capture_output=True, text=True,
        timeout=timeout, stdin=subprocess.DEVNULL,
    )


#: Source for reference scripts: ``msg_class("pkg/msg/Type")``, ``make(cls, values)`` (a
#: message from nested dicts/lists, as rosidl's set_message_fields) and ``to_plain(msg)``
#: (nested dicts, lists and scalars, every field), written against the real rclpy only.
ROS_MSG_HELPERS = '''
import importlib

def msg_class(ros_type):
    pkg, kind, name = ros_type.split("/")
    return getattr(importlib.import_module(f"{pkg}.{kind}"), name)

def fill(msg, values):
    for key, value in values.items():
        if isinstance(value, dict):
            fill(getattr(msg, key), value)
        else:
            setattr(msg, key, value)
    return msg

def make(cls, values):
    return fill(cls(), values)

def to_plain(value):
    if hasattr(value, "get_fields_and_field_types"):
        return {k: to_plain(getattr(value, k)) for k in value.get_fields_and_field_types()}
    if isinstance(value, (bytes, bytearray)):
        return list(value)
    if hasattr(value, "tolist"):
        return value.tolist()
    if isinstance(value, (list, tuple)):
        return [to_plain(v) for v in value]
    return value
'''
