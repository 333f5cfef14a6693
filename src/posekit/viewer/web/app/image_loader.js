// Shows a stream of JPEG blobs in an <img>, newest only, without ever aborting a load.
//
// Setting img.src while the previous source is still loading aborts that load: a stream
// that arrives faster than the browser decodes (a busy machine, a large image) would then
// never show a frame, and each aborted blob URL would leak. Here a blob that arrives while
// one is loading waits (replacing any older waiting one) and is shown when the load ends.
//
// newestImageLoader(img, onShown) returns show(blob, meta) and dispose();
// onShown(meta) runs once the blob given with meta is on screen (img.naturalWidth etc. are
// its size). A blob that fails to decode is skipped (the waiting one, if any, goes next).
export function newestImageLoader(img, onShown = () => {}) {
  let shownUrl = null;    // the URL on screen now (revoked when the next one is shown)
  let loading = null;     // {url, meta} being loaded
  let waiting = null;     // {blob, meta}: the newest that arrived during the load
  let disposed = false;

  const start = (item) => {
    loading = { url: URL.createObjectURL(item.blob), meta: item.meta };
    img.src = loading.url;
  };
  const next = () => {
    loading = null;
    if (waiting && !disposed) {
      const item = waiting;
      waiting = null;
      start(item);
    }
  };
  img.onload = () => {
    if (!loading) return;
    if (shownUrl) URL.revokeObjectURL(shownUrl);
    shownUrl = loading.url;
    onShown(loading.meta);  // img still holds this image (its size, pixels for a texture)
    next();
  };
  img.onerror = () => {
    if (!loading) return;
    URL.revokeObjectURL(loading.url);
    next();
  };
  return {
    show(blob, meta) {
      if (disposed) return;
      if (loading) waiting = { blob, meta };
      else start({ blob, meta });
    },
    dispose() {
      disposed = true;
      waiting = null;
      if (shownUrl) URL.revokeObjectURL(shownUrl);
      if (loading) URL.revokeObjectURL(loading.url);
      shownUrl = loading = null;
    },
  };
}
