// The browser client's modules that need no browser: the frame parser, the camera maths (orbit
// about a pivot, dolly clamp, fly and look), the lens maths, the undo history and saved views, the
// URL state and what the page says of frames and connections, under node's test runner.

import assert from 'node:assert/strict';
import { test } from 'node:test';
import {
  DOLLY_STEP, dollyStandoff, dollyToward, flySpeed, flyStep, forwardOf, look, orbitAbout, pan, rayThrough,
} from '../../client_web/camera.js';
import { Connection } from '../../client_web/connection.js';
import { bannerText, statusText } from '../../client_web/feedback.js';
import { describeLens, scalePosition } from '../../client_web/lens.js';
import {
  acceptableCocMm, depthOfField, fieldOfViewDeg, focalLengthForVerticalFov, FULL_FRAME, imageExtentMm, SENSORS,
} from '../../client_web/optics.js';
import * as protocol from '../../client_web/protocol.js';
import { describeBitrate, pictureState, plotScale } from '../../client_web/stats.js';
import { readUrlState, urlHash } from '../../client_web/url-state.js';
import {
  decodeSavedViews, encodeSavedViews, parseSavedViews, savedViewsJson, ViewHistory,
} from '../../client_web/views.js';

function frameMessage({ frame, width, height, seq, stats, jpeg }) {
  const statsBytes = new TextEncoder().encode(JSON.stringify(stats));
  const buffer = new ArrayBuffer(32 + statsBytes.length + jpeg.length);
  const header = new DataView(buffer);
  header.setUint32(0, protocol.FRAME_MAGIC, true);
  header.setUint16(4, 1, true);
  header.setUint16(6, 1, true);
  header.setUint32(8, frame, true);
  header.setUint32(12, width, true);
  header.setUint32(16, height, true);
  header.setUint32(20, seq, true);
  header.setUint32(24, statsBytes.length, true);
  new Uint8Array(buffer, 32).set(statsBytes);
  new Uint8Array(buffer, 32 + statsBytes.length).set(jpeg);
  return buffer;
}

test('parseFrame reads the header, the stats and the JPEG', async () => {
  const stats = { frame: 7, mode: 'hybrid', passes_ms: { gbuffer: 1.5 }, gpu_ms: 2, encode_ms: 1, bytes: 3 };
  const parsed = protocol.parseFrame(frameMessage({
    frame: 7, width: 480, height: 270, seq: 42, stats, jpeg: [0xff, 0xd8, 0xff],
  }));
  assert.deepEqual({ ...parsed, jpeg: undefined },
    { frame: 7, width: 480, height: 270, seq: 42, stats, jpeg: undefined });
  assert.deepEqual([...new Uint8Array(await parsed.jpeg.arrayBuffer())], [0xff, 0xd8, 0xff]);
  assert.equal(parsed.jpeg.type, 'image/jpeg');
});

test('parseFrame rejects what is not a v1 JPEG frame', () => {
  const good = () => frameMessage({ frame: 1, width: 16, height: 16, seq: 0, stats: {}, jpeg: [1] });
  assert.throws(() => protocol.parseFrame(new ArrayBuffer(31)), /shorter/);
  const badMagic = good();
  new DataView(badMagic).setUint32(0, 0, true);
  assert.throws(() => protocol.parseFrame(badMagic), /magic/);
  const badVersion = good();
  new DataView(badVersion).setUint16(4, 2, true);
  assert.throws(() => protocol.parseFrame(badVersion), /version 2/);
  const overrun = good();
  new DataView(overrun).setUint32(24, 1000, true);
  assert.throws(() => protocol.parseFrame(overrun), /overrun/);
});

test('messages carry only the protocol\'s fields', () => {
  assert.deepEqual(protocol.hello({ width: 480, height: 270 }, ''),
    { type: 'hello', protocol: 1, viewport: { width: 480, height: 270 } });
  assert.deepEqual(protocol.mode(3, 'postprocess', 'mask'), { type: 'mode', seq: 3, mode: 'postprocess' });
  assert.deepEqual(protocol.mode(4, 'hybrid', 'mask'), { type: 'mode', seq: 4, mode: 'hybrid', view: 'mask' });
  assert.deepEqual(protocol.mode(5, 'hybrid', null), { type: 'mode', seq: 5, mode: 'hybrid' });
  assert.deepEqual(Object.keys(protocol.camera(1, { position: [0, 0, 1], target: [0, 0, 0], up: [0, 1, 0], fov_y_deg: 40, name: 'x' })),
    ['type', 'seq', 'position', 'target', 'up']); // the field of view is the lens's
  const lens = protocol.lens(2, { focal_length_mm: 50, f_number: 2, focus_distance: 3, blades: 0 });
  assert.deepEqual([lens.sensor_width_mm, lens.sensor_height_mm], [36, 24]); // full frame unless chosen
});

