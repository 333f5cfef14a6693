"""The planar EKF: convergence, wrapping, sequential = batch update, message conventions."""

from __future__ import annotations

import math

import numpy as np
import pytest

from posekit.robot.ekf import VX, VY, VYAW, YAW, Ekf2D, Measurement
from posekit.robot.imu import ImuModel
from posekit.robot.odometry import WheelOdometry


def test_sequential_scalar_update_equals_batch_kalman_update() -> None:
    rng = np.random.default_rng(0)
    ekf = Ekf2D(t0=0.0)
    a = rng.normal(size=(6, 6))
    ekf.covariance = a @ a.T + 0.1 * np.eye(6)
    ekf.state[:] = rng.normal(size=6) * 0.1
    P, s = ekf.covariance.copy(), ekf.state.copy()
    z = np.array([0.3, -0.1, 0.2])
    r = np.array([0.01, 0.02, 0.03])
    ekf.update(Measurement(0.0, (VX, VY, VYAW), tuple(z), tuple(r)))
    # Batch textbook update with H selecting (vx, vy, vyaw).
    H = np.zeros((3, 6))
    H[[0, 1, 2], [VX, VY, VYAW]] = 1.0
    S = H @ P @ H.T + np.diag(r)
    K = P @ H.T @ np.linalg.inv(S)
    s_ref = s + K @ (z - H @ s)
    P_ref = (np.eye(6) - K @ H) @ P
    assert np.allclose(ekf.state, s_ref, atol=1e-12)
    assert np.allclose(ekf.covariance, P_ref, atol=1e-12)


def test_prediction_follows_constant_body_velocity() -> None:
    ekf = Ekf2D(t0=0.0, initial_pose=(1.0, 2.0, math.pi / 2))
    ekf.state[VX] = 0.5
    ekf.predict_to(2.0)
    assert ekf.pose == pytest.approx((1.0, 3.0, math.pi / 2))
    # Covariance grows with the process noise.
    assert ekf.covariance[0, 0] > 1e-9
    assert ekf.covariance[1, 1] > 1e-9


def test_converges_on_consistent_measurements() -> None:
    """Straight drive at 0.3 m/s: odometry vx and IMU yaw make x = 0.3 t."""
    ekf = Ekf2D(t0=0.0)
    for k in range(1, 201):
        t = 0.05 * k
        ekf.add_wheel_twist(t, 0.3, 0.0, 0.0, (3.3e-5, 3.3e-5, 2.8e-3))
        ekf.add_imu(t, 0.0, 0.0, (1.9e-3, 2.0e-3))
        ekf.step(t)
    assert ekf.state[VX] == pytest.approx(0.3, abs=1e-3)
    assert ekf.pose[0] == pytest.approx(0.3 * 10.0, abs=0.02)
    assert ekf.pose[1] == pytest.approx(0.0, abs=1e-6)


def test_yaw_innovation_is_wrapped() -> None:
    ekf = Ekf2D(t0=0.0, initial_pose=(0.0, 0.0, 3.1))
    ekf.add_imu(0.0, 3.1, 0.0, (1.9e-3, 2.0e-3))  # reference reading
    # True heading turns across +pi to -3.1 (i.e. +3.183): the filter must go the short way.
    for k in range(1, 21):
        t = 0.05 * k
        ekf.add_imu(
            t,
            3.1 + 0.0042 * k - 2 * math.pi * (3.1 + 0.0042 * k > math.pi),
            0.084,
            (1.9e-3, 2.0e-3),
        )
        ekf.step(t)
        assert abs(ekf.state[YAW]) > 3.0  # never swings through zero
    assert math.cos(ekf.state[YAW] - (3.1 + 0.084)) == pytest.approx(1.0, abs=1e-3)


