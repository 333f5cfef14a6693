"""Wheel encoders: exact by default, optional quantisation to ~1633 counts per revolution."""

from __future__ import annotations

import math

import numpy as np
import pytest

from posekit.robot.encoders import WheelEncoders
from posekit.robot.params import WHEEL_JOINT_NAMES, EncoderParams


def test_exact_by_default() -> None:
    enc = WheelEncoders()
    assert enc.read((0.1234567, -2.0, 3.0, 4.0)) == (0.1234567, -2.0, 3.0, 4.0)


def test_quantised_to_counts() -> None:
    params = EncoderParams(quantize=True)
    assert params.counts_per_revolution == pytest.approx(1632.672)
    enc = WheelEncoders(params)
    step = 2 * math.pi / params.counts_per_revolution
    angles = np.linspace(-20.0, 20.0, 1001)
    read = np.array([enc.read_angle(float(a)) for a in angles])
    counts = read / step
    assert np.allclose(counts, np.round(counts), atol=1e-6)
    assert np.max(np.abs(read - angles)) <= step / 2 + 1e-12
    # One full revolution reads back as exactly one revolution.
    assert enc.read_angle(2 * math.pi) == pytest.approx(2 * math.pi, abs=step / 2)


def test_joint_state_message() -> None:
    msg = WheelEncoders().joint_state((1.0, 2.0, 1.0, 2.0), (0.1, 0.2, 0.1, 0.2), 3.25)
    assert msg.name == list(WHEEL_JOINT_NAMES)
    assert np.array_equal(msg.position, [1.0, 2.0, 1.0, 2.0])
    assert (msg.header.stamp.sec, msg.header.stamp.nanosec) == (3, 250_000_000)
