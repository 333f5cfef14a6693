// Marker and MarkerArray (RViz2's Marker / MarkerArray displays): visualization_msgs markers
// by namespace and id, each in its header frame (re-placed with every TF update, i.e. as if
// frame_locked), kept until DELETE / DELETEALL or their lifetime runs out (measured on the
// clock the data uses: the run's time the server sends with TF, else the wall clock).
// Types drawn: ARROW, CUBE, SPHERE, CYLINDER, LINE_STRIP, LINE_LIST, CUBE_LIST, SPHERE_LIST,
// POINTS, TEXT_VIEW_FACING, TRIANGLE_LIST; MESH_RESOURCE is reported, not drawn.
import { disposeTree, makeArrow, poseFinite, poseMatrix, stampSeconds } from "./_util.js";

export const MARKER = {
  ARROW: 0, CUBE: 1, SPHERE: 2, CYLINDER: 3, LINE_STRIP: 4, LINE_LIST: 5, CUBE_LIST: 6,
  SPHERE_LIST: 7, POINTS: 8, TEXT_VIEW_FACING: 9, MESH_RESOURCE: 10, TRIANGLE_LIST: 11,
};
const ADD = 0, DELETE = 2, DELETEALL = 3;
const TYPE_NAMES = Object.fromEntries(Object.entries(MARKER).map(([k, v]) => [v, k]));

function rgba(THREE, c) {
  return { color: new THREE.Color(c.r, c.g, c.b), alpha: Math.max(0, Math.min(1, c.a)) };
}

function markerMaterial(THREE, c, extra = {}) {
  const { color, alpha } = rgba(THREE, c);
  return new THREE.MeshStandardMaterial({ color, transparent: alpha < 1, opacity: alpha, roughness: 0.7, ...extra });
}

const num = (v) => (typeof v === "number" && Number.isFinite(v) ? v : 0);
const vec = (THREE, p) => new THREE.Vector3(num(p.x), num(p.y), num(p.z));

// Instanced cylinders (one per segment [a, b]) of diameter `width`, coloured per segment.
function segmentMesh(THREE, segs, width, colors, mat) {
  const geom = new THREE.CylinderGeometry(0.5, 0.5, 1, 8);
  const mesh = new THREE.InstancedMesh(geom, mat, Math.max(1, segs.length));
  mesh.count = segs.length;
  const up = new THREE.Vector3(0, 1, 0), m = new THREE.Matrix4(), q = new THREE.Quaternion();
  segs.forEach(([a, b], i) => {
    const d = new THREE.Vector3().subVectors(b, a);
    const len = d.length();
    q.setFromUnitVectors(up, len > 1e-9 ? d.clone().divideScalar(len) : up);
    m.compose(a.clone().add(b).multiplyScalar(0.5), q, new THREE.Vector3(width, Math.max(len, 1e-6), width));
    mesh.setMatrixAt(i, m);
    if (colors) mesh.setColorAt(i, colors[i]);
  });
  return mesh;
}

function textSprite(THREE, text, height, c) {
  const canvas = document.createElement("canvas");
  const ctx2d = canvas.getContext("2d");
  const px = 64;
  ctx2d.font = `${px}px sans-serif`;
  const w = Math.max(1, Math.ceil(ctx2d.measureText(text).width));
  canvas.width = w + 8;
  canvas.height = px + 16;
  ctx2d.font = `${px}px sans-serif`;
  const { color, alpha } = rgba(THREE, c);
  ctx2d.fillStyle = `#${color.getHexString()}`;
  ctx2d.textBaseline = "middle";
  ctx2d.fillText(text, 4, canvas.height / 2);
  const tex = new THREE.CanvasTexture(canvas);
  tex.colorSpace = THREE.SRGBColorSpace;
  const sprite = new THREE.Sprite(new THREE.SpriteMaterial({ map: tex, transparent: true, opacity: alpha, depthTest: false }));
  const h = height > 0 ? height : 0.1;
  sprite.scale.set((h * canvas.width) / canvas.height, h, 1);
  return sprite;
}

