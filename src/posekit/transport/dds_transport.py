"""The runtime's :class:`~posekit.runtime.transport.Transport` over DDS (Eclipse Cyclone DDS).

Interoperable with real ROS 2 nodes on rmw_fastrtps or rmw_cyclonedds.

Select it with ``POSEKIT_TRANSPORT=dds``, ``init(transport="dds")``,
``Node(..., transport="dds")`` or ``--transport dds`` on the command-line tools. One DDS
participant per context (as rmw does); its nodes are announced on ``ros_discovery_info``.
The ROS 2 mapping (topic and type names, USER_DATA, discovery settings, graph messages) is
in :mod:`posekit.transport.dds_wire`; the Cyclone topic types in
:mod:`posekit.transport.dds_types`.

QoS, policy by policy as rmw_cyclonedds sets it: history (KEEP_LAST depth / KEEP_ALL),
reliability (RELIABLE / BEST_EFFORT), durability (VOLATILE / TRANSIENT_LOCAL, with a
durability service keeping the last ``depth`` samples for late joiners), liveliness
AUTOMATIC with an infinite lease, writer auto-dispose off, XCDR1 data representation, and
``typehash=RIHS01_...;`` in each endpoint's USER_DATA. One difference: a reliable writer
blocks at most 100 ms when its readers fall behind (rmw waits forever) and then drops that
sample with one logged warning, so a stalled peer never blocks a posekit node.

Rejections are logged once with the reason and never stop the node: a sample that does not
decode, a QoS incompatibility in either direction (DDS refuses the pair; the subscription or
the publisher logs ROS 2's "incompatible QoS" warning) and another endpoint on the same topic
with a different type.

Environment: ``ROS_DOMAIN_ID``, ``ROS_AUTOMATIC_DISCOVERY_RANGE`` (default ``LOCALHOST``),
``ROS_STATIC_PEERS``, ``CYCLONEDDS_URI`` (appended to posekit's configuration).
"""

from __future__ import annotations

import itertools
import logging
import threading
import time
import weakref
from collections.abc import Callable
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

from cyclonedds._clayer import ddspy_take, ddspy_write
from cyclonedds.builtin import (
    BuiltinDataReader,
    BuiltinTopicDcpsParticipant,
    BuiltinTopicDcpsPublication,
    BuiltinTopicDcpsSubscription,
)
from cyclonedds.core import (
    DDSException,
    DDSStatus,
    GuardCondition,
    InstanceState,
    ReadCondition,
    SampleState,
    ViewState,
    WaitSet,
)
from cyclonedds.domain import Domain, DomainParticipant
from cyclonedds.pub import DataWriter
from cyclonedds.qos import Policy, Qos
from cyclonedds.sub import DataReader
from cyclonedds.topic import Topic
from cyclonedds.util import duration

from posekit.msgs.cdr import cdr_decoder, to_cdr
from posekit.msgs.errors import CdrError
from posekit.runtime.inbox import Inbox
from posekit.runtime.qos import DurabilityPolicy, HistoryPolicy, QoSProfile, ReliabilityPolicy
from posekit.runtime.ratelimit import RateLimitedLog
from posekit.runtime.transport import (
    EndpointInfo,
    MessageSink,
    PublisherEndpoint,
    RequestSink,
    ServiceClientEndpoint,
    ServiceInfo,
    ServiceServerEndpoint,
    SourcedMessageSink,
    SubscriptionEndpoint,
    TopicTypeMismatchError,
    Transport,
)
from posekit.transport.dds_types import idl_struct
from posekit.transport.dds_wire import (
    DISCOVERY_TOPIC,
    DISCOVERY_TYPE,
    DdsEndpoint,
    DdsNode,
    DiscoveryOptions,
    NodeEntities,
    ParticipantEntities,
    client_service_id,
    cyclone_config,
    dds_topic_name,
    dds_type_name,
    decode_participant_entities,
    encode_participant_entities,
    parse_user_data,
    ros_service_name,
    ros_service_type,
    ros_topic_name,
    ros_type_name,
    service_topic_names,
    user_data_type_hash,
)
from posekit.transport.zenoh_wire import EntityKind, WireQoS, type_hash

if TYPE_CHECKING:
    from posekit.transport.dds_services import ServiceDispatcher, _ServiceEndpoints

__all__ = ["DdsTransport", "configure_domain", "endpoint_qos", "wire_qos_of"]

_log = logging.getLogger("posekit.transport.dds")

#: cyclonedds-python turns a C QoS into Python through class-level scratch buffers
#: (``cyclonedds.qos._CQos``), so two threads converting at once can read memory the other
#: freed (a segmentation fault). Every such conversion (a built-in topic read, a matched
#: endpoint's data) holds this lock.
QOS_CONVERSION_LOCK = threading.Lock()
_ANY = SampleState.Any | ViewState.Any | InstanceState.Any
_ALIVE = int(InstanceState.Alive)
_MAX_BLOCKING = duration(milliseconds=100)
_INFINITE = (9223372036, 854775807)
_TAKE_BATCH = 64
_WAIT_FOREVER_NS = 2**63 - 1  # Cyclone's DDS_INFINITY
# Cyclone's dds_qos_policy_id_t, for naming the policy in incompatibility reports.
_POLICY_NAMES = {
    1: "USER_DATA", 2: "DURABILITY", 3: "PRESENTATION", 4: "DEADLINE", 5: "LATENCY_BUDGET",
    6: "OWNERSHIP", 7: "OWNERSHIP_STRENGTH", 8: "LIVELINESS", 9: "TIME_BASED_FILTER",
    10: "PARTITION", 11: "RELIABILITY", 12: "DESTINATION_ORDER", 13: "HISTORY",
    14: "RESOURCE_LIMITS", 16: "WRITER_DATA_LIFECYCLE", 21: "LIFESPAN", 22: "DURABILITY_SERVICE",
    24: "TYPE_CONSISTENCY_ENFORCEMENT", 25: "DATA_REPRESENTATION",
}

# Cyclone holds one configuration per domain id and process; posekit creates each once.
_domains_lock = threading.Lock()
_domains: dict[int, tuple[str, Domain]] = {}
#: Type-mismatch warnings remembered (each printed once) before the table starts over.
_MAX_WARNED_TYPES = 1024


def configure_domain(options: DiscoveryOptions) -> None:
    """Create the process's Cyclone domain for ``options.domain_id``, with posekit's discovery.

    Once per process and domain; later differing settings are logged.
    """
    config = cyclone_config(options)
    with _domains_lock:
        known = _domains.get(options.domain_id)
        if known is None:
            _domains[options.domain_id] = (config, Domain(options.domain_id, config))
        elif known[0] != config:
            _log.warning(
                "DDS domain %d is already configured in this process; keeping the first "
                "discovery settings", options.domain_id,
            )


