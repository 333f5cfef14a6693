// 3D scene with three.js, in ROS coordinates (z up, metres). Everything is placed in the
// Fixed Frame: the server sends every frame's pose T_fixed_frame, and objects that live in a
// frame (the robot in base_link, the world and odometry trails in their header frame) are
// children of a group holding that pose.

import * as THREE from "three";
import { OrbitControls } from "three/addons/controls/OrbitControls.js";
import { createLabelLayer } from "./labels.js";

const AXIS_LENGTH = 0.15;         // m, per frame
const STALE_GREY = 0x8a8a8a;
const ODOM_COLORS = { "/odometry/filtered": 0xff1900, "/odometry/wheels": 0x2f7bff, truth: 0x21c45a };

// ROSbot 2R/3 (Husarion): about 0.20 m long, 0.15 m body width between the wheels,
// wheels of radius 0.0425 m at x = +-0.053, y = +-0.096 in body_link (robot/description.py).
const WHEEL_RADIUS = 0.0425;
const WHEEL_WIDTH = 0.04;
const WHEELS = [[0.053, 0.096], [0.053, -0.096], [-0.053, 0.096], [-0.053, -0.096]];

function poseToMatrix(x, y, z, qx, qy, qz, qw, m = new THREE.Matrix4()) {
  return m.compose(new THREE.Vector3(x, y, z), new THREE.Quaternion(qx, qy, qz, qw), new THREE.Vector3(1, 1, 1));
}

function makeAxes() {
  const group = new THREE.Group();
  const colors = [0xff2020, 0x20d020, 0x3060ff];
  const dirs = [[1, 0, 0], [0, 1, 0], [0, 0, 1]];
  group.userData.materials = [];
  dirs.forEach((d, i) => {
    const geom = new THREE.CylinderGeometry(0.006, 0.006, AXIS_LENGTH, 6);
    geom.translate(0, AXIS_LENGTH / 2, 0);
    const mat = new THREE.MeshBasicMaterial({ color: colors[i] });
    mat.userData.color = colors[i];
    const mesh = new THREE.Mesh(geom, mat);
    mesh.quaternion.setFromUnitVectors(new THREE.Vector3(0, 1, 0), new THREE.Vector3(...d));
    group.add(mesh);
    group.userData.materials.push(mat);
  });
  return group;
}

function makeRobot() {
  const robot = new THREE.Group();
  const body = new THREE.Mesh(
    new THREE.BoxGeometry(0.2, 0.15, 0.09),
    new THREE.MeshStandardMaterial({ color: 0x3a3f47, roughness: 0.7, metalness: 0.1 }),
  );
  body.position.set(0, 0, WHEEL_RADIUS + 0.045);
  robot.add(body);
  const cover = new THREE.Mesh(
    new THREE.BoxGeometry(0.16, 0.12, 0.012),
    new THREE.MeshStandardMaterial({ color: 0xc0392b, roughness: 0.6 }),
  );
  cover.position.set(-0.01, 0, WHEEL_RADIUS + 0.096);
  robot.add(cover);
  const camera = new THREE.Mesh(
    new THREE.BoxGeometry(0.03, 0.1, 0.03),
    new THREE.MeshStandardMaterial({ color: 0x15171a }),
  );
  camera.position.set(-0.02, 0, WHEEL_RADIUS + 0.15);
  robot.add(camera);
  const wheelMat = new THREE.MeshStandardMaterial({ color: 0x111111, roughness: 0.9 });
  for (const [x, y] of WHEELS) {
    const wheel = new THREE.Mesh(new THREE.CylinderGeometry(WHEEL_RADIUS, WHEEL_RADIUS, WHEEL_WIDTH, 20), wheelMat);
    wheel.position.set(x, y, WHEEL_RADIUS);   // cylinder axis is +y: the wheel axle
    robot.add(wheel);
  }
  return robot;
}

