"""The small interface between nodes and whatever carries their messages.

A :class:`Transport` connects publishers to subscriptions on named topics and answers graph
questions. Nodes only use this interface, so a transport that crosses processes (Zenoh,
later) plugs in without touching node or executor code. The default is
:class:`posekit.runtime.bus.InProcessBus` (name ``"inprocess"``).

Contract for implementations:

* ``advertise(info)`` returns a :class:`PublisherEndpoint`; ``publish(msg)`` must not keep a
  reference the caller could later mutate (the in-process bus snapshots, a network transport
  serializes). ``publish_transfer(msg)`` is the same for a message the caller gives up
  (rclcpp's ``publish(std::unique_ptr)``): a transport may keep and deliver that object;
  the default implementation calls ``publish``.
* ``subscribe(info, sink)`` returns a :class:`SubscriptionEndpoint`; the transport calls
  ``sink(msg)`` once per delivered message with an object this subscription owns, possibly
  from another thread and possibly before ``subscribe`` returns (TRANSIENT_LOCAL history).
  Queueing, depth, ordering and callbacks are the runtime's job, not the transport's.
  Optionally an endpoint lets an executor read it on the executor's own thread
  (``pull_into(inbox)`` / ``release_pull(inbox)``, the DDS transport does): the sink is then
  called from the executor's ``pull(budget)`` calls instead of a transport thread.
* QoS matching (reliability / durability offer vs request) is the transport's job; it should
  log incompatible pairs on ``info.logger``.
* ``info.remote_only`` (network transports): the endpoint matches endpoints of *other*
  processes/sessions only. A remote-only publisher is not delivered to this process's
  subscriptions, a remote-only subscription does not receive this process's publications,
  and their ``subscription_count`` / ``publisher_count`` count remote matches only. The
  in-process bus ignores it (everything on it is local). This is what
  :class:`posekit.runtime.mirror.MirroredTransport` builds on.
* ``crosses_processes`` says whether the endpoints are visible to other processes (a network
  transport). A :class:`~posekit.runtime.sim_executor.SimulatedTimeExecutor` publishes
  ``/clock`` exactly when one of its nodes sits on such a transport. Such a transport learns
  the graph from the network, so its view completes over time: ``sync_graph(timeout)`` waits
  for it (the base class returns at once: a process-local graph is always complete).
* Optional graph capabilities are declared on the base class with defaults that say "this
  transport cannot tell", so callers call them instead of probing for them:
  ``publisher_qos_profiles(topic)`` (None), ``get_node_names()``,
  ``get_publishers_info_by_topic(topic)`` / ``get_subscriptions_info_by_topic(topic)``
  (endpoint records with ``node_fqn``, ``ros_type`` and ``qos``, as rclpy's node methods of
  those names) and ``graph_entities()`` (every node and endpoint record, with ``kind``) all
  return ``[]``; ``graph_description()`` names the graph for a user ("the zenoh graph");
  ``own_topic(topic)`` does nothing (a mirrored transport keeps that topic from being taken
  from other processes).
* ``subscribe_with_source(info, sink)`` is ``subscribe`` whose sink also gets an opaque id of
  the sending publisher (bytes, e.g. rmw_zenoh's GID) or None when the transport cannot tell;
  nodes following ``/clock`` use it to ignore a second clock source. The default passes None.
* Services are an optional capability (``supports_services``). ``create_service_server(info,
  sink)`` returns a :class:`ServiceServerEndpoint`; the transport calls ``sink(request,
  respond, header)`` once per request (an object the server owns; ``header`` is the
  :class:`RequestHeader` naming the calling client and its request), and the runtime calls
  ``respond(response)`` exactly once, from any thread, possibly later. A client's
  ``send_request(request, on_response, header)`` (:class:`ServiceClientEndpoint`) delivers the
  request to one server with ``header`` (or a header of its own numbering when None) and
  calls ``on_response(response)`` at most once; its ``gid`` is the client's 16-byte id and
  its ``server_count`` is what ``wait_for_service`` polls. ``get_service_names_and_types``,
  ``..._by_node``, ``count_services`` and ``count_clients`` answer graph questions. The base
  class raises :class:`ServicesNotSupportedError` from the two factories (and reports an empty
  service graph), so a transport without services says so.

Selection: ``Node(..., transport="zenoh")`` (or ``"dds"``), else ``init(transport=...)`` of
the context, else the ``POSEKIT_TRANSPORT`` environment variable, else ``"inprocess"``. Names
map to factories in a registry (:func:`register_transport`); each context creates one instance per
name and shares it among its nodes. ``"inprocess+NET"`` (e.g. ``inprocess+zenoh``) is the
in-process bus mirrored onto the network transport ``NET``
(:class:`~posekit.runtime.mirror.MirroredTransport`).
"""