// The three.js object of one marker (in the marker's pose), or a string saying why not.
export function buildMarker(THREE, mk) {
  const s = { x: num(mk.scale.x), y: num(mk.scale.y), z: num(mk.scale.z) };
  const points = (mk.points || []).map((p) => vec(THREE, p));
  const colors = mk.colors && mk.colors.length === points.length && points.length
    ? mk.colors.map((c) => new THREE.Color(num(c.r), num(c.g), num(c.b))) : null;
  const mat = () => markerMaterial(THREE, mk.color);
  switch (mk.type) {
    case MARKER.ARROW: {
      if (points.length >= 2) {
        const [a, b] = points;
        const len = a.distanceTo(b);
        const headLength = s.z > 0 ? s.z : 0.23 * len;
        const arrow = makeArrow(THREE, { shaftLength: Math.max(len - headLength, 1e-6), shaftRadius: s.x / 2, headLength, headRadius: s.y / 2 }, mat());
        arrow.position.copy(a);
        if (len > 1e-9) arrow.quaternion.setFromUnitVectors(new THREE.Vector3(1, 0, 0), new THREE.Vector3().subVectors(b, a).normalize());
        const g = new THREE.Group();
        g.add(arrow);
        return g;
      }
      const arrow = makeArrow(THREE, { shaftLength: 0.77 * s.x, shaftRadius: 0.25, headLength: 0.23 * s.x, headRadius: 0.5 }, mat());
      // Width scale.y, height scale.z (the shaft half as wide as the head, as RViz2 draws).
      for (const child of arrow.children) child.geometry.scale(1, s.y, s.z);
      return arrow;
    }
    case MARKER.CUBE: return new THREE.Mesh(new THREE.BoxGeometry(s.x, s.y, s.z), mat());
    case MARKER.SPHERE: {
      const g = new THREE.SphereGeometry(0.5, 24, 16);
      g.scale(s.x, s.y, s.z);
      return new THREE.Mesh(g, mat());
    }
    case MARKER.CYLINDER: {
      const g = new THREE.CylinderGeometry(0.5, 0.5, 1, 24);
      g.rotateX(Math.PI / 2);       // three.js cylinders stand on y; ROS's on z
      g.scale(s.x, s.y, s.z);
      return new THREE.Mesh(g, mat());
    }
    case MARKER.LINE_STRIP:
    case MARKER.LINE_LIST: {
      const segs = [], segColors = colors ? [] : null;
      const step = mk.type === MARKER.LINE_STRIP ? 1 : 2;
      for (let i = 0; i + 1 < points.length; i += step) {
        segs.push([points[i], points[i + 1]]);
        if (segColors) segColors.push(colors[i]);
      }
      const material = mat();
      if (segColors) material.color.set(0xffffff);
      return segmentMesh(THREE, segs, Math.max(s.x, 1e-4), segColors, material);
    }
    case MARKER.CUBE_LIST:
    case MARKER.SPHERE_LIST: {
      const geom = mk.type === MARKER.CUBE_LIST ? new THREE.BoxGeometry(1, 1, 1) : new THREE.SphereGeometry(0.5, 16, 12);
      const material = mat();
      if (colors) material.color.set(0xffffff);
      const mesh = new THREE.InstancedMesh(geom, material, Math.max(1, points.length));
      mesh.count = points.length;
      const m = new THREE.Matrix4();
      points.forEach((p, i) => {
        mesh.setMatrixAt(i, m.makeScale(s.x, s.y, s.z).setPosition(p));
        if (colors) mesh.setColorAt(i, colors[i]);
      });
      return mesh;
    }
    case MARKER.POINTS: {
      const geom = new THREE.BufferGeometry().setFromPoints(points);
      const { color, alpha } = rgba(THREE, mk.color);
      if (colors) geom.setAttribute("color", new THREE.Float32BufferAttribute(colors.flatMap((c) => [c.r, c.g, c.b]), 3));
      const material = new THREE.PointsMaterial({ size: Math.max(s.x, 1e-4), sizeAttenuation: true, color: colors ? 0xffffff : color, vertexColors: Boolean(colors), transparent: alpha < 1, opacity: alpha });
      return new THREE.Points(geom, material);
    }
    case MARKER.TEXT_VIEW_FACING: return textSprite(THREE, String(mk.text || ""), s.z, mk.color);
    case MARKER.TRIANGLE_LIST: {
      const geom = new THREE.BufferGeometry().setFromPoints(points.slice(0, points.length - (points.length % 3)));
      geom.scale(s.x || 1, s.y || 1, s.z || 1);
      geom.computeVertexNormals();
      const material = mat();
      material.side = THREE.DoubleSide;
      if (colors) {
        geom.setAttribute("color", new THREE.Float32BufferAttribute(colors.flatMap((c) => [c.r, c.g, c.b]), 3));
        material.vertexColors = true;
        material.color.set(0xffffff);
      }
      return new THREE.Mesh(geom, material);
    }
    case MARKER.MESH_RESOURCE: return "MESH_RESOURCE markers are not drawn";
    default: return `unknown marker type ${mk.type}`;
  }
}