const view = { position: [0, 1, 5], target: [0, 1, 0], up: [0, 1, 0], fov_y_deg: 40 };
const between = (a, b) => Math.hypot(...a.map((p, i) => p - b[i]));
const near = (a, b, tolerance = 1e-9) => a.every((v, i) => Math.abs(v - b[i]) <= tolerance);
const degrees = (radians) => (radians * 180) / Math.PI;

test('a view is the starting one while its camera and lens are the welcome\'s', () => {
  const welcome = {
    camera: { type: 'camera', seq: 0, position: [1, 2, 3], target: [0, 1, 0], up: [0, 1, 0] },
    lens: {
      type: 'lens', seq: 0, focal_length_mm: 35, f_number: 2.8, focus_distance: 4, blades: 0,
      blade_rotation_deg: 0, sensor_width_mm: 36, sensor_height_mm: 24,
    },
  };
  const strip = ({ type, seq, ...rest }) => rest;
  const view = { camera: strip(welcome.camera), lens: strip(welcome.lens) };
  assert.ok(protocol.isStartingView(view, welcome));
  assert.ok(!protocol.isStartingView({ ...view, camera: { ...view.camera, position: [1, 2, 4] } }, welcome));
  assert.ok(!protocol.isStartingView({ ...view, lens: { ...view.lens, focal_length_mm: 50 } }, welcome));
  assert.ok(!protocol.isStartingView({ ...view, lens: { ...view.lens, sensor_width_mm: 23.6 } }, welcome));
});

test('orbit about a pivot keeps the distance to it and the view on it', () => {
  const pivot = [1, 0.5, 2]; // a near object, off the view axis
  const turned = orbitAbout(view, pivot, 120, -40, 480);
  assert.ok(Math.abs(between(turned.position, pivot) - between(view.position, pivot)) < 1e-9);
  assert.ok(Math.abs(between(turned.target, turned.position) - 5) < 1e-9, 'the target keeps its distance');
  // The pivot stays where it was in the picture: its direction in the camera's frame is kept.
  const local = (v, p) => {
    const f = forwardOf(v);
    const d = p.map((x, i) => x - v.position[i]);
    const r = [-f[2], 0, f[0]].map((x) => x / Math.hypot(f[0], f[2]));
    return [d[0] * r[0] + d[2] * r[2], d.reduce((s, x, i) => s + x * f[i], 0)];
  };
  assert.ok(near(local(turned, pivot), local(view, pivot), 1e-9));
});

test('a full pane width of drag is half a turn; the pitch stops short of straight up', () => {
  const turned = orbitAbout(view, view.target, 480, 0, 480);
  assert.ok(near(turned.position, [0, 1, -5], 1e-9), `${turned.position}`);
  const over = orbitAbout(view, view.target, 0, 1e5, 480);
  const pitch = degrees(Math.asin(forwardOf(over).at(1)));
  assert.ok(pitch > -89.5 && pitch < -88.5, `pitch ${pitch}`);
  assert.ok(Math.abs(between(over.position, view.target) - 5) < 1e-9);
});

test('look turns the view in place', () => {
  const turned = look(view, 240, 0, 480);
  assert.deepEqual(turned.position, view.position);
  assert.ok(Math.abs(degrees(Math.acos(forwardOf(turned).reduce((s, x, i) => s + x * forwardOf(view)[i], 0))) - 45) < 1e-6);
});

test('pan moves camera and target together', () => {
  const moved = pan(view, 50, 0, 270);
  assert.ok(near(moved.position.map((p, i) => p - moved.target[i]), [0, 0, 5], 1e-12));
  assert.ok(moved.target[0] !== 0);
});

