"""ROS 2 actions: ``ActionServer`` and ``ActionClient`` (rclpy.action's API).

An action ``<name>`` is carried, as in ROS 2, by three services and two topics of the node's
transport (so it works on every transport that has services; names resolve like any other):

* ``<name>/_action/send_goal`` (``Action.Impl.SendGoalService``): goal id + goal ->
  accepted + stamp;
* ``<name>/_action/cancel_goal`` (``action_msgs/srv/CancelGoal``);
* ``<name>/_action/get_result`` (``Action.Impl.GetResultService``): answered when the goal
  reaches a terminal state (STATUS_SUCCEEDED / CANCELED / ABORTED), or at once with
  STATUS_UNKNOWN for an unknown goal id;
* ``<name>/_action/feedback`` (``Action.Impl.FeedbackMessage``, KEEP_LAST 10);
* ``<name>/_action/status`` (``action_msgs/msg/GoalStatusArray``, KEEP_LAST 1, RELIABLE,
  TRANSIENT_LOCAL: rclpy's ``qos_profile_action_status_default``).

Server: ``ActionServer(node, Action, "name", execute_callback, goal_callback=...,
handle_accepted_callback=..., cancel_callback=...)``. A goal request calls
``goal_callback(goal)`` (default: accept) -> :class:`GoalResponse`; the response is sent,
then ``handle_accepted_callback(goal_handle)`` (default: ``goal_handle.execute()``) runs;
``execute()`` schedules ``execute_callback(goal_handle)`` as a task of the node's executor
(a coroutine function may ``await`` futures, which keeps a single-threaded or simulated-time
executor free while the goal runs). It must end the goal with ``succeed()``, ``abort()`` or
``canceled()`` and return a ``Result``; a goal left active is aborted with a warning, as
rclpy does. ``cancel_callback(goal_handle)`` (default: reject) -> :class:`CancelResponse`;
an accepted cancel moves the goal to CANCELING and sets ``is_cancel_requested``; the
execute callback then decides (``canceled()``). Terminal goals are forgotten
``result_timeout`` seconds (node clock) after they ended.

Client: ``ActionClient(node, Action, "name")``; ``wait_for_server``,
``send_goal_async(goal, feedback_callback=None)`` -> Future of a :class:`ClientGoalHandle`
(``accepted``, ``get_result_async()`` -> Future of the ``GetResult`` response with
``status`` and ``result``, ``cancel_goal_async()``); ``feedback_callback`` receives the
``FeedbackMessage`` (``msg.feedback``). The blocking ``send_goal`` / ``get_result`` /
``cancel_goal`` need the node spun in another thread, as in rclpy.

Every callback runs on the node's executor, so under ``SimulatedTimeExecutor`` a whole goal
(request, feedback, cancel, result) happens in reproducible order.
"""

from __future__ import annotations

import enum
import inspect
import threading
import traceback
import uuid
from collections.abc import Callable
from typing import TYPE_CHECKING, Any

import numpy as np

from posekit.msgs.action_msgs import CancelGoal, GoalInfo, GoalStatus, GoalStatusArray
from posekit.msgs.unique_identifier_msgs import UUID
from posekit.runtime.qos import (
    QoSProfile,
    qos_profile_action_status_default,
    qos_profile_services_default,
)
from posekit.runtime.task import Future
from posekit.time import stamp_to_ns

if TYPE_CHECKING:
    from posekit.runtime.callback_groups import CallbackGroup
    from posekit.runtime.node import Node

__all__ = [
    "ActionClient",
    "ActionServer",
    "CancelResponse",
    "ClientGoalHandle",
    "GoalResponse",
    "InvalidGoalTransitionError",
    "ServerGoalHandle",
    "action_topic_names",
    "default_cancel_callback",
    "default_goal_callback",
    "default_handle_accepted_callback",
    "get_action_client_names_and_types_by_node",
    "get_action_names_and_types",
    "get_action_server_names_and_types_by_node",
    "qos_profile_action_status_default",
]

_FEEDBACK_QOS = QoSProfile(depth=10)

