"""Recording topics into a rosbag2 directory (MCAP storage, zstd chunks) from a node.

    from posekit.bag import Recorder
    with Recorder("run1", topics=["/tf", "/tf_static"], context=ctx) as rec:
        executor.add_node(rec.node)
        executor.run_for(10.0)
    # run1/metadata.yaml + run1/run1_0.mcap

What is written, and how it relates to ``ros2 bag record``:

* **Timestamps**: by default each message is stored with its **receive time**, read from the
  recorder node's clock when the subscription callback runs (rosbag2 does the same). Added to
  a :class:`~posekit.runtime.SimulatedTimeExecutor` the node follows sim time, so stamps are
  the simulated time at which the message was delivered: deterministic, and equal to the
  ``header.stamp`` of messages published "now". ``stamp="header"`` stores ``header.stamp``
  instead (for ``tf2_msgs/TFMessage`` the first transform's stamp), falling back to the
  receive time for messages without a header.
* **Storage**: rosbags' ``Writer`` with ``StoragePlugin.MCAP``, one per storage file, named
  and split as rosbag2 Jazzy does (:mod:`posekit.bag._split`): ``<name>_0.mcap``,
  ``<name>_1.mcap``... with ``max_bag_size`` (bytes) / ``max_bag_duration`` (seconds of
  message time), ``ros_distro: jazzy`` in metadata.yaml. ``compression="zstd"`` (default)
  zstd-compresses every MCAP chunk (what rosbag2's MCAP storage does by default, so
  ``compression_format``/``compression_mode`` stay empty in metadata.yaml as in ROS 2's own
  bags); None writes uncompressed chunks; ``"file"`` and ``"message"`` are rosbag2's
  ``--compression-mode file|message`` with zstd (readable by rosbag2 and rosbags, not by
  plain MCAP readers such as Foxglove).
* **metadata.yaml** version 9 (ROS 2 Jazzy) by default, 8 (Iron) selectable: version 9 stores
  ``offered_qos_profiles`` as a YAML list with lower-case policy names, version 8 as a YAML
  string with numeric policies. The QoS recorded per topic is what each publisher offered
  (``/tf_static`` therefore shows ``transient_local``).
* **Message definitions**: every topic's type gets an MCAP schema with the full ``ros2msg``
  definition (dependencies included) and a RIHS01 type hash, generated from ROS 2 Jazzy's
  definitions, so Foxglove, ``ros2 bag`` and the ``mcap`` tools decode the bag.
* **Crash safety**: data goes to disk chunk by chunk as it comes: the open MCAP chunk is
  closed and flushed to the operating system at least every ``flush_period`` wall seconds
  (default 1 s) and whenever it holds 1 MiB, so a recorder killed without warning loses at
  most the last second; ``posekit bag reindex`` (:func:`posekit.bag.reindex`) turns what it
  left into a complete bag. ``posekit bag record`` finishes the bag on SIGTERM as on Ctrl-C.
* **Topic selection**: explicit topic names, or every topic the graph shows (``topics=None``)
  except hidden ones (a name token starting with ``_``) and ``exclude``; ``regex`` selects
  the topics whose name contains a match (``re.search``, as rosbag2's ``std::regex_search``)
  in addition to explicit names, ``exclude_regex`` removes matches from any selection; the
  graph is
  re-checked every ``discovery_period`` seconds of the node clock, so topics that appear
  later are recorded from then on. Types posekit cannot serialize are skipped with a warning.
"""

from __future__ import annotations

import re
import threading
import time
from collections.abc import Callable, Sequence
from pathlib import Path
from types import TracebackType
from typing import Any, cast

from posekit.bag._qos import to_rosbags_qos
from posekit.bag._split import SplitWriter
from posekit.bag._storage import SUPPORTED_VERSIONS
from posekit.bag.errors import BagOptionError
from posekit.bag.info import (
    SERVICE_EVENT_SUFFIX,
    is_service_event_topic,
    is_service_event_type,
)
from posekit.msgs.errors import UnknownMessageTypeError
from posekit.msgs.registry import normalize_type_name
from posekit.runtime.context import Context
from posekit.runtime.executors import Executor
from posekit.runtime.logging import get_logger
from posekit.runtime.names import is_hidden_name
from posekit.runtime.node import Node
from posekit.runtime.observe import ObservedTopic, TopicObserver, TopicSkipped
from posekit.runtime.ratelimit import RateLimitedLog
from posekit.runtime.sim_executor import SimulatedTimeExecutor
from posekit.runtime.transport import EndpointInfo, MessageSink, SubscriptionEndpoint
from posekit.time import stamp_to_ns

