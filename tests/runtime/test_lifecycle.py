"""Lifecycle nodes where posekit goes beyond rclpy, which the differential script cannot show.

tests/rclpy/differential/lifecycle.py compares the state machine, services, events and the
lifecycle publisher with the real rclpy. Here (oracle: rcl_lifecycle's transition table,
written out in the test): a callback returning something that is no result, the publisher's
``publish_transfer``, and the node's transitions by the services from another thread.
"""

from __future__ import annotations

import threading

from posekit.msgs.lifecycle_msgs import ChangeState, GetState, Transition
from posekit.msgs.std_msgs import String
from posekit.runtime.executors import SingleThreadedExecutor
from posekit.runtime.lifecycle import (
    TRANSITIONS,
    LifecycleNode,
    LifecycleState,
    TransitionCallbackReturn,
)
from posekit.runtime.logging import LogRecord, add_sink, remove_sink
from posekit.runtime.node import Node


def test_a_callback_returning_no_result_is_an_error_and_logged(ctx) -> None:
    class Sloppy(LifecycleNode):
        def on_configure(self, state: LifecycleState):  # type: ignore[override]
            return None

    node = Sloppy("sloppy", context=ctx)
    lines: list[LogRecord] = []
    add_sink(lines.append)
    try:
        assert node.trigger_configure() == TransitionCallbackReturn.ERROR
    finally:
        remove_sink(lines.append)
    assert node._state_id == 1  # errorprocessing's on_error succeeded: unconfigured again
    assert any("on_configure() returned None" in r.message for r in lines)


def test_publish_transfer_is_managed_too(ctx) -> None:
    node = LifecycleNode("talker", context=ctx)
    pub = node.create_lifecycle_publisher(String, "chatter", 10)
    heard: list[str] = []
    listener = Node("listener", context=ctx)
    listener.create_subscription(String, "chatter", lambda m: heard.append(m.data), 10)
    executor = SingleThreadedExecutor(context=ctx)
    executor.add_node(listener)
    pub.publish_transfer(String(data="inactive"))
    node.trigger_configure()
    node.trigger_activate()
    pub.publish_transfer(String(data="active"))
    executor.spin_once(timeout_sec=1.0)
    assert heard == ["active"]


def test_the_services_drive_the_node_from_another_thread(ctx) -> None:
    node = LifecycleNode("managed", context=ctx)
    caller = Node("caller", context=ctx)
    server = SingleThreadedExecutor(context=ctx)
    server.add_node(node)
    spinner = threading.Thread(target=server.spin, daemon=True)
    spinner.start()
    try:
        change = caller.create_client(ChangeState, "/managed/change_state")
        get = caller.create_client(GetState, "/managed/get_state")
        assert change.call(ChangeState.Request(Transition(label="configure")),
                           timeout_sec=5.0).success
        assert change.call(ChangeState.Request(Transition(id=Transition.TRANSITION_ACTIVATE)),
                           timeout_sec=5.0).success
        # a transition the state does not have: refused, the state kept
        assert not change.call(ChangeState.Request(Transition(id=Transition.TRANSITION_CONFIGURE)),
                               timeout_sec=5.0).success
        state = get.call(GetState.Request(), timeout_sec=5.0).current_state
        assert (state.id, state.label) == (3, "active")
    finally:
        server.shutdown()
        spinner.join(timeout=5.0)


def test_every_primary_state_has_a_shutdown_and_transition_states_all_three_results() -> None:
    primary = {1, 2, 3}
    assert {start for _, label, start, _ in TRANSITIONS if label == "shutdown"} == primary
    for state in range(10, 16):
        results = sorted(label for _, label, start, _ in TRANSITIONS if start == state)
        assert results == ["transition_error", "transition_failure", "transition_success"]