test('dolly steps a share of the way to the point and stops short of it', () => {
  const surface = [0, 1, 0];
  const step = dollyToward(view, surface, 1, 0.05);
  assert.ok(Math.abs(between(step.position, surface) - 5 * (1 - DOLLY_STEP)) < 1e-9);
  assert.ok(near(forwardOf(step), forwardOf(view)), 'the view direction is kept');
  let close = view;
  for (let i = 0; i < 200; i++) close = dollyToward(close, surface, 3, 0.05);
  assert.ok(Math.abs(between(close.position, surface) - 0.05) < 1e-9, 'stops at the standoff');
  assert.ok(close.position[2] > 0, 'never through the surface');
  const back = dollyToward(close, surface, -2, 0.05);
  assert.ok(between(back.position, surface) > 0.05);
  assert.equal(dollyStandoff({ min: [-1, -1, -1], max: [1, 1, 1] }), 0.05);
});

test('the ray through the image centre is the view direction; fly moves at its speed', () => {
  assert.ok(near(rayThrough(view, { u: 0.5, v: 0.5 }, 16 / 9), [0, 0, -1], 1e-12));
  assert.ok(rayThrough(view, { u: 1, v: 0.5 }, 1)[0] > 0, 'right of centre looks right');
  const bounds = { min: [0, 0, 0], max: [8, 0, 0] };
  assert.equal(flySpeed(bounds), 1);
  assert.equal(flySpeed(bounds, true), 4);
  const flown = flyStep(view, { forward: 1, right: 0, up: 0 }, 0.5, 2);
  assert.ok(near(flown.position, [0, 1, 4], 1e-12));
  assert.ok(near(flown.target, [0, 1, -1], 1e-12));
  const diagonal = flyStep(view, { forward: 1, right: 1, up: 0 }, 1, 1);
  assert.ok(Math.abs(between(diagonal.position, view.position) - 1) < 1e-12, 'diagonals are not faster');
  assert.equal(flyStep(view, { forward: 0, right: 0, up: 0 }, 1, 1), view);
});

test('undo goes back through the moves and redo forward; a new move forgets the redo', () => {
  const history = new ViewHistory();
  const a = view, b = { ...view, position: [1, 1, 5] }, c = { ...view, position: [2, 1, 5] };
  assert.equal(history.undo(a), null);
  history.record(a); // a move from a to b
  history.record(b); // from b to c
  assert.deepEqual(history.undo(c), b);
  assert.deepEqual(history.undo(b), a);
  assert.ok(!history.canUndo);
  assert.deepEqual(history.redo(a), b);
  history.record(b);
  assert.ok(!history.canRedo, 'a new move forgets the redo');
  const small = new ViewHistory(2);
  for (const x of [1, 2, 3]) small.record({ ...view, fov_y_deg: x });
  assert.equal(small.past.length, 2, 'bounded');
});

test('saved views round-trip through the URL and JSON; bad files get a reason', () => {
  const saved = [{ name: 'sofa: wide', position: [1, 2, 3], target: [0, 1, 0], up: [0, 1, 0], focal_length_mm: 35 }];
  const urlState = readUrlState(urlHash({ saved }));
  assert.deepEqual(urlState.saved, [{ ...saved[0], name: 'sofa  wide' }]);
  assert.deepEqual(decodeSavedViews(encodeSavedViews(saved) + ';broken:1,2'), [{ ...saved[0], name: 'sofa  wide' }]);
  assert.deepEqual(parseSavedViews(savedViewsJson(saved)), saved);
  assert.throws(() => parseSavedViews('nope'), /not JSON/);
  assert.throws(() => parseSavedViews('{"views":[]}'), /not a list of saved views/);
  const bad = (entry) => JSON.stringify({ format: 'hdof-saved-views', version: 1, views: [entry] });
  assert.throws(() => parseSavedViews(bad({ ...saved[0], focal_length_mm: 6000 })), /view 1 \('sofa: wide'\): 'focal_length_mm'/);
  assert.throws(() => parseSavedViews(bad({ ...saved[0], target: [1, 2] })), /'target' must be three numbers/);
  assert.throws(() => parseSavedViews(bad({ ...saved[0], name: '' })), /needs a name/);
});