__all__ = ["Recorder", "attach_recorder", "record_scenario"]

_STAMPS = ("receive", "header")


def _header_stamp_ns(msg: Any) -> int | None:
    header = getattr(msg, "header", None)
    if header is None:
        transforms = getattr(msg, "transforms", None)
        if transforms:
            header = getattr(transforms[0], "header", None)
    stamp = getattr(header, "stamp", None)
    if stamp is None:
        return None
    return stamp_to_ns(stamp)


#: Graph checks in a row without a publisher before a topic's subscription is let go.
_GRACE_REFRESHES = 10


def _recordable_class(type_name: str) -> type:
    """The class of a type the recorder can write (LookupError for any other).

    A message type with a ROS 2 definition, or the event type of a posekit service
    (``pkg/srv/Name_Event``).
    """
    from posekit.msgs.cdr import get_typestore, serializable_type

    if is_service_event_type(type_name):
        cls = get_typestore().types.get(type_name)
        if cls is None:
            raise LookupError(f"type {type_name!r} is not a service posekit knows")
        return cast(type, cls)
    try:
        return serializable_type(type_name)[1]
    except (LookupError, ValueError) as exc:
        raise LookupError(f"type {type_name!r} has no ROS 2 message definition posekit can "
                          f"serialize ({exc})") from None


def _definition(type_name: str) -> dict[str, Any]:
    """``add_connection`` keywords giving a topic's MCAP schema.

    For messages, the ``ros2msg`` text with dependencies (from the typestore); for a service
    event type the schema rosbag2 Jazzy writes (its ``LocalMessageDefinitionSource``): an
    ``SRV:`` delimiter, the service's ``.srv`` text (request ``---`` response) and its message
    dependencies.
    """
    from posekit.msgs._srv_defs import service_definition_text
    from posekit.msgs.cdr import get_typestore

    store = get_typestore()
    if not is_service_event_type(type_name):
        return {"typestore": store}
    service = type_name.removesuffix("_Event")
    return {"msgdef": service_definition_text(service), "rihs01": store.hash_rihs01(type_name)}


class _NodeSubscription(SubscriptionEndpoint):
    """A node's subscription seen as the transport endpoint the observer manages."""

    def __init__(self, node: Node, subscription: Any) -> None:
        self._node = node
        self._subscription = subscription

    def destroy(self) -> None:
        self._node.destroy_subscription(self._subscription)

    @property
    def publisher_count(self) -> int:
        return int(self._subscription.get_publisher_count())