def test_relative_imu_yaw() -> None:
    ekf = Ekf2D(t0=0.0)
    ekf.add_imu(0.05, 1.0, 0.0, (1e-4, 1e-4))
    ekf.add_imu(0.10, 1.2, 0.0, (1e-4, 1e-4))
    ekf.step(0.05)
    assert ekf.pose[2] == pytest.approx(0.0, abs=1e-6)
    ekf.step(0.10)
    assert ekf.pose[2] == pytest.approx(0.2, abs=0.02)


def test_queue_processed_in_stamp_order_and_old_measurements_fused() -> None:
    ekf = Ekf2D(t0=0.0)
    ekf.add_wheel_twist(0.10, 1.0, 0.0, 0.0, (1e-6, 1e-6, 1e-6))
    ekf.add_wheel_twist(0.05, 0.0, 0.0, 0.0, (1e-6, 1e-6, 1e-6))
    ekf.step(0.05)  # only the 0.05 measurement is due
    assert ekf.state[VX] == pytest.approx(0.0, abs=1e-6)
    ekf.step(0.10)
    assert ekf.state[VX] == pytest.approx(1.0, abs=1e-3)
    vx1, p1 = ekf.state[VX], ekf.covariance[VX, VX]
    ekf.add_wheel_twist(0.02, 0.5, 0.0, 0.0, (1e-6, 1e-6, 1e-6))  # older than filter time
    ekf.step(0.10)
    # Fused without prediction: a scalar Kalman step from the current prior.
    assert ekf.t == 0.10
    gain = p1 / (p1 + 1e-6)
    assert ekf.state[VX] == pytest.approx(vx1 + gain * (0.5 - vx1), rel=1e-9)


def test_messages_round_trip_into_filter() -> None:
    odom = WheelOdometry()
    odom.update(0.0, 0.0, 0.0)
    odom.update(1.0, 1.0, 0.05)
    imu = ImuModel(seed=0)
    ekf = Ekf2D(t0=0.0)
    ekf.add_odometry_msg(odom.to_msg())
    ekf.add_imu_msg(imu.to_msg(imu.sample(0.05, 0.0, 0.0, 0.0, 0.0)))
    ekf.step(0.05)
    # One scalar Kalman step on vx: prior variance 1e-9 + q_vx * dt, measurement 3.3e-5.
    prior = 1e-9 + 0.025 * 0.05
    assert ekf.state[VX] == pytest.approx(odom.v * prior / (prior + 3.3e-5), rel=1e-9)
    out = ekf.to_msg()
    assert out.header.frame_id == "odom"
    assert out.child_frame_id == "base_link"
    cov = out.pose.covariance.reshape(6, 6)
    assert cov[0, 0] == ekf.covariance[0, 0]
    assert cov[5, 5] == ekf.covariance[2, 2]
    assert cov[0, 5] == ekf.covariance[0, 2]
    tf = ekf.to_transform()
    assert (tf.header.frame_id, tf.child_frame_id) == ("odom", "base_link")
    assert tf.transform.translation.x == out.pose.pose.position.x
    assert (tf.header.stamp.sec, tf.header.stamp.nanosec) == (0, 50_000_000)


