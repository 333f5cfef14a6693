# Node.create_rate / Rate.sleep in a multithreaded executor, and wait_for_message.
import threading
import time

from rclpy.executors import MultiThreadedExecutor
from rclpy.node import Node
from rclpy.qos import DurabilityPolicy, QoSProfile
from rclpy.wait_for_message import wait_for_message
from std_msgs.msg import String

import rclpy

rclpy.init()
node = Node("rates")
show("rate 0 Hz", lambda: node.create_rate(0))
# wait_for_message before any executor spins the node (with rclpy, an executor spinning the
# node elsewhere may take the message first; posekit's never does)
show("wait, nobody publishes", lambda: wait_for_message(String, node, "nobody",
                                                        time_to_wait=0.3))
latched = QoSProfile(depth=1, durability=DurabilityPolicy.TRANSIENT_LOCAL)
pub = node.create_publisher(String, "latched", latched)
pub.publish(String(data="kept"))
show("wait, latched", lambda: (lambda ok_msg: (ok_msg[0], ok_msg[1].data))(
    wait_for_message(String, node, "latched", qos_profile=latched, time_to_wait=10)))
show("subscriptions left", lambda: (node.count_subscribers("latched"),
                                    len(list(node.subscriptions))))
executor = MultiThreadedExecutor()
executor.add_node(node)
threading.Thread(target=executor.spin, daemon=True).start()
rate = node.create_rate(50)


def five_sleeps():
    start = time.monotonic()
    for _ in range(5):
        rate.sleep()
    return time.monotonic() - start >= 0.08  # at least four periods


show("five sleeps", five_sleeps)
show("destroy_rate", lambda: node.destroy_rate(rate))
show("sleep after destroy", rate.sleep)
slow = node.create_rate(5)
threading.Timer(0.3, rclpy.shutdown).start()


def sleep_until_shutdown():
    while True:
        slow.sleep()


show("sleep across shutdown", sleep_until_shutdown)
