"""Managed (lifecycle) nodes, as rclpy.lifecycle and rcl_lifecycle run them.

A :class:`LifecycleNode` starts ``unconfigured``. A transition (``trigger_configure()``, the
``~/change_state`` service...) moves it to a transition state (``configuring``), runs the
node's callback for that state (``on_configure(previous_state)``) and, by the callback's
:class:`TransitionCallbackReturn`, moves on: SUCCESS to the goal (``inactive``), FAILURE
back to the start, ERROR to ``errorprocessing``, where ``on_error`` decides between
``unconfigured`` (SUCCESS) and ``finalized``. A callback that raises counts as ERROR (and is
logged). The states, transitions and labels are rcl_lifecycle's (:data:`TRANSITIONS`); a
transition the current state does not have raises :class:`RCLError` after rcl's warning.

With ``enable_communication_interface`` (the default) the node serves ``~/change_state``,
``~/get_state``, ``~/get_available_states``, ``~/get_available_transitions`` and
``~/get_transition_graph`` (lifecycle_msgs) and publishes every state change on
``~/transition_event``, as Jazzy's rcl_lifecycle fills it: the start and goal states, an
empty ``transition`` and a zero ``timestamp``. A :class:`LifecyclePublisher`
(``create_lifecycle_publisher``) sends only while the node is active. The differential
script tests/rclpy/differential/lifecycle.py compares all of it with the real rclpy.
"""

from __future__ import annotations

import enum
import functools
from collections.abc import Callable
from typing import TYPE_CHECKING, Any, NamedTuple

from posekit.msgs.lifecycle_msgs import (
    ChangeState,
    ChangeState_Request,
    ChangeState_Response,
    GetAvailableStates,
    GetAvailableStates_Request,
    GetAvailableStates_Response,
    GetAvailableTransitions,
    GetAvailableTransitions_Request,
    GetAvailableTransitions_Response,
    GetState,
    GetState_Request,
    GetState_Response,
    State,
    Transition,
    TransitionDescription,
    TransitionEvent,
)
from posekit.runtime.arguments import RCLError
from posekit.runtime.entities import Publisher
from posekit.runtime.logging import get_logger
from posekit.runtime.node import Node
from posekit.runtime.qos import qos_profile_services_default

if TYPE_CHECKING:
    from posekit.runtime.callback_groups import CallbackGroup

__all__ = [
    "STATE_LABELS",
    "TRANSITIONS",
    "LifecycleNode",
    "LifecycleNodeMixin",
    "LifecyclePublisher",
    "LifecycleState",
    "ManagedEntity",
    "SimpleManagedEntity",
    "TransitionCallbackReturn",
    "TransitionCallbackReturnType",
]


class TransitionCallbackReturnType(enum.IntEnum):
    """What a transition callback returns (rclpy's values; ``to_label()`` names the next step)."""

    SUCCESS = Transition.TRANSITION_CALLBACK_SUCCESS
    FAILURE = Transition.TRANSITION_CALLBACK_FAILURE
    ERROR = Transition.TRANSITION_CALLBACK_ERROR

    def to_label(self) -> str:
        """The label of the transition this result takes: ``transition_success``..."""
        return f"transition_{self.name.lower()}"


TransitionCallbackReturn = TransitionCallbackReturnType


class LifecycleState(NamedTuple):
    """A state as a callback gets it: the state the transition started from."""

    label: str
    state_id: int


#: Every state of the machine, by id, in rcl_lifecycle's order.
STATE_LABELS: dict[int, str] = {
    State.PRIMARY_STATE_UNKNOWN: "unknown",
    State.PRIMARY_STATE_UNCONFIGURED: "unconfigured",
    State.PRIMARY_STATE_INACTIVE: "inactive",
    State.PRIMARY_STATE_ACTIVE: "active",
    State.PRIMARY_STATE_FINALIZED: "finalized",
    State.TRANSITION_STATE_CONFIGURING: "configuring",
    State.TRANSITION_STATE_CLEANINGUP: "cleaningup",
    State.TRANSITION_STATE_SHUTTINGDOWN: "shuttingdown",
    State.TRANSITION_STATE_ACTIVATING: "activating",
    State.TRANSITION_STATE_DEACTIVATING: "deactivating",
    State.TRANSITION_STATE_ERRORPROCESSING: "errorprocessing",
}