def _dense_reference_step(
    s: np.ndarray, P: np.ndarray, t_filter: float, t: float, measurements: list, q: np.ndarray
) -> tuple[np.ndarray, np.ndarray, float]:
    """The module docstring's filter in textbook matrix form (numpy, 6x6 products): fuse
    ``measurements`` in stamp order, each after a prediction to its stamp, then predict to
    ``t``. Returns the new state, covariance and filter time."""

    def predict(s: np.ndarray, P: np.ndarray, dt: float) -> tuple[np.ndarray, np.ndarray]:
        x, y, yaw, vx, vy, vyaw = s
        c, sn = math.cos(yaw), math.sin(yaw)
        s2 = s.copy()
        s2[0] = x + (vx * c - vy * sn) * dt
        s2[1] = y + (vx * sn + vy * c) * dt
        s2[2] = math.remainder(yaw + vyaw * dt, 2 * math.pi)
        F = np.eye(6)
        F[0, 2], F[0, 3], F[0, 4] = (-vx * sn - vy * c) * dt, c * dt, -sn * dt
        F[1, 2], F[1, 3], F[1, 4] = (vx * c - vy * sn) * dt, sn * dt, c * dt
        F[2, 5] = dt
        return s2, F @ P @ F.T + np.diag(q) * dt

    for m in sorted(measurements, key=lambda m: m.t):
        if m.t > t_filter:
            s, P = predict(s, P, m.t - t_filter)
            t_filter = m.t
        for i, z, r in zip(m.indices, m.values, m.variances, strict=True):
            H = np.zeros((1, 6))
            H[0, i] = 1.0
            innovation = z - s[i]
            if i == YAW:
                innovation = math.remainder(innovation, 2 * math.pi)
            K = P @ H.T / (P[i, i] + r)
            s = s + K[:, 0] * innovation
            P = (np.eye(6) - K @ H) @ P
        s[YAW] = math.remainder(s[YAW], 2 * math.pi)
    if t > t_filter:
        s, P = predict(s, P, t - t_filter)
        t_filter = t
    return s, P, t_filter


def test_steps_match_dense_matrix_reference() -> None:
    """Random state/covariance and a 25 Hz IMU + 20 Hz odometry stream over 2 s: the
    Python-float filter equals the matrix-form filter to round-off."""
    rng = np.random.default_rng(3)
    ekf = Ekf2D(t0=0.0)
    a = rng.normal(size=(6, 6)) * 0.1
    ekf.covariance = a @ a.T + 0.01 * np.eye(6)
    ekf.state[:] = [0.2, -0.1, 0.3, 0.4, 0.01, 0.2]
    s_ref, P_ref, t_ref = ekf.state.copy(), ekf.covariance.copy(), 0.0
    q = np.asarray(ekf.params.process_noise_diagonal)
    imu_stamps = [0.04 * n for n in range(1, 51)]
    for k in range(1, 41):
        t = 0.05 * k
        due = [
            Measurement(ti, (YAW, VYAW), (float(rng.normal(0.3, 0.1)), 0.2), (1.9e-3, 2.0e-3))
            for ti in imu_stamps
            if t - 0.05 < ti <= t
        ]
        due.append(
            Measurement(t, (VX, VY, VYAW), (0.4 + float(rng.normal(0, 0.01)), 0.0, 0.2),
                        (3.3e-5, 3.3e-5, 2.8e-3))
        )
        for m in due:
            ekf.enqueue(m)
        ekf.step(t)
        s_ref, P_ref, t_ref = _dense_reference_step(s_ref, P_ref, t_ref, t, due, q)
        assert ekf.t == t_ref
        assert np.allclose(ekf.state, s_ref, rtol=0, atol=1e-12)
        assert np.allclose(ekf.covariance, P_ref, rtol=0, atol=1e-12)
        assert np.array_equal(ekf.covariance, ekf.covariance.T)  # exactly symmetric


def test_covariance_can_be_replaced_or_edited_in_place() -> None:
    ekf = Ekf2D(t0=0.0)
    ekf.covariance[VX, VX] = 1.0  # in-place edit of the array the property returned
    ekf.add_wheel_twist(0.0, 2.0, 0.0, 0.0, (1.0, 1.0, 1.0))
    ekf.step(0.0)
    assert ekf.state[VX] == pytest.approx(1.0)  # gain 1 / (1 + 1)
    asymmetric = np.eye(6)
    asymmetric[0, 1] = 0.2  # [1, 0] stays 0: used as the symmetric part, 0.1
    ekf.covariance = asymmetric
    ekf.predict_to(0.0)  # no time passes: the covariance is only re-read
    ekf.update(Measurement(0.0, (0,), (1.0,), (1.0,)))
    assert ekf.covariance[0, 1] == pytest.approx(0.1 - 1.0 * 0.1 / 2.0)
    with pytest.raises(ValueError, match="6x6"):
        ekf.covariance = np.eye(3)