test('the URL hash round-trips camera, lens, sensor and mode', () => {
  const lens = { focal_length_mm: 85, f_number: 1.4, focus_distance: 2.4, blades: 6, sensor_width_mm: 23.6, sensor_height_mm: 15.6 };
  const camera = { position: view.position, target: view.target, up: view.up };
  const state = readUrlState(urlHash({ camera, lens, mode: 'hybrid', view: 'mask', compare: 'postprocess' }));
  assert.deepEqual(state, { camera, lens, mode: 'hybrid', view: 'mask', compare: 'postprocess' });
  // Links from before the sensor and the lens's field of view: full frame, the view's position kept.
  assert.deepEqual(readUrlState('#camera=0,1,5,0,1,0,40&lens=50,2,3,0'), {
    camera,
    lens: { focal_length_mm: 50, f_number: 2, focus_distance: 3, blades: 0, sensor_width_mm: 36, sensor_height_mm: 24 },
  });
  assert.equal(urlHash({ mode: 'hybrid', view: null }), '#mode=hybrid'); // the finished image
  assert.deepEqual(readUrlState('#camera=1,2,nope'), {});
});

const within = (actual, expected, tolerance, what) =>
  assert.ok(Math.abs(actual - expected) <= tolerance, `${what}: ${actual}, expected ${expected}`);

test('field of view from focal length and sensor, worked out by hand', () => {
  // 3:2 on full frame uses all of it: 2 atan(18/50) = 39.598 across, 2 atan(12/50) = 26.991 up.
  const fov = fieldOfViewDeg(50, FULL_FRAME, 1.5);
  within(fov.x, 39.598, 1e-3, 'across');
  within(fov.y, 26.991, 1e-3, 'up');
  // Wider (16:9): the full width, 36 x 20.25 mm. Narrower (4:3): the full height, 32 x 24 mm.
  assert.deepEqual(imageExtentMm(FULL_FRAME, 16 / 9), { x: 36, y: 20.25 });
  within(imageExtentMm(FULL_FRAME, 4 / 3).x, 32, 1e-9, '4:3 width');
  within(fieldOfViewDeg(50, FULL_FRAME, 16 / 9).y, 22.895, 1e-3, '16:9 up');
  // A longer lens zooms in.
  assert.ok(fieldOfViewDeg(100, FULL_FRAME, 1.5).x < fov.x);
  // 40 degrees up at 16:9 on full frame: 20.25 / (2 tan 20) = 27.818 mm, and back.
  within(focalLengthForVerticalFov(40, FULL_FRAME, 16 / 9), 27.818, 1e-3, 'focal length');
  within(fieldOfViewDeg(focalLengthForVerticalFov(40, FULL_FRAME, 0.7), FULL_FRAME, 0.7).y, 40, 1e-9, 'round trip');
  assert.deepEqual(SENSORS.map((s) => s.id), ['full-frame', 'super35', 'aps-c', 'aps-c-canon', 'mft']);
});

test('acceptable CoC, hyperfocal, near and far limits, worked out by hand', () => {
  within(acceptableCocMm(FULL_FRAME), 0.028844, 1e-6, 'full frame: 43.267 / 1500');
  // 50 mm f/1.4 at 2.4 m, c = 0.03 mm: H = 59.5738 m, near 2.30885 m, far 2.49865 m.
  const dof = depthOfField(50, 1.4, 2.4, 0.03);
  within(dof.hyperfocal, 59.5738, 1e-4, 'hyperfocal');
  within(dof.near, 2.30885, 1e-5, 'near');
  within(dof.far, 2.49865, 1e-5, 'far');
  // 35 mm f/8 focused at its hyperfocal distance, 5.13917 m: sharp from half of it to infinity.
  const deep = depthOfField(35, 8, 5.139167, 0.03);
  within(deep.near, 2.56958, 1e-5, 'near at H');
  assert.equal(deep.far, Infinity);
  // The panel shows them; beyond the hyperfocal distance the far limit is infinity.
  const shown = describeLens({ focal_length_mm: 35, f_number: 8, focus_distance: 10, blades: 0 });
  assert.equal(shown.far, '∞');
  assert.equal(shown.coc, '0.0288 mm (sensor diagonal / 1500)');
  assert.equal(scalePosition(Infinity), 1);
  assert.ok(scalePosition(1) < scalePosition(2) && scalePosition(100) < 1);
});

