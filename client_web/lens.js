// The lens panel: f-number, focal length, focus distance and aperture blades. The sliders are
// logarithmic, as lenses are: a stop, a zoom step or a focus step is a ratio, not a difference.

const RANGES = {
  f_number: { min: 1, max: 22, format: (v) => `f/${v < 10 ? v.toFixed(1) : v.toFixed(0)}` },
  focal_length_mm: { min: 8, max: 400, format: (v) => `${v.toFixed(0)} mm` },
  focus_distance: { min: 0.05, max: 1000, format: (v) => `${v < 10 ? v.toFixed(2) : v.toFixed(1)} m` },
};
const STEPS = 1000;

const toSlider = (value, { min, max }) =>
  Math.round((STEPS * Math.log(Math.min(max, Math.max(min, value)) / min)) / Math.log(max / min));
const fromSlider = (step, { min, max }) => min * (max / min) ** (step / STEPS);

export function describeLens(lens) {
  return {
    f_number: RANGES.f_number.format(lens.f_number),
    focal_length_mm: RANGES.focal_length_mm.format(lens.focal_length_mm),
    focus_distance: RANGES.focus_distance.format(lens.focus_distance),
  };
}

export class LensPanel {
  // root holds inputs named f_number, focal_length_mm, focus_distance, blades, pull_ms and
  // <output data-for="NAME">; onChange(lens) when the user moves one.
  constructor(root, onChange) {
    this.root = root;
    this.onChange = onChange;
    this.lens = null;
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
    this.showValues();
  }

  showValues() {
    const text = describeLens(this.lens);
    for (const name of Object.keys(RANGES))
      this.root.querySelector(`output[data-for="${name}"]`).textContent = text[name];
  }
}
