// The hdof.v1 wire protocol (protocol/README.md): client messages and the binary frame parser.

import { FULL_FRAME } from './optics.js';

export const SUBPROTOCOL = 'hdof.v1';
export const PROTOCOL_VERSION = 1;
export const FRAME_MAGIC = 0x464f4448; // "HDOF"
export const FRAME_HEADER_BYTES = 32;
export const FORMAT_JPEG = 1;
// The render modes and debug views are the welcome's `modes` and `views`. The views other than
// the first (the finished image) show the stages of this one mode.
export const DEBUG_VIEW_MODE = 'hybrid';

export const CLOSE = {
  GOING_AWAY: 1001,
  PROTOCOL_ERROR: 1002,
  POLICY: 1008, // missing or wrong token, origin not allowed
  TOO_BIG: 1009,
  RENDER_FAILED: 1011,
  BUSY: 1013,
};

export function sessionUrl(location) {
  const scheme = location.protocol === 'https:' ? 'wss:' : 'ws:';
  return `${scheme}//${location.host}/session`;
}

export function hello(viewport, token) {
  const message = { type: 'hello', protocol: PROTOCOL_VERSION, viewport };
  if (token) message.token = token;
  return message;
}

export function camera(seq, view) {
  return {
    type: 'camera', seq,
    position: view.position, target: view.target, up: view.up,
  };
}

export function lens(seq, l) {
  return {
    type: 'lens', seq,
    focal_length_mm: l.focal_length_mm, f_number: l.f_number,
    focus_distance: l.focus_distance, blades: l.blades,
    blade_rotation_deg: l.blade_rotation_deg ?? 0,
    sensor_width_mm: l.sensor_width_mm ?? FULL_FRAME.width,
    sensor_height_mm: l.sensor_height_mm ?? FULL_FRAME.height,
  };
}

// Whether a view (camera and lens, as the state keeps them) is the session's starting one (the
// welcome's camera and lens): the frames a session renders before the client's messages apply
// show it already.
export function isStartingView(view, welcome) {
  const same = (build, a, b) => JSON.stringify(build(0, a)) === JSON.stringify(build(0, b));
  return same(camera, view.camera, welcome.camera) && same(lens, view.lens, welcome.lens);
}

export function focusAt(seq, x, y, pullMs) {
  return { type: 'focus_at', seq, x, y, pull_ms: pullMs };
}

// Asks where the surface under viewport pixel (x, y) is; the daemon answers `picked` with `id`.
export function pick(id, x, y) {
  return { type: 'pick', id, x, y };
}

// view: one of the welcome's views, or null for the finished image (the daemon's default). It is
// sent only with DEBUG_VIEW_MODE: the other modes have no stages to show.
export function mode(seq, name, view) {
  const message = { type: 'mode', seq, mode: name };
  if (name === DEBUG_VIEW_MODE && view) message.view = view;
  return message;
}

export function settings(fields) {
  return { type: 'settings', ...fields };
}

export function ack(frame) {
  return { type: 'ack', frame };
}

// One binary frame message: {frame, width, height, seq, stats, jpeg (a Blob)}, or throws.
export function parseFrame(buffer) {
  if (buffer.byteLength < FRAME_HEADER_BYTES) throw new Error('frame shorter than its header');
  const header = new DataView(buffer, 0, FRAME_HEADER_BYTES);
  const u32 = (offset) => header.getUint32(offset, true);
  if (u32(0) !== FRAME_MAGIC) throw new Error('frame without the HDOF magic');
  const version = header.getUint16(4, true);
  const format = header.getUint16(6, true);
  if (version !== PROTOCOL_VERSION || format !== FORMAT_JPEG)
    throw new Error(`frame version ${version} format ${format} not understood`);
  const statsBytes = u32(24);
  if (statsBytes > buffer.byteLength - FRAME_HEADER_BYTES) throw new Error('frame stats overrun');
  const statsText = new TextDecoder().decode(
    new Uint8Array(buffer, FRAME_HEADER_BYTES, statsBytes));
  return {
    frame: u32(8),
    width: u32(12),
    height: u32(16),
    seq: u32(20),
    stats: JSON.parse(statsText),
    jpeg: new Blob([new Uint8Array(buffer, FRAME_HEADER_BYTES + statsBytes)],
      { type: 'image/jpeg' }),
  };
}