_TERMINAL = (GoalStatus.STATUS_SUCCEEDED, GoalStatus.STATUS_CANCELED, GoalStatus.STATUS_ABORTED)
_STATUS_NAMES = {
    GoalStatus.STATUS_UNKNOWN: "UNKNOWN", GoalStatus.STATUS_ACCEPTED: "ACCEPTED",
    GoalStatus.STATUS_EXECUTING: "EXECUTING", GoalStatus.STATUS_CANCELING: "CANCELING",
    GoalStatus.STATUS_SUCCEEDED: "SUCCEEDED", GoalStatus.STATUS_CANCELED: "CANCELED",
    GoalStatus.STATUS_ABORTED: "ABORTED",
}


def action_topic_names(action_name: str) -> dict[str, str]:
    """The service and topic names under ``<action_name>/_action/``, by role."""
    base = action_name.rstrip("/") + "/_action/"
    return {role: base + role for role in
            ("send_goal", "cancel_goal", "get_result", "feedback", "status")}


class GoalResponse(enum.Enum):
    """What ``goal_callback`` returns (rclpy.action.server.GoalResponse)."""

    REJECT = 1
    ACCEPT = 2


class CancelResponse(enum.Enum):
    """What ``cancel_callback`` returns (rclpy.action.server.CancelResponse)."""

    REJECT = 1
    ACCEPT = 2


class InvalidGoalTransitionError(RuntimeError):
    """A goal handle was asked for a state change its current state does not allow."""


class _Event(enum.Enum):
    EXECUTE = "execute"
    CANCEL_GOAL = "cancel_goal"
    SUCCEED = "succeed"
    ABORT = "abort"
    CANCELED = "canceled"


# rcl_action's goal state machine: (state, event) -> new state.
_TRANSITIONS = {
    (GoalStatus.STATUS_ACCEPTED, _Event.EXECUTE): GoalStatus.STATUS_EXECUTING,
    (GoalStatus.STATUS_ACCEPTED, _Event.CANCEL_GOAL): GoalStatus.STATUS_CANCELING,
    (GoalStatus.STATUS_EXECUTING, _Event.CANCEL_GOAL): GoalStatus.STATUS_CANCELING,
    (GoalStatus.STATUS_EXECUTING, _Event.SUCCEED): GoalStatus.STATUS_SUCCEEDED,
    (GoalStatus.STATUS_EXECUTING, _Event.ABORT): GoalStatus.STATUS_ABORTED,
    (GoalStatus.STATUS_CANCELING, _Event.SUCCEED): GoalStatus.STATUS_SUCCEEDED,
    (GoalStatus.STATUS_CANCELING, _Event.ABORT): GoalStatus.STATUS_ABORTED,
    (GoalStatus.STATUS_CANCELING, _Event.CANCELED): GoalStatus.STATUS_CANCELED,
}


def _uuid_key(goal_id: Any) -> bytes:
    return bytes(bytearray(int(v) for v in goal_id.uuid))


def _uuid_hex(goal_id: Any) -> str:
    return _uuid_key(goal_id).hex()


async def _await_or_call(callback: Callable[..., Any], *args: Any) -> Any:
    result = callback(*args)
    if inspect.isawaitable(result):
        result = await result
    return result


def default_goal_callback(goal_request: Any) -> GoalResponse:
    """Accept every goal."""
    del goal_request
    return GoalResponse.ACCEPT


def default_handle_accepted_callback(goal_handle: ServerGoalHandle) -> None:
    """Start executing the goal at once."""
    goal_handle.execute()


def default_cancel_callback(cancel_request: Any) -> CancelResponse:
    """Reject every cancel request (rclpy's default)."""
    del cancel_request
    return CancelResponse.REJECT


