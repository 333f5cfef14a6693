"""Node: rclpy's Node API over posekit's transports, executors and clocks.

``Node(name, namespace=..., parameter_overrides=..., remappings=..., context=...)``. Topic
names are validated, expanded in the node's namespace and remapped (posekit.runtime.names);
the QoS argument is a :class:`QoSProfile` or an int depth. Every node declares
``use_sim_time`` (default False); setting it true makes ``get_clock()`` follow ``/clock``.

Name and parameter sources, weakest first: ``init(args=[--ros-args ...])`` of the context
(``sys.argv`` by default, as rclpy; see :mod:`posekit.runtime.arguments`), the
:func:`node_defaults` scope (used by posekit.launch: its parameters, then its ROS arguments,
the ``--ros-args`` of ``posekit run``), ``cli_args``, then the constructor's
``parameter_overrides``. Remap rules are tried in this order (the first match wins): the
constructor's ``remappings``, ``cli_args``, the scope's ROS arguments, the scope's
remappings, the global arguments.
"""

from __future__ import annotations

import contextvars
import math
from collections.abc import Callable, Iterator, Mapping, Sequence
from contextlib import contextmanager
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

from posekit.msgs.rcl_interfaces import ListParametersResult, ParameterEvent, ParameterValue
from posekit.runtime.arguments import RCLError
from posekit.runtime.callback_groups import CallbackGroup, MutuallyExclusiveCallbackGroup
from posekit.runtime.clock import Clock, ROSClock
from posekit.runtime.context import (
    Context,
    InvalidHandle,
    NotInitializedException,
    get_default_context,
)
from posekit.runtime.entities import Publisher, Subscription, Timer
from posekit.runtime.guard_condition import GuardCondition
from posekit.runtime.inbox import Handoff
from posekit.runtime.logging import RcutilsLogger
from posekit.runtime.names import (
    NameValidationError,
    RemapRule,
    normalize_namespace,
    parse_remap_rules,
    remap_node_name,
    remap_node_namespace,
    resolve_service_name,
    resolve_topic_name,
    validate_namespace,
    validate_node_name,
)
from posekit.runtime.parameters import (
    PARAM_REL_TOL,
    OnSetCallback,
    Parameter,
    ParameterDescriptor,
    ParameterStore,
    PostSetCallback,
    PreSetCallback,
    SetParametersResult,
)
from posekit.runtime.qos import (
    QoSProfile,
    qos_profile_parameter_events,
    qos_profile_services_default,
    to_qos_profile,
)
from posekit.runtime.rate import Rate
from posekit.runtime.rosout import RosoutPublisher
from posekit.runtime.services import Client, Service, _Queued
from posekit.runtime.time_source import TimeSource
from posekit.runtime.transport import EndpointInfo, ServiceInfo, Transport

if TYPE_CHECKING:
    from posekit.runtime.arguments import RosArguments
    from posekit.runtime.executors import Executor
    from posekit.runtime.qos_overriding_options import QoSOverridingOptions
    from posekit.runtime.topic_endpoint_info import TopicEndpointInfo

__all__ = ["Node", "NodeDefaults", "NodeNameNonExistentError", "node_defaults"]


class NodeNameNonExistentError(RCLError):
    """A graph query by node named a node that is not on the graph (rclpy's error)."""


@dataclass
class NodeDefaults:
    """Overrides applied to every Node constructed inside :func:`node_defaults`."""

    name: str | None = None
    namespace: str | None = None
    parameters: dict[str, Any] = field(default_factory=dict)
    remappings: list[RemapRule] = field(default_factory=list)
    context: Context | None = None
    #: ROS arguments for the nodes of the scope, as a process's ``--ros-args`` reach its
    #: nodes (parameters matched by fully qualified name, remaps, ``__node``/``__ns``).
    arguments: RosArguments | None = None
    #: Parameter entries (``(node name pattern, values)``, rcl's order) applied to a node of
    #: the scope whose fully qualified name matches: a launch entry's parameter files and
    #: dicts, as launch_ros hands them to rcl (``--params-file``). After ``parameters``.
    matched_parameters: RosArguments | None = None


_defaults: contextvars.ContextVar[NodeDefaults | None] = contextvars.ContextVar(
    "posekit_node_defaults", default=None
)


@contextmanager
def node_defaults(
    *,
    name: str | None = None,
    namespace: str | None = None,
    parameters: Mapping[str, Any] | None = None,
    remappings: Sequence[str | tuple[str, str]] | Mapping[str, str] | None = None,
    context: Context | None = None,
    arguments: RosArguments | None = None,
    matched_parameters: RosArguments | None = None,
) -> Iterator[NodeDefaults]:
    """Nodes created in this block get this name/namespace/parameters/remaps/context.

    This is how a launch description configures node classes whose ``__init__`` hard-codes
    ``super().__init__("name")`` (ROS does the same with ``--ros-args`` of the process).
    ``parameters`` reach every node of the block; ``matched_parameters`` the nodes whose
    fully qualified name an entry's pattern matches (``/**``, ``/ns/*``, ``/ns/name``), after
    ``parameters``; ``arguments`` (parsed ``--ros-args``) apply last and win over both.
    """
    value = NodeDefaults(
        name, namespace, dict(parameters or {}), parse_remap_rules(remappings), context,
        arguments, matched_parameters,
    )
    token = _defaults.set(value)
    try:
        yield value
    finally:
        _defaults.reset(token)