_T = Transition
#: rcl_lifecycle's transitions in its order: (id, label, start state, goal state), the
#: states by id (:data:`STATE_LABELS`). The ``transition_*`` ones leave a transition state
#: (10-15) by its callback's result.
TRANSITIONS: tuple[tuple[int, str, int, int], ...] = (
    (_T.TRANSITION_CONFIGURE, "configure", 1, 10),
    (_T.TRANSITION_ON_CONFIGURE_SUCCESS, "transition_success", 10, 2),
    (_T.TRANSITION_ON_CONFIGURE_FAILURE, "transition_failure", 10, 1),
    (_T.TRANSITION_ON_CONFIGURE_ERROR, "transition_error", 10, 15),
    (_T.TRANSITION_CLEANUP, "cleanup", 2, 11),
    (_T.TRANSITION_ON_CLEANUP_SUCCESS, "transition_success", 11, 1),
    (_T.TRANSITION_ON_CLEANUP_FAILURE, "transition_failure", 11, 2),
    (_T.TRANSITION_ON_CLEANUP_ERROR, "transition_error", 11, 15),
    (_T.TRANSITION_ACTIVATE, "activate", 2, 13),
    (_T.TRANSITION_ON_ACTIVATE_SUCCESS, "transition_success", 13, 3),
    (_T.TRANSITION_ON_ACTIVATE_FAILURE, "transition_failure", 13, 2),
    (_T.TRANSITION_ON_ACTIVATE_ERROR, "transition_error", 13, 15),
    (_T.TRANSITION_DEACTIVATE, "deactivate", 3, 14),
    (_T.TRANSITION_ON_DEACTIVATE_SUCCESS, "transition_success", 14, 2),
    (_T.TRANSITION_ON_DEACTIVATE_FAILURE, "transition_failure", 14, 3),
    (_T.TRANSITION_ON_DEACTIVATE_ERROR, "transition_error", 14, 15),
    (_T.TRANSITION_UNCONFIGURED_SHUTDOWN, "shutdown", 1, 12),
    (_T.TRANSITION_INACTIVE_SHUTDOWN, "shutdown", 2, 12),
    (_T.TRANSITION_ACTIVE_SHUTDOWN, "shutdown", 3, 12),
    (_T.TRANSITION_ON_SHUTDOWN_SUCCESS, "transition_success", 12, 4),
    (_T.TRANSITION_ON_SHUTDOWN_FAILURE, "transition_failure", 12, 4),
    (_T.TRANSITION_ON_SHUTDOWN_ERROR, "transition_error", 12, 15),
    (_T.TRANSITION_ON_ERROR_SUCCESS, "transition_success", 15, 1),
    (_T.TRANSITION_ON_ERROR_FAILURE, "transition_failure", 15, 4),
    (_T.TRANSITION_ON_ERROR_ERROR, "transition_error", 15, 4),
)

#: The callback (method name) run in each transition state.
_CALLBACKS = {10: "on_configure", 11: "on_cleanup", 12: "on_shutdown", 13: "on_activate",
              14: "on_deactivate", 15: "on_error"}


def _state_msg(state_id: int) -> State:
    return State(id=state_id, label=STATE_LABELS[state_id])


