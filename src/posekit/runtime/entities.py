"""Publisher, Subscription and Timer: what ``Node.create_*`` returns (rclpy's classes)."""

from __future__ import annotations

import inspect
import time
from collections import deque
from collections.abc import Callable
from typing import TYPE_CHECKING, Any, TypedDict

from posekit.runtime.callback_groups import CallbackGroup
from posekit.runtime.clock import Clock
from posekit.runtime.context import InvalidHandle
from posekit.runtime.qos import QoSProfile
from posekit.runtime.transport import PublisherEndpoint, SubscriptionEndpoint

if TYPE_CHECKING:
    from posekit.runtime.node import Node

__all__ = ["Publisher", "Subscription", "Timer"]

#: rclpy's text for an entity used after destroy().
_DESTROYED = "cannot use Destroyable because destruction was requested"


def _destroyed(*_args: object, **_kwargs: object) -> None:
    """What ``publish`` of a destroyed publisher is bound to."""
    raise InvalidHandle(_DESTROYED)


class Publisher:
    """Publishes messages of one type on one topic."""

    def __init__(
        self,
        node: Node,
        msg_type: type,
        topic: str,
        qos: QoSProfile,
        endpoint: PublisherEndpoint,
        given_topic: str | None = None,
    ) -> None:
        self._node = node
        self.msg_type = msg_type
        self._topic = topic
        self._given_topic = given_topic if given_topic is not None else topic
        self.qos_profile = qos
        self._endpoint = endpoint
        self.destroyed = False
        # Hot path: bind once.
        self.publish: Callable[[Any], None] = endpoint.publish
        #: ``publish_transfer(msg)``: publish a message the caller gives up and never reads
        #: or changes again (rclcpp's ``publish(std::unique_ptr<Msg>)``). The in-process bus
        #: then skips its publish snapshot and hands this object to the (last) subscriber;
        #: other transports treat it as ``publish`` (the contract's default). Not in rclpy: a
        #: posekit extension for nodes that build a fresh message per publish.
        self.publish_transfer: Callable[[Any], None] = endpoint.publish_transfer

    @property
    def topic_name(self) -> str:
        """Fully qualified (expanded, remapped) topic name."""
        if self.destroyed:
            raise InvalidHandle(_DESTROYED)
        return self._topic

    @property
    def topic(self) -> str:
        """The topic name as given to ``create_publisher`` (rclpy's; ``topic_name`` resolved)."""
        return self._given_topic

    def get_subscription_count(self) -> int:
        """Matched subscriptions."""
        if self.destroyed:
            raise InvalidHandle(_DESTROYED)
        return self._endpoint.subscription_count

    def destroy(self) -> None:
        """Same as ``node.destroy_publisher(self)``; afterwards ``publish`` raises InvalidHandle."""
        self._node.destroy_publisher(self)

    def _destroy(self) -> None:
        self.destroyed = True
        self.publish = self.publish_transfer = _destroyed
        self._endpoint.destroy()

    def __repr__(self) -> str:
        return f"Publisher({self.msg_type.__name__}, '{self._topic}')"


class MessageInfo(TypedDict):
    """rclpy's ``MessageInfo``: what a subscription callback ``callback(msg, info)`` gets.

    Times are ns since the epoch. The Zenoh transport fills the source timestamp and the
    publication sequence number from rmw_zenoh's sample attachment; the in-process bus has
    neither (0). ``reception_sequence_number`` is 0 (not provided, as rmw_zenoh).
    """

    source_timestamp: int
    received_timestamp: int
    publication_sequence_number: int
    reception_sequence_number: int


def _takes_message_info(callback: Callable[..., Any]) -> bool:
    """True for ``callback(msg, info)`` (two required positional parameters), as rclpy."""
    try:
        params = inspect.signature(callback).parameters.values()
    except (TypeError, ValueError):
        return False
    positional = [p for p in params
                  if p.kind in (p.POSITIONAL_ONLY, p.POSITIONAL_OR_KEYWORD)
                  and p.default is p.empty]
    return len(positional) == 2


