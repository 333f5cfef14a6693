// Image (RViz2's Image display / rqt_image_view): the newest frame of a sensor_msgs/Image
// topic in a panel of its own (JPEG from the server's image path, newest only).
import { newestImageLoader } from "../image_loader.js";

export default {
  name: "Image",
  types: ["sensor_msgs/msg/Image"],
  messages: false,
  needs3d: false,
  options: {
    width: { type: "number", default: 100, min: 10, max: 100, step: 10, label: "Width %" },
  },
  create(ctx, topic, options) {
    const body = ctx.panel(`Image ${topic}`);
    const img = document.createElement("img");
    img.alt = "no image yet";
    img.className = "display-image";
    const info = document.createElement("span");
    info.className = "image-info";
    info.textContent = "waiting for an image…";
    body.append(img, info);
    let frames = 0, width = 0, height = 0;  // of the frame last shown (stable while the next loads)
    const size = (o) => { img.style.width = `${o.width}%`; };
    size(options);
    const loader = newestImageLoader(img, (header) => {
      frames += 1;
      width = img.naturalWidth;
      height = img.naturalHeight;
      info.textContent = `${header.width}×${header.height} ${header.encoding}  stamp ${header.stamp.toFixed(3)} s`;
    });
    ctx.watchImage(topic, (blob, header) => loader.show(blob, header));
    return {
      update() {},
      setOptions: size,
      dispose() { loader.dispose(); },
      info: () => ({ frames, width, height }),
    };
  },
};