class ManagedEntity:
    """Something a lifecycle node's transitions reach (each callback returns SUCCESS here)."""

    def on_configure(self, state: LifecycleState) -> TransitionCallbackReturn:
        """Handle the configure transition."""
        return TransitionCallbackReturn.SUCCESS

    def on_cleanup(self, state: LifecycleState) -> TransitionCallbackReturn:
        """Handle the cleanup transition."""
        return TransitionCallbackReturn.SUCCESS

    def on_shutdown(self, state: LifecycleState) -> TransitionCallbackReturn:
        """Handle a shutdown transition."""
        return TransitionCallbackReturn.SUCCESS

    def on_activate(self, state: LifecycleState) -> TransitionCallbackReturn:
        """Handle the activate transition."""
        return TransitionCallbackReturn.SUCCESS

    def on_deactivate(self, state: LifecycleState) -> TransitionCallbackReturn:
        """Handle the deactivate transition."""
        return TransitionCallbackReturn.SUCCESS

    def on_error(self, state: LifecycleState) -> TransitionCallbackReturn:
        """Handle an error in a transition."""
        return TransitionCallbackReturn.SUCCESS


class SimpleManagedEntity(ManagedEntity):
    """A managed entity that is enabled while its node is active."""

    def __init__(self) -> None:
        self._enabled = False

    def on_activate(self, state: LifecycleState) -> TransitionCallbackReturn:
        """Enable."""
        self._enabled = True
        return TransitionCallbackReturn.SUCCESS

    def on_deactivate(self, state: LifecycleState) -> TransitionCallbackReturn:
        """Disable."""
        self._enabled = False
        return TransitionCallbackReturn.SUCCESS

    @property
    def is_activated(self) -> bool:
        """Whether the entity is enabled (its node active)."""
        return self._enabled

    @staticmethod
    def when_enabled(wrapped: Callable[..., Any] | None = None, *,
                     when_not_enabled: Callable[[], Any] | None = None) -> Any:
        """Decorate a method to run only while enabled (else ``when_not_enabled()``, if given)."""
        def decorator(method: Callable[..., Any]) -> Callable[..., Any]:
            @functools.wraps(method)
            def only_when_enabled(self: SimpleManagedEntity, *args: Any, **kwargs: Any) -> None:
                if not self._enabled:
                    if when_not_enabled is not None:
                        when_not_enabled()
                    return
                method(self, *args, **kwargs)
            return only_when_enabled
        return decorator if wrapped is None else decorator(wrapped)


class LifecyclePublisher(SimpleManagedEntity, Publisher):
    """A publisher that sends only while its lifecycle node is active (else drops)."""

    def __init__(self, *args: Any, **kwargs: Any) -> None:
        SimpleManagedEntity.__init__(self)
        Publisher.__init__(self, *args, **kwargs)
        send, transfer = self.publish, self.publish_transfer

        def publish(msg: Any) -> None:
            if self._enabled:
                send(msg)

        def publish_transfer(msg: Any) -> None:
            if self._enabled:
                transfer(msg)

        self.publish, self.publish_transfer = publish, publish_transfer


