"""ROS services over DDS, as rmw_cyclonedds carries them (server and client endpoints).

A server is a reader on ``rq/<service>Request`` and a writer on ``rr/<service>Reply``; a
client the reverse (names, types and the payload layout: :mod:`posekit.transport.dds_wire`).
Both endpoints of one server (client) carry the same ``serviceid=`` (``clientid=``) in their
USER_DATA, so either side can tell which reader and writer belong together.

* A client numbers its requests and writes each with its id (the instance handle of its
  request writer, a uint64, as rmw_cyclonedds uses) in the request header. Every client of
  the service receives every reply; a client takes only replies carrying its own id and the
  number of a request still pending, each at most once. DDS delivers a request to every
  matched server, so with two servers the first reply wins.
* A request written before a server's reader has matched the client's writer is lost (DDS
  keeps no history for a VOLATILE reader that did not exist yet). :attr:`server_count`
  therefore counts a server only once the client's request writer is matched to that
  server's request reader *and* the client's reply reader to its reply writer (as
  rmw_cyclonedds's ``rmw_service_server_is_available``); ``wait_for_service`` polls it. A
  server in turn waits up to 100 ms for its reply writer to match the calling client's reply
  reader before it answers (matching is not symmetric in time), as rmw_cyclonedds does.
* One thread per participant delivers the samples of all its servers' and clients' readers
  (:class:`ServiceDispatcher`, woken by a Cyclone wait set holding each reader's data
  condition), so a node's six parameter services cost no threads of their own. Sinks are
  called on that thread and must return quickly (the runtime's only queue the request or
  response for an executor). A malformed payload (shorter than the header, CDR that does
  not decode) is dropped with a logged reason, at most one line a second per reason, and
  never raises into the delivery thread. Requests from a writer without a ``clientid`` (Fast
  DDS: its requests carry no header) are dropped the same way (Cyclone itself already
  discards those too short for the header-carrying type), and servers without a
  ``serviceid`` are not counted, because they speak another format.
* The client id servers see (:class:`~posekit.runtime.transport.RequestHeader`'s
  ``client_gid``) is the 8-byte id followed by 8 zero bytes, which is also the client
  endpoint's :attr:`~DdsServiceClient.gid`, so both sides of a call name the client alike.
"""

from __future__ import annotations

import itertools
import logging
import threading
import time
from collections.abc import Callable
from typing import TYPE_CHECKING, Any

from cyclonedds._clayer import ddspy_write
from cyclonedds.core import GuardCondition, ReadCondition, WaitSet
from cyclonedds.domain import DomainParticipant
from cyclonedds.pub import DataWriter
from cyclonedds.qos import Policy
from cyclonedds.sub import DataReader
from cyclonedds.util import duration

from posekit.msgs.cdr import from_cdr, to_cdr
from posekit.msgs.errors import CdrError
from posekit.runtime.ratelimit import RateLimitedLog
from posekit.runtime.transport import (
    RequestHeader,
    RequestSink,
    ResponseSink,
    ServiceClientEndpoint,
    ServiceInfo,
    ServiceServerEndpoint,
)
from posekit.transport.dds_transport import (
    _ANY,
    QOS_CONVERSION_LOCK,
    _delete,
    drain_reader,
    endpoint_qos,
)
from posekit.transport.dds_types import idl_service_struct
from posekit.transport.dds_wire import (
    decode_service_payload,
    encode_service_payload,
    format_client_service_id,
    parse_user_data,
    service_topic_names,
    user_data_type_hash,
)
from posekit.transport.zenoh_wire import type_hash

if TYPE_CHECKING:
    from posekit.transport.dds_transport import DdsTransport

__all__ = ["DdsServiceClient", "DdsServiceServer", "ServiceDispatcher", "client_gid"]

_log = logging.getLogger("posekit.transport.dds")
#: How long a server waits for the calling client's reply reader to match (rmw_cyclonedds).
_REPLY_MATCH_WAIT_S = 0.1
#: Remembered request writers (their client ids) per server before the table starts over.
_MAX_KNOWN_WRITERS = 1024


def client_gid(client_id: int) -> bytes:
    """The 16-byte client id servers see: the 8-byte id (little endian), 8 zero bytes."""
    return client_id.to_bytes(8, "little") + bytes(8)


def _user_data(qos: Any) -> dict[str, str]:
    try:
        return parse_user_data(bytes(qos[Policy.Userdata].data))
    except (KeyError, TypeError, AttributeError):
        return {}