// A grid on the z = 0 plane of the Fixed Frame, +-half metres, one segment per cell edge:
// short segments because some software GL drivers drop a whole line that crosses the near
// plane (a long grid line under the camera would vanish).
function makeGrid(half, step) {
  const minor = [], major = [];
  for (let i = -half; i <= half; i += step) {
    const target = Math.abs(i) < 1e-9 ? major : minor;
    for (let j = -half; j < half; j += step) {
      target.push(i, j, 0, i, j + step, 0, j, i, 0, j + step, i, 0);
    }
  }
  const group = new THREE.Group();
  for (const [points, color] of [[minor, 0x5a5a66], [major, 0x9a9ab0]]) {
    const geometry = new THREE.BufferGeometry();
    geometry.setAttribute("position", new THREE.Float32BufferAttribute(points, 3));
    group.add(new THREE.LineSegments(geometry, new THREE.LineBasicMaterial({ color })));
  }
  return group;
}

function arrowLength(speed) {
  // Proportional to speed (where the robot is in 0.5 s), at least 3 cm so stops stay visible.
  return Math.max(0.03, 0.5 * speed);
}

// "x,y,z" from the page URL (e.g. ?camera=-1,-2,3&target=1,0,0), else the default.
function vectorParam(name, fallback) {
  const text = new URLSearchParams(location.search).get(name);
  const v = text ? text.split(",").map(Number) : [];
  return v.length === 3 && v.every(Number.isFinite) ? v : fallback;
}

