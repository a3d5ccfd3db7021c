// A physical lens on a stated sensor: the browser's copy of server/render/lens_optics.h (the same
// rule and formulas; the daemon renders with its own, the panel reads these).
//
// The image is the largest rectangle of its aspect centred on the sensor: an image wider than the
// sensor uses its full width, a narrower one its full height. The field of view is the lens's
// focused at infinity (tan(fov/2) = extent / 2f).

export const SENSORS = [
  { id: 'full-frame', label: 'Full frame', width: 36, height: 24 },
  { id: 'super35', label: 'Super 35', width: 24.89, height: 18.66 },
  { id: 'aps-c', label: 'APS-C', width: 23.6, height: 15.6 },
  { id: 'aps-c-canon', label: 'APS-C (Canon)', width: 22.3, height: 14.9 },
  { id: 'mft', label: 'Micro Four Thirds', width: 17.3, height: 13 },
];
export const FULL_FRAME = SENSORS[0];
// Each side in millimetres, as the daemon accepts.
export const SENSOR_RANGE_MM = { min: 1, max: 300 };

const degrees = (radians) => (radians * 180) / Math.PI;

// The part of the sensor (mm) an image of this aspect (width / height) takes: {x, y}.
export function imageExtentMm(sensor, aspect) {
  if (aspect >= sensor.width / sensor.height) return { x: sensor.width, y: sensor.width / aspect };
  return { x: sensor.height * aspect, y: sensor.height };
}

// The horizontal and vertical field of view in degrees: {x, y}.
export function fieldOfViewDeg(focalLengthMm, sensor, aspect) {
  const extent = imageExtentMm(sensor, aspect);
  const fov = (side) => degrees(2 * Math.atan(side / (2 * focalLengthMm)));
  return { x: fov(extent.x), y: fov(extent.y) };
}

// The focal length whose vertical field of view on this sensor and aspect is fovYDeg.
export function focalLengthForVerticalFov(fovYDeg, sensor, aspect) {
  return imageExtentMm(sensor, aspect).y / (2 * Math.tan((fovYDeg * Math.PI) / 360));
}

// The circle of confusion accepted as sharp: the sensor's diagonal / 1500 (0.0288 mm on full
// frame).
export function acceptableCocMm(sensor) {
  return Math.hypot(sensor.width, sensor.height) / 1500;
}

// Hyperfocal distance and the near and far limits of acceptable sharpness, in metres (far is
// Infinity at or beyond the hyperfocal distance): H = f^2 / (N c) + f,
// near = s (H - f) / (H + s - 2f), far = s (H - f) / (H - s).
export function depthOfField(focalLengthMm, fNumber, focusDistance, cocMm) {
  const f = focalLengthMm / 1000;
  const c = cocMm / 1000;
  const s = focusDistance;
  const hyperfocal = (f * f) / (fNumber * c) + f;
  const near = (s * (hyperfocal - f)) / (hyperfocal + s - 2 * f);
  const far = s < hyperfocal ? (s * (hyperfocal - f)) / (hyperfocal - s) : Infinity;
  return { hyperfocal, near, far };
}

// The lens message's sensor fields as a sensor.
export const sensorOf = (lens) =>
  lens.sensor_width_mm ? { width: lens.sensor_width_mm, height: lens.sensor_height_mm } : FULL_FRAME;