PayloadSink = Callable[[bytes, Any], None]


class ServiceDispatcher:
    """The thread that takes every service reader's samples of one participant.

    ``on_payload(data, sample_info)`` per valid sample, in arrival order per reader. The
    sinks handle their own errors; anything else is logged (rate limited) and the thread
    keeps going.
    """

    def __init__(self, participant: DomainParticipant) -> None:
        self._waitset = WaitSet(participant)
        self._stop = GuardCondition(participant)
        self._waitset.attach(self._stop)
        self._lock = threading.Lock()
        self._readers: dict[int, tuple[ReadCondition, DataReader[Any], PayloadSink]] = {}
        self._closed = False
        self._warn = RateLimitedLog(_log.warning)
        self._thread = threading.Thread(target=self._run, name="posekit-dds-services",
                                        daemon=True)
        self._thread.start()

    def add(self, reader: DataReader[Any], on_payload: PayloadSink) -> None:
        """Deliver ``reader``'s samples to ``on_payload`` from now on."""
        condition = ReadCondition(reader, _ANY)
        with self._lock:
            self._readers[reader._ref] = (condition, reader, on_payload)
        self._waitset.attach(condition)

    def remove(self, reader: DataReader[Any]) -> None:
        """Stop delivering ``reader``'s samples (before it is deleted)."""
        with self._lock:
            entry = self._readers.pop(reader._ref, None)
        if entry is not None:
            try:
                self._waitset.detach(entry[0])
            except Exception as exc:  # deleted with its participant
                _log.debug("detaching %r: %s", entry[0], exc)

    def _run(self) -> None:
        timeout = duration(seconds=1)
        while not self._closed:
            try:
                self._waitset.wait(timeout)
                if self._closed:
                    return
                with self._lock:
                    entries = list(self._readers.values())
                for condition, reader, on_payload in entries:
                    if condition.triggered:
                        drain_reader(reader._ref, on_payload)
            except Exception as exc:  # keep delivering whatever arrives
                if self._closed:
                    return
                self._warn("DDS service delivery failed", f"{type(exc).__name__}: {exc}")
                time.sleep(0.05)

    def close(self) -> None:
        """Stop the thread (before the participant is deleted)."""
        self._closed = True
        try:
            self._stop.set(True)
        except Exception as exc:  # already gone with the participant
            _log.debug("waking the service thread: %s", exc)
        if self._thread is not threading.current_thread():
            self._thread.join(timeout=2.0)


class _ServiceEndpoints:
    """The reader and writer of a server or a client, created together, deleted together."""

    def __init__(self, owner: DdsTransport, info: ServiceInfo, *, server: bool,
                 on_payload: Callable[[bytes, Any], None]) -> None:
        self._owner = owner
        self.info = info
        srv: Any = info.srv_type
        self.request_type: str = srv.Request.__msgtype__
        self.response_type: str = srv.Response.__msgtype__
        rq, rr = service_topic_names(info.service)
        csid = format_client_service_id(owner.next_client_service_id())
        user = f"{'serviceid' if server else 'clientid'}={csid};".encode()
        read_topic, read_type = (rq, self.request_type) if server else (rr, self.response_type)
        write_topic, write_type = (rr, self.response_type) if server else (rq, self.request_type)
        self.writer: DataWriter[Any] = DataWriter(
            owner.participant, owner._topic(write_topic, write_type, idl_service_struct),
            endpoint_qos(info.qos, user + user_data_type_hash(write_type, type_hash(write_type)),
                         writer=True))
        self.writer_gid: bytes = self.writer.guid.bytes
        self.alive = True
        #: Dropped payloads by reason.
        self.dropped: dict[str, int] = {}
        self._warn = RateLimitedLog(self._log_warning)
        try:
            self.reader: DataReader[Any] = DataReader(
                owner.participant, owner._topic(read_topic, read_type, idl_service_struct),
                endpoint_qos(info.qos, user + user_data_type_hash(read_type, type_hash(read_type)),
                             writer=False))
        except BaseException:
            _delete(self.writer)
            raise
        self.reader_gid: bytes = self.reader.guid.bytes
        self._dispatcher = owner.service_dispatcher()
        self._dispatcher.add(self.reader, on_payload)

    def _log_warning(self, line: str) -> None:
        try:
            self.info.logger.warning(line)
        except Exception:  # a broken logger must not kill the delivery thread
            _log.exception("warning callback failed")

    def drop(self, reason: str, detail: str) -> None:
        """Count a dropped payload and log its reason (rate limited per reason)."""
        self.dropped[reason] = self.dropped.get(reason, 0) + 1
        self._warn(f"service '{self.info.service}': {reason}", detail)

    def close(self) -> None:
        """Stop delivering and leave the graph (idempotent)."""
        if self.alive:
            self.alive = False
            self._dispatcher.remove(self.reader)
            self._owner._forget_service(self)