from __future__ import annotations

import importlib
import os
from abc import ABC, abstractmethod
from collections.abc import Callable
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

from posekit.msgs.errors import UnknownMessageTypeError
from posekit.msgs.registry import message_type_name
from posekit.runtime.logging import RcutilsLogger
from posekit.runtime.qos import QoSProfile, to_qos_profile

if TYPE_CHECKING:
    from posekit.runtime.inbox import Inbox

__all__ = [
    "ENV_TRANSPORT",
    "EndpointInfo",
    "GraphEndpoint",
    "MessageSink",
    "PublisherEndpoint",
    "RequestHeader",
    "RequestSink",
    "ResponseSink",
    "ServiceClientEndpoint",
    "ServiceInfo",
    "ServiceServerEndpoint",
    "ServicesNotSupportedError",
    "SourcedMessageSink",
    "SubscriptionEndpoint",
    "TopicTypeMismatchError",
    "Transport",
    "UnknownTransportError",
    "create_transport",
    "register_transport",
    "registered_transports",
    "selected_transport_name",
]

ENV_TRANSPORT = "POSEKIT_TRANSPORT"

MessageSink = Callable[[Any], None]
#: ``sink(msg, source)``: ``source`` identifies the sending publisher (bytes) or is None.
SourcedMessageSink = Callable[[Any, bytes | None], None]
#: ``on_response(response)``: a client's reply sink.
ResponseSink = Callable[[Any], None]


@dataclass(frozen=True, slots=True)
class RequestHeader:
    """Who sent a request: rmw's request id, as a server takes it with the request.

    ``client_gid`` is the calling client's 16-byte id (its rmw GID), ``sequence_number`` the
    client's number for this request (1, 2, ... per client).
    """

    client_gid: bytes
    sequence_number: int


#: ``sink(request, respond, header)``: a server's request sink; ``respond(response)`` answers
#: it, ``header`` says which client sent it.
RequestSink = Callable[[Any, ResponseSink, RequestHeader], None]


class ServicesNotSupportedError(NotImplementedError):
    """The selected transport carries topics only (no service servers or clients)."""


class TopicTypeMismatchError(TypeError):
    """An endpoint was created on a topic that already carries another message type."""


class UnknownTransportError(ValueError):
    """No transport is registered under the requested name."""


@dataclass(frozen=True, slots=True)
class EndpointInfo:
    """Who creates an endpoint, on which (fully qualified) topic, with what type and QoS."""

    topic: str
    msg_type: type
    qos: QoSProfile
    node_name: str
    node_namespace: str
    logger: RcutilsLogger
    #: Match endpoints of other processes only (see the module docstring).
    remote_only: bool = False

    def __post_init__(self) -> None:
        # A profile is mutable (rclpy's); the transport keeps its own copy, as rcl does.
        object.__setattr__(self, "qos", to_qos_profile(self.qos).copy())

    @property
    def type_name(self) -> str:
        """The ROS type name, e.g. ``tf2_msgs/msg/TFMessage``.

        As :func:`posekit.msgs.message_type_name` gives it. A class that is no ROS message (the
        in-process bus carries any class) is named by its qualified Python name.
        """
        try:
            return message_type_name(self.msg_type)
        except UnknownMessageTypeError:
            return f"{self.msg_type.__module__}.{self.msg_type.__qualname__}"


@dataclass(frozen=True, slots=True, eq=False)
class GraphEndpoint:
    """A publisher or subscription as the in-process bus reports it on its graph.

    The attribute names are those of the network transports' records (Zenoh's ``TokenInfo``,
    DDS's ``DdsEndpoint``), so one conversion serves all
    (:func:`posekit.runtime.topic_endpoint_info.endpoint_info_from_record`).
    """

    node_name: str
    namespace: str
    topic: str
    ros_type: str
    #: ``RIHS01_<64 hex>``, None when unknown (no ROS message, or no rosbags to compute it).
    type_hash: str | None
    qos: QoSProfile
    #: The endpoint's 16-byte id (random per endpoint, as an rmw GID).
    gid: bytes

    @property
    def node_fqn(self) -> str:
        """``/namespace/node``."""
        return f"{self.namespace.rstrip('/')}/{self.node_name}"