test('the picture says moving, refining or converged, in plain words', () => {
  assert.equal(pictureState({ moving: true, render_scale: 0.5 }), 'moving: 50%');
  assert.equal(pictureState({ moving: true, render_scale: 1 }), 'moving');
  assert.equal(pictureState({ moving: false, accumulated_frames: 37, accumulation_target: 64 }), 'refining 37/64');
  assert.equal(pictureState({ moving: false, accumulated_frames: 64, accumulation_target: 64 }), 'converged');
  assert.equal(plotScale(30), 50);
  assert.equal(plotScale(260), 500);
  assert.equal(plotScale(1e6), 10000);
  assert.equal(describeBitrate(2.5e6), '2.50 Mbit/s');
  assert.equal(describeBitrate(64000), '64 kbit/s');
});

test('the status waits for the first frame; a lost daemon gets a banner with its attempts', () => {
  assert.deepEqual(statusText({ state: 'live', message: '' }, 0), { state: 'waiting', text: 'waiting for the first frame' });
  assert.deepEqual(statusText({ state: 'live', message: '' }, 3), { state: 'live', text: 'live' });
  assert.equal(bannerText({ state: 'live' }), null);
  const banner = bannerText({ state: 'reconnecting', message: 'the daemon stopped; reconnect attempt 3 in 2.0 s', attempt: 3 });
  assert.match(banner, /^Disconnected: the daemon stopped; reconnect attempt 3 in 2\.0 s\..*2 attempts failed/);
  const second = bannerText({ state: 'reconnecting', message: 'closed (1006)', attempt: 2 });
  assert.match(second, /\(1 attempt failed so far\)\.$/);
  assert.match(bannerText({ state: 'reconnecting', message: 'closed (1006)', attempt: 1 }), /back\.$/);
});

// A stand-in for the browser's WebSocket: the test opens and closes each socket by hand.
class FakeSocket {
  static OPEN = 1;
  static made = [];
  constructor(url, subprotocol) {
    Object.assign(this, { url, subprotocol, readyState: 0, sent: [] });
    FakeSocket.made.push(this);
  }
  send(text) { this.sent.push(JSON.parse(text)); }
  close() { this.readyState = 3; }
  open() {
    this.readyState = 1;
    this.onopen();
  }
  closeFromServer(code) {
    this.readyState = 3;
    this.onclose({ code, reason: '' });
  }
}

test('while reconnection attempts fail, the banner still says why the session ended', (t) => {
  t.mock.timers.enable({ apis: ['setTimeout'] });
  globalThis.WebSocket = FakeSocket;
  t.after(() => delete globalThis.WebSocket);
  const statuses = [];
  const connection = new Connection('ws://daemon/session', { onStatus: (status) => statuses.push(status) });
  connection.open({ width: 480, height: 270 });
  FakeSocket.made.at(-1).open();
  assert.equal(FakeSocket.made.at(-1).sent[0].type, 'hello');
  connection.receive(FakeSocket.made.at(-1), JSON.stringify({ type: 'welcome' }));
  assert.equal(statuses.at(-1).state, 'live');
  FakeSocket.made.at(-1).closeFromServer(protocol.CLOSE.GOING_AWAY);
  assert.match(statuses.at(-1).message, /^the daemon stopped; reconnect attempt 1 in 0\.5 s/);
  // The daemon is gone: each attempt's socket closes without opening (1006).
  for (const attempt of [2, 3]) {
    t.mock.timers.tick(10000);
    FakeSocket.made.at(-1).closeFromServer(1006);
    assert.equal(statuses.at(-1).state, 'reconnecting');
    assert.match(statuses.at(-1).message, new RegExp(`^the daemon stopped; reconnect attempt ${attempt} in`));
  }
  // Back: a live session forgets the cause; a daemon never reached says so.
  t.mock.timers.tick(10000);
  FakeSocket.made.at(-1).open();
  connection.receive(FakeSocket.made.at(-1), JSON.stringify({ type: 'welcome' }));
  assert.equal(statuses.at(-1).state, 'live');
  connection.close();
  const fresh = new Connection('ws://daemon/session', { onStatus: (status) => statuses.push(status) });
  fresh.open({ width: 480, height: 270 });
  FakeSocket.made.at(-1).closeFromServer(1006);
  assert.match(statuses.at(-1).message, /^cannot reach the daemon; reconnect attempt 1/);
  fresh.close();
});
