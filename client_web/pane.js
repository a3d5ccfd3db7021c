// A pane: one canvas and its render session, with its label and stats, the orbit's pivot marker
// and a banner for a lost connection. The split view is two panes, each its own session on the
// daemon in its own mode, fed the same camera and lens.

import { Connection } from './connection.js';
import * as protocol from './protocol.js';
import { StatsOverlay } from './stats.js';
import { Viewer } from './viewer.js';

const MIN_SIDE = 16;

export class Pane {
  // element: the pane (its size is the viewport, or the largest part of it of `aspect`);
  // handlers: onStatus(status, pane), onWelcome(welcome, pane), onShown(frame, pane),
  // onServerError(error, pane), onTokenNeeded(message, pane).
  constructor(element, handlers) {
    this.element = element;
    this.canvas = element.querySelector('canvas');
    this.canvas.title = document.querySelector('#controls > .hint')?.textContent ?? '';
    this.handlers = handlers;
    this.limits = { max_width: 1920, max_height: 1080 };
    this.aspect = null; // width over height the picture keeps (the shot's), or null: the pane's
    this.lastShownAt = 0;
    // A new session starts from the daemon's defaults until the client's camera, lens and mode
    // (sent after its welcome) apply: its frames are shown from the one carrying this seq.
    this.firstSeqShown = 0;
    this.picks = new Map(); // id -> {resolve, sentAt}
    this.pickId = 0;
    this.marker = this.add('div', 'pivot');
    this.marker.hidden = true;
    this.marker.title = 'the point the view turns about';
    this.banner = this.add('p', 'banner');
    this.banner.hidden = true;
    this.banner.setAttribute('role', 'alert');
    this.stats = new StatsOverlay(element);
    this.viewer = new Viewer(this.canvas, (frame) => this.shown(frame));
    this.connection = new Connection(protocol.sessionUrl(location), {
      onStatus: (status) => {
        if (status.state !== 'live') this.answerPicks(null);
        handlers.onStatus?.(status, this);
      },
      onWelcome: (welcome) => {
        this.firstSeqShown = 0;
        this.limits = welcome.limits;
        this.viewer.reset();
        this.stats.reset();
        // The limits may be smaller than the viewport asked for: ask again within them.
        if (!sameSize(this.viewport(), this.connection.viewport)) this.resize();
        else handlers.onWelcome?.(welcome, this);
      },
      onFrame: (frame) => {
        this.stats.frameReceived(frame);
        if (frame.seq < this.firstSeqShown) this.connection.send(protocol.ack(frame.frame));
        else this.viewer.push(frame);
      },
      onPicked: (picked) => this.picked(picked),
      onServerError: (error) => {
        this.firstSeqShown = 0; // a refused message's seq may never apply
        handlers.onServerError?.(error, this);
      },
      onTokenNeeded: (message) => handlers.onTokenNeeded?.(message, this),
    });
  }

  add(tag, className) {
    const element = Object.assign(document.createElement(tag), { className });
    this.element.append(element);
    return element;
  }

  get active() {
    return !this.element.hidden;
  }

  // The pane's size in CSS pixels (or the largest part of it of the shot's aspect), within the
  // daemon's limits, keeping its aspect.
  viewport() {
    let width = Math.max(MIN_SIDE, Math.round(this.element.clientWidth));
    let height = Math.max(MIN_SIDE, Math.round(this.element.clientHeight));
    if (this.aspect) {
      if (width / height > this.aspect) width = Math.round(height * this.aspect);
      else height = Math.round(width / this.aspect);
    }
    const fit = Math.min(1, this.limits.max_width / width, this.limits.max_height / height);
    width = Math.max(MIN_SIDE, Math.floor(width * fit));
    height = Math.max(MIN_SIDE, Math.floor(height * fit));
    return { width, height };
  }

  // A new session when the pane's size changed (a session's viewport is fixed by its hello).
  resize() {
    const viewport = this.viewport();
    if (!this.connection.viewport || !sameSize(viewport, this.connection.viewport))
      this.connection.open(viewport);
  }

  open() {
    this.connection.open(this.viewport());
  }

  close() {
    this.connection.close();
    this.viewer.reset();
    this.answerPicks(null);
  }

  send(message) {
    return this.connection.send(message);
  }

  // The session's frames are shown once they carry this seq (the client's state applied).
  showFrom(seq) {
    this.firstSeqShown = seq;
  }

  shown(frame) {
    this.lastShownAt = performance.now();
    this.connection.send(protocol.ack(frame.frame));
    this.handlers.onShown?.(frame, this);
  }

  // The viewport pixel at a point given as fractions of the image ({u, v}, see Viewer).
  viewportPixel({ u, v }) {
    const { width, height } = this.connection.viewport;
    return { x: Math.floor(u * width), y: Math.floor(v * height) };
  }

  // What the session's camera sees at an image point: {point, depth, distance}, or null on the
  // background or without a session.
  pick(at) {
    const id = ++this.pickId;
    const { x, y } = this.viewportPixel(at);
    if (!this.send(protocol.pick(id, x, y))) return Promise.resolve(null);
    return new Promise((resolve) => this.picks.set(id, { resolve, sentAt: performance.now() }));
  }

  picked(message) {
    const pending = this.picks.get(message.id);
    if (!pending) return;
    this.picks.delete(message.id);
    this.stats.roundTrip(performance.now() - pending.sentAt);
    pending.resolve(message.hit ? message : null);
  }

  answerPicks(answer) {
    for (const { resolve } of this.picks.values()) resolve(answer);
    this.picks.clear();
  }

  // Disconnected: the last frame dimmed and a banner saying why and what happens next; null
  // takes them away.
  showBanner(text) {
    this.element.classList.toggle('disconnected', Boolean(text));
    this.banner.hidden = !text;
    this.banner.textContent = text ?? '';
  }
}

function sameSize(a, b) {
  return a && b && a.width === b.width && a.height === b.height;
}
