// Camera maths for moving through a room: orbit about a picked point, pan, dolly toward a point
// without passing it, mouse look and fly steps. Pure functions of a view, the camera message's
// form {position, target, up, fov_y_deg}; `target` only gives the view direction (and the
// distance the camera message carries), so moves keep the target's offset from the camera.

const WORLD_UP = [0, 1, 0];
const MAX_PITCH = (89 * Math.PI) / 180; // keeps the view off straight up or down (up must differ)
// A full pane width of drag turns the view half way round: a room can be looked over in one drag,
// and a small drag is a small turn.
export const ORBIT_RADIANS_PER_PANE = Math.PI;
// Mouse look turns less: a full pane width is a quarter turn.
export const LOOK_RADIANS_PER_PANE = Math.PI / 2;
// One wheel notch moves this share of the way to the point under the cursor.
export const DOLLY_STEP = 0.2;
export const WHEEL_NOTCH_PX = 100;

export const sub = (a, b) => [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
export const add = (a, b) => [a[0] + b[0], a[1] + b[1], a[2] + b[2]];
export const scale = (a, s) => [a[0] * s, a[1] * s, a[2] * s];
export const dot = (a, b) => a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
export const length = (a) => Math.hypot(a[0], a[1], a[2]);
export const normalize = (a) => scale(a, 1 / (length(a) || 1));
export const cross = (a, b) => [
  a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]];

// v rotated by `angle` radians about the unit `axis` (Rodrigues).
function rotate(v, axis, angle) {
  const c = Math.cos(angle), s = Math.sin(angle);
  return add(add(scale(v, c), scale(cross(axis, v), s)), scale(axis, dot(axis, v) * (1 - c)));
}

export function forwardOf(view) {
  return normalize(sub(view.target, view.position));
}

// The scene's size (the diagonal of its bounds, metres): what fly speed and dolly stops scale with.
export function sceneSize(bounds) {
  return bounds ? Math.max(1e-3, length(sub(bounds.max, bounds.min))) : 10;
}

// The closest a dolly comes to the surface it moves toward: a little short of it, so that the
// surface stays in front of the camera (and its near plane).
export function dollyStandoff(bounds) {
  return Math.max(0.05, sceneSize(bounds) * 0.005);
}

// Metres per second in fly mode: a room's width in a few seconds; Shift is `FLY_FAST` times.
export function flySpeed(bounds, fast = false) {
  return (sceneSize(bounds) / 8) * (fast ? FLY_FAST : 1);
}
export const FLY_FAST = 4;

// The view turned about `pivot` by a drag of (dxPx, dyPx) in a pane `widthPx` wide: the camera
// and its target swing round the pivot together, so the pivot stays where it is on screen and
// its distance to the camera does not change. Dragging right turns the scene to the right, down
// raises the camera above the pivot. The pitch stops short of straight up or down.
export function orbitAbout(view, pivot, dxPx, dyPx, widthPx) {
  const radiansPerPx = ORBIT_RADIANS_PER_PANE / Math.max(1, widthPx);
  return turnAbout(view, pivot, -dxPx * radiansPerPx, -dyPx * radiansPerPx);
}

// The view turned in place (mouse look): as orbiting about the camera itself.
export function look(view, dxPx, dyPx, widthPx) {
  const radiansPerPx = LOOK_RADIANS_PER_PANE / Math.max(1, widthPx);
  return turnAbout(view, view.position, -dxPx * radiansPerPx, -dyPx * radiansPerPx);
}

// Yaw about the world's up axis through `pivot`, then pitch (the view direction's elevation
// changes by `pitch`, clamped) about the camera's horizontal right axis through it.
function turnAbout(view, pivot, yaw, pitch) {
  const around = (point, axis, angle) => add(pivot, rotate(sub(point, pivot), axis, angle));
  let position = around(view.position, WORLD_UP, yaw);
  let target = around(view.target, WORLD_UP, yaw);
  const forward = normalize(sub(target, position));
  const elevation = Math.asin(Math.max(-1, Math.min(1, forward[1])));
  const turn = Math.max(-MAX_PITCH, Math.min(MAX_PITCH, elevation + pitch)) - elevation;
  const right = cross(forward, WORLD_UP);
  if (length(right) > 1e-9 && turn !== 0) {
    const axis = normalize(right);
    position = around(position, axis, turn);
    target = around(target, axis, turn);
  }
  return { ...view, position, target, up: WORLD_UP };
}

// Moves camera and target together so that the point under the cursor follows it; `distance` is
// the depth of what is being dragged (the pivot's), which moves with the cursor exactly.
export function pan(view, dxPx, dyPx, viewportHeightPx, distance = length(sub(view.target, view.position))) {
  const forward = forwardOf(view);
  const right = normalize(cross(forward, view.up));
  const up = normalize(cross(right, forward));
  const metresPerPx = (2 * distance * Math.tan((view.fov_y_deg * Math.PI) / 360)) / viewportHeightPx;
  const move = add(scale(right, -dxPx * metresPerPx), scale(up, dyPx * metresPerPx));
  return { ...view, position: add(view.position, move), target: add(view.target, move) };
}

// `notches` wheel notches toward `point` (negative: away from it): each covers DOLLY_STEP of the
// distance left, so steps shrink near a surface, and the camera stops `standoff` short of the
// point, never passing it. The view direction is kept: the point stays under the cursor.
export function dollyToward(view, point, notches, standoff) {
  const offset = sub(point, view.position);
  const distance = length(offset);
  if (distance === 0) return view;
  let wanted = distance * (1 - DOLLY_STEP) ** notches;
  if (notches > 0) wanted = Math.min(distance, Math.max(standoff, wanted));
  const move = scale(offset, (distance - wanted) / distance);
  return { ...view, position: add(view.position, move), target: add(view.target, move) };
}

// The unit ray from the camera through a point of the image given as fractions ({u, v}, from the
// top left) of an image of this aspect (width over height).
export function rayThrough(view, { u, v }, aspect) {
  const forward = forwardOf(view);
  const right = normalize(cross(forward, view.up));
  const up = cross(right, forward);
  const tanY = Math.tan((view.fov_y_deg * Math.PI) / 360);
  const x = (2 * u - 1) * tanY * aspect;
  const y = (1 - 2 * v) * tanY;
  return normalize(add(forward, add(scale(right, x), scale(up, y))));
}

// One fly step of `seconds` at `speed` m/s: `move` is {forward, right, up}, each -1, 0 or 1 (held
// keys). Forward follows the view direction (looking down and flying forward descends); up is
// the world's.
export function flyStep(view, move, seconds, speed) {
  const forward = forwardOf(view);
  const right = normalize(cross(forward, WORLD_UP));
  let direction = add(add(scale(forward, move.forward), scale(right, move.right)), scale(WORLD_UP, move.up));
  if (length(direction) === 0) return view;
  direction = scale(normalize(direction), speed * seconds);
  return { ...view, position: add(view.position, direction), target: add(view.target, direction) };
}
