// Pointer, wheel and key input that moves the camera through a room (the maths is camera.js):
// a drag orbits about the surface under the cursor where it starts (asked of the daemon with
// `pick`), or about the focus point when there is none, with a marker on the pivot; right,
// middle or shift drag pans; the wheel dollies toward the surface under the cursor and stops
// short of it; in fly mode a drag looks around and W A S D (Q, E down and up; Shift faster)
// fly. A click (no drag) calls onClick.

import {
  dollyStandoff, dollyToward, flySpeed, flyStep, forwardOf, add, look, orbitAbout, pan, rayThrough,
  scale, sceneSize, WHEEL_NOTCH_PX, DOLLY_STEP,
} from './camera.js';

const CLICK_SLOP_PX = 4;
// A pick that has not come back by then is given up: the drag goes on about the focus point.
const PICK_WAIT_MS = 600;
// Wheel notches this close in time and place dolly toward the same point.
const WHEEL_GESTURE_MS = 500;

export class CameraControls {
  // element: the canvas; marker: the pivot marker element (positioned in the canvas's parent).
  // options: getView(), setView(view), pick({u, v}) -> Promise<{point, depth} | null>,
  // imagePoint(event) -> {u, v} | null, aspect(), bounds(), focusDistance(), flying(),
  // onMoveStart() (a move begins: the view before it goes to the undo history), onClick(event).
  constructor(element, marker, options) {
    this.element = element;
    this.marker = marker;
    this.options = options;
    this.pointers = new Map(); // pointerId -> {x, y}
    this.gesture = null;
    this.wheelState = null; // {target, x, y, at, notches, busy}
    element.addEventListener('pointerdown', (e) => this.down(e));
    element.addEventListener('pointermove', (e) => this.move(e));
    element.addEventListener('pointerup', (e) => this.up(e));
    element.addEventListener('pointercancel', (e) => this.up(e, true));
    element.addEventListener('wheel', (e) => this.wheel(e), { passive: false });
    element.addEventListener('contextmenu', (e) => e.preventDefault());
  }

  // The point the view turns about when nothing is under the cursor: the focus point.
  focusPoint(view) {
    return add(view.position, scale(forwardOf(view), this.options.focusDistance()));
  }

  // What lies under the pointer: {point, depth} from the daemon, or null (the background, no
  // answer in time, outside the image).
  async surfaceUnder(event) {
    const at = this.options.imagePoint(event);
    if (!at) return null;
    const timeout = new Promise((resolve) => setTimeout(() => resolve(null), PICK_WAIT_MS));
    return Promise.race([this.options.pick(at).catch(() => null), timeout]);
  }

  down(event) {
    const view = this.options.getView();
    if (!view) return;
    // Keys go to the page again (undo, fly), not to the control used last.
    if (document.activeElement instanceof HTMLElement) document.activeElement.blur();
    this.element.setPointerCapture(event.pointerId);
    this.pointers.set(event.pointerId, { x: event.clientX, y: event.clientY });
    event.preventDefault();
    if (this.pointers.size > 1) {
      this.gesture = { kind: 'pinch', travel: Infinity, started: true }; // never a click
      this.hideMarker();
      return;
    }
    const panning = event.button === 1 || event.button === 2 || event.shiftKey;
    const kind = this.options.flying() ? 'look' : panning ? 'pan' : 'orbit';
    const gesture = { kind, travel: 0, button: event.button, view, dx: 0, dy: 0, pivot: null, depth: null };
    this.gesture = gesture;
    if (kind === 'look') return;
    const rect = this.element.getBoundingClientRect();
    const at = { x: event.clientX - rect.left, y: event.clientY - rect.top };
    this.surfaceUnder(event).then((surface) => {
      if (this.gesture !== gesture) return;
      if (surface) {
        gesture.pivot = surface.point;
        gesture.depth = surface.depth;
        gesture.markerAt = at;
      } else { // the focus point is on the view axis: the image's centre
        gesture.pivot = this.focusPoint(view);
        gesture.depth = this.options.focusDistance();
        gesture.markerAt = { x: rect.width / 2, y: rect.height / 2 };
      }
      this.apply(gesture);
    });
  }

  move(event) {
    const last = this.pointers.get(event.pointerId);
    const gesture = this.gesture;
    if (!last || !gesture) return;
    const before = this.centroid();
    const spreadBefore = this.spread();
    last.x = event.clientX;
    last.y = event.clientY;
    const after = this.centroid();
    const dx = after.x - before.x, dy = after.y - before.y;
    gesture.travel += Math.hypot(dx, dy);
    gesture.dx += dx;
    gesture.dy += dy;
    if (gesture.travel < CLICK_SLOP_PX) return;
    if (!gesture.started) {
      gesture.started = true;
      this.options.onMoveStart();
    }
    let view = this.options.getView();
    if (!view) return;
    const { width, height } = this.element.getBoundingClientRect();
    if (gesture.kind === 'orbit') return this.apply(gesture);
    if (gesture.kind === 'look') view = look(view, dx, dy, width || 1);
    else view = pan(view, dx, dy, height || 1, gesture.depth ?? undefined);
    if (gesture.kind === 'pinch' && spreadBefore > 0 && this.spread() > 0) {
      const notches = Math.log(this.spread() / spreadBefore) / -Math.log(1 - DOLLY_STEP);
      view = dollyToward(view, this.focusPoint(view), notches, dollyStandoff(this.options.bounds()));
    }
    this.options.setView(view);
  }

