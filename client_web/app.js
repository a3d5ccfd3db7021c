// The browser client: wires the panes (render sessions), camera controls, lens panel, stats and
// the URL together. The state here is what the user chose; the panes send it to their sessions.

import { CameraControls, dollyRange } from './camera.js';
import { describeLens, LensPanel } from './lens.js';
import { fieldOfViewDeg, focalLengthForVerticalFov, sensorOf } from './optics.js';
import { Pane } from './pane.js';
import * as protocol from './protocol.js';
import { StatsOverlay } from './stats.js';
import { readUrlState, urlWriter } from './url-state.js';

const $ = (selector) => document.querySelector(selector);
const fromUrl = readUrlState();
const state = {
  camera: null, // {position, target, up}; the field of view is the lens's
  lens: null, // {focal_length_mm, f_number, focus_distance, blades, blade_rotation_deg,
  //             sensor_width_mm, sensor_height_mm}
  mode: fromUrl.mode ?? null, // null: the daemon's default, learnt from the first frame
  view: fromUrl.view ?? null, // a debug view of the welcome's; null: the finished image
  compare: fromUrl.compare ?? null, // the split view's second mode, null when not split
  settings: {},
};
let welcome = null;
// The split view's second mode at first, when the daemon has it: the post-process alone, to set
// beside the hybrid.
const COMPARE_MODE = 'postprocess';
let seq = 0;
let lensSeq = 0; // the newest lens or focus_at input: frames before it show an older focus
let stillQuality = 0; // the highest JPEG quality seen: the daemon's still quality
const inputSentAt = new Map(); // seq -> performance.now(), for the input-to-frame latency
const writeUrl = urlWriter();
// The welcome's camera and lens are messages; the state keeps their fields.
const strip = ({ type, seq: _, ...rest }) => rest;
// The main pane's aspect, which with the lens makes the field of view.
const aspect = () => {
  const { width, height } = primary.viewport();
  return width / height;
};
const FOCUS_ZONE_VIEW = 'focus_zone';

const stats = new StatsOverlay($('#stats'));
const lensPanel = new LensPanel($('#lens'), (lens) => {
  state.lens = lens;
  queue('lens');
});
const handlers = {
  onStatus: showStatus,
  onWelcome: welcomed,
  onShown: shown,
  onServerError: (error, pane) => {
    // A rejected message leaves the session live; the status says why.
    if (pane.connection.live) showStatus({ state: 'live', message: error.message }, pane);
  },
  onTokenNeeded: (message) => {
    $('#token-form').hidden = false;
    $('#token-form output').textContent = message;
    $('#token').focus();
  },
};
const primary = new Pane($('#pane-main'), handlers);
const secondary = new Pane($('#pane-compare'), handlers);
const panes = [primary, secondary];

// Sends one input to every active pane with a new seq; returns the seq.
function sendInput(build) {
  const s = ++seq;
  inputSentAt.set(s, performance.now());
  for (const pane of panes) if (pane.active) pane.send(build(s, pane));
  return s;
}

function modeMessage(s, pane) {
  return protocol.mode(s, pane === primary ? state.mode : state.compare, state.view);
}

// Camera and lens changes coalesce to one message per animation frame.
const queued = new Set();
function queue(kind) {
  if (kind === 'camera') $('#cameras').value = ''; // the view is no longer a scene camera's
  if (queued.size === 0) requestAnimationFrame(flush);
  queued.add(kind);
}
function flush() {
  if (queued.has('camera')) sendInput((s) => protocol.camera(s, state.camera));
  if (queued.has('lens')) lensSeq = sendInput((s) => protocol.lens(s, state.lens));
  queued.clear();
  writeUrl(state);
}

function welcomed(message, pane) {
  if (!welcome) {
    welcome = message;
    state.camera = fromUrl.camera ?? strip(message.camera);
    state.lens = { ...strip(message.lens), ...fromUrl.lens };
    lensPanel.set(state.lens);
    fillControls(message);
  }
  // A new session starts from the daemon's defaults: bring it to the client's state.
  pane.send(protocol.camera(++seq, state.camera));
  const s = ++seq;
  pane.send(protocol.lens(s, state.lens));
  if (pane === primary) lensSeq = s;
  if (pane === secondary || state.mode) pane.send(modeMessage(++seq, pane));
  if (Object.keys(state.settings).length) pane.send(protocol.settings(state.settings));
  sessionStorage.setItem('hdof-token', pane.connection.token);
}

