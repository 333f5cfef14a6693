"""QoS overrides by parameter (rclpy.qos_overriding_options).

``create_publisher(..., qos_overriding_options=QoSOverridingOptions.with_default_policies())``
declares one read-only parameter per policy, ``qos_overrides.<topic>.publisher.<policy>``
(``subscription`` for a subscription, ``_<entity_id>`` after it when given), valued from the
profile: ``keep_last``, ``20``, ``best_effort``, durations in nanoseconds. A parameter
override (``--ros-args -p qos_overrides./chatter.publisher.depth:=20``, a parameter file, a
launch) therefore changes the profile before the entity is made. The options' callback then
validates the profile (``InvalidQosOverridesError`` when it refuses); an override naming no
member of its policy raises ``RuntimeError``. Subscriptions have no ``lifespan``.
tests/rclpy/differential/qos_overrides.py compares it with the real rclpy.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable
from typing import TYPE_CHECKING, Any

from posekit.msgs.rcl_interfaces import ParameterDescriptor, SetParametersResult
from posekit.runtime.parameters import ParameterAlreadyDeclaredException
from posekit.runtime.qos import (
    DurabilityPolicy,
    HistoryPolicy,
    LivelinessPolicy,
    QoSPolicyKind,
    QoSProfile,
    ReliabilityPolicy,
)
from posekit.time import Duration

if TYPE_CHECKING:
    from posekit.runtime.node import Node

__all__ = [
    "InvalidQosOverridesError",
    "QoSOverridingOptions",
    "QosCallbackResult",
    "QosCallbackType",
    "declare_qos_parameters",
]

QosCallbackResult = SetParametersResult
QosCallbackType = Callable[[QoSProfile], SetParametersResult]

#: The policies given as an enum member's name (lower case) in their parameter.
_ENUMS: dict[QoSPolicyKind, type[Any]] = {
    QoSPolicyKind.HISTORY: HistoryPolicy, QoSPolicyKind.RELIABILITY: ReliabilityPolicy,
    QoSPolicyKind.DURABILITY: DurabilityPolicy, QoSPolicyKind.LIVELINESS: LivelinessPolicy,
}
#: The policies given in nanoseconds.
_DURATIONS = (QoSPolicyKind.LIFESPAN, QoSPolicyKind.DEADLINE,
              QoSPolicyKind.LIVELINESS_LEASE_DURATION)


class InvalidQosOverridesError(Exception):
    """The options' callback refused the overridden profile."""


class QoSOverridingOptions:
    """Which policies of an entity get a ``qos_overrides`` parameter, and a validation."""

    def __init__(self, policy_kinds: Iterable[QoSPolicyKind], *,
                 callback: QosCallbackType | None = None, entity_id: str | None = None) -> None:
        self._policy_kinds = policy_kinds
        self._callback = callback
        self._entity_id = entity_id

    @property
    def policy_kinds(self) -> Iterable[QoSPolicyKind]:
        """The policies that get a parameter."""
        return self._policy_kinds

    @property
    def callback(self) -> QosCallbackType | None:
        """Validates the profile once the overrides are applied."""
        return self._callback

    @property
    def entity_id(self) -> str | None:
        """Tells apart entities of one topic in the parameter names."""
        return self._entity_id

    @classmethod
    def with_default_policies(cls, *, callback: QosCallbackType | None = None,
                              entity_id: str | None = None) -> QoSOverridingOptions:
        """History, depth and reliability."""
        return cls([QoSPolicyKind.HISTORY, QoSPolicyKind.DEPTH, QoSPolicyKind.RELIABILITY],
                   callback=callback, entity_id=entity_id)


def _policy_value(qos: QoSProfile, policy: QoSPolicyKind) -> Any:
    value = getattr(qos, policy.name.lower())
    if policy in _ENUMS:
        if value.name == "UNKNOWN":
            raise ValueError("User provided QoS profile is invalid")
        return value.name.lower()
    return value.nanoseconds if policy in _DURATIONS else value


def _set_policy(qos: QoSProfile, policy: QoSPolicyKind, value: Any) -> None:
    if policy in _ENUMS:
        try:
            value = _ENUMS[policy][str(value).upper()]
        except KeyError:
            raise RuntimeError(
                f"Unexpected QoS override for policy `{policy.name.lower()}`: `{value}`"
            ) from None
    elif policy in _DURATIONS:
        value = Duration(nanoseconds=value)
    setattr(qos, policy.name.lower(), value)


def declare_qos_parameters(node: Node, kind: str, topic: str, qos: QoSProfile,
                           options: QoSOverridingOptions) -> None:
    """Declare ``qos``'s parameters on ``node`` and apply their values to ``qos`` in place.

    ``kind``: ``"publisher"`` or ``"subscription"``; ``topic``: the entity's full name.
    """
    suffix = "" if options.entity_id is None else f"_{options.entity_id}"
    prefix = f"qos_overrides.{topic}.{kind}{suffix}."
    for policy in options.policy_kinds:
        if kind == "subscription" and policy == QoSPolicyKind.LIFESPAN:
            continue
        name = policy.name.lower()
        descriptor = ParameterDescriptor(
            description=f"{name} for {kind} `{topic}` with id `{options.entity_id}`",
            read_only=True)
        try:
            param = node.declare_parameter(prefix + name, _policy_value(qos, policy), descriptor)
        except ParameterAlreadyDeclaredException:
            param = node.get_parameter(prefix + name)
        _set_policy(qos, policy, param.value)
    if options.callback is not None:
        result = options.callback(qos)
        if not result.successful:
            raise InvalidQosOverridesError(
                f"Provided QoS overrides for {kind} `{topic}` with id `{options.entity_id}`, "
                f"are not valid: {result.reason}")