class LifecycleNodeMixin(ManagedEntity):
    """The state machine, its services and its callbacks, for a class that is also a Node.

    The default callbacks pass the transition to every managed entity (a lifecycle
    publisher, or one given to :meth:`add_managed_entity`) and stop at the first that does
    not return SUCCESS; override them, calling ``super()`` to keep that.
    """

    def __init__(self, *, enable_communication_interface: bool = True,
                 callback_group: CallbackGroup | None = None) -> None:
        node: Any = self
        self._state_id = State.PRIMARY_STATE_UNCONFIGURED
        self._managed_entities: set[ManagedEntity] = set()
        self._transition_event_publisher: Publisher | None = None
        if not enable_communication_interface:
            return
        self._transition_event_publisher = Node.create_publisher(
            node, TransitionEvent, "~/transition_event", 10)
        group = callback_group if callback_group is not None else node.default_callback_group
        for name, srv_type, handler in (
                ("change_state", ChangeState, self._on_change_state),
                ("get_state", GetState, self._on_get_state),
                ("get_available_states", GetAvailableStates, self._on_get_available_states),
                ("get_available_transitions", GetAvailableTransitions,
                 self._on_get_available_transitions),
                ("get_transition_graph", GetAvailableTransitions,
                 self._on_get_transition_graph)):
            node.create_service(srv_type, f"~/{name}", handler,
                                qos_profile=qos_profile_services_default, callback_group=group)

    # -- transitions ------------------------------------------------------------------
    def trigger_configure(self) -> TransitionCallbackReturn:
        """Take the configure transition (unconfigured -> inactive)."""
        return self._change_state(Transition.TRANSITION_CONFIGURE)

    def trigger_cleanup(self) -> TransitionCallbackReturn:
        """Take the cleanup transition (inactive -> unconfigured)."""
        return self._change_state(Transition.TRANSITION_CLEANUP)

    def trigger_activate(self) -> TransitionCallbackReturn:
        """Take the activate transition (inactive -> active)."""
        return self._change_state(Transition.TRANSITION_ACTIVATE)

    def trigger_deactivate(self) -> TransitionCallbackReturn:
        """Take the deactivate transition (active -> inactive)."""
        return self._change_state(Transition.TRANSITION_DEACTIVATE)

    def trigger_shutdown(self) -> TransitionCallbackReturn:
        """Take the shutdown transition of the current primary state (-> finalized)."""
        return self._change_state("shutdown")  # each primary state has one of that label

    def _take(self, key: int | str) -> None:
        """Move along the transition with id or label ``key`` from the current state."""
        for tid, label, start, goal in TRANSITIONS:
            if start == self._state_id and key in (tid, label):
                self._publish_transition(start, goal)
                self._state_id = goal
                return
        current = STATE_LABELS[self._state_id]
        get_logger("rcl_lifecycle").warning(
            f"No transition matching {key} found for current state {current}")
        raise RCLError(f"no transition {key!r} from the current state '{current}'")

    def _publish_transition(self, start: int, goal: int) -> None:
        if self._transition_event_publisher is not None:
            # as Jazzy's rcl_lifecycle: no transition and no timestamp filled in
            self._transition_event_publisher.publish(TransitionEvent(
                start_state=_state_msg(start), goal_state=_state_msg(goal)))

    def _run_callback(self, previous: LifecycleState) -> TransitionCallbackReturn:
        name = _CALLBACKS[self._state_id]
        node: Any = self
        try:
            result = getattr(self, name)(previous)
        except Exception as exc:  # a raising callback is an ERROR result
            node.get_logger().error(f"{name}() raised {type(exc).__name__}: {exc}")
            return TransitionCallbackReturn.ERROR
        if not isinstance(result, TransitionCallbackReturnType):
            node.get_logger().error(
                f"{name}() returned {result!r}, not a TransitionCallbackReturn")
            return TransitionCallbackReturn.ERROR
        return result

    def _change_state(self, transition: int | str) -> TransitionCallbackReturn:
        """Take ``transition`` (an id or a label) and the callback's result transition."""
        previous = LifecycleState(STATE_LABELS[self._state_id], self._state_id)
        self._take(transition)
        result = self._run_callback(previous)
        self._take(result.to_label())
        if result == TransitionCallbackReturn.ERROR:  # now in errorprocessing: on_error
            self._take(self._run_callback(previous).to_label())
        return result

    # -- managed entities -------------------------------------------------------------
    def add_managed_entity(self, entity: ManagedEntity) -> None:
        """Pass this node's transitions to ``entity`` too (by the default callbacks)."""
        if not isinstance(entity, ManagedEntity):
            raise TypeError("Expected a rclpy.lifecycle.ManagedEntity instance.")
        self._managed_entities.add(entity)

    def _pass_on(self, name: str, state: LifecycleState) -> TransitionCallbackReturn:
        for entity in self._managed_entities:
            result = getattr(entity, name)(state)
            if not isinstance(result, TransitionCallbackReturnType):
                raise TypeError(f"{name}() return value of class {type(entity)} should be "
                                "`TransitionCallbackReturn`.")
            if result != TransitionCallbackReturn.SUCCESS:
                return result
        return TransitionCallbackReturn.SUCCESS

    def on_configure(self, state: LifecycleState) -> TransitionCallbackReturn:
        """Configuring: the managed entities' ``on_configure`` (override to do more)."""
        return self._pass_on("on_configure", state)

    def on_cleanup(self, state: LifecycleState) -> TransitionCallbackReturn:
        """Cleaning up: the managed entities' ``on_cleanup``."""
        return self._pass_on("on_cleanup", state)

    def on_shutdown(self, state: LifecycleState) -> TransitionCallbackReturn:
        """Shutting down: the managed entities' ``on_shutdown``."""
        return self._pass_on("on_shutdown", state)

    def on_activate(self, state: LifecycleState) -> TransitionCallbackReturn:
        """Activating: the managed entities' ``on_activate`` (lifecycle publishers start)."""
        return self._pass_on("on_activate", state)

    def on_deactivate(self, state: LifecycleState) -> TransitionCallbackReturn:
        """Deactivating: the managed entities' ``on_deactivate`` (lifecycle publishers stop)."""
        return self._pass_on("on_deactivate", state)

    def on_error(self, state: LifecycleState) -> TransitionCallbackReturn:
        """Error processing: the managed entities' ``on_error``."""
        return self._pass_on("on_error", state)

    def create_lifecycle_publisher(self, *args: Any, **kwargs: Any) -> LifecyclePublisher:
        """``create_publisher``'s arguments; a publisher that sends only while active."""
        if "publisher_class" in kwargs:
            raise TypeError(
                "create_publisher() got an unexpected keyword argument 'publisher_class'")
        node: Any = self
        pub = Node.create_publisher(node, *args, **kwargs, publisher_class=LifecyclePublisher)
        assert isinstance(pub, LifecyclePublisher)
        self._managed_entities.add(pub)
        return pub

    def destroy_lifecycle_publisher(self, publisher: LifecyclePublisher) -> bool:
        """Destroy a lifecycle publisher (False if it was destroyed before)."""
        self._managed_entities.discard(publisher)
        node: Any = self
        return Node.destroy_publisher(node, publisher)

    # -- services ---------------------------------------------------------------------
    def _on_change_state(self, request: ChangeState_Request,
                         response: ChangeState_Response) -> ChangeState_Response:
        transition = request.transition.label or request.transition.id  # the label decides
        try:
            response.success = self._change_state(transition) == TransitionCallbackReturn.SUCCESS
        except RCLError:
            response.success = False
        return response

    def _on_get_state(self, request: GetState_Request,
                      response: GetState_Response) -> GetState_Response:
        response.current_state = _state_msg(self._state_id)
        return response

    def _on_get_available_states(
            self, request: GetAvailableStates_Request,
            response: GetAvailableStates_Response) -> GetAvailableStates_Response:
        response.available_states = [_state_msg(i) for i in STATE_LABELS]
        return response

    def _descriptions(self, only_current: bool) -> list[TransitionDescription]:
        return [TransitionDescription(Transition(tid, label), _state_msg(start), _state_msg(goal))
                for tid, label, start, goal in TRANSITIONS
                if not only_current or start == self._state_id]

    def _on_get_available_transitions(
            self, request: GetAvailableTransitions_Request,
            response: GetAvailableTransitions_Response) -> GetAvailableTransitions_Response:
        response.available_transitions = self._descriptions(only_current=True)
        return response

    def _on_get_transition_graph(
            self, request: GetAvailableTransitions_Request,
            response: GetAvailableTransitions_Response) -> GetAvailableTransitions_Response:
        response.available_transitions = self._descriptions(only_current=False)
        return response


class LifecycleNode(LifecycleNodeMixin, Node):
    """A managed node: a :class:`Node` with the lifecycle state machine (starts unconfigured)."""

    def __init__(self, node_name: str, *, enable_communication_interface: bool = True,
                 **kwargs: Any) -> None:
        Node.__init__(self, node_name, **kwargs)
        LifecycleNodeMixin.__init__(
            self, enable_communication_interface=enable_communication_interface)
