// The browser client: wires the panes (render sessions), camera controls and panel, lens panel,
// feedback and the URL together. The state here is what the user chose; the panes send it to
// their sessions.

import { CameraControls, FlyKeys } from './controls.js';
import {
  bannerText, copyLink, explainDisabled, labelResolutions, showControlError, showLegend, showNote,
  statusText,
} from './feedback.js';
import { describeLens, LensPanel } from './lens.js';
import { fieldOfViewDeg, focalLengthForVerticalFov, sensorOf } from './optics.js';
import { Pane } from './pane.js';
import * as protocol from './protocol.js';
import { pictureState } from './stats.js';
import { readUrlState, urlWriter } from './url-state.js';
import { ViewPanel } from './view-panel.js';

const $ = (selector) => document.querySelector(selector);
const fromUrl = readUrlState();
const state = {
  camera: null, // {position, target, up}; the field of view is the lens's
  lens: null, // {focal_length_mm, f_number, focus_distance, blades, blade_rotation_deg,
  //             sensor_width_mm, sensor_height_mm}
  mode: fromUrl.mode ?? null, // null: the daemon's default, learnt from the first frame
  view: fromUrl.view ?? null, // a debug view of the welcome's; null: the finished image
  compare: fromUrl.compare ?? null, // the split view's second mode, null when not split
  saved: fromUrl.saved ?? [], // named saved views {name, position, target, up, focal_length_mm}
  settings: {}, // the settings in force (the daemon's defaults for those not here)
};
let welcome = null;
// The split view's second mode at first, when the daemon has it: the post-process alone, to set
// beside the hybrid.
const COMPARE_MODE = 'postprocess';
const RASTER_MODES = ['pinhole', 'postprocess']; // they trace no rays
const SNAPSHOT_TIMEOUT_MS = 120000;
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

const lensPanel = new LensPanel($('#lens'), (lens) => {
  state.lens = lens;
  queue('lens');
});
const handlers = {
  onStatus: showStatus,
  onWelcome: welcomed,
  onShown: shown,
  onServerError: serverError,
  onTokenNeeded: (message) => {
    $('#token-form').hidden = false;
    $('#token-form output').textContent = message;
    $('#token').focus();
  },
};
const primary = new Pane($('#pane-main'), handlers);
const secondary = new Pane($('#pane-compare'), handlers);
const panes = [primary, secondary];
// A view, as undo and saved views keep it: the camera and the focal length (the framing).
const viewPanel = new ViewPanel({
  getView: () => state.camera && { ...state.camera, focal_length_mm: state.lens.focal_length_mm },
  setView: applyView,
  sceneCamera,
  home: () => applyView({ ...strip(welcome.camera), focal_length_mm: welcome.lens.focal_length_mm }),
  saved: state.saved,
  onSavedChange: () => writeUrl(state),
  showError: (message) => showControlError('camera', message),
});

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

function setCamera(camera) {
  if (!camera) return;
  state.camera = camera;
  queue('camera');
}

function applyView({ focal_length_mm: focalLength, ...camera }) {
  setCamera(camera);
  if (focalLength && focalLength !== state.lens.focal_length_mm) {
    state.lens = { ...state.lens, focal_length_mm: focalLength };
    lensPanel.set(state.lens);
    queue('lens');
  }
}

// The camera as the navigation maths take it: with the vertical field of view, the lens's at the
// main pane's aspect; and back.
const navigationView = () => state.camera && {
  ...state.camera,
  fov_y_deg: fieldOfViewDeg(state.lens.focal_length_mm, sensorOf(state.lens), aspect()).y,
};
const setNavigationView = ({ fov_y_deg: _, ...camera }) => setCamera(camera);

// Camera and lens changes coalesce to one message per animation frame.
const queued = new Set();
function queue(kind) {
  if (kind === 'camera') viewPanel.viewMoved(); // the view is no longer a scene camera's
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
  // A new session starts from the daemon's defaults: bring it to the client's state, and show
  // its frames from the one that carries these messages' seq, unless the defaults are that state.
  pane.send(protocol.camera(++seq, state.camera));
  const s = ++seq;
  pane.send(protocol.lens(s, state.lens));
  if (pane === primary) lensSeq = s;
  const sendsMode = pane === secondary || Boolean(state.mode);
  if (sendsMode) pane.send(modeMessage(++seq, pane));
  const sendsSettings = Object.keys(state.settings).length > 0;
  if (sendsSettings) pane.send(protocol.settings(state.settings));
  const starting = !sendsMode && !sendsSettings && protocol.isStartingView(state, message);
  pane.showFrom(starting ? 0 : seq);
  sessionStorage.setItem('hdof-token', pane.connection.token);
  if (pane === primary) labelResolutions($('#scale'), pane.viewport());
}

