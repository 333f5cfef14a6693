from rclpy.executors import SingleThreadedExecutor
from rclpy.node import Node
from rclpy.task import Future

import rclpy

f = Future()
show("pending", lambda: (f.done(), f.cancelled(), f.result(), f.exception()))
seen = []
f.add_done_callback(lambda fut: seen.append(("cb", fut.result())))
f.set_result(3)
show("done", lambda: (f.done(), f.cancelled(), f.result(), f.exception(), seen))
f.set_result(4)
show("set twice", lambda: f.result())
late = []
f.add_done_callback(lambda fut: late.append(fut.result()))
show("callback after done", lambda: late)

e = Future()
e.set_exception(ValueError("bad"))
show("exception", lambda: (e.done(), repr(e.exception())))
show("exception result", lambda: e.result())

c = Future()
called = []
c.add_done_callback(lambda fut: called.append(fut.cancelled()))
c.cancel()
show("cancelled", lambda: (c.done(), c.cancelled(), called))
show("cancelled result", lambda: c.result())
c.set_result(1)
show("result after cancel", lambda: (c.cancelled(), c.done()))

rclpy.init()
node = Node("diff_futures")
executor = SingleThreadedExecutor()
executor.add_node(node)
never = Future()
executor.spin_until_future_complete(never, timeout_sec=0.05)
show("timeout leaves it pending", lambda: never.done())
inner = Future()


async def waiter():
    value = await inner
    return value * 2


task = executor.create_task(waiter)
show("task pending", lambda: task.done())
executor.spin_once(timeout_sec=0.1)
inner.set_result(21)
executor.spin_until_future_complete(task, timeout_sec=1.0)
show("task result", lambda: (task.done(), task.result()))


plain = executor.create_task(lambda: 5)
executor.spin_until_future_complete(plain, timeout_sec=1.0)
show("plain callable task", lambda: plain.result())
timer_calls = []
timer = node.create_timer(0.01, lambda: timer_calls.append(1))
done_when = Future()
node.create_timer(0.05, lambda: done_when.set_result("t"))
executor.spin_until_future_complete(done_when, timeout_sec=2.0)
show("timer future", lambda: (done_when.result(), len(timer_calls) >= 2))


async def failing():
    raise RuntimeError("inside")


bad = executor.create_task(failing)
show("spin with a failing task", lambda: executor.spin_until_future_complete(
    bad, timeout_sec=1.0))
show("failing task", lambda: (bad.done(), repr(bad.exception())))
rclpy.shutdown()
