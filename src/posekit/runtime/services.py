"""Service and Client: what ``Node.create_service`` / ``create_client`` return (rclpy's).

A server's requests wait in its queue and run on the node's executor like subscription
callbacks (same arrival order across the context, same callback groups):
``callback(request, response) -> response``, where ``response`` is a fresh
``srv_type.Response()``; a coroutine callback is awaited as a task. Returning something
other than a ``Response`` is logged and the request gets no answer (rclpy raises in the
executor instead).

A client's ``call_async(request)`` returns a :class:`~posekit.runtime.task.Future`. The
response is queued for the client's node's executor, which completes the future there (as
rclpy does), so under :class:`~posekit.runtime.sim_executor.SimulatedTimeExecutor` a request,
its handling and its response happen in a reproducible order. For a client node in no
executor the response completes the future where it arrives (over a network transport on a
thread of its own: done-callbacks never hold the transport's receive thread).
``call(request)`` blocks:

* in a thread that is not spinning the node's executor, it waits for another thread (or
  the transport) to complete the future; when the node has no executor at all, the
  response completes the future directly, so a plain script never hangs;
* inside a callback of an executor (where rclpy's single-threaded executor deadlocks), it
  keeps running that executor's other ready callbacks until the response arrives, so a
  server on another node of the same executor is served. A server in the caller's own
  mutually exclusive callback group cannot run meanwhile: pass ``timeout_sec``.

Service introspection (ROS 2 Jazzy's, off by default as in rclpy):
``configure_introspection(clock, qos, ServiceIntrospectionState.CONTENTS)`` on a Service or a
Client publishes a ``<srv>_Event`` message (``service_msgs/msg/ServiceEventInfo info``,
``request[<=1]``, ``response[<=1]``) on the hidden topic ``<service>/_service_event`` for each
step of a call: a client's REQUEST_SENT and RESPONSE_RECEIVED, a server's REQUEST_RECEIVED
(when its executor takes the request, as ``rcl_take_request``) and RESPONSE_SENT. ``info``
holds the event type, the ``clock``'s time, the calling client's 16-byte id and the
request's sequence number; METADATA leaves ``request``/``response`` empty, CONTENTS includes
them, OFF removes the event publisher. A client numbers its requests 1, 2, ... and its id is
its transport endpoint's GID (rmw_zenoh's client GID on Zenoh, a random one in process).
The request carries both to the server (as rmw's request header), so the server's events
of a call carry the same client id and sequence number as the client's, as in rcl. This is
what ``ros2 bag record --services`` / ``posekit bag record --services`` record.
"""

from __future__ import annotations

import enum
import inspect
import threading
import time
import traceback
from collections import deque
from collections.abc import Callable
from typing import TYPE_CHECKING, Any

from posekit.runtime.callback_groups import CallbackGroup
from posekit.runtime.qos import QoSProfile
from posekit.runtime.task import Future
from posekit.runtime.transport import (
    RequestHeader,
    ResponseSink,
    ServiceClientEndpoint,
    ServiceServerEndpoint,
)

if TYPE_CHECKING:
    from posekit.runtime.executors import Executor
    from posekit.runtime.node import Node

__all__ = ["SERVICE_EVENT_SUFFIX", "Client", "Service", "ServiceIntrospectionState"]

#: What service introspection appends to a service name for its event topic (rcl's
#: ``RCL_SERVICE_INTROSPECTION_TOPIC_POSTFIX``).
SERVICE_EVENT_SUFFIX = "/_service_event"


class ServiceIntrospectionState(enum.IntEnum):
    """How much a service or client publishes about its calls (rclpy's enum)."""

    OFF = 0
    METADATA = 1
    CONTENTS = 2


class _EventType(enum.IntEnum):
    """``service_msgs/msg/ServiceEventInfo`` event types."""

    REQUEST_SENT = 0
    REQUEST_RECEIVED = 1
    RESPONSE_SENT = 2
    RESPONSE_RECEIVED = 3


