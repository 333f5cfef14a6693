// Odometry (RViz2's Odometry display): a shape (arrow or axes) per kept pose in the message's
// header frame, a new pose kept only past the position/angle tolerances from the previous
// kept one, the last `keep` poses; optionally the position covariance as an ellipsoid at the
// newest pose (radii: `covariance_scale` standard deviations along the covariance's axes).
import { ARROW_OPTIONS, disposeTree, makePoseShape, material, poseFinite, poseMatrix } from "./_util.js";

// Eigen decomposition of a symmetric 3x3 matrix (cyclic Jacobi): {values, vectors (columns)}.
export function symmetricEigen3(a) {
  const m = [[a[0][0], a[0][1], a[0][2]], [a[1][0], a[1][1], a[1][2]], [a[2][0], a[2][1], a[2][2]]];
  const v = [[1, 0, 0], [0, 1, 0], [0, 0, 1]];
  for (let sweep = 0; sweep < 50; sweep += 1) {
    const off = Math.abs(m[0][1]) + Math.abs(m[0][2]) + Math.abs(m[1][2]);
    if (off < 1e-15) break;
    for (const [p, q] of [[0, 1], [0, 2], [1, 2]]) {
      if (Math.abs(m[p][q]) < 1e-300) continue;
      const theta = (m[q][q] - m[p][p]) / (2 * m[p][q]);
      const t = Math.sign(theta || 1) / (Math.abs(theta) + Math.sqrt(theta * theta + 1));
      const c = 1 / Math.sqrt(t * t + 1), s = t * c;
      for (let k = 0; k < 3; k += 1) {
        const mkp = m[k][p], mkq = m[k][q];
        m[k][p] = c * mkp - s * mkq;
        m[k][q] = s * mkp + c * mkq;
      }
      for (let k = 0; k < 3; k += 1) {
        const mpk = m[p][k], mqk = m[q][k];
        m[p][k] = c * mpk - s * mqk;
        m[q][k] = s * mpk + c * mqk;
      }
      for (let k = 0; k < 3; k += 1) {
        const vkp = v[k][p], vkq = v[k][q];
        v[k][p] = c * vkp - s * vkq;
        v[k][q] = s * vkp + c * vkq;
      }
    }
  }
  return { values: [m[0][0], m[1][1], m[2][2]], vectors: v };
}

export default {
  name: "Odometry",
  types: ["nav_msgs/msg/Odometry"],
  options: {
    position_tolerance: { type: "number", default: 0.1, min: 0, max: 100, step: 0.05, label: "Position Tolerance" },
    angle_tolerance: { type: "number", default: 0.1, min: 0, max: 6.3, step: 0.05, label: "Angle Tolerance" },
    keep: { type: "number", default: 100, min: 1, max: 10000, step: 1, label: "Keep" },
    ...ARROW_OPTIONS,
    covariance: { type: "bool", default: false, label: "Covariance" },
    covariance_color: { type: "color", default: "#cc33cc", label: "Covariance Color" },
    covariance_alpha: { type: "number", default: 0.3, min: 0, max: 1, step: 0.1, label: "Covariance Alpha" },
    covariance_scale: { type: "number", default: 1, min: 0.01, max: 100, step: 0.1, label: "Covariance Scale" },
  },
  create(ctx, topic, options) {
    const { THREE } = ctx;
    const frameGroup = new THREE.Group();
    ctx.root.add(frameGroup);
    let o = options;
    let template = makePoseShape(THREE, o);
    const kept = [];           // {pose, object}
    let frame = null;
    const ellipsoid = new THREE.Mesh(new THREE.SphereGeometry(1, 24, 16), material(THREE, o.covariance_color, o.covariance_alpha));
    ellipsoid.matrixAutoUpdate = false;
    ellipsoid.visible = false;
    frameGroup.add(ellipsoid);
    let lastCov = null;

    const addShape = (pose) => {
      const obj = template.clone();
      obj.matrixAutoUpdate = false;
      poseMatrix(THREE, pose, obj.matrix);
      frameGroup.add(obj);
      return obj;
    };
    const trim = () => {
      while (kept.length > o.keep) frameGroup.remove(kept.shift().object);
    };
    const placeCovariance = () => {
      const cov = lastCov;
      ellipsoid.visible = Boolean(o.covariance && cov);
      if (!ellipsoid.visible) return;
      const c = cov.covariance;
      const { values, vectors } = symmetricEigen3([[c[0], c[1], c[2]], [c[6], c[7], c[8]], [c[12], c[13], c[14]]]);
      const r = values.map((ev) => Math.max(1e-4, o.covariance_scale * Math.sqrt(Math.max(ev, 0))));
      const axes = new THREE.Matrix4().set(
        vectors[0][0], vectors[0][1], vectors[0][2], 0,
        vectors[1][0], vectors[1][1], vectors[1][2], 0,
        vectors[2][0], vectors[2][1], vectors[2][2], 0, 0, 0, 0, 1);
      const p = cov.pose.position;
      ellipsoid.matrix.makeTranslation(p.x, p.y, p.z).multiply(axes).multiply(new THREE.Matrix4().makeScale(...r));
      ellipsoid.matrixWorldNeedsUpdate = true;
      ellipsoid.userData.radii = r;
    };

    return {
      update(msg) {
        const pose = msg.pose.pose;
        if (!poseFinite(pose)) { ctx.setStatus("warn", "non-finite pose"); return; }
        if (frame !== msg.header.frame_id) {
          for (const k of kept.splice(0)) frameGroup.remove(k.object);
          frame = msg.header.frame_id;
        }
        const placed = ctx.attach(frameGroup, frame);
        ctx.setStatus(placed ? "ok" : "warn", placed ? "" : `no transform from [${frame}]`);
        lastCov = { pose, covariance: msg.pose.covariance };
        placeCovariance();
        const last = kept[kept.length - 1];
        if (last) {
          const a = last.pose, p = pose.position;
          const moved = Math.hypot(a.position.x - p.x, a.position.y - p.y, a.position.z - p.z);
          const q1 = a.orientation, q2 = pose.orientation;
          const dot = Math.abs(q1.x * q2.x + q1.y * q2.y + q1.z * q2.z + q1.w * q2.w);
          const turned = 2 * Math.acos(Math.min(1, dot));
          if (moved < o.position_tolerance && turned < o.angle_tolerance) return;
        }
        kept.push({ pose, object: addShape(pose) });
        trim();
      },
      setOptions(next) {
        const reshape = ["shape", "color", "alpha", "shaft_length", "shaft_radius", "head_length",
          "head_radius", "axes_length", "axes_radius"].some((k) => next[k] !== o[k]);
        o = next;
        ellipsoid.material.color.set(o.covariance_color);
        ellipsoid.material.opacity = o.covariance_alpha;
        ellipsoid.material.transparent = o.covariance_alpha < 1;
        if (reshape) {
          disposeTree(template);
          template = makePoseShape(THREE, o);
          for (const k of kept) { frameGroup.remove(k.object); k.object = addShape(k.pose); }
        }
        trim();
        placeCovariance();
      },
      dispose() { disposeTree(template); disposeTree(frameGroup); },
      info: () => ({ frame, kept: kept.length, covariance_radii: ellipsoid.visible ? ellipsoid.userData.radii : null }),
    };
  },
};