def _no_callback() -> None:
    """Placeholder timer callback a Rate replaces with its own."""


def _merged_overrides(
    fqn: str,
    glob: RosArguments,
    scope: NodeDefaults | None,
    local: RosArguments,
    parameter_overrides: Sequence[Parameter] | Mapping[str, Any] | None,
) -> dict[str, Any]:
    """A node's parameter overrides (name -> value) from every source, the last one winning.

    Weakest first: the global arguments, the launch scope (its parameters, its matched
    parameters, then its ROS arguments), the node's cli_args, then the constructor's
    ``parameter_overrides``. ``fqn`` is the node's fully qualified name.
    """
    overrides: dict[str, Any] = glob.parameters_for(fqn)
    if scope is not None:
        overrides.update(scope.parameters)
        if scope.matched_parameters is not None:
            overrides.update(scope.matched_parameters.parameters_for(fqn))
        if scope.arguments is not None:
            overrides.update(scope.arguments.parameters_for(fqn))
    overrides.update(local.parameters_for(fqn))
    if isinstance(parameter_overrides, Mapping):
        overrides.update(parameter_overrides)
    elif parameter_overrides is not None:
        overrides.update({p.name: p.value for p in parameter_overrides})
    return overrides


class Node:
    """A ROS 2 node (rclpy.node.Node API)."""

    #: Relative tolerance of floating point range checks (rclpy's ``Node.PARAM_REL_TOL``).
    PARAM_REL_TOL = PARAM_REL_TOL

    def __init__(
        self,
        node_name: str,
        *,
        context: Context | None = None,
        cli_args: Sequence[str] | None = None,
        namespace: str | None = None,
        use_global_arguments: bool = True,
        enable_rosout: bool = True,
        start_parameter_services: bool = True,
        parameter_overrides: Sequence[Parameter] | Mapping[str, Any] | None = None,
        allow_undeclared_parameters: bool = False,
        automatically_declare_parameters_from_overrides: bool = False,
        remappings: Sequence[str | tuple[str, str]] | Mapping[str, str] | None = None,
        transport: str | Transport | None = None,
    ) -> None:
        self._destroyed = False
        scope = _defaults.get()
        self._context = context or (scope.context if scope else None) or get_default_context()
        if not self._context.ok():
            raise NotInitializedException(f"cannot create node '{node_name}'")
        validate_node_name(node_name)

        from posekit.runtime.arguments import RosArguments, parse_arguments

        local = parse_arguments(cli_args) if cli_args else RosArguments()
        glob = self._context.arguments if use_global_arguments else RosArguments()
        rules: list[RemapRule] = parse_remap_rules(remappings) + local.remaps
        if scope is not None:
            if scope.arguments is not None:
                rules += scope.arguments.remaps
            rules += scope.remappings
        rules += glob.remaps

        # rcl's order: the name first, then the namespace by rules for the new name
        name_remap = remap_node_name(rules, node_name)
        if scope is not None and scope.name:
            node_name = scope.name
        if scope is not None and scope.namespace is not None and namespace is None:
            namespace = scope.namespace
        if name_remap:
            node_name = name_remap
        ns_remap = remap_node_namespace(rules, node_name)
        if ns_remap:
            namespace = ns_remap
        self._name = validate_node_name(node_name)
        self._namespace = normalize_namespace(namespace)
        self._remap_rules = [r for r in rules if not r.from_name.startswith("__")]

        overrides = _merged_overrides(
            self.get_fully_qualified_name(), glob, scope, local, parameter_overrides
        )

        if isinstance(transport, Transport):
            self._transport = transport
        else:
            self._transport = self._context.transport(transport)
        self._transport.declare_node(self._name, self._namespace)

        self._time_source = TimeSource(self)
        #: The hand-off between this node's entities and its executor (posekit's, not rclpy
        #: API; see :mod:`posekit.runtime.inbox`).
        self.handoff = Handoff(self, self._queued_entities, self._time_source)
        self._publishers: list[Publisher] = []
        self._subscriptions: list[Subscription] = []
        self._timers: list[Timer] = []
        self._services: list[Service] = []
        self._clients: list[Client] = []
        self._guards: list[GuardCondition] = []
        self._default_callback_group: CallbackGroup = MutuallyExclusiveCallbackGroup()
        self._callback_groups: list[CallbackGroup] = [self._default_callback_group]
        self._rate_group: CallbackGroup | None = None  # rates' own group (made on first use)

        self._clock = ROSClock()
        logger_name = (self._namespace.strip("/").replace("/", ".") + "." + self._name).lstrip(".")
        self._logger = RcutilsLogger(logger_name, self._clock.now_ns)
        self._parameters = ParameterStore.create(
            self._name, overrides, allow_undeclared_parameters
        )
        self._parameter_event_publisher = self.create_publisher(
            ParameterEvent, "/parameter_events", qos_profile_parameter_events
        )
        self._parameters.on_event = self._publish_parameter_event
        self._time_source.attach_clock(self._clock)
        self._parameters.add_post_set(self._on_parameters_set)
        self._parameters.add_on_set(self._check_use_sim_time)
        self.declare_parameter("use_sim_time", False)
        self._rosout: RosoutPublisher | None = RosoutPublisher(self) if enable_rosout else None
        if automatically_declare_parameters_from_overrides:
            for pname, value in overrides.items():
                if not self._parameters.has(pname):
                    self.declare_parameter(pname, value)
        self._parameter_service: Any = None
        if start_parameter_services and self._transport.supports_services:
            from posekit.runtime.parameter_service import ParameterService

            self._parameter_service = ParameterService(self)
        self._type_description_service: Any = None
        if self._transport.supports_services:
            from posekit.runtime.type_description_service import TypeDescriptionService

            self._type_description_service = TypeDescriptionService(
                self, with_rosout=self._rosout is not None)

    # -- identity ---------------------------------------------------------------------
    @property
    def context(self) -> Context:
        """The context the node lives in."""
        return self._context

    @property
    def default_callback_group(self) -> CallbackGroup:
        """The group of entities created without one (a MutuallyExclusiveCallbackGroup)."""
        return self._default_callback_group

    @property
    def executor(self) -> Executor | None:
        """The executor the node was added to, if any."""
        executor: Executor | None = self.handoff.executor
        return executor

    @executor.setter
    def executor(self, new_executor: Executor | None) -> None:
        current = self.executor
        if new_executor is current:
            return
        if current is not None:
            current.remove_node(self)
        if new_executor is not None:
            new_executor.add_node(self)

    @property
    def transport(self) -> Transport:
        """The transport carrying this node's messages."""
        return self._transport

    def _check_handle(self) -> None:
        """rclpy's InvalidHandle for a node used after ``destroy_node()``."""
        if self._destroyed:
            raise InvalidHandle("cannot use Destroyable because destruction was requested")

    def get_name(self) -> str:
        """The node's name (after remapping)."""
        self._check_handle()
        return self._name

    def get_namespace(self) -> str:
        """The node's namespace, '/' for the root."""
        self._check_handle()
        return self._namespace

    def get_fully_qualified_name(self) -> str:
        """``/ns/name``."""
        self._check_handle()
        return self._fqn()

    def _fqn(self) -> str:
        return ("" if self._namespace == "/" else self._namespace) + "/" + self._name

    @property
    def fully_qualified_name(self) -> str:
        """``/ns/name``, also after ``destroy_node()`` (posekit's, for reports on finished runs).

        The get_* methods raise InvalidHandle after ``destroy_node()``, as rclpy's do.
        """
        return self._fqn()

    def get_logger(self) -> RcutilsLogger:
        """The node's logger (named after the node, stamped with the node's clock)."""
        return self._logger

    def get_clock(self) -> ROSClock:
        """The node's ROS clock (sim time when use_sim_time is true)."""
        return self._clock

    def resolve_topic_name(self, topic: str, *, only_expand: bool = False) -> str:
        """Expand (and unless ``only_expand``, remap) a topic name as this node would."""
        rules: Sequence[RemapRule] = () if only_expand else [
            r for r in self._remap_rules if r.kind != "service"]
        return resolve_topic_name(topic, self._name, self._namespace, rules)

    def resolve_service_name(self, service: str, *, only_expand: bool = False) -> str:
        """Expand (and unless ``only_expand``, remap) a service name as this node would."""
        rules: Sequence[RemapRule] = () if only_expand else [
            r for r in self._remap_rules if r.kind != "topic"]
        return resolve_service_name(service, self._name, self._namespace, rules)

    # -- entities ---------------------------------------------------------------------
    def _check_alive(self) -> None:
        self._check_handle()
        if not self._context.ok():
            raise NotInitializedException(f"node '{self._name}'")

    def _info(self, msg_type: type, topic: str, qos: QoSProfile) -> EndpointInfo:
        if not isinstance(msg_type, type):
            raise TypeError(f"message type must be a class, got {msg_type!r}")
        return EndpointInfo(topic, msg_type, qos, self._name, self._namespace, self._logger)

    def create_publisher(
        self,
        msg_type: type,
        topic: str,
        qos_profile: QoSProfile | int,
        *,
        callback_group: CallbackGroup | None = None,
        event_callbacks: object = None,
        qos_overriding_options: QoSOverridingOptions | None = None,
        publisher_class: type[Publisher] | None = None,
    ) -> Publisher:
        """Publisher of ``msg_type`` on ``topic`` (relative names use the node namespace).

        ``publisher_class``: a :class:`Publisher` subclass to make instead (as rclpy's
        lifecycle publisher is made). ``qos_overriding_options``: a
        :class:`~posekit.runtime.qos_overriding_options.QoSOverridingOptions` (QoS from
        ``qos_overrides.*`` parameters).
        """
        del callback_group, event_callbacks
        self._check_alive()
        qos = to_qos_profile(qos_profile)
        full = self.resolve_topic_name(topic)
        self._qos_overrides("publisher", full, qos, qos_overriding_options)
        endpoint = self._transport.advertise(self._info(msg_type, full, qos))
        pub = (publisher_class or Publisher)(self, msg_type, full, qos, endpoint, topic)
        self._publishers.append(pub)
        return pub

    def create_subscription(
        self,
        msg_type: type,
        topic: str,
        callback: Callable[..., Any],
        qos_profile: QoSProfile | int,
        *,
        callback_group: CallbackGroup | None = None,
        event_callbacks: object = None,
        qos_overriding_options: QoSOverridingOptions | None = None,
        raw: bool = False,
    ) -> Subscription:
        """Subscription calling ``callback(msg)`` from the executor for each message.

        A two-argument callback gets ``callback(msg, info)`` with rclpy's MessageInfo.
        """
        del event_callbacks
        if raw:
            raise NotImplementedError("raw (serialized) subscriptions need a serializing transport")
        return self._subscribe(msg_type, topic, callback, qos_profile, callback_group, False,
                               qos_overriding_options)

    def _qos_overrides(self, kind: str, topic: str, qos: QoSProfile,
                       options: QoSOverridingOptions | None) -> None:
        """Apply ``qos_overrides.*`` parameters to ``qos`` when ``options`` asks for them."""
        if options is not None:
            from posekit.runtime.qos_overriding_options import declare_qos_parameters

            declare_qos_parameters(self, kind, topic, qos, options)

    def _subscribe(
        self,
        msg_type: type,
        topic: str,
        callback: Callable[[Any], Any],
        qos_profile: QoSProfile | int,
        callback_group: CallbackGroup | None,
        with_source: bool,
        qos_overriding_options: QoSOverridingOptions | None = None,
    ) -> Subscription:
        """create_subscription whose callback also gets the sending publisher's id.

        The callback gets ``(msg, source)`` (see Transport.subscribe_with_source).
        """
        self._check_alive()
        if not callable(callback):
            raise TypeError(f"subscription callback must be callable, got {callback!r}")
        qos = to_qos_profile(qos_profile)
        full = self.resolve_topic_name(topic)
        self._qos_overrides("subscription", full, qos, qos_overriding_options)
        group = callback_group or self._default_callback_group
        sub = Subscription(self, msg_type, full, callback, qos, group, topic)
        self._subscriptions.append(sub)
        info = self._info(msg_type, full, qos)
        try:
            if with_source:
                enqueue = sub._enqueue
                endpoint = self._transport.subscribe_with_source(
                    info, lambda msg, source: enqueue((msg, source))
                )
            else:
                endpoint = self._transport.subscribe(info, sub._enqueue)
        except BaseException:
            self._subscriptions.remove(sub)
            raise
        sub._attach(endpoint)
        self.handoff.entities_changed()
        return sub

    def create_timer(
        self,
        timer_period_sec: float,
        callback: Callable[[], Any] | None,
        callback_group: CallbackGroup | None = None,
        clock: Clock | None = None,
        autostart: bool = True,
    ) -> Timer:
        """Timer calling ``callback()`` every ``timer_period_sec`` seconds of ``clock``.

        The default clock is the node clock, so sim time under use_sim_time. ``callback``
        may be None, as in rclpy (see :class:`~posekit.runtime.entities.Timer`).
        """
        self._check_alive()
        if callback is not None and not callable(callback):
            raise TypeError(f"timer callback must be callable or None, got {callback!r}")
        period_s = float(timer_period_sec)
        # rclpy raises ValueError for NaN, OverflowError for inf, an error for negatives.
        if math.isnan(period_s):
            raise ValueError(f"timer period must be a number of seconds, got {period_s}")
        if math.isinf(period_s):
            raise OverflowError(f"timer period must be finite, got {period_s} s")
        period_ns = round(period_s * 1e9)
        if period_ns < 0:
            raise ValueError(f"timer period must be non-negative, got {timer_period_sec} s")
        timer = Timer(
            self,
            callback,
            period_ns,
            clock or self._clock,
            callback_group or self._default_callback_group,
            autostart,
        )
        self._timers.append(timer)
        self.handoff.entities_changed()
        return timer

    def create_rate(self, frequency: float, clock: Clock | None = None) -> Rate:
        """A :class:`Rate` ticking at ``frequency`` Hz on ``clock`` (default: the node clock).

        ``rate.sleep()`` needs the node to be spun in another thread (posekit.runtime.rate):
        from a callback of a single-threaded executor it blocks forever, as in rclpy.
        """
        if frequency <= 0:
            raise ValueError("frequency must be > 0")
        if self._rate_group is None:
            from posekit.runtime.callback_groups import ReentrantCallbackGroup

            self._rate_group = ReentrantCallbackGroup()
        timer = self.create_timer(1.0 / frequency, _no_callback, self._rate_group, clock)
        return Rate(timer, context=self._context)

    def destroy_rate(self, rate: Rate) -> bool:
        """Destroy a Rate's timer and wake its sleepers; False if the timer is unknown."""
        success = self.destroy_timer(rate._timer)
        rate.destroy()
        return success

    def _queued_entities(self) -> list[Any]:
        """Everything whose queue the executor drains: subscriptions, servers, clients, guards."""
        return [
            *self._subscriptions,
            *(s._queued for s in self._services),
            *(c._queued for c in self._clients),
            *(g._queued for g in self._guards if g._queued is not None),
        ]

    def create_guard_condition(
        self, callback: Callable[[], Any], callback_group: CallbackGroup | None = None
    ) -> GuardCondition:
        """A :class:`GuardCondition` whose ``trigger()`` makes the executor run ``callback()``."""
        self._check_alive()
        group = callback_group or self._default_callback_group
        guard = GuardCondition(callback, group, context=self._context)

        def run(_: object) -> Any:
            return callback()

        guard._queued = _Queued(self, "guard condition", group, run,
                                "guard condition callback", limit=1)
        self._guards.append(guard)
        return guard

    def destroy_guard_condition(self, guard: GuardCondition) -> bool:
        """Destroy a guard condition of this node; False if it is not this node's."""
        if guard in self._guards:
            self._guards.remove(guard)
            guard.destroy()
            return True
        return False

    @property
    def guards(self) -> Iterator[GuardCondition]:
        """This node's guard conditions."""
        return iter(list(self._guards))

    def _service_info(self, srv_type: type, name: str, qos: QoSProfile) -> ServiceInfo:
        from posekit.msgs._service import is_service_type

        if not is_service_type(srv_type):
            raise TypeError(
                f"service type must be a service class with Request and Response, "
                f"got {srv_type!r}"
            )
        return ServiceInfo(name, srv_type, qos, self._name, self._namespace, self._logger)

    def create_service(
        self,
        srv_type: type,
        srv_name: str,
        callback: Callable[[Any, Any], Any],
        *,
        qos_profile: QoSProfile = qos_profile_services_default,
        callback_group: CallbackGroup | None = None,
    ) -> Service:
        """Service server calling ``callback(request, response) -> response`` for each request.

        Called from the executor (see :mod:`posekit.runtime.services`).
        """
        self._check_alive()
        if not callable(callback):
            raise TypeError(f"service callback must be callable, got {callback!r}")
        full = self.resolve_service_name(srv_name)
        qos = to_qos_profile(qos_profile)
        info = self._service_info(srv_type, full, qos)
        group = callback_group or self._default_callback_group
        service = Service(self, srv_type, full, callback, qos, group, srv_name)
        service._attach(self._transport.create_service_server(info, service._receive))
        self._services.append(service)
        return service

    def create_client(
        self,
        srv_type: type,
        srv_name: str,
        *,
        qos_profile: QoSProfile = qos_profile_services_default,
        callback_group: CallbackGroup | None = None,
    ) -> Client:
        """Service client (``call_async``, ``call``, ``wait_for_service``)."""
        self._check_alive()
        full = self.resolve_service_name(srv_name)
        qos = to_qos_profile(qos_profile)
        info = self._service_info(srv_type, full, qos)
        group = callback_group or self._default_callback_group
        endpoint = self._transport.create_service_client(info)
        client = Client(self, srv_type, full, qos, group, endpoint, srv_name)
        self._clients.append(client)
        return client

    def destroy_service(self, service: Service) -> bool:
        """Remove a service server; False if it is not this node's."""
        if service in self._services:
            self._services.remove(service)
            service._destroy()
            return True
        return False

    def destroy_client(self, client: Client) -> bool:
        """Remove a client (pending futures never complete); False if unknown."""
        if client in self._clients:
            self._clients.remove(client)
            client._destroy()
            return True
        return False

    @property
    def services(self) -> Iterator[Service]:
        """This node's service servers."""
        return iter(list(self._services))

    @property
    def clients(self) -> Iterator[Client]:
        """This node's service clients."""
        return iter(list(self._clients))

    def destroy_publisher(self, publisher: Publisher) -> bool:
        """Remove a publisher; False if it is not this node's."""
        if publisher in self._publishers:
            self._publishers.remove(publisher)
            publisher._destroy()
            return True
        return False

    def destroy_subscription(self, subscription: Subscription) -> bool:
        """Remove a subscription (safe inside its own callback); False if unknown."""
        if subscription in self._subscriptions:
            self._subscriptions.remove(subscription)
            subscription._destroy()
            self.handoff.entities_changed()
            return True
        return False

    def destroy_timer(self, timer: Timer) -> bool:
        """Remove a timer; False if unknown."""
        if timer in self._timers:
            self._timers.remove(timer)
            timer.destroyed = True
            self.handoff.entities_changed()
            return True
        return False

    def create_callback_group(self, reentrant: bool = False) -> CallbackGroup:
        """Convenience: a new callback group registered with the node."""
        from posekit.runtime.callback_groups import ReentrantCallbackGroup

        group: CallbackGroup = (
            ReentrantCallbackGroup() if reentrant else MutuallyExclusiveCallbackGroup()
        )
        self._callback_groups.append(group)
        return group

    @property
    def publishers(self) -> Iterator[Publisher]:
        """This node's publishers."""
        return iter(list(self._publishers))

    @property
    def subscriptions(self) -> Iterator[Subscription]:
        """This node's subscriptions."""
        return iter(list(self._subscriptions))

    @property
    def timers(self) -> Iterator[Timer]:
        """This node's timers."""
        return iter(list(self._timers))

    def destroy_node(self) -> None:
        """Destroy every entity and leave the executor (again: nothing happens).

        Afterwards, as in rclpy, the node's name, graph and entity methods raise
        :class:`InvalidHandle`; its logger, clock and parameters still answer.
        """
        if self._destroyed:
            return
        executor = self.executor
        if executor is not None:
            executor.remove_node(self)
        for pub in list(self._publishers):
            self.destroy_publisher(pub)
        for sub in list(self._subscriptions):
            self.destroy_subscription(sub)
        for timer in list(self._timers):
            self.destroy_timer(timer)
        for service in list(self._services):
            self.destroy_service(service)
        for client in list(self._clients):
            self.destroy_client(client)
        for guard in list(self._guards):
            self.destroy_guard_condition(guard)
        self._time_source.destroy()
        if self._rosout is not None:
            self._rosout.destroy()
        self._transport.undeclare_node(self._name, self._namespace)
        self._destroyed = self.handoff.destroyed = True

    # -- graph ------------------------------------------------------------------------
    def get_topic_names_and_types(self, no_demangle: bool = False) -> list[tuple[str, list[str]]]:
        """Every topic known to the node's transport, with type names."""
        self._check_handle()
        del no_demangle
        return self._transport.get_topic_names_and_types()

    def get_service_names_and_types(self) -> list[tuple[str, list[str]]]:
        """Every service known to the node's transport, with type names."""
        return self._transport.get_service_names_and_types()

    def _names_and_types_by_node(
        self, what: str, query: Callable[[str, str], list[tuple[str, list[str]]]],
        node_name: str, node_namespace: str,
    ) -> list[tuple[str, list[str]]]:
        """``query(node_name, node_namespace)`` once the node is known to be on the graph.

        As rcl: an empty namespace is the root, a bad name or namespace raises
        :class:`RCLError`, a node not on the graph :class:`NodeNameNonExistentError`.
        """
        self._check_handle()
        namespace = node_namespace or "/"
        try:
            validate_node_name(node_name)
            validate_namespace(namespace)
        except NameValidationError as exc:
            raise RCLError(f"failed to get {what} names and types: {exc.reason}") from None
        if (node_name, namespace) not in self.get_node_names_and_namespaces():
            raise NodeNameNonExistentError(
                f"cannot get {what} names and types for nonexistent node "
                f"'{namespace.rstrip('/')}/{node_name}'")
        return query(node_name, namespace)

    def get_publisher_names_and_types_by_node(
        self, node_name: str, node_namespace: str, no_demangle: bool = False
    ) -> list[tuple[str, list[str]]]:
        """The topics node ``node_name`` in ``node_namespace`` publishes, with type names.

        ROS names and types (``no_demangle`` is accepted and ignored: posekit shows no
        middleware names). Raises :class:`NodeNameNonExistentError` if the node is not on
        the graph, :class:`RCLError` for a bad name or a relative namespace.
        """
        del no_demangle
        return self._names_and_types_by_node(
            "publisher", self._transport.get_publisher_names_and_types_by_node,
            node_name, node_namespace)

    def get_subscriber_names_and_types_by_node(
        self, node_name: str, node_namespace: str, no_demangle: bool = False
    ) -> list[tuple[str, list[str]]]:
        """The topics node ``node_name`` in ``node_namespace`` subscribes to (as above)."""
        del no_demangle
        return self._names_and_types_by_node(
            "subscriber", self._transport.get_subscriber_names_and_types_by_node,
            node_name, node_namespace)

    def get_service_names_and_types_by_node(
        self, node_name: str, node_namespace: str
    ) -> list[tuple[str, list[str]]]:
        """The services node ``node_name`` in ``node_namespace`` serves (errors as above)."""
        return self._names_and_types_by_node(
            "service", self._transport.get_service_names_and_types_by_node,
            node_name, node_namespace)

    def get_client_names_and_types_by_node(
        self, node_name: str, node_namespace: str
    ) -> list[tuple[str, list[str]]]:
        """The services node ``node_name`` in ``node_namespace`` has clients for."""
        return self._names_and_types_by_node(
            "client", self._transport.get_client_names_and_types_by_node,
            node_name, node_namespace)

    def count_services(self, service_name: str) -> int:
        """Servers of ``service_name`` (expanded in the node's namespace, not remapped)."""
        return self._transport.count_services(
            self.resolve_service_name(service_name, only_expand=True)
        )

    def count_clients(self, service_name: str) -> int:
        """Clients of ``service_name`` (expanded in the node's namespace, not remapped)."""
        return self._transport.count_clients(
            self.resolve_service_name(service_name, only_expand=True)
        )

    def get_node_names(self) -> list[str]:
        """The names (without namespace) of the nodes on the graph, this one included."""
        return [name for name, _ in self.get_node_names_and_namespaces()]

    def get_node_names_and_namespaces(self) -> list[tuple[str, str]]:
        """``(name, namespace)`` of every node on the graph (namespace ``/`` for the root)."""
        self._check_handle()
        return self._transport.get_node_names_and_namespaces()

    def get_node_names_and_namespaces_with_enclaves(self) -> list[tuple[str, str, str]]:
        """``(name, namespace, enclave)`` of every node on the graph."""
        self._check_handle()
        return self._transport.get_node_names_and_namespaces_with_enclaves()

    def get_fully_qualified_node_names(self) -> list[str]:
        """``/namespace/name`` of every node on the graph."""
        return [ns + ("" if ns.endswith("/") else "/") + name
                for name, ns in self.get_node_names_and_namespaces()]

    def wait_for_node(self, fully_qualified_node_name: str, timeout: float) -> bool:
        """Wait up to ``timeout`` wall seconds for the node to be on the graph; True if it is.

        A name without a leading ``/`` is taken as absolute. As rclpy's, it looks every
        0.1 s, and a timeout <= 0 returns False at once (rclpy's docstring says a negative
        one waits forever; its code does not).
        """
        import time

        if not fully_qualified_node_name.startswith("/"):
            fully_qualified_node_name = "/" + fully_qualified_node_name
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline:
            self._transport.sync_graph(min(0.1, max(0.0, deadline - time.monotonic())))
            if fully_qualified_node_name in self.get_fully_qualified_node_names():
                return True
            time.sleep(min(0.1, max(0.0, deadline - time.monotonic())))
        return False

    def _info_by_topic(self, topic_name: str, no_mangle: bool, publishers: bool
                       ) -> list[TopicEndpointInfo]:
        from posekit.runtime.topic_endpoint_info import (
            TopicEndpointTypeEnum,
            endpoint_info_from_record,
        )

        self._check_handle()
        topic = topic_name if no_mangle else self.resolve_topic_name(topic_name)
        if publishers:
            records = self._transport.get_publishers_info_by_topic(topic)
            kind = TopicEndpointTypeEnum.PUBLISHER
        else:
            records = self._transport.get_subscriptions_info_by_topic(topic)
            kind = TopicEndpointTypeEnum.SUBSCRIPTION
        return [endpoint_info_from_record(record, kind) for record in records]

    def get_publishers_info_by_topic(self, topic_name: str, no_mangle: bool = False
                                     ) -> list[TopicEndpointInfo]:
        """rclpy's TopicEndpointInfo of every publisher on ``topic_name``.

        The name is expanded and remapped as the node's own topics (``no_mangle``: taken as
        it is). The QoS is what the transport reports: in process the profile the publisher
        was made with, with unset durations shown as infinite, as middlewares report them.
        """
        return self._info_by_topic(topic_name, no_mangle, publishers=True)

    def get_subscriptions_info_by_topic(self, topic_name: str, no_mangle: bool = False
                                        ) -> list[TopicEndpointInfo]:
        """rclpy's TopicEndpointInfo of every subscription on ``topic_name``."""
        return self._info_by_topic(topic_name, no_mangle, publishers=False)

    def count_publishers(self, topic_name: str) -> int:
        """Publishers on ``topic_name`` (expanded and remapped like the node's own topics)."""
        self._check_handle()
        return self._transport.count_publishers(self.resolve_topic_name(topic_name))

    def count_subscribers(self, topic_name: str) -> int:
        """Subscriptions on ``topic_name``."""
        self._check_handle()
        return self._transport.count_subscribers(self.resolve_topic_name(topic_name))

    # -- parameters -------------------------------------------------------------------
    def _publish_parameter_event(self, event: ParameterEvent) -> None:
        event.node = self.get_fully_qualified_name()
        sec, nanosec = divmod(self._clock.now_ns(), 1_000_000_000)
        event.stamp.sec, event.stamp.nanosec = sec, nanosec
        self._parameter_event_publisher.publish(event)

    def _check_use_sim_time(self, params: list[Parameter]) -> SetParametersResult:
        for p in params:
            if p.name == "use_sim_time" and p.type_ != Parameter.Type.BOOL:
                return SetParametersResult(
                    successful=False, reason="use_sim_time parameter must be a boolean"
                )
        return SetParametersResult(successful=True)

    def _on_parameters_set(self, params: list[Parameter]) -> None:
        for p in params:
            if p.name == "use_sim_time":
                self._time_source.ros_time_is_active = bool(p.value)
                self.handoff.entities_changed()  # its timers may change clocks of record

    def declare_parameter(
        self,
        name: str,
        value: Any = None,
        descriptor: ParameterDescriptor | None = None,
        ignore_override: bool = False,
    ) -> Parameter:
        """Declare ``name`` with a default value (or a ``Parameter.Type``) and return the parameter.

        A launch or override value wins (rclpy's rules, see :mod:`posekit.runtime.parameters`).
        """
        return self._parameters.declare(name, value, descriptor, ignore_override)

    def declare_parameters(
        self,
        namespace: str,
        parameters: Sequence[tuple[Any, ...]],
        ignore_override: bool = False,
    ) -> list[Parameter]:
        """Declare ``(name[, value[, descriptor]])`` tuples under ``namespace.``."""
        return self._parameters.declare_many(namespace, parameters, ignore_override)

    def undeclare_parameter(self, name: str) -> None:
        """Remove a declared parameter (ParameterImmutableException if read-only)."""
        self._parameters.undeclare(name)

    def has_parameter(self, name: str) -> bool:
        """Whether ``name`` is declared."""
        return self._parameters.has(name)

    def get_parameter(self, name: str) -> Parameter:
        """The declared parameter (``.value`` holds the value)."""
        return self._parameters.get(name)

    def get_parameters(self, names: Sequence[str]) -> list[Parameter]:
        """Several declared parameters."""
        if not all(isinstance(n, str) for n in names):
            raise TypeError("All names must be instances of type str")
        return [self._parameters.get(n) for n in names]

    def get_parameter_or(self, name: str, alternative_value: Parameter | None = None) -> Parameter:
        """The parameter if declared and set, else ``alternative_value`` (or a NOT_SET one)."""
        return self._parameters.get_or(name, alternative_value)

    def get_parameter_type(self, name: str) -> Any:
        """The ParameterType constant (an int) of a declared parameter.

        ``Type.NOT_SET`` for an undeclared one when undeclared parameters are allowed (as
        rclpy).
        """
        return self._parameters.get_type(name)

    def get_parameter_types(self, names: Sequence[str]) -> list[Any]:
        """ParameterType constants of several declared parameters."""
        if not all(isinstance(n, str) for n in names):
            raise TypeError("All names must be instances of type str")
        return [self._parameters.get_type(n) for n in names]

    def get_parameters_by_prefix(self, prefix: str) -> dict[str, Parameter]:
        """Declared parameters under ``prefix.`` keyed by the rest of the name."""
        pre = prefix + "." if prefix else ""
        return {n[len(pre):]: p for n, p in self._parameters.items() if n.startswith(pre)}

    def list_parameters(self, prefixes: list[str], depth: int) -> ListParametersResult:
        """Names (and their prefixes) under ``prefixes`` down to ``depth`` levels (0: all)."""
        return self._parameters.list_names(prefixes, depth)

    def set_parameters(self, parameter_list: Sequence[Parameter]) -> list[SetParametersResult]:
        """Set each parameter; one result per parameter (undeclared names raise)."""
        return self._parameters.set(parameter_list)

    def set_parameters_atomically(self, parameter_list: Sequence[Parameter]) -> SetParametersResult:
        """Set all or none."""
        return self._parameters.set_atomically(parameter_list)

    def describe_parameter(self, name: str) -> ParameterDescriptor:
        """The descriptor of a declared parameter."""
        return self._parameters.descriptor(name)

    def set_descriptor(
        self,
        name: str,
        descriptor: ParameterDescriptor,
        alternative_value: ParameterValue | None = None,
    ) -> ParameterValue:
        """Give a declared parameter a new descriptor; returns the value afterwards.

        If its value does not fit the descriptor, ``alternative_value`` is used
        (InvalidParameterValueException if that does not fit either).
        """
        return self._parameters.set_descriptor(name, descriptor, alternative_value)

    def describe_parameters(self, names: Sequence[str]) -> list[ParameterDescriptor]:
        """Descriptors of several declared parameters."""
        return [self._parameters.descriptor(n) for n in names]

    def add_pre_set_parameters_callback(self, callback: PreSetCallback) -> None:
        """Rewrite the list of parameters about to be set (before validation)."""
        self._parameters.add_pre_set(callback)

    def remove_pre_set_parameters_callback(self, callback: PreSetCallback) -> None:
        """Undo add_pre_set_parameters_callback."""
        self._parameters.remove_pre_set(callback)

    def add_on_set_parameters_callback(self, callback: OnSetCallback) -> None:
        """Validate (and possibly refuse) parameter changes."""
        self._parameters.add_on_set(callback)

    def remove_on_set_parameters_callback(self, callback: OnSetCallback) -> None:
        """Undo add_on_set_parameters_callback."""
        self._parameters.remove_on_set(callback)

    def add_post_set_parameters_callback(self, callback: PostSetCallback) -> None:
        """React to parameters that were set (after they changed)."""
        self._parameters.add_post_set(callback)

    def remove_post_set_parameters_callback(self, callback: PostSetCallback) -> None:
        """Undo add_post_set_parameters_callback."""
        self._parameters.remove_post_set(callback)

    def __repr__(self) -> str:
        return f"Node('{self._fqn()}')"