function fillControls(message) {
  const cameras = $('#cameras');
  for (const [index, camera] of message.scene.cameras.entries())
    cameras.add(new Option(camera.name || `camera ${index + 1}`, index));
  for (const select of [$('#mode'), $('#compare-mode')])
    for (const name of message.modes) select.add(new Option(name, name));
  if (state.mode) $('#mode').value = state.mode;
  $('#compare-mode').value = message.modes.includes(COMPARE_MODE) ? COMPARE_MODE : message.modes[0];
  // The first view is the finished image: the state keeps it as null (the daemon's default).
  const views = message.views ?? [];
  const [finished, ...stages] = views;
  for (const name of views) $('#view').add(new Option(name, name));
  if (!stages.includes(state.view)) state.view = null;
  $('#view').value = state.view ?? finished;
  const rays = $('#rays');
  rays.max = message.limits.max_rays_per_pixel;
  rays.disabled = rays.max <= 1;
  updateViewControl();
  if (state.compare) {
    $('#compare-mode').value = state.compare;
    setSplit(true);
  }
}

function shown(frame, pane) {
  if (pane !== primary) return;
  let latency;
  if (inputSentAt.has(frame.seq)) latency = performance.now() - inputSentAt.get(frame.seq);
  for (const s of inputSentAt.keys()) if (s <= frame.seq) inputSentAt.delete(s);
  stats.shown(frame, latency);
  stillQuality = Math.max(stillQuality, frame.stats.jpeg_quality ?? 0);
  if (!state.mode) {
    state.mode = frame.stats.mode;
    $('#mode').value = state.mode;
    updateViewControl();
  }
  // A focus pull moves the focus on the server: follow it, unless a newer lens is on its way.
  const focus = frame.stats.focus_distance;
  if (focus > 0 && frame.seq >= lensSeq && Math.abs(focus - state.lens.focus_distance) > 1e-4) {
    state.lens = { ...state.lens, focus_distance: focus };
    lensPanel.set(state.lens);
    writeUrl(state);
  }
  $('#focus-distance').textContent = describeLens(state.lens).focus_distance;
  if (frame.stats.fov_y_deg) lensPanel.showFieldOfView({ x: frame.stats.fov_x_deg, y: frame.stats.fov_y_deg });
}

function showStatus({ state: connectionState, message }, pane) {
  const element = pane === primary ? $('#status') : $('#compare-status');
  element.dataset.state = connectionState;
  element.textContent = message ? `${connectionState}: ${message}` : connectionState;
}

function updateViewControl() {
  $('#view').disabled = state.mode !== protocol.DEBUG_VIEW_MODE;
  const zone = $('#focus-zone');
  zone.disabled = $('#view').disabled || !welcome?.views?.includes(FOCUS_ZONE_VIEW);
  zone.checked = state.view === FOCUS_ZONE_VIEW;
}

function setSplit(on) {
  $('#split').checked = on;
  state.compare = on ? $('#compare-mode').value : null;
  secondary.element.hidden = !on;
  $('#compare-mode').disabled = !on;
  if (!on) secondary.close();
  // The layout changes first; then both panes ask for their new size.
  requestAnimationFrame(() => {
    primary.resize();
    if (on) secondary.open();
  });
  writeUrl(state);
}

async function snapshot() {
  const button = $('#snapshot');
  button.disabled = true;
  try {
    await fullQualityFrame(primary);
    const blob = await primary.viewer.png();
    const lens = describeLens(state.lens);
    const name = `hdof-${state.mode}-${lens.f_number.replace('/', '')}-` +
      `${lens.focal_length_mm.replace(' ', '')}-focus${lens.focus_distance.replace(' ', '')}.png`;
    const link = Object.assign(document.createElement('a'), { href: URL.createObjectURL(blob), download: name });
    link.click();
    setTimeout(() => URL.revokeObjectURL(link.href), 10000);
  } finally {
    button.disabled = false;
  }
}

// Asks for JPEG quality 100 once the view rests and waits until such a frame is shown and no
// other follows (raytrace and hybrid accumulate); then restores the still quality.
async function fullQualityFrame(pane) {
  const before = stillQuality;
  pane.send(protocol.settings({ jpeg_quality_still: 100 }));
  const deadline = performance.now() + 30000;
  let nudged = false;
  while (performance.now() < deadline) {
    await new Promise((resolve) => setTimeout(resolve, 100));
    const quiet = performance.now() - pane.lastShownAt;
    if (pane.viewer.shown?.stats.jpeg_quality === 100 && quiet > 700) break;
    if (!nudged && quiet > 1000) { // the view had settled: render it again
      nudged = true;
      pane.send(protocol.camera(++seq, state.camera));
    }
  }
  // The welcome does not say the daemon's still quality; 90 is its default.
  pane.send(protocol.settings({ jpeg_quality_still: before || 90 }));
  stillQuality = before;
}