class Recorder:
    """A node that records topics into a new rosbag2 directory (see the module docstring).

    Args:
        output: directory to create; must not exist (bags are never overwritten).
        topics: topic names to record (relative names are made absolute); None or empty
            (and no ``regex``, ``services`` or ``all_services``) records every topic
            discovered in the graph.
        context: context of the recorder node (default: the default context).
        node_name: name of the recorder node.
        version: metadata.yaml version, 9 (default) or 8.
        compression: ``"zstd"`` (default) compresses MCAP chunks; None stores them raw;
            ``"file"`` / ``"message"`` compress whole files / single messages (zstd).
        stamp: ``"receive"`` (default, as rosbag2) or ``"header"``.
        exclude: topics never recorded in all-topics mode (default ``/clock``: the player
            regenerates the clock from the bag's timestamps; list it explicitly to record it).
        include_hidden: also record hidden topics in all-topics mode.
        regex: also record every topic whose name contains a match of this expression.
        exclude_regex: never record topics whose name contains a match.
        max_bag_size: bytes per storage file before a new one starts (0: no splitting).
        max_bag_duration: seconds of message time per storage file (0: no splitting).
        discovery_period: seconds of node-clock time between graph checks (None: only
            at start and on :meth:`discover`).
        transport: transport name for the node (default: the context's).
        flush_period: wall seconds between forced chunk writes (None: only when a chunk is
            full, as rosbags does).
        services: services whose events to record (``<service>/_service_event``; their
            servers or clients must have introspection on, see
            :meth:`posekit.runtime.services.Service.configure_introspection`).
        all_services: record the events of every service (``--all-services``).
        exclude_services: services never recorded (with ``all_services`` or ``regex``).
        all_topics: record every (non-hidden) topic; default: when no other selection is
            given.
        topic_types: also record every topic of these types (``pkg/msg/Name``).
        exclude_topic_types: never record topics of these types.

    Raises:
        BagExistsError: ``output`` exists.
        BagOptionError: bad version, compression, stamp, topic name, regex or threshold.
    """

    def __init__(
        self,
        output: str | Path,
        topics: Sequence[str] | None = None,
        *,
        context: Context | None = None,
        node_name: str = "rosbag2_recorder",
        version: int = 9,
        compression: str | None = "zstd",
        stamp: str = "receive",
        exclude: Sequence[str] = ("/clock",),
        include_hidden: bool = False,
        discovery_period: float | None = 0.1,
        transport: str | None = None,
        regex: str | None = None,
        exclude_regex: str | None = None,
        max_bag_size: int = 0,
        max_bag_duration: float = 0.0,
        flush_period: float | None = 1.0,
        services: Sequence[str] | None = None,
        all_services: bool = False,
        exclude_services: Sequence[str] = (),
        all_topics: bool | None = None,
        topic_types: Sequence[str] = (),
        exclude_topic_types: Sequence[str] = (),
    ) -> None:
        if version not in SUPPORTED_VERSIONS:
            raise BagOptionError(
                f"unsupported rosbag2 metadata version {version!r}; choose 8 or 9"
            )
        modes = {"zstd": "storage", None: "none", "file": "file", "message": "message"}
        if compression not in modes:
            raise BagOptionError(
                f"unsupported compression {compression!r}; choose 'zstd' (MCAP chunks), "
                "'file', 'message' or None"
            )
        try:
            self._regex = re.compile(regex) if regex else None
            self._exclude_regex = re.compile(exclude_regex) if exclude_regex else None
        except re.error as exc:
            raise BagOptionError(f"invalid regular expression: {exc}") from None
        if not (max_bag_size >= 0 and max_bag_duration >= 0):
            raise BagOptionError("max_bag_size and max_bag_duration must be >= 0 (0: no split)")
        if stamp not in _STAMPS:
            raise BagOptionError(f"stamp must be 'receive' or 'header', got {stamp!r}")
        if flush_period is not None and not flush_period > 0:
            raise BagOptionError(f"flush_period must be > 0 s, got {flush_period}")
        if discovery_period is not None and discovery_period <= 0:
            raise BagOptionError(f"discovery_period must be > 0 s, got {discovery_period}")
        self.path = Path(output)
        self._writer = SplitWriter(
            self.path, version=8 if version == 8 else 9, compression=modes[compression],
            max_bytes=int(max_bag_size), max_duration_ns=int(max_bag_duration * 1e9),
        )

        self.node = Node(node_name, context=context, transport=transport)
        try:
            self._explicit = {self.node.resolve_topic_name(t) for t in topics or ()}
            self._services = {
                self.node.resolve_service_name(s).removesuffix(SERVICE_EVENT_SUFFIX)
                + SERVICE_EVENT_SUFFIX for s in services or ()
            }
            self._exclude_services = {
                self.node.resolve_service_name(s).removesuffix(SERVICE_EVENT_SUFFIX)
                + SERVICE_EVENT_SUFFIX for s in exclude_services
            }
        except Exception as exc:
            self.node.destroy_node()
            raise BagOptionError(
                f"invalid topic or service name in {[*(topics or []), *(services or [])]}: "
                f"{exc}") from exc
        self._all_services = all_services
        try:
            self._types = {normalize_type_name(t) for t in topic_types}
            self._exclude_types = {normalize_type_name(t) for t in exclude_topic_types}
        except (ValueError, LookupError, UnknownMessageTypeError) as exc:
            self.node.destroy_node()
            raise BagOptionError(f"invalid topic type: {exc}") from None
        self._all_topics = (not (self._explicit or self._services or all_services
                                 or self._types or self._regex is not None)
                            if all_topics is None else all_topics)
        self._exclude = {self.node.resolve_topic_name(t) for t in exclude}
        self._include_hidden = include_hidden
        self._use_header = stamp == "header"
        self.version = version
        self._lock = threading.Lock()
        self._writer.set_custom_data("recorder", "posekit")
        self._writer.set_custom_data("timestamps", stamp)
        try:
            self._writer.open()
        except BaseException:
            self.node.destroy_node()
            raise
        self._flush_period = flush_period
        self._last_flush = time.monotonic()
        self._flush_storage(close_chunk=False)  # the file header is on disk from the start
        self._connections: dict[str, tuple[Any, str]] = {}
        #: Messages written per topic.
        self.counts: dict[str, int] = {}
        #: Messages that could not be serialized, per topic (each logged).
        self.errors: dict[str, int] = {}
        self._closed = False
        self._timer = None
        # one line per skipped topic; a flood of peer-chosen names is rate limited
        self._skip_log = RateLimitedLog(self.node.get_logger().warning)
        self._observer = TopicObserver(
            self.node.transport, self._sink_for, select=self._wanted,
            on_skipped=self._on_skipped, node_name=self.node.get_name(),
            node_namespace=self.node.get_namespace(), depth=None, resolve=_recordable_class,
            grace_refreshes=_GRACE_REFRESHES, logger=self.node.get_logger(),
            subscribe=self._node_subscription,
        )
        self.discover()
        if discovery_period is not None:
            self._timer = self.node.create_timer(discovery_period, self._on_timer)

    # -- writing to disk -----------------------------------------------------------------
    def _flush_storage(self, close_chunk: bool = True) -> None:
        """Close the open MCAP chunk and hand the file's buffered bytes to the operating system.

        A chunk is closed only if it holds anything. The caller holds the lock or owns the
        writer.
        """
        storage: Any = getattr(self._writer, "storage", None)
        chunk = getattr(storage, "chunk", None)
        if close_chunk and chunk is not None and chunk.msgs and hasattr(storage, "close_chunk"):
            storage.close_chunk()
        bio = getattr(storage, "bio", None)
        if bio is not None and not bio.closed:
            bio.flush()
        self._last_flush = time.monotonic()

    def flush(self) -> None:
        """Write everything received so far to disk now (one MCAP chunk)."""
        with self._lock:
            if not self._closed:
                self._flush_storage()

    def _maybe_flush(self) -> None:
        period = self._flush_period
        if period is not None and time.monotonic() - self._last_flush >= period:
            self._flush_storage()

    def _on_timer(self) -> None:
        self.discover()
        with self._lock:
            if not self._closed:
                self._maybe_flush()

    # -- discovery --------------------------------------------------------------------
    @property
    def topics(self) -> list[str]:
        """Topics subscribed so far."""
        with self._lock:
            return sorted(self._connections)

    def _wanted(self, topic: str, type_name: str) -> bool:
        """rosbag2 Jazzy's topic filter (``TopicFilter::take_topic``) over our options."""
        if is_service_event_topic(topic, type_name):
            if not (self._all_services or self._services or self._regex is not None):
                return False
            service = topic.removesuffix(SERVICE_EVENT_SUFFIX)
            if not self._all_services and topic not in self._services and (
                    self._regex is None or not self._regex.search(service)):
                return False
            if topic in self._exclude_services:
                return False
            return not (self._exclude_regex is not None and self._exclude_regex.search(service))
        if not (self._all_topics or self._explicit or self._types or self._regex is not None):
            return False
        if not self._all_topics and topic not in self._explicit and (
                type_name not in self._types) and (
                self._regex is None or not self._regex.search(topic)):
            return False
        if type_name in self._exclude_types:
            return False
        if topic in self._exclude and topic not in self._explicit:
            return False
        if self._exclude_regex is not None and self._exclude_regex.search(topic):
            return False
        return self._include_hidden or topic in self._explicit or not is_hidden_name(topic)

    def discover(self) -> list[str]:
        """Subscribe to wanted topics that appeared in the graph; returns the new ones.

        Topics whose publishers left are let go.
        """
        if self._closed:
            return []
        return self._observer.refresh()

    def _node_subscription(self, info: EndpointInfo, sink: MessageSink) -> SubscriptionEndpoint:
        """A subscription of the recorder node.

        Messages are written by its executor, at the node clock's time of delivery (sim time
        under a SimulatedTimeExecutor).
        """
        return _NodeSubscription(
            self.node, self.node.create_subscription(info.msg_type, info.topic, sink, info.qos))

    def _on_skipped(self, topic: str, reason: str) -> None:
        self._skip_log(f"not recording '{topic}'", reason)

    def _sink_for(self, observed: ObservedTopic) -> Callable[[Any], None]:
        """Open (or reuse) the bag connection of a topic the observer starts observing."""
        topic, type_name = observed.name, observed.type_name
        with self._lock:
            if self._closed:
                raise TopicSkipped("the recorder is closed")
            known = self._connections.get(topic)
            if known is not None and known[1] != type_name:
                raise TopicSkipped(f"its type changed from {known[1]} to {type_name}; a bag "
                                   "topic has one type")
            if known is None:
                connection = self._writer.add_connection(
                    topic, type_name, **_definition(type_name),
                    offered_qos_profiles=[to_rosbags_qos(p) for p in observed.offered],
                )
                self._connections[topic] = (connection, type_name)
                self.counts[topic] = 0
            else:
                connection = known[0]
        self.node.get_logger().info(f"Subscribed to topic '{topic}'")
        return self._make_callback(topic, type_name, connection)

    def _make_callback(self, topic: str, type_name: str,
                       connection: Any) -> Callable[[Any], None]:
        from posekit.msgs.cdr import to_cdr
        from posekit.msgs.errors import MessageError

        clock = self.node.get_clock()
        use_header = self._use_header

        def on_message(msg: Any) -> None:
            if self._closed:
                return
            stamp_ns = _header_stamp_ns(msg) if use_header else None
            if stamp_ns is None:
                stamp_ns = clock.now_ns()
            try:
                data = to_cdr(msg, type_name)
            except MessageError as exc:
                with self._lock:
                    self.errors[topic] = self.errors.get(topic, 0) + 1
                self.node.get_logger().error(f"dropped a message on '{topic}': {exc}")
                return
            with self._lock:
                if self._closed:
                    return
                self._writer.write(connection, stamp_ns, data)
                self.counts[topic] += 1
                self._maybe_flush()

        return on_message

    def set_custom_data(self, key: str, value: str) -> None:
        """Store ``key: value`` under ``custom_data`` in the bag's metadata.yaml."""
        self._writer.set_custom_data(key, value)

    # -- lifetime ---------------------------------------------------------------------
    @property
    def closed(self) -> bool:
        """True after :meth:`close`."""
        return self._closed

    def close(self) -> dict[str, int]:
        """Stop recording, destroy the node and finish the bag (index, metadata.yaml).

        Idempotent; returns the number of messages written per topic.
        """
        with self._lock:
            if self._closed:
                return dict(self.counts)
            self._closed = True
        try:
            self._observer.close()
            self.node.destroy_node()
        finally:
            with self._lock:
                self._writer.close()
        return dict(self.counts)

    def __enter__(self) -> Recorder:
        return self

    def __exit__(self, exc_type: type[BaseException] | None, exc: BaseException | None,
                 tb: TracebackType | None) -> None:
        self.close()