class Subscription:
    """Receives messages of one type on one topic.

    The executor calls ``callback(msg)``, or ``callback(msg, info)`` (a :class:`MessageInfo`)
    for a callback taking two arguments.

    Undelivered messages wait in a queue bounded by the QoS depth (KEEP_LAST drops the
    oldest); each queued entry carries the context-wide sequence number of its arrival.
    """

    def __init__(
        self,
        node: Node,
        msg_type: type,
        topic: str,
        callback: Callable[..., Any],
        qos: QoSProfile,
        callback_group: CallbackGroup,
        given_topic: str | None = None,
    ) -> None:
        self._node = node
        self.msg_type = msg_type
        self._topic = topic
        self._given_topic = given_topic if given_topic is not None else topic
        #: True when the callback takes ``(msg, info)``; transports that know the sample's
        #: metadata then pass it to :meth:`_enqueue`.
        self.wants_message_info = _takes_message_info(callback)
        self.callback: Callable[[Any], Any] = callback
        if self.wants_message_info:
            with_info: Callable[[Any, Any], Any] = callback

            def unpack(payload: tuple[Any, MessageInfo]) -> Any:
                return with_info(payload[0], payload[1])

            self.callback = unpack
        self.qos_profile = qos
        self.callback_group = callback_group
        self.queue: deque[tuple[int, Any]] = deque(maxlen=qos.queue_limit)
        #: The node's hand-off to its executor (posekit's, not rclpy API).
        self.handoff = node.handoff
        #: What an executor's error report calls this callback.
        self.callback_description = f"subscription callback on '{topic}'"
        self._seq = node.context.seq
        self._endpoint: SubscriptionEndpoint | None = None
        self.destroyed = False

    def _attach(self, endpoint: SubscriptionEndpoint) -> None:
        self._endpoint = endpoint

    @property
    def endpoint(self) -> SubscriptionEndpoint | None:
        """The transport's endpoint (None until subscribed); posekit's, not rclpy API."""
        return self._endpoint

    def _enqueue(self, msg: Any, info: MessageInfo | None = None) -> None:
        """Transport sink: queue ``msg`` and tell the node's executor."""
        if self.destroyed:
            return
        if self.wants_message_info:
            msg = (msg, info if info is not None else MessageInfo(
                source_timestamp=0, received_timestamp=time.time_ns(),
                publication_sequence_number=0, reception_sequence_number=0))
        seq = next(self._seq)
        self.queue.append((seq, msg))
        inbox = self.handoff.inbox
        if inbox is not None:  # inbox.put(seq, self), without its frame (the hot path)
            inbox.append((seq, self))
            if inbox.waiting:
                inbox.wake()

    @property
    def topic_name(self) -> str:
        """Fully qualified (expanded, remapped) topic name."""
        if self.destroyed:
            raise InvalidHandle(_DESTROYED)
        return self._topic

    @property
    def topic(self) -> str:
        """The topic name as given to ``create_subscription`` (``topic_name``: resolved)."""
        return self._given_topic

    def get_publisher_count(self) -> int:
        """Matched publishers."""
        if self.destroyed:
            raise InvalidHandle(_DESTROYED)
        return self._endpoint.publisher_count if self._endpoint is not None else 0

    def destroy(self) -> None:
        """Same as ``node.destroy_subscription(self)``."""
        self._node.destroy_subscription(self)

    def _destroy(self) -> None:
        self.destroyed = True
        self.queue.clear()
        if self._endpoint is not None:
            self._endpoint.destroy()

    def __repr__(self) -> str:
        return f"Subscription({self.msg_type.__name__}, '{self._topic}')"


