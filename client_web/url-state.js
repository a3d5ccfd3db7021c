// The view in the URL's hash, so that a link shares it:
//   #camera=px,py,pz,tx,ty,tz,fov&lens=focal_mm,f_number,focus_m,blades&mode=M&view=V&compare=M
//   &saved=NAME:px,py,pz,tx,ty,tz,fov;NAME:... (the named saved views, see views.js)

import { decodeSavedViews, encodeSavedViews } from './views.js';

const round = (v) => Number(v.toPrecision(5));
const numbers = (text, count) => {
  const values = (text ?? '').split(',').map(Number);
  return values.length === count && values.every(Number.isFinite) ? values : null;
};

export function readUrlState(hash = location.hash) {
  const params = new URLSearchParams(hash.replace(/^#/, ''));
  const state = {};
  const c = numbers(params.get('camera'), 7);
  if (c) state.camera = { position: c.slice(0, 3), target: c.slice(3, 6), up: [0, 1, 0], fov_y_deg: c[6] };
  const l = numbers(params.get('lens'), 4);
  if (l) state.lens = { focal_length_mm: l[0], f_number: l[1], focus_distance: l[2], blades: l[3] };
  for (const key of ['mode', 'view', 'compare']) if (params.get(key)) state[key] = params.get(key);
  const saved = decodeSavedViews(params.get('saved'));
  if (saved.length) state.saved = saved;
  return state;
}

export function urlHash({ camera, lens, mode, view, compare, saved }) {
  const params = new URLSearchParams();
  if (camera)
    params.set('camera', [...camera.position, ...camera.target, camera.fov_y_deg].map(round).join(','));
  if (lens)
    params.set('lens', [lens.focal_length_mm, lens.f_number, lens.focus_distance, lens.blades ?? 0]
      .map(round).join(','));
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