def attach_recorder(target: Any, output: str | Path, topics: Sequence[str] | None = None,
                    **options: Any) -> Recorder:
    """Start recording a running system.

    ``target`` is a :class:`posekit.launch.LaunchRun` (anything with ``.executor``), an
    :class:`Executor`, or a :class:`Context`. With a run or an executor the recorder node joins
    that executor (under a SimulatedTimeExecutor it records in sim time); with a bare context
    the caller adds ``recorder.node`` to whatever spins it. Either way the bag is finished
    when the context shuts down, or earlier by :meth:`Recorder.close`. ``options`` are
    :class:`Recorder`'s keyword arguments.
    """
    executor: Executor | None
    if isinstance(target, Context):
        context, executor = target, None
    else:
        executor = target if isinstance(target, Executor) else getattr(target, "executor", None)
        if not isinstance(executor, Executor):
            raise BagOptionError(
                "attach_recorder needs a LaunchRun, an Executor or a Context, got "
                f"{type(target).__name__}"
            )
        context = executor.context
    recorder = Recorder(output, topics, context=context, **options)
    if executor is not None:
        executor.add_node(recorder.node)

    def finish() -> None:
        try:
            recorder.close()
        except Exception as exc:  # a shutdown callback must not stop the context's shutdown
            get_logger("rosbag2_recorder").error(f"could not finish bag {output}: {exc}")

    context.on_shutdown(finish)
    return recorder