// Controls.
for (const pane of panes) {
  new CameraControls(pane.canvas, {
    // Panning needs the vertical field of view: the lens's at the main pane's aspect.
    getView: () => state.camera && {
      ...state.camera,
      fov_y_deg: fieldOfViewDeg(state.lens.focal_length_mm, sensorOf(state.lens), aspect()).y,
    },
    setView: (view) => { state.camera = view; queue('camera'); },
    getRange: () => dollyRange(welcome?.scene.bounds),
    onClick: (event) => {
      const point = pane.viewer.imagePoint(event);
      if (!point || !state.lens) return;
      lensSeq = sendInput((s, target) => {
        const { x, y } = target.viewportPixel(point); // the panes' sizes may differ by a pixel
        return protocol.focusAt(s, x, y, lensPanel.pullMs);
      });
    },
  });
}
// A scene camera stays shown in the picker until the view moves. It brings its framing: the focal
// length that gives its field of view on the current sensor. Its own focus distance where the
// scene has one, else (glTF cameras carry none), as the CLI does, the surface at the image centre.
$('#cameras').addEventListener('change', (event) => {
  if (event.target.value === '') return;
  const { name, focus_distance: focus, fov_y_deg: fov, ...camera } = welcome.scene.cameras[event.target.value];
  state.camera = camera;
  sendInput((s) => protocol.camera(s, state.camera));
  state.lens = {
    ...state.lens,
    focal_length_mm: focalLengthForVerticalFov(fov, sensorOf(state.lens), aspect()),
    ...(focus ? { focus_distance: focus } : {}),
  };
  lensPanel.set(state.lens);
  lensSeq = sendInput((s) => protocol.lens(s, state.lens));
  if (!focus) {
    lensSeq = sendInput((s, target) => {
      const { x, y } = target.viewportPixel({ u: 0.5, v: 0.5 });
      return protocol.focusAt(s, x, y, 0);
    });
  }
  writeUrl(state);
});
$('#home').addEventListener('click', () => {
  state.camera = strip(welcome.camera);
  queue('camera');
});
$('#mode').addEventListener('change', (event) => {
  state.mode = event.target.value;
  updateViewControl();
  for (const pane of panes) if (pane.active) pane.send(modeMessage(++seq, pane));
  writeUrl(state);
});
function setView(view) {
  state.view = view;
  $('#view').value = view ?? welcome.views[0];
  updateViewControl();
  primary.send(modeMessage(++seq, primary));
  writeUrl(state);
}
$('#view').addEventListener('change', (event) =>
  setView(event.target.value === welcome.views?.[0] ? null : event.target.value));
$('#focus-zone').addEventListener('change', (event) => setView(event.target.checked ? FOCUS_ZONE_VIEW : null));
$('#split').addEventListener('change', (event) => setSplit(event.target.checked));
$('#compare-mode').addEventListener('change', (event) => {
  state.compare = event.target.value;
  secondary.send(modeMessage(++seq, secondary));
  writeUrl(state);
});
for (const [id, key] of [['#rays', 'rays_per_pixel'], ['#scale', 'resolution_scale']]) {
  $(id).addEventListener('change', (event) => {
    state.settings[key] = Number(event.target.value);
    for (const pane of panes) if (pane.active) pane.send(protocol.settings({ [key]: state.settings[key] }));
  });
}
$('#snapshot').addEventListener('click', snapshot);
$('#share').addEventListener('click', () => navigator.clipboard?.writeText(location.href));
$('#stats-toggle').addEventListener('click', () => { $('#stats').hidden = !$('#stats').hidden; });
$('#token-form').addEventListener('submit', (event) => {
  event.preventDefault();
  $('#token-form').hidden = true;
  for (const pane of panes) {
    if (pane.active) pane.connection.useToken($('#token').value);
    else pane.connection.token = $('#token').value;
  }
});

let resizeTimer = 0;
new ResizeObserver(() => {
  clearTimeout(resizeTimer);
  resizeTimer = setTimeout(() => { for (const pane of panes) if (pane.active) pane.resize(); }, 250);
}).observe($('#panes'));

primary.connection.token = secondary.connection.token = sessionStorage.getItem('hdof-token') ?? '';
primary.open();
