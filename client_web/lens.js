// The lens panel: f-number, focal length, focus distance, aperture blades and the sensor, with
// what a camera assistant reads: the field of view, the near and far limits of acceptable
// sharpness and the hyperfocal distance (optics.js), and a distance scale marking the focus. The
// sliders are logarithmic, as lenses are: a stop, a zoom step or a focus step is a ratio, not a
// difference.

import { acceptableCocMm, depthOfField, SENSOR_RANGE_MM, SENSORS, sensorOf } from './optics.js';

const RANGES = {
  f_number: { min: 1, max: 22, format: (v) => `f/${v < 10 ? v.toFixed(1) : v.toFixed(0)}` },
  focal_length_mm: { min: 8, max: 400, format: (v) => `${v.toFixed(0)} mm` },
  focus_distance: { min: 0.05, max: 1000, format: (v) => `${v < 10 ? v.toFixed(2) : v.toFixed(1)} m` },
};
const STEPS = 1000;

const CUSTOM = 'custom';
// The distance scale: logarithmic from SCALE_MIN to SCALE_MAX metres over the first SCALE_FINITE
// of its width; infinity at the right end.
const SCALE_MIN = 0.1;
const SCALE_MAX = 100;
const SCALE_FINITE = 0.9;
const SCALE_TICKS = [0.2, 0.5, 1, 2, 5, 10, 20, 50];

const toSlider = (value, { min, max }) =>
  Math.round((STEPS * Math.log(Math.min(max, Math.max(min, value)) / min)) / Math.log(max / min));
const fromSlider = (step, { min, max }) => min * (max / min) ** (step / STEPS);

export const formatDistance = (metres) =>
  metres === Infinity ? '∞' : RANGES.focus_distance.format(metres);

export function describeLens(lens) {
  const coc = acceptableCocMm(sensorOf(lens));
  const dof = depthOfField(lens.focal_length_mm, lens.f_number, lens.focus_distance, coc);
  return {
    f_number: RANGES.f_number.format(lens.f_number),
    focal_length_mm: RANGES.focal_length_mm.format(lens.focal_length_mm),
    focus_distance: RANGES.focus_distance.format(lens.focus_distance),
    near: formatDistance(dof.near),
    far: formatDistance(dof.far),
    hyperfocal: formatDistance(dof.hyperfocal),
    coc: `${coc.toFixed(4)} mm (sensor diagonal / 1500)`,
  };
}

// Where a distance sits on the distance scale, as a fraction of its width.
export function scalePosition(metres) {
  if (metres === Infinity) return 1;
  const clamped = Math.min(SCALE_MAX, Math.max(SCALE_MIN, metres));
  return (SCALE_FINITE * Math.log(clamped / SCALE_MIN)) / Math.log(SCALE_MAX / SCALE_MIN);
}

export class LensPanel {
  // root holds inputs named f_number, focal_length_mm, focus_distance, blades, pull_ms, sensor,
  // sensor_width_mm and sensor_height_mm, <output data-for="NAME"> for each value of
  // describeLens and a .dof-scale; onChange(lens) when the user moves one.
  constructor(root, onChange) {
    this.root = root;
    this.onChange = onChange;
    this.lens = null;
    this.customChosen = false; // the user picked Custom: its fields stay open on any size
    for (const [name, range] of Object.entries(RANGES)) {
      const input = this.input(name);
      input.min = 0;
      input.max = STEPS;
      input.addEventListener('input', () => {
        this.lens = { ...this.lens, [name]: fromSlider(Number(input.value), range) };
        this.showValues();
        this.onChange(this.lens);
      });
    }
    this.input('blades').addEventListener('change', () => {
      this.lens = { ...this.lens, blades: Number(this.input('blades').value) };
      this.onChange(this.lens);
    });
    const sensor = this.input('sensor');
    for (const preset of SENSORS)
      sensor.add(new Option(`${preset.label} ${preset.width}×${preset.height}`, preset.id));
    sensor.add(new Option('Custom…', CUSTOM));
    sensor.addEventListener('change', () => {
      const preset = SENSORS.find((s) => s.id === sensor.value);
      this.customChosen = !preset;
      if (preset) this.setSensor(preset.width, preset.height);
      else this.showSensor(); // custom: the size fields open on the current sensor
    });
    for (const name of ['sensor_width_mm', 'sensor_height_mm']) {
      this.input(name).addEventListener('change', () => {
        const width = Number(this.input('sensor_width_mm').value);
        const height = Number(this.input('sensor_height_mm').value);
        const valid = [width, height].every((v) => v >= SENSOR_RANGE_MM.min && v <= SENSOR_RANGE_MM.max);
        this.input(name).setCustomValidity(valid ? '' : `${SENSOR_RANGE_MM.min} to ${SENSOR_RANGE_MM.max} mm`);
        if (valid) this.setSensor(width, height);
      });
    }
    this.scale = root.querySelector('.dof-scale');
    for (const tick of [...SCALE_TICKS, Infinity]) {
      const label = document.createElement('span');
      label.className = 'tick';
      label.style.left = `${100 * scalePosition(tick)}%`;
      label.textContent = tick === Infinity ? '∞' : String(tick);
      this.scale.append(label);
    }
  }

  // A sensor chosen here: the focal length stays, so the field of view changes, as on a camera.
  setSensor(width, height) {
    this.lens = { ...this.lens, sensor_width_mm: width, sensor_height_mm: height };
    this.showSensor();
    this.showValues();
    this.onChange(this.lens);
  }

  showSensor() {
    const { width, height } = sensorOf(this.lens);
    const select = this.input('sensor');
    const preset = SENSORS.find((s) => s.width === width && s.height === height);
    select.value = preset && !this.customChosen ? preset.id : CUSTOM;
    this.root.querySelector('.sensor-custom').hidden = select.value !== CUSTOM;
    this.input('sensor_width_mm').value = width;
    this.input('sensor_height_mm').value = height;
  }

  input(name) {
    return this.root.querySelector(`[name="${name}"]`);
  }

  get pullMs() {
    return Number(this.input('pull_ms').value);
  }

  // Shows a lens that came from elsewhere (welcome, the URL, a focus pull) without sending it.
  set(lens) {
    this.lens = { ...lens };
    for (const [name, range] of Object.entries(RANGES))
      this.input(name).value = toSlider(lens[name], range);
    const blades = this.input('blades');
    if (![...blades.options].some((o) => Number(o.value) === lens.blades))
      blades.add(new Option(`${lens.blades} blades`, lens.blades));
    blades.value = String(lens.blades ?? 0);
    this.showSensor();
    this.showValues();
  }

  // The field of view in force, as the daemon's frames report it ({x, y} in degrees).
  showFieldOfView({ x, y }) {
    this.root.querySelector('output[data-for="fov"]').textContent = `${x.toFixed(1)}° × ${y.toFixed(1)}°`;
  }

  showValues() {
    const text = describeLens(this.lens);
    for (const [name, value] of Object.entries(text))
      this.root.querySelector(`output[data-for="${name}"]`).textContent = value;
    const { near, far } = depthOfField(this.lens.focal_length_mm, this.lens.f_number,
      this.lens.focus_distance, acceptableCocMm(sensorOf(this.lens)));
    const zone = this.scale.querySelector('.dof-zone');
    zone.style.left = `${100 * scalePosition(near)}%`;
    zone.style.width = `${100 * (scalePosition(far) - scalePosition(near))}%`;
    this.scale.querySelector('.dof-focus').style.left = `${100 * scalePosition(this.lens.focus_distance)}%`;
  }
}