class ServerGoalHandle:
    """The server's side of one goal (rclpy.action.server.ServerGoalHandle)."""

    def __init__(self, server: ActionServer, goal_info: GoalInfo, goal_request: Any) -> None:
        self._server = server
        self._goal_info = goal_info
        self._goal_request = goal_request
        self._status = GoalStatus.STATUS_ACCEPTED
        self._cancel_requested = False
        self._lock = threading.Lock()
        self._ended_ns: int | None = None

    @property
    def request(self) -> Any:
        """The goal message."""
        return self._goal_request

    @property
    def goal_id(self) -> UUID:
        """The goal's UUID."""
        return self._goal_info.goal_id

    @property
    def is_active(self) -> bool:
        """Not yet in a terminal state."""
        return self._status not in _TERMINAL

    @property
    def is_cancel_requested(self) -> bool:
        """A cancel request was accepted (the goal is CANCELING)."""
        return self._status == GoalStatus.STATUS_CANCELING

    @property
    def status(self) -> int:
        """The action_msgs/GoalStatus STATUS_* value."""
        return self._status

    def _update_state(self, event: _Event) -> None:
        with self._lock:
            new = _TRANSITIONS.get((self._status, event))
            if new is None:
                raise InvalidGoalTransitionError(
                    f"goal {_uuid_hex(self.goal_id)} cannot '{event.value}' in state "
                    f"{_STATUS_NAMES.get(self._status, self._status)}"
                )
            self._status = new
        if new in _TERMINAL:
            self._ended_ns = self._server._node.get_clock().now().nanoseconds
        self._server._publish_status()

    def execute(self, execute_callback: Callable[[ServerGoalHandle], Any] | None = None) -> None:
        """Move to EXECUTING and run ``execute_callback`` (default: the server's) as a task."""
        self._update_state(_Event.EXECUTE)
        self._server._start(self, execute_callback or self._server._execute_callback)

    def publish_feedback(self, feedback: Any) -> None:
        """Publish ``feedback`` (an ``Action.Feedback``) for this goal."""
        message = self._server._action_type.Impl.FeedbackMessage()
        message.goal_id = self.goal_id
        message.feedback = feedback
        self._server._feedback_pub.publish(message)

    def succeed(self) -> None:
        """End the goal as SUCCEEDED (from EXECUTING or CANCELING)."""
        self._update_state(_Event.SUCCEED)

    def abort(self) -> None:
        """End the goal as ABORTED (from EXECUTING or CANCELING)."""
        self._update_state(_Event.ABORT)

    def canceled(self) -> None:
        """End the goal as CANCELED (only after an accepted cancel request)."""
        self._update_state(_Event.CANCELED)

    def destroy(self) -> None:
        """Kept for rclpy compatibility; the server forgets goals itself."""

    def __repr__(self) -> str:
        return (f"ServerGoalHandle(goal_id={_uuid_hex(self.goal_id)}, "
                f"status={_STATUS_NAMES.get(self._status, self._status)})")


