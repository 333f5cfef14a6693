# /rosout: what a node's logger publishes (records logged before the subscription existed
# arrive through TRANSIENT_LOCAL; child and by-name loggers publish too; DEBUG does not).
import os
import time

from rcl_interfaces.msg import Log
from rclpy.node import Node
from rclpy.qos import DurabilityPolicy, QoSProfile

import rclpy

rclpy.init()
talker = Node("talker", namespace="/ns")
listener = Node("listener")
got = []
talker.get_logger().info("before subscribing")
talker.get_logger().debug("below the level")
qos = QoSProfile(depth=100, durability=DurabilityPolicy.TRANSIENT_LOCAL)
listener.create_subscription(Log, "/rosout", got.append, qos)


def emit():
    talker.get_logger().warning(f"warn {1}")
    talker.get_logger().get_child("kid").error("child")
    rclpy.logging.get_logger("ns.talker").fatal("by name")
    rclpy.logging.get_logger("other").info("no node has this name")


emit()


def mine():
    return [m for m in got if m.name.startswith(("ns.talker", "other"))]


deadline = time.monotonic() + 10
while len(mine()) < 4 and time.monotonic() < deadline:
    rclpy.spin_once(listener, timeout_sec=0.1)
for i, m in enumerate(mine()):
    show(f"record {i}", lambda m=m: (m.level, m.name, m.msg, os.path.basename(m.file), m.function,
                                     m.line))
show("records", lambda: len(mine()))
show("fields", Log.get_fields_and_field_types)
show("levels", lambda: (Log.DEBUG, Log.INFO, Log.WARN, Log.ERROR, Log.FATAL))
