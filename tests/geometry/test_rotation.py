"""Rotation: lecture reference values, API protocol, errors, group properties, batch == singles."""

import math
import warnings

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from posekit.geometry import (
    EULER_SEQUENCES,
    GimbalLockWarning,
    InvalidQuaternionError,
    NonFiniteError,
    NonOrthonormalMatrixError,
    Rotation,
    ShapeError,
    UnknownSequenceError,
    ZeroAxisError,
    compose_body,
    compose_world,
)

S2 = math.sqrt(2.0) / 2.0
angle = st.floats(-math.pi, math.pi, allow_nan=False)
seqs = st.sampled_from(EULER_SEQUENCES)


@st.composite
def rotations(draw):
    q = np.array([draw(st.floats(-1, 1, allow_nan=False)) for _ in range(4)])
    if np.linalg.norm(q) < 0.1:
        q = np.array([0.1, -0.2, 0.3, 0.9])
    return Rotation.from_quat(q)


def rx(a):
    return np.array([[1, 0, 0], [0, math.cos(a), -math.sin(a)], [0, math.sin(a), math.cos(a)]])


def ry(a):
    return np.array([[math.cos(a), 0, math.sin(a)], [0, 1, 0], [-math.sin(a), 0, math.cos(a)]])


def rz(a):
    return np.array([[math.cos(a), -math.sin(a), 0], [math.sin(a), math.cos(a), 0], [0, 0, 1]])


ELEMENTARY = {"x": rx, "y": ry, "z": rz}

# ---------------------------------------------------------------- lecture reference values

# The lecture's table of common quaternions, (w, x, y, z) to 3 decimals.
COMMON = [
    ("identity", (0, 0, 1), 0.0, (1.0, 0.0, 0.0, 0.0)),
    ("90 deg about Z", (0, 0, 1), 90.0, (0.707, 0.0, 0.0, 0.707)),
    ("180 deg about Z", (0, 0, 1), 180.0, (0.0, 0.0, 0.0, 1.0)),
    ("90 deg about X", (1, 0, 0), 90.0, (0.707, 0.707, 0.0, 0.0)),
    ("45 deg about Y", (0, 1, 0), 45.0, (0.924, 0.0, 0.383, 0.0)),
]


@pytest.mark.parametrize(("name", "axis", "deg", "wxyz"), COMMON)
def test_lecture_common_quaternion_table(name, axis, deg, wxyz):
    r = Rotation.from_axis_angle(axis, deg, degrees=True)
    np.testing.assert_allclose(r.as_quat(scalar_first=True), wxyz, atol=5e-4)


def test_lecture_exercise_pi_over_2_about_x():
    q = Rotation.from_axis_angle([1, 0, 0], math.pi / 2).as_quat(scalar_first=True)
    np.testing.assert_allclose(q, (S2, S2, 0.0, 0.0), atol=1e-15)
    # apply it: y axis goes to z, the right-hand rule
    np.testing.assert_allclose(
        Rotation.from_quat(q, scalar_first=True).apply([0, 1, 0]), [0, 0, 1], atol=1e-15
    )


def test_lecture_double_cover():
    a = Rotation.from_quat([S2, S2, 0, 0], scalar_first=True)
    b = Rotation.from_quat([-S2, -S2, 0, 0], scalar_first=True)
    assert a.approx_equal(b, atol=1e-15)
    np.testing.assert_allclose(a.as_matrix(), b.as_matrix(), atol=1e-15)
    np.testing.assert_allclose(b.as_quat(canonical=True, scalar_first=True), (S2, S2, 0, 0))
    assert not a.approx_equal(a.inv(), atol=1e-3)