def test_state_array_is_updated_in_place_and_edits_are_picked_up() -> None:
    ekf = Ekf2D(t0=0.0, initial_pose=(1.0, 2.0, 0.0))
    state = ekf.state
    assert state.tolist() == [1.0, 2.0, 0.0, 0.0, 0.0, 0.0]
    state[VX] = 0.5  # edit in place, then predict 2 s at 0.5 m/s along x
    ekf.predict_to(2.0)
    assert ekf.state is state  # the same array, updated in place
    assert state[0] == pytest.approx(2.0)
    assert ekf.pose == pytest.approx((2.0, 2.0, 0.0))
    with pytest.raises(ValueError, match="6 entries"):
        ekf.state = np.zeros(3)


def test_set_pose_replaces_state_covariance_and_queue() -> None:
    """robot_localization's set_pose: the pose with zero velocities, 1e-6 I with the given
    pose block, queued and older measurements dropped, relative IMU yaw restarted."""
    ekf = Ekf2D(t0=0.0)
    ekf.add_wheel_twist(0.5, 1.0, 0.0, 0.2, (1e-3, 1e-3, 1e-3))
    ekf.step(1.0)
    ekf.add_wheel_twist(1.5, 1.0, 0.0, 0.2, (1e-3, 1e-3, 1e-3))  # queued, then dropped
    cov3 = np.array([[0.25, 0.01, 0.0], [0.01, 0.25, 0.0], [0.0, 0.0, 0.07]])
    ekf.set_pose(2.0, 3.0, -1.0, 0.5, cov3)
    assert np.array_equal(ekf.state, [3.0, -1.0, 0.5, 0.0, 0.0, 0.0])
    expected = np.eye(6) * 1e-6
    expected[np.ix_([0, 1, 2], [0, 1, 2])] = cov3
    assert np.array_equal(ekf.covariance, expected)
    assert ekf.t == 2.0
    ekf.add_wheel_twist(1.9, 5.0, 0.0, 0.0, (1e-3, 1e-3, 1e-3))  # before the reset: ignored
    ekf.add_imu(2.1, 1.3, 0.0, (1e-3, 1e-3))   # the new zero of the relative IMU yaw
    ekf.step(2.1)
    assert ekf.state[0] == 3.0
    assert ekf.state[3] == 0.0
    assert ekf.state[YAW] == pytest.approx(0.5, abs=1e-9)
    with pytest.raises(ValueError, match="3x3"):
        ekf.set_pose(3.0, 0.0, 0.0, 0.0, np.eye(2))
    with pytest.raises(ValueError, match="finite"):
        ekf.set_pose(3.0, float("nan"), 0.0, 0.0, np.eye(3))


@pytest.mark.parametrize("indices", [(6,), (-1,), (VX, 7)])
def test_measurement_with_a_non_state_index_is_refused_when_made(indices: tuple[int, ...]) -> None:
    # The state has six components (X .. VYAW = 0 .. 5); a bad index raises at construction,
    # before anything is queued: the filter then runs as a twin that never saw it.
    ekf, twin = Ekf2D(t0=0.0), Ekf2D(t0=0.0)
    n = len(indices)
    with pytest.raises(IndexError, match=r"not a state index 0\.\.5"):
        ekf.enqueue(Measurement(0.1, indices, (1.0,) * n, (0.01,) * n))
    for f in (ekf, twin):
        f.enqueue(Measurement(0.15, (VX,), (0.5,), (0.01,)))
        f.step(0.2)
    np.testing.assert_array_equal(ekf.state, twin.state)
    np.testing.assert_array_equal(ekf.covariance, twin.covariance)
    assert ekf.state[VX] > 0.1  # the good measurement was fused
