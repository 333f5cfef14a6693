"""The course's simulation worlds as validated data, and a loader for users' own worlds.

A world is a mapping (Python, JSON, or YAML when PyYAML is installed)::

    name: aruco_box_world                  # required, str
    description: "..."                     # optional
    physics_step: 0.001                    # s, optional (> 0)
    spawn: [0.0, 0.0, 0.0]                 # robot spawn (x, y, yaw) in odom, optional
    boxes:                                 # optional list
      - {name: box_1, model: aruco_box, pose: [2.25, 0.0, 0.25, 0.0, 0.0, 0.0],
         collision: true}                  # optional: solid for the robot (default true)
    walls:                                 # optional list of vertical walls (prisms)
      - {name: room, height: 1.0, loops: [[[-5, -5], [5, -5], [5, 5], [-5, 5]]],
         collision: true}
    cameras:                               # optional list of fixed cameras
      - {name: overhead_camera, pose: [2, 2, 2, 0, 1.5708, 0], width: 640, height: 480,
         horizontal_fov: 1.047, rate_hz: 30, clip: [0.1, 100],
         image_topic: overhead_camera/image_raw, info_topic: overhead_camera/camera_info,
         frame_id: overhead_camera}
    static_transforms:                     # optional, published on /tf_static by the launch
      - {parent: odom, child: overhead_camera, xyz: [2, 2, 2], rpy: [0, 1.5708, 0]}

``pose`` is ``(x, y, z, roll, pitch, yaw)`` in the world frame (= odom: the robot spawns at
the origin), metres and radians, rpy on fixed axes (R = Rz(yaw) Ry(pitch) Rx(roll)) as in
SDF; a mapping with those six keys is accepted too. A box pose is T_world_box (its origin is
the cube centre). Every box is seen by the simulated LiDAR; ``collision`` (default true)
marks a box as solid for the robot (:mod:`posekit.robot.contact`). A wall is the vertical
extrusion, from the ground to ``height`` (m), of closed outline ``loops`` of (x, y) points
(m, world frame; the last point joins the first): each loop edge is a wall face the LiDAR
sees and the robot stops at (a ring is two loops). A camera pose is the SDF
*model* pose: the camera looks along its +x axis (the optical frame is the static transform
the launch adds). Validation rejects unknown keys, wrong types, non-finite numbers,
duplicate names and unknown models, with a :class:`WorldError` naming the world and the
field.

Limits (a world file is input like any other; these keep a typo or a hostile file from
exhausting memory or CPU): a camera side is at most :data:`MAX_CAMERA_SIDE` pixels and a
camera image at most :data:`MAX_CAMERA_PIXELS`, its rate at most :data:`MAX_CAMERA_RATE_HZ`;
at most :data:`MAX_LIST_ITEMS` boxes, cameras and static transforms each; a world file is at
most :data:`MAX_WORLD_FILE_BYTES` and must be UTF-8.
"""

from __future__ import annotations

import json
import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
import numpy.typing as npt

from posekit.geometry import Transform
from posekit.geometry.scalar import quat_from_rpy
from posekit.worlds.aruco_box import ARUCO_BOX, ArucoBoxModel
from posekit.worlds.errors import WorldError

__all__ = [
    "MAX_CAMERA_PIXELS",
    "MAX_CAMERA_RATE_HZ",
    "MAX_CAMERA_SIDE",
    "MAX_LIST_ITEMS",
    "MAX_WORLD_FILE_BYTES",
    "WORLDS",
    "BoxSpec",
    "CameraSpec",
    "MarkerPose",
    "StaticTransformSpec",
    "WallSpec",
    "World",
    "box_half_extents",
    "load_world",
    "marker_poses",
    "world_names",
]