class ActionServer:
    """Serves one action on a node (rclpy.action.ActionServer); see the module docstring."""

    def __init__(
        self,
        node: Node,
        action_type: Any,
        action_name: str,
        execute_callback: Callable[[ServerGoalHandle], Any],
        *,
        callback_group: CallbackGroup | None = None,
        goal_callback: Callable[[Any], Any] = default_goal_callback,
        handle_accepted_callback: Callable[[ServerGoalHandle], Any] = (
            default_handle_accepted_callback),
        cancel_callback: Callable[[ServerGoalHandle], Any] = default_cancel_callback,
        goal_service_qos_profile: QoSProfile = qos_profile_services_default,
        result_service_qos_profile: QoSProfile = qos_profile_services_default,
        cancel_service_qos_profile: QoSProfile = qos_profile_services_default,
        feedback_pub_qos_profile: QoSProfile = _FEEDBACK_QOS,
        status_pub_qos_profile: QoSProfile = qos_profile_action_status_default,
        result_timeout: float = 900,
    ) -> None:
        self._node = node
        self._action_type = action_type
        self._action_name = action_name
        self._execute_callback = execute_callback
        self._goal_callback = goal_callback
        self._handle_accepted_callback = handle_accepted_callback
        self._cancel_callback = cancel_callback
        self._result_timeout_ns = round(result_timeout * 1e9)
        self._lock = threading.RLock()
        self._goals: dict[bytes, ServerGoalHandle] = {}
        self._results: dict[bytes, Future[Any]] = {}
        impl = action_type.Impl
        names = action_topic_names(action_name)
        group = callback_group or node.default_callback_group
        self._services = [
            node.create_service(impl.SendGoalService, names["send_goal"], self._on_send_goal,
                                qos_profile=goal_service_qos_profile, callback_group=group),
            node.create_service(impl.CancelGoalService, names["cancel_goal"], self._on_cancel,
                                qos_profile=cancel_service_qos_profile, callback_group=group),
            node.create_service(impl.GetResultService, names["get_result"],
                                self._on_get_result, qos_profile=result_service_qos_profile,
                                callback_group=group),
        ]
        self._feedback_pub = node.create_publisher(
            impl.FeedbackMessage, names["feedback"], feedback_pub_qos_profile)
        self._status_pub = node.create_publisher(
            impl.GoalStatusMessage, names["status"], status_pub_qos_profile)
        self._destroyed = False

    @property
    def action_name(self) -> str:
        """The name given at construction."""
        return self._action_name

    # -- requests -----------------------------------------------------------------------
    async def _on_send_goal(self, request: Any, response: Any) -> Any:
        self._forget_expired()
        key = _uuid_key(request.goal_id)
        accepted = False
        with self._lock:
            known = key in self._goals
        if not known:
            decision = await _await_or_call(self._goal_callback, request.goal)
            if isinstance(decision, GoalResponse):
                accepted = decision == GoalResponse.ACCEPT
            else:
                self._node.get_logger().warning(
                    "Goal request callback did not return a GoalResponse type. Rejecting goal."
                )
        response.accepted = accepted
        if not accepted:
            return response
        goal_info = GoalInfo(goal_id=request.goal_id,
                             stamp=self._node.get_clock().now().to_msg())
        response.stamp = goal_info.stamp
        handle = ServerGoalHandle(self, goal_info, request.goal)
        with self._lock:
            self._goals[key] = handle
            self._results[key] = Future()
        self._publish_status()
        executor = self._node.executor
        if executor is not None:  # after this response is sent, as rclpy does
            executor.create_task(_await_or_call, self._handle_accepted_callback, handle)
        return response

    async def _on_cancel(self, request: Any, response: Any) -> Any:
        wanted = request.goal_info
        key = _uuid_key(wanted.goal_id)
        stamp_ns = stamp_to_ns(wanted.stamp)
        with self._lock:
            goals = list(self._goals.items())
        candidates: list[ServerGoalHandle] = []
        code = CancelGoal.Response.ERROR_NONE
        if any(key):  # a specific goal (and, with a stamp, all accepted before it)
            chosen = dict(goals).get(key)
            if chosen is None:
                code = CancelGoal.Response.ERROR_UNKNOWN_GOAL_ID
            elif not chosen.is_active:
                code = CancelGoal.Response.ERROR_GOAL_TERMINATED
            else:
                candidates.append(chosen)
        if code == CancelGoal.Response.ERROR_NONE and (not any(key) or stamp_ns):
            for other_key, handle in goals:
                info = handle._goal_info
                accepted_ns = stamp_to_ns(info.stamp)
                if other_key != key and handle.is_active and (
                    (stamp_ns == 0 and not any(key)) or accepted_ns <= stamp_ns
                ):
                    candidates.append(handle)
        canceling: list[GoalInfo] = []
        for handle in candidates:
            if handle.status == GoalStatus.STATUS_CANCELING:
                canceling.append(handle._goal_info)
                continue
            decision = await _await_or_call(self._cancel_callback, handle)
            if decision == CancelResponse.ACCEPT and handle.is_active:
                handle._update_state(_Event.CANCEL_GOAL)
                canceling.append(handle._goal_info)
        if code == CancelGoal.Response.ERROR_NONE and not canceling:
            code = CancelGoal.Response.ERROR_REJECTED
        response.return_code = code
        response.goals_canceling = canceling
        return response

    async def _on_get_result(self, request: Any, response: Any) -> Any:
        key = _uuid_key(request.goal_id)
        with self._lock:
            future = self._results.get(key)
        if future is None:
            response.status = GoalStatus.STATUS_UNKNOWN
            return response
        return await future

    # -- goals --------------------------------------------------------------------------
    def _start(self, handle: ServerGoalHandle, callback: Callable[[ServerGoalHandle], Any]
               ) -> None:
        executor = self._node.executor
        if executor is None:
            raise RuntimeError("an action server's node must be added to an executor")
        executor.create_task(self._run_goal, handle, callback)

    async def _run_goal(self, handle: ServerGoalHandle,
                        callback: Callable[[ServerGoalHandle], Any]) -> None:
        logger = self._node.get_logger()
        try:
            result = await _await_or_call(callback, handle)
        except Exception:
            logger.error("Error raised in execute callback:\n" + traceback.format_exc().rstrip())
            result = None
        if result is None or not isinstance(result, self._action_type.Result):
            if result is not None:
                logger.error(f"execute callback returned {type(result).__name__}, expected "
                             f"{self._action_type.Result.__name__}")
            result = self._action_type.Result()
        if handle.is_active:
            logger.warning(
                f"Goal state not set, assuming aborted. Goal ID: {_uuid_hex(handle.goal_id)}")
            if handle.status == GoalStatus.STATUS_ACCEPTED:
                handle._update_state(_Event.EXECUTE)
            handle._update_state(_Event.ABORT)
        response = self._action_type.Impl.GetResultService.Response()
        response.status = handle.status
        response.result = result
        with self._lock:
            future = self._results.get(_uuid_key(handle.goal_id))
        if future is not None and not future.done():
            future.set_result(response)

    def _forget_expired(self) -> None:
        now = self._node.get_clock().now().nanoseconds
        with self._lock:
            for key, handle in list(self._goals.items()):
                ended = handle._ended_ns
                if ended is not None and now - ended >= self._result_timeout_ns:
                    results = self._results.get(key)
                    if results is None or results.done():
                        del self._goals[key]
                        self._results.pop(key, None)

    def _publish_status(self) -> None:
        if self._destroyed:
            return
        with self._lock:
            handles = list(self._goals.values())
        self._status_pub.publish(GoalStatusArray(status_list=[
            GoalStatus(goal_info=h._goal_info, status=h.status) for h in handles
        ]))

    def destroy(self) -> None:
        """Remove the action's services and publishers from the node."""
        if self._destroyed:
            return
        self._destroyed = True
        for service in self._services:
            self._node.destroy_service(service)
        self._node.destroy_publisher(self._feedback_pub)
        self._node.destroy_publisher(self._status_pub)


