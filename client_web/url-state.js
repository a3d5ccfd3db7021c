// The view in the URL's hash, so that a link shares it:
//   #camera=px,py,pz,tx,ty,tz&lens=focal_mm,f_number,focus_m,blades,sensor_w_mm,sensor_h_mm
//   &mode=M&view=V&compare=M&saved=NAME:px,py,pz,tx,ty,tz,focal_mm;NAME:... (the named saved
//   views, see views.js)
// The field of view follows from the lens (focal length and sensor) and the pane's aspect.

import { FULL_FRAME, sensorOf } from './optics.js';
import { decodeSavedViews, encodeSavedViews } from './views.js';

const round = (v) => Number(v.toPrecision(5));
const numbers = (text, count) => {
  const values = (text ?? '').split(',').map(Number);
  return values.length === count && values.every(Number.isFinite) ? values : null;
};

export function readUrlState(hash = location.hash) {
  const params = new URLSearchParams(hash.replace(/^#/, ''));
  const state = {};
  // Links made before the lens set the field of view carry a seventh number, the field of view:
  // their position and target still hold.
  const c = numbers(params.get('camera'), 6) ?? numbers(params.get('camera'), 7);
  if (c) state.camera = { position: c.slice(0, 3), target: c.slice(3, 6), up: [0, 1, 0] };
  // Without the sensor (older links): full frame.
  const l = numbers(params.get('lens'), 6) ?? numbers(params.get('lens'), 4);
  if (l) {
    const [width, height] = l.length === 6 ? l.slice(4) : [FULL_FRAME.width, FULL_FRAME.height];
    state.lens = {
      focal_length_mm: l[0], f_number: l[1], focus_distance: l[2], blades: l[3],
      sensor_width_mm: width, sensor_height_mm: height,
    };
  }
  for (const key of ['mode', 'view', 'compare']) if (params.get(key)) state[key] = params.get(key);
  const saved = decodeSavedViews(params.get('saved'));
  if (saved.length) state.saved = saved;
  return state;
}

export function urlHash({ camera, lens, mode, view, compare, saved }) {
  const params = new URLSearchParams();
  if (camera)
    params.set('camera', [...camera.position, ...camera.target].map(round).join(','));
  if (lens) {
    const sensor = sensorOf(lens);
    params.set('lens', [lens.focal_length_mm, lens.f_number, lens.focus_distance, lens.blades ?? 0,
      sensor.width, sensor.height].map(round).join(','));
  }
  if (mode) params.set('mode', mode);
  if (view) params.set('view', view); // null: the finished image
  if (compare) params.set('compare', compare);
  if (saved?.length) params.set('saved', encodeSavedViews(saved));
  return '#' + params.toString().replaceAll('%2C', ',').replaceAll('%3A', ':').replaceAll('%3B', ';');
}

// Replaces the hash at most every delayMs (history.replaceState: no history entry per drag step).
export function urlWriter(delayMs = 250) {
  let timer = 0;
  let latest = null;
  return (state) => {
    latest = state;
    if (timer) return;
    timer = setTimeout(() => {
      timer = 0;
      history.replaceState(null, '', urlHash(latest));
    }, delayMs);
  };
}
