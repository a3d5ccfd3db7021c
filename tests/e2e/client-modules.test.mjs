// The browser client's modules that need no browser: the frame parser, the camera maths, the lens
// maths and the URL state, under node's test runner.

import assert from 'node:assert/strict';
import { test } from 'node:test';
import { dolly, dollyRange, orbit, pan } from '../../client_web/camera.js';
import { describeLens, scalePosition } from '../../client_web/lens.js';
import {
  acceptableCocMm, depthOfField, fieldOfViewDeg, focalLengthForVerticalFov, FULL_FRAME, imageExtentMm, SENSORS,
} from '../../client_web/optics.js';
import * as protocol from '../../client_web/protocol.js';
import { readUrlState, urlHash } from '../../client_web/url-state.js';

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
const distance = (v) => Math.hypot(...v.position.map((p, i) => p - v.target[i]));

test('orbit keeps the distance to the target and never looks straight up or down', () => {
  const turned = orbit(view, 100, 0);
  assert.ok(Math.abs(distance(turned) - 5) < 1e-9);
  assert.notDeepEqual(turned.position, view.position);
  const over = orbit(view, 0, 1e5);
  assert.ok(over.position[1] - over.target[1] < 5); // pitch clamped below 90 degrees
});

test('pan moves camera and target together; dolly keeps to its range', () => {
  const moved = pan(view, 50, 0, 270);
  assert.deepEqual(moved.position.map((p, i) => p - moved.target[i]), [0, 0, 5]);
  assert.ok(moved.target[0] !== 0);
  const range = dollyRange({ min: [-1, -1, -1], max: [1, 1, 1] });
  assert.ok(Math.abs(distance(dolly(view, 0.5, range)) - 2.5) < 1e-9);
  assert.equal(distance(dolly(view, 1e-9, range)), range.min);
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

const near = (actual, expected, tolerance, what) =>
  assert.ok(Math.abs(actual - expected) <= tolerance, `${what}: ${actual}, expected ${expected}`);

test('field of view from focal length and sensor, worked out by hand', () => {
  // 3:2 on full frame uses all of it: 2 atan(18/50) = 39.598 across, 2 atan(12/50) = 26.991 up.
  const fov = fieldOfViewDeg(50, FULL_FRAME, 1.5);
  near(fov.x, 39.598, 1e-3, 'across');
  near(fov.y, 26.991, 1e-3, 'up');
  // Wider (16:9): the full width, 36 x 20.25 mm. Narrower (4:3): the full height, 32 x 24 mm.
  assert.deepEqual(imageExtentMm(FULL_FRAME, 16 / 9), { x: 36, y: 20.25 });
  near(imageExtentMm(FULL_FRAME, 4 / 3).x, 32, 1e-9, '4:3 width');
  near(fieldOfViewDeg(50, FULL_FRAME, 16 / 9).y, 22.895, 1e-3, '16:9 up');
  // A longer lens zooms in.
  assert.ok(fieldOfViewDeg(100, FULL_FRAME, 1.5).x < fov.x);
  // 40 degrees up at 16:9 on full frame: 20.25 / (2 tan 20) = 27.818 mm, and back.
  near(focalLengthForVerticalFov(40, FULL_FRAME, 16 / 9), 27.818, 1e-3, 'focal length');
  near(fieldOfViewDeg(focalLengthForVerticalFov(40, FULL_FRAME, 0.7), FULL_FRAME, 0.7).y, 40, 1e-9, 'round trip');
  assert.deepEqual(SENSORS.map((s) => s.id), ['full-frame', 'super35', 'aps-c', 'aps-c-canon', 'mft']);
});

test('acceptable CoC, hyperfocal, near and far limits, worked out by hand', () => {
  near(acceptableCocMm(FULL_FRAME), 0.028844, 1e-6, 'full frame: 43.267 / 1500');
  // 50 mm f/1.4 at 2.4 m, c = 0.03 mm: H = 59.5738 m, near 2.30885 m, far 2.49865 m.
  const dof = depthOfField(50, 1.4, 2.4, 0.03);
  near(dof.hyperfocal, 59.5738, 1e-4, 'hyperfocal');
  near(dof.near, 2.30885, 1e-5, 'near');
  near(dof.far, 2.49865, 1e-5, 'far');
  // 35 mm f/8 focused at its hyperfocal distance, 5.13917 m: sharp from half of it to infinity.
  const deep = depthOfField(35, 8, 5.139167, 0.03);
  near(deep.near, 2.56958, 1e-5, 'near at H');
  assert.equal(deep.far, Infinity);
  // The panel shows them; beyond the hyperfocal distance the far limit is infinity.
  const shown = describeLens({ focal_length_mm: 35, f_number: 8, focus_distance: 10, blades: 0 });
  assert.equal(shown.far, '∞');
  assert.equal(shown.coc, '0.0288 mm (sensor diagonal / 1500)');
  assert.equal(scalePosition(Infinity), 1);
  assert.ok(scalePosition(1) < scalePosition(2) && scalePosition(100) < 1);
});
