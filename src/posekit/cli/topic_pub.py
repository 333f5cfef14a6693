"""``posekit topic pub``: ``ros2 topic pub``'s arguments and output.

``pub TOPIC TYPE [VALUES] [-r R] [-1/--once] [-t TIMES] [-w N] [-p N]``: VALUES is YAML
(``"{linear: {x: 0.5}}"``), parsed with PyYAML's ``safe_load`` exactly like ``ros2 topic pub``
(YAML 1.1 scalars, flow or block style); ``header: auto`` and ``stamp: now`` fill in the
current time. Prints ``publishing #N: pkg.msg.Type(...)`` like ros2.
"""

from __future__ import annotations

import argparse
import math
import sys
import time
from collections.abc import Callable, Sequence
from typing import Any, TextIO

from posekit.cli._graph import add_transport_args, resolve_topic, session_for
from posekit.msgs.registry import message_type_name
from posekit.msgs.yaml_io import (
    MessageFieldError,
    default_message,
    message_class,
    parse_values,
    ros_repr,
    set_message_fields,
)

__all__ = ["main_pub"]


def _uses_now(values: Any) -> bool:
    """Whether parsed VALUES ask for the current time (``header: auto`` / ``stamp: now``)."""
    if isinstance(values, dict):
        return any(_uses_now(v) for v in values.values())
    if isinstance(values, list):
        return any(_uses_now(v) for v in values)
    return values in ("auto", "now")


def main_pub(argv: Sequence[str], *, context: Any = None, out: TextIO | None = None,
             err: TextIO | None = None, sleep: Callable[[float], None] | None = None) -> int:
    """``topic pub TOPIC TYPE [VALUES] [-r R] [-1] [-t N] [-w N] [-p N] [--keep-alive S]``."""
    from posekit.cli._session import add_sim_time_args
    from posekit.runtime.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy

    out = out or sys.stdout
    err = err or sys.stderr
    parser = argparse.ArgumentParser(prog="posekit topic pub")
    parser.add_argument("topic_name")
    parser.add_argument("message_type")
    parser.add_argument("values", nargs="?", default="{}")
    parser.add_argument("-r", "--rate", type=float, default=1.0,
                        help="publishing rate in Hz (default 1)")
    parser.add_argument("-p", "--print", dest="print_nth", type=int, default=1,
                        help="print every N-th published message (0: never)")
    group = parser.add_mutually_exclusive_group()
    group.add_argument("-1", "--once", action="store_true", help="publish one message and exit")
    group.add_argument("-t", "--times", type=int, default=0, help="publish N messages and exit")
    parser.add_argument("-w", "--wait-matching-subscriptions", type=int, default=None,
                        help="wait for N matching subscriptions first (default 1 with "
                             "--once/--times, else 0)")
    parser.add_argument("--keep-alive", type=float, default=0.1,
                        help="seconds to stay alive after the last message (default 0.1)")
    parser.add_argument("--qos-durability", choices=["volatile", "transient_local"],
                        default="volatile")
    parser.add_argument("--qos-reliability", choices=["reliable", "best_effort"],
                        default="reliable")
    parser.add_argument("--qos-depth", type=int, default=10)
    add_transport_args(parser)
    add_sim_time_args(parser)
    ns = parser.parse_args(list(argv))
    times = 1 if ns.once else ns.times
    if not (ns.rate > 0 and math.isfinite(ns.rate)):
        err.write(f"posekit topic pub: error: rate must be a positive finite number, got "
                  f"{ns.rate}\n")
        return 2
    try:
        msg_cls = message_class(ns.message_type)  # posekit's, else rosbags' (any Jazzy type)
        type_name = message_type_name(msg_cls)
        values = parse_values(ns.values)
        set_message_fields(default_message(type_name), values)
    except ValueError as exc:  # MessageFieldError, UnknownMessageTypeError
        err.write(f"Failed to populate field: {exc}\n" if isinstance(exc, MessageFieldError)
                  else f"{exc}\n")
        return 1
    wait_subs = ns.wait_matching_subscriptions
    if wait_subs is None:
        wait_subs = 1 if times else 0
    qos = QoSProfile(
        depth=max(1, ns.qos_depth),
        durability=(DurabilityPolicy.TRANSIENT_LOCAL if ns.qos_durability == "transient_local"
                    else DurabilityPolicy.VOLATILE),
        reliability=(ReliabilityPolicy.BEST_EFFORT if ns.qos_reliability == "best_effort"
                     else ReliabilityPolicy.RELIABLE),
    )
    with session_for(ns, context) as session:
        if ns.use_sim_time or (ns.use_sim_time is None and _uses_now(values)):
            session.follow_sim_time(ns.use_sim_time)  # header: auto stamps sim time
        now_ns = session.node.get_clock().now_ns
        topic = resolve_topic(session, ns.topic_name)
        pub = session.node.create_publisher(msg_cls, topic, qos)
        waited = 0
        while pub.get_subscription_count() < wait_subs and session.context.ok():
            if waited % 10 == 0:
                out.write(f"Waiting for at least {wait_subs} matching subscription(s)...\n")
                out.flush()
            waited += 1
            session.spin_for(0.1)
        out.write("publisher: beginning loop\n")
        count = 0
        period = 1.0 / ns.rate
        next_at = time.monotonic()
        while session.context.ok():
            # header: auto / stamp: now are re-evaluated for every message, as ros2 does
            fresh = default_message(type_name)
            set_message_fields(fresh, values, now_ns=now_ns)
            pub.publish(fresh)
            count += 1
            if ns.print_nth and count % ns.print_nth == 0:
                out.write(f"publishing #{count}: {ros_repr(fresh)}\n\n")
                out.flush()
            if times and count >= times:
                break
            next_at += period
            session.spin_for(max(0.0, next_at - time.monotonic()))
        session.spin_for(max(0.0, ns.keep_alive))
    return 0