class ClientGoalHandle:
    """The client's side of one goal (rclpy.action.client.ClientGoalHandle)."""

    def __init__(self, client: ActionClient, goal_id: UUID, goal_response: Any) -> None:
        self._client = client
        self._goal_id = goal_id
        self._goal_response = goal_response
        self._status = GoalStatus.STATUS_UNKNOWN

    @property
    def goal_id(self) -> UUID:
        """The goal's UUID."""
        return self._goal_id

    @property
    def stamp(self) -> Any:
        """When the server accepted the goal (builtin_interfaces/Time)."""
        return self._goal_response.stamp

    @property
    def accepted(self) -> bool:
        """Whether the server accepted the goal."""
        return bool(self._goal_response.accepted)

    @property
    def status(self) -> int:
        """The last known action_msgs/GoalStatus STATUS_* value."""
        return self._status

    def cancel_goal_async(self) -> Future[Any]:
        """Ask the server to cancel; the Future completes with the CancelGoal response."""
        return self._client._cancel_goal_async(self)

    def get_result_async(self) -> Future[Any]:
        """The Future of the GetResult response (``.status``, ``.result``)."""
        return self._client._get_result_async(self)

    def cancel_goal(self) -> Any:
        """Blocking cancel_goal_async (the node must be spun in another thread)."""
        future = self.cancel_goal_async()
        future.wait()
        return future.result()

    def get_result(self) -> Any:
        """Blocking get_result_async (the node must be spun in another thread)."""
        future = self.get_result_async()
        future.wait()
        return future.result()

    def __repr__(self) -> str:
        return (f"ClientGoalHandle(goal_id={_uuid_hex(self._goal_id)}, "
                f"accepted={self.accepted}, status={_STATUS_NAMES.get(self._status)})")


