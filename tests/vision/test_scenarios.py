"""The lecture's ArUco scenarios end to end (simulator, cameras, detectors, tf2), checked
against docs/specs/rosbot_and_worlds.md's true marker poses: static_aruco_box within 3 cm, markers
2, 4, 5 within 5 cm in odom, the KDL composition equal to tf2's direct lookup to 1e-9."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.spatial.transform import Rotation as R

import posekit.vision.scenarios  # noqa: F401 - registers the scenarios
from posekit.launch.scenarios import ScenarioError, run_scenario, scenario_names
from posekit.time import Time

# docs/specs/rosbot_and_worlds.md: aruco_box_world front markers; aruco_box_camera_world top marker
# (id 3)
FRONT_MARKERS = {"aruco_marker_4": (2.000, 0.000, 0.250),
                 "aruco_marker_2": (2.000, -0.5002, 0.250),
                 "aruco_marker_5": (2.000, 0.5002, 0.250)}
BOX_TOP_MARKER = (2.0, 2.0, 0.5)


def test_the_four_scenarios_are_registered() -> None:
    assert {"static_aruco_detector", "dynamic_detector", "dynamic_detector_listener",
            "kdl_chain_demo"} <= set(scenario_names())


def test_static_detector_box_in_odom_within_3_cm() -> None:
    result = run_scenario("static_aruco_detector", until_sim_time=0.5)
    det = result.node("static_aruco_detector")
    assert det.tf_published
    t = det.published_transform
    assert (t.header.frame_id, t.child_frame_id) == ("overhead_camera_optical_frame",
                                                     "static_aruco_box")
    # compose by hand with the launch file's static frames (docs/specs/rosbot_and_worlds.md)
    R_odom_cam = R.from_euler("xyz", [0, 1.5708, 0]) * R.from_euler("xyz",
                                                                     [-1.5708, 0, -1.5708])
    p = t.transform.translation
    box_in_odom = R_odom_cam.apply([p.x, p.y, p.z]) + np.array([2.0, 2.0, 2.0])
    assert np.linalg.norm(box_in_odom - BOX_TOP_MARKER) < 0.03
    # the marker's z axis (out of the top face) points up, its x axis along -x
    # (docs/specs/rosbot_and_worlds.md table)
    q = t.transform.rotation
    R_odom_box = R_odom_cam * R.from_quat([q.x, q.y, q.z, q.w])
    assert R_odom_box.apply([0, 0, 1]) @ [0, 0, 1] > 0.99
    assert R_odom_box.apply([1, 0, 0]) @ [-1, 0, 0] > 0.99
    # the camera stopped rendering once the detector unsubscribed (lazy camera)
    assert result.node("overhead_camera").frames_published <= 2


def test_kdl_chain_demo_matches_the_direct_lookup() -> None:
    result = run_scenario("kdl_chain_demo", until_sim_time=2.0)
    demo = result.node("kdl_chain_demo")
    assert demo.compositions == 2
    direct = demo.buffer.lookup_transform("odom", "static_aruco_box", Time()).transform
    p = np.array(list(demo.last_frame.p))
    assert p == pytest.approx([direct.translation.x, direct.translation.y,
                               direct.translation.z], abs=1e-9)
    q = np.array(demo.last_frame.M.GetQuaternion())
    qd = np.array([direct.rotation.x, direct.rotation.y, direct.rotation.z, direct.rotation.w])
    assert min(np.abs(q - qd).max(), np.abs(q + qd).max()) < 1e-9
    assert np.linalg.norm(p - BOX_TOP_MARKER) < 0.03
    lines = [r.message for r in result.logs if r.name == "kdl_chain_demo"
             and r.message.startswith("KDL-composed static_aruco_box in odom: pos=(")]
    assert len(lines) == 2


def test_dynamic_pipeline_sees_markers_2_4_5_within_5_cm() -> None:
    result = run_scenario("dynamic_detector_listener", until_sim_time=3.0)
    listener = result.node("aruco_marker_listener")
    assert set(listener.positions) == set(FRONT_MARKERS)
    for frame, truth in FRONT_MARKERS.items():
        assert np.linalg.norm(np.subtract(listener.positions[frame], truth)) < 0.05, frame
    # every lookup during the run, not only the last one, and no failures
    assert len(listener.lookups) == 9
    for _, frame, xyz in listener.lookups:
        assert np.linalg.norm(np.subtract(xyz, FRONT_MARKERS[frame])) < 0.05
    assert listener.failures == []
    detector = result.node("dynamic_detector")
    assert detector.frames_processed == 90  # 30 Hz for 3 s
    assert set(detector.detection_counts) == {2, 4, 5}
    # the robot moved towards the boxes meanwhile (ground truth)
    x, _y, _ = result.node("world_simulation").true_pose
    assert x > 0.3


def test_scenario_parameters_reach_the_nodes() -> None:
    result = run_scenario("dynamic_detector", {"marker_size": 0.194, "p_controller.goal_x": 0.0},
                          until_sim_time=0.1)
    assert result.node("dynamic_detector").get_parameter("marker_size").value == 0.194
    with pytest.raises(ScenarioError, match="unknown parameter"):
        run_scenario("static_aruco_detector", {"no_such_parameter": 1}, until_sim_time=0.1)


def test_image_saver_hook_and_camera_noise(tmp_path) -> None:
    from posekit.vision.nodes import attach_image_saver

    hooks = [lambda run: attach_image_saver(run, tmp_path, period=0.05)]
    result = run_scenario("dynamic_detector", {"oak_camera.noise_sigma": 3.0},
                          until_sim_time=0.2, on_start=hooks)
    saver = result.node("image_saver")
    names = sorted(p.name for p in saver.saved)
    # frames at 1/30 s steps, at least 0.05 s apart, then the last one at shutdown
    assert names[:3] == ["aruco_detection_image_0_033333333.png",
                         "aruco_detection_image_0_099999999.png",  # 3 x 33333333 ns
                         "aruco_detection_image_0_166666665.png"]  # 5 x 33333333 ns
    assert names[-1] == "aruco_detection_image_last.png"
    import cv2

    image = cv2.imread(str(tmp_path / names[0]))
    assert image.shape == (720, 1280, 3)
    # noise: the sky (top rows, uniform without noise) now varies around its grey level
    sky = image[:40, 200:1000, 1].astype(float)
    assert 2.0 < sky.std() < 4.0
    assert set(result.node("dynamic_detector").detection_counts) == {2, 4, 5}
