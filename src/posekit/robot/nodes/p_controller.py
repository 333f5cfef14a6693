"""``p_controller``: the course's go-to-pose P controller (robot_control_demo) as a node.

Subscribes ``odometry/filtered`` (nav_msgs/Odometry) and, optionally, ``goal_pose``
(geometry_msgs/PoseStamped in ``odom``; a new goal replaces the current one). A 20 Hz timer
runs :class:`~posekit.robot.p_controller.PController` on the latest filtered pose and
publishes ``cmd_vel`` (geometry_msgs/TwistStamped, stamped now, frame ``base_link``). When
both tolerances are met it publishes a zero twist and ``goal_reached`` (std_msgs/Bool True,
once per goal) and logs ``Goal reached: x=.., y=.., yaw=..`` with the final filtered pose;
afterwards it keeps commanding zero until a new goal arrives. A goal of (0, 0, 0), the node
default, means "no goal": nothing is published.

Parameters (course names and node defaults): ``k_rho`` (0.4), ``k_alpha`` (0.8), ``k_yaw``
(0.8), ``goal_tolerance`` (0.10 m), ``yaw_tolerance`` (0.05 rad), ``goal_x``, ``goal_y``,
``goal_yaw`` (0.0; the course's launch file sets 5.0, 5.0, pi/2). Velocity clamps are the
course's fixed ±0.5 m/s and ±1.0 rad/s.

Action ``navigate_to_pose`` (``posekit_interfaces/action/NavigateToPose``; on transports with
services, which posekit's are): a goal pose in
``odom`` (or with an empty frame) becomes the controller's goal; every tick publishes feedback
with the remaining distance ``rho`` (m); the goal succeeds when both tolerances are met, with
the final distance as result. A cancel request stops the robot (one zero twist, then the
controller idles) and ends the goal as canceled; a newer goal (action, ``goal_pose`` or goal
parameters) aborts the running one. Goals in other frames or with non-finite values are
rejected.

Every parameter is live, as the lecture's tip needs ("increase ``k_rho`` to 1.0 ..."):
``posekit param set /p_controller k_rho 1.0`` (or ``ros2 param set``) changes the gains and
tolerances from the next tick on; a new ``goal_x``/``goal_y``/``goal_yaw`` replaces the goal as
a ``goal_pose`` would. Non-finite values and negative tolerances are refused with the reason.
"""

from __future__ import annotations

import dataclasses
import math
from typing import Any

from posekit.geometry import wrap_angle
from posekit.msgs.geometry_msgs import PoseStamped, Twist, TwistStamped, Vector3
from posekit.msgs.nav_msgs import Odometry
from posekit.msgs.posekit_interfaces import NavigateToPose
from posekit.msgs.std_msgs import Bool, Header
from posekit.robot.kinematics import yaw_from_quaternion_xyzw
from posekit.robot.p_controller import PController, PControllerParams, Phase
from posekit.runtime.action import ActionServer, CancelResponse, GoalResponse, ServerGoalHandle
from posekit.runtime.node import Node
from posekit.runtime.parameters import Parameter, SetParametersResult, declare_value
from posekit.runtime.task import Future
from posekit.time import stamp_from_ns

__all__ = ["PControllerNode"]


def _pose_of(msg: Any) -> tuple[float, float, float]:
    p, q = msg.position, msg.orientation
    yaw = yaw_from_quaternion_xyzw(float(q.x), float(q.y), float(q.z), float(q.w))
    return float(p.x), float(p.y), yaw


#: Parameters that take effect while the node runs (PControllerParams field names).
_LIVE = frozenset(
    ("k_rho", "k_alpha", "k_yaw", "goal_tolerance", "yaw_tolerance", "goal_x", "goal_y",
     "goal_yaw")
)