export async function createScene3D(container) {
  const canvas = document.createElement("canvas");
  canvas.id = "scene";
  container.prepend(canvas);
  let renderer;
  try {
    // preserveDrawingBuffer: the canvas content stays readable (canvas.toDataURL()).
    renderer = new THREE.WebGLRenderer({ canvas, antialias: true, preserveDrawingBuffer: true });
  } catch (err) {
    canvas.remove();
    throw new Error(`WebGL is not available: ${err.message || err}`);
  }
  renderer.setPixelRatio(Math.min(window.devicePixelRatio || 1, 2));
  renderer.setClearColor(0x30303a);

  const scene = new THREE.Scene();
  const camera = new THREE.PerspectiveCamera(50, 1, 0.02, 500);
  camera.up.set(0, 0, 1);
  camera.position.set(...vectorParam("camera", [-1.5, -2.5, 4.0]));
  const controls = new OrbitControls(camera, canvas);
  controls.target.set(...vectorParam("target", [2.0, 2.0, 0]));
  controls.update();
  let controlsMoved = false;
  controls.addEventListener("change", () => { controlsMoved = true; });

  scene.add(new THREE.HemisphereLight(0xffffff, 0x404050, 1.6));
  const sun = new THREE.DirectionalLight(0xffffff, 1.6);
  sun.position.set(3, -1, 8);
  scene.add(sun);

  const grid = makeGrid(10, 1.0);
  scene.add(grid);

  const tfRoot = new THREE.Group();
  scene.add(tfRoot);
  const frameObjects = new Map();               // name -> {group, axes, stale, ok}
  const linkGeometry = new THREE.BufferGeometry();
  linkGeometry.setAttribute("position", new THREE.Float32BufferAttribute(new Float32Array(6 * 256), 3));
  const links = new THREE.LineSegments(linkGeometry, new THREE.LineBasicMaterial({ color: 0xf0d050, transparent: true, opacity: 0.8 }));
  links.frustumCulled = false;
  scene.add(links);

  const framePose = new Map();                  // name -> Matrix4 in the fixed frame
  const robot = makeRobot();
  robot.visible = false;
  scene.add(robot);
  const worldGroup = new THREE.Group();
  worldGroup.matrixAutoUpdate = false;
  scene.add(worldGroup);
  let worldFrame = "odom";

  // The current goal (goal_pose, in its header frame) and the 2D Goal Pose tool's draft.
  const GOAL_COLOR = 0xff40ff;
  const goalGroup = new THREE.Group();
  goalGroup.matrixAutoUpdate = false;
  goalGroup.visible = false;
  const goalArrow = new THREE.ArrowHelper(new THREE.Vector3(1, 0, 0), new THREE.Vector3(), 0.45, GOAL_COLOR, 0.12, 0.07);
  goalGroup.add(goalArrow);
  scene.add(goalGroup);
  let goal = null;
  const draft = new THREE.ArrowHelper(new THREE.Vector3(1, 0, 0), new THREE.Vector3(), 0.45, 0x40ff40, 0.12, 0.07);
  draft.visible = false;
  scene.add(draft);

  // Detected ArUco markers: the detector's aruco_marker_<id> frames (fresh, not stale) get a
  // bright square of the marker's size (from the world, else 0.2 m) on the marker's face
  // (the frame's x-y plane) and a halo, drawn apart from the TF axes and over everything
  // (no depth test): an estimate a few millimetres behind the box face stays visible.
  const DETECTION_COLOR = 0x00ff66;
  const detectionRoot = new THREE.Group();
  scene.add(detectionRoot);
  const detections = new Map();                 // frame -> Group
  let markerSizes = new Map();                  // marker id -> size (m)
  function detectionObject(size) {
    const g = new THREE.Group();
    g.matrixAutoUpdate = false;
    const fill = new THREE.Mesh(new THREE.PlaneGeometry(size * 1.25, size * 1.25),
      new THREE.MeshBasicMaterial({ color: DETECTION_COLOR, transparent: true, opacity: 0.3, side: THREE.DoubleSide, depthWrite: false, depthTest: false }));
    fill.renderOrder = 10;
    fill.position.z = 0.004;
    g.add(fill);
    const bar = Math.max(0.01, size * 0.08), half = size * 0.625;
    const mat = new THREE.MeshBasicMaterial({ color: DETECTION_COLOR, depthTest: false });
    for (const [x, y, w, h] of [[0, half, 2 * half + bar, bar], [0, -half, 2 * half + bar, bar], [half, 0, bar, 2 * half], [-half, 0, bar, 2 * half]]) {
      const edge = new THREE.Mesh(new THREE.BoxGeometry(w, h, bar / 2), mat);
      edge.position.set(x, y, 0.004);
      edge.renderOrder = 11;
      g.add(edge);
    }
    g.userData.size = size;
    return g;
  }
  function placeDetections(msg, staleSeconds) {
    const seen = new Set();
    for (const f of msg.frames) {
      const [name, , x, y, z, qx, qy, qz, qw, age, isStatic, ok] = f;
      const m = /(?:^|\/)aruco_marker_(\d+)$/.exec(name);
      if (!m || !ok || (!isStatic && age > staleSeconds)) continue;
      seen.add(name);
      let g = detections.get(name);
      const size = markerSizes.get(Number(m[1])) || 0.2;
      if (!g || g.userData.size !== size) {
        if (g) g.removeFromParent();
        g = detectionObject(size);
        detections.set(name, g);
        detectionRoot.add(g);
      }
      poseToMatrix(x, y, z, qx, qy, qz, qw, g.matrix);
      g.matrixWorldNeedsUpdate = true;
    }
    for (const [name, g] of detections) {
      if (!seen.has(name)) { g.removeFromParent(); detections.delete(name); }
    }
    detectionRoot.visible = vis.detections !== false;
  }

  // What the displays added from the topic list draw (app/display_manager.js).
  const displayRoot = new THREE.Group();
  scene.add(displayRoot);

  const odomGroups = new Map();                 // topic -> {group, arrows: [], frame}
  let vis = {};
  let hello = null;

  function frameGroup(name) {
    let obj = frameObjects.get(name);
    if (!obj) {
      const group = new THREE.Group();
      group.matrixAutoUpdate = false;
      const axes = makeAxes();
      axes.scale.setScalar(tfOptions.scale);
      group.add(axes);
      tfRoot.add(group);
      obj = { group, axes, stale: false, ok: false };
      frameObjects.set(name, obj);
    }
    return obj;
  }

  function setStale(obj, stale) {
    if (obj.stale === stale) return;
    obj.stale = stale;
    for (const mat of obj.axes.userData.materials) mat.color.setHex(stale ? STALE_GREY : mat.userData.color);
  }

  // RViz2's TF display options: frames hidden, frames whose name is hidden, marker scale.
  let tfOptions = { hidden: new Set(), noName: new Set(), scale: 1.0 };
  function setTfOptions(o) {
    tfOptions = o;
    for (const [name, obj] of frameObjects) {
      obj.axes.scale.setScalar(o.scale);
      obj.group.visible = obj.ok && vis.tf !== false && !o.hidden.has(name);
    }
    controlsMoved = true;
  }

  // Frame names in screen space, de-overlapped (labels.js), refreshed on every render.
  const labelLayer = createLabelLayer(container);
  let labelsHidden = 0;
  const projected = new THREE.Vector3();
  function updateLabels() {
    const items = [];
    if (vis.tf !== false && vis.names !== false) {
      const w = canvas.clientWidth, h = canvas.clientHeight;
      for (const [name, obj] of frameObjects) {
        if (!obj.group.visible || tfOptions.noName.has(name)) continue;
        projected.setFromMatrixPosition(obj.group.matrix).project(camera);
        if (projected.z > 1 || Math.abs(projected.x) > 1.2 || Math.abs(projected.y) > 1.2) continue;
        items.push({ name, x: ((projected.x + 1) / 2) * w, y: ((1 - projected.y) / 2) * h, stale: obj.stale });
      }
    }
    labelsHidden = labelLayer.update(items);
  }

  function setFrames(msg, staleSeconds) {
    framePose.clear();
    const seen = new Set();
    const positions = links.geometry.attributes.position;
    let nLinks = 0;
    const okFrames = new Map();
    for (const f of msg.frames) {
      const [name, , x, y, z, qx, qy, qz, qw, , , ok] = f;
      if (ok) okFrames.set(name, f);
    }
    for (const f of msg.frames) {
      const [name, parent, x, y, z, qx, qy, qz, qw, age, isStatic, ok] = f;
      const obj = frameGroup(name);
      seen.add(name);
      obj.ok = Boolean(ok);
      obj.group.visible = obj.ok && vis.tf !== false && !tfOptions.hidden.has(name);
      if (!ok) continue;
      const m = poseToMatrix(x, y, z, qx, qy, qz, qw);
      framePose.set(name, m);
      obj.group.matrix.copy(m);
      obj.group.matrixWorldNeedsUpdate = true;
      setStale(obj, !isStatic && age > staleSeconds);
      const p = okFrames.get(parent);
      if (p && nLinks < 256) {
        positions.setXYZ(2 * nLinks, x, y, z);
        positions.setXYZ(2 * nLinks + 1, p[2], p[3], p[4]);
        nLinks += 1;
      }
    }
    for (const [name, obj] of frameObjects) if (!seen.has(name)) obj.group.visible = obj.ok = false;
    positions.needsUpdate = true;
    links.geometry.setDrawRange(0, 2 * nLinks);
    links.visible = vis.tf !== false;
    const base = framePose.get((hello && hello.base_frame) || "base_link");
    robot.visible = Boolean(base) && vis.robot !== false;
    if (base) robot.matrix.copy(base), (robot.matrixAutoUpdate = false), (robot.matrixWorldNeedsUpdate = true);
    placeWorld();
    placeOdometry();
    placeGoal();
    placeDetections(msg, staleSeconds);
  }

  function placeGoal() {
    const m = goal ? framePose.get(goal.frame) : null;
    goalGroup.visible = Boolean(m) && vis.goal !== false;
    if (m) { goalGroup.matrix.copy(m); goalGroup.matrixWorldNeedsUpdate = true; }
  }

  function setGoal(g) {
    goal = g;
    if (g) {
      const [x, y, z, qx, qy, qz, qw] = g.pose;
      goalArrow.position.set(x, y, z + 0.01);
      goalArrow.setDirection(new THREE.Vector3(1, 0, 0).applyQuaternion(new THREE.Quaternion(qx, qy, qz, qw)));
    }
    placeGoal();
    controlsMoved = true;
  }

  // Where a pixel of the canvas (client coordinates) meets the Fixed Frame's z = 0 plane.
  const raycaster = new THREE.Raycaster();
  const ground = new THREE.Plane(new THREE.Vector3(0, 0, 1), 0);
  function pickGround(clientX, clientY) {
    const r = canvas.getBoundingClientRect();
    const ndc = new THREE.Vector2(((clientX - r.left) / r.width) * 2 - 1, -((clientY - r.top) / r.height) * 2 + 1);
    raycaster.setFromCamera(ndc, camera);
    const hit = raycaster.ray.intersectPlane(ground, new THREE.Vector3());
    return hit ? { x: hit.x, y: hit.y } : null;
  }

  // The client coordinates of a point of the Fixed Frame (three.js's projection).
  function projectPoint(x, y, z = 0) {
    const r = canvas.getBoundingClientRect();
    const v = new THREE.Vector3(x, y, z).project(camera);
    return { x: r.left + ((v.x + 1) / 2) * r.width, y: r.top + ((1 - v.y) / 2) * r.height };
  }

  function setDraft(from, yaw, kind = "goal") {
    draft.setColor(kind === "pose" ? 0x40a0ff : 0x40ff40);
    draft.visible = Boolean(from);
    if (from) {
      draft.position.set(from.x, from.y, 0.02);
      draft.setDirection(new THREE.Vector3(Math.cos(yaw), Math.sin(yaw), 0));
    }
    controlsMoved = true;
  }

  function placeWorld() {
    const m = framePose.get(worldFrame);
    worldGroup.visible = Boolean(m) && vis.world !== false;
    if (m) { worldGroup.matrix.copy(m); worldGroup.matrixWorldNeedsUpdate = true; }
  }

  function setWorld(world) {
    worldGroup.clear();
    if (!world) return;
    worldFrame = world.frame || "odom";
    markerSizes = new Map(world.markers.map((mk) => [mk.id, mk.size]));
    const boxMat = new THREE.MeshStandardMaterial({ color: 0xf4f4f0, roughness: 0.8 });
    const edgeMat = new THREE.LineBasicMaterial({ color: 0x999999 });
    for (const b of world.boxes) {
      const geom = new THREE.BoxGeometry(b.size, b.size, b.size);
      const mesh = new THREE.Mesh(geom, boxMat);
      mesh.matrixAutoUpdate = false;
      mesh.matrix.set(...b.T);
      const edges = new THREE.LineSegments(new THREE.EdgesGeometry(geom), edgeMat);
      mesh.add(edges);
      worldGroup.add(mesh);
    }
    const loader = new THREE.TextureLoader();
    for (const mk of world.markers) {
      const mat = new THREE.MeshBasicMaterial({ color: 0xffffff });
      if (mk.image) {
        const tex = loader.load(mk.image, () => { controlsMoved = true; });
        tex.magFilter = THREE.NearestFilter;
        tex.colorSpace = THREE.SRGBColorSpace;
        mat.map = tex;
      } else {
        mat.color.setHex(0x111111);
      }
      const plane = new THREE.Mesh(new THREE.PlaneGeometry(mk.size, mk.size), mat);
      plane.matrixAutoUpdate = false;
      const m = new THREE.Matrix4().set(...mk.T);
      m.multiply(new THREE.Matrix4().makeTranslation(0, 0, 0.001));  // just off the face
      plane.matrix.copy(m);
      worldGroup.add(plane);
    }
    for (const c of world.cameras) {
      const cam = new THREE.Mesh(new THREE.BoxGeometry(0.12, 0.08, 0.08), new THREE.MeshStandardMaterial({ color: 0x222222 }));
      cam.matrixAutoUpdate = false;
      cam.matrix.set(...c.T);
      worldGroup.add(cam);
    }
  }

  function odomGroup(topic) {
    let g = odomGroups.get(topic);
    if (!g) {
      const group = new THREE.Group();
      group.matrixAutoUpdate = false;
      scene.add(group);
      g = { group, arrows: [], frame: "odom" };
      odomGroups.set(topic, g);
    }
    return g;
  }

  function placeOdometry() {
    for (const [topic, g] of odomGroups) {
      const m = framePose.get(g.frame);
      const key = topic === (hello && hello.ground_truth_topic) ? "truth" : topic;
      g.group.visible = Boolean(m) && vis[key] !== false;
      if (m) { g.group.matrix.copy(m); g.group.matrixWorldNeedsUpdate = true; }
    }
  }

  const xAxis = new THREE.Vector3();
  function setOdometry(displays, helloMsg) {
    hello = helloMsg;
    for (const [topic, d] of Object.entries(displays)) {
      const g = odomGroup(topic);
      g.frame = d.frame || "odom";
      const truth = topic === (hello && hello.ground_truth_topic);
      const color = truth ? ODOM_COLORS.truth : (ODOM_COLORS[topic] || 0xffaa00);
      while (g.arrows.length < d.trail.length) {
        const arrow = new THREE.ArrowHelper(new THREE.Vector3(1, 0, 0), new THREE.Vector3(), 0.1, color, 0.04, 0.025);
        g.group.add(arrow);
        g.arrows.push(arrow);
      }
      g.arrows.forEach((arrow, i) => {
        const p = d.trail[i];
        arrow.visible = Boolean(p);
        if (!p) return;
        arrow.position.set(p[0], p[1], p[2] + (truth ? 0.004 : 0.002));
        xAxis.set(1, 0, 0).applyQuaternion(new THREE.Quaternion(p[3], p[4], p[5], p[6]));
        arrow.setDirection(xAxis);
        const len = arrowLength(p[7]);
        arrow.setLength(len, Math.min(0.04, 0.5 * len), Math.min(0.025, 0.35 * len));
      });
    }
    placeOdometry();
  }

  function resetTrails() {
    for (const g of odomGroups.values()) {
      for (const a of g.arrows) a.visible = false;
    }
  }

  function setVisibility(v) {
    vis = v;
    grid.visible = v.grid !== false;
    detectionRoot.visible = v.detections !== false;
    placeGoal();
    links.visible = v.tf !== false;
    for (const [name, obj] of frameObjects) {
      obj.group.visible = obj.ok && v.tf !== false && !tfOptions.hidden.has(name);
    }
    controlsMoved = true;
  }

  function resize() {
    const w = container.clientWidth || 640;
    const h = container.clientHeight || 480;
    const size = renderer.getSize(new THREE.Vector2());
    if (size.x !== w || size.y !== h) {
      renderer.setSize(w, h, false);
      camera.aspect = w / h;
      camera.updateProjectionMatrix();
      controlsMoved = true;
    }
  }
  new ResizeObserver(resize).observe(container);
  resize();

  return {
    kind: "webgl",
    canvas,
    three: THREE,
    camera,
    displayRoot,
    // T_fixed_frame of a frame at the latest time (the frame's Matrix4, do not modify), or null.
    framePose: (name) => framePose.get(name) || null,
    setFrames,
    setWorld,
    setOdometry,
    resetTrails,
    setVisibility,
    setGoal,
    setDraft,
    pickGround,
    projectPoint,
    setControlsEnabled(on) { controls.enabled = on; },
    setTfOptions,
    // The view (camera position and orbit target in the Fixed Frame, m) for saved configs.
    getView: () => ({ camera: camera.position.toArray(), target: controls.target.toArray() }),
    setView(v) {
      const ok = (a) => Array.isArray(a) && a.length === 3 && a.every(Number.isFinite);
      if (!v || !ok(v.camera) || !ok(v.target)) return false;
      camera.position.fromArray(v.camera);
      controls.target.fromArray(v.target);
      controls.update();
      controlsMoved = true;
      return true;
    },
    // The highlighted detections: frame -> marker size (m).
    detections: () => Object.fromEntries([...detections].map(([n, g]) => [n, {
      size: g.userData.size, visible: detectionRoot.visible,
      position: new THREE.Vector3().setFromMatrixPosition(g.matrix).toArray().map((v) => Math.round(v * 1000) / 1000),
      normal: new THREE.Vector3(0, 0, 1).transformDirection(g.matrix).toArray().map((v) => Math.round(v * 1000) / 1000) }])),
    labelState: () => ({ hidden: labelsHidden,
      shown: [...document.querySelectorAll("#tf-labels .tf-label:not([hidden])")].map((e) => e.dataset.frame),
      frames: [...frameObjects].filter(([, o]) => o.group.visible).map(([n]) => n) }),
    needsRender: () => controlsMoved,
    render() {
      controlsMoved = false;
      resize();
      // Re-apply the TF visibility toggle (setFrames sets group visibility per message).
      renderer.render(scene, camera);
      updateLabels();
    },
  };
}