function fillControls(message) {
  viewPanel.setSceneCameras(message.scene.cameras);
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
  $('#rays').max = message.limits.max_rays_per_pixel;
  updateModeControls();
  if (state.compare) {
    $('#compare-mode').value = state.compare;
    setSplit(true);
  }
}

function shown(frame, pane) {
  pane.framesShown = (pane.framesShown ?? 0) + 1;
  if (pane.framesShown === 1) showStatus(pane.connectionStatus, pane);
  if (pane !== primary) return void pane.stats.shown(frame);
  let latency;
  if (inputSentAt.has(frame.seq)) latency = performance.now() - inputSentAt.get(frame.seq);
  for (const s of inputSentAt.keys()) if (s <= frame.seq) inputSentAt.delete(s);
  pane.stats.shown(frame, latency);
  stillQuality = Math.max(stillQuality, frame.stats.jpeg_quality ?? 0);
  if (!state.mode) {
    state.mode = frame.stats.mode;
    $('#mode').value = state.mode;
    updateModeControls();
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

function showStatus(status, pane) {
  if (status.state === 'connecting') pane.framesShown = 0;
  pane.connectionStatus = status;
  pane.showBanner(bannerText(status));
  if (pane !== primary) return;
  const { state: shownState, text } = statusText(status, pane.framesShown ?? 0);
  $('#status').dataset.state = shownState;
  $('#status').textContent = text;
}

// The daemon rejected a message: the error goes next to the control that sent it, and that
// control returns to the value in force.
const SETTING_CONTROLS = { rays_per_pixel: 'rays', resolution_scale: 'scale' };
const FIELD_CONTROLS = {
  ...SETTING_CONTROLS, mode: 'mode', view: 'view',
  position: 'camera', target: 'camera', up: 'camera', x: 'camera', y: 'camera',
};
function serverError(error, pane) {
  const control = FIELD_CONTROLS[error.field] ?? 'general';
  showControlError(control, error.message);
  if (error.field in SETTING_CONTROLS) {
    const key = error.field;
    const before = settingsBefore[key];
    if (before === undefined) delete state.settings[key];
    else state.settings[key] = before;
    $(`#${SETTING_CONTROLS[key]}`).value = String(before ?? 1); // both default to 1
  }
  if (error.field === 'mode' || error.field === 'view') {
    $('#mode').value = state.mode = pane.viewer.shown?.stats.mode ?? state.mode;
    updateModeControls();
  }
}

function updateModeControls() {
  const hybrid = state.mode === protocol.DEBUG_VIEW_MODE;
  explainDisabled($('#view'), hybrid ? null : `Debug views show the ${protocol.DEBUG_VIEW_MODE}'s stages: choose the ${protocol.DEBUG_VIEW_MODE} mode`);
  showLegend(hybrid ? state.view : null);
  explainDisabled($('#focus-zone'), !hybrid
    ? `The in-focus zone is a debug view of the ${protocol.DEBUG_VIEW_MODE}: choose the ${protocol.DEBUG_VIEW_MODE} mode`
    : welcome?.views?.includes(FOCUS_ZONE_VIEW) ? null : 'This daemon has no in-focus zone view');
  $('#focus-zone').checked = state.view === FOCUS_ZONE_VIEW;
  const max = Number($('#rays').max || 1);
  explainDisabled($('#rays'), RASTER_MODES.includes(state.mode)
    ? `${state.mode} traces no rays: rays per pixel apply to raytrace and hybrid`
    : max <= 1 ? 'the daemon allows 1 ray per pixel (max_rays_per_pixel)' : null);
  explainDisabled($('#compare-mode'), state.compare ? null : 'Tick Compare to split the view and pick the second pane\'s mode');
}

// The split view keeps the shot's framing: both panes show the whole picture the single pane
// showed, letterboxed, rather than each cropping it to a narrow portrait.
function setSplit(on) {
  $('#split').checked = on;
  state.compare = on ? $('#compare-mode').value : null;
  const shot = $('#panes').clientWidth / Math.max(1, $('#panes').clientHeight);
  for (const pane of panes) pane.aspect = on ? shot : null;
  secondary.element.hidden = !on;
  updateModeControls();
  if (!on) secondary.close();
  // The layout changes first; then both panes ask for their new size.
  requestAnimationFrame(() => {
    primary.resize();
    if (on) secondary.open();
  });
  writeUrl(state);
}

// Asks for JPEG quality 100 and waits for a converged frame at that quality (the daemon sends a
// resting view once more when the still quality changes), showing the refinement meanwhile;
// then saves it as PNG and restores the still quality.
async function snapshot() {
  const button = $('#snapshot');
  const label = button.textContent;
  button.disabled = true;
  const before = stillQuality;
  primary.send(protocol.settings({ jpeg_quality_still: 100 }));
  try {
    const deadline = performance.now() + SNAPSHOT_TIMEOUT_MS;
    for (;;) {
      const stats = primary.viewer.shown?.stats;
      const picture = stats ? pictureState(stats) : 'waiting';
      if (stats?.jpeg_quality === 100 && picture === 'converged') break;
      if (performance.now() > deadline)
        return showNote(`No converged frame in ${SNAPSHOT_TIMEOUT_MS / 1000} s: try again once the picture says converged`, true);
      button.textContent = `Snapshot: ${picture}…`;
      await new Promise((resolve) => setTimeout(resolve, 100));
    }
    const blob = await primary.viewer.png();
    const lens = describeLens(state.lens);
    const name = `hdof-${state.mode}-${lens.f_number.replace('/', '')}-` +
      `${lens.focal_length_mm.replace(' ', '')}-focus${lens.focus_distance.replace(' ', '')}.png`;
    const link = Object.assign(document.createElement('a'), { href: URL.createObjectURL(blob), download: name });
    link.click();
    setTimeout(() => URL.revokeObjectURL(link.href), 10000);
    showNote(`Saved ${name}`);
  } finally {
    // The welcome does not say the daemon's still quality; 90 is its default.
    primary.send(protocol.settings({ jpeg_quality_still: before || 90 }));
    stillQuality = before;
    button.textContent = label;
    button.disabled = false;
  }
}

// A scene camera brings its framing: the focal length that gives its field of view on the current
// sensor. Its own focus distance where the scene has one, else (glTF cameras carry none), as the
// CLI does, the surface at the image centre.
function sceneCamera(index) {
  const { name, focus_distance: focus, fov_y_deg: fov, ...camera } = welcome.scene.cameras[index];
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
}

// Controls.
for (const pane of panes) {
  new CameraControls(pane.canvas, pane.marker, {
    getView: navigationView,
    setView: setNavigationView,
    // The newest camera goes first: the daemon picks in the camera it has.
    pick: (at) => { flush(); return pane.pick(at); },
    imagePoint: (event) => pane.viewer.imagePoint(event),
    aspect: () => pane.canvas.width / Math.max(1, pane.canvas.height),
    bounds: () => welcome?.scene.bounds,
    focusDistance: () => state.lens?.focus_distance ?? 5,
    flying: () => viewPanel.flying,
    onMoveStart: () => viewPanel.moveStarts(),
    onClick: (event) => {
      const point = pane.viewer.imagePoint(event);
      if (!point || !state.lens) return;
      if (!pane.connection.live) { // said, not dropped silently
        pane.banner.classList.remove('flash');
        void pane.banner.offsetWidth; // restarts the animation
        pane.banner.classList.add('flash');
        return showControlError('general', 'Not connected: the click to focus was not sent');
      }
      lensSeq = sendInput((s, target) => {
        const { x, y } = target.viewportPixel(point); // the panes' sizes may differ by a pixel
        return protocol.focusAt(s, x, y, lensPanel.pullMs);
      });
    },
  });
}
new FlyKeys(window, {
  active: () => viewPanel.flying,
  getView: navigationView,
  setView: setNavigationView,
  bounds: () => welcome?.scene.bounds,
  onMoveStart: () => viewPanel.moveStarts(),
});
$('#mode').addEventListener('change', (event) => {
  state.mode = event.target.value;
  showControlError('mode', null);
  updateModeControls();
  for (const pane of panes) if (pane.active) pane.send(modeMessage(++seq, pane));
  writeUrl(state);
});
function setView(view) {
  state.view = view;
  $('#view').value = view ?? welcome.views[0];
  updateModeControls();
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
const settingsBefore = {}; // the value in force before the newest change of each setting
for (const [key, id] of Object.entries(SETTING_CONTROLS)) {
  $(`#${id}`).addEventListener('change', (event) => {
    settingsBefore[key] = state.settings[key];
    state.settings[key] = Number(event.target.value);
    showControlError(id, null);
    for (const pane of panes) if (pane.active) pane.send(protocol.settings({ [key]: state.settings[key] }));
  });
}
$('#snapshot').addEventListener('click', snapshot);
$('#share').addEventListener('click', () => copyLink(location.href));
$('#stats-toggle').addEventListener('click', () => document.body.classList.toggle('no-stats'));
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
  resizeTimer = setTimeout(() => {
    if (state.compare) for (const pane of panes) pane.aspect = $('#panes').clientWidth / Math.max(1, $('#panes').clientHeight);
    for (const pane of panes) if (pane.active) pane.resize();
    labelResolutions($('#scale'), primary.viewport());
  }, 250);
}).observe($('#panes'));

primary.connection.token = secondary.connection.token = sessionStorage.getItem('hdof-token') ?? '';
primary.open();