def test_lecture_appendix_a_gimbal_lock():
    # R = Rz(psi) Ry(theta) Rx(phi) with theta = 90 deg: only psi - phi survives
    def closed_form(d):
        return np.array(
            [[0, -math.sin(d), math.cos(d)], [0, math.cos(d), math.sin(d)], [-1, 0, 0]]
        )

    r1 = Rotation.from_euler("ZYX", [90, 90, 30], degrees=True)
    r2 = Rotation.from_euler("ZYX", [120, 90, 60], degrees=True)
    np.testing.assert_allclose(r1.as_matrix(), closed_form(math.radians(60)), atol=1e-15)
    np.testing.assert_allclose(r2.as_matrix(), closed_form(math.radians(60)), atol=1e-15)
    with pytest.warns(GimbalLockWarning, match="third angle"):
        ang = r1.as_euler("ZYX", degrees=True)
    # documented choice: third angle (phi, roll) = 0, psi carries psi - phi
    np.testing.assert_allclose(ang, [60.0, 90.0, 0.0], atol=1e-9)
    ang2, locked = r2.as_euler_checked("ZYX", degrees=True)
    assert locked is True
    np.testing.assert_allclose(ang2, [60.0, 90.0, 0.0], atol=1e-9)


def test_no_warning_away_from_gimbal_lock():
    r = Rotation.from_euler("xyz", [0.1, 1.5, 0.3])
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # any GimbalLockWarning would raise here
        np.testing.assert_allclose(r.as_euler("xyz"), [0.1, 1.5, 0.3], atol=1e-12)
        np.testing.assert_allclose(r.as_euler("xyz", warn=True), [0.1, 1.5, 0.3], atol=1e-12)


def test_world_vs_body_composition():
    # Start yawed 90 deg; roll 90 deg about world x vs about the body's own x.
    O_init = Rotation.from_rpy(0, 0, math.pi / 2)
    O_rot = Rotation.from_rpy(math.pi / 2, 0, 0)
    world = compose_world(O_rot, O_init)
    body = compose_body(O_init, O_rot)
    np.testing.assert_allclose(world.as_matrix(), rx(math.pi / 2) @ rz(math.pi / 2), atol=1e-15)
    np.testing.assert_allclose(body.as_matrix(), rz(math.pi / 2) @ rx(math.pi / 2), atol=1e-15)
    # body roll keeps the nose (body x, now world y) in place; world roll moves it to z
    np.testing.assert_allclose(body.apply([1, 0, 0]), [0, 1, 0], atol=1e-15)
    np.testing.assert_allclose(world.apply([1, 0, 0]), [0, 0, 1], atol=1e-15)
    assert O_init.rotated_about_world(O_rot).approx_equal(world)
    assert O_init.rotated_about_body(O_rot).approx_equal(body)


# ---------------------------------------------------------------- closed forms


@given(seqs, angle, angle, angle)
def test_from_euler_matches_matrix_products(seq, a, b, c):
    mats = [ELEMENTARY[ax.lower()] for ax in seq]
    if seq.islower():  # extrinsic: first rotation leftmost in time, rightmost in product
        expected = mats[2](c) @ mats[1](b) @ mats[0](a)
    else:
        expected = mats[0](a) @ mats[1](b) @ mats[2](c)
    got = Rotation.from_euler(seq, [a, b, c]).as_matrix()
    np.testing.assert_allclose(got, expected, atol=1e-14)


@given(rotations(), seqs)
def test_euler_round_trip_all_sequences(r, seq):
    ang, _locked = r.as_euler_checked(seq)
    lo, hi = (-math.pi / 2, math.pi / 2) if seq[0].lower() != seq[2].lower() else (0, math.pi)
    assert lo - 1e-12 <= ang[1] <= hi + 1e-12
    assert np.all(np.abs(ang[[0, 2]]) <= math.pi)
    assert Rotation.from_euler(seq, ang).approx_equal(r, atol=1e-12)


@given(angle, st.floats(-1.5, 1.5), angle)
def test_rpy_round_trip_and_equals_extrinsic_xyz(r, p, y):
    rot = Rotation.from_rpy(r, p, y)
    assert rot.approx_equal(Rotation.from_euler("xyz", [r, p, y]), atol=1e-15)
    assert rot.approx_equal(Rotation.from_euler("ZYX", [y, p, r]), atol=1e-15)
    np.testing.assert_allclose(rot.as_rpy(), (r, p, y), atol=1e-12)


