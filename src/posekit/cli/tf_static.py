"""``posekit tf static ...``: static_transform_publisher with tf2_ros's arguments and messages."""

from __future__ import annotations

import random
import string
import sys
from collections.abc import Sequence
from typing import Any, TextIO

from posekit.cli.static_args import USAGE, StaticArgsError, parse_static_args

__all__ = ["main", "make_transform"]


def make_transform(argv: Sequence[str]) -> Any:
    """The TransformStamped the tool would publish (stamp left at zero), or StaticArgsError."""
    from posekit.msgs.geometry_msgs import TransformStamped
    from posekit.tf2 import quat_from_rpy

    args = parse_static_args(list(argv))
    t = TransformStamped()
    t.header.frame_id = args.frame_id
    t.child_frame_id = args.child_frame_id
    t.transform.translation.x, t.transform.translation.y, t.transform.translation.z = (
        args.translation
    )
    # Quaternions from flags are passed on un-normalised, as tf2_ros does; receivers normalise.
    q = args.quaternion_xyzw if args.rpy is None else quat_from_rpy(*args.rpy)
    assert q is not None
    rot = t.transform.rotation
    rot.x, rot.y, rot.z, rot.w = q
    return t


def main(argv: Sequence[str], *, context: Any = None, out: TextIO | None = None,
         spin_seconds: float | None = None) -> int:
    """Publish one latched transform and spin (until Ctrl-C, or ``spin_seconds`` for tests)."""
    out = out or sys.stdout
    transport = None
    argv = list(argv)
    if "--zenoh" in argv:
        argv.remove("--zenoh")
        transport = "zenoh"
    if "--transport" in argv:
        at = argv.index("--transport")
        transport = argv[at + 1] if at + 1 < len(argv) else None
        del argv[at:at + 2]
    try:
        parsed = parse_static_args(argv)
    except StaticArgsError as exc:
        sys.stderr.write(f"[ERROR] [static_transform_publisher]: error parsing command line "
                         f"arguments: {exc}\n")
        out.write(USAGE)
        return 1
    if parsed.show_help:
        out.write(USAGE)
        return 0
    if parsed.old_style:
        sys.stderr.write("[WARN] [static_transform_publisher]: Old-style arguments are deprecated;"
                         " see --help for new-style arguments\n")
    if parsed.frame_id == parsed.child_frame_id:
        sys.stderr.write(f"[ERROR] [static_transform_publisher]: cannot publish static transform "
                         f"from '{parsed.frame_id}' to '{parsed.frame_id}', exiting\n")
        return 1
    t = make_transform(argv)

    from posekit.cli._session import ToolSession
    from posekit.tf2_ros import StaticTransformBroadcaster

    suffix = "".join(random.choices(string.ascii_letters + string.digits, k=16))
    tr, rot = t.transform.translation, t.transform.rotation
    overrides = {
        "translation.x": tr.x, "translation.y": tr.y, "translation.z": tr.z,
        "rotation.x": rot.x, "rotation.y": rot.y, "rotation.z": rot.z, "rotation.w": rot.w,
        "frame_id": t.header.frame_id, "child_frame_id": t.child_frame_id,
    }
    with ToolSession(f"static_transform_publisher_{suffix}", context=context,
                     transport=transport) as session:
        for name, value in overrides.items():
            session.node.declare_parameter(name, value)
        t.header.stamp = session.node.get_clock().now().to_msg()
        StaticTransformBroadcaster(session.node).sendTransform(t)
        session.node.get_logger().info(
            "Spinning until stopped - publishing transform\n"
            f"translation: ('{tr.x:f}', '{tr.y:f}', '{tr.z:f}')\n"
            f"rotation: ('{rot.x:f}', '{rot.y:f}', '{rot.z:f}', '{rot.w:f}')\n"
            f"from '{t.header.frame_id}' to '{t.child_frame_id}'"
        )
        try:
            if spin_seconds is None:
                while session.context.ok():
                    session.spin_for(1.0)
            else:
                session.spin_for(spin_seconds)
        except KeyboardInterrupt:
            pass
    return 0