class ActionClient:
    """Sends goals to one action (rclpy.action.ActionClient); see the module docstring."""

    def __init__(
        self,
        node: Node,
        action_type: Any,
        action_name: str,
        *,
        callback_group: CallbackGroup | None = None,
        goal_service_qos_profile: QoSProfile = qos_profile_services_default,
        result_service_qos_profile: QoSProfile = qos_profile_services_default,
        cancel_service_qos_profile: QoSProfile = qos_profile_services_default,
        feedback_sub_qos_profile: QoSProfile = _FEEDBACK_QOS,
        status_sub_qos_profile: QoSProfile = qos_profile_action_status_default,
    ) -> None:
        self._node = node
        self._action_type = action_type
        self._action_name = action_name
        impl = action_type.Impl
        names = action_topic_names(action_name)
        group = callback_group or node.default_callback_group
        self._lock = threading.Lock()
        self._handles: dict[bytes, ClientGoalHandle] = {}
        self._feedback_callbacks: dict[bytes, Callable[[Any], Any]] = {}
        self._send_goal = node.create_client(impl.SendGoalService, names["send_goal"],
                                             qos_profile=goal_service_qos_profile,
                                             callback_group=group)
        self._cancel = node.create_client(impl.CancelGoalService, names["cancel_goal"],
                                          qos_profile=cancel_service_qos_profile,
                                          callback_group=group)
        self._get_result = node.create_client(impl.GetResultService, names["get_result"],
                                              qos_profile=result_service_qos_profile,
                                              callback_group=group)
        self._subscriptions = [
            node.create_subscription(impl.FeedbackMessage, names["feedback"],
                                     self._on_feedback, feedback_sub_qos_profile,
                                     callback_group=group),
            node.create_subscription(impl.GoalStatusMessage, names["status"],
                                     self._on_status, status_sub_qos_profile,
                                     callback_group=group),
        ]

    @property
    def action_name(self) -> str:
        """The name given at construction."""
        return self._action_name

    def _clients(self) -> list[Any]:
        return [self._send_goal, self._cancel, self._get_result]

    def server_is_ready(self) -> bool:
        """Whether the action's three services have a server now."""
        return all(client.service_is_ready() for client in self._clients())

    def wait_for_server(self, timeout_sec: float | None = None) -> bool:
        """Wait (wall time) until the server is ready; False after ``timeout_sec``."""
        import time

        deadline = None if timeout_sec is None or timeout_sec < 0 else (
            time.monotonic() + timeout_sec)
        for client in self._clients():
            remaining = None if deadline is None else max(0.0, deadline - time.monotonic())
            if not client.wait_for_service(timeout_sec=remaining):
                return False
        return True

    def send_goal_async(self, goal: Any, feedback_callback: Callable[[Any], Any] | None = None,
                        goal_uuid: UUID | None = None) -> Future[Any]:
        """Send ``goal``; the Future completes with a :class:`ClientGoalHandle`.

        Check the handle's ``accepted``. ``feedback_callback(feedback_message)`` gets this
        goal's feedback.
        """
        if not isinstance(goal, self._action_type.Goal):
            raise TypeError(f"goal must be {self._action_type.Goal.__name__}, "
                            f"got {type(goal).__name__}")
        raw = uuid.uuid4().bytes if goal_uuid is None else _uuid_key(goal_uuid)
        goal_id = UUID(uuid=np.frombuffer(raw, dtype=np.uint8).copy())
        key = raw
        request = self._action_type.Impl.SendGoalService.Request(goal_id=goal_id, goal=goal)
        if feedback_callback is not None:
            with self._lock:
                self._feedback_callbacks[key] = feedback_callback
        result: Future[Any] = Future()

        def on_response(future: Future[Any]) -> None:
            if future.cancelled() or future.exception() is not None:
                result.set_exception(future.exception() or RuntimeError("goal request dropped"))
                return
            handle = ClientGoalHandle(self, goal_id, future.result())
            if handle.accepted:
                with self._lock:
                    self._handles[key] = handle
                    if handle.status == GoalStatus.STATUS_UNKNOWN:
                        handle._status = GoalStatus.STATUS_ACCEPTED
            else:
                with self._lock:
                    self._feedback_callbacks.pop(key, None)
            result.set_result(handle)

        self._send_goal.call_async(request).add_done_callback(on_response)
        return result

    def send_goal(self, goal: Any, **kwargs: Any) -> Any:
        """Blocking: send ``goal`` and return the GetResult response (None if rejected).

        The node must be spun in another thread.
        """
        future = self.send_goal_async(goal, **kwargs)
        future.wait()
        handle: Any = future.result()
        if not handle.accepted:
            return None
        return handle.get_result()

    def _get_result_async(self, handle: ClientGoalHandle) -> Future[Any]:
        request = self._action_type.Impl.GetResultService.Request(goal_id=handle.goal_id)
        future = self._get_result.call_async(request)

        def done(f: Future[Any]) -> None:
            if f.exception() is None and not f.cancelled():
                response: Any = f.result()
                handle._status = response.status
                self._forget(handle)

        future.add_done_callback(done)
        return future

    def _cancel_goal_async(self, handle: ClientGoalHandle) -> Future[Any]:
        request = CancelGoal.Request(goal_info=GoalInfo(goal_id=handle.goal_id))
        return self._cancel.call_async(request)

    def _forget(self, handle: ClientGoalHandle) -> None:
        key = _uuid_key(handle.goal_id)
        with self._lock:
            self._handles.pop(key, None)
            self._feedback_callbacks.pop(key, None)

    def _on_feedback(self, message: Any) -> None:
        with self._lock:
            callback = self._feedback_callbacks.get(_uuid_key(message.goal_id))
        if callback is not None:
            callback(message)

    def _on_status(self, message: Any) -> None:
        for status in message.status_list:
            key = _uuid_key(status.goal_info.goal_id)
            with self._lock:
                handle = self._handles.get(key)
            if handle is not None:
                handle._status = status.status

    def destroy(self) -> None:
        """Remove the action's clients and subscriptions from the node."""
        for client in self._clients():
            self._node.destroy_client(client)
        for sub in self._subscriptions:
            self._node.destroy_subscription(sub)