@given(rotations())
def test_conversion_round_trips(r):
    assert Rotation.from_matrix(r.as_matrix()).approx_equal(r, atol=1e-14)
    assert Rotation.from_rotvec(r.as_rotvec()).approx_equal(r, atol=1e-14)
    axis, ang = r.as_axis_angle()
    assert Rotation.from_axis_angle(axis, ang).approx_equal(r, atol=1e-14)
    assert 0.0 <= ang <= math.pi
    assert r.magnitude() == pytest.approx(ang, abs=1e-14)
    wxyz = r.as_quat(scalar_first=True)
    assert Rotation.from_quat(wxyz, scalar_first=True).approx_equal(r, 1e-15)
    np.testing.assert_allclose(r.as_matrix() @ [0.3, -1, 2], r.apply([0.3, -1, 2]), atol=1e-14)


def test_rotvec_degrees_and_tiny_angles():
    r = Rotation.from_rotvec([0, 0, 90], degrees=True)
    np.testing.assert_allclose(r.as_matrix(), rz(math.pi / 2), atol=1e-15)
    np.testing.assert_allclose(r.as_rotvec(degrees=True), [0, 0, 90], atol=1e-12)
    tiny = Rotation.from_rotvec([1e-9, 0, 0])
    np.testing.assert_allclose(tiny.as_rotvec(), [1e-9, 0, 0], rtol=1e-15, atol=0)
    assert tiny.magnitude() == pytest.approx(1e-9, rel=1e-15)


# ---------------------------------------------------------------- group axioms


@given(rotations(), rotations(), rotations())
def test_group_axioms(a, b, c):
    assert ((a * b) * c).approx_equal(a * (b * c), atol=1e-13)
    assert (a * Rotation.identity()).approx_equal(a, atol=1e-15)
    assert (Rotation.identity() * a).approx_equal(a, atol=1e-15)
    assert (a * a.inv()).approx_equal(Rotation.identity(), atol=1e-14)
    # r1 * r2 applies r2 first
    v = np.array([0.2, -0.7, 1.1])
    np.testing.assert_allclose((a * b).apply(v), a.apply(b.apply(v)), atol=1e-14)
    np.testing.assert_allclose(a.apply(a.apply(v), inverse=True), v, atol=1e-14)


@given(rotations(), rotations(), st.floats(0, 1))
def test_slerp_properties(a, b, t):
    assert a.slerp(b, 0.0).approx_equal(a, atol=1e-12)
    assert a.slerp(b, 1.0).approx_equal(b, atol=1e-7)
    # constant angular speed along the shortest arc: angle(a, r_t) = t * angle(a, b)
    total = (a.inv() * b).magnitude()
    part = (a.inv() * a.slerp(b, t)).magnitude()
    assert part == pytest.approx(t * total, abs=1e-7)
    assert total <= math.pi + 1e-12


# ---------------------------------------------------------------- batch protocol


def test_batch_equals_loop_of_singles():
    rng = np.random.default_rng(3)
    rs = Rotation.random(300, rng)
    other = Rotation.random(300, rng)
    v = rng.normal(size=(300, 3))
    singles = list(rs)
    for seq in EULER_SEQUENCES:
        batch = rs.as_euler(seq)
        loop = np.array([r.as_euler(seq) for r in singles])
        np.testing.assert_allclose(batch, loop, atol=1e-14)
        back = Rotation.from_euler(seq, batch).as_quat()
        back_loop = np.array([Rotation.from_euler(seq, e).as_quat() for e in loop])
        np.testing.assert_allclose(back, back_loop, atol=1e-15)
    pairs = list(zip(rs, other, strict=True))
    checks = {
        "matrix": (rs.as_matrix(), [r.as_matrix() for r in singles]),
        "rotvec": (rs.as_rotvec(), [r.as_rotvec() for r in singles]),
        "compose": ((rs * other).as_quat(), [(a * b).as_quat() for a, b in pairs]),
        "inv": (rs.inv().as_quat(), [r.inv().as_quat() for r in singles]),
        "apply": (rs.apply(v), [r.apply(x) for r, x in zip(singles, v, strict=False)]),
        "magnitude": (rs.magnitude(), [r.magnitude() for r in singles]),
        "canonical": (rs.as_quat(canonical=True), [r.as_quat(canonical=True) for r in singles]),
        "slerp": (rs.slerp(other, 0.3).as_quat(), [a.slerp(b, 0.3).as_quat() for a, b in pairs]),
        "from_matrix": (
            Rotation.from_matrix(rs.as_matrix()).as_quat(),
            [Rotation.from_matrix(m).as_quat() for m in rs.as_matrix()],
        ),
        "rpy": (np.stack(rs.as_rpy(), axis=1), [r.as_rpy() for r in singles]),
    }
    for name, (batch, loop) in checks.items():
        np.testing.assert_allclose(batch, np.array(loop), atol=1e-14, err_msg=name)


