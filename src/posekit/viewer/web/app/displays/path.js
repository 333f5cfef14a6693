// Path (RViz2's Path display): the poses of a nav_msgs/Path joined by a line in the path's
// header frame, optionally an arrow or axes at every pose.
import { addAtPoses, makeArrowOfLength, makeAxes, material, newestPosesDisplay, poseFinite } from "./_util.js";

export default {
  name: "Path",
  types: ["nav_msgs/msg/Path"],
  options: {
    color: { type: "color", default: "#19ff00", label: "Color" },
    alpha: { type: "number", default: 1, min: 0, max: 1, step: 0.1, label: "Alpha" },
    line_width: { type: "number", default: 0, min: 0, max: 10, step: 0.01, label: "Line Width (m, 0: 1 px lines)" },
    pose_style: { type: "enum", choices: ["None", "Axes", "Arrows"], default: "None", label: "Pose Style" },
    pose_size: { type: "number", default: 0.3, min: 0.001, max: 100, step: 0.05, label: "Pose Length" },
  },
  create(ctx, topic, options) {
    const { THREE } = ctx;
    const frameGroup = new THREE.Group();
    ctx.root.add(frameGroup);
    return newestPosesDisplay(ctx, frameGroup, options, (msg, o) => {
      const poses = msg.poses.map((p) => p.pose).filter(poseFinite);
      const pts = poses.map((p) => new THREE.Vector3(p.position.x, p.position.y, p.position.z));
      if (pts.length >= 2) {
        if (o.line_width > 0) {
          // A tube of the line width: visible at any zoom (WebGL lines are 1 px wide).
          const curve = new THREE.CurvePath();
          for (let i = 1; i < pts.length; i += 1) curve.add(new THREE.LineCurve3(pts[i - 1], pts[i]));
          frameGroup.add(new THREE.Mesh(new THREE.TubeGeometry(curve, Math.max(1, pts.length - 1), o.line_width / 2, 6), material(THREE, o.color, o.alpha)));
        } else {
          const geom = new THREE.BufferGeometry().setFromPoints(pts);
          frameGroup.add(new THREE.Line(geom, new THREE.LineBasicMaterial({ color: o.color, transparent: o.alpha < 1, opacity: o.alpha })));
        }
      }
      if (o.pose_style !== "None") {
        const shape = o.pose_style === "Axes"
          ? makeAxes(THREE, o.pose_size, o.pose_size / 20)
          : makeArrowOfLength(THREE, o.pose_size, material(THREE, o.color, o.alpha));
        addAtPoses(THREE, frameGroup, shape, poses);
      }
    });
  },
};
