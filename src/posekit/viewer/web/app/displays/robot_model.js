// RobotModel (RViz2's RobotModel display): the URDF published on /robot_description drawn at
// the TF frames of its links: each link's <visual> elements (box, cylinder, sphere; meshes are
// not loaded and counted in the status), placed by their <origin xyz rpy> (fixed-axis roll,
// pitch, yaw) and coloured by their <material> (inline or named at the top level), else grey.
// "Hidden Links" (comma-separated link names) are not drawn.

const num = (s, d = 0) => { const v = Number.parseFloat(s); return Number.isFinite(v) ? v : d; };
const nums = (s, n, d = 0) => {
  const parts = String(s || "").trim().split(/\s+/).filter(Boolean).map((x) => num(x, d));
  while (parts.length < n) parts.push(d);
  return parts.slice(0, n);
};

// {links: [{name, visuals: [{geometry: {kind, size|radius|length|filename}, xyz, rpy, rgba}]}]}
export function parseUrdf(text) {
  const doc = new DOMParser().parseFromString(text, "application/xml");
  if (doc.getElementsByTagName("parsererror").length) throw new Error("the robot description is not valid XML");
  const robot = doc.documentElement;
  if (!robot || robot.tagName !== "robot") throw new Error("the robot description has no <robot> element");
  const named = {};
  for (const m of robot.children) {
    if (m.tagName !== "material") continue;
    const c = m.getElementsByTagName("color")[0];
    if (c && m.getAttribute("name")) named[m.getAttribute("name")] = nums(c.getAttribute("rgba"), 4, 1);
  }
  const links = [];
  for (const link of robot.children) {
    if (link.tagName !== "link") continue;
    const visuals = [];
    for (const v of link.children) {
      if (v.tagName !== "visual") continue;
      const origin = v.getElementsByTagName("origin")[0];
      const g = v.getElementsByTagName("geometry")[0];
      const shape = g ? [...g.children][0] : null;
      if (!shape) continue;
      const geometry = { kind: shape.tagName };
      if (shape.tagName === "box") geometry.size = nums(shape.getAttribute("size"), 3);
      else if (shape.tagName === "cylinder") { geometry.radius = num(shape.getAttribute("radius")); geometry.length = num(shape.getAttribute("length")); }
      else if (shape.tagName === "sphere") geometry.radius = num(shape.getAttribute("radius"));
      else if (shape.tagName === "mesh") geometry.filename = shape.getAttribute("filename") || "";
      const mat = v.getElementsByTagName("material")[0];
      let rgba = null;
      if (mat) {
        const c = mat.getElementsByTagName("color")[0];
        rgba = c ? nums(c.getAttribute("rgba"), 4, 1) : named[mat.getAttribute("name")] || null;
      }
      visuals.push({
        geometry,
        xyz: nums(origin && origin.getAttribute("xyz"), 3),
        rpy: nums(origin && origin.getAttribute("rpy"), 3),
        rgba,
      });
    }
    links.push({ name: link.getAttribute("name") || "", visuals });
  }
  return { name: robot.getAttribute("name") || "", links };
}

export default {
  name: "RobotModel",
  types: ["std_msgs/msg/String"],
  options: {
    visual_enabled: { type: "bool", default: true, label: "Visual Enabled" },
    alpha: { type: "number", default: 1, min: 0, max: 1, step: 0.1, label: "Alpha" },
    default_color: { type: "color", default: "#b3b3b3", label: "Default Color" },
    hidden_links: { type: "string", default: "", label: "Hidden Links" },
  },
  create(ctx, topic, options) {
    const { THREE } = ctx;
    let o = options, model = null;
    const groups = [];        // {group, link}
    const clear = () => {
      for (const { group } of groups) {
        ctx.detach(group);
        group.traverse((x) => { if (x.geometry) x.geometry.dispose(); if (x.material) x.material.dispose(); });
        group.removeFromParent();
      }
      groups.length = 0;
    };
    const build = () => {
      clear();
      if (!model) return;
      const hidden = new Set(o.hidden_links.split(",").map((s) => s.trim()).filter(Boolean));
      let meshes = 0, drawn = 0, missing = 0;
      for (const link of model.links) {
        if (!link.visuals.length || hidden.has(link.name)) continue;
        const group = new THREE.Group();
        group.name = `link:${link.name}`;
        for (const v of link.visuals) {
          let geom = null;
          const g = v.geometry;
          if (g.kind === "box") geom = new THREE.BoxGeometry(g.size[0], g.size[1], g.size[2]);
          else if (g.kind === "cylinder") { geom = new THREE.CylinderGeometry(g.radius, g.radius, g.length, 24); geom.rotateX(Math.PI / 2); }
          else if (g.kind === "sphere") geom = new THREE.SphereGeometry(g.radius, 24, 16);
          else { meshes += 1; continue; }
          const [r, gg, b, a] = v.rgba || [...new THREE.Color(o.default_color).toArray(), 1];
          const alpha = a * o.alpha;
          const mat = new THREE.MeshStandardMaterial({ color: new THREE.Color(r, gg, b), roughness: 0.7, transparent: alpha < 1, opacity: alpha });
          const mesh = new THREE.Mesh(geom, mat);
          mesh.position.set(v.xyz[0], v.xyz[1], v.xyz[2]);
          mesh.rotation.set(v.rpy[0], v.rpy[1], v.rpy[2], "ZYX");  // R = Rz(yaw) Ry(pitch) Rx(roll)
          group.add(mesh);
          drawn += 1;
        }
        group.userData.wantVisible = o.visual_enabled;  // the frame placement keeps it hidden
        ctx.root.add(group);
        if (!ctx.attach(group, link.name)) missing += 1;
        groups.push({ group, link: link.name });
      }
      const parts = [`${drawn} visuals of ${model.links.length} links`];
      if (meshes) parts.push(`${meshes} meshes not drawn`);
      if (missing) parts.push(`${missing} links without a transform`);
      ctx.setStatus(missing || meshes ? "warn" : "ok", parts.join(", "));
    };
    ctx.onFrames(() => {
      if (!model) return;
      const missing = groups.filter(({ link }) => !ctx.lookup(link)).length;
      ctx.setStatus(missing ? "warn" : "ok", missing
        ? `${missing} of ${groups.length} links without a transform`
        : `${groups.length} links drawn`);
    });
    return {
      update(msg) {
        const text = msg && typeof msg.data === "string" ? msg.data : "";
        model = parseUrdf(text);
        build();
      },
      setOptions(next) { o = next; build(); },
      dispose() { clear(); },
      info() {
        return model ? { robot: model.name, links: groups.map((g) => g.link),
                         placed: groups.filter((g) => Boolean(ctx.lookup(g.link))).map((g) => g.link) } : null;
      },
    };
  },
};