def test_batch_protocol_like_scipy():
    single = Rotation.identity()
    assert single.single
    with pytest.raises(TypeError):
        len(single)
    with pytest.raises(TypeError):
        single[0]
    assert bool(single)
    batch = Rotation.random(5, rng=1)
    assert len(batch) == 5
    assert not batch.single
    assert batch[2].single
    assert len(batch[1:3]) == 2
    assert len(batch[[True, False, True, False, True]]) == 3
    assert batch[-1].approx_equal(list(batch)[-1], atol=0)
    one = Rotation.from_quat([[0, 0, 0, 1]])
    assert not one.single
    assert len(one) == 1
    empty = Rotation.from_quat(np.zeros((0, 4)))
    assert len(empty) == 0
    assert empty.as_matrix().shape == (0, 3, 3)
    assert len(Rotation.concatenate([single, batch])) == 6
    assert Rotation.identity(3).as_quat().tolist() == [[0, 0, 0, 1]] * 3
    # a single broadcasts against a batch
    assert len(single * batch) == 5
    assert len(batch.apply([1, 0, 0])) == 5


def test_random_is_seeded_and_unit():
    a = Rotation.random(1000, rng=7).as_quat()
    assert np.array_equal(a, Rotation.random(1000, rng=7).as_quat())
    np.testing.assert_allclose(np.linalg.norm(a, axis=1), 1.0, atol=1e-15)
    # uniform on S^3: w has density (2/pi) sqrt(1 - w^2), so E[|w|] = 4 / (3 pi)
    assert np.abs(a[:, 3]).mean() == pytest.approx(4 / (3 * math.pi), abs=0.02)


def test_as_quat_canonical_and_orders():
    r = Rotation.from_quat([0.0, 0.0, 0.0, -1.0])
    assert r.as_quat(canonical=True).tolist() == [0, 0, 0, 1]
    r = Rotation.from_quat([0.0, -1.0, 0.0, 0.0])
    assert r.as_quat(canonical=True).tolist() == [0, 1, 0, 0]
    r = Rotation.from_quat([1, 2, 3, 4], scalar_first=True)
    np.testing.assert_allclose(r.as_quat(), np.array([2, 3, 4, 1]) / math.sqrt(30))
    np.testing.assert_allclose(r.as_quat(scalar_first=True), np.array([1, 2, 3, 4]) / math.sqrt(30))
    assert r.as_quat_tuple(scalar_first=True) == tuple(r.as_quat(scalar_first=True))


def test_extreme_but_finite_quaternions_are_normalised():
    big = Rotation.from_quat([[0, 0, 1e200, 1e200], [1e-200, 0, 0, 1e-200]])
    s = math.sqrt(0.5)
    np.testing.assert_allclose(big.as_quat(), [[0, 0, s, s], [s, 0, 0, s]], atol=1e-15)
    np.testing.assert_allclose(Rotation.from_quat([0, 0, 1e200, 1e200]).as_quat(), [0, 0, s, s])


def test_non_unit_quaternions_are_normalised():
    r = Rotation.from_quat([0, 0, 0, 5.0])
    assert r.as_quat().tolist() == [0, 0, 0, 1]
    rs = Rotation.from_quat([[0, 0, 3.0, 4.0], [2.0, 0, 0, 0]])
    np.testing.assert_allclose(rs.as_quat(), [[0, 0, 0.6, 0.8], [1, 0, 0, 0]])


# ---------------------------------------------------------------- errors


@pytest.mark.parametrize(
    "quat",
    [[0, 0, 0, 0], [math.nan, 0, 0, 1], [0, 0, math.inf, 1], [[0, 0, 0, 1], [0, 0, 0, 0]]],
)
def test_invalid_quaternions_raise(quat):
    with pytest.raises(InvalidQuaternionError) as info:
        Rotation.from_quat(quat)
    assert isinstance(info.value, ValueError)