#: Largest camera width or height accepted (pixels).
MAX_CAMERA_SIDE = 8192
#: Largest camera image accepted (width x height pixels: 16.7 MP, 50 MB as rgb8).
MAX_CAMERA_PIXELS = 4096 * 4096
#: Fastest camera rate accepted (Hz).
MAX_CAMERA_RATE_HZ = 1000.0
#: Most boxes, cameras or static transforms in one world (each).
MAX_LIST_ITEMS = 10_000
#: Largest world file read (bytes).
MAX_WORLD_FILE_BYTES = 16 * 1024 * 1024

_FloatArray = npt.NDArray[np.float64]
_POSE_KEYS = ("x", "y", "z", "roll", "pitch", "yaw")


_MODELS: dict[str, ArucoBoxModel] = {ARUCO_BOX.name: ARUCO_BOX}


@dataclass(frozen=True, slots=True)
class BoxSpec:
    """A static box.

    ``name``, ``model`` (``"aruco_box"``), ``pose`` (x, y, z, roll, pitch, yaw), ``collision``
    (the robot cannot drive through it).
    """

    name: str
    model: str
    pose: tuple[float, float, float, float, float, float]
    collision: bool = True

    @property
    def T_world_box(self) -> _FloatArray:
        """4x4 pose of the box (centre) in the world frame."""
        return Transform.from_xyz_rpy(self.pose[:3], self.pose[3:]).as_matrix()

    def to_dict(self) -> dict[str, Any]:
        """As the plain mapping the loader accepts."""
        return {
            "name": self.name,
            "model": self.model,
            "pose": list(self.pose),
            "collision": self.collision,
        }


def box_half_extents(box: BoxSpec) -> tuple[float, float, float]:
    """Half side lengths (m) of ``box`` along its own x, y, z axes."""
    half = 0.5 * _MODELS[box.model].size
    return half, half, half


@dataclass(frozen=True, slots=True)
class WallSpec:
    """Vertical walls: ``loops`` of (x, y) points (m, closed) extruded from 0 to ``height``."""

    name: str
    height: float
    loops: tuple[tuple[tuple[float, float], ...], ...]
    collision: bool = True

    def segments(self) -> _FloatArray:
        """``(S, 2, 2)`` wall faces as (start, end) points, every loop closed."""
        out = []
        for loop in self.loops:
            pts = np.asarray(loop, dtype=np.float64)
            out.append(np.stack([pts, np.roll(pts, -1, axis=0)], axis=1))
        return np.concatenate(out) if out else np.zeros((0, 2, 2))

    def to_dict(self) -> dict[str, Any]:
        """As the plain mapping the loader accepts."""
        return {
            "name": self.name,
            "height": self.height,
            "loops": [[list(p) for p in loop] for loop in self.loops],
            "collision": self.collision,
        }


@dataclass(frozen=True, slots=True)
class CameraSpec:
    """A fixed Gazebo camera (model pose: the camera looks along its +x axis).

    ``horizontal_fov`` in rad, ``clip`` (near, far) in m, ``rate_hz`` in Hz. Gazebo derives
    the intrinsics from the size and field of view (see :attr:`K`), with no distortion.
    """

    name: str
    pose: tuple[float, float, float, float, float, float]
    width: int
    height: int
    horizontal_fov: float
    rate_hz: float = 30.0
    clip: tuple[float, float] = (0.1, 100.0)
    image_topic: str = ""
    info_topic: str = ""
    frame_id: str = ""

    @property
    def T_world_camera(self) -> _FloatArray:
        """4x4 pose of the camera model frame in the world."""
        return Transform.from_xyz_rpy(self.pose[:3], self.pose[3:]).as_matrix()

    @property
    def K(self) -> _FloatArray:
        """3x3 intrinsics: fx = fy = (width/2) / tan(hfov/2), cx = width/2, cy = height/2."""
        f = 0.5 * self.width / math.tan(0.5 * self.horizontal_fov)
        return np.array([[f, 0.0, 0.5 * self.width], [0.0, f, 0.5 * self.height], [0, 0, 1.0]])

    def to_dict(self) -> dict[str, Any]:
        """As the plain mapping the loader accepts."""
        return {
            "name": self.name,
            "pose": list(self.pose),
            "width": self.width,
            "height": self.height,
            "horizontal_fov": self.horizontal_fov,
            "rate_hz": self.rate_hz,
            "clip": list(self.clip),
            "image_topic": self.image_topic,
            "info_topic": self.info_topic,
            "frame_id": self.frame_id,
        }


