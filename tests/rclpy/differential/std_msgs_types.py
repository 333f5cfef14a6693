# Every std_msgs message of ROS 2 Jazzy: importable from std_msgs.msg, its fields (names,
# order, types) and default values. (CDR bytes: tests/msgs/test_cdr.py against rosbags.)
import std_msgs.msg

NAMES = ["Bool", "Byte", "ByteMultiArray", "Char", "ColorRGBA", "Empty", "Float32",
         "Float32MultiArray", "Float64", "Float64MultiArray", "Header", "Int16",
         "Int16MultiArray", "Int32", "Int32MultiArray", "Int64", "Int64MultiArray", "Int8",
         "Int8MultiArray", "MultiArrayDimension", "MultiArrayLayout", "String", "UInt16",
         "UInt16MultiArray", "UInt32", "UInt32MultiArray", "UInt64", "UInt64MultiArray",
         "UInt8", "UInt8MultiArray"]


def defaults(msg):
    out = {}
    for name in msg.get_fields_and_field_types():
        value = getattr(msg, name)
        if name == "data" and type(msg).__name__.endswith("MultiArray"):
            value = plain(value)
        elif hasattr(value, "get_fields_and_field_types"):
            value = defaults(value)
        out[name] = value
    return out


for name in NAMES:
    cls = getattr(std_msgs.msg, name)
    show(f"{name} fields", lambda cls=cls: list(cls.get_fields_and_field_types().items()))
    if name != "Byte":  # rclpy: b'\x00'; posekit: 0 (docs/ros2-users.md)
        show(f"{name} defaults", lambda cls=cls: defaults(cls()))
show("set fields", lambda: (lambda m: (m.layout.dim[0].label, plain(m.data)))(
    std_msgs.msg.Float32MultiArray(
        layout=std_msgs.msg.MultiArrayLayout(dim=[std_msgs.msg.MultiArrayDimension(
            label="x", size=2, stride=2)]),
        data=[1.5, 2.5])))
show("ColorRGBA", lambda: (lambda c: (c.r, c.g, c.b, c.a))(std_msgs.msg.ColorRGBA(r=1.0, a=0.5)))
