"""Differential tests: posekit.geometry.Rotation vs scipy (and transforms3d), 10,000 rotations
per Euler sequence and per conversion, agreement to 1e-12."""

import math
import warnings

import numpy as np
import pytest
import transforms3d.euler as t3e
import transforms3d.quaternions as t3q
from scipy.spatial.transform import Rotation as SciRot

from posekit.geometry import EULER_SEQUENCES, Rotation, ShapeError

N = 10_000
TOL = 1e-12


@pytest.fixture(scope="module")
def quats():
    return SciRot.random(N, rng=12345).as_quat()


def same_rotation_quats(a, b):
    """Max component error of unit quaternions modulo the double cover."""
    return np.minimum(np.abs(a - b).max(axis=1), np.abs(a + b).max(axis=1)).max()


def angle_error(a, b):
    return np.abs(np.angle(np.exp(1j * (a - b))))


def singular_distance(seq, angles):
    mid = angles[:, 1]
    if seq[0].lower() == seq[2].lower():
        return np.minimum(np.abs(mid), np.abs(mid - np.pi))
    return np.pi / 2 - np.abs(mid)


@pytest.mark.parametrize("seq", EULER_SEQUENCES)
def test_as_euler_matches_scipy(seq, quats):
    ours = Rotation.from_quat(quats).as_euler(seq)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        ref = SciRot.from_quat(quats).as_euler(seq)
    regular = singular_distance(seq, ref) > 1e-4
    assert regular.sum() > N * 0.99
    assert angle_error(ours[regular], ref[regular]).max() < TOL
    # everywhere (including near singularities): the angles reproduce the rotation
    back = SciRot.from_euler(seq, ours).as_quat()
    assert same_rotation_quats(back, quats) < TOL


@pytest.mark.parametrize("seq", EULER_SEQUENCES)
def test_from_euler_matches_scipy(seq):
    rng = np.random.default_rng(abs(hash(seq)) % 2**32)
    ang = rng.uniform(-math.pi, math.pi, size=(N, 3))
    ang[:, 1] /= 2 if seq[0].lower() != seq[2].lower() else 1
    ours = Rotation.from_euler(seq, ang).as_quat()
    ref = SciRot.from_euler(seq, ang).as_quat()
    assert same_rotation_quats(ours, ref) < TOL
    deg = Rotation.from_euler(seq, np.degrees(ang), degrees=True).as_quat()
    assert same_rotation_quats(deg, ref) < TOL


@pytest.mark.parametrize("seq", EULER_SEQUENCES)
def test_gimbal_lock_compared_as_rotations(seq):
    proper = seq[0].lower() == seq[2].lower()
    exact_mids = [0.0, math.pi] if proper else [math.pi / 2, -math.pi / 2]
    rng = np.random.default_rng(1)
    ang = rng.uniform(-math.pi, math.pi, size=(100, 3))
    ang[:, 1] = np.repeat(exact_mids, 50)
    r = SciRot.from_euler(seq, ang)
    ours, locked = Rotation.from_quat(r.as_quat()).as_euler_checked(seq)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        ref = r.as_euler(seq)
    assert locked.all()
    np.testing.assert_allclose(
        SciRot.from_euler(seq, ours).as_matrix(), r.as_matrix(), atol=TOL, rtol=0
    )
    # scipy's documented choice (third angle = 0) is ours too
    assert np.all(ours[:, 2] == 0.0)
    assert angle_error(ours, ref).max() < 1e-9


@pytest.mark.parametrize("seq", ["xyz", "ZYX", "zxz", "YZY"])
def test_inside_lock_threshold_the_rotation_error_is_bounded_by_the_distance(seq):
    # Within 1e-7 rad of the singularity both scipy and posekit report lock and drop the
    # third angle; the reconstructed rotation is then off by at most ~ the distance.
    proper = seq[0].lower() == seq[2].lower()
    mid = 1e-9 if proper else math.pi / 2 - 1e-9
    ang = np.column_stack([np.linspace(-3, 3, 50), np.full(50, mid), np.linspace(2, -2, 50)])
    r = SciRot.from_euler(seq, ang)
    ours, locked = Rotation.from_quat(r.as_quat()).as_euler_checked(seq)
    assert locked.all()
    err = (SciRot.from_euler(seq, ours).inv() * r).magnitude()
    assert err.max() < 3e-9


