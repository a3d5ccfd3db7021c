// Camera views the user keeps: the undo/redo history of camera moves, and named saved views (in
// the URL, and as a JSON file to download and upload). Views are the camera message's form.

const HISTORY_LIMIT = 100;
const MAX_NAME = 60;
const MAX_SAVED = 50;
export const SAVED_VIEWS_FORMAT = 'hdof-saved-views';

const sameView = (a, b) => JSON.stringify(a) === JSON.stringify(b);
const copy = (view) => structuredClone(view);

// Undo and redo of camera moves: a move records the view it starts from; undo goes back to it
// (keeping the current view for redo) and a new move forgets what could be redone.
export class ViewHistory {
  constructor(limit = HISTORY_LIMIT) {
    this.limit = limit;
    this.past = [];
    this.future = [];
  }

  get canUndo() { return this.past.length > 0; }
  get canRedo() { return this.future.length > 0; }

  // A move starts from `view`.
  record(view) {
    if (!view) return;
    if (!this.past.length || !sameView(this.past.at(-1), view)) this.past.push(copy(view));
    if (this.past.length > this.limit) this.past.shift();
    this.future = [];
  }

  // The view to go back to from `current`, or null when there is none.
  undo(current) {
    if (!this.past.length) return null;
    this.future.push(copy(current));
    return this.past.pop();
  }

  redo(current) {
    if (!this.future.length) return null;
    this.past.push(copy(current));
    return this.future.pop();
  }
}

// A saved view: {name, position, target, up, focal_length_mm} (the framing: where the camera is
// and the lens it frames with). Throws an Error saying what is wrong.
export function checkSavedView(entry, where = 'a saved view') {
  if (typeof entry !== 'object' || entry === null) throw new Error(`${where} is not an object`);
  const name = typeof entry.name === 'string' ? entry.name.trim() : '';
  if (!name || name.length > MAX_NAME)
    throw new Error(`${where} needs a name of 1 to ${MAX_NAME} characters`);
  const vector = (key) => {
    const v = entry[key];
    if (!Array.isArray(v) || v.length !== 3 || !v.every((x) => Number.isFinite(x) && Math.abs(x) <= 1e6))
      throw new Error(`${where} ('${name}'): '${key}' must be three numbers within ±1e6`);
    return [...v];
  };
  const position = vector('position');
  const target = vector('target');
  const up = entry.up === undefined ? [0, 1, 0] : vector('up');
  if (position.every((x, i) => x === target[i]))
    throw new Error(`${where} ('${name}'): 'target' must differ from 'position'`);
  const focalLength = entry.focal_length_mm;
  if (!Number.isFinite(focalLength) || focalLength < 1 || focalLength > 5000)
    throw new Error(`${where} ('${name}'): 'focal_length_mm' must be 1 to 5000`);
  return { name, position, target, up, focal_length_mm: focalLength };
}

// The saved views as the JSON of a downloadable file.
export function savedViewsJson(views) {
  return JSON.stringify({ format: SAVED_VIEWS_FORMAT, version: 1, views }, null, 2);
}

// The saved views of a file's text; throws an Error with a one-line message for a person.
export function parseSavedViews(text) {
  let data;
  try {
    data = JSON.parse(text);
  } catch {
    throw new Error('the file is not JSON: choose a file saved with the download button (⤓)');
  }
  if (data?.format !== SAVED_VIEWS_FORMAT || !Array.isArray(data.views))
    throw new Error(`the file is not a list of saved views (format "${SAVED_VIEWS_FORMAT}")`);
  if (data.views.length > MAX_SAVED) throw new Error(`the file has more than ${MAX_SAVED} views`);
  return data.views.map((entry, i) => checkSavedView(entry, `view ${i + 1}`));
}

// Saved views in the URL: `name:px,py,pz,tx,ty,tz,focal_mm` joined by `;` (URLSearchParams encodes the
// names). Entries that do not read are left out: a hand-edited link still opens.
const round = (v) => Number(v.toPrecision(5));
export function encodeSavedViews(views) {
  return views.map((v) => `${v.name.replace(/[:;]/g, ' ')}:` +
    [...v.position, ...v.target, v.focal_length_mm].map(round).join(',')).join(';');
}

export function decodeSavedViews(text) {
  const views = [];
  for (const part of (text ?? '').split(';')) {
    const at = part.lastIndexOf(':');
    const n = part.slice(at + 1).split(',').map(Number);
    if (at <= 0 || n.length !== 7) continue;
    try {
      views.push(checkSavedView({ name: part.slice(0, at), position: n.slice(0, 3), target: n.slice(3, 6), focal_length_mm: n[6] }));
    } catch {
      // left out, as above
    }
  }
  return views.slice(0, MAX_SAVED);
}
