# rclpy.qos.qos_check_compatible: the verdict and reasons for pairs of publisher and
# subscription profiles over every reliability, durability and liveliness pair, deadlines and
# lease durations, and several errors at once.
import itertools

from rclpy.duration import Duration
from rclpy.qos import (
    DurabilityPolicy,
    LivelinessPolicy,
    QoSCompatibility,
    QoSProfile,
    ReliabilityPolicy,
    qos_check_compatible,
)


def check(pub, sub):
    verdict, reason = qos_check_compatible(QoSProfile(depth=1, **pub), QoSProfile(depth=1, **sub))
    return (verdict.name, int(verdict), reason)


show("verdicts", lambda: [(c.name, int(c)) for c in (QoSCompatibility.OK,
                                                      QoSCompatibility.WARNING,
                                                      QoSCompatibility.ERROR)])
auto = {"liveliness": LivelinessPolicy.AUTOMATIC}
policies = {
    "reliability": [ReliabilityPolicy.RELIABLE, ReliabilityPolicy.BEST_EFFORT,
                    ReliabilityPolicy.SYSTEM_DEFAULT, ReliabilityPolicy.BEST_AVAILABLE],
    "durability": [DurabilityPolicy.VOLATILE, DurabilityPolicy.TRANSIENT_LOCAL,
                   DurabilityPolicy.SYSTEM_DEFAULT, DurabilityPolicy.BEST_AVAILABLE],
    "liveliness": [LivelinessPolicy.AUTOMATIC, LivelinessPolicy.MANUAL_BY_TOPIC,
                   LivelinessPolicy.SYSTEM_DEFAULT, LivelinessPolicy.BEST_AVAILABLE],
}
for name, values in policies.items():
    base = {} if name == "liveliness" else auto
    for p, s in itertools.product(values, values):
        show(f"{name} {p.name} {s.name}", lambda p=p, s=s, n=name, b=base: check(
            {**b, n: p}, {**b, n: s}))
for field in ("deadline", "liveliness_lease_duration"):
    for p, s in ((1, 2), (2, 1), (0, 1), (1, 0), (0, 0)):
        show(f"{field} {p} {s}", lambda p=p, s=s, f=field: check(
            {**auto, f: Duration(seconds=p)}, {**auto, f: Duration(seconds=s)}))
show("defaults", lambda: check({}, {}))
show("every error", lambda: check(
    {"reliability": ReliabilityPolicy.BEST_EFFORT, "durability": DurabilityPolicy.VOLATILE,
     "liveliness": LivelinessPolicy.AUTOMATIC},
    {"reliability": ReliabilityPolicy.RELIABLE, "durability": DurabilityPolicy.TRANSIENT_LOCAL,
     "liveliness": LivelinessPolicy.MANUAL_BY_TOPIC, "deadline": Duration(seconds=1),
     "liveliness_lease_duration": Duration(seconds=1)}))
show("warnings together", lambda: check(
    {"reliability": ReliabilityPolicy.SYSTEM_DEFAULT, "durability": DurabilityPolicy.VOLATILE},
    {"reliability": ReliabilityPolicy.RELIABLE, "durability": DurabilityPolicy.SYSTEM_DEFAULT}))