@dataclass(frozen=True, slots=True)
class StaticTransformSpec:
    """A static transform T_parent_child a launch file publishes (``xyz`` m, ``rpy`` rad)."""

    parent: str
    child: str
    xyz: tuple[float, float, float]
    rpy: tuple[float, float, float]

    @property
    def quaternion_xyzw(self) -> tuple[float, ...]:
        """The rotation as (x, y, z, w)."""
        return quat_from_rpy(*self.rpy)

    def to_dict(self) -> dict[str, Any]:
        """As the plain mapping the loader accepts."""
        return {
            "parent": self.parent,
            "child": self.child,
            "xyz": list(self.xyz),
            "rpy": list(self.rpy),
        }


@dataclass(frozen=True, slots=True)
class World:
    """A validated world (see the module doc for the schema)."""

    name: str
    description: str = ""
    physics_step: float = 0.001
    spawn: tuple[float, float, float] = (0.0, 0.0, 0.0)
    boxes: tuple[BoxSpec, ...] = ()
    cameras: tuple[CameraSpec, ...] = ()
    static_transforms: tuple[StaticTransformSpec, ...] = ()
    walls: tuple[WallSpec, ...] = ()
    source: str = field(default="<builtin>", compare=False)

    def to_dict(self) -> dict[str, Any]:
        """As the plain mapping the loader accepts (JSON-serialisable)."""
        return {
            "name": self.name,
            "description": self.description,
            "physics_step": self.physics_step,
            "spawn": list(self.spawn),
            "boxes": [b.to_dict() for b in self.boxes],
            "cameras": [c.to_dict() for c in self.cameras],
            "static_transforms": [s.to_dict() for s in self.static_transforms],
            "walls": [w.to_dict() for w in self.walls],
        }

    @classmethod
    def from_dict(cls, data: Any, *, source: str = "<dict>") -> World:
        """Validate a mapping and build the world; raises :class:`WorldError`."""
        return _parse_world(data, source)


@dataclass(frozen=True, slots=True)
class MarkerPose:
    """One marker of one box: ``T_world_marker`` (4x4, origin at the marker centre)."""

    box: str
    marker_id: int
    size: float
    dictionary: str
    T_world_marker: _FloatArray


def marker_poses(world: World) -> list[MarkerPose]:
    """Every marker of every box of ``world`` (box order, then marker id)."""
    out = []
    for box in world.boxes:
        model = _MODELS[box.model]
        T_world_box = box.T_world_box
        for marker_id in model.marker_ids:
            out.append(
                MarkerPose(
                    box.name,
                    marker_id,
                    model.marker_size,
                    model.dictionary,
                    T_world_box @ model.T_box_marker(marker_id),
                )
            )
    return out


# ---------------------------------------------------------------------------- validation
class _Ctx:
    def __init__(self, world: str, source: str) -> None:
        self.world, self.source = world, source

    def fail(self, where: str, problem: str) -> WorldError:
        return WorldError(f"world {self.world!r} ({self.source}): {where}: {problem}")


def _number(ctx: _Ctx, where: str, value: Any) -> float:
    if isinstance(value, bool) or not isinstance(value, int | float):
        raise ctx.fail(where, f"expected a number, got {type(value).__name__} {value!r}")
    if not math.isfinite(value):
        raise ctx.fail(where, f"expected a finite number, got {value!r}")
    return float(value)


