// Camera: a camera in the 3D scene from its sensor_msgs/CameraInfo — the viewing frustum
// (pinhole K, width, height) out to the far plane, in the info's header frame (an optical
// frame: z forward, x right, y down), with the camera's newest image textured on that
// plane. The image topic is the option's, else paired automatically (pairImageTopic).
import { newestImageLoader } from "../image_loader.js";
import { disposeTree } from "./_util.js";

const IMAGE_TYPE = "sensor_msgs/msg/Image";
const PREFERRED = ["image_raw", "image_rect_color", "image_color", "image_rect", "color", "image"];
const notForDisplay = (name) => /depth|disparity|aruco_detection|debug/.test(name);

// The image topic of a camera_info topic: one in the same namespace (image_raw first), else
// the colour image sharing the longest namespace prefix with it (depth and debug images
// left out); null when none. topics: [{name, type}].
export function pairImageTopic(infoTopic, topics) {
  const images = topics.filter((t) => t.type === IMAGE_TYPE && !notForDisplay(t.name)).map((t) => t.name);
  const parts = infoTopic.split("/").filter(Boolean);
  const ns = `/${parts.slice(0, -1).join("/")}`;
  const local = images.filter((n) => n.slice(0, n.lastIndexOf("/")) === (ns === "/" ? "" : ns));
  if (local.length) {
    return local.sort((a, b) => rank(a) - rank(b) || (a < b ? -1 : 1))[0];
  }
  let best = null, bestShared = 0;
  for (const n of images.sort()) {
    const p = n.split("/").filter(Boolean);
    let shared = 0;
    while (shared < Math.min(p.length - 1, parts.length - 1) && p[shared] === parts[shared]) shared += 1;
    if (shared > bestShared) { best = n; bestShared = shared; }
  }
  return best;
}

function rank(name) {
  const i = PREFERRED.indexOf(name.slice(name.lastIndexOf("/") + 1));
  return i < 0 ? PREFERRED.length : i;
}

// The far-plane corners (optical frame, m) of pixels (0,0), (w,0), (w,h), (0,h) at distance d.
export function frustumCorners(info, d) {
  const k = info.k || info.K;
  const fx = k[0], cx = k[2], fy = k[4], cy = k[5];
  const w = info.width, h = info.height;
  return [[0, 0], [w, 0], [w, h], [0, h]].map(([u, v]) => [((u - cx) / fx) * d, ((v - cy) / fy) * d, d]);
}

export default {
  name: "Camera",
  types: ["sensor_msgs/msg/CameraInfo"],
  options: {
    image_topic: { type: "string", default: "", label: "Image Topic (empty: paired)" },
    far_plane: { type: "number", default: 1, min: 0.05, max: 100, step: 0.1, label: "Far Plane (m)" },
    color: { type: "color", default: "#ffcc00", label: "Frustum Color" },
    image_alpha: { type: "number", default: 1, min: 0, max: 1, step: 0.1, label: "Image Alpha" },
    show_image: { type: "bool", default: true, label: "Show Image" },
  },
  create(ctx, topic, options) {
    const { THREE } = ctx;
    const frameGroup = new THREE.Group();
    ctx.root.add(frameGroup);
    let o = options, info = null, frame = null, corners = null;
    let imageTopic = null, unwatch = null, frames = 0, imageSize = null;
    const img = new Image();
    const texture = new THREE.Texture(img);
    texture.colorSpace = THREE.SRGBColorSpace;
    const loader = newestImageLoader(img, () => {
      texture.needsUpdate = true;
      frames += 1;
      imageSize = [img.naturalWidth, img.naturalHeight];
      planeMaterial.map = texture;
      planeMaterial.color.set(0xffffff);
      planeMaterial.needsUpdate = true;
      plane.visible = o.show_image;
      ctx.requestRender();
    });
    const planeMaterial = new THREE.MeshBasicMaterial({ color: 0x202020, side: THREE.DoubleSide, transparent: true, opacity: o.image_alpha });
    const plane = new THREE.Mesh(new THREE.BufferGeometry(), planeMaterial);
    plane.visible = false;
    const lines = new THREE.LineSegments(new THREE.BufferGeometry(), new THREE.LineBasicMaterial({ color: o.color }));
    frameGroup.add(plane, lines);

    const draw = () => {
      if (!info) return;
      corners = frustumCorners(info, o.far_plane);
      const c = corners;
      const seg = [];
      for (let i = 0; i < 4; i += 1) seg.push([0, 0, 0], c[i], c[i], c[(i + 1) % 4]);
      lines.geometry.dispose();
      lines.geometry = new THREE.BufferGeometry();
      lines.geometry.setAttribute("position", new THREE.Float32BufferAttribute(seg.flat(), 3));
      lines.material.color.set(o.color);
      const g = new THREE.BufferGeometry();
      g.setAttribute("position", new THREE.Float32BufferAttribute(c.flat(), 3));
      // Pixel (0,0) is the image's top-left: texture v = 1 (three.js flips images on upload).
      g.setAttribute("uv", new THREE.Float32BufferAttribute([0, 1, 1, 1, 1, 0, 0, 0], 2));
      g.setIndex([0, 3, 1, 1, 3, 2]);
      plane.geometry.dispose();
      plane.geometry = g;
      planeMaterial.opacity = o.image_alpha;
      planeMaterial.transparent = o.image_alpha < 1;
      plane.visible = o.show_image && frames > 0;
    };

    const watch = () => {
      const wanted = o.image_topic || pairImageTopic(topic, ctx.topics());
      if (wanted === imageTopic) return;
      if (unwatch) unwatch();
      unwatch = null;
      imageTopic = wanted;
      if (!wanted) return;
      unwatch = ctx.watchImage(wanted, (blob) => loader.show(blob));
    };
    watch();
    const pairing = setInterval(() => { if (!imageTopic) watch(); }, 1000);

    return {
      update(msg) {
        const k = msg.k || [];
        if (!(k[0] > 0 && k[4] > 0 && msg.width > 0 && msg.height > 0)) {
          ctx.setStatus("error", "camera_info without intrinsics (K) or size");
          return;
        }
        const changed = !info || msg.width !== info.width || msg.height !== info.height || k.some((v, i) => v !== info.k[i]);
        info = { k: [...k], width: msg.width, height: msg.height };
        frame = msg.header.frame_id;
        const placed = ctx.attach(frameGroup, frame);
        if (changed) draw();
        ctx.setStatus(placed ? "ok" : "warn", placed ? (imageTopic || "no image topic") : `no transform from [${frame}]`);
      },
      setOptions(next) { o = next; watch(); draw(); },
      dispose() {
        clearInterval(pairing);
        loader.dispose();
        texture.dispose();
        disposeTree(frameGroup);
      },
      info: () => ({ frame, corners, image_topic: imageTopic, image_frames: frames, image_size: imageSize, image_shown: plane.visible }),
    };
  },
};
