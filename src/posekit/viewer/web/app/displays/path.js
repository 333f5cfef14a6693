// Path (RViz2's Path display): the poses of a nav_msgs/Path joined by a line in the path's
// header frame, optionally an arrow or axes at every pose.
import { disposeTree, makeArrow, makeAxes, material, poseFinite, poseMatrix } from "./_util.js";

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
    let o = options, last = null;
    const draw = () => {
      disposeTree(frameGroup);
      if (!last) return;
      const poses = last.poses.map((p) => p.pose).filter(poseFinite);
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
          : makeArrow(THREE, { shaftLength: 0.77 * o.pose_size, shaftRadius: o.pose_size / 20, headLength: 0.23 * o.pose_size, headRadius: o.pose_size / 10 }, material(THREE, o.color, o.alpha));
        for (const p of poses) {
          const s = shape.clone();
          s.matrixAutoUpdate = false;
          poseMatrix(THREE, p, s.matrix);
          frameGroup.add(s);
        }
      }
    };
    return {
      update(msg) {
        last = msg;
        const placed = ctx.attach(frameGroup, msg.header.frame_id);
        ctx.setStatus(placed ? "ok" : "warn", placed ? `${msg.poses.length} poses` : `no transform from [${msg.header.frame_id}]`);
        draw();
      },
      setOptions(next) { o = next; draw(); },
      dispose() { disposeTree(frameGroup); },
      info: () => (last ? { frame: last.header.frame_id, poses: last.poses.length } : null),
    };
  },
};
