"""ros2cli's ``--qos-*`` options (``add_qos_arguments``) and the profile they describe."""

from __future__ import annotations

import argparse
from typing import Any

__all__ = ["add_qos_args", "qos_from_args", "qos_overridden"]

_PRESETS = ("system_default", "sensor_data", "services_default", "parameters",
            "parameter_events", "action_status_default", "best_available")
_HISTORY = ("system_default", "keep_last", "keep_all", "unknown")
_RELIABILITY = ("system_default", "reliable", "best_effort", "unknown", "best_available")
_DURABILITY = ("system_default", "transient_local", "volatile", "unknown", "best_available")
_LIVELINESS = ("system_default", "automatic", "manual_by_topic", "unknown", "best_available")


def add_qos_args(parser: argparse.ArgumentParser, verb: str, default_profile: str) -> None:
    """The options ``ros2 topic echo/pub`` take, with their names, choices and defaults.

    posekit's QoS has no liveliness policy: ``--qos-liveliness`` and
    ``--qos-liveliness-lease-duration-seconds`` are accepted (scripts written for ros2 run
    unchanged) and do not change the endpoint.
    """
    parser.add_argument("--qos-profile", choices=_PRESETS, default=default_profile,
                        help=f"Quality of service preset profile to {verb} with "
                             f"(default: {default_profile})")
    parser.add_argument("--qos-depth", metavar="N", type=int,
                        help=f"Queue size setting to {verb} with (overrides depth value of "
                             "--qos-profile option)")
    parser.add_argument("--qos-history", choices=_HISTORY,
                        help=f"History of samples setting to {verb} with (overrides history "
                             "value of --qos-profile option, default: keep_last)")
    parser.add_argument("--qos-reliability", choices=_RELIABILITY,
                        help=f"Quality of service reliability setting to {verb} with "
                             "(overrides reliability value of --qos-profile option, default: "
                             "Compatible profile with running endpoints )")
    parser.add_argument("--qos-durability", choices=_DURABILITY,
                        help=f"Quality of service durability setting to {verb} with "
                             "(overrides durability value of --qos-profile option, default: "
                             "Compatible profile with running endpoints )")
    parser.add_argument("--qos-liveliness", choices=_LIVELINESS,
                        help=f"Quality of service liveliness setting to {verb} with "
                             "(accepted; posekit endpoints have no liveliness policy)")
    parser.add_argument("--qos-liveliness-lease-duration-seconds", type=float,
                        help=f"Quality of service liveliness lease duration setting to {verb} "
                             "with (accepted; posekit endpoints have no liveliness policy)")


def qos_overridden(ns: argparse.Namespace) -> bool:
    """True when any ``--qos-*`` policy option was given (ros2 then uses exactly that)."""
    return any(getattr(ns, name) is not None for name in (
        "qos_depth", "qos_history", "qos_reliability", "qos_durability", "qos_liveliness",
        "qos_liveliness_lease_duration_seconds"))


def qos_from_args(ns: argparse.Namespace) -> Any:
    """The preset ``--qos-profile`` with the given ``--qos-*`` overrides applied."""
    from posekit.cli.errors import CliError
    from posekit.runtime import qos as q

    profile = q.QoSPresetProfiles.get_from_short_key(ns.qos_profile)
    changes: dict[str, Any] = {}
    if ns.qos_history is not None:
        changes["history"] = q.HistoryPolicy[ns.qos_history.upper()]
    if ns.qos_reliability is not None:
        changes["reliability"] = q.ReliabilityPolicy[ns.qos_reliability.upper()]
    if ns.qos_durability is not None:
        changes["durability"] = q.DurabilityPolicy[ns.qos_durability.upper()]
    if ns.qos_depth is not None:
        if ns.qos_depth < 0:
            raise CliError(f"--qos-depth must be >= 0, got {ns.qos_depth}", 2)
        changes["depth"] = ns.qos_depth
    try:
        return profile.with_(**changes)
    except (TypeError, ValueError) as exc:
        raise CliError(str(exc), 2) from None
