// A pane's label and stats overlay: the pane's mode and what its picture is doing (moving at a
// lower resolution, refining, converged), and, collapsible, frame rate, the daemon's render and
// encode times, frame size and bitrate, latencies, round trip, dropped frames, rays and the ray
// mask's coverage, with a plot of the time between frames shown that scales to fit them.

const PLOT_SECONDS = 5;
const PLOT_SCALES_MS = [50, 100, 200, 500, 1000, 2000, 5000, 10000];
const SHOWN_STEPS = 3;
const PLOT = { width: 240, height: 84, left: 34, bottom: 14, top: 12 };

const FIELDS = [
  ['fps', 'Frames shown', 'frames shown in the last second'],
  ['size', 'Picture', 'the frame\'s size in pixels'],
  ['gpu', 'Render time', 'the daemon\'s wall-clock time to render the frame; its steps\' added up'],
  ['steps', 'Costliest steps', 'the render steps that took longest on the GPU'],
  ['encode', 'JPEG encode', 'the daemon\'s time to compress the frame'],
  ['bytes', 'Frame', 'the compressed frame and its JPEG quality (lower while moving)'],
  ['bitrate', 'Bitrate', 'frames received in the last second'],
  ['latency', 'Input to picture', 'from sending a camera or lens change to showing its first frame'],
  ['server-latency', 'Input to send', 'in the daemon: from receiving the change to sending its frame'],
  ['round-trip', 'Round trip', 'a question to the daemon and its answer (the last pick)'],
  ['dropped', 'Dropped frames', 'frames the daemon rendered that this page never showed'],
  ['rays', 'Rays traced', 'camera rays traced for the frame'],
  ['coverage', 'Ray mask', 'the hybrid\'s share of pixels that trace rays'],
];

const ms = (v) => (v === undefined ? '–' : `${v < 10 ? v.toFixed(1) : v.toFixed(0)} ms`);

// What the picture is doing, from the frame's stats: "moving: 50%" (the daemon renders a moving
// view smaller to keep up), "moving", "refining 37/64" or "converged".
export function pictureState(stats) {
  const scale = stats.render_scale ?? 1;
  if (stats.moving) return scale < 1 ? `moving: ${Math.round(scale * 100)}%` : 'moving';
  const done = stats.accumulated_frames ?? 1;
  const target = stats.accumulation_target;
  if (target && done < target) return `refining ${done}/${target}`;
  return 'converged';
}

// The top of the plot's scale: the smallest of PLOT_SCALES_MS that holds `maxMs`.
export function plotScale(maxMs) {
  return PLOT_SCALES_MS.find((s) => s >= maxMs) ?? PLOT_SCALES_MS.at(-1);
}

export function describeBitrate(bitsPerSecond) {
  if (bitsPerSecond >= 1e6) return `${(bitsPerSecond / 1e6).toFixed(2)} Mbit/s`;
  return `${(bitsPerSecond / 1e3).toFixed(0)} kbit/s`;
}

export class StatsOverlay {
  // pane: the pane element; the label and overlay are added to it.
  constructor(pane) {
    this.label = Object.assign(document.createElement('p'), { className: 'pane-label' });
    this.label.innerHTML = '<span data-field="mode"></span> <span data-field="state">waiting for the first frame</span>';
    this.root = document.createElement('details');
    this.root.className = 'stats';
    this.root.open = innerHeight >= 700 && innerWidth >= 900; // on a small screen the picture comes first
    this.root.innerHTML = '<summary>Stats</summary><dl></dl><canvas></canvas>';
    const list = this.root.querySelector('dl');
    for (const [name, label, help] of FIELDS) {
      const term = Object.assign(document.createElement('dt'), { textContent: label, title: help });
      list.append(term, Object.assign(document.createElement('dd'), { textContent: '–' }));
      list.lastChild.dataset.field = name;
    }
    this.plot = this.root.querySelector('canvas');
    this.plot.width = PLOT.width;
    this.plot.height = PLOT.height;
    this.plot.title = 'Time between frames shown over the last 5 s (ms)';
    pane.append(this.label, this.root);
    this.reset();
  }

  // A new session: its frame numbers start again.
  reset() {
    this.shownAt = []; // performance.now() of the frames shown, last PLOT_SECONDS
    this.received = []; // [performance.now(), bytes] of the frames received, last second
    this.lastFrame = 0;
    this.dropped = 0;
    this.latencyMs = undefined;
  }

