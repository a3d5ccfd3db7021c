// The browser client's modules that need no browser: the frame parser, the camera maths and the
// URL state, under node's test runner.

import assert from 'node:assert/strict';
import { test } from 'node:test';
import { dolly, dollyRange, orbit, pan } from '../../client_web/camera.js';
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
    ['type', 'seq', 'position', 'target', 'up', 'fov_y_deg']);
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

test('the URL hash round-trips camera, lens and mode', () => {
  const lens = { focal_length_mm: 50, f_number: 1.4, focus_distance: 2.4, blades: 6 };
  const state = readUrlState(urlHash({ camera: view, lens, mode: 'hybrid', view: 'mask', compare: 'postprocess' }));
  assert.deepEqual(state, { camera: view, lens, mode: 'hybrid', view: 'mask', compare: 'postprocess' });
  assert.equal(urlHash({ mode: 'hybrid', view: null }), '#mode=hybrid'); // the finished image
  assert.deepEqual(readUrlState('#camera=1,2,nope'), {});
});
