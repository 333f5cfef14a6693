"""Named exceptions and warnings of :mod:`posekit.geometry`.

Every error is a :class:`ValueError` subclass, so ``except ValueError`` keeps working for
callers that do not care which input was bad, while callers that do can catch the precise
class.
"""

from __future__ import annotations

__all__ = [
    "GeometryError",
    "GimbalLockWarning",
    "InvalidQuaternionError",
    "NonFiniteError",
    "NonOrthonormalMatrixError",
    "ShapeError",
    "UnknownSequenceError",
    "ZeroAxisError",
]


class GeometryError(ValueError):
    """Base class of every bad-input error raised by :mod:`posekit.geometry`."""


class InvalidQuaternionError(GeometryError):
    """A quaternion is NaN/inf or has zero norm, so it encodes no rotation.

    Finite non-unit quaternions are *not* errors: they are normalised (see
    :doc:`conventions`).
    """


class NonOrthonormalMatrixError(GeometryError):
    """A matrix is not a rotation (``R Rᵀ ≠ I`` or ``det R ≠ +1``) beyond the tolerance."""


class ZeroAxisError(GeometryError):
    """An axis-angle axis has zero (or non-finite) length, so it names no direction."""


class ShapeError(GeometryError):
    """An array argument has the wrong shape (e.g. a 3-vector where a quaternion belongs)."""


class UnknownSequenceError(GeometryError):
    """An Euler sequence is not one of the 24 valid ones (``'xyz'``, ``'ZYX'``, ``'zxz'``, ...)."""


class NonFiniteError(GeometryError):
    """An angle, vector or translation contains NaN or infinity."""


class GimbalLockWarning(UserWarning):
    """Euler angles were requested at (or within 1e-7 rad of) a gimbal-lock configuration.

    Only the sum (or difference) of the first and third angles is then determined; posekit,
    like scipy, sets the **third** angle of the requested sequence to zero and puts the
    whole rotation about that axis pair into the first angle. At the singularity itself the
    returned angles reproduce the rotation exactly; inside the 1e-7 rad band around it the
    dropped third angle costs a rotation error of about the distance to the singularity
    (scipy behaves the same).
    """