def _ros_type(info: EndpointInfo) -> str:
    name = getattr(info.msg_type, "__msgtype__", None)
    if not isinstance(name, str):
        raise TypeError(
            f"the dds transport carries ROS messages only; {info.msg_type!r} on "
            f"'{info.topic}' has no __msgtype__"
        )
    return name


def endpoint_qos(qos: QoSProfile, user_data: bytes, *, writer: bool,
                 remote_only: bool = False) -> Qos:
    """Cyclone QoS for a ROS profile, policy by policy as rmw_cyclonedds maps it.

    ``remote_only`` adds IGNORE_LOCAL (participant): no matching within this participant
    (:attr:`EndpointInfo.remote_only`).
    """
    keep_all = qos.history == HistoryPolicy.KEEP_ALL
    depth = max(1, qos.depth)
    history = Policy.History.KeepAll if keep_all else Policy.History.KeepLast(depth)
    policies: list[Any] = [
        history,
        Policy.Reliability.BestEffort
        if qos.resolved_reliability == ReliabilityPolicy.BEST_EFFORT
        else Policy.Reliability.Reliable(_MAX_BLOCKING),
        Policy.Liveliness.Automatic(lease_duration=duration(infinite=True)),
        Policy.DataRepresentation(use_cdrv0_representation=True),
        Policy.Userdata(user_data),
    ]
    if qos.resolved_durability == DurabilityPolicy.TRANSIENT_LOCAL:
        policies.append(Policy.Durability.TransientLocal)
        if writer:
            policies.append(Policy.DurabilityService(
                cleanup_delay=0, history=history, max_samples=-1, max_instances=-1,
                max_samples_per_instance=-1,
            ))
    else:
        policies.append(Policy.Durability.Volatile)
    if writer:
        policies.append(Policy.WriterDataLifecycle(autodispose=False))
        if qos.lifespan_ns is not None:  # /rosout's 10 s, as rcl asks for it
            policies.append(Policy.Lifespan(lifespan=qos.lifespan_ns))
    if remote_only:
        policies.append(Policy.IgnoreLocal.Participant)
    return Qos(*policies)


def wire_qos_of(qos: Qos) -> WireQoS:
    """An announced endpoint's DDS QoS as rmw's integers (what ``topic info -v`` prints)."""

    def get(policy: Any) -> Any:
        try:
            return qos[policy]
        except (KeyError, TypeError):
            return None

    live = get(Policy.Liveliness)
    # RTPS discovery does not carry HISTORY: rmw reports it UNKNOWN (3), depth 0.
    return WireQoS(
        reliability=2 if get(Policy.Reliability) == Policy.Reliability.BestEffort else 1,
        durability=1 if get(Policy.Durability) == Policy.Durability.TransientLocal else 2,
        history=3,
        depth=0,
        liveliness=3 if isinstance(live, Policy.Liveliness.ManualByTopic) else 1,
        liveliness_lease=_duration_pair(getattr(live, "lease_duration", None)),
        deadline=_duration_pair(getattr(get(Policy.Deadline), "deadline", None)),
        lifespan=_duration_pair(getattr(get(Policy.Lifespan), "lifespan", None)),
    )