class DdsServiceServer(ServiceServerEndpoint):
    """A service server on DDS (see the module docstring)."""

    def __init__(self, owner: DdsTransport, info: ServiceInfo, sink: RequestSink) -> None:
        self._sink = sink
        self._response_cls: Any = getattr(info.srv_type, "Response")  # noqa: B009
        self._request_cls: Any = getattr(info.srv_type, "Request")  # noqa: B009
        self._clients: dict[int, str | None] = {}  # request writer handle -> its clientid
        self.entities = _ServiceEndpoints(owner, info, server=True, on_payload=self._on_request)
        self.requests = 0

    @property
    def alive(self) -> bool:
        """Whether the server still takes requests."""
        return self.entities.alive

    def _client_id_of(self, handle: int | None) -> str | None:
        """The ``clientid`` of the request writer ``handle`` ("" when it has none)."""
        if handle is None:
            return None
        known = self._clients.get(handle)
        if known is not None or handle in self._clients:
            return known
        try:
            with QOS_CONVERSION_LOCK:
                writer = self.entities.reader.get_matched_publication_data(handle)
        except Exception:  # gone (or never matched)
            writer = None
        clientid = None if writer is None else _user_data(writer.qos).get("clientid", "")
        if len(self._clients) >= _MAX_KNOWN_WRITERS:
            self._clients.clear()
        self._clients[handle] = clientid
        return clientid

    def _on_request(self, data: bytes, sample_info: Any) -> None:
        entities = getattr(self, "entities", None)
        if entities is None or not entities.alive:  # being created (nothing matched) or gone
            return
        handle = getattr(sample_info, "publication_handle", None)
        clientid = self._client_id_of(None if handle is None else int(handle))
        if clientid == "":
            entities.drop("dropping a request from a client that is not rmw_cyclonedds's",
                          "its writer announces no clientid (a Fast DDS client sends no "
                          "request header)")
            return
        try:
            client_id, seq, body = decode_service_payload(data)
            request = from_cdr(body, self._request_cls)
        except (ValueError, CdrError) as exc:
            entities.drop("dropping a malformed request", str(exc))
            return
        self.requests += 1
        answered = threading.Lock()

        def respond(response: Any) -> None:
            if entities.alive and answered.acquire(blocking=False):
                self._reply(response, client_id, seq, clientid)

        try:
            self._sink(request, respond, RequestHeader(client_gid(client_id), seq))
        except Exception as exc:  # never into the delivery thread
            entities.drop("request callback failed", f"{type(exc).__name__}: {exc}")

    def _reply_reader_matched(self, clientid: str | None) -> bool:
        if not clientid:
            return True
        writer = self.entities.writer
        for handle in writer.get_matched_subscriptions():
            try:
                with QOS_CONVERSION_LOCK:
                    reader = writer.get_matched_subscription_data(handle)
            except Exception:
                continue
            if reader is not None and _user_data(reader.qos).get("clientid") == clientid:
                return True
        return False

    def _reply(self, response: Any, client_id: int, seq: int, clientid: str | None) -> None:
        entities = self.entities
        try:
            payload = encode_service_payload(
                to_cdr(response, entities.response_type), client_id, seq)
            deadline = time.monotonic() + _REPLY_MATCH_WAIT_S
            while not self._reply_reader_matched(clientid) and time.monotonic() < deadline:
                time.sleep(0.01)
            ret = ddspy_write(entities.writer._ref, payload)
        except Exception as exc:  # a response that does not serialize, a deleted writer
            entities.drop("cannot send a response", f"{type(exc).__name__}: {exc}")
            return
        if ret < 0:
            entities.drop("cannot send a response", f"DDS write failed (code {ret})")

    def destroy(self) -> None:
        """Leave the graph; requests still arriving are dropped, answers not sent."""
        self.entities.close()