def _positive(ctx: _Ctx, where: str, value: Any) -> float:
    x = _number(ctx, where, value)
    if x <= 0.0:
        raise ctx.fail(where, f"must be > 0, got {x}")
    return x


def _string(ctx: _Ctx, where: str, value: Any, *, allow_empty: bool = False) -> str:
    if not isinstance(value, str):
        raise ctx.fail(where, f"expected a string, got {type(value).__name__} {value!r}")
    if not allow_empty and not value:
        raise ctx.fail(where, "must not be empty")
    return value


def _flag(ctx: _Ctx, where: str, value: Any) -> bool:
    if not isinstance(value, bool):
        raise ctx.fail(where, f"expected true or false, got {value!r}")
    return value


def _vector(ctx: _Ctx, where: str, value: Any, n: int, meaning: str) -> tuple[float, ...]:
    if isinstance(value, str) or not isinstance(value, Sequence):
        raise ctx.fail(where, f"expected {n} numbers ({meaning}), got {value!r}")
    if len(value) != n:
        raise ctx.fail(where, f"expected {n} numbers ({meaning}), got {len(value)}")
    return tuple(_number(ctx, f"{where}[{i}]", v) for i, v in enumerate(value))


def _pose(ctx: _Ctx, where: str, value: Any) -> tuple[float, float, float, float, float, float]:
    if isinstance(value, Mapping):
        _check_keys(ctx, where, value, required=(), optional=_POSE_KEYS)
        value = [value.get(k, 0.0) for k in _POSE_KEYS]
    x, y, z, roll, pitch, yaw = _vector(ctx, where, value, 6, "x, y, z, roll, pitch, yaw")
    return x, y, z, roll, pitch, yaw


def _check_keys(
    ctx: _Ctx, where: str, data: Any, *, required: Sequence[str], optional: Sequence[str]
) -> None:
    if not isinstance(data, Mapping):
        raise ctx.fail(where, f"expected a mapping, got {type(data).__name__}")
    for key in required:
        if key not in data:
            raise ctx.fail(where, f"missing required key {key!r}")
    allowed = set(required) | set(optional)
    unknown = sorted(str(k) for k in data if k not in allowed)
    if unknown:
        raise ctx.fail(where, f"unknown key(s) {unknown}; allowed: {sorted(allowed)}")


def _list(ctx: _Ctx, where: str, value: Any) -> Sequence[Any]:
    if isinstance(value, str) or not isinstance(value, Sequence):
        raise ctx.fail(where, f"expected a list, got {type(value).__name__}")
    if len(value) > MAX_LIST_ITEMS:
        raise ctx.fail(where, f"{len(value)} entries is over the limit of {MAX_LIST_ITEMS}")
    return value


def _unique(ctx: _Ctx, where: str, names: list[str]) -> None:
    seen: set[str] = set()
    for n in names:
        if n in seen:
            raise ctx.fail(where, f"duplicate name {n!r}")
        seen.add(n)


def _parse_box(ctx: _Ctx, where: str, data: Any) -> BoxSpec:
    _check_keys(ctx, where, data, required=("name", "model", "pose"), optional=("collision",))
    model = _string(ctx, f"{where}.model", data["model"])
    if model not in _MODELS:
        raise ctx.fail(f"{where}.model", f"unknown model {model!r}; known: {sorted(_MODELS)}")
    collision = _flag(ctx, f"{where}.collision", data.get("collision", True))
    return BoxSpec(
        _string(ctx, f"{where}.name", data["name"]),
        model,
        _pose(ctx, f"{where}.pose", data["pose"]),
        collision,
    )