  field(name, text) {
    for (const element of [this.label, this.root]) {
      const field = element.querySelector(`[data-field="${name}"]`);
      if (field) field.textContent = text;
    }
  }

  frameReceived(frame) {
    const now = performance.now();
    this.received.push([now, frame.stats.bytes ?? 0]);
    while (this.received[0][0] < now - 1000) this.received.shift();
  }

  roundTrip(milliseconds) {
    this.field('round-trip', ms(milliseconds));
  }

  // A frame was shown; latencyMs when it is the first to apply an input the client timed.
  shown(frame, latencyMs) {
    const now = performance.now();
    this.shownAt.push(now);
    while (this.shownAt[0] < now - PLOT_SECONDS * 1000) this.shownAt.shift();
    if (latencyMs !== undefined) this.latencyMs = latencyMs;
    if (frame.frame > this.lastFrame + 1 && this.lastFrame > 0) this.dropped += frame.frame - this.lastFrame - 1;
    this.lastFrame = frame.frame;

    const s = frame.stats;
    const state = pictureState(s);
    this.label.dataset.state = state.split(/[ :]/)[0];
    this.field('mode', s.mode);
    this.field('state', state);
    this.field('fps', `${this.shownAt.filter((t) => t >= now - 1000).length} per second`);
    this.field('size', `${frame.width}×${frame.height} px`);
    const stepsMs = ms(s.gpu_ms);
    this.field('gpu', s.render_ms === undefined ? stepsMs : `${ms(s.render_ms)} (steps ${stepsMs})`);
    const steps = Object.entries(s.passes_ms ?? {}).sort((a, b) => b[1] - a[1]);
    const lines = steps.slice(0, SHOWN_STEPS).map(([step, t]) => `${step} ${ms(t)}`);
    if (steps.length > SHOWN_STEPS) lines.push(`and ${steps.length - SHOWN_STEPS} other steps`);
    this.field('steps', lines.join('\n') || '–');
    this.field('encode', ms(s.encode_ms));
    this.field('bytes', `${((s.bytes ?? 0) / 1024).toFixed(1)} KiB at JPEG quality ${s.jpeg_quality ?? '?'}`);
    const bytes = this.received.reduce((sum, [, b]) => sum + b, 0);
    this.field('bitrate', describeBitrate(bytes * 8));
    this.field('latency', ms(this.latencyMs));
    this.field('server-latency', ms(s.input_to_send_ms));
    this.field('dropped', `${this.dropped}`);
    this.field('rays', s.rays_shot ? `${(s.rays_shot / 1e6).toFixed(2)} million per frame` : 'none');
    this.field('coverage', s.mode === 'hybrid' && s.mask_coverage !== undefined
      ? `${(s.mask_coverage * 100).toFixed(1)}% of pixels` : 'not this mode');
    if (this.root.open) this.drawPlot(now);
  }

  drawPlot(now) {
    const g = this.plot.getContext('2d');
    const { width, height, left, bottom, top } = PLOT;
    const intervals = [];
    for (let i = 1; i < this.shownAt.length; i++)
      intervals.push([this.shownAt[i], this.shownAt[i] - this.shownAt[i - 1]]);
    const max = plotScale(Math.max(1, ...intervals.map(([, v]) => v)));
    const plotHeight = height - bottom - top;
    const x = (t) => left + (1 - (now - t) / (PLOT_SECONDS * 1000)) * (width - left);
    const y = (v) => top + plotHeight * (1 - v / max);
    g.clearRect(0, 0, width, height);
    g.font = '9px ui-monospace, monospace';
    g.fillStyle = 'rgba(255,255,255,0.7)';
    g.strokeStyle = 'rgba(255,255,255,0.2)';
    g.textAlign = 'right';
    for (const v of [0, max / 2, max]) {
      g.beginPath(); g.moveTo(left, y(v)); g.lineTo(width, y(v)); g.stroke();
      g.fillText(`${v}`, left - 3, y(v) + 3);
    }
    g.textAlign = 'left';
    g.fillText('ms between frames', left, 8);
    g.textAlign = 'center';
    for (let s = PLOT_SECONDS; s >= 0; s--)
      g.fillText(s === 0 ? 'now' : `-${s} s`, Math.min(width - 10, Math.max(left + 8, x(now - s * 1000))), height - 2);
    g.strokeStyle = '#7fdc8a';
    g.beginPath();
    intervals.forEach(([t, v], i) => (i ? g.lineTo(x(t), y(v)) : g.moveTo(x(t), y(v))));
    g.stroke();
  }
}
