# QoSProfile as an object (mutable, every rmw field), the presets, the policy enums' short
# keys and rclpy's older QoS-prefixed names.
import rclpy.qos as qos_module
from rclpy.duration import Duration
from rclpy.node import Node
from rclpy.qos import (
    DurabilityPolicy,
    HistoryPolicy,
    LivelinessPolicy,
    QoSDurabilityPolicy,
    QoSHistoryPolicy,
    QoSLivelinessPolicy,
    QoSPolicyKind,
    QoSPresetProfiles,
    QoSProfile,
    QoSReliabilityPolicy,
    ReliabilityPolicy,
    qos_policy_name_from_kind,
    qos_profile_sensor_data,
    qos_profile_system_default,
)
from std_msgs.msg import String

import rclpy

for name in ["unknown", "default", "system_default", "sensor_data", "services_default",
             "parameters", "parameter_events", "best_available", "action_status_default"]:
    show(f"preset {name}", lambda name=name: str(getattr(qos_module, f"qos_profile_{name}")))

profile = QoSProfile(depth=5)
profile.depth = 3
profile.reliability = ReliabilityPolicy.BEST_EFFORT
profile.durability = 1
profile.history = HistoryPolicy.KEEP_ALL
profile.lifespan = Duration(seconds=2)
profile.liveliness = LivelinessPolicy.MANUAL_BY_TOPIC
show("mutated", lambda: str(profile))
show("mutated types", lambda: (type(profile.durability).__name__, profile.durability.name))
show("every field", lambda: str(QoSProfile(
    depth=5, deadline=Duration(seconds=1), liveliness=LivelinessPolicy.AUTOMATIC,
    liveliness_lease_duration=Duration(seconds=2), lifespan=Duration(nanoseconds=3),
    avoid_ros_namespace_conventions=True)))
show("default durations", lambda: (QoSProfile(depth=1).deadline,
                                   QoSProfile(depth=1).liveliness_lease_duration))
kind("hash", lambda: hash(QoSProfile(depth=1)))
show("eq after change", lambda: (lambda a, b: (a == b, setattr(b, "depth", 2), a == b))(
    QoSProfile(depth=1), QoSProfile(depth=1)))
show("eq other type", lambda: QoSProfile(depth=1) == 1)

show("aliases", lambda: (QoSReliabilityPolicy is ReliabilityPolicy,
                         QoSHistoryPolicy is HistoryPolicy,
                         QoSDurabilityPolicy is DurabilityPolicy,
                         QoSLivelinessPolicy is LivelinessPolicy))
show("short key", lambda: (ReliabilityPolicy.BEST_EFFORT.short_key,
                           DurabilityPolicy.TRANSIENT_LOCAL.short_key,
                           LivelinessPolicy.MANUAL_BY_TOPIC.short_key))
show("from short key", lambda: (ReliabilityPolicy.get_from_short_key("reliable"),
                                HistoryPolicy.get_from_short_key("KEEP_ALL")))
kind("from bad short key", lambda: ReliabilityPolicy.get_from_short_key("nope"))
for policy in [HistoryPolicy, ReliabilityPolicy, DurabilityPolicy, LivelinessPolicy]:
    show(f"short keys {policy.__name__}", lambda policy=policy: policy.short_keys())
show("liveliness values", lambda: [(m.name, m.value) for m in LivelinessPolicy])
show("policy kind", lambda: (int(QoSPolicyKind.RELIABILITY), qos_policy_name_from_kind(16)))

show("preset names", lambda: list(QoSPresetProfiles.__members__))
show("preset short keys", lambda: QoSPresetProfiles.short_keys())
show("preset alias", lambda: QoSPresetProfiles.PARAMETER_EVENTS.name)
show("preset by short key", lambda: QoSPresetProfiles.get_from_short_key("sensor_data")
     is qos_profile_sensor_data)
show("preset is module's", lambda: QoSPresetProfiles.SYSTEM_DEFAULT.value
     is qos_module.qos_profile_system_default)

rclpy.init()
node = Node("qos_user")
sub = node.create_subscription(String, "sensors", lambda msg: None, qos_profile_sensor_data)
pub = node.create_publisher(String, "deadline", QoSProfile(
    depth=2, deadline=Duration(seconds=1), lifespan=Duration(seconds=4)))
show("publisher keeps the fields", lambda: (pub.qos_profile.deadline, pub.qos_profile.lifespan))
show("subscription has the object", lambda: sub.qos_profile is qos_profile_sensor_data)
qos_profile_sensor_data.depth = 7  # shared: every later user sees 7
show("preset mutated", lambda: (qos_module.qos_profile_sensor_data.depth,
                                QoSPresetProfiles.SENSOR_DATA.value.depth))
qos_profile_sensor_data.depth = 5
show("system default subscription", lambda: node.create_subscription(
    String, "sys", lambda msg: None, qos_profile_system_default).qos_profile.depth)
show("int depth", lambda: str(node.create_publisher(String, "n", 4).qos_profile))
rclpy.shutdown()
