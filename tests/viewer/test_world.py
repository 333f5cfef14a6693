"""World payload: box and marker poses as the world module defines them, marker images that
OpenCV's own detector reads back as the right ids."""

from __future__ import annotations

import base64

import numpy as np
import pytest

cv2 = pytest.importorskip("cv2")

from posekit.viewer.world import world_payload  # noqa: E402
from posekit.worlds import WORLDS, marker_poses  # noqa: E402


def test_boxes_and_markers_match_the_world() -> None:
    world = WORLDS["aruco_box_world"]
    payload = world_payload("aruco_box_world")
    assert payload is not None
    assert payload["frame"] == "odom"
    assert [b["name"] for b in payload["boxes"]] == [b.name for b in world.boxes]
    for b, spec in zip(payload["boxes"], world.boxes, strict=True):
        np.testing.assert_allclose(np.reshape(b["T"], (4, 4)), spec.T_world_box, atol=1e-6)
        assert b["size"] == 0.5
    expected = marker_poses(world)
    assert len(payload["markers"]) == len(expected) == 18
    for m, ref in zip(payload["markers"], expected, strict=True):
        assert (m["box"], m["id"], m["size"]) == (ref.box, ref.marker_id, ref.size)
        np.testing.assert_allclose(np.reshape(m["T"], (4, 4)), ref.T_world_marker, atol=1e-6)


def test_marker_images_decode_to_their_ids() -> None:
    payload = world_payload("aruco_box_world")
    assert payload is not None
    dictionary = cv2.aruco.getPredefinedDictionary(cv2.aruco.DICT_5X5_250)
    detector = cv2.aruco.ArucoDetector(dictionary)
    for m in payload["markers"][:6]:
        png = base64.b64decode(m["image"].split(",", 1)[1])
        image = cv2.imdecode(np.frombuffer(png, np.uint8), cv2.IMREAD_GRAYSCALE)
        canvas = np.full((image.shape[0] + 80, image.shape[1] + 80), 255, np.uint8)
        canvas[40:-40, 40:-40] = image  # quiet zone, as on the box face
        _, ids, _ = detector.detectMarkers(canvas)
        assert ids is not None
        assert ids.ravel().tolist() == [m["id"]]


def test_cameras_and_no_world() -> None:
    payload = world_payload(WORLDS["aruco_box_camera_world"])
    assert payload is not None
    assert [c["name"] for c in payload["cameras"]] == ["overhead_camera"]
    assert world_payload(None) is None
