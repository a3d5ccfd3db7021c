// What the page says about itself: the connection status (waiting for the first frame, live,
// reconnecting, error), a dimmed picture with a banner while the daemon is away, an error next to
// the control that caused it, legends of the debug views, why a control does nothing now, the
// pixel sizes of the resolution choices, and confirmations.

const $ = (selector) => document.querySelector(selector);
const ERROR_SHOWN_MS = 8000;
const NOTE_SHOWN_MS = 3000;

// The connection state of a pane as the status line says it. A live session that has shown no
// frame yet is waiting for it, not live.
export function statusText({ state, message }, framesShown) {
  if (state === 'live' && framesShown === 0) return { state: 'waiting', text: 'waiting for the first frame' };
  return { state, text: message ? `${state}: ${message}` : state };
}

// The banner over a pane whose session is gone, or null while it is connected.
export function bannerText({ state, message, attempt }) {
  const failed = attempt - 1;
  if (state === 'reconnecting')
    return `Disconnected: ${message}. Input is not sent until the daemon is back` +
      (failed > 0 ? ` (${failed} ${failed === 1 ? 'attempt' : 'attempts'} failed so far).` : '.');
  if (state === 'error') return `Disconnected: ${message}`;
  return null;
}

// The legend of each debug view: a colour scale from one end to the other, and what it shows.
export const VIEW_LEGENDS = {
  mask: { scale: 'linear-gradient(to right, #000, #fff)', ends: ['0', 'rays per pixel'],
    text: 'Ray mask: rays per pixel this frame (white: the cap)' },
  hitratio: { scale: 'linear-gradient(to right, #000, #fff)', ends: ['far', 'near'],
    text: 'Share of rays hitting the near layer; dark blue: not traced' },
  coc: { scale: 'linear-gradient(to right, rgb(26,77,255), #000, rgb(255,77,26))', ends: ['near 32 px', 'far 32 px'],
    text: 'Blur size (circle of confusion): black is in focus' },
  near: { text: 'Traced near layer (black: none)' },
  far: { text: 'Traced far layer behind near edges (black: none)' },
};

export function showLegend(view) {
  const legend = $('#legend');
  const entry = VIEW_LEGENDS[view];
  legend.hidden = !entry;
  if (!entry) return;
  legend.querySelector('.scale').style.background = entry.scale ?? 'none';
  legend.querySelector('.scale').hidden = !entry.scale;
  legend.querySelector('.ends').textContent = entry.ends ? entry.ends.join(' → ') : '';
  legend.querySelector('.text').textContent = entry.text;
}

const timers = new Map();

// A one-line error next to the control `name` (data-error-for); null clears it.
export function showControlError(name, message) {
  const output = document.querySelector(`[data-error-for="${name}"]`);
  if (!output) return false;
  clearTimeout(timers.get(output));
  output.hidden = !message;
  output.textContent = message ?? '';
  if (message) timers.set(output, setTimeout(() => { output.hidden = true; }, ERROR_SHOWN_MS));
  return true;
}

// A short confirmation under the share buttons.
export function showNote(text, isError = false) {
  const note = $('#share-note');
  clearTimeout(timers.get(note));
  note.hidden = false;
  note.textContent = text;
  note.classList.toggle('error', isError);
  timers.set(note, setTimeout(() => { note.hidden = true; }, NOTE_SHOWN_MS));
}

// A control that does nothing in the current state is disabled and says why on its label.
export function explainDisabled(control, reason) {
  control.disabled = Boolean(reason);
  const label = control.closest('label');
  if (label) label.title = reason ?? '';
}

// The resolution choices with the pixels each gives for a viewport.
export function labelResolutions(select, viewport) {
  const names = { 1: 'full', 0.5: 'half', 0.25: 'quarter' };
  for (const option of select.options) {
    const scale = Number(option.value);
    const w = Math.max(16, Math.round(viewport.width * scale));
    const h = Math.max(16, Math.round(viewport.height * scale));
    option.textContent = `${names[scale] ?? scale} (${w}×${h})`;
  }
}

// Copies text (the page's link) and says whether it worked.
export async function copyLink(text) {
  try {
    await navigator.clipboard.writeText(text);
  } catch {
    // Without clipboard permission (an insecure origin, a headless browser) the old way may work.
    const area = Object.assign(document.createElement('textarea'), { value: text });
    document.body.append(area);
    area.select();
    const copied = document.execCommand('copy');
    area.remove();
    if (!copied) return showNote('Could not copy: copy the address bar instead', true);
  }
  showNote('Link copied: it holds the camera, lens and saved views');
}