def test_matrix_conversions_match_scipy(quats):
    ours = Rotation.from_quat(quats)
    ref = SciRot.from_quat(quats)
    np.testing.assert_allclose(ours.as_matrix(), ref.as_matrix(), atol=TOL, rtol=0)
    mats = ref.as_matrix()
    assert same_rotation_quats(Rotation.from_matrix(mats).as_quat(), quats) < TOL


def test_rotvec_and_magnitude_match_scipy(quats):
    ours = Rotation.from_quat(quats)
    ref = SciRot.from_quat(quats)
    np.testing.assert_allclose(ours.as_rotvec(), ref.as_rotvec(), atol=TOL, rtol=0)
    np.testing.assert_allclose(ours.magnitude(), ref.magnitude(), atol=TOL, rtol=0)
    rv = ref.as_rotvec()
    assert same_rotation_quats(Rotation.from_rotvec(rv).as_quat(), quats) < TOL


def test_compose_inverse_apply_match_scipy(quats):
    other = SciRot.random(N, rng=99)
    ours = Rotation.from_quat(quats) * Rotation.from_quat(other.as_quat())
    ref = SciRot.from_quat(quats) * other
    assert same_rotation_quats(ours.as_quat(), ref.as_quat()) < TOL
    assert same_rotation_quats(
        Rotation.from_quat(quats).inv().as_quat(), SciRot.from_quat(quats).inv().as_quat()
    ) < TOL
    v = np.random.default_rng(5).normal(size=(N, 3))
    np.testing.assert_allclose(
        Rotation.from_quat(quats).apply(v), SciRot.from_quat(quats).apply(v), atol=TOL, rtol=0
    )
    np.testing.assert_allclose(
        Rotation.from_quat(quats).apply(v, inverse=True),
        SciRot.from_quat(quats).apply(v, inverse=True),
        atol=TOL,
        rtol=0,
    )


def test_scalar_first_and_canonical_match_scipy(quats):
    np.testing.assert_allclose(
        Rotation.from_quat(quats).as_quat(canonical=True),
        SciRot.from_quat(quats).as_quat(canonical=True),
        atol=TOL,
        rtol=0,
    )
    wxyz = quats[:, [3, 0, 1, 2]]
    np.testing.assert_allclose(
        Rotation.from_quat(wxyz, scalar_first=True).as_quat(), quats, atol=TOL, rtol=0
    )
    np.testing.assert_allclose(
        Rotation.from_quat(quats).as_quat(scalar_first=True),
        SciRot.from_quat(quats).as_quat(scalar_first=True),
        atol=TOL,
        rtol=0,
    )


def test_single_path_matches_scipy_on_sample(quats):
    for q in quats[:500]:
        ours = Rotation.from_quat(q.tolist())
        ref = SciRot.from_quat(q)
        np.testing.assert_allclose(ours.as_euler("zyx"), ref.as_euler("zyx"), atol=TOL)
        np.testing.assert_allclose(ours.as_matrix(), ref.as_matrix(), atol=TOL)
        np.testing.assert_allclose(ours.as_rotvec(), ref.as_rotvec(), atol=TOL)


def test_slerp_matches_scipy_slerp():
    from scipy.spatial.transform import Slerp

    a, b = SciRot.random(rng=3), SciRot.random(rng=4)
    ts = np.linspace(0, 1, 101)
    ref = Slerp([0, 1], SciRot.concatenate([a, b]))(ts)
    ours = Rotation.from_quat(a.as_quat()).slerp(Rotation.from_quat(b.as_quat()), ts)
    assert same_rotation_quats(ours.as_quat(), ref.as_quat()) < TOL