def _duration_pair(value: int | None) -> tuple[int, int]:
    if value is None or value >= 2**63 - 1 or value < 0:
        return _INFINITE
    return (value // 1_000_000_000, value % 1_000_000_000)


# ---------------------------------------------------------------------------------------
# Endpoints


class _Publisher(PublisherEndpoint):
    def __init__(self, owner: DdsTransport, info: EndpointInfo, ros_type: str,
                 writer: DataWriter[Any]) -> None:
        self._owner = owner
        self.info = info
        self.ros_type = ros_type
        self.writer = writer
        self.gid: bytes = writer.guid.bytes
        self._ref = writer._ref
        self._type = info.msg_type
        self._warned_timeout = False
        self._warned_qos: set[str] = set()
        self.alive = True

    def publish(self, msg: Any) -> None:
        if not self.alive:
            raise RuntimeError(f"publisher on '{self.info.topic}' has been destroyed")
        if type(msg) is not self._type and not isinstance(msg, self._type):
            raise TypeError(
                f"publisher on '{self.info.topic}' expects {self._type.__name__}, "
                f"got {type(msg).__name__}"
            )
        self.publish_serialized(to_cdr(msg, self.ros_type))

    def publish_serialized(self, data: bytes) -> None:
        """Write an already serialized CDR payload (encapsulation header included)."""
        ret = ddspy_write(self._ref, data)
        if ret < 0:
            if ret == -10 and not self._warned_timeout:  # DDS_RETCODE_TIMEOUT
                self._warned_timeout = True
                self.info.logger.warning(
                    f"publishing on '{self.info.topic}': a reliable subscription is not "
                    "keeping up; samples are dropped after 100 ms (logged once)"
                )
            elif ret != -10:
                raise RuntimeError(f"DDS write on '{self.info.topic}' failed (code {ret})")

    def report_incompatible(self) -> None:
        """Log (once per policy) that a subscription requests QoS this writer cannot offer."""
        status = self.writer.get_offered_incompatible_qos_status()  # type: ignore[no-untyped-call]
        policy = _POLICY_NAMES.get(int(getattr(status, "last_policy_id", 0)), "UNKNOWN")
        if policy in self._warned_qos:
            return
        self._warned_qos.add(policy)
        self.info.logger.warning(
            f"New subscription discovered on topic '{self.info.topic}', requesting "
            f"incompatible QoS. No messages will be sent to it. Last incompatible policy: "
            f"{policy}"
        )

    def destroy(self) -> None:
        if self.alive:
            self.alive = False
            self._owner._forget(self, self.writer)

    @property
    def subscription_count(self) -> int:
        try:
            return len(self.writer.get_matched_subscriptions())
        except Exception:  # deleted underneath (context shut down)
            return 0


class _Subscription(SubscriptionEndpoint):
    def __init__(self, owner: DdsTransport, info: EndpointInfo, ros_type: str,
                 sink: MessageSink, sourced: SourcedMessageSink | None = None) -> None:
        self._owner = owner
        self.info = info
        self.ros_type = ros_type
        self._sink = sink
        self._sourced = sourced
        self._decode = cdr_decoder(info.msg_type)
        self.reader: DataReader[Any] | None = None
        self.gid = b""
        self.alive = True
        self.received = 0
        self.dropped = 0
        self._warned: set[str] = set()
        # Who delivers (own thread / an executor / nobody) changes under this lock: an
        # executor's thread and a context shutdown may switch it at the same time.
        self._mode_lock = threading.RLock()

    def warn_once(self, tag: str, text: str) -> None:
        if tag in self._warned:
            return
        self._warned.add(tag)
        try:
            self.info.logger.warning(text)
        except Exception:  # a broken logger must not kill Cyclone's thread
            _log.exception("warning callback failed")

    def start(self, participant: DomainParticipant, reader: DataReader[Any]) -> None:
        """Deliver on a thread of our own, woken by Cyclone (until an executor pulls).

        No Cyclone listeners: those run Python on Cyclone's threads, which deadlocks against a
        write holding the GIL.
        """
        self.reader = reader
        self.gid = reader.guid.bytes
        self._participant = participant
        # data wakes this thread; QoS reports go to the transport's graph thread
        reader.set_status_mask(DDSStatus.RequestedIncompatibleQos)
        self._data = ReadCondition(reader, _ANY)
        self._thread: threading.Thread | None = None
        self._generation = 0  # of the delivery thread: a new one per start
        self._pulled_by: Inbox | None = None
        self._waiter: _DdsWaiter | None = None
        self._start_thread()

    def _start_thread(self) -> None:
        self._generation += 1
        self._waitset = WaitSet(self._participant)
        self._stop = GuardCondition(self._participant)
        self._waitset.attach(self._data)
        self._waitset.attach(self._stop)
        self._thread = threading.Thread(
            target=self._run, args=(self._generation,), name=f"posekit-dds {self.info.topic}",
            daemon=True)
        self._thread.start()

    def _stop_thread(self) -> None:
        thread, self._thread = self._thread, None
        if thread is None:
            return
        self._generation += 1
        self._stop.set(True)
        if thread is not threading.current_thread():
            thread.join(timeout=2.0)
        try:
            self._waitset.detach(self._data)
        except Exception as exc:  # already gone with its reader
            _log.debug("detaching %r: %s", self._data, exc)

    def _run(self, generation: int) -> None:
        reader = self.reader
        assert reader is not None
        ref, wait, timeout = reader._ref, self._waitset.wait, duration(seconds=1)
        while self.alive and self._generation == generation:
            try:
                wait(timeout)
                if not self.alive or self._generation != generation:
                    return
                self._drain(ref)
            except Exception as exc:  # keep delivering whatever arrives
                if not self.alive:
                    return
                self.warn_once("internal", f"subscription on '{self.info.topic}': "
                                           f"unexpected {type(exc).__name__}: {exc}")
                time.sleep(0.05)

    # -- an executor taking the samples on its own thread (Executor._pulls_samples) ------
    def pull_into(self, inbox: Inbox) -> bool:
        """Stop the delivery thread; ``inbox``'s executor takes the samples (:meth:`pull`).

        The executor then waits on a Cyclone wait set holding this reader's data condition.
        """
        with self._mode_lock:
            if not self.alive or self.reader is None or self._pulled_by is not None:
                return False
            waiter = inbox.adopt_waiter(self._owner, self._owner.make_waiter)
            if not isinstance(waiter, _DdsWaiter):
                return False  # the inbox waits on another transport's waiter
            self._stop_thread()
            waiter.attach(self._data)
            self._pulled_by, self._waiter = inbox, waiter
            inbox.add_source(self)
            return True

    def release_pull(self, inbox: Inbox) -> None:
        """Back to the delivery thread (which takes what the executor left in the reader)."""
        with self._mode_lock:
            if self._pulled_by is not inbox:
                return
            self._leave_waiter()
            if self.alive:
                self._start_thread()

    def _leave_waiter(self) -> None:
        inbox, waiter = self._pulled_by, self._waiter
        self._pulled_by = self._waiter = None
        if waiter is not None:
            waiter.detach(self._data)
        if inbox is not None:
            inbox.remove_source(self)

    def pending(self) -> bool:
        """False: the data condition keeps the executor's wait set awake while samples wait."""
        return False

    def pull(self, budget: int) -> int:
        """Take up to ``budget`` samples (at most one Cyclone batch) into the sink, here."""
        reader = self.reader
        if not self.alive or reader is None:
            return 0
        try:
            batch = ddspy_take(reader._ref, _ANY, min(budget, _TAKE_BATCH))
            if isinstance(batch, int) or not batch:
                return 0
            if self._sourced is not None:
                deliver = self._deliver
                for data, sample_info in batch:
                    if sample_info.valid_data:
                        deliver(data, sample_info)
                return len(batch)
            # _deliver inlined for a plain sink (one Python frame less per sample)
            decode, sink = self._decode, self._sink
            for data, sample_info in batch:
                if sample_info.valid_data:
                    try:
                        msg = decode(data)
                    except CdrError as exc:
                        self._drop_undecodable(exc)
                        continue
                    self.received += 1
                    if self.alive:
                        sink(msg)
            return len(batch)
        except Exception as exc:  # never into the executor: log and keep going
            self.warn_once("internal", f"subscription on '{self.info.topic}': "
                                       f"unexpected {type(exc).__name__}: {exc}")
            return 0

    def _drain(self, ref: int) -> None:
        drain_reader(ref, self._deliver, lambda: self.alive)

    def _deliver(self, data: bytes, sample_info: Any = None) -> None:
        try:
            msg = self._decode(data)
        except CdrError as exc:
            self._drop_undecodable(exc)
            return
        self.received += 1
        if not self.alive:
            return
        if self._sourced is None:
            self._sink(msg)
        else:
            # the writer's instance handle: unique per publisher as seen from this reader
            handle = getattr(sample_info, "publication_handle", None)
            self._sourced(msg, None if handle is None else int(handle).to_bytes(8, "little"))

    def _drop_undecodable(self, exc: CdrError) -> None:
        self.dropped += 1
        self.warn_once("cdr", f"dropping a sample on '{self.info.topic}' that does not "
                              f"decode as {self.ros_type}: {exc} (logged once)")

    def report_incompatible(self, reader: DataReader[Any]) -> None:
        """Log (once per policy) that a publisher offers less than this subscription wants."""
        status = reader.get_requested_incompatible_qos_status()  # type: ignore[no-untyped-call]
        policy = _POLICY_NAMES.get(int(getattr(status, "last_policy_id", 0)), "UNKNOWN")
        self.warn_once(
            f"qos-{policy}",
            f"New publisher discovered on topic '{self.info.topic}', offering incompatible "
            f"QoS. No messages will be received from it. Last incompatible policy: {policy}",
        )

    def stop(self) -> None:
        """Stop delivering (the reader itself is deleted by the transport)."""
        with self._mode_lock:
            self.alive = False
            if self.reader is None:  # never started
                return
            self._stop_thread()
            self._leave_waiter()

    def destroy(self) -> None:
        if self.alive:
            self.stop()
            if self.reader is not None:
                self._owner._forget(self, self.reader)

    @property
    def publisher_count(self) -> int:
        if self.reader is None:
            return 0
        try:
            return len(self.reader.get_matched_publications())
        except Exception:
            return 0


class _DdsWaiter:
    """An executor's wake-up as a Cyclone wait set (:class:`~posekit.runtime.inbox.Waiter`).

    A guard condition is the executor's own signal (``set``/``clear``); pulled readers'
    data conditions are attached beside it, so Cyclone's receive thread wakes the executor
    directly. Once the participant is gone (the context shut down) waits return at once.
    """

    def __init__(self, participant: DomainParticipant) -> None:
        self._waitset = WaitSet(participant)
        self._guard = GuardCondition(participant)
        self._waitset.attach(self._guard)
        self._closed = False

    def set(self) -> None:
        try:
            self._guard.set(True)
        except Exception:  # deleted with its participant
            self._closed = True

    def clear(self) -> None:
        try:
            self._guard.set(False)
        except Exception:
            self._closed = True

    def is_set(self) -> bool:
        try:
            return self._closed or self._guard.read()
        except Exception:
            self._closed = True
            return True

    def wait(self, timeout: float | None = None) -> bool:
        if self._closed:
            time.sleep(min(0.01, timeout if timeout is not None else 0.01))
            return True
        ns = _WAIT_FOREVER_NS if timeout is None else max(0, int(timeout * 1e9))
        try:
            return bool(self._waitset.wait(ns) > 0)
        except Exception:  # the participant was deleted under us
            self._closed = True
            return True

    def attach(self, condition: ReadCondition) -> None:
        self._waitset.attach(condition)

    def detach(self, condition: ReadCondition) -> None:
        try:
            self._waitset.detach(condition)
        except Exception as exc:  # deleted with its reader or participant
            _log.debug("detaching %r: %s", condition, exc)

    def close(self) -> None:
        """Wake any waiter for good (the participant is about to be deleted)."""
        self.set()
        self._closed = True


@dataclass(slots=True)
class _NodeRef:
    node: NodeEntities
    refs: int = 0


# ---------------------------------------------------------------------------------------
# The transport


class DdsTransport(Transport):
    """Nodes' endpoints as DDS readers and writers of one Cyclone DDS participant."""

    name = "dds"
    crosses_processes = True
    supports_services = True

    def __init__(self, options: DiscoveryOptions | None = None) -> None:
        self.options = options or DiscoveryOptions.from_env()
        configure_domain(self.options)
        self.domain_id = self.options.domain_id
        self.participant = DomainParticipant(
            self.domain_id, qos=Qos(Policy.Userdata(b"enclave=/;"))
        )
        self.gid: bytes = self.participant.guid.bytes
        self._lock = threading.RLock()
        self._closed = False
        self._topics: dict[str, tuple[str, Topic[Any]]] = {}  # dds topic -> (ros type, topic)
        self._nodes: dict[tuple[str, str], _NodeRef] = {}
        self._publishers: list[_Publisher] = []
        self._subscriptions: list[_Subscription] = []
        self._services: list[_ServiceEndpoints] = []  # servers' and clients' endpoints
        self._csid_counter = itertools.count(1)
        self._service_dispatcher: ServiceDispatcher | None = None
        self._warned_types: set[tuple[str, str, str]] = set()
        # Peers choose what they announce: graph warnings are rate-limited per reason.
        self._warn_graph = RateLimitedLog(_log.warning)
        # graph state
        self._changed = threading.Condition(self._lock)
        self._generation = 0
        self._started = self._last_change = time.monotonic()
        self._remote: dict[bytes, ParticipantEntities] = {}
        self._participants: set[bytes] = set()
        self._endpoints: dict[bytes, tuple[EntityKind, Any]] = {}
        # ros_discovery_info: writer keeps the latest, reader everything (rmw's QoS)
        disc_topic = self._topic(DISCOVERY_TOPIC, DISCOVERY_TYPE)
        disc_hash = user_data_type_hash(DISCOVERY_TYPE, type_hash(DISCOVERY_TYPE))
        self._disc_writer = DataWriter(self.participant, disc_topic, endpoint_qos(
            QoSProfile(depth=1, durability=DurabilityPolicy.TRANSIENT_LOCAL), disc_hash,
            writer=True))
        self._disc_reader = DataReader(self.participant, disc_topic, Qos(
            Policy.History.KeepAll, Policy.Reliability.Reliable(_MAX_BLOCKING),
            Policy.Durability.TransientLocal, Policy.IgnoreLocal.Participant,
            Policy.DataRepresentation(use_cdrv0_representation=True),
            Policy.Userdata(disc_hash)))
        self._builtin = {
            "participant": BuiltinDataReader(self.participant, BuiltinTopicDcpsParticipant),
            "publication": BuiltinDataReader(self.participant, BuiltinTopicDcpsPublication),
            "subscription": BuiltinDataReader(self.participant, BuiltinTopicDcpsSubscription),
        }
        self._waitset = WaitSet(self.participant)
        self._wake = GuardCondition(self.participant)
        self._waitset.attach(self._wake)
        #: Each builtin reader's samples not taken yet (what _refresh takes), and
        #: ros_discovery_info's: all wake the graph thread.
        self._not_read = {
            name: ReadCondition(reader, SampleState.NotRead | ViewState.Any | InstanceState.Any)
            for name, reader in (*self._builtin.items(), ("discovery", self._disc_reader))
        }
        for cond in self._not_read.values():
            self._waitset.attach(cond)
        self._publish_graph()
        self._thread = threading.Thread(target=self._graph_loop, name="posekit-dds-graph",
                                        daemon=True)
        self._thread.start()
        #: Executors' wait sets on this participant (see make_waiter), closed with it.
        self._waiters: weakref.WeakSet[_DdsWaiter] = weakref.WeakSet()

    def make_waiter(self) -> _DdsWaiter:
        """A wait set for an executor that pulls this transport's subscriptions."""
        waiter = _DdsWaiter(self.participant)
        self._waiters.add(waiter)
        return waiter

    # -- topics and nodes ------------------------------------------------------------
    def _topic(self, dds_topic: str, ros_type: str,
               make: Callable[[str], type] = idl_struct) -> Topic[Any]:
        """The process's Cyclone topic ``dds_topic`` (one per name), of type ``make(ros_type)``."""
        with self._lock:
            known = self._topics.get(dds_topic)
            if known is not None:
                if known[0] != ros_type:
                    raise TopicTypeMismatchError(
                        f"topic '{ros_topic_name(dds_topic) or dds_topic}' already carries "
                        f"{known[0]} in this process; cannot add an endpoint of {ros_type}"
                    )
                return known[1]
            topic: Topic[Any] = Topic(self.participant, dds_topic, make(ros_type))
            self._topics[dds_topic] = (ros_type, topic)
            return topic

    def declare_node(self, name: str, namespace: str = "/") -> NodeEntities:
        """Announce a node on ``ros_discovery_info`` (reference counted with its endpoints)."""
        return self._acquire_node(namespace, name)

    def undeclare_node(self, name: str, namespace: str = "/") -> None:
        """Balance one :meth:`declare_node` call; unknown nodes: no-op."""
        self._release_node(namespace, name)

    def _acquire_node(self, namespace: str, name: str) -> NodeEntities:
        key = (namespace or "/", name)
        with self._lock:
            entry = self._nodes.get(key)
            created = entry is None
            if entry is None:
                entry = self._nodes[key] = _NodeRef(NodeEntities(key[0], name))
            entry.refs += 1
        if created:
            self._publish_graph()
        return entry.node

    def _release_node(self, namespace: str, name: str) -> None:
        key = (namespace or "/", name)
        with self._lock:
            entry = self._nodes.get(key)
            if entry is None:
                return
            entry.refs -= 1
            if entry.refs > 0:
                return
            del self._nodes[key]
        self._publish_graph()

    def _publish_graph(self) -> None:
        with self._lock:
            if self._closed:
                return
            info = ParticipantEntities(self.gid, [ref.node for ref in self._nodes.values()])
            data = encode_participant_entities(info)
            self._generation += 1
            self._last_change = time.monotonic()
            self._changed.notify_all()
        ddspy_write(self._disc_writer._ref, data)

    # -- endpoints -------------------------------------------------------------------
    def advertise(self, info: EndpointInfo) -> PublisherEndpoint:
        """A DDS writer on ``info``'s topic (see :meth:`Transport.advertise`)."""
        ros_type = _ros_type(info)
        dds_topic = dds_topic_name(info.topic)
        topic = self._topic(dds_topic, ros_type)
        node = self._acquire_node(info.node_namespace, info.node_name)
        try:
            writer = DataWriter(self.participant, topic, endpoint_qos(
                info.qos, user_data_type_hash(ros_type, type_hash(ros_type)), writer=True,
                remote_only=info.remote_only))
        except BaseException:
            self._release_node(info.node_namespace, info.node_name)
            raise
        pub = _Publisher(self, info, ros_type, writer)
        # the graph thread reports subscriptions that want more than this writer offers
        writer.set_status_mask(DDSStatus.OfferedIncompatibleQos)
        self._waitset.attach(writer)
        with self._lock:
            node.writer_gids.append(pub.gid)
            self._publishers.append(pub)
        self._publish_graph()
        self._check_types(dds_topic, ros_type, info)
        return pub

    def subscribe(self, info: EndpointInfo, sink: MessageSink) -> SubscriptionEndpoint:
        """A DDS reader on ``info``'s topic calling ``sink(msg)``."""
        return self._subscribe(info, sink, None)

    def subscribe_with_source(
        self, info: EndpointInfo, sink: SourcedMessageSink
    ) -> SubscriptionEndpoint:
        """:meth:`subscribe` whose sink also gets an id of the sending publisher (8 bytes)."""
        return self._subscribe(info, lambda msg: sink(msg, None), sink)

    def _subscribe(self, info: EndpointInfo, sink: MessageSink,
                   sourced: SourcedMessageSink | None) -> SubscriptionEndpoint:
        ros_type = _ros_type(info)
        dds_topic = dds_topic_name(info.topic)
        topic = self._topic(dds_topic, ros_type)
        node = self._acquire_node(info.node_namespace, info.node_name)
        sub = _Subscription(self, info, ros_type, sink, sourced)
        try:
            reader = DataReader(self.participant, topic, endpoint_qos(
                info.qos, user_data_type_hash(ros_type, type_hash(ros_type)), writer=False,
                remote_only=info.remote_only))
            sub.start(self.participant, reader)
            self._waitset.attach(reader)  # incompatible-QoS reports (graph thread)
        except BaseException:
            self._release_node(info.node_namespace, info.node_name)
            raise
        with self._lock:
            node.reader_gids.append(sub.gid)
            self._subscriptions.append(sub)
        self._publish_graph()
        self._check_types(dds_topic, ros_type, info)
        return sub

    def _forget(self, endpoint: _Publisher | _Subscription, entity: Any) -> None:
        info = endpoint.info
        with self._lock:
            ref = self._nodes.get((info.node_namespace or "/", info.node_name))
            if ref is not None:
                gids = ref.node.writer_gids if isinstance(endpoint, _Publisher) \
                    else ref.node.reader_gids
                if endpoint.gid in gids:
                    gids.remove(endpoint.gid)
            if isinstance(endpoint, _Publisher) and endpoint in self._publishers:
                self._publishers.remove(endpoint)
            if isinstance(endpoint, _Subscription) and endpoint in self._subscriptions:
                self._subscriptions.remove(endpoint)
            closed = self._closed
        if not closed:
            try:
                self._waitset.detach(entity)
            except Exception as exc:  # not attached (or already gone)
                _log.debug("detaching %r: %s", entity, exc)
            _delete(entity)
        self._release_node(info.node_namespace, info.node_name)
        self._publish_graph()

    # -- services --------------------------------------------------------------------
    def service_dispatcher(self) -> ServiceDispatcher:
        """The one thread delivering every service reader's samples (started on first use)."""
        from posekit.transport.dds_services import ServiceDispatcher

        with self._lock:
            if self._service_dispatcher is None:
                self._service_dispatcher = ServiceDispatcher(self.participant)
            return self._service_dispatcher

    def next_client_service_id(self) -> bytes:
        """A new ``serviceid``/``clientid`` of this participant (rmw_cyclonedds's scheme)."""
        with self._lock:
            return client_service_id(self.gid, next(self._csid_counter))

    def create_service_server(self, info: ServiceInfo, sink: RequestSink) -> ServiceServerEndpoint:
        """A server of ``info``'s service: a reader on ``rq/...Request``, a writer on ``rr/...``.

        ``sink(request, respond, header)`` is called on the server's delivery thread
        (:mod:`posekit.transport.dds_services`).
        """
        from posekit.transport.dds_services import DdsServiceServer

        info.require_ros_service("dds")
        node = self._acquire_node(info.node_namespace, info.node_name)
        try:
            server = DdsServiceServer(self, info, sink)
        except BaseException:
            self._release_node(info.node_namespace, info.node_name)
            raise
        self._add_service(node, server.entities)
        return server

    def create_service_client(self, info: ServiceInfo) -> ServiceClientEndpoint:
        """A client of ``info``'s service: a writer on ``rq/...Request``, a reader on ``rr/...``."""
        from posekit.transport.dds_services import DdsServiceClient

        info.require_ros_service("dds")
        node = self._acquire_node(info.node_namespace, info.node_name)
        try:
            client = DdsServiceClient(self, info)
        except BaseException:
            self._release_node(info.node_namespace, info.node_name)
            raise
        self._add_service(node, client.entities)
        return client

    def _add_service(self, node: NodeEntities, entities: _ServiceEndpoints) -> None:
        with self._lock:
            node.reader_gids.append(entities.reader_gid)
            node.writer_gids.append(entities.writer_gid)
            self._services.append(entities)
        self._publish_graph()

    def _forget_service(self, entities: _ServiceEndpoints) -> None:
        info = entities.info
        with self._lock:
            ref = self._nodes.get((info.node_namespace or "/", info.node_name))
            if ref is not None:
                if entities.reader_gid in ref.node.reader_gids:
                    ref.node.reader_gids.remove(entities.reader_gid)
                if entities.writer_gid in ref.node.writer_gids:
                    ref.node.writer_gids.remove(entities.writer_gid)
            if entities in self._services:
                self._services.remove(entities)
            closed = self._closed
        if not closed:
            _delete(entities.reader)
            _delete(entities.writer)
        self._release_node(info.node_namespace, info.node_name)
        self._publish_graph()

    def _service_graph(self) -> list[tuple[EntityKind, str, bool, str, tuple[str, str] | None]]:
        """Every service endpoint: (kind, service, on the request topic, srv type, node)."""
        with self._lock:
            owners = self._node_of()
            out = []
            for gid, (kind, s) in self._endpoints.items():
                named = ros_service_name(s.topic_name)
                srv_type = ros_service_type(s.type_name)
                if named is None or srv_type is None:
                    continue
                out.append((kind, named[0], named[1], srv_type, owners.get(gid)))
        return out

    def get_service_names_and_types(self) -> list[tuple[str, list[str]]]:
        """Every service with a request or reply endpoint on the graph, with its types."""
        services: dict[str, set[str]] = {}
        for _kind, service, _request, srv_type, _node in self._service_graph():
            services.setdefault(service, set()).add(srv_type)
        return [(name, sorted(types)) for name, types in sorted(services.items())]

    def _services_by_node(self, node_name: str, node_namespace: str,
                          request: bool) -> list[tuple[str, list[str]]]:
        node = (node_namespace or "/", node_name)
        services: dict[str, set[str]] = {}
        for kind, service, on_request, srv_type, owner in self._service_graph():
            if kind is EntityKind.SUBSCRIPTION and on_request is request and owner == node:
                services.setdefault(service, set()).add(srv_type)
        return [(name, sorted(types)) for name, types in sorted(services.items())]

    def get_service_names_and_types_by_node(
        self, node_name: str, node_namespace: str
    ) -> list[tuple[str, list[str]]]:
        """The services a node serves: its readers on ``rq/...Request`` (as rmw_cyclonedds)."""
        return self._services_by_node(node_name, node_namespace, True)

    def get_client_names_and_types_by_node(
        self, node_name: str, node_namespace: str
    ) -> list[tuple[str, list[str]]]:
        """The services a node calls: its readers on ``rr/...Reply`` (as rmw_cyclonedds)."""
        return self._services_by_node(node_name, node_namespace, False)

    def _count_reply_endpoints(self, service: str, kind: EntityKind) -> int:
        reply_topic = service_topic_names(service)[1]
        with self._lock:
            return sum(1 for k, s in self._endpoints.values()
                       if k is kind and s.topic_name == reply_topic)

    def count_services(self, service: str) -> int:
        """Servers of ``service``: writers on its reply topic (as rmw_cyclonedds counts)."""
        return self._count_reply_endpoints(service, EntityKind.PUBLISHER)

    def count_clients(self, service: str) -> int:
        """Clients of ``service``: readers on its reply topic (as rmw_cyclonedds counts)."""
        return self._count_reply_endpoints(service, EntityKind.SUBSCRIPTION)

    # -- graph -----------------------------------------------------------------------
    def _graph_loop(self) -> None:
        """Apply discovery's news when it arrives, or when :meth:`sync_graph` asks.

        The wait set holds the builtin readers' and ``ros_discovery_info``'s not-read
        conditions and the ``_wake`` guard. The one-second timeout only checks the
        endpoints' incompatible-QoS statuses, which wake no condition: an idle graph costs
        nothing (each builtin sample's QoS is converted in Python, holding the GIL).
        """
        while not self._closed:
            try:
                triggered = self._waitset.wait(duration(seconds=1))
                if self._closed:
                    return
                self._check_incompatible_qos()
                if triggered:
                    # untrigger before reading: a sync_graph() during the read comes round again
                    self._wake.set(False)
                    self._refresh()
            except Exception as exc:  # keep the graph alive whatever a peer announces
                if self._closed:
                    return
                self._warn_graph("DDS graph update failed", f"{type(exc).__name__}: {exc}")
                time.sleep(0.1)

    def _check_incompatible_qos(self) -> None:
        with self._lock:
            publishers = list(self._publishers)
            subscriptions = list(self._subscriptions)
        for pub in publishers:
            if _took_status(pub, pub.writer, DDSStatus.OfferedIncompatibleQos):
                pub.report_incompatible()
        for sub in subscriptions:
            reader = sub.reader
            if reader is not None and _took_status(sub, reader,
                                                   DDSStatus.RequestedIncompatibleQos):
                sub.report_incompatible(reader)

    def _refresh(self) -> None:
        """Apply what discovery announced since the last call (only the graph thread calls).

        Takes only the builtin samples that arrived since (each reader's not-read condition),
        so a call costs what changed, not the whole graph: each builtin sample has its QoS
        converted in Python. A disposed or unregistered endpoint or participant arrives as a
        sample whose instance is no longer alive.
        """
        changed = False
        not_read = self._not_read
        participants = _take_new(self._builtin["participant"], not_read["participant"])
        alive_parts = self._participants
        departed: set[bytes] = set()
        if participants:
            alive_parts = set(alive_parts)
            for s in participants:
                if int(s.sample_info.instance_state) == _ALIVE:
                    alive_parts.add(s.key.bytes)
                    departed.discard(s.key.bytes)
                else:
                    alive_parts.discard(s.key.bytes)
                    departed.add(s.key.bytes)
        endpoints = self._endpoints
        for kind, name in ((EntityKind.PUBLISHER, "publication"),
                           (EntityKind.SUBSCRIPTION, "subscription")):
            endpoints = _with_endpoints(
                endpoints, kind, _take_new(self._builtin[name], not_read[name]))
        announced: list[ParticipantEntities] = []
        for data, sample_info in ddspy_take(self._disc_reader._ref, _ANY, 100000) or []:
            if not sample_info.valid_data:
                continue
            try:
                announced.append(decode_participant_entities(data))
            except CdrError as exc:
                self._warn_graph("ignoring an undecodable ros_discovery_info sample", str(exc))
        with self._lock:
            # A participant's announcement may be taken before its builtin sample (it arrived
            # in between): it stays until the participant is seen to leave.
            for part in announced:
                if part.gid not in departed and self._remote.get(part.gid) != part:
                    self._remote[part.gid] = part
                    changed = True
            for gid in departed & self._remote.keys():
                del self._remote[gid]
                changed = True
            if alive_parts != self._participants or endpoints.keys() != self._endpoints.keys():
                changed = True
            self._participants = alive_parts
            self._endpoints = endpoints
            if changed:
                self._generation += 1
                self._last_change = time.monotonic()
                self._changed.notify_all()
            endpoints_here: list[_Publisher | _Subscription] = [
                *self._publishers, *self._subscriptions]
            local = [(dds_topic_name(p.info.topic), p.ros_type, p.info) for p in endpoints_here]
        if changed:
            for dds_topic, ros_type, info in local:
                self._check_types(dds_topic, ros_type, info)

    def _check_types(self, dds_topic: str, ros_type: str, info: EndpointInfo) -> None:
        wanted = dds_type_name(ros_type)
        with self._lock:
            others = {s.type_name for _kind, s in self._endpoints.values()
                      if s.topic_name == dds_topic and s.type_name != wanted}
        for other in sorted(others):
            tag = (dds_topic, wanted, other)
            if tag in self._warned_types:
                continue
            if len(self._warned_types) >= _MAX_WARNED_TYPES:  # peers pick the type names
                self._warned_types.clear()
            self._warned_types.add(tag)
            try:
                shown = ros_type_name(other)
            except ValueError:
                shown = other
            info.logger.warning(
                f"topic '{info.topic}' also has endpoints of type {shown}, this one uses "
                f"{ros_type}: DDS does not connect different types, no messages are exchanged "
                "between them"
            )

    def _node_of(self) -> dict[bytes, tuple[str, str]]:
        owners: dict[bytes, tuple[str, str]] = {}
        for part in (*self._remote.values(), self._local_entities()):
            for node in part.nodes:
                for gid in (*node.reader_gids, *node.writer_gids):
                    owners[gid] = (node.namespace, node.name)
        return owners

    def _local_entities(self) -> ParticipantEntities:
        return ParticipantEntities(self.gid, [ref.node for ref in self._nodes.values()])

    def _graph_endpoints(self, topic: str | None = None,
                         kind: EntityKind | None = None) -> list[DdsEndpoint]:
        with self._lock:
            owners = self._node_of()
            out: list[DdsEndpoint] = []
            for gid, (k, s) in self._endpoints.items():
                if kind is not None and k is not kind:
                    continue
                ros_topic = ros_topic_name(s.topic_name)
                if ros_topic is None or (topic is not None and ros_topic != topic):
                    continue
                try:
                    ros_type = ros_type_name(s.type_name)
                except ValueError:
                    continue
                out.append(_endpoint_record(k, gid, s, ros_topic, ros_type, owners.get(gid)))
        return out

    def _service_records(self) -> list[DdsEndpoint]:
        """Every service server (kind SERVICE) and client (CLIENT) on the graph, one record each.

        A server is its reader on the request topic, a client its reader on the reply topic,
        as :meth:`get_service_names_and_types_by_node` and
        :meth:`get_client_names_and_types_by_node` count them.
        """
        with self._lock:
            owners = self._node_of()
            out: list[DdsEndpoint] = []
            for gid, (k, s) in self._endpoints.items():
                if k is not EntityKind.SUBSCRIPTION:
                    continue
                named = ros_service_name(s.topic_name)
                srv_type = ros_service_type(s.type_name)
                if named is None or srv_type is None:
                    continue
                service, on_request = named
                role = EntityKind.SERVICE if on_request else EntityKind.CLIENT
                out.append(_endpoint_record(role, gid, s, service, srv_type, owners.get(gid)))
        return out

    def graph_entities(self) -> list[DdsEndpoint | DdsNode]:
        """Every node, publisher, subscription, service server and client on the graph.

        Nodes as ``ros_discovery_info`` announces them (this process's included), topic
        endpoints as :meth:`get_publishers_info_by_topic` gives them, servers and clients as
        one record per reader (see :class:`~posekit.transport.dds_wire.DdsEndpoint`).
        Duplicates are kept.
        """
        with self._lock:
            nodes: list[DdsEndpoint | DdsNode] = [
                DdsNode(part.gid, node.namespace, node.name)
                for part in self._graph_participants() for node in part.nodes]
        return [*nodes, *self._graph_endpoints(), *self._service_records()]

    def _topics_by_node(self, node_name: str, node_namespace: str,
                        kind: EntityKind) -> list[tuple[str, list[str]]]:
        topics: dict[str, set[str]] = {}
        for ep in self._graph_endpoints(kind=kind):
            if ep.node_name == node_name and ep.namespace == node_namespace:
                topics.setdefault(ep.topic, set()).add(ep.ros_type)
        return [(name, sorted(types)) for name, types in sorted(topics.items())]

    def get_publisher_names_and_types_by_node(
        self, node_name: str, node_namespace: str
    ) -> list[tuple[str, list[str]]]:
        """The topics a node publishes: its writers on ``rt/...`` topics (as rmw_cyclonedds)."""
        return self._topics_by_node(node_name, node_namespace, EntityKind.PUBLISHER)

    def get_subscriber_names_and_types_by_node(
        self, node_name: str, node_namespace: str
    ) -> list[tuple[str, list[str]]]:
        """The topics a node subscribes to: its readers on ``rt/...`` topics."""
        return self._topics_by_node(node_name, node_namespace, EntityKind.SUBSCRIPTION)

    def get_topic_names_and_types(self) -> list[tuple[str, list[str]]]:
        """Every topic of the discovered graph, with its type names."""
        topics: dict[str, set[str]] = {}
        for ep in self._graph_endpoints():
            topics.setdefault(ep.topic, set()).add(ep.ros_type)
        return [(name, sorted(types)) for name, types in sorted(topics.items())]

    def count_publishers(self, topic: str) -> int:
        """Number of discovered publishers on ``topic``."""
        return len(self._graph_endpoints(topic, EntityKind.PUBLISHER))

    def count_subscribers(self, topic: str) -> int:
        """Number of discovered subscriptions on ``topic``."""
        return len(self._graph_endpoints(topic, EntityKind.SUBSCRIPTION))

    def get_publishers_info_by_topic(self, topic: str) -> list[DdsEndpoint]:
        """Every publisher on ``topic`` (node, type, type hash, QoS, GID)."""
        return self._graph_endpoints(topic, EntityKind.PUBLISHER)

    def publisher_qos_profiles(self, topic: str) -> list[QoSProfile]:
        """The QoS each publisher on ``topic`` announced on the graph."""
        return [e.qos.to_profile() for e in self.get_publishers_info_by_topic(topic)
                if e.qos is not None]

    def get_subscriptions_info_by_topic(self, topic: str) -> list[DdsEndpoint]:
        """Every subscription on ``topic``."""
        return self._graph_endpoints(topic, EntityKind.SUBSCRIPTION)

    def _graph_participants(self) -> list[ParticipantEntities]:
        """The participants' announcements: every remote one and this participant's own."""
        with self._lock:
            return [*(p for g, p in self._remote.items() if g != self.gid),
                    self._local_entities()]

    def get_node_names_and_namespaces(self) -> list[tuple[str, str]]:
        """(name, namespace) of every node on the graph, this process's included."""
        return sorted((n.name, n.namespace) for p in self._graph_participants() for n in p.nodes)

    def get_node_names(self) -> list[str]:
        """Fully qualified names of every node on the graph (duplicates kept), sorted."""
        return sorted(f"{ns.rstrip('/')}/{name}"
                      for name, ns in self.get_node_names_and_namespaces())

    def sync_graph(self, timeout: float = 2.0) -> int:
        """Wait (at most ``timeout`` s) until discovery has settled; returns the graph generation.

        Settled: every discovered participant has announced its nodes and nothing changed for
        0.3 s, and at least 0.6 s have passed since this participant joined.
        """
        deadline = time.monotonic() + max(0.0, timeout)
        self._wake.set(True)
        with self._lock:
            while True:
                now = time.monotonic()
                complete = all(g in self._remote for g in self._participants if g != self.gid)
                settled = now - self._last_change >= 0.3 and now - self._started >= 0.6
                if (complete and settled) or now >= deadline:
                    return self._generation
                self._changed.wait(min(0.1, max(0.0, deadline - now)))

    def close(self) -> None:
        """Delete this transport's DDS entities and stop its delivery threads."""
        with self._lock:
            if self._closed:
                return
            self._closed = True
            subs, self._subscriptions = self._subscriptions, []
            services, self._services = self._services, []
            self._publishers = []
        for sub in subs:
            sub.stop()
        for service in services:
            service.alive = False
        if self._service_dispatcher is not None:
            self._service_dispatcher.close()
        for waiter in list(self._waiters):
            waiter.close()
        self._wake.set(True)
        self._thread.join(timeout=2.0)
        _delete(self.participant)


def drain_reader(ref: int, deliver: Callable[[bytes, Any], None],
                 alive: Callable[[], bool] | None = None) -> None:
    """Take every sample waiting in reader ``ref`` (in batches) into ``deliver(data, info)``.

    Stops when the reader is empty or deleted, or when ``alive()`` turns False.
    """
    while alive is None or alive():
        batch = ddspy_take(ref, _ANY, _TAKE_BATCH)
        if isinstance(batch, int) or not batch:  # nothing, or deleted meanwhile
            return
        for data, sample_info in batch:
            if sample_info.valid_data:
                deliver(data, sample_info)
        if len(batch) < _TAKE_BATCH:
            return


def _take_new(reader: BuiltinDataReader, condition: ReadCondition) -> list[Any]:
    """Every sample of builtin ``reader`` that ``condition`` (not read) selects, taken.

    Taken, not read: the graph keeps what it needs, and Cyclone then forgets an instance
    once it is gone (read samples of departed participants stayed in the reader for good).
    In batches: a take allocates room for as many samples as it may return, and one for
    100,000 took 0.5 ms with nothing there.
    """
    samples: list[Any] = []
    while True:
        with QOS_CONVERSION_LOCK:
            batch = reader.take(N=_TAKE_BATCH, condition=condition)
        samples += batch
        if len(batch) < _TAKE_BATCH:
            return samples


def _with_endpoints(endpoints: dict[bytes, tuple[EntityKind, Any]], kind: EntityKind,
                    samples: list[Any]) -> dict[bytes, tuple[EntityKind, Any]]:
    """``endpoints`` with builtin ``samples`` of ``kind`` applied, as a new dict if any.

    New so that readers of the transport's dict need no copy. Alive instances go in (or
    replace what was there), the others go out.
    """
    if not samples:
        return endpoints
    endpoints = dict(endpoints)
    for s in samples:
        if int(s.sample_info.instance_state) == _ALIVE:
            endpoints[s.key.bytes] = (kind, s)
        else:
            endpoints.pop(s.key.bytes, None)
    return endpoints


def _endpoint_record(kind: EntityKind, gid: bytes, sample: Any, name: str, ros_type: str,
                     node: tuple[str, str] | None) -> DdsEndpoint:
    """The graph record of a builtin publication or subscription ``sample``.

    ``name`` and ``ros_type`` are its ROS topic (or service) name and type, ``node`` the
    (namespace, name) of the node that announced it (None if none did).
    """
    try:
        user = parse_user_data(bytes(sample.qos[Policy.Userdata].data))
    except (KeyError, TypeError, AttributeError):
        user = {}
    extra = {"namespace": node[0], "node_name": node[1]} if node else {}
    return DdsEndpoint(
        kind=kind, gid=gid, participant_gid=sample.participant_key.bytes, topic=name,
        ros_type=ros_type, type_hash=user.get("typehash"), qos=wire_qos_of(sample.qos),
        **extra)


def _took_status(endpoint: _Publisher | _Subscription, entity: Any, status: int) -> bool:
    """Whether ``entity`` had ``status`` raised (now taken); False once the endpoint is gone.

    An endpoint destroyed on another thread between the ``alive`` check and the take has
    its entity deleted: that is not an error of the graph thread.
    """
    if not endpoint.alive:
        return False
    try:
        return bool(entity.take_status(status))
    except DDSException:
        if endpoint.alive:
            raise
        return False


def _delete(entity: Any) -> None:
    """Delete a Cyclone entity now (with its children), not when Python collects it."""
    try:
        entity.__del__()
    except Exception as exc:  # already gone with its participant
        _log.debug("deleting %r: %s", entity, exc)
