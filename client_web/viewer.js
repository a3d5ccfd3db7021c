// Draws a session's frames on a canvas: decoded off the main thread with createImageBitmap, only
// the newest decoded frame is kept, drawn on the next animation frame, then reported as shown
// (the caller acks it; acks are cumulative, so a frame skipped here is acknowledged too).

export class Viewer {
  // onShown(frame) after the frame is on screen.
  constructor(canvas, onShown) {
    this.canvas = canvas;
    this.context = canvas.getContext('2d', { alpha: false });
    this.onShown = onShown;
    this.epoch = 0;
    this.newest = 0; // the newest frame number decoded or being drawn
    this.pending = null; // {frame, bitmap}
    this.drawScheduled = false;
    this.shown = null; // the frame on the canvas (without its bitmap)
  }

  // A new session: its frame numbers start again from 1.
  reset() {
    this.epoch++;
    this.newest = 0;
    this.pending?.bitmap?.close();
    this.pending = null;
  }

  async push(frame) {
    const epoch = this.epoch;
    let bitmap = null;
    try {
      bitmap = await createImageBitmap(frame.jpeg);
    } catch {
      // An undecodable frame is still acknowledged, or the server would stop sending.
    }
    if (epoch !== this.epoch || frame.frame <= this.newest) {
      bitmap?.close(); // a newer frame overtook this one
      return;
    }
    this.newest = frame.frame;
    this.pending?.bitmap?.close();
    this.pending = { frame, bitmap };
    if (!this.drawScheduled) {
      this.drawScheduled = true;
      requestAnimationFrame(() => this.draw());
    }
  }

  draw() {
    this.drawScheduled = false;
    const pending = this.pending;
    this.pending = null;
    if (!pending) return;
    const { frame, bitmap } = pending;
    if (bitmap) {
      if (this.canvas.width !== bitmap.width || this.canvas.height !== bitmap.height) {
        this.canvas.width = bitmap.width;
        this.canvas.height = bitmap.height;
      }
      this.context.drawImage(bitmap, 0, 0);
      bitmap.close();
    }
    const { jpeg, ...shown } = frame;
    this.shown = shown;
    this.onShown(frame);
  }

  // The point under a pointer event as a fraction of the image shown (object-fit: contain), or
  // null outside it.
  imagePoint(event) {
    const rect = this.canvas.getBoundingClientRect();
    const aspect = this.canvas.width / this.canvas.height;
    let width = rect.width, height = rect.height;
    if (width / height > aspect) width = height * aspect;
    else height = width / aspect;
    const u = (event.clientX - rect.left - (rect.width - width) / 2) / width;
    const v = (event.clientY - rect.top - (rect.height - height) / 2) / height;
    return u >= 0 && u < 1 && v >= 0 && v < 1 ? { u, v } : null;
  }

  // The canvas as a PNG Blob, at the frame's own resolution.
  png() {
    return new Promise((resolve) => this.canvas.toBlob(resolve, 'image/png'));
  }
}