@dataclass(frozen=True, slots=True)
class ServiceInfo:
    """Who creates a service server or client, on which service name, with what type and QoS.

    The name is fully qualified; the type is a service class such as ``SetBool``, with
    ``Request``/``Response``.
    """

    service: str
    srv_type: type
    qos: QoSProfile
    node_name: str
    node_namespace: str
    logger: RcutilsLogger

    def __post_init__(self) -> None:
        object.__setattr__(self, "qos", to_qos_profile(self.qos).copy())  # as EndpointInfo

    @property
    def type_name(self) -> str:
        """The ROS service type name, e.g. ``std_srvs/srv/SetBool``."""
        name = getattr(self.srv_type, "__srvtype__", None)
        if isinstance(name, str):
            return name
        return f"{self.srv_type.__module__}.{self.srv_type.__qualname__}"

    def require_ros_service(self, transport: str) -> None:
        """Raise TypeError unless the type is a ROS service (what network transports carry)."""
        if not isinstance(getattr(self.srv_type, "__srvtype__", None), str):
            raise TypeError(
                f"the {transport} transport carries ROS services only; {self.srv_type!r} on "
                f"'{self.service}' has no __srvtype__"
            )


class ServiceServerEndpoint(ABC):
    """A service server's handle on the transport."""

    @abstractmethod
    def destroy(self) -> None:
        """Leave the graph; no further requests are delivered."""


class ServiceClientEndpoint(ABC):
    """A service client's handle on the transport."""

    @abstractmethod
    def send_request(self, request: Any, on_response: ResponseSink,
                     header: RequestHeader | None = None) -> None:
        """Send ``request`` to one server; ``on_response(response)`` at most once.

        ``on_response`` may run on the transport's own receive thread: it must not block.
        The server learns ``header`` (this client's gid and the request's number); when None
        the endpoint numbers the request itself.
        """

    @property
    @abstractmethod
    def gid(self) -> bytes:
        """This client's 16-byte id (rmw's client GID), what servers see as the caller."""

    @property
    @abstractmethod
    def server_count(self) -> int:
        """How many servers of this service (with this type) are known now."""

    @abstractmethod
    def destroy(self) -> None:
        """Leave the graph; pending responses are dropped."""


class PublisherEndpoint(ABC):
    """A publisher's handle on the transport."""

    @abstractmethod
    def publish(self, msg: Any) -> None:
        """Send ``msg`` to every matched subscription."""

    def publish_transfer(self, msg: Any) -> None:
        """Send ``msg``, which the caller hands over and never touches again.

        A transport may therefore deliver this very object instead of a copy. Default:
        :meth:`publish`.
        """
        self.publish(msg)

    @abstractmethod
    def destroy(self) -> None:
        """Leave the graph; further publish() calls raise."""

    @property
    @abstractmethod
    def subscription_count(self) -> int:
        """How many matched subscriptions there are now."""


class SubscriptionEndpoint(ABC):
    """A subscription's handle on the transport."""

    @abstractmethod
    def destroy(self) -> None:
        """Leave the graph; the sink is not called afterwards."""

    def pull_into(self, inbox: Inbox) -> bool:
        """Let the executor of ``inbox`` take this endpoint's samples on its own thread.

        On True the transport stopped delivering from its own thread, registered this
        endpoint with ``inbox.add_source`` (the executor calls ``pull(budget)``, which hands
        samples to the sink on the calling thread) and made the inbox wait on a waiter its
        data wakes (``inbox.adopt_waiter``). The default says no: the transport keeps
        delivering on its own.
        """
        del inbox
        return False

    def release_pull(self, inbox: Inbox) -> None:
        """Undo :meth:`pull_into`: deliver from the transport's own thread again.

        Nothing once destroyed. Samples not yet pulled are delivered, not lost.
        """
        del inbox

    @property
    @abstractmethod
    def publisher_count(self) -> int:
        """How many matched publishers there are now."""