# ---------------------------------------------------------------- transforms3d (w, x, y, z)

T3D_AXES = {}
for _seq in EULER_SEQUENCES:
    # transforms3d: 's' static = extrinsic, 'r' rotating = intrinsic (axes listed in order)
    T3D_AXES[_seq] = ("s" if _seq.islower() else "r") + _seq.lower()


@pytest.mark.parametrize("seq", EULER_SEQUENCES)
def test_euler_matches_transforms3d(seq):
    rng = np.random.default_rng(7)
    for ang in rng.uniform(-1.2, 1.2, size=(200, 3)):
        q = Rotation.from_euler(seq, ang).as_quat(scalar_first=True)
        ref = t3e.euler2quat(*ang, axes=T3D_AXES[seq])
        assert same_rotation_quats(q[None], np.asarray(ref)[None]) < TOL
        back = t3e.quat2euler(q, axes=T3D_AXES[seq])
        r_back = Rotation.from_euler(seq, back)
        assert r_back.approx_equal(Rotation.from_euler(seq, ang), atol=1e-10)


def test_quaternion_ops_match_transforms3d(quats):
    rng = np.random.default_rng(8)
    for q, v in zip(quats[:300], rng.normal(size=(300, 3)), strict=True):
        wxyz = q[[3, 0, 1, 2]]
        r = Rotation.from_quat(q)
        np.testing.assert_allclose(r.as_matrix(), t3q.quat2mat(wxyz), atol=TOL)
        np.testing.assert_allclose(r.apply(v), t3q.rotate_vector(v, wxyz), atol=TOL)
        prod = (r * r).as_quat(scalar_first=True)
        np.testing.assert_allclose(prod, t3q.qmult(wxyz, wxyz), atol=TOL)
        axis, angle = r.as_axis_angle()
        ref_axis, ref_angle = t3q.quat2axangle(wxyz)
        ref = Rotation.from_axis_angle(ref_axis, ref_angle)
        assert ref.approx_equal(Rotation.from_axis_angle(axis, angle), atol=TOL)


def test_mrp_matches_scipy(quats):
    ours = Rotation.from_quat(quats).as_mrp()
    ref = SciRot.from_quat(quats).as_mrp()
    assert np.abs(ours - ref).max() < TOL
    assert np.linalg.norm(ours, axis=1).max() <= 1.0 + TOL  # the shorter way round
    mrps = np.random.default_rng(3).normal(scale=2.0, size=(N, 3))
    assert same_rotation_quats(Rotation.from_mrp(mrps).as_quat(),
                               SciRot.from_mrp(mrps).as_quat()) < TOL
    single = Rotation.from_mrp(mrps[0])
    assert single.single
    assert same_rotation_quats(single.as_quat()[None],
                               SciRot.from_mrp(mrps[0]).as_quat()[None]) < TOL
    assert np.allclose(Rotation.from_quat(quats[0]).as_mrp(), SciRot.from_quat(quats[0]).as_mrp())


@pytest.mark.parametrize("n", [0.0, 1.0, -1.0, 2.0, 0.5, -0.25, 3.7])
def test_power_matches_scipy(n, quats):
    ours = (Rotation.from_quat(quats[:1000]) ** n).as_quat()
    ref = (SciRot.from_quat(quats[:1000]) ** n).as_quat()
    assert same_rotation_quats(ours, ref) < 1e-10
    single = Rotation.from_quat(quats[0]) ** n
    assert single.single
    ref = SciRot.from_quat(quats[0]) ** n
    assert same_rotation_quats(single.as_quat()[None], ref.as_quat()[None]) < 1e-10