def _parse_camera(ctx: _Ctx, where: str, data: Any) -> CameraSpec:
    _check_keys(
        ctx,
        where,
        data,
        required=("name", "pose", "width", "height", "horizontal_fov"),
        optional=("rate_hz", "clip", "image_topic", "info_topic", "frame_id"),
    )
    name = _string(ctx, f"{where}.name", data["name"])
    size = []
    for key in ("width", "height"):
        v = data[key]
        if isinstance(v, bool) or not isinstance(v, int) or v <= 0:
            raise ctx.fail(f"{where}.{key}", f"expected a positive integer (pixels), got {v!r}")
        if v > MAX_CAMERA_SIDE:
            raise ctx.fail(f"{where}.{key}", f"{v} px is over the limit of {MAX_CAMERA_SIDE}")
        size.append(v)
    if size[0] * size[1] > MAX_CAMERA_PIXELS:
        raise ctx.fail(
            f"{where}.width x height",
            f"{size[0]} x {size[1]} px is over the limit of {MAX_CAMERA_PIXELS} pixels",
        )
    rate_hz = _positive(ctx, f"{where}.rate_hz", data.get("rate_hz", 30.0))
    if rate_hz > MAX_CAMERA_RATE_HZ:
        raise ctx.fail(f"{where}.rate_hz", f"{rate_hz} Hz is over the limit of "
                                           f"{MAX_CAMERA_RATE_HZ:g} Hz")
    hfov = _positive(ctx, f"{where}.horizontal_fov", data["horizontal_fov"])
    if hfov >= math.pi:
        raise ctx.fail(f"{where}.horizontal_fov", f"must be < pi rad, got {hfov}")
    near, far = _vector(ctx, f"{where}.clip", data.get("clip", (0.1, 100.0)), 2, "near, far")
    if not 0.0 < near < far:
        raise ctx.fail(f"{where}.clip", f"need 0 < near < far, got ({near}, {far})")
    return CameraSpec(
        name=name,
        pose=_pose(ctx, f"{where}.pose", data["pose"]),
        width=size[0],
        height=size[1],
        horizontal_fov=hfov,
        rate_hz=rate_hz,
        clip=(near, far),
        image_topic=_string(
            ctx, f"{where}.image_topic", data.get("image_topic", f"{name}/image_raw")
        ),
        info_topic=_string(
            ctx, f"{where}.info_topic", data.get("info_topic", f"{name}/camera_info")
        ),
        frame_id=_string(ctx, f"{where}.frame_id", data.get("frame_id", name)),
    )


def _parse_static(ctx: _Ctx, where: str, data: Any) -> StaticTransformSpec:
    _check_keys(ctx, where, data, required=("parent", "child"), optional=("xyz", "rpy"))
    parent = _string(ctx, f"{where}.parent", data["parent"])
    child = _string(ctx, f"{where}.child", data["child"])
    if parent == child:
        raise ctx.fail(where, f"parent and child are the same frame {parent!r}")
    x, y, z = _vector(ctx, f"{where}.xyz", data.get("xyz", (0.0, 0.0, 0.0)), 3, "x, y, z")
    r, p, yw = _vector(ctx, f"{where}.rpy", data.get("rpy", (0.0, 0.0, 0.0)), 3, "roll, pitch, yaw")
    return StaticTransformSpec(parent, child, (x, y, z), (r, p, yw))


def _parse_wall(ctx: _Ctx, where: str, data: Any) -> WallSpec:
    _check_keys(ctx, where, data, required=("name", "height", "loops"), optional=("collision",))
    loops = []
    points = 0
    for i, loop in enumerate(_list(ctx, f"{where}.loops", data["loops"])):
        pts = tuple(
            _vector(ctx, f"{where}.loops[{i}][{j}]", p, 2, "x, y")
            for j, p in enumerate(_list(ctx, f"{where}.loops[{i}]", loop))
        )
        if len(pts) < 3:
            raise ctx.fail(f"{where}.loops[{i}]", f"a loop needs >= 3 points, got {len(pts)}")
        points += len(pts)
        loops.append(tuple((p[0], p[1]) for p in pts))
    if not loops:
        raise ctx.fail(f"{where}.loops", "needs at least one loop")
    if points > MAX_LIST_ITEMS:
        raise ctx.fail(f"{where}.loops", f"{points} points is over the limit of {MAX_LIST_ITEMS}")
    collision = _flag(ctx, f"{where}.collision", data.get("collision", True))
    return WallSpec(
        _string(ctx, f"{where}.name", data["name"]),
        _positive(ctx, f"{where}.height", data["height"]),
        tuple(loops),
        collision,
    )