class DdsServiceClient(ServiceClientEndpoint):
    """A service client on DDS (see the module docstring)."""

    def __init__(self, owner: DdsTransport, info: ServiceInfo) -> None:
        self._response_cls: Any = getattr(info.srv_type, "Response")  # noqa: B009
        self._lock = threading.Lock()
        self._pending: dict[int, ResponseSink] = {}
        self._numbers = itertools.count(1)
        self._warned_foreign = False
        self.entities = _ServiceEndpoints(owner, info, server=False, on_payload=self._on_reply)
        # the request writer's instance handle, as rmw_cyclonedds (Python reads it signed)
        self.client_id: int = int(self.entities.writer.get_instance_handle()) & 0xFFFFFFFFFFFFFFFF
        self._gid = client_gid(self.client_id)

    @property
    def gid(self) -> bytes:
        """The 8-byte client id in the request header, then 8 zero bytes."""
        return self._gid

    def send_request(self, request: Any, on_response: ResponseSink,
                     header: RequestHeader | None = None) -> None:
        """Write ``request`` with this client's id and a sequence number.

        ``header`` (the caller's numbering) must name this client (:attr:`gid`).
        """
        entities = self.entities
        if not entities.alive:
            raise RuntimeError(f"client of '{entities.info.service}' has been destroyed")
        if header is not None and header.client_gid != self._gid:
            raise ValueError("a DDS client sends its own id with each request")
        seq = next(self._numbers) if header is None else header.sequence_number
        payload = encode_service_payload(
            to_cdr(request, entities.request_type), self.client_id, seq)
        with self._lock:
            self._pending[seq] = on_response
        ret = ddspy_write(entities.writer._ref, payload)
        if ret < 0:
            with self._lock:
                self._pending.pop(seq, None)
            if ret == -10:  # DDS_RETCODE_TIMEOUT: the servers' readers are not keeping up
                entities.drop("request not sent", "a server is not keeping up (100 ms)")
                return
            raise RuntimeError(
                f"DDS write of a request to '{entities.info.service}' failed (code {ret})")

    def _on_reply(self, data: bytes, sample_info: Any) -> None:
        del sample_info
        entities = getattr(self, "entities", None)
        if entities is None or not hasattr(self, "client_id"):  # still being created
            return
        try:
            client_id, seq, body = decode_service_payload(data)
        except ValueError as exc:
            entities.drop("dropping a malformed reply", str(exc))
            return
        if client_id != self.client_id:
            return  # the reply to another client of this service
        with self._lock:
            waiting = seq in self._pending
        if not waiting:
            return  # answered already (another server), or forgotten
        try:
            response = from_cdr(body, self._response_cls)
        except CdrError as exc:
            entities.drop("dropping a malformed reply", str(exc))
            return
        with self._lock:
            on_response = self._pending.pop(seq, None)
        if on_response is None:
            return
        try:
            on_response(response)
        except Exception:
            _log.exception("response callback of %s raised", entities.info.service)

    @property
    def server_count(self) -> int:
        """Servers matched in both directions (request reader and reply writer).

        Servers are told apart by the ``serviceid`` both their endpoints announce; servers
        without one (not rmw_cyclonedds) are not counted, and said so once.
        """
        entities = self.entities
        if not entities.alive:
            return 0
        try:
            request_readers = self._service_ids(
                entities.writer, entities.writer.get_matched_subscriptions(), readers=True)
            reply_writers = self._service_ids(
                entities.reader, entities.reader.get_matched_publications(), readers=False)
        except Exception:  # deleted underneath (context shut down)
            return 0
        foreign = "" in request_readers or "" in reply_writers
        if foreign and not self._warned_foreign:
            self._warned_foreign = True
            entities.drop(
                "a server cannot be called",
                "it announces no serviceid (not rmw_cyclonedds's service format, e.g. Fast "
                "DDS); posekit's DDS services call posekit and rmw_cyclonedds servers only")
        return len((request_readers & reply_writers) - {""})

    @staticmethod
    def _service_ids(entity: Any, handles: list[int], *, readers: bool) -> set[str]:
        ids: set[str] = set()
        for handle in handles:
            try:
                with QOS_CONVERSION_LOCK:
                    data = (entity.get_matched_subscription_data(handle) if readers
                            else entity.get_matched_publication_data(handle))
            except Exception:
                continue
            if data is not None:
                ids.add(_user_data(data.qos).get("serviceid", ""))
        return ids

    def destroy(self) -> None:
        """Leave the graph; responses still in flight are dropped."""
        with self._lock:
            self._pending.clear()
        self.entities.close()