export default {
  name: "Marker",
  types: ["visualization_msgs/msg/Marker", "visualization_msgs/msg/MarkerArray"],
  queue: 100,
  options: {},
  create(ctx, topic) {
    const { THREE } = ctx;
    const markers = new Map();      // "ns/id" -> {group, expires, type, ns}
    const problems = new Map();     // "ns/id" -> why not drawn
    const now = () => { const t = ctx.now(); return typeof t === "number" ? t : Date.now() / 1000; };

    const drop = (key) => {
      const m = markers.get(key);
      if (!m) return;
      ctx.detach(m.group);
      disposeTree(m.group);
      m.group.removeFromParent();
      markers.delete(key);
    };

    const status = () => {
      const bad = [...problems.values()];
      ctx.setStatus(bad.length ? "warn" : "ok", bad.length ? bad[bad.length - 1] : `${markers.size} markers`);
    };

    const apply = (mk) => {
      const key = `${mk.ns}/${mk.id}`;
      if (mk.action === DELETEALL) {
        for (const k of [...markers.keys()]) if (!mk.ns || markers.get(k).ns === mk.ns) drop(k);
        problems.clear();
        return;
      }
      if (mk.action === DELETE) { drop(key); problems.delete(key); return; }
      if (mk.action !== ADD && mk.action !== 1) { problems.set(key, `unknown action ${mk.action}`); return; }
      if (!poseFinite(mk.pose)) { problems.set(key, `${key}: non-finite pose`); return; }
      const obj = buildMarker(THREE, mk);
      drop(key);
      if (typeof obj === "string") { problems.set(key, `${key}: ${obj}`); return; }
      problems.delete(key);
      const group = new THREE.Group();
      obj.matrixAutoUpdate = false;
      poseMatrix(THREE, mk.pose, obj.matrix);
      group.add(obj);
      ctx.root.add(group);
      ctx.attach(group, mk.header.frame_id);
      const life = stampSeconds(mk.lifetime);
      markers.set(key, { group, ns: mk.ns, type: mk.type, expires: life > 0 ? now() + life : null });
    };

    const expire = () => {
      const t = now();
      let changed = false;
      for (const [key, m] of markers) if (m.expires !== null && t >= m.expires) { drop(key); changed = true; }
      if (changed) { status(); ctx.requestRender(); }
    };
    ctx.onFrames(expire);
    const timer = setInterval(expire, 250);

    return {
      update(msg) {
        for (const mk of Array.isArray(msg.markers) ? msg.markers : [msg]) apply(mk);
        status();
      },
      setOptions() {},
      dispose() {
        clearInterval(timer);
        for (const key of [...markers.keys()]) drop(key);
      },
      info: () => ({
        count: markers.size,
        markers: Object.fromEntries([...markers].map(([k, m]) => [k, TYPE_NAMES[m.type]])),
        problems: [...problems.values()],
      }),
    };
  },
};