def _parse_world(data: Any, source: str) -> World:
    name = data.get("name") if isinstance(data, Mapping) else None
    ctx = _Ctx(name if isinstance(name, str) and name else "?", source)
    _check_keys(
        ctx,
        "top level",
        data,
        required=("name",),
        optional=(
            "description", "physics_step", "spawn", "boxes", "cameras", "static_transforms",
            "walls",
        ),
    )
    name = _string(ctx, "name", data["name"])
    boxes = tuple(
        _parse_box(ctx, f"boxes[{i}]", b)
        for i, b in enumerate(_list(ctx, "boxes", data.get("boxes", [])))
    )
    cameras = tuple(
        _parse_camera(ctx, f"cameras[{i}]", c)
        for i, c in enumerate(_list(ctx, "cameras", data.get("cameras", [])))
    )
    statics = tuple(
        _parse_static(ctx, f"static_transforms[{i}]", s)
        for i, s in enumerate(_list(ctx, "static_transforms", data.get("static_transforms", [])))
    )
    walls = tuple(
        _parse_wall(ctx, f"walls[{i}]", w)
        for i, w in enumerate(_list(ctx, "walls", data.get("walls", [])))
    )
    _unique(
        ctx,
        "boxes/cameras/walls",
        [b.name for b in boxes] + [c.name for c in cameras] + [w.name for w in walls],
    )
    _unique(ctx, "static_transforms", [s.child for s in statics])
    sx, sy, syaw = _vector(ctx, "spawn", data.get("spawn", (0.0, 0.0, 0.0)), 3, "x, y, yaw")
    return World(
        name=name,
        description=_string(ctx, "description", data.get("description", ""), allow_empty=True),
        physics_step=_positive(ctx, "physics_step", data.get("physics_step", 0.001)),
        spawn=(sx, sy, syaw),
        boxes=boxes,
        cameras=cameras,
        static_transforms=statics,
        walls=walls,
        source=source,
    )


# ---------------------------------------------------------------------------- built-ins
_OVERHEAD_POSE = [2.0, 2.0, 2.0, 0.0, 1.5708, 0.0]

_BUILTIN: dict[str, dict[str, Any]] = {
    "empty_world": {
        "name": "empty_world",
        "description": "Ground plane and sun; the ROSbot at the origin.",
    },
    "aruco_box_world": {
        "name": "aruco_box_world",
        "description": "Three static aruco_boxes in front of the robot (aruco_box_worlds.sdf).",
        "boxes": [
            {"name": "box_1", "model": "aruco_box", "pose": [2.25, 0.0, 0.25, 0.0, 0.0, 0.0]},
            {"name": "box_2", "model": "aruco_box", "pose": [2.25, -0.5, 0.25, 0.0, 0.0, -1.57]},
            {"name": "box_3", "model": "aruco_box", "pose": [2.25, 0.5, 0.25, 0.0, 0.0, 1.57]},
        ],
    },
    "aruco_box_camera_world": {
        "name": "aruco_box_camera_world",
        "description": "One aruco_box under a downward-looking overhead camera.",
        "boxes": [
            {"name": "box_1", "model": "aruco_box", "pose": [2.0, 2.0, 0.25, 0.0, 0.0, 0.0]},
        ],
        "cameras": [
            {
                "name": "overhead_camera",
                "pose": _OVERHEAD_POSE,
                "width": 640,
                "height": 480,
                "horizontal_fov": 1.047,
                "rate_hz": 30.0,
                "clip": [0.1, 100.0],
                "image_topic": "overhead_camera/image_raw",
                "info_topic": "overhead_camera/camera_info",
                "frame_id": "overhead_camera",
            }
        ],
        # From frame_demo/static_aruco_detector.launch.py.
        "static_transforms": [
            {
                "parent": "odom",
                "child": "overhead_camera",
                "xyz": [2.0, 2.0, 2.0],
                "rpy": [0.0, 1.5708, 0.0],
            },
            {
                "parent": "overhead_camera",
                "child": "overhead_camera_optical_frame",
                "xyz": [0.0, 0.0, 0.0],
                "rpy": [-1.5708, 0.0, -1.5708],
            },
        ],
    },
}