  // An orbit is the drag so far applied to the view it started from, once the pivot is known.
  apply(gesture) {
    if (gesture.kind !== 'orbit' || !gesture.pivot || !gesture.started) return;
    this.showMarker(gesture.markerAt);
    const width = this.element.getBoundingClientRect().width || 1;
    this.options.setView(orbitAbout(gesture.view, gesture.pivot, gesture.dx, gesture.dy, width));
  }

  up(event, cancelled = false) {
    if (!this.pointers.delete(event.pointerId)) return;
    const gesture = this.gesture;
    if (this.pointers.size === 0) {
      this.gesture = null;
      this.hideMarker();
    }
    if (!cancelled && gesture && gesture.kind !== 'pinch' && !gesture.started && gesture.button === 0 &&
        !event.shiftKey)
      this.options.onClick(event);
  }

  // Each notch covers a share of the way to the surface under the cursor (picked once for
  // notches close together); toward the background, a point at the focus distance or the
  // scene's size further.
  async wheel(event) {
    event.preventDefault();
    const view = this.options.getView();
    if (!view) return;
    const pixels = event.deltaMode === WheelEvent.DOM_DELTA_LINE ? event.deltaY * 16 : event.deltaY;
    const now = performance.now();
    let state = this.wheelState;
    const near = state && Math.hypot(event.clientX - state.x, event.clientY - state.y) < CLICK_SLOP_PX;
    if (!state || !near || now - state.at > WHEEL_GESTURE_MS) {
      this.options.onMoveStart();
      state = this.wheelState = { target: null, x: event.clientX, y: event.clientY, notches: 0, busy: false };
    }
    state.at = now;
    state.notches += -pixels / WHEEL_NOTCH_PX;
    if (state.busy) return;
    state.busy = true;
    if (!state.target) {
      const surface = await this.surfaceUnder(event);
      const at = this.options.imagePoint(event) ?? { u: 0.5, v: 0.5 };
      const start = this.options.getView();
      const reach = Math.max(this.options.focusDistance(), sceneSize(this.options.bounds()));
      state.target = surface?.point ??
        add(start.position, scale(rayThrough(start, at, this.options.aspect()), reach));
    }
    const notches = state.notches;
    state.notches = 0;
    state.busy = false;
    this.options.setView(dollyToward(this.options.getView(), state.target, notches,
      dollyStandoff(this.options.bounds())));
  }

  showMarker(at) {
    if (!this.marker || !at) return;
    this.marker.style.left = `${at.x}px`;
    this.marker.style.top = `${at.y}px`;
    this.marker.hidden = false;
  }

  hideMarker() {
    if (this.marker) this.marker.hidden = true;
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

const FLY_KEYS = {
  KeyW: ['forward', 1], ArrowUp: ['forward', 1], KeyS: ['forward', -1], ArrowDown: ['forward', -1],
  KeyD: ['right', 1], ArrowRight: ['right', 1], KeyA: ['right', -1], ArrowLeft: ['right', -1],
  KeyE: ['up', 1], KeyQ: ['up', -1],
};
const MAX_STEP_S = 0.1; // a stalled page does not leap

// Fly mode's keys: while some are held, the view moves every animation frame.
export class FlyKeys {
  // options: active() (fly mode is on), getView(), setView(view), bounds(), onMoveStart().
  constructor(target, options) {
    this.options = options;
    this.held = new Set();
    this.fast = false;
    this.last = 0;
    target.addEventListener('keydown', (e) => this.key(e, true));
    target.addEventListener('keyup', (e) => this.key(e, false));
    target.addEventListener('blur', () => this.held.clear());
  }

  key(event, down) {
    this.fast = event.shiftKey;
    if (!(event.code in FLY_KEYS) || !this.options.active() || event.ctrlKey || event.metaKey ||
        event.altKey || isTyping(event.target)) return;
    event.preventDefault();
    if (!down) return void this.held.delete(event.code);
    if (this.held.has(event.code)) return;
    if (this.held.size === 0) {
      this.options.onMoveStart();
      this.last = performance.now();
      requestAnimationFrame((t) => this.step(t));
    }
    this.held.add(event.code);
  }

  step(now) {
    if (this.held.size === 0 || !this.options.active()) return void this.held.clear();
    const seconds = Math.min(MAX_STEP_S, Math.max(0, (now - this.last) / 1000));
    this.last = now;
    const move = { forward: 0, right: 0, up: 0 };
    for (const code of this.held) {
      const [axis, sign] = FLY_KEYS[code];
      move[axis] += sign;
    }
    const view = this.options.getView();
    if (view) this.options.setView(flyStep(view, move, seconds, flySpeed(this.options.bounds(), this.fast)));
    requestAnimationFrame((t) => this.step(t));
  }
}

// Keys typed into a field are the field's (letters pick a select's options too); sliders, boxes
// and buttons leave them to the page.
export function isTyping(element) {
  if (!(element instanceof HTMLElement)) return false;
  if (element.isContentEditable || element.tagName === 'TEXTAREA' || element.tagName === 'SELECT') return true;
  return element.tagName === 'INPUT' && !['range', 'checkbox', 'radio', 'button', 'file'].includes(element.type);
}