class Timer:
    """Calls ``callback()`` every ``period`` on ``clock`` (first call one period after start).

    Like rcl: if the clock moved past several periods at once, missed calls are skipped and
    the schedule stays on the original grid; a backward jump of the clock restarts the
    period from the new time. A None callback is accepted (rclpy's too); when such a timer
    comes due, calling it fails like any raising callback (logged; rclpy's spin raises).
    """

    #: What an executor's error report calls this callback.
    callback_description = "timer callback"

    def __init__(
        self,
        node: Node,
        callback: Callable[[], Any] | None,
        period_ns: int,
        clock: Clock,
        callback_group: CallbackGroup,
        autostart: bool = True,
    ) -> None:
        if period_ns < 0:
            raise ValueError(f"timer period must be >= 0, got {period_ns} ns")
        self._node = node
        self.callback = callback
        self._period_ns = int(period_ns)
        self.clock = clock
        self.callback_group = callback_group
        self.seq = next(node.context.seq)
        #: The node's hand-off to its executor (posekit's, not rclpy API).
        self.handoff = node.handoff
        self._canceled = not autostart
        now = clock.now_ns()
        #: Clock time (ns) of the last call (or the start); read-only for users.
        self.last_call_ns = now
        #: Clock time (ns) of the next call; read-only for users.
        self.next_call_ns = now + self._period_ns
        self.destroyed = False

    def _check_handle(self) -> None:
        if self.destroyed:
            raise InvalidHandle(_DESTROYED)

    @property
    def timer_period_ns(self) -> int:
        """Period in nanoseconds."""
        self._check_handle()
        return self._period_ns

    @timer_period_ns.setter
    def timer_period_ns(self, value: int) -> None:
        self._check_handle()
        self._period_ns = int(value)
        self.reset()

    def is_canceled(self) -> bool:
        """True after cancel()."""
        self._check_handle()
        return self._canceled

    def cancel(self) -> None:
        """Stop calling until reset()."""
        self._check_handle()
        self._canceled = True
        self.handoff.timers_changed()

    def reset(self) -> None:
        """Restart: next call one period from now."""
        self._check_handle()
        now = self.clock.now_ns()
        self._canceled = False
        self.last_call_ns = now
        self.next_call_ns = now + self._period_ns
        self.handoff.timers_changed()

    def _check_jump(self, now: int) -> None:
        if now < self.last_call_ns:  # the clock jumped back: restart the period
            self.last_call_ns = now
            self.next_call_ns = now + self._period_ns

    def is_ready(self) -> bool:
        """Whether the next call is due."""
        self._check_handle()
        return self.ready_now()

    def time_until_next_call(self) -> int | None:
        """Nanoseconds until the next call (<= 0 if due), None if canceled."""
        self._check_handle()
        return self.ns_until_next_call()

    def time_since_last_call(self) -> int:
        """Nanoseconds since the last call (or the start)."""
        self._check_handle()
        return self.clock.now_ns() - self.last_call_ns

    # -- the schedule's view (posekit's; never raises, False/None once destroyed) ---------
    @property
    def stopped(self) -> bool:
        """Canceled or destroyed: not to be called."""
        return self._canceled or self.destroyed

    @property
    def period_ns(self) -> int:
        """The period in nanoseconds (``timer_period_ns`` without the destroyed check)."""
        return self._period_ns

    def ready_now(self) -> bool:
        """``is_ready()`` for the executor: False once destroyed instead of raising."""
        if self._canceled or self.destroyed:
            return False
        now = self.clock.now_ns()
        self._check_jump(now)
        return now >= self.next_call_ns

    def ns_until_next_call(self) -> int | None:
        """``time_until_next_call()`` for the executor: None once destroyed."""
        if self._canceled or self.destroyed:
            return None
        now = self.clock.now_ns()
        self._check_jump(now)
        return self.next_call_ns - now

    def mark_called(self, now_ns: int | None = None) -> None:
        """An executor took this timer's call now: the next call moves one period on.

        It moves to the first one after now, skipping missed periods.
        """
        now = self.clock.now_ns() if now_ns is None else now_ns
        self.last_call_ns = now
        nxt = self.next_call_ns + self._period_ns
        if nxt <= now and self._period_ns > 0:
            missed = (now - nxt) // self._period_ns + 1
            nxt += missed * self._period_ns
        elif self._period_ns == 0:
            # "As often as possible": ready again as soon as the clock moves (a frozen sim
            # clock would otherwise re-fire it forever within one step).
            nxt = now + 1
        self.next_call_ns = nxt

    def destroy(self) -> None:
        """Same as ``node.destroy_timer(self)``; afterwards its methods raise InvalidHandle."""
        self._node.destroy_timer(self)

    def __repr__(self) -> str:
        return f"Timer(period={self._period_ns} ns, clock={self.clock.clock_type.name})"
