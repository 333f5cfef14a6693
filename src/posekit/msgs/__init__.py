"""ROS 2 message types as light dataclasses (numpy only), laid out as ROS 2 Jazzy defines them.

Import paths mirror ROS packages: ``from posekit.msgs.geometry_msgs import TransformStamped``,
``from posekit.msgs.std_srvs import SetBool`` (services: ``SetBool.Request`` / ``.Response``),
``from posekit.msgs.posekit_interfaces import NavigateToPose`` (actions: ``.Goal`` / ``.Result``
/ ``.Feedback``, registered in ``ACTION_CLASSES``).
Every class has ``__msgtype__`` (e.g. ``"geometry_msgs/msg/TransformStamped"``), is
constructible with no arguments (ROS defaults) or by keyword, and has assignable fields.
CDR serialization lives in :mod:`posekit.msgs.cdr` and loads rosbags only when used.
"""

from __future__ import annotations

from posekit.msgs import (
    action_msgs,
    builtin_interfaces,
    geometry_msgs,
    nav_msgs,
    posekit_interfaces,
    rcl_interfaces,
    rosgraph_msgs,
    sensor_msgs,
    std_msgs,
    std_srvs,
    tf2_msgs,
    unique_identifier_msgs,
)
from posekit.msgs._service import is_service_type, service_type_name
from posekit.msgs.cdr import from_cdr, to_cdr, type_hash_rihs01
from posekit.msgs.errors import (
    CdrError,
    ImageConversionError,
    MessageError,
    UnknownMessageTypeError,
)
from posekit.msgs.image import image_to_numpy, numpy_to_image
from posekit.msgs.registry import (
    ACTION_CLASSES,
    MESSAGE_CLASSES,
    SERVICE_CLASSES,
    get_action_class,
    get_message_class,
    get_service_class,
    message_type_name,
)

__all__ = [
    "ACTION_CLASSES",
    "MESSAGE_CLASSES",
    "SERVICE_CLASSES",
    "CdrError",
    "ImageConversionError",
    "MessageError",
    "UnknownMessageTypeError",
    "action_msgs",
    "builtin_interfaces",
    "from_cdr",
    "geometry_msgs",
    "get_action_class",
    "get_message_class",
    "get_service_class",
    "image_to_numpy",
    "is_service_type",
    "message_type_name",
    "nav_msgs",
    "numpy_to_image",
    "posekit_interfaces",
    "rcl_interfaces",
    "rosgraph_msgs",
    "sensor_msgs",
    "service_type_name",
    "std_msgs",
    "std_srvs",
    "tf2_msgs",
    "to_cdr",
    "type_hash_rihs01",
    "unique_identifier_msgs",
]