# -- graph (rclpy.action.graph) ----------------------------------------------------------------
def _actions(found: list[tuple[str, list[str]]], name_suffix: str, type_suffix: str
             ) -> list[tuple[str, list[str]]]:
    out = []
    for name, types in found:
        if name.endswith(name_suffix):
            actions = [t[: -len(type_suffix)] for t in types if t.endswith(type_suffix)]
            if actions:
                out.append((name[: -len(name_suffix)], actions))
    return sorted(out)


def get_action_names_and_types(node: Node) -> list[tuple[str, list[str]]]:
    """Every action on the node's graph, as ``(name, [pkg/action/Type])``.

    Found as the ``<name>/_action/feedback`` topics of a ``..._FeedbackMessage`` type.
    """
    return _actions(node.get_topic_names_and_types(), "/_action/feedback", "_FeedbackMessage")


def get_action_server_names_and_types_by_node(
    node: Node, remote_node_name: str, remote_node_namespace: str
) -> list[tuple[str, list[str]]]:
    """The actions node ``remote_node_name`` serves (its ``.../_action/send_goal`` servers).

    A node not on the graph raises :class:`~posekit.runtime.node.NodeNameNonExistentError`,
    an ``RCLError`` (rclpy raises a plain ``RCLError`` there).
    """
    found = node.get_service_names_and_types_by_node(remote_node_name, remote_node_namespace)
    return _actions(found, "/_action/send_goal", "_SendGoal")


def get_action_client_names_and_types_by_node(
    node: Node, remote_node_name: str, remote_node_namespace: str
) -> list[tuple[str, list[str]]]:
    """The actions node ``remote_node_name`` has clients of."""
    found = node.get_client_names_and_types_by_node(remote_node_name, remote_node_namespace)
    return _actions(found, "/_action/send_goal", "_SendGoal")