class PControllerNode(Node):
    """The P-controller node (see the module docstring).

    ``controller`` is the model; ``goal_reached_ns`` the sim time (ns) of the last "Goal
    reached", else None.
    """

    def __init__(self, node_name: str = "p_controller", **kwargs: Any) -> None:
        super().__init__(node_name, **kwargs)
        d = PControllerParams()
        params = PControllerParams(
            k_rho=float(declare_value(self, "k_rho", d.k_rho)),
            k_alpha=float(declare_value(self, "k_alpha", d.k_alpha)),
            k_yaw=float(declare_value(self, "k_yaw", d.k_yaw)),
            goal_tolerance=float(declare_value(self, "goal_tolerance", d.goal_tolerance)),
            yaw_tolerance=float(declare_value(self, "yaw_tolerance", d.yaw_tolerance)),
            goal_x=float(declare_value(self, "goal_x", d.goal_x)),
            goal_y=float(declare_value(self, "goal_y", d.goal_y)),
            goal_yaw=float(declare_value(self, "goal_yaw", d.goal_yaw)),
        )
        #: The control law.
        self.controller = PController(params)
        self.goal_reached_ns: int | None = None
        self._pose: tuple[float, float, float] | None = None
        self._phase = Phase.IDLE
        self._cmd_pub = self.create_publisher(TwistStamped, "cmd_vel", 10)
        self._reached_pub = self.create_publisher(Bool, "goal_reached", 10)
        self.create_subscription(Odometry, "odometry/filtered", self._on_odom, 10)
        self.create_subscription(PoseStamped, "goal_pose", self._on_goal, 10)
        self._now_ns = self.get_clock().now_ns
        self.create_timer(1.0 / params.rate_hz, self._on_tick)
        # The running navigate_to_pose goal and the future its execute callback awaits
        # ("reached", "canceled" or "preempted"), completed by the control tick.
        self._action_goal: tuple[ServerGoalHandle, Future[Any]] | None = None
        self._last_rho = 0.0
        #: The navigate_to_pose server (None on a transport without services).
        self.navigate_action = ActionServer(
            self, NavigateToPose, "navigate_to_pose", self._execute_goal,
            goal_callback=self._check_goal,
            cancel_callback=lambda _handle: CancelResponse.ACCEPT,
        ) if self.transport.supports_services else None
        self.add_on_set_parameters_callback(self._check_params)
        self.add_post_set_parameters_callback(self._apply_params)
        goal = self.controller.goal
        if goal is None:
            self.get_logger().info("No goal set (goal (0, 0, 0)); waiting for goal_pose")
        else:
            self.get_logger().info(
                f"Goal: x={goal[0]:.2f}, y={goal[1]:.2f}, yaw={goal[2]:.2f}"
            )

    def _check_params(self, params: list[Parameter]) -> SetParametersResult:
        for p in params:
            if p.name not in _LIVE or not isinstance(p.value, float):
                continue
            if not math.isfinite(p.value):
                return SetParametersResult(successful=False, reason=f"{p.name} must be finite")
            if p.name.endswith("_tolerance") and p.value <= 0.0:
                return SetParametersResult(successful=False, reason=f"{p.name} must be > 0")
        return SetParametersResult(successful=True)

    def _apply_params(self, params: list[Parameter]) -> None:
        changes = {p.name: float(p.value) for p in params if p.name in _LIVE}
        if not changes:
            return
        old = self.controller.params
        new = dataclasses.replace(old, **changes)
        self.controller.params = new
        if (new.goal_x, new.goal_y, new.goal_yaw) != (old.goal_x, old.goal_y, old.goal_yaw):
            self.controller.set_goal(new.goal_x, new.goal_y, new.goal_yaw)
            self.goal_reached_ns = None
            self._phase = Phase.IDLE
            self._end_action_goal("preempted")
        self.get_logger().info(
            "Parameters updated: " + ", ".join(f"{k}={v:g}" for k, v in sorted(changes.items()))
        )

    # -- navigate_to_pose action -----------------------------------------------------------
    def _check_goal(self, goal: Any) -> GoalResponse:
        frame = goal.pose.header.frame_id
        x, y, yaw = _pose_of(goal.pose.pose)
        if frame not in ("", "odom") or not all(math.isfinite(v) for v in (x, y, yaw)):
            self.get_logger().warning(
                f"Rejecting navigate_to_pose goal ({x}, {y}, {yaw}) in frame '{frame}': "
                "goals must be finite and in 'odom'"
            )
            return GoalResponse.REJECT
        return GoalResponse.ACCEPT

    def _end_action_goal(self, outcome: str) -> None:
        if self._action_goal is not None:
            _, done = self._action_goal
            self._action_goal = None
            done.set_result(outcome)

    async def _execute_goal(self, goal_handle: ServerGoalHandle) -> Any:
        x, y, yaw = _pose_of(goal_handle.request.pose.pose)
        self._end_action_goal("preempted")
        # set directly: (0, 0, 0) is a real place here, not set_goal's "no goal"
        self.controller.goal = (x, y, wrap_angle(yaw))
        self.controller.goal_reached = False
        self.goal_reached_ns = None
        self._phase = Phase.IDLE
        self.get_logger().info(f"navigate_to_pose goal: x={x:.2f}, y={y:.2f}, yaw={yaw:.2f}")
        done: Future[Any] = Future()
        self._action_goal = (goal_handle, done)
        outcome = await done
        if outcome == "reached":
            goal_handle.succeed()
        elif outcome == "canceled":
            goal_handle.canceled()
        else:
            goal_handle.abort()
        return NavigateToPose.Result(distance_remaining=self._last_rho)

    def _action_tick(self, rho: float, just_reached: bool) -> bool:
        """Feedback, cancel and success of the running goal; True when it was cancelled.

        After a cancel the tick stops the robot instead of commanding.
        """
        if self._action_goal is None:
            return False
        handle, _ = self._action_goal
        self._last_rho = rho
        if handle.is_cancel_requested:
            self.controller.goal = None
            self._phase = Phase.IDLE
            self._end_action_goal("canceled")
            self.get_logger().info(f"navigate_to_pose canceled {rho:.2f} m from the goal")
            return True
        handle.publish_feedback(NavigateToPose.Feedback(distance_remaining=rho))
        if just_reached:
            self._end_action_goal("reached")
        return False

    def _on_odom(self, msg: Odometry) -> None:
        self._pose = _pose_of(msg.pose.pose)

    def _on_goal(self, msg: PoseStamped) -> None:
        frame = msg.header.frame_id
        if frame not in ("", "odom"):
            self.get_logger().warning(
                f"Ignoring goal_pose in frame '{frame}': goals must be in 'odom'"
            )
            return
        x, y, yaw = _pose_of(msg.pose)
        if not all(math.isfinite(v) for v in (x, y, yaw)):
            self.get_logger().warning(f"Ignoring non-finite goal_pose ({x}, {y}, {yaw})")
            return
        self.controller.set_goal(x, y, yaw)
        self.goal_reached_ns = None
        self._phase = Phase.IDLE
        self._end_action_goal("preempted")
        self.get_logger().info(f"New goal: x={x:.2f}, y={y:.2f}, yaw={yaw:.2f}")

    def _on_tick(self) -> None:
        if self._pose is None:
            return
        x, y, yaw = self._pose
        out = self.controller.compute(x, y, yaw)
        if self._action_tick(out.rho, out.just_reached):
            out = dataclasses.replace(out, v=0.0, omega=0.0, just_reached=False)  # stop
        elif not out.publish:
            return
        now_ns = self._now_ns()
        # Positional fields in ROS order (header, twist = (linear, angular)): fastest.
        cmd = TwistStamped(
            Header(stamp_from_ns(now_ns), "base_link"),
            Twist(Vector3(out.v, 0.0, 0.0), Vector3(0.0, 0.0, out.omega)),
        )
        self._cmd_pub.publish_transfer(cmd)  # built for this publish: no copy
        if out.phase != self._phase:
            if out.phase == Phase.ORIENTATION:
                self.get_logger().info(
                    f"Position reached (rho={out.rho:.3f} m); turning to the goal yaw"
                )
            self._phase = out.phase
        if out.just_reached:
            self.goal_reached_ns = now_ns
            self._reached_pub.publish_transfer(Bool(data=True))
            self.get_logger().info(f"Goal reached: x={x:.2f}, y={y:.2f}, yaw={yaw:.2f}")