class _Introspection:
    """The event publisher of one service or client (see the module docstring)."""

    def __init__(self, node: Node, srv_type: Any, service_name: str, clock: Any,
                 qos: QoSProfile, state: ServiceIntrospectionState) -> None:
        from posekit.msgs._service import service_type_name
        from posekit.msgs.cdr import get_typestore

        type_name = service_type_name(srv_type)
        types = get_typestore().types
        self._event_cls = types[f"{type_name}_Event"]
        self._info_cls = types["service_msgs/msg/ServiceEventInfo"]
        self._clock = clock
        self.state = state
        self.publisher = node.create_publisher(
            self._event_cls, service_name + SERVICE_EVENT_SUFFIX, qos)

    def publish(self, event_type: _EventType, client_gid: bytes, sequence_number: int,
                request: Any = None, response: Any = None) -> None:
        import numpy as np

        contents = self.state == ServiceIntrospectionState.CONTENTS
        info = self._info_cls(
            event_type=int(event_type),
            stamp=self._clock.now().to_msg(),
            client_gid=np.frombuffer(client_gid, dtype=np.uint8).copy(),
            sequence_number=int(sequence_number),
        )
        self.publisher.publish(self._event_cls(
            info=info,
            request=[request] if contents and request is not None else [],
            response=[response] if contents and response is not None else [],
        ))


def _configure(current: _Introspection | None, node: Node, srv_type: Any, name: str,
               clock: Any, qos: QoSProfile,
               state: ServiceIntrospectionState | int) -> _Introspection | None:
    """The introspection a ``configure_introspection`` call leaves in place."""
    state = ServiceIntrospectionState(int(state))
    if state == ServiceIntrospectionState.OFF:
        if current is not None:
            node.destroy_publisher(current.publisher)
        return None
    if current is not None:
        current.state = state
        current._clock = clock
        return current
    return _Introspection(node, srv_type, name, clock, qos, state)


_spinning = threading.local()


def current_executor() -> Executor | None:
    """The executor whose callback the calling thread is running, if any."""
    executor: Executor | None = getattr(_spinning, "executor", None)
    return executor


def set_current_executor(executor: Executor | None) -> Executor | None:
    """Record that this thread now runs ``executor``'s callbacks; returns the previous."""
    previous = getattr(_spinning, "executor", None)
    _spinning.executor = executor
    return previous


class _Queued:
    """The part of a Service/Client the executor sees.

    A queue drained through ``callback`` in the node's callback group, like a Subscription's.
    """

    def __init__(self, node: Node, name: str, callback_group: CallbackGroup,
                 run: Callable[[Any], None], what: str, limit: int | None = None) -> None:
        self._node = node
        self.topic_name = name
        self.callback_group = callback_group
        self.callback = run
        self.callback_description = what
        self.queue: deque[tuple[int, Any]] = deque(maxlen=limit)
        self.destroyed = False
        self.handoff = node.handoff
        self._seq = node.context.seq

    def enqueue(self, payload: Any) -> None:
        if self.destroyed:
            return
        seq = next(self._seq)
        self.queue.append((seq, payload))
        inbox = self.handoff.inbox
        if inbox is not None:
            inbox.put(seq, self)


