// Orbit, pan and dolly about the camera's target, with mouse, wheel and touch.
// A view is the camera message's form: {position, target, up, fov_y_deg}.

const WORLD_UP = [0, 1, 0];
const MAX_PITCH = (89 * Math.PI) / 180; // keeps `up` off the view direction
const ORBIT_RADIANS_PER_PX = 0.006;
const CLICK_SLOP_PX = 4;

const sub = (a, b) => [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
const add = (a, b) => [a[0] + b[0], a[1] + b[1], a[2] + b[2]];
const scale = (a, s) => [a[0] * s, a[1] * s, a[2] * s];
const length = (a) => Math.hypot(a[0], a[1], a[2]);
const normalize = (a) => scale(a, 1 / (length(a) || 1));
const cross = (a, b) => [
  a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]];

// Distances the dolly keeps to, from the scene's bounds.
export function dollyRange(bounds) {
  const size = bounds ? length(sub(bounds.max, bounds.min)) : 10;
  return { min: Math.max(1e-3, size * 1e-3), max: Math.max(1, size * 5) };
}

export function orbit(view, dxPx, dyPx) {
  const offset = sub(view.position, view.target);
  const distance = length(offset);
  const yaw = Math.atan2(offset[0], offset[2]) - dxPx * ORBIT_RADIANS_PER_PX;
  const pitch = Math.max(-MAX_PITCH, Math.min(MAX_PITCH,
    Math.asin(offset[1] / distance) + dyPx * ORBIT_RADIANS_PER_PX));
  const direction = [Math.cos(pitch) * Math.sin(yaw), Math.sin(pitch), Math.cos(pitch) * Math.cos(yaw)];
  return { ...view, position: add(view.target, scale(direction, distance)), up: WORLD_UP };
}

// Moves camera and target together so that the point under the cursor follows it.
export function pan(view, dxPx, dyPx, viewportHeightPx) {
  const forward = sub(view.target, view.position);
  const distance = length(forward);
  const right = normalize(cross(forward, view.up));
  const up = normalize(cross(right, forward));
  const metresPerPx = (2 * distance * Math.tan((view.fov_y_deg * Math.PI) / 360)) / viewportHeightPx;
  const move = add(scale(right, -dxPx * metresPerPx), scale(up, dyPx * metresPerPx));
  return { ...view, position: add(view.position, move), target: add(view.target, move) };
}

// factor < 1 moves closer to the target.
export function dolly(view, factor, range) {
  const offset = sub(view.position, view.target);
  const distance = Math.max(range.min, Math.min(range.max, length(offset) * factor));
  return { ...view, position: add(view.target, scale(normalize(offset), distance)) };
}

// Pointer input on an element: drag orbits; right/middle/shift drag pans; wheel and pinch dolly;
// a two-finger drag pans; a click (no drag) calls onClick(event).
export class CameraControls {
  // getView(), setView(view), getRange(), onClick(pointerEvent)
  constructor(element, { getView, setView, getRange, onClick }) {
    this.element = element;
    this.callbacks = { getView, setView, getRange, onClick };
    this.pointers = new Map(); // pointerId -> {x, y}
    this.gesture = null; // {kind, travel, button, shift}
    element.addEventListener('pointerdown', (e) => this.down(e));
    element.addEventListener('pointermove', (e) => this.move(e));
    element.addEventListener('pointerup', (e) => this.up(e));
    element.addEventListener('pointercancel', (e) => this.up(e, true));
    element.addEventListener('wheel', (e) => this.wheel(e), { passive: false });
    element.addEventListener('contextmenu', (e) => e.preventDefault());
  }

  down(event) {
    this.element.setPointerCapture(event.pointerId);
    this.pointers.set(event.pointerId, { x: event.clientX, y: event.clientY });
    const panning = event.button === 1 || event.button === 2 || event.shiftKey;
    if (this.pointers.size === 1) this.gesture = { kind: panning ? 'pan' : 'orbit', travel: 0, button: event.button };
    else this.gesture = { kind: 'pinch', travel: Infinity }; // never a click
    event.preventDefault();
  }

  move(event) {
    const last = this.pointers.get(event.pointerId);
    if (!last || !this.gesture) return;
    const before = this.centroid();
    const spreadBefore = this.spread();
    last.x = event.clientX;
    last.y = event.clientY;
    const after = this.centroid();
    const dx = after.x - before.x;
    const dy = after.y - before.y;
    this.gesture.travel += Math.hypot(dx, dy);
    if (this.gesture.travel < CLICK_SLOP_PX) return;
    const { getView, setView, getRange } = this.callbacks;
    let view = getView();
    if (!view) return;
    const height = this.element.getBoundingClientRect().height || 1;
    if (this.gesture.kind === 'orbit') view = orbit(view, dx, dy);
    else view = pan(view, dx, dy, height);
    if (this.gesture.kind === 'pinch' && spreadBefore > 0)
      view = dolly(view, spreadBefore / Math.max(1, this.spread()), getRange());
    setView(view);
  }

  up(event, cancelled = false) {
    if (!this.pointers.delete(event.pointerId)) return;
    const gesture = this.gesture;
    if (this.pointers.size === 0) this.gesture = null;
    if (!cancelled && gesture && gesture.kind === 'orbit' && gesture.button === 0 &&
        gesture.travel < CLICK_SLOP_PX)
      this.callbacks.onClick(event);
  }

  wheel(event) {
    event.preventDefault();
    const view = this.callbacks.getView();
    if (!view) return;
    const pixels = event.deltaMode === WheelEvent.DOM_DELTA_LINE ? event.deltaY * 16 : event.deltaY;
    this.callbacks.setView(dolly(view, Math.exp(pixels * 0.001), this.callbacks.getRange()));
  }

  centroid() {
    let x = 0, y = 0;
    for (const p of this.pointers.values()) { x += p.x; y += p.y; }
    return { x: x / this.pointers.size, y: y / this.pointers.size };
  }

  spread() {
    if (this.pointers.size < 2) return 0;
    const c = this.centroid();
    let sum = 0;
    for (const p of this.pointers.values()) sum += Math.hypot(p.x - c.x, p.y - c.y);
    return sum / this.pointers.size;
  }
}