def record_scenario(
    scenario: str,
    output: str | Path,
    *,
    duration: float,
    topics: Sequence[str] | None = None,
    params: dict[str, Any] | None = None,
    seed: int = 0,
    **options: Any,
) -> dict[str, int]:
    """Run the named robot scenario for ``duration`` simulated seconds while recording.

    Starts it with :func:`posekit.launch.scenarios.start_scenario` (its nodes on a
    SimulatedTimeExecutor, nothing run yet), attaches a :class:`Recorder` before the first
    step, runs, finishes the bag and shuts the scenario down. ``params``/``seed`` are the
    scenario's; ``options`` are :class:`Recorder`'s keyword arguments. Returns the messages
    written per topic.
    """
    # Only needed for this helper: the framework, and the robot's scenarios registered in it.
    import posekit.robot.scenarios  # noqa: F401
    from posekit.launch.scenarios import start_scenario

    if not duration >= 0.0:
        raise BagOptionError(f"duration must be >= 0 s, got {duration}")
    run = start_scenario(scenario, params, seed)
    try:
        recorder = attach_recorder(run, output, topics, **options)
        executor = run.executor
        assert isinstance(executor, SimulatedTimeExecutor)
        executor.run_for(duration)
        return recorder.close()
    finally:
        run.shutdown()