class Transport(ABC):
    """Carries messages between endpoints (see the module docstring for the contract)."""

    name: str = "abstract"
    #: Whether other processes see (and can talk to) this transport's endpoints.
    crosses_processes: bool = False

    @abstractmethod
    def advertise(self, info: EndpointInfo) -> PublisherEndpoint:
        """Create a publisher endpoint."""

    @abstractmethod
    def subscribe(self, info: EndpointInfo, sink: MessageSink) -> SubscriptionEndpoint:
        """Create a subscription endpoint delivering to ``sink``."""

    def subscribe_with_source(
        self, info: EndpointInfo, sink: SourcedMessageSink
    ) -> SubscriptionEndpoint:
        """:meth:`subscribe`, calling ``sink(msg, source)`` with the sending publisher's id.

        The default passes None: the transport cannot tell publishers apart.
        """
        return self.subscribe(info, lambda msg: sink(msg, None))

    @abstractmethod
    def get_topic_names_and_types(self) -> list[tuple[str, list[str]]]:
        """Every topic with at least one endpoint, sorted, with its type names."""

    @abstractmethod
    def count_publishers(self, topic: str) -> int:
        """Publishers on a fully qualified topic."""

    @abstractmethod
    def count_subscribers(self, topic: str) -> int:
        """Subscriptions on a fully qualified topic."""

    def publisher_qos_profiles(self, topic: str) -> list[QoSProfile] | None:
        """The QoS each publisher on ``topic`` offers, or None when this transport cannot tell.

        One profile per publisher, as far as the graph tells: reliability, durability, history
        and depth (default: None). Passive observers subscribe with a profile every offer
        matches (:mod:`posekit.runtime.observe`).
        """
        return None

    #: Whether :meth:`create_service_server` / :meth:`create_service_client` work.
    supports_services: bool = False

    def _no_services(self) -> ServicesNotSupportedError:
        return ServicesNotSupportedError(
            f"the '{self.name}' transport does not carry services "
            "(posekit's 'inprocess', 'zenoh' and 'dds' transports do)"
        )

    def create_service_server(self, info: ServiceInfo, sink: RequestSink) -> ServiceServerEndpoint:
        """Create a service server endpoint delivering requests to ``sink``."""
        raise self._no_services()

    def create_service_client(self, info: ServiceInfo) -> ServiceClientEndpoint:
        """Create a service client endpoint."""
        raise self._no_services()

    def get_service_names_and_types(self) -> list[tuple[str, list[str]]]:
        """Every service with at least one server or client, sorted, with its type names."""
        return []

    def get_service_names_and_types_by_node(
        self, node_name: str, node_namespace: str
    ) -> list[tuple[str, list[str]]]:
        """The services a node serves (its servers, as rcl reports them)."""
        return []

    def count_services(self, service: str) -> int:
        """Servers of a fully qualified service name."""
        return 0

    def count_clients(self, service: str) -> int:
        """Clients of a fully qualified service name."""
        return 0

    def get_client_names_and_types_by_node(
        self, node_name: str, node_namespace: str
    ) -> list[tuple[str, list[str]]]:
        """The services a node has clients for."""
        return []

    def get_publisher_names_and_types_by_node(
        self, node_name: str, node_namespace: str
    ) -> list[tuple[str, list[str]]]:
        """The topics a node publishes, sorted, with their type names; default: none known."""
        return []

    def get_subscriber_names_and_types_by_node(
        self, node_name: str, node_namespace: str
    ) -> list[tuple[str, list[str]]]:
        """The topics a node subscribes to, sorted, with their type names."""
        return []

    # -- optional graph capabilities (defaults: the transport cannot tell) ----------------
    def get_node_names(self) -> list[str]:
        """Fully qualified names of the nodes on the graph (duplicates kept), sorted.

        Default: none known.
        """
        return []

    def get_node_names_and_namespaces(self) -> list[tuple[str, str]]:
        """``(name, namespace)`` of every node on the graph (duplicates kept), sorted.

        Default: split from :meth:`get_node_names`.
        """
        pairs = []
        for fqn in self.get_node_names():
            namespace, _, name = fqn.rpartition("/")
            pairs.append((name, namespace or "/"))
        return sorted(pairs)

    def get_node_names_and_namespaces_with_enclaves(self) -> list[tuple[str, str, str]]:
        """``(name, namespace, enclave)`` of every node; default: the root enclave ``/``."""
        return [(name, ns, "/") for name, ns in self.get_node_names_and_namespaces()]

    def get_publishers_info_by_topic(self, topic: str) -> list[Any]:
        """Records of the publishers on ``topic``, each like :class:`GraphEndpoint`.

        ``node_name``, ``namespace``, ``ros_type``, ``type_hash`` (``RIHS01_...`` or None),
        ``qos`` (a profile, or a wire QoS with ``to_profile(exact=...)``), ``gid`` (bytes); the
        node's ``get_publishers_info_by_topic`` turns them into rclpy's TopicEndpointInfo
        (:mod:`posekit.runtime.topic_endpoint_info`). Default: none known.
        """
        return []

    def get_subscriptions_info_by_topic(self, topic: str) -> list[Any]:
        """Records of the subscriptions on ``topic``; default: none known."""
        return []

    def graph_entities(self) -> list[Any]:
        """Every node and endpoint on the graph, as records.

        Each record has ``kind`` (:class:`~posekit.transport.zenoh_wire.EntityKind`),
        ``node_fqn``, ``topic`` and ``ros_type`` (duplicates kept). Default: none known.
        """
        return []

    def sync_graph(self, timeout: float = 2.0) -> int:
        """Complete this transport's view of the graph; returns a graph generation.

        Waits at most ``timeout`` s (a network transport asks its peers). Default: returns 0 at
        once (a process-local graph is always complete).
        """
        return 0

    def graph_description(self) -> str:
        """Where this transport's graph is, for a user-facing line ("the zenoh graph")."""
        return f"the {self.name} graph"

    def own_topic(self, topic: str) -> None:  # noqa: B027 - optional
        """Keep ``topic`` from being taken from other processes.

        For a mirrored transport (see :class:`~posekit.runtime.mirror.MirroredTransport`);
        default: nothing to keep.
        """

    def declare_node(self, name: str, namespace: str = "/") -> Any:  # noqa: B027 - optional
        """Announce a node on the graph (called by ``Node.__init__``); default: nothing."""

    def undeclare_node(self, name: str, namespace: str = "/") -> None:  # noqa: B027 - optional
        """Withdraw one :meth:`declare_node` (called by ``Node.destroy_node``)."""

    def close(self) -> None:  # noqa: B027 - optional hook
        """Release resources (called by Context.shutdown)."""