class Service:
    """A service server (rclpy.service.Service)."""

    def __init__(
        self,
        node: Node,
        srv_type: type,
        srv_name: str,
        callback: Callable[[Any, Any], Any],
        qos: QoSProfile,
        callback_group: CallbackGroup,
        given_name: str | None = None,
    ) -> None:
        self._node = node
        self.srv_type: Any = srv_type
        self._srv_name = srv_name
        #: The name as given to ``create_service`` (rclpy's attribute; ``service_name`` is
        #: the expanded one).
        self.srv_name = srv_name if given_name is None else given_name
        self.callback = callback
        self.qos_profile = qos
        self.callback_group = callback_group
        # Requests waiting for the executor: at most the QoS depth (KEEP_LAST drops the
        # oldest, which then never gets an answer, as with rmw's request queue).
        self._queued = _Queued(
            node, srv_name, callback_group, self._handle,
            f"service callback of '{srv_name}'", qos.queue_limit,
        )
        self._endpoint: ServiceServerEndpoint | None = None
        self._introspection: _Introspection | None = None

    def configure_introspection(self, clock: Any, service_event_qos_profile: QoSProfile,
                                introspection_state: ServiceIntrospectionState | int) -> None:
        """Publish (or stop publishing) this server's service events (module docstring)."""
        self._introspection = _configure(
            self._introspection, self._node, self.srv_type, self._srv_name, clock,
            service_event_qos_profile, introspection_state)

    def _attach(self, endpoint: ServiceServerEndpoint) -> None:
        self._endpoint = endpoint

    def _receive(self, request: Any, respond: ResponseSink, header: RequestHeader) -> None:
        """Transport sink: queue the request for the executor."""
        self._queued.enqueue((request, respond, header))

    def _handle(self, payload: tuple[Any, ResponseSink, RequestHeader]) -> None:
        request, respond, header = payload
        introspection = self._introspection
        if introspection is not None:
            introspection.publish(_EventType.REQUEST_RECEIVED, header.client_gid,
                                  header.sequence_number, request)
            respond = self._introspected(respond, header)
        result = self.callback(request, self.srv_type.Response())
        if inspect.iscoroutine(result):
            executor = self._node.executor
            if executor is None:  # cannot happen from the executor; be safe
                result.close()
                return
            task = executor.create_task(result)
            task.add_done_callback(lambda f: self._finish(f, respond))
            return
        self._send(result, respond)

    def _introspected(self, respond: ResponseSink, header: RequestHeader) -> ResponseSink:
        def send(response: Any) -> None:
            introspection = self._introspection
            if introspection is not None:
                introspection.publish(_EventType.RESPONSE_SENT, header.client_gid,
                                      header.sequence_number, response=response)
            respond(response)

        return send

    def _finish(self, future: Future[Any], respond: ResponseSink) -> None:
        exc = future.exception()
        if exc is not None:
            tb = "".join(traceback.format_exception(type(exc), exc, exc.__traceback__))
            self._node.get_logger().error(
                f"Exception in service callback of '{self._srv_name}':\n{tb.rstrip()}"
            )
            return
        self._send(future.result(), respond)

    def _send(self, response: Any, respond: ResponseSink) -> None:
        if not isinstance(response, self.srv_type.Response):
            self._node.get_logger().error(
                f"service callback of '{self._srv_name}' returned {type(response).__name__}, "
                f"expected {self.srv_type.Response.__name__}; the request gets no response"
            )
            return
        respond(response)

    @property
    def service_name(self) -> str:
        """Fully qualified (expanded, remapped) service name."""
        return self._srv_name

    def destroy(self) -> bool:
        """Same as ``node.destroy_service(self)``."""
        return self._node.destroy_service(self)

    def _destroy(self) -> None:
        self._queued.destroyed = True
        self._queued.queue.clear()
        if self._endpoint is not None:
            self._endpoint.destroy()

    def __repr__(self) -> str:
        return f"Service({self.srv_type.__name__}, '{self._srv_name}')"


