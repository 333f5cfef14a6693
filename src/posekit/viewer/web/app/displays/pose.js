// PoseStamped (RViz2's Pose display): the newest pose as an arrow or axes in its header frame.
import { ARROW_OPTIONS, disposeTree, makePoseShape, poseFinite, poseMatrix } from "./_util.js";

export default {
  name: "Pose",
  types: ["geometry_msgs/msg/PoseStamped"],
  options: ARROW_OPTIONS,
  create(ctx, topic, options) {
    const { THREE } = ctx;
    const frameGroup = new THREE.Group();
    ctx.root.add(frameGroup);
    const holder = new THREE.Group();
    holder.matrixAutoUpdate = false;
    frameGroup.add(holder);
    let o = options, last = null;
    const rebuild = () => { disposeTree(holder); holder.add(makePoseShape(THREE, o)); };
    rebuild();
    holder.visible = false;
    return {
      update(msg) {
        if (!poseFinite(msg.pose)) { ctx.setStatus("warn", "non-finite pose"); return; }
        last = { frame: msg.header.frame_id, pose: msg.pose };
        poseMatrix(THREE, msg.pose, holder.matrix);
        holder.matrixWorldNeedsUpdate = true;
        holder.visible = true;
        const placed = ctx.attach(frameGroup, msg.header.frame_id);
        ctx.setStatus(placed ? "ok" : "warn", placed ? "" : `no transform from [${msg.header.frame_id}]`);
      },
      setOptions(next) { o = next; rebuild(); },
      dispose() { disposeTree(frameGroup); },
      info: () => last,
    };
  },
};