def test_mean_matches_scipy(quats):
    rng = np.random.default_rng(5)
    for size in (1, 2, 7, 1000):
        chunk = quats[:size]
        weights = rng.uniform(0.0, 3.0, size)
        for w in (None, weights):
            ours = Rotation.from_quat(chunk).mean(w)
            ref = SciRot.from_quat(chunk).mean(w)
            assert ours.single
            assert same_rotation_quats(ours.as_quat()[None], ref.as_quat()[None]) < 1e-9
    # a spread of yaws about 40 degrees: the mean is 40 degrees
    yaws = Rotation.from_euler("z", [[30], [40], [50]], degrees=True)
    assert yaws.mean().approx_equal(Rotation.from_euler("z", 40, degrees=True), atol=1e-12)
    with pytest.raises(ValueError, match="non-negative"):
        yaws.mean([1.0, -1.0, 1.0])
    with pytest.raises(ShapeError):
        yaws.mean([1.0, 1.0])


def test_align_vectors_matches_scipy():
    rng = np.random.default_rng(7)
    for n in (2, 3, 10, 500):
        b = rng.normal(size=(n, 3))
        truth = SciRot.random(rng=rng)
        a = truth.apply(b) + rng.normal(scale=0.01, size=(n, 3))
        weights = rng.uniform(0.1, 2.0, n)
        for w in (None, weights):
            ours, ours_rssd = Rotation.align_vectors(a, b, w)
            ref, ref_rssd = SciRot.align_vectors(a, b, w)
            assert ours.single
            assert same_rotation_quats(ours.as_quat()[None], ref.as_quat()[None]) < 1e-9
            assert ours_rssd == pytest.approx(ref_rssd, rel=1e-6, abs=1e-9)
    # a mirror image: the best proper rotation flips the smallest singular direction
    b = rng.normal(size=(20, 3))
    a = b * np.array([1.0, 1.0, -1.0])
    ours, ours_rssd = Rotation.align_vectors(a, b)
    ref, ref_rssd = SciRot.align_vectors(a, b)
    assert same_rotation_quats(ours.as_quat()[None], ref.as_quat()[None]) < 1e-9
    assert ours_rssd == pytest.approx(ref_rssd, rel=1e-9)
    # one pair: the smallest rotation between the directions, as scipy
    for a, b in (([1, 0, 0], [0, 1, 0]), ([0, 0, 2], [0, 0, 1]), ([1, 2, 3], [-3, 1, 0.5])):
        ours, ours_rssd = Rotation.align_vectors(a, b)
        ref, ref_rssd = SciRot.align_vectors(a, b)
        assert same_rotation_quats(ours.as_quat()[None], ref.as_quat()[None]) < 1e-9
        assert ours_rssd == pytest.approx(ref_rssd, abs=1e-9)
    # opposite directions: half a turn taking b onto a
    turned, _ = Rotation.align_vectors([-1.0, 0.0, 0.0], [1.0, 0.0, 0.0])
    assert np.allclose(turned.apply([1.0, 0.0, 0.0]), [-1.0, 0.0, 0.0])
    with pytest.raises(ShapeError):
        Rotation.align_vectors([[1, 0, 0]], [[0, 1, 0], [1, 0, 0]])
    with pytest.raises(ValueError, match="zero vector"):
        Rotation.align_vectors([0, 0, 0], [1, 0, 0])


@pytest.mark.parametrize("angles", [90, [90], [[90]], [[10], [20]], [[1.0, 2.0]], (5.0, 6.0)])
def test_one_and_two_axis_angle_shapes_follow_scipy(angles):
    seq = "z" if np.asarray(angles).size in (1,) or np.asarray(angles).shape[-1] == 1 else "zx"
    ours = Rotation.from_euler(seq, angles, degrees=True)
    ref = SciRot.from_euler(seq, angles, degrees=True)
    assert ours.single == ref.single
    assert ours.as_quat().shape == ref.as_quat().shape
    assert np.allclose(ours.as_quat(), ref.as_quat())


def test_one_axis_angles_of_shape_n_are_refused_as_by_scipy():
    with pytest.raises(ValueError, match="last dimension"):
        SciRot.from_euler("z", [10, 20], degrees=True)
    with pytest.raises(ShapeError, match=r"\(N, 1\)"):
        Rotation.from_euler("z", [10, 20], degrees=True)