class Client:
    """A service client (rclpy.client.Client)."""

    def __init__(
        self,
        node: Node,
        srv_type: type,
        srv_name: str,
        qos: QoSProfile,
        callback_group: CallbackGroup,
        endpoint: ServiceClientEndpoint,
        given_name: str | None = None,
    ) -> None:
        self._node = node
        self.srv_type: Any = srv_type
        self._srv_name = srv_name
        #: The name as given to ``create_client`` (rclpy's attribute; ``service_name`` is
        #: the expanded one).
        self.srv_name = srv_name if given_name is None else given_name
        self.qos_profile = qos
        self.callback_group = callback_group
        self._endpoint = endpoint
        self._lock = threading.Lock()
        self._pending: dict[int, Future[Any]] = {}
        self._next_id = 1
        self._queued = _Queued(
            node, srv_name, callback_group, self._complete,
            f"client response of '{srv_name}'",
        )
        self._destroyed = False
        self._introspection: _Introspection | None = None
        self._gid = endpoint.gid  # this client's id, sent with requests and in its events

    def configure_introspection(self, clock: Any, service_event_qos_profile: QoSProfile,
                                introspection_state: ServiceIntrospectionState | int) -> None:
        """Publish (or stop publishing) this client's service events (module docstring)."""
        self._introspection = _configure(
            self._introspection, self._node, self.srv_type, self._srv_name, clock,
            service_event_qos_profile, introspection_state)

    @property
    def service_name(self) -> str:
        """Fully qualified (expanded, remapped) service name."""
        return self._srv_name

    def _send(self, request: Any, direct: bool) -> Future[Any]:
        if self._destroyed:
            raise RuntimeError(f"client of '{self._srv_name}' has been destroyed")
        if not isinstance(request, self.srv_type.Request):
            raise TypeError(
                f"Request must be instance of '{self.srv_type.Request.__name__}', "
                f"got '{type(request).__name__}'"
            )
        future: Future[Any] = Future()
        with self._lock:
            request_id = self._next_id
            self._next_id += 1
            self._pending[request_id] = future

        def on_response(response: Any) -> None:
            # (on the transport's thread, which must never block)
            if direct:  # call(): only the caller's wait holds this future
                self._complete((request_id, response))
            elif self._node.executor is not None:
                self._queued.enqueue((request_id, response))
            elif self._node.transport.crosses_processes:
                # No executor, a network transport's receive thread: the future's
                # done-callbacks, user code, run on a thread of their own (one may make a
                # blocking call whose response this thread must deliver)
                threading.Thread(target=self._complete, args=((request_id, response),),
                                 name=f"posekit response {self._srv_name}",
                                 daemon=True).start()
            else:  # in process: on the thread that ran the server's callback
                self._complete((request_id, response))

        introspection = self._introspection
        if introspection is not None:
            introspection.publish(_EventType.REQUEST_SENT, self._gid, request_id, request)
        self._endpoint.send_request(request, on_response, RequestHeader(self._gid, request_id))
        return future

    def _complete(self, payload: tuple[int, Any]) -> None:
        request_id, response = payload
        with self._lock:
            future = self._pending.pop(request_id, None)
        if future is None:
            return
        introspection = self._introspection
        if introspection is not None:
            introspection.publish(_EventType.RESPONSE_RECEIVED, self._gid, request_id,
                                  response=response)
        if not future.done():
            future.set_result(response)

    def call_async(self, request: Any) -> Future[Any]:
        """Send ``request``; the Future completes with the response (on the executor)."""
        return self._send(request, direct=False)

    def call(self, request: Any, timeout_sec: float | None = None) -> Any:
        """Send ``request`` and block until the response (see the module docstring).

        Returns the response, or None after ``timeout_sec`` seconds without one (the request
        is then forgotten, as rclpy's ``remove_pending_request``).
        """
        future = self._send(request, direct=True)
        executor = current_executor()
        if executor is not None:  # inside a callback: keep that executor's work going
            executor.serve_until_future_complete(future, timeout_sec)
        else:
            future.wait(timeout_sec)
        if not future.done():
            self.remove_pending_request(future)
            return None
        return future.result()

    def remove_pending_request(self, future: Future[Any]) -> None:
        """Forget a pending request; its response, if it comes, is dropped."""
        with self._lock:
            for request_id, pending in list(self._pending.items()):
                if pending is future:
                    del self._pending[request_id]

    def service_is_ready(self) -> bool:
        """Whether a server of this service is available now."""
        return not self._destroyed and self._endpoint.server_count > 0

    def wait_for_service(self, timeout_sec: float | None = None) -> bool:
        """Wait (wall time) until a server is available; False after ``timeout_sec``."""
        deadline = None if timeout_sec is None or timeout_sec < 0 else (
            time.monotonic() + timeout_sec
        )
        delay = 0.001
        while not self.service_is_ready():
            if not self._node.context.ok() or self._destroyed:
                return False
            if deadline is not None:
                remaining = deadline - time.monotonic()
                if remaining <= 0:
                    return False
                delay = min(delay, remaining)
            time.sleep(delay)
            delay = min(delay * 2, 0.05)
        return True

    def destroy(self) -> bool:
        """Same as ``node.destroy_client(self)``."""
        return self._node.destroy_client(self)

    def _destroy(self) -> None:
        self._destroyed = True
        self._queued.destroyed = True
        self._queued.queue.clear()
        self._endpoint.destroy()

    def __repr__(self) -> str:
        return f"Client({self.srv_type.__name__}, '{self._srv_name}')"
