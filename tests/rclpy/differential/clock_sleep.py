# rclpy.clock: Clock(clock_type=ROS_TIME) is a ROSClock; sleep_for / sleep_until on system,
# steady and ROS time (simulated time, ROS time switched off, context shutdown); the
# ROSClock's override.
import threading
import time

from rclpy.clock import Clock, ClockType, ROSClock
from rclpy.duration import Duration
from rclpy.time import Time

import rclpy

show("ros time clock", lambda: type(Clock(clock_type=ClockType.ROS_TIME)).__name__)
show("ros time clock repr", lambda: Clock(clock_type=ClockType.ROS_TIME))
show("steady clock", lambda: type(Clock(clock_type=ClockType.STEADY_TIME)).__name__)
show("clock type int", lambda: Clock(clock_type=2))
kind("clock positional", lambda: Clock(ClockType.SYSTEM_TIME))
show("methods", lambda: sorted(m for m in ("sleep_for", "sleep_until", "now", "clock_type",
                                           "create_jump_callback") if hasattr(Clock, m)))
show("ros methods", lambda: sorted(m for m in ("ros_time_is_active", "_set_ros_time_is_active",
                                               "set_ros_time_override") if hasattr(ROSClock, m)))

clock = ROSClock()
show("inactive", lambda: clock.ros_time_is_active)
show("override while inactive", lambda: (
    clock.set_ros_time_override(Time(seconds=5, clock_type=ClockType.ROS_TIME)),
    clock.now().nanoseconds > 10**18))
show("activate", lambda: (clock._set_ros_time_is_active(True), clock.ros_time_is_active,
                          clock.now()))
show("override a system time", lambda: (clock.set_ros_time_override(Time(seconds=7)),
                                        clock.now()))
show("override not a time", lambda: clock.set_ros_time_override(5))

kind("sleep before init", lambda: Clock().sleep_for(Duration(seconds=0.01)))
rclpy.init()
show("sleep_for", lambda: Clock().sleep_for(Duration(seconds=0.01)))
show("sleep_for steady", lambda: Clock(clock_type=ClockType.STEADY_TIME).sleep_for(
    Duration(seconds=0.01)))
show("sleep_for 0", lambda: Clock().sleep_for(Duration()))
show("sleep_for negative", lambda: Clock().sleep_for(Duration(seconds=-1)))
show("sleep_until the past", lambda: Clock().sleep_until(Time(seconds=1)))
show("sleep_until another clock", lambda: Clock().sleep_until(
    Time(seconds=1, clock_type=ClockType.STEADY_TIME)))
show("sleep_for a float", lambda: Clock().sleep_for(0.01))
start = time.monotonic()
show("sleep_for inactive ros clock", lambda: ROSClock().sleep_for(Duration(seconds=0.05)))
show("slept", lambda: time.monotonic() - start >= 0.05)

sim = ROSClock()
sim._set_ros_time_is_active(True)
sim.set_ros_time_override(Time(seconds=1, clock_type=ClockType.ROS_TIME))


def advance():
    for s in range(2, 6):
        time.sleep(0.05)
        sim.set_ros_time_override(Time(seconds=s, clock_type=ClockType.ROS_TIME))


mover = threading.Thread(target=advance)
mover.start()
show("sim sleep_for", lambda: sim.sleep_for(Duration(seconds=3)))
mover.join()
show("sim now", lambda: sim.now())
# (rclpy blocks forever in sim.sleep_until(a time already reached) until the next /clock
# jump; posekit returns True at once: tests/runtime/test_clock.py)

switched = ROSClock()
switched._set_ros_time_is_active(True)
threading.Timer(0.1, lambda: switched._set_ros_time_is_active(False)).start()
show("ros time switched off", lambda: switched.sleep_for(Duration(seconds=100)))
switched_on = ROSClock()
threading.Timer(0.1, lambda: switched_on._set_ros_time_is_active(True)).start()
show("ros time switched on", lambda: switched_on.sleep_for(Duration(seconds=100)))

context = rclpy.Context()
context.init()
show("own context", lambda: Clock().sleep_for(Duration(seconds=0.01), context))
frozen = ROSClock()
frozen._set_ros_time_is_active(True)
threading.Timer(0.1, context.shutdown).start()
show("context shut down", lambda: frozen.sleep_for(Duration(seconds=100), context))
kind("after shutdown", lambda: Clock().sleep_for(Duration(seconds=0.01), context))
rclpy.shutdown()