@pytest.mark.parametrize("bad", [[1, 2, 3], [[1, 2, 3]], np.zeros((2, 2, 4)), []])
def test_wrong_shapes_raise(bad):
    with pytest.raises(ShapeError):
        Rotation.from_quat(bad)


def test_other_errors():
    with pytest.raises(NonOrthonormalMatrixError):
        Rotation.from_matrix(np.diag([1.0, 1.0, 1.1]))
    with pytest.raises(NonOrthonormalMatrixError):
        Rotation.from_matrix(np.diag([1.0, 1.0, -1.0]))  # reflection
    with pytest.raises(NonOrthonormalMatrixError):
        Rotation.from_matrix(np.stack([np.eye(3), 2 * np.eye(3)]))
    with pytest.raises(NonOrthonormalMatrixError):
        Rotation.from_matrix(np.full((3, 3), math.nan))
    # within tolerance: accepted, result is a proper rotation close to the input
    near = rz(0.3) + 1e-8
    assert Rotation.from_matrix(near).approx_equal(Rotation.from_matrix(rz(0.3)), atol=1e-7)
    with pytest.raises(ShapeError):
        Rotation.from_matrix(np.eye(4))
    with pytest.raises(ZeroAxisError):
        Rotation.from_axis_angle([0, 0, 0], 1.0)
    with pytest.raises(ZeroAxisError):
        Rotation.from_axis_angle([[1, 0, 0], [0, 0, 0]], [1.0, 2.0])
    for seq in ("xyx2", "xxy", "Xyz", "abc", ""):
        with pytest.raises(UnknownSequenceError):
            Rotation.from_euler(seq, [0, 0, 0])
        with pytest.raises(UnknownSequenceError):
            Rotation.identity().as_euler(seq)
    with pytest.raises(NonFiniteError):
        Rotation.from_euler("xyz", [0, math.nan, 0])
    with pytest.raises(NonFiniteError):
        Rotation.from_euler("xyz", [[0, 0, 0], [math.inf, 0, 0]])
    with pytest.raises(NonFiniteError):
        Rotation.from_rotvec([0, math.nan, 0])
    with pytest.raises(ShapeError):
        Rotation.random(3, rng=0) * Rotation.random(4, rng=0)
    with pytest.raises(ShapeError):
        Rotation.random(3, rng=0).apply(np.zeros((4, 3)))


def test_gimbal_lock_warning_is_a_user_warning_and_batch_warns_once():
    assert issubclass(GimbalLockWarning, UserWarning)
    rows = [[0.1, math.pi / 2, 0.2], [0.1, 0.2, 0.3], [0, -math.pi / 2, 1]]
    rs = Rotation.from_euler("xyz", rows)
    with pytest.warns(GimbalLockWarning) as rec:
        ang = rs.as_euler("xyz")
    assert len(rec) == 1
    _, locked = rs.as_euler_checked("xyz")
    assert locked.tolist() == [True, False, True]
    assert ang[0, 2] == 0.0
    assert ang[2, 2] == 0.0
    assert Rotation.from_euler("xyz", ang).approx_equal(rs, atol=1e-12).all()


@pytest.mark.parametrize("seq", ["x", "Y", "z", "xy", "ZX", "yz", "XY"])
def test_short_euler_sequences_match_scipy(seq: str) -> None:
    from scipy.spatial.transform import Rotation as SciRotation

    rng = np.random.default_rng(7)
    k = len(seq)
    batch = rng.uniform(-np.pi, np.pi, size=(50, k))
    ours = Rotation.from_euler(seq, batch).as_matrix()
    ref = SciRotation.from_euler(seq, batch).as_matrix()
    np.testing.assert_allclose(ours, ref, atol=1e-12)
    single = batch[0, 0] if k == 1 else batch[0]
    np.testing.assert_allclose(
        Rotation.from_euler(seq, single).as_matrix(),
        SciRotation.from_euler(seq, single).as_matrix(), atol=1e-12,
    )


def test_lecture_exercise_with_a_single_axis_sequence() -> None:
    # The lecture's exercise: pi/2 about x is (w, x, y, z) = (0.707, 0.707, 0, 0).
    q = Rotation.from_euler("x", 90, degrees=True).as_quat(scalar_first=True)
    np.testing.assert_allclose(q, [np.sqrt(0.5), np.sqrt(0.5), 0.0, 0.0], atol=1e-15)
