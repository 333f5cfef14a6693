// PoseArray (RViz2's PoseArray display): every pose as a flat arrow (lines), a 3D arrow or
// axes, in the array's header frame.
import { addAtPoses, makeArrowOfLength, makeAxes, material, newestPosesDisplay, poseFinite, poseMatrix } from "./_util.js";

export default {
  name: "PoseArray",
  types: ["geometry_msgs/msg/PoseArray"],
  options: {
    shape: { type: "enum", choices: ["Arrow (Flat)", "Arrow (3D)", "Axes"], default: "Arrow (Flat)", label: "Shape" },
    color: { type: "color", default: "#ff1900", label: "Color" },
    alpha: { type: "number", default: 1, min: 0, max: 1, step: 0.1, label: "Alpha" },
    arrow_length: { type: "number", default: 0.3, min: 0.001, max: 100, step: 0.05, label: "Arrow Length" },
    axes_length: { type: "number", default: 0.3, min: 0.001, max: 100, step: 0.05, label: "Axes Length" },
    axes_radius: { type: "number", default: 0.01, min: 0.0001, max: 10, step: 0.005, label: "Axes Radius" },
  },
  create(ctx, topic, options) {
    const { THREE } = ctx;
    const frameGroup = new THREE.Group();
    ctx.root.add(frameGroup);
    return newestPosesDisplay(ctx, frameGroup, options, (msg, o) => {
      const poses = msg.poses.filter(poseFinite);
      const m = new THREE.Matrix4();
      if (o.shape === "Arrow (Flat)") {
        // Shaft along x and a head of two strokes, as RViz2 draws it, all in one geometry.
        const L = o.arrow_length, h = 0.3 * L;
        const local = [[0, 0, L, 0], [L, 0, L - h, 0.5 * h], [L, 0, L - h, -0.5 * h]];
        const pts = [];
        for (const p of poses) {
          poseMatrix(THREE, p, m);
          for (const [x0, y0, x1, y1] of local) {
            pts.push(new THREE.Vector3(x0, y0, 0).applyMatrix4(m), new THREE.Vector3(x1, y1, 0).applyMatrix4(m));
          }
        }
        const geom = new THREE.BufferGeometry().setFromPoints(pts);
        frameGroup.add(new THREE.LineSegments(geom, new THREE.LineBasicMaterial({ color: o.color, transparent: o.alpha < 1, opacity: o.alpha })));
      } else {
        const shape = o.shape === "Axes"
          ? makeAxes(THREE, o.axes_length, o.axes_radius, o.alpha)
          : makeArrowOfLength(THREE, o.arrow_length, material(THREE, o.color, o.alpha));
        addAtPoses(THREE, frameGroup, shape, poses);
      }
    });
  },
};
