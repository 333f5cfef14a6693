"""ROS 2's lifecycle demo talker (``lifecycle lifecycle_talker``) as an rclpy node with the
imports pointing at posekit (each changed line says what it replaces).

A managed node ``lc_talker``: configuring creates a lifecycle publisher on
``lifecycle_chatter`` and a 1 s timer; while active it publishes ``Lifecycle HelloWorld #N``,
while inactive the timer only says that nothing is published. Drive it from other terminals
as with ROS 2 (``--transport``/``POSEKIT_TRANSPORT`` to leave the process, see
docs/distributed.md):

    POSEKIT_TRANSPORT=zenoh python examples/lifecycle_talker.py
    posekit lifecycle set /lc_talker configure     # Transitioning successful
    posekit lifecycle set /lc_talker activate
    posekit topic echo /lifecycle_chatter          # data: Lifecycle HelloWorld #3 ...
    posekit lifecycle get /lc_talker               # active [3]

Expected output of the talker (stderr)::

    [INFO] [...] [lc_talker]: on_configure() is called.
    [INFO] [...] [lc_talker]: Lifecycle publisher is currently inactive. Messages are not published.
    [INFO] [...] [lc_talker]: on_activate() is called.
    [INFO] [...] [lc_talker]: Lifecycle publisher is active. Publishing: [Lifecycle HelloWorld #3]
"""

from posekit import rclpy  # was: import rclpy
from posekit.msgs.std_msgs import String  # was: from std_msgs.msg import String
from posekit.rclpy.lifecycle import Node, State, TransitionCallbackReturn  # was: rclpy.lifecycle


class LifecycleTalker(Node):
    def __init__(self):
        super().__init__("lc_talker")
        self.count = 0
        self.pub = None
        self.timer = None

    def publish(self):
        self.count += 1
        msg = String(data=f"Lifecycle HelloWorld #{self.count}")
        if not self.pub.is_activated:
            self.get_logger().info(
                "Lifecycle publisher is currently inactive. Messages are not published.")
        else:
            self.get_logger().info(
                f"Lifecycle publisher is active. Publishing: [{msg.data}]")
        self.pub.publish(msg)  # a lifecycle publisher drops it while inactive

    def on_configure(self, state: State) -> TransitionCallbackReturn:
        self.pub = self.create_lifecycle_publisher(String, "lifecycle_chatter", 10)
        self.timer = self.create_timer(1.0, self.publish)
        self.get_logger().info("on_configure() is called.")
        return TransitionCallbackReturn.SUCCESS

    def on_activate(self, state: State) -> TransitionCallbackReturn:
        self.get_logger().info("on_activate() is called.")
        return super().on_activate(state)  # activates the lifecycle publisher

    def on_deactivate(self, state: State) -> TransitionCallbackReturn:
        self.get_logger().info("on_deactivate() is called.")
        return super().on_deactivate(state)

    def on_cleanup(self, state: State) -> TransitionCallbackReturn:
        self.destroy_timer(self.timer)
        self.destroy_lifecycle_publisher(self.pub)
        self.get_logger().info("on_cleanup() is called.")
        return TransitionCallbackReturn.SUCCESS

    def on_shutdown(self, state: State) -> TransitionCallbackReturn:
        self.get_logger().info(f"on_shutdown() is called from state {state.label}.")
        return TransitionCallbackReturn.SUCCESS


def main(args=None):
    rclpy.init(args=args)
    node = LifecycleTalker()
    try:
        rclpy.spin(node)
    except KeyboardInterrupt:
        pass
    finally:
        node.destroy_node()
        rclpy.try_shutdown()


if __name__ == "__main__":
    main()