TransportFactory = Callable[[], Transport]
_registry: dict[str, TransportFactory | str] = {
    "inprocess": "posekit.runtime.bus:InProcessBus",
    # Registered lazily by name so importing the runtime never imports zenoh or cyclonedds.
    "zenoh": "posekit.transport.zenoh:ZenohTransport",
    "dds": "posekit.transport.dds_transport:DdsTransport",
}


def register_transport(name: str, factory: TransportFactory | str) -> None:
    """Make ``name`` selectable; ``factory`` is a callable or a ``"module:attr"`` string."""
    _registry[name] = factory


def registered_transports() -> list[str]:
    """The selectable transport names."""
    return sorted(_registry)


def selected_transport_name(explicit: str | None = None) -> str:
    """``explicit`` if given, else $POSEKIT_TRANSPORT, else ``"inprocess"``."""
    if explicit:
        return explicit
    return os.environ.get(ENV_TRANSPORT, "").strip() or "inprocess"


def create_transport(name: str) -> Transport:
    """Instantiate the transport registered as ``name``."""
    local_name, plus, network_name = name.partition("+")
    if plus and local_name == "inprocess" and network_name and network_name != "inprocess":
        from posekit.runtime.bus import InProcessBus
        from posekit.runtime.mirror import MirroredTransport

        return MirroredTransport(InProcessBus(), create_transport(network_name))
    factory = _registry.get(name)
    if factory is None:
        raise UnknownTransportError(
            f"unknown transport {name!r} (from {ENV_TRANSPORT} or a node/context option); "
            f"known: {', '.join(registered_transports())}"
        )
    if isinstance(factory, str):
        module_name, _, attr = factory.partition(":")
        try:
            module = importlib.import_module(module_name)
        except ImportError as exc:
            # The built-in network transports come with an extra of the same name.
            hint = f" (pip install 'posekit[{name}]')" if name in ("zenoh", "dds") else ""
            raise UnknownTransportError(
                f"transport {name!r} is not available: {exc}{hint}"
            ) from exc
        factory = getattr(module, attr)
    transport = factory()
    if not isinstance(transport, Transport):
        raise TypeError(f"transport factory for {name!r} returned {transport!r}")
    return transport
