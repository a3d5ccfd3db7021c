// The stats overlay: frame rate, the server's per-pass GPU and encode times, frame bytes, the
// input-to-frame latency the client measures, and a plot of frame intervals.

const PLOT_SECONDS = 5;
const PLOT_MAX_MS = 200;
const SHOWN_PASSES = 4;

const ms = (v) => (v === undefined ? '–' : `${v.toFixed(1)} ms`);
const kib = (v) => (v === undefined ? '–' : `${(v / 1024).toFixed(1)} KiB`);

export class StatsOverlay {
  // root holds <dd data-field="NAME"> elements and a <canvas> for the plot.
  constructor(root) {
    this.root = root;
    this.plot = root.querySelector('canvas');
    this.shownAt = []; // performance.now() of the frames shown, last PLOT_SECONDS
    this.latencyMs = undefined;
  }

  field(name, text) {
    const element = this.root.querySelector(`[data-field="${name}"]`);
    if (element) element.textContent = text;
  }

  // A frame was shown; latencyMs when it is the first to apply an input the client timed.
  shown(frame, latencyMs) {
    const now = performance.now();
    this.shownAt.push(now);
    while (this.shownAt[0] < now - PLOT_SECONDS * 1000) this.shownAt.shift();
    if (latencyMs !== undefined) this.latencyMs = latencyMs;

    const s = frame.stats;
    const lastSecond = this.shownAt.filter((t) => t >= now - 1000).length;
    this.field('fps', `${lastSecond}`);
    this.field('mode', s.mode);
    // Below full size while the view moves: the daemon's interactive resolution.
    const scale = s.render_scale ?? 1;
    this.field('size', `${frame.width}×${frame.height}` +
      (scale < 1 ? ` (moving: ${Math.round(scale * 100)}%)` : ''));
    this.field('gpu', ms(s.gpu_ms));
    // The costliest passes; the hybrid has a dozen more.
    const passes = Object.entries(s.passes_ms ?? {}).sort((a, b) => b[1] - a[1]);
    const lines = passes.slice(0, SHOWN_PASSES).map(([pass, t]) => `${pass} ${t.toFixed(1)}`);
    if (passes.length > SHOWN_PASSES) lines.push(`+${passes.length - SHOWN_PASSES} more`);
    this.field('passes', lines.join('\n') || '–');
    this.field('encode', ms(s.encode_ms));
    this.field('bytes', `${kib(s.bytes)} (q${s.jpeg_quality ?? '?'})`);
    this.field('latency', ms(this.latencyMs));
    this.field('server-latency', ms(s.input_to_send_ms));
    this.field('accumulated', `${s.accumulated_frames ?? 1}`);
    this.field('rays', s.rays_shot ? `${(s.rays_shot / 1e6).toFixed(2)} M` : '–');
    this.drawPlot(now);
  }

  drawPlot(now) {
    const canvas = this.plot;
    const g = canvas.getContext('2d');
    const { width, height } = canvas;
    g.clearRect(0, 0, width, height);
    g.strokeStyle = 'rgba(255,255,255,0.25)';
    for (const target of [1000 / 60, 1000 / 30]) { // 60 and 30 fps lines
      const y = height - (target / PLOT_MAX_MS) * height;
      g.beginPath(); g.moveTo(0, y); g.lineTo(width, y); g.stroke();
    }
    g.strokeStyle = '#7fdc8a';
    g.beginPath();
    for (let i = 1; i < this.shownAt.length; i++) {
      const interval = Math.min(PLOT_MAX_MS, this.shownAt[i] - this.shownAt[i - 1]);
      const x = width - ((now - this.shownAt[i]) / (PLOT_SECONDS * 1000)) * width;
      const y = height - (interval / PLOT_MAX_MS) * height;
      if (i === 1) g.moveTo(x, y); else g.lineTo(x, y);
    }
    g.stroke();
  }
}