def _husarion_world() -> dict[str, Any]:
    from posekit.worlds._husarion_world import WALLS

    return {
        "name": "husarion_world",
        "description": "Husarion's logo extruded into 1.8 m walls: a ring around six feathers "
        "and an H (husarion_gz_worlds); the ROSbot starts where Husarion's map does.",
        "spawn": [0.0, -1.9, 0.0],
        "walls": [
            {"name": name, "height": height, "loops": [list(loop) for loop in loops]}
            for name, height, loops in WALLS
        ],
    }


_BUILTIN["husarion_world"] = _husarion_world()

#: Other names the course uses for the same worlds.
_ALIASES = {"aruco_markers_world": "aruco_box_world"}

#: The built-in worlds, validated at import.
WORLDS: dict[str, World] = {n: _parse_world(d, "<builtin>") for n, d in _BUILTIN.items()}


def world_names() -> list[str]:
    """Names accepted by :func:`load_world` (built-ins and aliases)."""
    return sorted([*WORLDS, *_ALIASES])


def load_world(name_or_path: str | Path) -> World:
    """A built-in world by name (or alias), or a user's world file (.json, .yaml/.yml).

    Raises:
        WorldError: unknown name, unreadable or malformed file, invalid content.
    """
    key = str(name_or_path)
    key = _ALIASES.get(key, key)
    if key in WORLDS:
        return WORLDS[key]
    path = Path(name_or_path)
    if not path.suffix:
        raise WorldError(f"unknown world {key!r}; built-in worlds: {world_names()}")
    try:
        with path.open("rb") as f:
            raw = f.read(MAX_WORLD_FILE_BYTES + 1)
    except OSError as exc:
        raise WorldError(f"cannot read world file {str(path)!r}: {exc}") from exc
    if len(raw) > MAX_WORLD_FILE_BYTES:
        raise WorldError(
            f"world file {str(path)!r} is over the limit of {MAX_WORLD_FILE_BYTES} bytes"
        )
    try:
        text = raw.decode("utf-8")
    except UnicodeDecodeError as exc:
        raise WorldError(
            f"world file {str(path)!r} is not UTF-8 text (byte {exc.start}: {exc.reason})"
        ) from None
    suffix = path.suffix.lower()
    if suffix == ".json":
        try:
            data = json.loads(text)
        except json.JSONDecodeError as exc:
            raise WorldError(f"world file {str(path)!r} is not valid JSON: {exc}") from exc
    elif suffix in (".yaml", ".yml"):
        try:
            import yaml  # type: ignore[import-untyped,unused-ignore]
        except ImportError as exc:
            raise WorldError(
                f"world file {str(path)!r} is YAML but PyYAML is not installed "
                "(pip install pyyaml), or write it as JSON"
            ) from exc
        try:
            data = yaml.safe_load(text)
        except yaml.YAMLError as exc:
            raise WorldError(f"world file {str(path)!r} is not valid YAML: {exc}") from exc
    else:
        raise WorldError(
            f"world file {str(path)!r}: unsupported extension {suffix!r} (.json, .yaml)"
        )
    return _parse_world(data, str(path))
